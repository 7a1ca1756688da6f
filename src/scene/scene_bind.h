/* Binding a YAML tree to an orr_scene (or a dome profile) through a table of
 * keys (internal to src/scene). The binder checks each value's type and the
 * ranges the table gives; the checks that involve several keys are done
 * afterwards by each stage (orr_X_prepare) and, for those that span stages,
 * by scene_check.c, which use the marks recorded here to say where each key
 * was set. */
#ifndef ORR_SCENE_SCENE_BIND_H
#define ORR_SCENE_SCENE_BIND_H

#include "core/keys.h"
#include "scene/scene.h"
#include "scene/ytree.h"

#define SCENE_MAX_KEYS 192

/* A dome profile, domes/NAME.yaml: defaults for a dome master. */
typedef struct dome_profile {
    char description[256]; /* description: one line for people */
    double fov;            /* fov: 90..360 degrees, -> camera.dome_fov */
    double tilt;           /* tilt: 0..90 degrees, -> camera.dome_tilt */
    int size;              /* size: 1..65536 pixels, -> image.width and image.height */
    int has_fov, has_tilt, has_size;
} dome_profile;

/* Where a key was set: origin is NULL when it was not. */
typedef struct scene_loc {
    const char *origin;
    int line;
} scene_loc;

typedef struct scene_marks {
    scene_loc loc[SCENE_MAX_KEYS];
} scene_marks;

/* Stores every key of root (a mapping) in s, which holds the defaults and
 * s->dir, and records in marks where each key was set. */
orr_status scene_bind(orr_scene *s, const yt_node *root, scene_marks *marks, orr_error *err);

/* Stores every key of root (a mapping) in p, which starts zeroed; unknown
 * keys and bad values are errors naming the origin and line of the node. */
orr_status dome_profile_bind(dome_profile *p, const yt_node *root, orr_error *err);

/* Where key was set, or NULL when the scene does not set it. */
const scene_loc *scene_mark(const scene_marks *marks, const char *key);

/* Writes "origin:line: " (or "origin: " for overrides, whose line is 0). */
void scene_loc_prefix(const char *origin, int line, char *buf, size_t size);

/* Fails with ORR_ERR_USAGE and "origin:line: " (or "origin: ") before the formatted text. */
orr_status scene_fail_at(orr_error *err, const char *origin, int line, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

/* A scene's keys as the stages' checks see them (core/keys.h): whether
 * each was given and where. s and m must outlive the result. */
typedef struct scene_keyed {
    const orr_scene *s;
    const scene_marks *m;
} scene_keyed;
orr_keys scene_keys(const scene_keyed *k);

/* Fails with ORR_ERR_USAGE and "origin:line: " of key (or the scene path
 * when the key was not set) before the formatted text. */
orr_status scene_fail_key(const orr_scene *s, const scene_marks *m, const char *key, orr_error *err,
                          const char *fmt, ...) __attribute__((format(printf, 5, 6)));

#endif
