/* Rows of midpoint samples of a column kernel, the inner loop of large
 * kernels (splat/sph.c): F(u) + lap * lap F(u) at the pixel centres of one
 * image row, u = q^2 from the kernel's ellipse.
 *
 * The samples come from the kernel's piecewise polynomials (splat/kernel.h),
 * evaluated by Horner's rule with fused multiply-adds. On a CPU with
 * AVX-512 sixteen samples are computed at once, each picking its piece's
 * coefficients from two registers with one permute (the 32 pieces' values
 * of one coefficient fill two registers); elsewhere a plain loop does the
 * same operations in the same order. A fused multiply-add is rounded once
 * (fmaf, exactly as the instruction), so both give the same bits. */
#ifndef ORR_SPLAT_KERNEL_ROW_H
#define ORR_SPLAT_KERNEL_ROW_H

#include "splat/kernel.h"

/* One kernel's sample polynomial: F + lap * lap F, coefficient d of piece
 * p at c[d][p]. */
typedef struct orr_sample_poly {
    _Alignas(64) float c[ORR_KERNEL_POLY_DEGREE + 1][ORR_KERNEL_POLY_PIECES];
} orr_sample_poly;

/* lap: the midpoint rule's correction, (sample area / 24) / h^2 in units
 * of the kernel's u. */
void orr_sample_poly_make(orr_sample_poly *p, const orr_kernel *k, float lap);

/* The sample at t = ORR_KERNEL_POLY_T u: 0 from the support's edge
 * (t >= 32) on. */
float orr_sample_poly_at(const orr_sample_poly *p, float t);

typedef enum orr_sample_mode {
    ORR_SAMPLES_SET,  /* out[m] = sample */
    ORR_SAMPLES_ADD,  /* out[m] += sample */
    ORR_SAMPLES_DRAW, /* out[m] += scale * sample: out is an image row */
} orr_sample_mode;

/* The samples of a row at dx = dx0 + m, m in [m0, m1), where
 * u = (a dx + bdy) dx + cdy (bdy = 2 b dy, cdy = c dy^2 for the ellipse
 * a dx^2 + 2 b dx dy + c dy^2), into out[m] as mode says. Picks the AVX-512
 * loop when the CPU has it. */
void orr_sample_row(const orr_sample_poly *p, float a, float bdy, float cdy, float dx0, int m0, int m1,
                    float *out, orr_sample_mode mode, float scale);

/* The plain loop alone (for the tests: it must match the vector loop bit
 * for bit). */
void orr_sample_row_plain(const orr_sample_poly *p, float a, float bdy, float cdy, float dx0, int m0, int m1,
                          float *out, orr_sample_mode mode, float scale);

/* 1 when orr_sample_row uses the AVX-512 loop on this CPU. */
int orr_sample_row_vector(void);

#endif
