/* The colour.populations list of a scene: named particle populations, each
 * with a selection, a colour and a luminance rule (docs/colour.md). */
#ifndef ORR_SCENE_SCENE_COLOUR_H
#define ORR_SCENE_SCENE_COLOUR_H

#include "scene/scene.h"
#include "scene/ytree.h"

/* Binds the list n (at origin:line, key path) into s->populations and turns
 * colour on; errors name the file, line and the population's key. */
orr_status scene_bind_populations(orr_scene *s, const char *origin, int line, const char *path, const yt_node *n,
                                  orr_error *err);

/* Binds colour.tint.path, a list of 1 to ORR_COLOUR_PATH_MAX temperatures. */
orr_status scene_bind_tint(orr_scene *s, const char *origin, int line, const char *path, const yt_node *n,
                           orr_error *err);

/* Binds compose.layers, a list of {file, colour, gain}. */
orr_status scene_bind_layers(orr_scene *s, const char *origin, int line, const char *path, const yt_node *n,
                             orr_error *err);

#endif
