#include <math.h>
#include <stdlib.h>

#include "check.h"
#include "post/stretch.h"

static orr_plane make_plane(int w, int h)
{
    orr_plane p;
    orr_error err;
    if (orr_plane_alloc(&p, w, h, "test", "", &err) != ORR_OK) {
        fprintf(stderr, "cannot allocate a %d x %d plane: %s\n", w, h, err.msg);
        exit(1);
    }
    return p;
}

/* Stretches a single value with a fixed white level. */
static float stretch_one(orr_stretch_kind kind, double white, double n, float v)
{
    orr_plane p = make_plane(1, 1);
    p.data[0] = v;
    orr_stretch s = {.kind = kind, .white = white, .white_percentile = 99, .n = n};
    float out = -1;
    orr_error err;
    orr_status st = orr_stretch_apply(&s, &p, &out, NULL, &err);
    CHECK(st == ORR_OK);
    orr_plane_free(&p);
    return out;
}

static void test_names(void)
{
    orr_stretch_kind k = ORR_STRETCH_LINEAR;
    CHECK(orr_stretch_from_name("log", &k) && k == ORR_STRETCH_LOG);
    CHECK(orr_stretch_from_name("asinh", &k) && k == ORR_STRETCH_ASINH);
    CHECK(orr_stretch_from_name("linear", &k) && k == ORR_STRETCH_LINEAR);
    CHECK(!orr_stretch_from_name("sqrt", &k));
    CHECK(!orr_stretch_from_name("", &k));
    CHECK(!orr_stretch_from_name(NULL, &k));
    for (int i = ORR_STRETCH_LINEAR; i <= ORR_STRETCH_ASINH; i++) {
        CHECK(orr_stretch_from_name(orr_stretch_name((orr_stretch_kind)i), &k));
        CHECK((int)k == i);
    }
}

static void test_linear(void)
{
    CHECK_NEAR(stretch_one(ORR_STRETCH_LINEAR, 2, 0, 1.0f), 0.5, 1e-7);
    CHECK_NEAR(stretch_one(ORR_STRETCH_LINEAR, 2, 0, 2.0f), 1.0, 0);
    CHECK_NEAR(stretch_one(ORR_STRETCH_LINEAR, 2, 0, 4.0f), 1.0, 0);
    CHECK_NEAR(stretch_one(ORR_STRETCH_LINEAR, 2, 0, -1.0f), 0.0, 0);
    CHECK_NEAR(stretch_one(ORR_STRETCH_LINEAR, 2, 0, NAN), 0.0, 0);
    CHECK_NEAR(stretch_one(ORR_STRETCH_LINEAR, 2, 0, INFINITY), 1.0, 0);
}

static void test_log(void)
{
    CHECK_NEAR(stretch_one(ORR_STRETCH_LOG, 10, 1000, 10.0f), 1.0, 1e-6);
    CHECK_NEAR(stretch_one(ORR_STRETCH_LOG, 10, 1000, 5.0f), log(501.0) / log(1001.0), 1e-6);
    CHECK_NEAR(stretch_one(ORR_STRETCH_LOG, 10, 1000, 0.01f), log(2.0) / log(1001.0), 1e-6);
    CHECK_NEAR(stretch_one(ORR_STRETCH_LOG, 10, 1000, 0.0f), 0.0, 0);
    CHECK_NEAR(stretch_one(ORR_STRETCH_LOG, 10, 1000, -3.0f), 0.0, 0);
    CHECK_NEAR(stretch_one(ORR_STRETCH_LOG, 10, 1000, NAN), 0.0, 0);
    CHECK_NEAR(stretch_one(ORR_STRETCH_LOG, 10, 1000, 50.0f), 1.0, 0);
}

static void test_asinh(void)
{
    CHECK_NEAR(stretch_one(ORR_STRETCH_ASINH, 1, 10, 1.0f), 1.0, 1e-6);
    CHECK_NEAR(stretch_one(ORR_STRETCH_ASINH, 1, 10, 0.5f), asinh(5.0) / asinh(10.0), 1e-6);
    CHECK_NEAR(stretch_one(ORR_STRETCH_ASINH, 4, 10, 1.0f), asinh(2.5) / asinh(10.0), 1e-6);
    CHECK_NEAR(stretch_one(ORR_STRETCH_ASINH, 1, 10, -0.5f), 0.0, 0);
    CHECK_NEAR(stretch_one(ORR_STRETCH_ASINH, 1, 10, NAN), 0.0, 0);
}

/* Values 1..100 in a scrambled order among zeros, negatives and NaN: the
 * nearest-rank percentile of the positive pixels is known exactly. */
static void test_percentile_known_plane(void)
{
    orr_plane p = make_plane(20, 10);
    for (int i = 0; i < 200; i++)
        p.data[i] = i % 3 == 0 ? 0.0f : (i % 3 == 1 ? -5.0f : NAN);
    for (int v = 1; v <= 100; v++)
        p.data[(v * 37) % 200] = (float)v; /* 37 is coprime to 200: distinct slots */
    orr_stretch s = {.kind = ORR_STRETCH_LINEAR, .white = 0, .white_percentile = 50, .n = 1};
    orr_error err;
    double white = 0;
    const double pct[] = {50, 99, 100, 0.5, 1, 99.5, 37.2};
    const double expect[] = {50, 99, 100, 1, 1, 100, 38};
    for (size_t i = 0; i < sizeof pct / sizeof pct[0]; i++) {
        s.white_percentile = pct[i];
        CHECK(orr_stretch_white(&s, &p, &white, &err) == ORR_OK);
        CHECK_NEAR(white, expect[i], 0);
    }
    /* apply uses the same white and reports it */
    float *out = malloc(200 * sizeof *out);
    s.white_percentile = 50;
    double used = 0;
    CHECK(orr_stretch_apply(&s, &p, out, &used, &err) == ORR_OK);
    CHECK_NEAR(used, 50, 0);
    CHECK_NEAR(out[(25 * 37) % 200], 0.5, 1e-7);
    CHECK_NEAR(out[(80 * 37) % 200], 1.0, 0);
    CHECK_NEAR(out[0], 0.0, 0);
    CHECK_NEAR(out[2], 0.0, 0); /* NaN */
    free(out);
    /* a fixed white ignores the pixels */
    s.white = 7;
    CHECK(orr_stretch_white(&s, &p, &white, &err) == ORR_OK);
    CHECK_NEAR(white, 7, 0);
    orr_plane_free(&p);
}

static void test_no_positive_pixel_gives_white_one(void)
{
    orr_plane p = make_plane(8, 8);
    p.data[3] = -1.0f;
    p.data[5] = NAN;
    orr_stretch s = {.kind = ORR_STRETCH_LOG, .white = 0, .white_percentile = 99.5, .n = 100};
    orr_error err;
    double white = 0;
    CHECK(orr_stretch_white(&s, &p, &white, &err) == ORR_OK);
    CHECK_NEAR(white, 1, 0);
    float out[64];
    CHECK(orr_stretch_apply(&s, &p, out, &white, &err) == ORR_OK);
    for (int i = 0; i < 64; i++)
        CHECK_NEAR(out[i], 0.0, 0);
    orr_plane_free(&p);
}

static int compare_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* The plane's white levels at a few percentiles are the nearest ranks in
 * sorted, its m positive finite values in order. */
static void check_percentiles(const orr_plane *p, const float *sorted, size_t m)
{
    orr_stretch s = {.kind = ORR_STRETCH_ASINH, .white = 0, .white_percentile = 99.9, .n = 10};
    orr_error err;
    const double pct[] = {99.9, 50, 1e-4, 100};
    for (size_t i = 0; i < sizeof pct / sizeof pct[0]; i++) {
        s.white_percentile = pct[i];
        double white = 0;
        CHECK(orr_stretch_white(&s, p, &white, &err) == ORR_OK);
        size_t k = (size_t)ceil(pct[i] / 100.0 * (double)m);
        k = k < 1 ? 0 : k - 1;
        CHECK_NEAR(white, sorted[k], 0);
    }
}

/* A large plane with many repeated values: the selection must agree with a
 * full sort, and a constant plane (many equal keys) must not go quadratic. */
static void test_percentile_large_plane(void)
{
    int w = 2000, h = 1500;
    size_t n = (size_t)w * h;
    orr_plane p = make_plane(w, h);
    unsigned state = 12345;
    for (size_t i = 0; i < n; i++) {
        state = state * 1103515245u + 12345u;
        p.data[i] = (float)((state >> 8) % 5000) - 1000.0f; /* ~20% non-positive, many ties */
    }
    float *sorted = malloc(n * sizeof *sorted);
    size_t m = 0;
    for (size_t i = 0; i < n; i++)
        if (p.data[i] > 0)
            sorted[m++] = p.data[i];
    qsort(sorted, m, sizeof *sorted, compare_float);
    check_percentiles(&p, sorted, m);
    /* Values over many octaves, most of them unique, with NaN, infinities
     * and negatives among them: every bit of the value is selected. */
    m = 0;
    for (size_t i = 0; i < n; i++) {
        state = state * 1103515245u + 12345u;
        unsigned r = state >> 8;
        float v = ldexpf(1.0f + (float)(r % 65521) / 65521.0f, (int)(r % 41) - 20);
        p.data[i] = r % 53 == 0 ? NAN : r % 59 == 0 ? INFINITY : r % 7 == 0 ? -v : v;
        if (p.data[i] > 0 && isfinite(p.data[i]))
            sorted[m++] = p.data[i];
    }
    qsort(sorted, m, sizeof *sorted, compare_float);
    check_percentiles(&p, sorted, m);
    free(sorted);
    for (size_t i = 0; i < n; i++)
        p.data[i] = 3.0f;
    orr_stretch s = {.kind = ORR_STRETCH_ASINH, .white = 0, .white_percentile = 99.9, .n = 10};
    orr_error err;
    double white = 0;
    CHECK(orr_stretch_white(&s, &p, &white, &err) == ORR_OK);
    CHECK_NEAR(white, 3.0, 0);
    orr_plane_free(&p);
}

static void test_bad_parameters(void)
{
    orr_plane p = make_plane(2, 2);
    float out[4];
    orr_error err;
    orr_stretch s = {.kind = ORR_STRETCH_LOG, .white = 1, .white_percentile = 99, .n = 0};
    CHECK(orr_stretch_apply(&s, &p, out, NULL, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "log");
    s.n = 10;
    s.white = -1;
    CHECK(orr_stretch_apply(&s, &p, out, NULL, &err) == ORR_ERR_USAGE);
    s.white = NAN;
    CHECK(orr_stretch_apply(&s, &p, out, NULL, &err) == ORR_ERR_USAGE);
    s.white = 0;
    s.white_percentile = 0;
    CHECK(orr_stretch_apply(&s, &p, out, NULL, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "percentile");
    s.white_percentile = 101;
    CHECK(orr_stretch_apply(&s, &p, out, NULL, &err) == ORR_ERR_USAGE);
    /* linear does not use n */
    s.kind = ORR_STRETCH_LINEAR;
    s.white = 1;
    s.n = 0;
    CHECK(orr_stretch_apply(&s, &p, out, NULL, &err) == ORR_OK);
    orr_plane_free(&p);
}

int main(void)
{
    RUN(test_names);
    RUN(test_linear);
    RUN(test_log);
    RUN(test_asinh);
    RUN(test_percentile_known_plane);
    RUN(test_no_positive_pixel_gives_white_one);
    RUN(test_percentile_large_plane);
    RUN(test_bad_parameters);
    return check_summary();
}
