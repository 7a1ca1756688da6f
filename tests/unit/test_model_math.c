/* The model's vectorisable maths (src/source/models/model_math.h,
 * orr_sincos_turn in rng.h) against the C library: the logarithm, the
 * exponential and the sines and cosines to within a few units of the
 * last place, and the uniform deviate from bits equal to orr_rng_uniform's. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>

#include "check.h"
#include "source/models/model_math.h"
#include "source/models/rng.h"

/* ln x over 10^6 uniform deviates, their products (the discs' radii),
 * x spread over 600 decades and x near 1 (where ln x is small and a
 * relative error shows most): within 5e-16 of libm's, relative (4.3e-16
 * measured: two units of the last place). */
static void test_log_against_libm(void)
{
    orr_rng r = orr_rng_seed(3, 0, 0);
    double worst = 0.0;
    for (int i = 0; i < 1000000; i++) {
        double u = orr_rng_uniform(&r), v = orr_rng_uniform(&r);
        double xs[4] = {u, u * v, exp(-690.0 + 1380.0 * v), 1.0 + (u - 0.5) * 1e-6};
        for (int k = 0; k < 4; k++) {
            double ref = log(xs[k]);
            if (ref == 0.0)
                continue;
            worst = fmax(worst, fabs(orr_log_poly(xs[k]) - ref) / fabs(ref));
        }
    }
    static const double exact_points[] = {1.0, 2.0, 0.5, 0x1.6a09e667f3bcdp-1, 0x1.6a09e667f3bccp-1, 1e-300, 1e300};
    for (size_t k = 0; k < sizeof exact_points / sizeof exact_points[0]; k++) {
        double ref = log(exact_points[k]);
        double got = orr_log_poly(exact_points[k]);
        worst = ref == 0.0 ? fmax(worst, fabs(got)) : fmax(worst, fabs(got - ref) / fabs(ref));
    }
    fprintf(stderr, "  orr_log_poly within %.3g of libm's log (relative)\n", worst);
    CHECK(worst <= 5e-16);
}

/* e^x for x over [-700, 700] and over [-1, 1] (the bulges' ln(r_eq / r)):
 * within 5e-16 of libm's exp, relative. */
static void test_exp_against_libm(void)
{
    orr_rng r = orr_rng_seed(6, 0, 0);
    double worst = 0.0;
    for (int i = 0; i < 1000000; i++) {
        double u = orr_rng_uniform(&r), xs[2] = {1400.0 * u - 700.0, 2.0 * u - 1.0};
        for (int k = 0; k < 2; k++)
            worst = fmax(worst, fabs(orr_exp_poly(xs[k]) - exp(xs[k])) / exp(xs[k]));
    }
    CHECK(orr_exp_poly(0.0) == 1.0);
    fprintf(stderr, "  orr_exp_poly within %.3g of libm's exp (relative)\n", worst);
    CHECK(worst <= 5e-16);
}

/* sin and cos of 2 pi u, the branch-free quarter turns: within 8e-16 of
 * libm's sin and cos of the rounded 2 pi u (7.2e-16 measured). */
static void test_sincos_turn_against_libm(void)
{
    orr_rng r = orr_rng_seed(4, 0, 0);
    double worst = 0.0;
    for (int i = 0; i < 1000000; i++) {
        double u = orr_rng_uniform(&r), s, c;
        orr_sincos_turn(u, &s, &c);
        worst = fmax(worst, fmax(fabs(s - sin(6.283185307179586 * u)), fabs(c - cos(6.283185307179586 * u))));
    }
    fprintf(stderr, "  orr_sincos_turn within %.3g of libm's (absolute)\n", worst);
    CHECK(worst <= 8e-16);
}

/* The uniform from bits is orr_rng_uniform's value exactly, including
 * outputs with the top bit set and the extremes. */
static void test_uniform_of_bits(void)
{
    orr_rng r = orr_rng_seed(5, 0, 0);
    int same = 1;
    for (int i = 0; i < 1000000; i++) {
        orr_rng copy = r;
        double u = orr_rng_uniform(&r);
        same &= orr_uniform_of_bits(orr_rng_next(&copy)) == u;
    }
    CHECK(same);
    CHECK(orr_uniform_of_bits(0) == 0.5 / 9007199254740992.0);
    CHECK(orr_uniform_of_bits(~(uint64_t)0) == (9007199254740991.0 + 0.5) / 9007199254740992.0);
}

int main(void)
{
    RUN(test_log_against_libm);
    RUN(test_exp_against_libm);
    RUN(test_sincos_turn_against_libm);
    RUN(test_uniform_of_bits);
    return check_summary();
}
