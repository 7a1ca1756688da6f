/* Vectorisable maths for the model's batch samplers (model_batch.c): a
 * natural logarithm, an exponential and a uniform deviate from plain IEEE operations and
 * integer bit work, with no branch and no library call, so a loop over
 * particles that calls them is compiled to vector instructions (libm's
 * log is a call per lane), and gives the same bits on any machine and in
 * any clone (-ffp-contract=off: no fused multiply-adds).
 *
 * Written from the textbook method: x = 2^e m with m in [sqrt(1/2),
 * sqrt(2)), and ln m = 2 atanh(f), f = (m - 1) / (m + 1), |f| <= 0.1716,
 * by its Taylor series f + f^3/3 + ... + f^21/21 (the next term is below
 * 10^-18 of the sum). Within 4.3 x 10^-16 of libm's log, relative (two
 * units of the last place; tests/unit/test_model_math.c measures it). */
#ifndef ORR_SOURCE_MODEL_MATH_H
#define ORR_SOURCE_MODEL_MATH_H

#include <stdint.h>
#include <string.h>

#include "core/simd.h"

static ORR_ALWAYS_INLINE uint64_t orr_bits_of(double x)
{
    uint64_t b;
    memcpy(&b, &x, sizeof b);
    return b;
}

static ORR_ALWAYS_INLINE double orr_double_of(uint64_t b)
{
    double x;
    memcpy(&x, &b, sizeof x);
    return x;
}

/* ln x for a positive, finite, normal x. */
static ORR_ALWAYS_INLINE double orr_log_poly(double x)
{
    const uint64_t sqrt_half = 0x3FE6A09E667F3BCDULL; /* the bits of sqrt(1/2) */
    uint64_t b = orr_bits_of(x);
    /* e: how many octaves x lies above [sqrt(1/2), sqrt(2)), from the
     * exponent field of b less sqrt(1/2)'s (x >= sqrt(1/2) gives e >= 0) */
    uint64_t shifted = b - sqrt_half + ((uint64_t)1023 << 52); /* exponent field 1023 + e, e in [-1022, 1024] */
    uint64_t field = shifted >> 52;
    double m = orr_double_of(b - ((field - 1023) << 52));
    /* field as a double, exactly, by the 2^52 trick (integers below 2^52) */
    double e = orr_double_of(0x4330000000000000ULL | field) - (4503599627370496.0 + 1023.0);
    double f = (m - 1.0) / (m + 1.0), s = f * f, s2 = s * s, s4 = s2 * s2, s8 = s4 * s4;
    /* Estrin's scheme: 1/3 + s/5 + ... + s^9/21, in pairs */
    double p01 = 1.0 / 3 + s * (1.0 / 5), p23 = 1.0 / 7 + s * (1.0 / 9), p45 = 1.0 / 11 + s * (1.0 / 13);
    double p67 = 1.0 / 15 + s * (1.0 / 17), p89 = 1.0 / 19 + s * (1.0 / 21);
    double p = (p01 + s2 * p23) + s4 * (p45 + s2 * p67) + s8 * p89;
    /* ln 2 in two parts: e ln2_hi is exact (|e| < 2^11, ln2_hi has 11
     * trailing zero bits) */
    const double ln2_hi = 6.93147180369123816490e-01, ln2_lo = 1.90821492927058770002e-10;
    double two_f = f + f;
    return e * ln2_hi + (two_f + (two_f * s * p + e * ln2_lo));
}

/* e^x for |x| < 700: x = k ln 2 + t, k the nearest integer to x / ln 2
 * (rounded by adding and taking away 1.5 x 2^52), |t| <= ln 2 / 2, e^t by
 * its Taylor series to t^14 (the next term is below 3 x 10^-19), 2^k by
 * the exponent's bits. */
static ORR_ALWAYS_INLINE double orr_exp_poly(double x)
{
    const double shifter = 6755399441055744.0; /* 1.5 x 2^52: k in the low bits */
    const double ln2_hi = 6.93147180369123816490e-01, ln2_lo = 1.90821492927058770002e-10;
    double shifted = x * 1.4426950408889634 + shifter, k = shifted - shifter;
    double t = (x - k * ln2_hi) - k * ln2_lo, t2 = t * t, t4 = t2 * t2, t8 = t4 * t4;
    /* Estrin's scheme, the coefficients 1 / n! in pairs */
    double c01 = 1.0 + t, c23 = 1.0 / 2 + t * (1.0 / 6), c45 = 1.0 / 24 + t * (1.0 / 120);
    double c67 = 1.0 / 720 + t * (1.0 / 5040), c89 = 1.0 / 40320 + t * (1.0 / 362880);
    double c1011 = 1.0 / 3628800 + t * (1.0 / 39916800), c1213 = 1.0 / 479001600 + t * (1.0 / 6227020800.0);
    double c14 = 1.0 / 87178291200.0;
    double p = ((c01 + t2 * c23) + t4 * (c45 + t2 * c67)) + t8 * ((c89 + t2 * c1011) + t4 * (c1213 + t2 * c14));
    /* 2^k: k + 1023 into the exponent field (k's bits are the low bits of
     * `shifted` less the shifter's, modulo 2^64) */
    uint64_t kbits = orr_bits_of(shifted) - orr_bits_of(shifter);
    return p * orr_double_of((kbits + 1023) << 52);
}

/* The top 53 bits of a SplitMix64 output as a uniform double in (0, 1):
 * orr_rng_uniform's value exactly, with the integer made a double by bit
 * work (vector units up to AVX2 have no 64-bit integer conversion). */
static ORR_ALWAYS_INLINE double orr_uniform_of_bits(uint64_t z)
{
    uint64_t k = z >> 11; /* below 2^53 */
    /* the low 52 bits by the 2^52 trick, the top bit added exactly */
    double lo = orr_double_of(0x4330000000000000ULL | (k & 0xFFFFFFFFFFFFFULL)) - 4503599627370496.0;
    double hi = orr_double_of(orr_bits_of(4503599627370496.0) & (0 - (k >> 52)));
    return ((lo + hi) + 0.5) * (1.0 / 9007199254740992.0);
}

#endif
