/* SPH kernels on a HEALPix map (Gorski et al. 2005, ApJ 622, 759): a
 * particle's kernel is a cap of angular size theta = h / r on the sphere,
 * and each pixel it overlaps gets the kernel's integral over its area.
 *
 * The integral is a midpoint sum over equal-area sub-pixels: HEALPix's own
 * pixels at nside_f = nside 2^k, k the least level whose pixels are at most
 * theta / 4 across, so every kernel, however small against the map's
 * pixels, is sampled by some 200 to 800 sub-pixel centres (the column kernel
 * F, splat/kernel.h, at their angular distance as a chord, with the
 * Laplacian term for their size, as the other sky maps do); each sample
 * goes to the map pixel that contains its sub-pixel (NESTED: index >> 2k).
 * The sums are then scaled so that the particle's pixels add up to its
 * weight, in double: mass is conserved to float round-off. A kernel too
 * small for nside 2^29, or with no sub-pixel centre inside it, goes whole
 * into the pixel of its direction, as a point does.
 *
 * The sub-pixels inside the support are found ring by ring from the
 * pixelisation's ring geometry (orr_healpix_ring), without a pass over the
 * map; a kernel covering the sky costs a pass over its pixels.
 *
 * A sub-pixel's centre is not quite its centroid near the poles, so the
 * sum there is biased by a fraction of the sub-pixel's size: a uniform sky
 * of kernels comes out 0.25 % bright in the four pixels at each pole and
 * uniform to 0.01 % within 60 degrees of the equator (rms 0.013 % over the
 * map, tests/cli/check_healpix_kernels.py); sub-pixels of theta / 2
 * doubled the poles' excess. */
#ifndef ORR_SPLAT_HEALPIX_KERNEL_H
#define ORR_SPLAT_HEALPIX_KERNEL_H

#include <stddef.h>
#include <stdint.h>

#include "splat/kernel.h"

/* Ring i (1 to 4 nside - 1, from the north pole) of the RING scheme: its
 * pixels start + j, j = 0 .. n - 1, have their centres at z = cos(colatitude)
 * and longitude phi0 + j 2 pi / n. */
typedef struct orr_healpix_ring {
    double z, sin_theta, phi0;
    int64_t start, n;
} orr_healpix_ring;

orr_healpix_ring orr_healpix_ring_at(int64_t nside, int64_t i);

/* What a deposit collects for one particle before it is scaled: the map
 * pixels and their weights. One per thread; zeroed is empty. */
typedef struct orr_healpix_share {
    int64_t pixel;
    double weight;
} orr_healpix_share;

typedef struct orr_healpix_scratch {
    orr_healpix_share *share;
    size_t n, room;
} orr_healpix_scratch;

void orr_healpix_scratch_free(orr_healpix_scratch *s);

/* A map and its kernel. */
typedef struct orr_healpix_target {
    const orr_kernel *kernel;
    int64_t nside;
    int nested;  /* the map's pixels in NESTED order, else RING */
    float *data; /* 12 nside^2 pixels */
} orr_healpix_target;

/* Adds weight w, spread by a kernel of angular size theta (radians) about
 * the unit vector dir (HEALPix's frame: z the pole, x toward phi = 0), to
 * the map. Returns 0 when out of memory for the scratch list (nothing
 * added: the caller deposits the particle as a point). */
int orr_healpix_kernel_deposit(const orr_healpix_target *t, const double dir[3], double theta, float w,
                               orr_healpix_scratch *scratch);

#endif
