/* The codes of sRGB-encoded values from the thresholds' table are the
 * formula's (core/srgb_code.h): on floats spread over [0, 1], on every
 * float near each code's boundary and the curve's joint, and on values
 * off [0, 1]. */
#include <math.h>
#include <stdint.h>

#include "check.h"
#include "core/colourimetry.h"
#include "core/srgb_code.h"

enum { BATCH = 4096 };

static unsigned formula(float x, unsigned max) { return orr_code_of((float)orr_srgb_encode(x), max); }

/* The table's codes of n floats against the formula's, at 8 and 16 bits;
 * the number that differ. */
static long mismatches(const float *x, size_t n)
{
    uint16_t c8[BATCH], c16[BATCH];
    orr_srgb_codes_of(x, n, 8, c8);
    orr_srgb_codes_of(x, n, 16, c16);
    long bad = 0;
    for (size_t i = 0; i < n; i++)
        bad += (c8[i] != formula(x[i], 255)) + (c16[i] != formula(x[i], 65535));
    return bad;
}

/* Every float in [from, to) with the given stride in its bits. */
static long mismatches_over(float from, float to, uint32_t stride)
{
    uint32_t b, end;
    memcpy(&b, &from, sizeof b);
    memcpy(&end, &to, sizeof end);
    float x[BATCH];
    long bad = 0;
    while (b < end) {
        size_t n = 0;
        for (; n < BATCH && b < end; n++, b += stride)
            memcpy(&x[n], &b, sizeof b);
        bad += mismatches(x, n);
    }
    return bad;
}

static void test_spread_over_unit_interval(void) { CHECK(mismatches_over(0.0f, 1.0001f, 1009) == 0); }

/* Every float within 40 of each boundary of a 16-bit code (and so of an
 * 8-bit one, whose boundaries are among them to within a float or two)
 * and near the joint of the curve's linear part and its power law, where
 * the encoded float dips. */
static void test_near_boundaries(void)
{
    long bad = 0;
    for (unsigned q = 1; q <= 65535; q++) {
        float x = (float)orr_srgb_decode((q - 0.5) / 65535), lo = x, hi = x;
        for (int k = 0; k < 40; k++)
            lo = nextafterf(lo, 0), hi = nextafterf(hi, 2);
        bad += mismatches_over(lo, hi, 1);
    }
    for (unsigned q = 1; q <= 255; q++) {
        float x = (float)orr_srgb_decode((q - 0.5) / 255);
        bad += mismatches_over(x * (1 - 1e-6f), x * (1 + 1e-6f), 1);
    }
    bad += mismatches_over(0.0031308f * (1 - 1e-4f), 0.0031308f * (1 + 1e-4f), 1);
    CHECK(bad == 0);
}

static void test_off_the_interval(void)
{
    const float x[] = {NAN, -NAN, INFINITY, -INFINITY, -1.0f, -0.0f, 0.0f, 1e-45f, 1.0f, 1.0000001f, 2.0f, 1e30f};
    const size_t n = sizeof x / sizeof x[0];
    uint16_t c[sizeof x / sizeof x[0]];
    orr_srgb_codes_of(x, n, 16, c);
    CHECK(c[0] == 0 && c[1] == 0 && c[2] == 65535 && c[3] == 0 && c[4] == 0 && c[5] == 0 && c[6] == 0);
    CHECK(c[8] == 65535 && c[9] == 65535 && c[10] == 65535 && c[11] == 65535);
    CHECK(mismatches(x, n) == 0);
}

static void test_plain_codes(void)
{
    const float x[] = {NAN, -1, 0, 1.0f / 65535, 0.49f, 0.5f, 1, 3};
    uint16_t c8[8], c16[8];
    orr_codes_of(x, 8, 8, c8);
    orr_codes_of(x, 8, 16, c16);
    const unsigned want8[] = {0, 0, 0, 0, 125, 128, 255, 255}, want16[] = {0, 0, 0, 1, 32112, 32768, 65535, 65535};
    for (int i = 0; i < 8; i++)
        CHECK(c8[i] == want8[i] && c16[i] == want16[i]);
}

int main(void)
{
    RUN(test_spread_over_unit_interval);
    RUN(test_near_boundaries);
    RUN(test_off_the_interval);
    RUN(test_plain_codes);
    return check_summary();
}
