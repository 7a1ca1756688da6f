/* Reading values inside list-valued scene keys (colour.populations,
 * compose.layers, camera.path.keyframes): where the value sits, for
 * messages ("scene.yaml:12: camera.path.keyframes[1].position: ..."), and
 * the number readers they share. */
#ifndef ORR_SCENE_SCENE_VALUE_H
#define ORR_SCENE_SCENE_VALUE_H

#include <stddef.h>

#include "core/error.h"
#include "scene/ytree.h"

typedef struct scene_at {
    const char *origin;
    int line;
    char path[160];
    orr_error *err;
} scene_at;

/* The place of entry e of the mapping at `at` ("path.key", e's line). */
scene_at scene_child_at(const scene_at *at, const yt_entry *e);

/* A finite number. */
orr_status scene_get_number(const scene_at *at, const yt_node *n, double *v);

/* A list of exactly count finite numbers; form (may be NULL) shows their
 * meaning in the message, e.g. "[x, y, z]". */
orr_status scene_get_numbers(const scene_at *at, const yt_node *n, double *v, size_t count, const char *form);

#endif
