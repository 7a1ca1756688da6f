/* A float accumulation plane: one channel of an image, row 0 at the top. */
#ifndef ORR_CORE_PLANE_H
#define ORR_CORE_PLANE_H

#include <stddef.h>

#include "core/error.h"

#define ORR_PLANE_NAME_MAX 64
/* The populations whose light a view can keep as planes of their own
 * (output.exr_population_layers), and so a view's planes at most: the
 * weight, or CIE X, Y, Z and then each population's X, Y, Z. */
#define ORR_POPULATION_LAYERS_MAX 8
#define ORR_PLANES_MAX (3 + 3 * ORR_POPULATION_LAYERS_MAX)

typedef struct orr_plane {
    int width, height;
    float *data; /* width * height values, row-major, row 0 at the top */
    char name[ORR_PLANE_NAME_MAX]; /* e.g. "mass": becomes the FITS EXTNAME */
    char unit[ORR_PLANE_NAME_MAX]; /* becomes the FITS BUNIT */
} orr_plane;

/* Allocates a zeroed plane; fails cleanly on absurd sizes. */
orr_status orr_plane_alloc(orr_plane *p, int width, int height, const char *name, const char *unit,
                           orr_error *err);
/* Zeroes an allocated plane again (a frame after the first), the large
 * ones on every thread. */
void orr_plane_clear(orr_plane *p);
void orr_plane_free(orr_plane *p);
/* Sum of all pixels, accumulated in double. */
double orr_plane_sum(const orr_plane *p);

#endif
