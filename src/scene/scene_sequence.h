/* input.sequence.files, a list of paths, bound into an orr_scene (internal
 * to src/scene; the table-driven binder calls it for K_SEQ_FILES). */
#ifndef ORR_SCENE_SCENE_SEQUENCE_H
#define ORR_SCENE_SCENE_SEQUENCE_H

#include "scene/scene.h"
#include "scene/ytree.h"

/* Stores the list n (at least 2 paths) in s->input.sequence.files, each resolved
 * against s->dir as input.file is; errors name origin, line and path[i]. */
orr_status scene_bind_sequence_files(orr_scene *s, const char *origin, int line, const char *path, const yt_node *n,
                                     orr_error *err);

#endif
