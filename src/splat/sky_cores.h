/* A sky map's PSF cores from a table of stamps (docs/psf.md, "Cores from
 * a table").
 *
 * With a PSF on a sky map every star is drawn as the PSF's core: a kernel
 * of one angular size, theta = h / r, everywhere (post/view_psf.h).
 * What it looks like in pixels depends only on where it falls: the map's
 * local scale and distortion (the ellipse of the local affine model,
 * splat/sph.c) and the star's offset within its pixel. So the map is cut
 * into cells of ORR_SKY_CORE_CELL pixels; the first star to land in a cell
 * has the cell's stamps made: the kernel with the cell centre's ellipse,
 * pixel-integrated exactly as the deposit does it (the same sub-sampled
 * midpoint rule), at (ORR_SKY_CORE_STEPS + 1)^2 sub-pixel offsets, each
 * normalised to 1. A star is then drawn as the bilinear blend of the four
 * stamps around its offset: four multiply-adds a pixel instead of the
 * kernel's samples, and no projection of its own.
 *
 * What the blend keeps: each stamp sums to 1, so a star's flux is its
 * weight (to float round-off); a stamp's centroid is its offset, and the
 * blend's is the same bilinear combination of them, so the centroid is
 * where the star is; the pixel values differ from the star's own
 * evaluation by the ellipse's change across half a cell and the blend's
 * smoothing over a quarter pixel (measured: docs/psf.md). A cell's stamps
 * depend on the cell alone, whichever thread makes them, so images are
 * the same bits on any thread count.
 *
 * Stars whose kernel is not the core alone (a smoothing length of their
 * own, in quadrature), whose stamp would leave the map or the image, or
 * that fall where the affine model does not hold (near the map's outline,
 * across seams) are drawn as before, one by one. */
#ifndef ORR_SPLAT_SKY_CORES_H
#define ORR_SPLAT_SKY_CORES_H

#include "core/error.h"
#include "core/plane.h"

#define ORR_SKY_CORE_CELL 64
#define ORR_SKY_CORE_STEPS 4

struct orr_sph;
typedef struct orr_sky_cores orr_sky_cores;

/* The table for the sky deposit s (its index built) and the core's angle. */
orr_status orr_sky_cores_create(orr_sky_cores **out, const struct orr_sph *s, double theta, orr_error *err);
void orr_sky_cores_free(orr_sky_cores *c);

/* Draws weight w at image point (px, py) from the stamps when the particle's
 * kernel (angular size theta) is the core and the table may draw it there;
 * returns 0, having drawn nothing, otherwise. Threads may share the table. */
int orr_sky_cores_draw(orr_sky_cores *c, const struct orr_sph *s, double px, double py, double theta, float w,
                       orr_plane *plane);
/* The same into nplanes planes of the map's size at once, weight w[k] into
 * planes[k] (colour's X, Y, Z): one look-up and each stamp row read once;
 * each plane gets the bits orr_sky_cores_draw gives it. */
int orr_sky_cores_draw_planes(orr_sky_cores *c, const struct orr_sph *s, double px, double py, double theta,
                              const float *w, orr_plane *planes, int nplanes);

/* Stamps made so far, and the bytes they hold (for reports and tests). */
void orr_sky_cores_usage(const orr_sky_cores *c, long *cells, size_t *bytes);

#endif
