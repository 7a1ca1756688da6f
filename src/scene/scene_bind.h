/* Binding a YAML tree to an orr_scene through one table of keys (internal to
 * src/scene). The binder checks each value's type and range; the checks that
 * involve several keys are done afterwards in scene.c, which uses the marks
 * recorded here to say where each key was set. */
#ifndef ORR_SCENE_SCENE_BIND_H
#define ORR_SCENE_SCENE_BIND_H

#include "scene/scene.h"
#include "scene/ytree.h"

#define SCENE_MAX_KEYS 64

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

/* Where key was set, or NULL when the scene does not set it. */
const scene_loc *scene_mark(const scene_marks *marks, const char *key);

/* Writes "origin:line: " (or "origin: " for overrides, whose line is 0). */
void scene_loc_prefix(const char *origin, int line, char *buf, size_t size);

#endif
