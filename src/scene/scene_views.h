/* Views: several scenes from one file, each the base scene with the keys of
 * one entry of `views:` merged in (internal to src/scene). */
#ifndef ORR_SCENE_SCENE_VIEWS_H
#define ORR_SCENE_SCENE_VIEWS_H

#include "scene/scene.h"
#include "scene/ytree.h"

/* Where a scene came from; every view gets the same. */
typedef struct scene_source {
    const char *path; /* for messages, and orr_scene.path; outlives the tree */
    const char *dir;  /* relative paths in the scene are resolved against it */
    const char *stem; /* the default output name */
} scene_source;

/* An override "views.NAME.KEY=..." must name a view the scene has: otherwise
 * a typo in NAME would quietly add a view. Setting "views.NAME" whole may add
 * one. Other keys pass. */
orr_status scene_views_check_override(const yt_node *root, const char *key, const char *origin,
                                      orr_error *err);

/* Fills out from root, the scene tree after the overrides (its `views` entry
 * is taken out): one unnamed scene when there are no views, else one per
 * view, each bound and checked. */
orr_status scene_views_from_tree(orr_scene_views *out, yt_node *root, const scene_source *src, orr_error *err);

#endif
