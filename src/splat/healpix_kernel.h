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

#include <stdatomic.h>
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

/* A frame's work limit, shared by the threads: a kernel costs one
 * evaluation per sub-pixel centre inside its support, about 6 (1 - cos R)
 * nside_f^2 for a support of angular radius R, so a camera among the
 * particles, whose nearest kernels cover much of the sky, costs up to
 * 12 nside^2 per particle: at nside 4096 hours. The deposits stop once
 * `limit` samples are taken, and the frame is refused (pass/splat_pass.c)
 * rather than left to run for hours. */
typedef struct orr_healpix_budget {
    uint64_t limit;              /* kernel samples a frame may take */
    int64_t expected;            /* particles the frame has (0: unknown) */
    _Atomic uint64_t samples;    /* taken (or asked for) so far this frame */
    _Atomic uint64_t particles;  /* kernels deposited so far this frame */
    _Atomic uint64_t foreseen, foreseen_particles; /* the blocks' estimates, made before their deposits */
    _Atomic int exceeded;        /* 1 once a kernel was refused, or the frame foreseen far beyond */
    /* Progress on a long frame: called with the kernels deposited and the
     * frame's particles, by one thread at a time, every second or so. */
    void (*progress)(void *user, uint64_t done, int64_t total);
    void *progress_user;
    _Atomic int reporting;       /* 1 while a thread calls progress */
    _Atomic int64_t next_report; /* when, in ms of CLOCK_MONOTONIC */
} orr_healpix_budget;

/* About a minute of work on one core (2e9 samples at some 3e7 a second). */
#define ORR_HEALPIX_SAMPLE_LIMIT_PER_THREAD 2000000000ull

/* Zeroes the counts for a frame of `expected` particles (0: unknown). */
void orr_healpix_budget_start(orr_healpix_budget *b, uint64_t limit, int64_t expected);

/* The samples a kernel of angular size theta costs on a map of nside. */
uint64_t orr_healpix_kernel_cost(int64_t nside, double theta);

/* Adds a block's n particles and their estimated samples; 0 (and the
 * budget exceeded) when the frame's particles at that rate would need
 * more than four times the limit: refused at once, not after the limit's
 * minutes of work. */
int orr_healpix_budget_foresee(orr_healpix_budget *b, uint64_t samples, size_t n);

/* A map and its kernel. */
typedef struct orr_healpix_target {
    const orr_kernel *kernel;
    int64_t nside;
    int nested;  /* the map's pixels in NESTED order, else RING */
    float *data; /* 12 nside^2 pixels */
    orr_healpix_budget *budget; /* NULL: no limit */
} orr_healpix_target;

/* Adds weight w, spread by a kernel of angular size theta (radians) about
 * the unit vector dir (HEALPix's frame: z the pole, x toward phi = 0), to
 * the map. Returns 0 when out of memory for the scratch list (nothing
 * added: the caller deposits the particle as a point), -1 when the kernel
 * would go beyond the budget (nothing added: the frame is refused). */
int orr_healpix_kernel_deposit(const orr_healpix_target *t, const double dir[3], double theta, float w,
                               orr_healpix_scratch *scratch);

#endif
