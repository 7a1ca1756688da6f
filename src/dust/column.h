/* Optical depth through dust particles (docs/dust.md).
 *
 * Each dust particle is an SPH kernel W(r, h) = sigma w(r/h) / h^3 of the
 * renderer's own kernel (splat/kernel.h, support 2h) carrying an opacity
 * k = kappa_V * dust_to_gas * mass (an area), so the V-band optical depth
 * along a segment is
 *
 *     tau_V = sum_j k_j * integral over the segment of W(|r - x_j|, h_j) dl.
 *
 * Two ways to get it:
 * - orr_dust_tau_exact: every kernel, each integral by Gauss-Legendre
 *   quadrature of the kernel formula itself: slow, the tests' truth.
 * - orr_dust_tau: a bounding-volume tree over the kernels' supports, walked
 *   along the segment; each kernel the segment meets adds
 *   k / h^2 * (P(b/h, s1/h) - P(b/h, s0/h)), where b is the segment's
 *   closest approach to the kernel's centre, s0 and s1 its ends measured from
 *   there, and P(beta, s) the integral of sigma w(sqrt(beta^2 + t^2)) over
 *   t < s, tabulated once. Exact up to the table's interpolation, including
 *   kernels that contain the eye or the star; independent of thread count
 *   (each segment's sum is taken in the tree's fixed order). */
#ifndef ORR_DUST_COLUMN_H
#define ORR_DUST_COLUMN_H

#include <stddef.h>
#include <stdint.h>

#include "core/error.h"
#include "splat/kernel.h"

/* Partial column table P(beta, s) at beta = 2 i / NB, s = 2 j / NS. */
#define ORR_DUST_PCOL_NB 256
#define ORR_DUST_PCOL_NS 256
/* The whole column F(beta) in u = beta^2 (no square root for a kernel
 * crossed whole), at u = 4 i / NU. */
#define ORR_DUST_FCOL_NU 2048

typedef struct orr_dust_node {
    float lo[3], hi[3]; /* bounds of the kernels' supports (centre +- 2h) */
    uint32_t first;     /* leaf: first particle (in tree order); inner: left child (right = left + 1) */
    uint32_t count;     /* leaf: particles; 0 for an inner node */
} orr_dust_node;

typedef struct orr_dust_set {
    size_t n, cap;
    float *x, *y, *z, *h; /* positions and smoothing lengths (support 2h) */
    float *k;             /* opacity kappa * dust_to_gas * mass: an area */
    float *ih, *kih2;     /* after the build: 1 / h and k / h^2, which the walk uses */
    orr_kernel_kind kernel_kind;
    double sigma;         /* the kernel's 3-D normalisation */
    orr_kernel kernel;    /* its formula (orr_kernel_shape) */
    int kernel_ready;
    float *pcol;          /* (NB + 1) x (NS + 1): row i = beta, column j = s >= 0 */
    float *fcol;          /* ORR_DUST_FCOL_NU + 1: the whole column F at u = beta^2 = 4 i / NU */
    orr_dust_node *nodes; /* the tree, root at 0, after orr_dust_set_build */
    size_t nnodes;
} orr_dust_set;

/* An empty set for the given kernel (its tables built: about 20 ms). */
orr_status orr_dust_set_init(orr_dust_set *s, orr_kernel_kind kernel, orr_error *err);
void orr_dust_set_free(orr_dust_set *s);

/* Appends one particle (h > 0 and k >= 0 finite: the caller checks and
 * names bad ones). The tree must be rebuilt afterwards. */
orr_status orr_dust_set_add(orr_dust_set *s, float x, float y, float z, float h, float k, orr_error *err);

/* Builds the tree (reorders the particles). */
orr_status orr_dust_set_build(orr_dust_set *s, orr_error *err);

/* P(beta, s) from the table (any s; beta >= 2 gives 0). */
double orr_dust_partial_column(const orr_dust_set *s, double beta, double sv);

/* tau_V along the segment from eye to p, by the tree (after build). */
double orr_dust_tau(const orr_dust_set *s, const double eye[3], const double p[3]);
/* tau_V from eye to each of the n points (x[i], y[i], z[i]) with want[i]
 * nonzero (want NULL: every point) into tau[i]; 0 for the others. The
 * stars are grouped by direction and each group shares one traversal of the
 * tree (column_group.c); each value is orr_dust_tau's for that point bit for
 * bit, whatever the other points and the number of threads. Fails only
 * when out of memory. */
orr_status orr_dust_tau_many(const orr_dust_set *s, const double eye[3], size_t n, const float *x, const float *y,
                             const float *z, const unsigned char *want, double *tau, orr_error *err);
/* How orr_dust_tau_many_with computes a star's terms over its group's
 * candidates: eight stars at once with AVX-512, else with AVX2, where the
 * CPU has them (BEST, what orr_dust_tau_many does); eight stars at once
 * with AVX2 where the CPU has it (EIGHT_AVX2, what CPUs without AVX-512
 * run); or one star and one term at a time (PLAIN, what other CPUs run);
 * the same bits every way. */
typedef enum { ORR_DUST_TERMS_BEST, ORR_DUST_TERMS_EIGHT_AVX2, ORR_DUST_TERMS_PLAIN } orr_dust_terms;
orr_status orr_dust_tau_many_with(orr_dust_terms terms, const orr_dust_set *s, const double eye[3], size_t n,
                                  const float *x, const float *y, const float *z, const unsigned char *want,
                                  double *tau, orr_error *err);
/* tau_V from eye to infinity along the unit direction dir. */
double orr_dust_tau_ray(const orr_dust_set *s, const double eye[3], const double dir[3]);

/* The same by brute force over every kernel, by quadrature of the formula. */
double orr_dust_tau_exact(const orr_dust_set *s, const double eye[3], const double p[3]);

#endif
