/* SPH kernels: 3-D and column normalisations, known values, the tables
 * against direct integration, the Laplacian table against finite
 * differences, rectangle integrals, the piecewise polynomials against the
 * exact kernel and the vector sample rows against the plain loop, names. */
#include <math.h>
#include <stdio.h>
#include <stdint.h>
#include <stdlib.h>

#include "check.h"
#include "core/vecmath.h"
#include "splat/kernel.h"
#include "splat/kernel_row.h"
#include "test_random.h"

static const orr_kernel_kind kinds[] = {ORR_KERNEL_CUBIC, ORR_KERNEL_WENDLAND_C2, ORR_KERNEL_WENDLAND_C4};

static orr_kernel make(orr_kernel_kind kind)
{
    orr_kernel k;
    orr_error err = {0};
    CHECK(orr_kernel_init(&k, kind, &err) == ORR_OK);
    return k;
}

/* Composite Simpson over [0, 2] with n (even) intervals of f(q) * weight(q). */
static double simpson(const orr_kernel *k, double (*f)(const orr_kernel *, double), int power, int n)
{
    double dq = 2.0 / n, s = 0.0;
    for (int i = 0; i <= n; i++) {
        double q = i * dq, c = i == 0 || i == n ? 1 : i % 2 ? 4 : 2;
        s += c * f(k, q) * pow(q, power);
    }
    return s * dq / 3.0;
}

static double w3_unit(const orr_kernel *k, double q) { return orr_kernel_w3(k, q, 1.0); }

static void test_3d_normalisation(void)
{
    for (int i = 0; i < 3; i++) {
        orr_kernel k = make(kinds[i]);
        /* Simpson's rule is accurate to 1e-9 here: the kernels are
         * polynomials between joints (q = 1, 2) that fall on grid points. */
        CHECK_NEAR(4 * ORR_PI * simpson(&k, w3_unit, 2, 2000), 1.0, 1e-6);
        /* W scales as 1/h^3: the integral over r with h = 2.5. */
        double h = 2.5, s = 0.0;
        int n = 4000;
        for (int j = 0; j <= n; j++) {
            double r = j * 2 * h / n, c = j == 0 || j == n ? 1 : j % 2 ? 4 : 2;
            s += c * 4 * ORR_PI * r * r * orr_kernel_w3(&k, r, h);
        }
        CHECK_NEAR(s * (2 * h / n) / 3, 1.0, 1e-6);
        CHECK(orr_kernel_w3(&k, 2.0, 1.0) == 0.0);
        CHECK(orr_kernel_w3(&k, 5.0, 1.0) == 0.0);
        CHECK(orr_kernel_shape(&k, 0.0) == 1.0);
        orr_kernel_free(&k);
    }
}

static void test_column_normalisation(void)
{
    for (int i = 0; i < 3; i++) {
        orr_kernel k = make(kinds[i]);
        /* The integral of F over the plane, from the exact column integral
         * and from the table; F's edge behaviour (2-q)^3.5 and more limits
         * Simpson's order, so use many points. */
        CHECK_NEAR(2 * ORR_PI * simpson(&k, orr_kernel_column_exact, 1, 4000), 1.0, 1e-6);
        CHECK_NEAR(2 * ORR_PI * simpson(&k, orr_kernel_column, 1, 20000), 1.0, 1e-6);
        orr_kernel_free(&k);
    }
}

/* F(0) = 2 sigma * integral of w over [0, 2], worked by hand. */
static void test_column_known_values(void)
{
    const double f0[3] = {3.0 / (2 * ORR_PI), 7.0 / (4 * ORR_PI), 55.0 / (24 * ORR_PI)};
    for (int i = 0; i < 3; i++) {
        orr_kernel k = make(kinds[i]);
        CHECK_NEAR(orr_kernel_column_exact(&k, 0.0), f0[i], 1e-9);
        CHECK_NEAR(orr_kernel_column(&k, 0.0), f0[i], 1e-6);
        CHECK(orr_kernel_column_exact(&k, 2.0) == 0.0);
        CHECK(orr_kernel_column(&k, 2.0) == 0.0);
        CHECK(orr_kernel_column(&k, 7.0) == 0.0);
        orr_kernel_free(&k);
    }
}

/* The column integral against a plain midpoint sum along the line. */
static void test_column_against_line_sum(void)
{
    const double qs[] = {0.0, 0.05, 0.3, 0.99, 1.0, 1.4, 1.9, 1.999};
    for (int i = 0; i < 3; i++) {
        orr_kernel k = make(kinds[i]);
        for (size_t j = 0; j < sizeof qs / sizeof qs[0]; j++) {
            double q = qs[j], s = 0.0;
            int n = 200000;
            for (int m = 0; m < n; m++) {
                double z = -2.0 + 4.0 * (m + 0.5) / n;
                s += orr_kernel_w3(&k, sqrt(q * q + z * z), 1.0);
            }
            s *= 4.0 / n;
            CHECK_NEAR(orr_kernel_column_exact(&k, q), s, 1e-8);
            /* The table, linear in q^2 between 4096 nodes. */
            CHECK_NEAR(orr_kernel_column(&k, q), s, 2e-6);
        }
        orr_kernel_free(&k);
    }
}

/* The table's Laplacian (the projected 3-D Laplacian) against finite
 * differences of the exact column kernel: lap F = F'' + F'/q. */
static void test_laplacian_table(void)
{
    const double qs[] = {0.3, 0.7, 1.2, 1.6};
    for (int i = 0; i < 3; i++) {
        orr_kernel k = make(kinds[i]);
        for (size_t j = 0; j < sizeof qs / sizeof qs[0]; j++) {
            double q = qs[j], d = 1e-3;
            double fm = orr_kernel_column_exact(&k, q - d), f0 = orr_kernel_column_exact(&k, q),
                   fp = orr_kernel_column_exact(&k, q + d);
            double lap = (fp - 2 * f0 + fm) / (d * d) + (fp - fm) / (2 * d * q);
            float table;
            orr_kernel_column_u(&k, (float)(q * q), &table);
            CHECK_NEAR(table, lap, 1e-3 * fabs(orr_kernel_column_exact(&k, 0.0)) + 1e-4 * fabs(lap));
        }
        orr_kernel_free(&k);
    }
}

/* Rectangles: the whole support is exactly 1, pieces tile it, and a few
 * against a direct 2-D quadrature of the exact kernel. */
static double rect_direct(const orr_kernel *k, double x0, double x1, double y0, double y1)
{
    const int n = 400;
    double s = 0.0;
    for (int a = 0; a < n; a++)
        for (int b = 0; b < n; b++) {
            double x = x0 + (x1 - x0) * (a + 0.5) / n, y = y0 + (y1 - y0) * (b + 0.5) / n;
            s += orr_kernel_column(k, sqrt(x * x + y * y));
        }
    return s * (x1 - x0) * (y1 - y0) / ((double)n * n);
}

static void test_rectangles(void)
{
    for (int i = 0; i < 3; i++) {
        orr_kernel k = make(kinds[i]);
        CHECK_NEAR(orr_kernel_rect(&k, -2, 2, -2, 2), 1.0, 1e-7);
        CHECK_NEAR(orr_kernel_rect(&k, -9, 9, -5, 3), 1.0, 1e-7);
        CHECK_NEAR(orr_kernel_rect(&k, 0, 2, 0, 2), 0.25, 1e-7);
        /* Four quadrants about an off-centre point add up to the whole. */
        double s = orr_kernel_rect(&k, -2, 0.3, -2, -0.7) + orr_kernel_rect(&k, 0.3, 2, -2, -0.7) +
                   orr_kernel_rect(&k, -2, 0.3, -0.7, 2) + orr_kernel_rect(&k, 0.3, 2, -0.7, 2);
        CHECK_NEAR(s, 1.0, 1e-6);
        CHECK_NEAR(orr_kernel_rect(&k, 0.2, 0.9, -0.4, 0.1), rect_direct(&k, 0.2, 0.9, -0.4, 0.1), 2e-6);
        CHECK_NEAR(orr_kernel_rect(&k, -1.7, -1.1, 0.5, 1.9), rect_direct(&k, -1.7, -1.1, 0.5, 1.9), 2e-6);
        CHECK_NEAR(orr_kernel_rect(&k, -0.05, 0.05, -0.05, 0.05), rect_direct(&k, -0.05, 0.05, -0.05, 0.05),
                   2e-6);
        orr_kernel_free(&k);
    }
}

/* The separable expansion: the integral of F over a rectangle as the sum
 * of products of the one-dimensional integrals E_k. */
static double separable_rect(const orr_kernel *k, double x0, double x1, double y0, double y1)
{
    float e[4][ORR_KERNEL_SEP_RANK];
    orr_kernel_separable_at(k, (float)x0, e[0]);
    orr_kernel_separable_at(k, (float)x1, e[1]);
    orr_kernel_separable_at(k, (float)y0, e[2]);
    orr_kernel_separable_at(k, (float)y1, e[3]);
    double s = 0.0;
    for (int r = 0; r < ORR_KERNEL_SEP_RANK; r++)
        s += k->separable_sign[r] * ((double)e[1][r] - e[0][r]) * ((double)e[3][r] - e[2][r]);
    return s;
}

/* The whole support holds 1 (to the truncated terms), E_k is odd and
 * constant beyond the support, and pixel-sized squares anywhere on the
 * support (h = 2, 5 and 10 pixels) match a direct quadrature of F to a
 * small fraction of F's peak times their area. */
static void test_separable(void)
{
    uint64_t seed = 3;
    for (int i = 0; i < 3; i++) {
        orr_kernel k = make(kinds[i]);
        CHECK_NEAR(separable_rect(&k, -2, 2, -2, 2), 1.0, 2e-6);
        CHECK_NEAR(separable_rect(&k, -7, 9, -2.5, 30), 1.0, 2e-6);
        float e[ORR_KERNEL_SEP_RANK], f[ORR_KERNEL_SEP_RANK];
        for (double x = 0.0; x < 2.5; x += 0.137) {
            orr_kernel_separable_at(&k, (float)x, e);
            orr_kernel_separable_at(&k, (float)-x, f);
            for (int r = 0; r < ORR_KERNEL_SEP_RANK; r++)
                CHECK(e[r] == -f[r]);
        }
        const double peak = orr_kernel_column_exact(&k, 0.0), sides[] = {0.5, 0.2, 0.1};
        double worst = 0.0;
        for (int s = 0; s < 3; s++)
            for (int t = 0; t < 40; t++) {
                double side = sides[s], x0 = -2 + (4 - side) * test_uniform(&seed),
                       y0 = -2 + (4 - side) * test_uniform(&seed);
                double got = separable_rect(&k, x0, x0 + side, y0, y0 + side);
                double want = rect_direct(&k, x0, x0 + side, y0, y0 + side);
                worst = fmax(worst, fabs(got - want) / (peak * side * side));
            }
        fprintf(stderr, "  %s: separable squares within %.2g of the peak\n", orr_kernel_name(kinds[i]), worst);
        CHECK(worst < 2e-5);
        orr_kernel_free(&k);
    }
}

static void test_names(void)
{
    orr_kernel_kind kind = ORR_KERNEL_WENDLAND_C4;
    orr_error err = {0};
    for (int i = 0; i < 3; i++) {
        CHECK(orr_kernel_parse(orr_kernel_name(kinds[i]), &kind, &err) == ORR_OK);
        CHECK(kind == kinds[i]);
    }
    CHECK(orr_kernel_parse("m4", &kind, &err) == ORR_OK && kind == ORR_KERNEL_CUBIC);
    CHECK(orr_kernel_parse("c2", &kind, &err) == ORR_OK && kind == ORR_KERNEL_WENDLAND_C2);
    CHECK(orr_kernel_parse("gaussian", &kind, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "gaussian");
    CHECK_CONTAINS(err.msg, "wendland-c2");
    orr_kernel k;
    CHECK(orr_kernel_init(&k, (orr_kernel_kind)42, &err) == ORR_ERR_USAGE);
    orr_kernel_free(&k); /* harmless after a failed init */
}

/* The piecewise polynomials against the exact column kernel (line-of-sight
 * quadrature) and its Laplacian (finite differences), at 4001 points of
 * u. Measured: F within 3.2e-7, 1.2e-6 and 7e-8 of F(0) (cubic, Wendland
 * C2, C4; the worst is the piece at the centre, whose u^2 log u term no
 * polynomial holds), lap F within 6e-5, 1.7e-4 and 4e-6 of its largest
 * value (it enters the samples divided by 24 h^2, h in pixels). Each test
 * point is also checked to sit in the piece kernel.h says. */
static void test_polynomials(void)
{
    for (int i = 0; i < 3; i++) {
        orr_kernel k = make(kinds[i]);
        orr_sample_poly f, lap;
        orr_sample_poly_make(&f, &k, 0.0f);
        orr_sample_poly_make(&lap, &k, 1.0f);
        const double f0 = orr_kernel_column_exact(&k, 0.0);
        double worst_f = 0.0, worst_lap = 0.0, lap_max = 0.0;
        for (int j = 0; j <= 4000; j++) {
            const double u = 4.0 * j / 4000.0, q = sqrt(u);
            const float t = (float)(u * ORR_KERNEL_POLY_T);
            float x;
            const int piece = orr_kernel_poly_piece(t, &x);
            const double t0 = piece == 0 ? 0.0 : piece == 1 ? 0.25 : piece - 1.0;
            CHECK(piece >= 0 && piece < ORR_KERNEL_POLY_PIECES && t >= t0 && x >= 0.0f && x <= 2.0f);
            const double exact = orr_kernel_column_exact(&k, q);
            const double fit = orr_sample_poly_at(&f, t);
            worst_f = fmax(worst_f, fabs(fit - exact));
            if (q > 0.05 && q < 1.95) {
                const double d = 1e-3;
                const double fm = orr_kernel_column_exact(&k, q - d), fp = orr_kernel_column_exact(&k, q + d);
                const double l = (fp - 2 * exact + fm) / (d * d) + (fp - fm) / (2 * d * q);
                worst_lap = fmax(worst_lap, fabs((orr_sample_poly_at(&lap, t) - fit) - l));
                lap_max = fmax(lap_max, fabs(l));
            }
        }
        printf("  %s: |poly - F| <= %.2e F(0), |poly - lap F| <= %.2e max|lap F|\n", orr_kernel_name(kinds[i]),
               worst_f / f0, worst_lap / lap_max);
        CHECK(worst_f <= 1.5e-6 * f0);
        CHECK(worst_lap <= 3e-4 * lap_max);
        /* Zero from the support's edge on. */
        CHECK(orr_sample_poly_at(&f, 4.0f * ORR_KERNEL_POLY_T) == 0.0f);
        CHECK(orr_sample_poly_at(&f, 5.0f * ORR_KERNEL_POLY_T) == 0.0f);
        orr_kernel_free(&k);
    }
}

/* The integral of the polynomial F over the plane (dA = pi du), by a
 * 5-point Gauss rule on each piece (exact for the degree-5 polynomial up
 * to the float coefficients): 1. */
static void test_polynomial_integral(void)
{
    static const double gx[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                                 0.9061798459386640};
    static const double gw[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665,
                                 0.2369268850561891};
    for (int i = 0; i < 3; i++) {
        orr_kernel k = make(kinds[i]);
        orr_sample_poly f;
        orr_sample_poly_make(&f, &k, 0.0f);
        double s = 0.0;
        for (int p = 0; p < ORR_KERNEL_POLY_PIECES; p++) {
            const double t0 = p == 0 ? 0.0 : p == 1 ? 0.25 : p - 1.0;
            const double t1 = p == 0 ? 0.25 : p == 1 ? 1.0 : p == ORR_KERNEL_POLY_PIECES - 1 ? 32.0 : p;
            for (int g = 0; g < 5; g++) {
                /* Just inside the piece: the point's own piece, whatever the float rounding of t. */
                const double t = 0.5 * (t0 + t1) + 0.5 * (t1 - t0) * gx[g];
                s += 0.5 * (t1 - t0) * gw[g] * orr_sample_poly_at(&f, (float)t);
            }
        }
        CHECK_NEAR(ORR_PI * s / ORR_KERNEL_POLY_T, 1.0, 1e-6);
        orr_kernel_free(&k);
    }
}

/* Every vector loop this CPU runs (AVX2, AVX-512) against the plain loop,
 * bit for bit, for every mode and every row length 0 .. 40 at odd offsets
 * (the vector loops' masked tails), for tilted ellipses whose
 * rows cross every piece, including samples past the support's edge. */
static void test_sample_rows(void)
{
    static const char *names[] = {"plain", "AVX2", "AVX-512"};
    const orr_sample_rows best = orr_sample_rows_best();
    printf("  this CPU's rows: %s%s\n", names[best],
           best == ORR_ROWS_AVX512 ? "" : " (the AVX-512 loop is not tested here)");
    orr_kernel k = make(ORR_KERNEL_CUBIC);
    orr_sample_poly p;
    orr_sample_poly_make(&p, &k, 1.0f / 24.0f / 9.0f);
    for (int rows = ORR_ROWS_AVX2; rows <= (int)best; rows++) {
        uint64_t seed = 7;
        int differ = 0, count = 0;
        for (int mode = ORR_SAMPLES_SET; mode <= ORR_SAMPLES_DRAW; mode++)
            for (int n = 0; n <= 40; n++)
                for (int rep = 0; rep < 5; rep++) {
                    const float h = 0.5f + (float)test_below(&seed, 1000) * 0.03f;
                    const float a = 1.0f / (h * h), b = 0.3f * a * ((float)test_below(&seed, 200) / 100.0f - 1.0f);
                    const float dy = ((float)test_below(&seed, 1000) / 250.0f - 2.0f) * h;
                    const float dx0 = -2.2f * h + (float)test_below(&seed, 100) * 0.01f;
                    const int m0 = (int)test_below(&seed, 3);
                    float v[48], s[48];
                    for (int m = 0; m < 48; m++)
                        v[m] = s[m] = (float)test_below(&seed, 1000) * 1e-3f;
                    orr_sample_row_with((orr_sample_rows)rows, &p, a, 2.0f * b * dy, a * dy * dy, dx0, m0, m0 + n, v,
                                        (orr_sample_mode)mode, 0.7f);
                    orr_sample_row_plain(&p, a, 2.0f * b * dy, a * dy * dy, dx0, m0, m0 + n, s,
                                         (orr_sample_mode)mode, 0.7f);
                    differ += memcmp(v, s, sizeof v) != 0;
                    count++;
                }
        CHECK(differ == 0);
        printf("  %s: %d of %d rows differ from the plain loop's\n", names[rows], differ, count);
    }
    /* The plain loop is the scalar sample: a row of one. */
    float one = 0.0f;
    orr_sample_row_plain(&p, 0.01f, 0.0f, 0.5f, 3.0f, 0, 1, &one, ORR_SAMPLES_SET, 1.0f);
    CHECK(one == orr_sample_poly_at(&p, (0.01f * 3.0f * 3.0f + 0.5f) * ORR_KERNEL_POLY_T));
    orr_kernel_free(&k);
}

/* orr_sample_spans_draw against the plain loop row by row, bit for bit:
 * 0 to 11 rows of one tilted ellipse (whole groups of four and the rest),
 * each row with its own columns, some of them empty, some reaching past
 * the support's edge. */
static void test_sample_spans(void)
{
    orr_kernel k = make(ORR_KERNEL_CUBIC);
    orr_sample_poly p;
    orr_sample_poly_make(&p, &k, 1.0f / 24.0f / 9.0f);
    enum { ROWS = 11, COLS = 64 };
    uint64_t seed = 11;
    int differ = 0, count = 0;
    for (int n = 0; n <= ROWS; n++)
        for (int rep = 0; rep < 20; rep++) {
            const float h = 0.5f + (float)test_below(&seed, 1000) * 0.012f;
            const float a = 1.0f / (h * h), b = 0.3f * a * ((float)test_below(&seed, 200) / 100.0f - 1.0f);
            const float dx0 = -2.2f * h + (float)test_below(&seed, 100) * 0.01f;
            float v[ROWS][COLS], s[ROWS][COLS];
            for (int r = 0; r < ROWS; r++)
                for (int m = 0; m < COLS; m++)
                    v[r][m] = s[r][m] = (float)test_below(&seed, 1000) * 1e-3f;
            orr_sample_span spans[ROWS];
            for (int r = 0; r < n; r++) {
                const float dy = ((float)test_below(&seed, 1000) / 250.0f - 2.0f) * h;
                const int m0 = (int)test_below(&seed, 20), len = (int)test_below(&seed, COLS - 20 + 1);
                spans[r] = (orr_sample_span){2.0f * b * dy, a * dy * dy, m0, m0 + len, v[r]};
                orr_sample_row_plain(&p, a, spans[r].bdy, spans[r].cdy, dx0, m0, m0 + len, s[r], ORR_SAMPLES_DRAW,
                                     0.7f);
            }
            orr_sample_spans_draw(&p, a, dx0, spans, n, 0.7f);
            differ += memcmp(v, s, sizeof v) != 0;
            count++;
        }
    CHECK(differ == 0);
    printf("  %d of %d sets of spans differ from the plain loop's rows\n", differ, count);
    orr_kernel_free(&k);
}

int main(void)
{
    RUN(test_3d_normalisation);
    RUN(test_column_normalisation);
    RUN(test_column_known_values);
    RUN(test_column_against_line_sum);
    RUN(test_laplacian_table);
    RUN(test_polynomials);
    RUN(test_polynomial_integral);
    RUN(test_sample_rows);
    RUN(test_sample_spans);
    RUN(test_rectangles);
    RUN(test_separable);
    RUN(test_names);
    return check_summary();
}
