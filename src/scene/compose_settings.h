/* compose.layers' settings, which the scene holds (scene/scene.h) and the
 * plan copies into each view's files (render/view_files.h): a header of
 * their own, so the renderer's stages take them without the scene. */
#ifndef ORR_SCENE_COMPOSE_SETTINGS_H
#define ORR_SCENE_COMPOSE_SETTINGS_H

#include "core/error.h"
#include "post/colour.h"

/* compose.layers: `orrery compose` (render/compose.c) blends raw planes of
 * several renders (e.g. one per population, or single-channel maps of
 * different particle types) with colours assigned there, then synthesises. */
typedef struct orr_compose_layer {
    char *file;              /* a raw FITS file: one luminance plane, or X, Y, Z; owned (core/owned.h) */
    int has_colour;
    orr_colour colour;       /* required for a luminance plane */
    double gain;             /* multiplies the layer (default 1) */
} orr_compose_layer;

#define ORR_COMPOSE_LAYERS_MAX 8

typedef struct orr_compose_settings {
    int nlayers;
    orr_compose_layer layers[ORR_COMPOSE_LAYERS_MAX];
} orr_compose_settings;

/* c's owned strings (core/owned.h), every layer's file (NULL when unused),
 * ORR_COMPOSE_STRINGS of them, into fields; returns how many. */
#define ORR_COMPOSE_STRINGS ORR_COMPOSE_LAYERS_MAX
int orr_compose_settings_strings(orr_compose_settings *c, char **fields[]);
/* Frees c's strings (core/owned.h). */
void orr_compose_settings_free(orr_compose_settings *c);
/* dst (its strings freed first) becomes a copy of src with strings of its own. */
orr_status orr_compose_settings_copy(orr_compose_settings *dst, const orr_compose_settings *src, orr_error *err);

#endif
