/* Smoothing lengths from the distance to the k-th nearest neighbour, for
 * snapshots that carry none (N-body particles: dark matter, stars).
 *
 * Convention (SPLASH, Monaghan): h is the smoothing length of a kernel with
 * compact support 2h, such as the cubic spline. With r_k the distance from
 * a particle to its k-th nearest neighbour, not counting the particle
 * itself,
 *
 *     h = factor * r_k,   factor = 0.5 by default,
 *
 * so the kernel's support 2h just reaches the k-th neighbour and each
 * kernel overlaps about k others, as in SPH with k neighbours. (Gadget's
 * HSML is the support radius itself: that is factor 1 in its convention.)
 *
 * The values are exact: r_k is the k-th smallest of the distances computed
 * in double (orr_kd_dist2), the same for any number of threads.
 *
 * - n <= k: every other particle is a neighbour, and h comes from the
 *   farthest one.
 * - n == 1: there is no neighbour; h = 0.
 * - h = 0 also when more than k other particles sit exactly at a
 *   particle's position.
 * - A non-finite position is an ORR_ERR_DATA error naming the particle's
 *   index (in the arrays given); nothing is skipped, so the caller decides
 *   whether to drop such particles first.
 * - Open boundaries: a periodic box is not wrapped, so particles near a face
 *   find their neighbours on one side only and get a larger h.
 *
 * Cost: O(n log n) to build the tree and about O(n (k + log n)) for the
 * queries, which run in parallel (OpenMP); memory 19 to 22 bytes per
 * particle for the tree plus 8 (k + 1) bytes per thread. */
#ifndef ORR_PARTICLES_SMOOTHING_H
#define ORR_PARTICLES_SMOOTHING_H

#include <stddef.h>

#include "core/error.h"
#include "core/names.h"
#include "particles/kdtree.h"

/* Where the SPH deposit's smoothing lengths come from (smoothing.lengths). */
typedef enum {
    ORR_LENGTHS_AUTO,       /* the file's, or the neighbours' when it has none */
    ORR_LENGTHS_FILE,       /* the file's; an error when it has none */
    ORR_LENGTHS_NEIGHBOURS, /* always from the k-th nearest neighbour */
} orr_smoothing_source;

extern const orr_named orr_smoothing_source_names[];

#define ORR_SMOOTHING_K_DEFAULT 32
#define ORR_SMOOTHING_FACTOR_DEFAULT 0.5f

/* Fills h_out[i] for the n particles at (x[i], y[i], z[i]). k >= 1 is the
 * neighbour rank, factor > 0 (finite) the multiple of r_k. Errors:
 * ORR_ERR_USAGE for a bad k or factor, or n above ORR_KD_MAX_POINTS;
 * ORR_ERR_DATA for a non-finite position; ORR_ERR_NOMEM. h_out is
 * unspecified after an error. */
orr_status orr_smoothing_lengths(size_t n, const float *x, const float *y, const float *z, int k,
                                 float factor, float *h_out, orr_error *err);

/* The same on a tree already built over the particles (h_out indexed like
 * the arrays the tree was built from): for reusing a tree, or timing the
 * build and the queries apart. */
orr_status orr_smoothing_lengths_tree(const orr_kdtree *tree, int k, float factor, float *h_out,
                                      orr_error *err);

/* The same, for callers that need some lengths only up to a limit: for
 * point i (indexed like the arrays) with enough[i] > 0, any value from its
 * length up to enough[i] will do (a glow as wide as the wider of two
 * lengths, the other one already wider: pass/lengths.h). Where a cheap
 * upper bound on the length is within enough[i] (the farthest corner, else
 * the farthest point, of the deepest k-d node around it that holds at
 * least k + 1 points), h_out[i] takes the bound and the neighbour search
 * is skipped; *skipped (may be NULL) says how many. Every other length
 * (enough NULL, or enough[i] 0, negative or NaN) is exact, as above; the
 * skipped ones and the count are the same on any number of threads. */
orr_status orr_smoothing_lengths_bounded(const orr_kdtree *tree, int k, float factor, const float *enough,
                                         float *h_out, size_t *skipped, orr_error *err);

#endif
