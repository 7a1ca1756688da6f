/* Pixels as surface brightness: the splat deposits each particle's weight
 * (its flux) into pixels, and a pixel's share depends on how much sky (or
 * area) it covers, which varies across a dome master, a panorama or a wide
 * perspective frame. Dividing each pixel by what it covers (its solid angle,
 * or its area for orthographic views: frame/projection.h) makes a uniform
 * sky uniform on every projection, and a star's flux the sum of its pixels
 * times their solid angles wherever it falls. docs/output.md. */
#ifndef ORR_POST_BRIGHTNESS_H
#define ORR_POST_BRIGHTNESS_H

#include "frame/projection.h"
#include "core/plane.h"

/* Divides every pixel of planes[0..n) (each of the projection's size) by
 * orr_pixel_measure. Rows run in parallel; each pixel's result depends on
 * that pixel alone, so it is the same on any thread count. */
void orr_to_surface_brightness(const orr_projection *p, orr_plane *planes, int n);

/* The FITS unit (FITS standard 4.0, section 4.3; astropy's "fits" format
 * parses it) of a plane of surface brightness of weights in weight_unit:
 * "W sr-1" for sky maps and perspective, "W L-2" per squared length_unit for
 * orthographic. An empty weight_unit is an unknown one: the weight is then a
 * pure number ("sr-1"). An orthographic plane without a length unit gets ""
 * (no BUNIT): per an unknown area has no FITS unit. */
void orr_brightness_unit(const orr_projection *p, const char *weight_unit, const char *length_unit, char *out,
                         size_t size);

#endif
