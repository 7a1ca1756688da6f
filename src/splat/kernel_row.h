/* Rows of midpoint samples of a column kernel, the inner loop of large
 * kernels (splat/sph.c): F(u) + lap * lap F(u) at the pixel centres of one
 * image row, u = q^2 from the kernel's ellipse.
 *
 * The samples come from the kernel's piecewise polynomials (splat/kernel.h),
 * evaluated by Horner's rule. On a CPU with AVX-512 sixteen samples are
 * computed at once, each picking its piece's coefficients from two
 * registers with one permute (the 32 pieces' values of one coefficient
 * fill two registers); with AVX2, eight, from four registers; elsewhere a
 * plain loop. All do the same operations in the same order, none fused,
 * so every CPU gives the same bits. */
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
 * a dx^2 + 2 b dx dy + c dy^2), into out[m] as mode says, by the fastest
 * loop this CPU has. */
void orr_sample_row(const orr_sample_poly *p, float a, float bdy, float cdy, float dx0, int m0, int m1,
                    float *out, orr_sample_mode mode, float scale);

/* One image row's samples for orr_sample_spans_draw: dx = dx0 + m, m in
 * [m0, m1), bdy and cdy as for orr_sample_row, into out[m]. */
typedef struct orr_sample_span {
    float bdy, cdy;
    int m0, m1;
    float *out;
} orr_sample_span;

/* out[m] += scale * sample over each of n spans (one ellipse: the same a
 * and dx0), with the same bits as orr_sample_row in ORR_SAMPLES_DRAW mode
 * span by span. The spans must not overlap, and each one's out must take
 * the columns of the others (rows of one image, columns on the image: the
 * vector loop forms out + m over their union, touching only its own
 * columns). With AVX-512 four spans are
 * computed at once: one row's samples are a chain of dependent operations
 * some 60 cycles long, and a large kernel's rows are only a few vectors
 * wide, so a row alone leaves the core waiting. */
void orr_sample_spans_draw(const orr_sample_poly *p, float a, float dx0, const orr_sample_span *spans, int n,
                           float scale);

/* The loops, for the tests (each must match the plain one bit for bit). */
typedef enum orr_sample_rows {
    ORR_ROWS_PLAIN,  /* a loop a sample (vectorised by the compiler with gathers) */
    ORR_ROWS_AVX2,   /* eight samples, coefficients by four permutes and two blends */
    ORR_ROWS_AVX512, /* sixteen samples, coefficients by one two-register permute */
} orr_sample_rows;

/* The fastest this CPU runs. */
orr_sample_rows orr_sample_rows_best(void);

/* With the given loop, which the CPU must run (rows <= orr_sample_rows_best()). */
void orr_sample_row_with(orr_sample_rows rows, const orr_sample_poly *p, float a, float bdy, float cdy, float dx0,
                         int m0, int m1, float *out, orr_sample_mode mode, float scale);

/* The plain loop, which every CPU runs. */
void orr_sample_row_plain(const orr_sample_poly *p, float a, float bdy, float cdy, float dx0, int m0, int m1,
                          float *out, orr_sample_mode mode, float scale);

#endif
