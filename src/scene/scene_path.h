/* The camera.path.* keys of a scene (docs/paths.md): the keyframe list's
 * binder, and the checks across the path's keys and the camera's. */
#ifndef ORR_SCENE_SCENE_PATH_H
#define ORR_SCENE_SCENE_PATH_H

#include "scene/scene.h"
#include "scene/scene_bind.h"
#include "scene/ytree.h"

/* Binds camera.path.keyframes, a list of 2 to ORR_PATH_KEYFRAMES_MAX
 * mappings {frame, position, look_at | direction | quaternion, up, roll}
 * in increasing frame order; errors name the file, line and keyframe. */
orr_status scene_bind_keyframes(orr_scene *s, const char *origin, int line, const char *path, const yt_node *n,
                                orr_error *err);

/* The checks across keys: camera.path.* needs camera.path.kind; a path
 * excludes observer.id and (but for kind rotate) the camera's placement;
 * each kind takes its own keys and needs some of them; reads
 * camera.path.file; completes the path (orbit plane, rotate's start). */
orr_status scene_check_path(orr_scene *s, const scene_marks *m, orr_error *err);

#endif
