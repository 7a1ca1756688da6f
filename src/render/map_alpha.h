/* Alpha for the map's outline: 1 on the map (inside a dome master's circle,
 * a Hammer-Aitoff ellipse; every pixel of the other projections), 0 off it,
 * so a planetarium's or a compositor's software needs no mask of its own. */
#ifndef ORR_RENDER_MAP_ALPHA_H
#define ORR_RENDER_MAP_ALPHA_H

#include "core/error.h"
#include "frame/projection.h"

/* Fills alpha[width * height] (row 0 at the top). */
void orr_map_alpha_fill(const orr_projection *p, float *alpha);

/* A picture with its alpha: *rgba gets width * height * 4 values (to free),
 * each pixel rgb's three then its alpha; off the map the colour is 0. */
orr_status orr_map_rgba(const orr_projection *p, const float *rgb, float **rgba, orr_error *err);

#endif
