/* SPH smoothing kernels and their column (line-of-sight) integrals.
 *
 * Every kernel has compact support of radius 2h, SPLASH's convention, so
 * images compare with SPLASH's: W(r, h) = sigma w(r / h) / h^3 with
 * w(q) = 0 for q >= 2. The column kernel F(q) = h^2 * integral of W along
 * a line passing at distance q h from the particle is dimensionless, and
 * a particle of mass m has surface density m F(R / h) / h^2 at projected
 * distance R; the integral of F over the plane is 1.
 *
 * orr_kernel_init tabulates F (and its Laplacian, for the pixel-area
 * correction) in u = q^2, fits both with piecewise polynomials in u, and
 * tabulates the integral of F over rectangles from the kernel's centre
 * and the separable expansion, once, by numerical integration; the
 * splat's inner loops only read these tables and coefficients
 * (splat/sph.h, splat/kernel_row.h). */
#ifndef ORR_SPLAT_KERNEL_H
#define ORR_SPLAT_KERNEL_H

#include "core/error.h"
#include "core/names.h"

typedef enum {
    ORR_KERNEL_CUBIC,       /* M4 cubic spline (the default) */
    ORR_KERNEL_WENDLAND_C2,
    ORR_KERNEL_WENDLAND_C4,
} orr_kernel_kind;

#define ORR_KERNEL_SUPPORT 2.0 /* support radius in units of h */

/* The column tables hold F and its Laplacian at u = q^2 = 4 k / ORR_KERNEL_NU,
 * k = 0 .. ORR_KERNEL_NU (u = 4 is the edge of the support, where both are
 * zero), interleaved as pairs {F, lap F} so one cache line serves both,
 * then ORR_KERNEL_PAD zero pairs, so a read a little past the support
 * (float rounding at a footprint's edge) finds zeros without a test. */
#define ORR_KERNEL_NU 4096
#define ORR_KERNEL_PAD 4
/* The cumulative table holds G(a, b) = integral of F over [0, a] x [0, b] at
 * a, b = 2 k / ORR_KERNEL_NG, k = 0 .. ORR_KERNEL_NG. */
#define ORR_KERNEL_NG 256

/* F and lap F as piecewise polynomials in t = ORR_KERNEL_POLY_T u, for the
 * vectorised sample loops (splat/kernel_row.h), which pick each sample's
 * coefficients with a register permute instead of reading a table.
 * Piece p covers t in [0, 1/4) (p = 0), [1/4, 1) (p = 1), [p - 1, p)
 * (p = 2 .. 30) and [30, 32) (p = 31), and is a polynomial of degree
 * ORR_KERNEL_POLY_DEGREE in x = t - min(trunc(t), 30). The two narrow
 * pieces at the centre are there because F is not smooth at u = 0 (the
 * kernels' odd powers of q give u^2 log u terms); the cubic spline's joint
 * at q = 1 (t = 8) is a piece edge. */
#define ORR_KERNEL_POLY_T 8.0f
#define ORR_KERNEL_POLY_PIECES 32
#define ORR_KERNEL_POLY_DEGREE 5
#define ORR_KERNEL_POLY_LAST 30 /* the largest truncation of t that is subtracted */

/* The separable expansion of F over the plane (splat/kernel_separable.c):
 * F(x, y) ~ sum over k < ORR_KERNEL_SEP_RANK of s_k f_k(x) f_k(y), the
 * leading terms of its eigen-expansion (f_k the k-th eigenfunction times
 * the square root of |lambda_k|, s_k = +1 or -1 the sign of lambda_k),
 * so the integral of F over any pixel is
 * sum_k s_k (E_k(x1) - E_k(x0)) (E_k(y1) - E_k(y0)) with E_k the integral
 * of f_k from 0: a pixel costs ORR_KERNEL_SEP_RANK multiply-adds once the
 * differences along each axis are known. E_k is odd; the table holds
 * E_k(x) for x = 2 i / ORR_KERNEL_SEP_N, i = 0 .. ORR_KERNEL_SEP_N, the
 * ORR_KERNEL_SEP_RANK values of one x together, then one copy of the last
 * row, so a read at the support's edge needs no test. */
#define ORR_KERNEL_SEP_RANK 8
#define ORR_KERNEL_SEP_N 4096

typedef struct orr_kernel {
    orr_kernel_kind kind;
    double sigma;      /* 3-D normalisation: W(r, h) = sigma w(r / h) / h^3 */
    float *column;     /* 2 (ORR_KERNEL_NU + 1 + ORR_KERNEL_PAD) floats: {F, lap F} pairs */
    float *cumulative; /* (ORR_KERNEL_NG + 1)^2 floats, row b, column a; G(2, 2) = 1/4 exactly */
    /* Coefficient d of piece p at poly_f[d * ORR_KERNEL_POLY_PIECES + p]
     * (lap F: poly_lap), so one coefficient of all pieces is one row. */
    float poly_f[(ORR_KERNEL_POLY_DEGREE + 1) * ORR_KERNEL_POLY_PIECES];
    float poly_lap[(ORR_KERNEL_POLY_DEGREE + 1) * ORR_KERNEL_POLY_PIECES];
    float *separable; /* (ORR_KERNEL_SEP_N + 2) * ORR_KERNEL_SEP_RANK floats: E_k(x) */
    float separable_sign[ORR_KERNEL_SEP_RANK];
} orr_kernel;

/* Tabulates the kernel (about 10 ms). Fails only when out of memory (or,
 * which the tests would show, if the expansion's eigenvectors did not
 * converge). */
orr_status orr_kernel_init(orr_kernel *k, orr_kernel_kind kind, orr_error *err);
void orr_kernel_free(orr_kernel *k);

/* The kernels' own names (orr_kernel_parse also takes SPLASH-style aliases). */
extern const orr_named orr_kernel_names[];
const char *orr_kernel_name(orr_kernel_kind kind);
/* Accepts "cubic" (also "m4", "cubic-spline"), "wendland-c2" ("wendland2",
 * "c2") and "wendland-c4" ("wendland4", "c4"); returns ORR_ERR_USAGE, with a
 * message listing the names, for anything else. */
orr_status orr_kernel_parse(const char *name, orr_kernel_kind *kind, orr_error *err);

/* The dimensionless shape w(q) and the 3-D kernel W(r, h) = sigma w(r/h) / h^3,
 * from the formulas. */
double orr_kernel_shape(const orr_kernel *k, double q);
double orr_kernel_w3(const orr_kernel *k, double r, double h);

/* The column kernel F(q) by direct numerical integration along the line of
 * sight (slow: for tests and for building the tables). */
double orr_kernel_column_exact(const orr_kernel *k, double q);
/* The column kernel F(q) from the table (linear in q^2). */
double orr_kernel_column(const orr_kernel *k, double q);

/* The integral of F over the rectangle [x0, x1] x [y0, y1] (in units of h,
 * relative to the kernel's centre), from the cumulative table: exact
 * telescoping sums, so adjacent rectangles tiling the support add up to 1. */
double orr_kernel_rect(const orr_kernel *k, double x0, double x1, double y0, double y1);

/* The piece of t = ORR_KERNEL_POLY_T u (t >= 0) and the local variable x. */
static inline int orr_kernel_poly_piece(float t, float *x)
{
    const int ti = t < (float)ORR_KERNEL_POLY_LAST ? (int)t : ORR_KERNEL_POLY_LAST;
    *x = t - (float)ti;
    return t < 1.0f ? (t < 0.25f ? 0 : 1) : ti + 1;
}

/* The separable expansion's integrals E_k at x (in units of h, any sign:
 * clamped to the support), all ORR_KERNEL_SEP_RANK of them into e. */
static inline void orr_kernel_separable_at(const orr_kernel *k, float x, float *restrict e)
{
    const float support = (float)ORR_KERNEL_SUPPORT;
    const float ax = x < 0.0f ? (x > -support ? -x : support) : (x < support ? x : support);
    const float t = ax * (float)(ORR_KERNEL_SEP_N / ORR_KERNEL_SUPPORT);
    const int i = (int)t;
    const float f = t - (float)i, sign = x < 0.0f ? -1.0f : 1.0f;
    const float *restrict row = k->separable + (size_t)i * ORR_KERNEL_SEP_RANK;
    for (int r = 0; r < ORR_KERNEL_SEP_RANK; r++)
        e[r] = sign * (row[r] + f * (row[r + ORR_KERNEL_SEP_RANK] - row[r]));
}

/* Table lookups for the inner loops. u = q^2 must be >= 0. */
static inline float orr_kernel_column_u(const orr_kernel *k, float u, float *laplacian)
{
    const float t = u * (float)(ORR_KERNEL_NU / 4.0);
    if (!(t < (float)ORR_KERNEL_NU)) {
        *laplacian = 0.0f;
        return 0.0f;
    }
    const int i = (int)t;
    const float f = t - (float)i;
    const float *c = k->column + 2 * i;
    *laplacian = c[1] + f * (c[3] - c[1]);
    return c[0] + f * (c[2] - c[0]);
}

#endif
