/* Binding a scene tree and the checks across keys (internal to src/scene). */
#ifndef ORR_SCENE_SCENE_CHECK_H
#define ORR_SCENE_SCENE_CHECK_H

#include "scene/scene.h"
#include "scene/ytree.h"

/* Binds root (a mapping) to s, which holds the defaults, s->path and s->dir,
 * then has each stage check its keys against each other, checks the rules
 * that span stages and applies the dome profile. Errors name the key and
 * where it was set. */
orr_status scene_bind_checked(orr_scene *s, const yt_node *root, orr_error *err);

#endif
