/* Alpha for the map's outline: each pixel's coverage of the map (1 inside a
 * dome master's circle or a Hammer-Aitoff ellipse, and every pixel of the
 * other projections; 0 off it; on the outline the share of the pixel
 * inside, so the edge is anti-aliased as compositors expect of alpha), so
 * a planetarium's or a compositor's software needs no mask of its own. */
#ifndef ORR_RENDER_MAP_ALPHA_H
#define ORR_RENDER_MAP_ALPHA_H

#include "core/error.h"
#include "frame/projection.h"

/* The share of pixel (i, j) inside the map's outline, in steps of 1/256. */
float orr_map_pixel_coverage(const orr_projection *p, int i, int j);

/* Row j's coverages into out[width]: orr_map_pixel_coverage's values,
 * sampled only along the outline. */
void orr_map_row_coverage(const orr_projection *p, int j, float *out);

/* Fills alpha[width * height] with the coverage (row 0 at the top). */
void orr_map_alpha_fill(const orr_projection *p, float *alpha);

/* A picture with its alpha: *rgba gets width * height * 4 values (to free),
 * each pixel rgb's three (not premultiplied) then its coverage; where the
 * coverage is 0 the colour is 0. */
orr_status orr_map_rgba(const orr_projection *p, const float *rgb, float **rgba, orr_error *err);

#endif
