#include "post/stretch.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const orr_named orr_stretch_names[] = {
    {"linear", ORR_STRETCH_LINEAR}, {"log", ORR_STRETCH_LOG}, {"asinh", ORR_STRETCH_ASINH}, {NULL, 0}};

ORR_NAMED_PARSER(orr_stretch_from_name, orr_stretch_kind, orr_stretch_names)

const char *orr_stretch_name(orr_stretch_kind kind) { return orr_named_name(orr_stretch_names, (int)kind); }

/* ---- percentile selection ---------------------------------------------- */

static int compare_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

static float median_of_three(float a, float b, float c)
{
    if (a > b) {
        float t = a;
        a = b;
        b = t;
    }
    /* now a <= b */
    if (c <= a)
        return a;
    if (c >= b)
        return b;
    return c;
}

/* Returns the k-th smallest of a[0..n-1] (0-based), reordering a.
 * Quickselect with Hoare partitioning, which splits runs of equal values
 * evenly (a flat image is common), and a median-of-three pivot. Should the
 * partitions keep coming out lopsided, the rest is sorted instead, which caps
 * the worst case at O(n log n). a holds no NaN (callers filter them). */
static float select_kth(float *a, size_t n, size_t k)
{
    ptrdiff_t lo = 0, hi = (ptrdiff_t)n - 1, want = (ptrdiff_t)k;
    int rounds_left = 2 * 64;
    while (lo < hi) {
        if (rounds_left-- == 0) {
            qsort(a + lo, (size_t)(hi - lo + 1), sizeof *a, compare_float);
            break;
        }
        float pivot = median_of_three(a[lo], a[lo + (hi - lo) / 2], a[hi]);
        ptrdiff_t i = lo, j = hi;
        while (i <= j) {
            /* The pivot is one of the range's values, so these scans stop. */
            while (a[i] < pivot)
                i++;
            while (pivot < a[j])
                j--;
            if (i <= j) {
                float t = a[i];
                a[i] = a[j];
                a[j] = t;
                i++;
                j--;
            }
        }
        /* Now a[lo..j] <= pivot, a[i..hi] >= pivot, and anything between
         * equals the pivot, so the k-th is already in place there. */
        if (j < want)
            lo = i;
        if (want < i)
            hi = j;
    }
    return a[want];
}

/* Nearest-rank percentile of the finite positive pixels; *white = 1 when
 * there are none, so an empty image renders black instead of failing. */
static orr_status percentile_white(const orr_plane *plane, double percentile, double *white, orr_error *err)
{
    size_t npix = (size_t)plane->width * (size_t)plane->height;
    size_t m = 0;
    for (size_t i = 0; i < npix; i++)
        if (plane->data[i] > 0 && isfinite(plane->data[i]))
            m++;
    if (m == 0) {
        *white = 1;
        return ORR_OK;
    }
    float *pos = orr_malloc(m * sizeof *pos, "white-level percentile", err);
    if (!pos)
        return ORR_ERR_NOMEM;
    size_t j = 0;
    for (size_t i = 0; i < npix; i++)
        if (plane->data[i] > 0 && isfinite(plane->data[i]))
            pos[j++] = plane->data[i];
    /* Nearest rank: the smallest value with at least p% of pixels at or below. */
    double rank = ceil(percentile / 100.0 * (double)m);
    size_t k = rank < 1 ? 0 : (size_t)rank - 1;
    if (k >= m)
        k = m - 1;
    *white = select_kth(pos, m, k);
    free(pos);
    return ORR_OK;
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
