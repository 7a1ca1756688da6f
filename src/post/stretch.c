#include "post/stretch.h"

#include <math.h>
#include <omp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

const orr_named orr_stretch_names[] = {
    {"linear", ORR_STRETCH_LINEAR}, {"log", ORR_STRETCH_LOG}, {"asinh", ORR_STRETCH_ASINH}, {NULL, 0}};

ORR_NAMED_PARSER(orr_stretch_from_name, orr_stretch_kind, orr_stretch_names)

const char *orr_stretch_name(orr_stretch_kind kind) { return orr_named_name(orr_stretch_names, (int)kind); }

/* ---- percentile selection ---------------------------------------------- */

/* Positive finite floats sort as their bit patterns do (as unsigned
 * integers), so the k-th smallest is found digit by digit: its high 16
 * bits from a histogram of all the pixels' high halves, then its low 16
 * bits from a histogram of the pixels that share them. Two passes over the
 * plane, on every thread, and no copy of its pixels (268 MB at 8192^2). */
enum { DIGITS = 1 << 16 };

static uint32_t float_bits(float v)
{
    uint32_t b;
    memcpy(&b, &v, sizeof b);
    return b;
}

static int positive_finite(float v) { return v > 0 && isfinite(v); }

/* counts[d] = the positive finite pixels whose high half is d (high < 0)
 * or, among those whose high half is `high`, whose low half is d; summed
 * over per-thread histograms. Returns 0 when no memory. */
static int digit_histogram(const float *v, size_t n, long high, size_t *counts)
{
    int nthreads = omp_get_max_threads();
    size_t *part = calloc((size_t)nthreads * DIGITS, sizeof *part);
    if (!part)
        return 0;
#pragma omp parallel
    {
        size_t *mine = part + (size_t)omp_get_thread_num() * DIGITS;
#pragma omp for schedule(static)
        for (size_t i = 0; i < n; i++) {
            if (!positive_finite(v[i]))
                continue;
            uint32_t b = float_bits(v[i]);
            if (high < 0)
                mine[b >> 16]++;
            else if ((long)(b >> 16) == high)
                mine[b & 0xffff]++;
        }
    }
    memset(counts, 0, DIGITS * sizeof *counts);
    for (int t = 0; t < nthreads; t++)
        for (size_t d = 0; d < DIGITS; d++)
            counts[d] += part[(size_t)t * DIGITS + d];
    free(part);
    return 1;
}

/* The digit holding the k-th smallest (0-based) of the counted values;
 * *k becomes its rank among that digit's. */
static size_t digit_of_rank(const size_t *counts, size_t *k)
{
    size_t d = 0;
    while (*k >= counts[d]) {
        *k -= counts[d];
        d++;
    }
    return d;
}

/* Nearest-rank percentile of the finite positive pixels; *white = 1 when
 * there are none, so an empty image renders black instead of failing. */
static orr_status percentile_white(const orr_plane *plane, double percentile, double *white, orr_error *err)
{
    size_t npix = (size_t)plane->width * (size_t)plane->height;
    size_t *counts = orr_malloc(DIGITS * sizeof *counts, "white-level percentile", err);
    if (!counts)
        return ORR_ERR_NOMEM;
    orr_status st = ORR_OK;
    if (!digit_histogram(plane->data, npix, -1, counts)) {
        free(counts);
        return orr_fail(err, ORR_ERR_NOMEM, "out of memory for the white-level percentile");
    }
    size_t m = 0;
    for (size_t d = 0; d < DIGITS; d++)
        m += counts[d];
    if (m == 0) {
        *white = 1;
        free(counts);
        return ORR_OK;
    }
    /* Nearest rank: the smallest value with at least p% of pixels at or below. */
    double rank = ceil(percentile / 100.0 * (double)m);
    size_t k = rank < 1 ? 0 : (size_t)rank - 1;
    if (k >= m)
        k = m - 1;
    size_t high = digit_of_rank(counts, &k);
    if (!digit_histogram(plane->data, npix, (long)high, counts))
        st = orr_fail(err, ORR_ERR_NOMEM, "out of memory for the white-level percentile");
    else {
        uint32_t b = (uint32_t)(high << 16 | digit_of_rank(counts, &k));
        float v;
        memcpy(&v, &b, sizeof v);
        *white = v;
    }
    free(counts);
    return st;
}

/* ---- stretch --------------------------------------------------------- */

static orr_status validate(const orr_stretch *s, orr_error *err)
{
    if (!orr_named_has(orr_stretch_names, (int)s->kind))
        return orr_fail(err, ORR_ERR_USAGE, "stretch: unknown kind %d", (int)s->kind);
    if (!(s->white >= 0) || isinf(s->white))
        return orr_fail(err, ORR_ERR_USAGE, "stretch: white %g must be a positive number (or 0 for automatic)",
                        s->white);
    if (s->white == 0 && !(s->white_percentile > 0 && s->white_percentile <= 100))
        return orr_fail(err, ORR_ERR_USAGE, "stretch: white percentile %g must be in (0, 100]",
                        s->white_percentile);
    if (s->kind != ORR_STRETCH_LINEAR && !(s->n > 0 && isfinite(s->n)))
        return orr_fail(err, ORR_ERR_USAGE, "stretch %s: softening n = %g must be positive",
                        orr_stretch_name(s->kind), s->n);
    return ORR_OK;
}

orr_status orr_stretch_white(const orr_stretch *s, const orr_plane *plane, double *white, orr_error *err)
{
    orr_status st = validate(s, err);
    if (st != ORR_OK)
        return st;
    if (s->white > 0) {
        *white = s->white;
        return ORR_OK;
    }
    return percentile_white(plane, s->white_percentile, white, err);
}

static float clip01(double t)
{
    /* NaN compares false both ways and so falls through to 0. */
    if (t > 1)
        return 1.0f;
    if (t > 0)
        return (float)t;
    return 0.0f;
}

void orr_stretch_span(const orr_stretch *s, double white, const float *in, size_t count, float *out)
{
    double inv_white = 1.0 / white;
    double n = s->n;
    switch (s->kind) {
    case ORR_STRETCH_LINEAR:
        for (size_t i = 0; i < count; i++)
            out[i] = clip01(in[i] * inv_white);
        break;
    case ORR_STRETCH_LOG: {
        double norm = 1.0 / log1p(n);
        for (size_t i = 0; i < count; i++) {
            double x = in[i] * inv_white;
            /* Negative values would take log1p below -1: they show black anyway. */
            out[i] = x > 0 ? clip01(log1p(n * x) * norm) : 0.0f;
        }
        break;
    }
    case ORR_STRETCH_ASINH: {
        double norm = 1.0 / asinh(n);
        for (size_t i = 0; i < count; i++)
            out[i] = clip01(asinh(n * in[i] * inv_white) * norm);
        break;
    }
    }
}

orr_status orr_stretch_apply(const orr_stretch *s, const orr_plane *plane, float *out, double *white_used,
                             orr_error *err)
{
    double white;
    orr_status st = orr_stretch_white(s, plane, &white, err);
    if (st != ORR_OK)
        return st;
    if (white_used)
        *white_used = white;
    /* Pixel by pixel, so the threads change nothing in the result. */
    const size_t w = (size_t)plane->width;
#pragma omp parallel for schedule(static)
    for (int j = 0; j < plane->height; j++)
        orr_stretch_span(s, white, plane->data + (size_t)j * w, w, out + (size_t)j * w);
    return ORR_OK;
}
