/* k-d tree and k-th-neighbour smoothing lengths against brute force: exact
 * equality of the k-th squared distance (both sides use orr_kd_dist2), on
 * uniform, clustered and duplicated points; the tree's structure; the same
 * results with 1 and 2 threads; errors. */
#include <math.h>
#include <omp.h>
#include <stdint.h>
#include <stdlib.h>

#include "check.h"
#include "particles/kdtree.h"
#include "particles/smoothing.h"

typedef struct cloud {
    size_t n;
    float *x, *y, *z;
} cloud;

static uint64_t rng_state;

static double uniform01(void)
{
    /* splitmix64 */
    uint64_t z = (rng_state += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    z ^= z >> 31;
    return (double)(z >> 11) * (1.0 / 9007199254740992.0);
}

static cloud cloud_alloc(size_t n)
{
    cloud c = {n, malloc((n ? n : 1) * sizeof(float)), malloc((n ? n : 1) * sizeof(float)),
               malloc((n ? n : 1) * sizeof(float))};
    return c;
}

static void cloud_free(cloud *c)
{
    free(c->x);
    free(c->y);
    free(c->z);
}

enum { UNIFORM, CLUSTERED, DUPLICATED, NKINDS };
static const char *kind_names[] = {"uniform", "clustered", "duplicated"};

/* Clusters of very different sizes far from the origin: float positions
 * near 1000 with neighbours 1e-3 apart test the double distances. */
static void fill_clustered(cloud *c)
{
    const double centre[4][3] = {{1000, 1000, 1000}, {1001, 1000, 999}, {0, 0, 0}, {-5, 3, 2}};
    const double size[4] = {1e-3, 0.5, 1e-5, 2.0};
    for (size_t i = 0; i < c->n; i++) {
        int g = (int)(uniform01() * 4) & 3;
        /* the sum of three uniforms: centrally concentrated */
        double u[3];
        for (int a = 0; a < 3; a++)
            u[a] = (uniform01() + uniform01() + uniform01() - 1.5) * size[g];
        c->x[i] = (float)(centre[g][0] + u[0]);
        c->y[i] = (float)(centre[g][1] + u[1]);
        c->z[i] = (float)(centre[g][2] + u[2]);
    }
}

/* Few distinct positions, many copies of each (more than 32 for large n),
 * some on a common plane, plus unique points. */
static void fill_duplicated(cloud *c)
{
    size_t distinct = c->n / 40 + 1;
    for (size_t i = 0; i < c->n; i++) {
        if (uniform01() < 0.2) {
            c->x[i] = (float)uniform01();
            c->y[i] = (float)uniform01();
            c->z[i] = 0.5f;
            continue;
        }
        uint64_t s = (uint64_t)(uniform01() * (double)distinct);
        c->x[i] = (float)((s % 7) * 0.125);
        c->y[i] = (float)((s / 7 % 7) * 0.125);
        c->z[i] = (float)((s / 49) * 0.125);
    }
}

static cloud make_cloud(int kind, size_t n, uint64_t seed)
{
    rng_state = seed;
    cloud c = cloud_alloc(n);
    if (kind == CLUSTERED)
        fill_clustered(&c);
    else if (kind == DUPLICATED)
        fill_duplicated(&c);
    else
        for (size_t i = 0; i < n; i++) {
            c.x[i] = (float)uniform01();
            c.y[i] = (float)uniform01();
            c.z[i] = (float)uniform01();
        }
    return c;
}

/* The rank-th smallest squared distance from q to the cloud's points, by
 * keeping the rank smallest in a sorted array; INFINITY when rank > n. */
static double brute_kth_dist2(const cloud *c, const float q[3], size_t rank)
{
    double best[64];
    for (size_t j = 0; j < rank; j++)
        best[j] = INFINITY;
    for (size_t i = 0; i < c->n; i++) {
        float p[3] = {c->x[i], c->y[i], c->z[i]};
        double d2 = orr_kd_dist2(q, p);
        if (!(d2 < best[rank - 1]))
            continue;
        size_t j = rank - 1;
        for (; j > 0 && best[j - 1] > d2; j--)
            best[j] = best[j - 1];
        best[j] = d2;
    }
    return best[rank - 1];
}

/* Compares the tree's k-th distances and the smoothing lengths with brute
 * force for every particle; returns the number of mismatches. */
static int compare_with_brute_force(const cloud *c, int k, float factor)
{
    orr_error err = {0};
    float *h = malloc((c->n ? c->n : 1) * sizeof *h);
    int bad = orr_smoothing_lengths(c->n, c->x, c->y, c->z, k, factor, h, &err) != ORR_OK;
    orr_kdtree t;
    bad += orr_kdtree_build(&t, c->n, c->x, c->y, c->z, &err) != ORR_OK;
    double heap[64];
    size_t rank = (size_t)k + 1 < c->n ? (size_t)k + 1 : c->n;
    for (size_t i = 0; i < c->n && !bad; i++) {
        float q[3] = {c->x[i], c->y[i], c->z[i]};
        double want = brute_kth_dist2(c, q, rank);
        double got = orr_kdtree_kth_dist2(&t, q, rank, heap);
        float want_h = (float)((double)factor * sqrt(want));
        if (got != want || h[i] != want_h) {
            if (bad++ < 3)
                fprintf(stderr, "  particle %zu of %zu, k = %d: dist2 %.17g vs %.17g, h %.9g vs %.9g\n", i,
                        c->n, k, got, want, (double)h[i], (double)want_h);
        }
    }
    orr_kdtree_free(&t);
    free(h);
    return bad;
}

static void test_matches_brute_force(void)
{
    const int ks[] = {1, 8, 32};
    for (int kind = 0; kind < NKINDS; kind++)
        for (int ki = 0; ki < 3; ki++) {
            int k = ks[ki];
            size_t sizes[] = {0, 1, 2, (size_t)k, (size_t)k + 1, (size_t)k + 2, 17, 500, 5000};
            for (size_t si = 0; si < sizeof sizes / sizeof sizes[0]; si++) {
                cloud c = make_cloud(kind, sizes[si], 1000 + 17 * si + 3 * ki + kind);
                int bad = compare_with_brute_force(&c, k, ORR_SMOOTHING_FACTOR_DEFAULT);
                if (bad)
                    fprintf(stderr, "  %s, n = %zu, k = %d: %d mismatches\n", kind_names[kind], c.n, k, bad);
                CHECK(bad == 0);
                cloud_free(&c);
            }
        }
}

static void test_small_cases_by_hand(void)
{
    orr_error err = {0};
    /* One particle: no neighbour, h = 0. */
    float x1[] = {3}, y1[] = {4}, z1[] = {5}, h[4] = {-1, -1, -1, -1};
    CHECK(orr_smoothing_lengths(1, x1, y1, z1, 32, 0.5f, h, &err) == ORR_OK);
    CHECK(h[0] == 0.0f);
    /* Two particles 2 apart: each one's only neighbour is the other. */
    float x2[] = {0, 2}, y2[] = {0, 0}, z2[] = {0, 0};
    CHECK(orr_smoothing_lengths(2, x2, y2, z2, 32, 0.5f, h, &err) == ORR_OK);
    CHECK(h[0] == 1.0f && h[1] == 1.0f);
    /* On a line at 0, 1, 3, 7 with k = 2 and factor 1: the second-nearest
     * others are at 3, 2, 3 and 6; n <= k takes the farthest. */
    float x4[] = {0, 1, 3, 7}, y4[] = {0, 0, 0, 0}, z4[] = {0, 0, 0, 0};
    CHECK(orr_smoothing_lengths(4, x4, y4, z4, 2, 1.0f, h, &err) == ORR_OK);
    CHECK(h[0] == 3.0f && h[1] == 2.0f && h[2] == 3.0f && h[3] == 6.0f);
    CHECK(orr_smoothing_lengths(4, x4, y4, z4, 3, 1.0f, h, &err) == ORR_OK);
    CHECK(h[0] == 7.0f && h[1] == 6.0f && h[2] == 4.0f && h[3] == 7.0f);
    CHECK(orr_smoothing_lengths(4, x4, y4, z4, 100, 1.0f, h, &err) == ORR_OK);
    CHECK(h[0] == 7.0f && h[1] == 6.0f && h[2] == 4.0f && h[3] == 7.0f);
    /* n == 0 is nothing to do. */
    CHECK(orr_smoothing_lengths(0, x1, y1, z1, 32, 0.5f, h, &err) == ORR_OK);
}

/* More than k copies of a position give h = 0 there; exactly k copies
 * (k - 1 others) reach out to the next position. */
static void test_identical_positions(void)
{
    enum { N = 50000 };
    cloud c = cloud_alloc(N);
    for (size_t i = 0; i < N; i++)
        c.x[i] = c.y[i] = c.z[i] = 1.5f;
    float *h = malloc(N * sizeof *h);
    orr_error err = {0};
    CHECK(orr_smoothing_lengths(N, c.x, c.y, c.z, 32, 0.5f, h, &err) == ORR_OK);
    int zero = 1;
    for (size_t i = 0; i < N; i++)
        zero &= h[i] == 0.0f;
    CHECK(zero);
    /* 8 copies at 0 and one point at 4: with k = 8 the copies' 8th other
     * neighbour is the point at 4 (h = 2); with k = 7 it is a copy. */
    for (size_t i = 0; i < 8; i++)
        c.x[i] = c.y[i] = c.z[i] = 0.0f;
    c.x[8] = 4.0f;
    c.y[8] = c.z[8] = 0.0f;
    CHECK(orr_smoothing_lengths(9, c.x, c.y, c.z, 8, 0.5f, h, &err) == ORR_OK);
    CHECK(h[0] == 2.0f && h[7] == 2.0f && h[8] == 2.0f);
    CHECK(orr_smoothing_lengths(9, c.x, c.y, c.z, 7, 0.5f, h, &err) == ORR_OK);
    CHECK(h[0] == 0.0f && h[7] == 0.0f && h[8] == 2.0f);
    free(h);
    cloud_free(&c);
}

/* Queries at arbitrary points, every rank from 0 to past n. */
static void test_queries_off_the_points(void)
{
    cloud c = make_cloud(CLUSTERED, 300, 77);
    orr_kdtree t;
    orr_error err = {0};
    CHECK(orr_kdtree_build(&t, c.n, c.x, c.y, c.z, &err) == ORR_OK);
    double heap[400];
    int bad = 0;
    for (int trial = 0; trial < 40; trial++) {
        float q[3] = {(float)(uniform01() * 20 - 10), (float)(uniform01() * 20 - 10), (float)(uniform01() * 20 - 10)};
        if (trial % 4 == 0)
            q[0] = q[1] = q[2] = 1000.0f + (float)uniform01() * 1e-3f;
        for (size_t k = 1; k <= 60; k += 7)
            bad += orr_kdtree_kth_dist2(&t, q, k, heap) != brute_kth_dist2(&c, q, k);
        bad += orr_kdtree_kth_dist2(&t, q, c.n + 1, heap) != INFINITY;
        bad += orr_kdtree_kth_dist2(&t, q, 0, heap) != 0.0;
    }
    CHECK(bad == 0);
    orr_kdtree_free(&t);
    cloud_free(&c);
}

/* Checks the subtree of node: its box holds its points tightly, the
 * children split along some axis, and leaves have 8 to 16 points. */
static int check_node(const orr_kdtree *t, size_t node, size_t b, size_t e, int level)
{
    int bad = 0;
    const orr_kdbox *box = &t->box[node];
    for (int a = 0; a < 3; a++) {
        float lo = INFINITY, hi = -INFINITY;
        for (size_t i = b; i < e; i++) {
            lo = fminf(lo, t->pts[i].p[a]);
            hi = fmaxf(hi, t->pts[i].p[a]);
        }
        bad += lo != box->lo[a] || hi != box->hi[a];
    }
    if (level == t->depth)
        return bad + (e - b < 8 || e - b > ORR_KD_LEAF_MAX);
    const orr_kdbox *l = &t->box[2 * node + 1], *r = &t->box[2 * node + 2];
    int split = 0;
    for (int a = 0; a < 3; a++)
        split |= l->hi[a] <= r->lo[a];
    size_t m = orr_kd_mid(b, e);
    return bad + !split + check_node(t, 2 * node + 1, b, m, level + 1) +
           check_node(t, 2 * node + 2, m, e, level + 1);
}

static void test_tree_structure(void)
{
    const size_t sizes[] = {17, 100, 1000, 40000, 70001};
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++)
        for (int kind = 0; kind < NKINDS; kind++) {
            cloud c = make_cloud(kind, sizes[s], 5 + s);
            orr_kdtree t;
            orr_error err = {0};
            CHECK(orr_kdtree_build(&t, c.n, c.x, c.y, c.z, &err) == ORR_OK);
            CHECK(t.nnodes == ((size_t)2 << t.depth) - 1);
            CHECK(check_node(&t, 0, 0, t.n, 0) == 0);
            /* every particle appears exactly once */
            char *seen = calloc(c.n, 1);
            int ok = 1;
            for (size_t i = 0; i < c.n; i++) {
                uint32_t j = t.pts[i].index;
                ok &= j < c.n && !seen[j] && t.pts[i].p[0] == c.x[j] && t.pts[i].p[1] == c.y[j] &&
                      t.pts[i].p[2] == c.z[j];
                seen[j] = 1;
            }
            CHECK(ok);
            free(seen);
            orr_kdtree_free(&t);
            cloud_free(&c);
        }
}

/* Sorted, reversed and sawtooth coordinates: inputs that defeat naive
 * pivots. The tree must still be balanced and the answers right. */
static void test_ordered_inputs(void)
{
    enum { N = 60000 };
    cloud c = cloud_alloc(N);
    for (int pattern = 0; pattern < 3; pattern++) {
        for (size_t i = 0; i < N; i++) {
            float v = pattern == 0 ? (float)i : pattern == 1 ? (float)(N - i) : (float)(i % 1000);
            c.x[i] = v;
            c.y[i] = 0.5f * v;
            c.z[i] = (float)(i % 3);
        }
        orr_kdtree t;
        orr_error err = {0};
        CHECK(orr_kdtree_build(&t, c.n, c.x, c.y, c.z, &err) == ORR_OK);
        CHECK(check_node(&t, 0, 0, t.n, 0) == 0);
        double heap[33];
        int bad = 0;
        for (size_t i = 0; i < N; i += 997) {
            float q[3] = {c.x[i], c.y[i], c.z[i]};
            bad += orr_kdtree_kth_dist2(&t, q, 33, heap) != brute_kth_dist2(&c, q, 33);
        }
        CHECK(bad == 0);
        orr_kdtree_free(&t);
    }
    cloud_free(&c);
}

/* Above the task threshold, with 1 and 2 threads: the same lengths, and a
 * sample of them right. */
static void test_thread_count_independence(void)
{
    enum { N = 120000 };
    cloud c = make_cloud(CLUSTERED, N, 4242);
    float *h1 = malloc(N * sizeof *h1), *h2 = malloc(N * sizeof *h2);
    orr_error err = {0};
    int saved = omp_get_max_threads();
    omp_set_num_threads(1);
    CHECK(orr_smoothing_lengths(N, c.x, c.y, c.z, 32, 0.5f, h1, &err) == ORR_OK);
    omp_set_num_threads(2);
    CHECK(orr_smoothing_lengths(N, c.x, c.y, c.z, 32, 0.5f, h2, &err) == ORR_OK);
    omp_set_num_threads(saved);
    CHECK(memcmp(h1, h2, N * sizeof *h1) == 0);
    int bad = 0;
    for (size_t i = 0; i < N; i += 1201) {
        float q[3] = {c.x[i], c.y[i], c.z[i]};
        bad += h1[i] != (float)(0.5 * sqrt(brute_kth_dist2(&c, q, 33)));
    }
    CHECK(bad == 0);
    free(h1);
    free(h2);
    cloud_free(&c);
}

/* orr_smoothing_lengths_bounded on one cloud, with each point's limit
 * drawn around its exact length: below it (the search must find it
 * exactly), equal to it (the boundary: only the exact length is within),
 * one float below it, above it by up to 4 times, 0 and NaN (exact). A
 * length within its limit may stand at a bound: at least the exact one,
 * at most the limit. Returns the mismatches; *skipped the bounded count. */
static int check_bounded(const cloud *c, int k, const float *exact, size_t *skipped)
{
    orr_error err = {0};
    float *enough = malloc((c->n ? c->n : 1) * sizeof *enough), *h = malloc((c->n ? c->n : 1) * sizeof *h);
    for (size_t i = 0; i < c->n; i++) {
        switch (i % 7) {
        case 0: enough[i] = exact[i]; break;
        case 1: enough[i] = nextafterf(exact[i], 0.0f); break;
        case 2: enough[i] = exact[i] * 0.5f; break;
        case 3: enough[i] = 0.0f; break;
        case 4: enough[i] = NAN; break;
        default: enough[i] = exact[i] * (float)(1.0 + 3.0 * uniform01()); break;
        }
    }
    orr_kdtree t;
    int bad = orr_kdtree_build(&t, c->n, c->x, c->y, c->z, &err) != ORR_OK;
    bad += !bad && orr_smoothing_lengths_bounded(&t, k, 0.5f, enough, h, skipped, &err) != ORR_OK;
    size_t within = 0;
    for (size_t i = 0; i < c->n && !bad; i++) {
        int may_bound = enough[i] > 0 && exact[i] <= enough[i];
        within += may_bound;
        int ok = may_bound ? h[i] >= exact[i] && h[i] <= enough[i] : h[i] == exact[i];
        if (!ok && bad++ < 3)
            fprintf(stderr, "  particle %zu of %zu, k = %d: h %.9g, exact %.9g, limit %.9g\n", i, c->n, k,
                    (double)h[i], (double)exact[i], (double)enough[i]);
    }
    bad += *skipped > within;
    orr_kdtree_free(&t);
    free(enough);
    free(h);
    return bad;
}

static void test_bounded_lengths(void)
{
    const int ks[] = {1, 8, 32};
    size_t skipped_all = 0;
    for (int kind = 0; kind < NKINDS; kind++)
        for (int ki = 0; ki < 3; ki++) {
            size_t sizes[] = {0, 1, 2, (size_t)ks[ki], (size_t)ks[ki] + 1, (size_t)ks[ki] + 2, 500, 5000};
            for (size_t si = 0; si < sizeof sizes / sizeof sizes[0]; si++) {
                cloud c = make_cloud(kind, sizes[si], 7000 + 17 * si + 3 * ki + kind);
                float *exact = malloc((c.n ? c.n : 1) * sizeof *exact);
                orr_error err = {0};
                CHECK(orr_smoothing_lengths(c.n, c.x, c.y, c.z, ks[ki], 0.5f, exact, &err) == ORR_OK);
                size_t skipped = 0;
                int bad = check_bounded(&c, ks[ki], exact, &skipped);
                if (bad)
                    fprintf(stderr, "  %s, n = %zu, k = %d: %d mismatches\n", kind_names[kind], c.n, ks[ki], bad);
                CHECK(bad == 0);
                skipped_all += skipped;
                free(exact);
                cloud_free(&c);
            }
        }
    CHECK(skipped_all > 0); /* (the limits above their lengths leave some at a bound) */
}

/* A limit far above every length: each is left at a bound (the node's), on
 * 1 and 2 threads alike; with no limits the lengths are exact. */
static void test_bounded_threads(void)
{
    enum { N = 120000 };
    cloud c = make_cloud(UNIFORM, N, 99);
    float *enough = malloc(N * sizeof *enough), *h1 = malloc(N * sizeof *h1), *h2 = malloc(N * sizeof *h2);
    float *exact = malloc(N * sizeof *exact);
    for (size_t i = 0; i < N; i++)
        enough[i] = i % 2 ? 10.0f : 0.0f;
    orr_error err = {0};
    orr_kdtree t;
    CHECK(orr_kdtree_build(&t, N, c.x, c.y, c.z, &err) == ORR_OK);
    size_t s1 = 0, s2 = 0;
    int saved = omp_get_max_threads();
    omp_set_num_threads(1);
    CHECK(orr_smoothing_lengths_bounded(&t, 32, 0.5f, enough, h1, &s1, &err) == ORR_OK);
    omp_set_num_threads(2);
    CHECK(orr_smoothing_lengths_bounded(&t, 32, 0.5f, enough, h2, &s2, &err) == ORR_OK);
    omp_set_num_threads(saved);
    CHECK(orr_smoothing_lengths_bounded(&t, 32, 0.5f, NULL, exact, NULL, &err) == ORR_OK);
    CHECK(memcmp(h1, h2, N * sizeof *h1) == 0);
    CHECK(s1 == N / 2 && s2 == N / 2);
    int bad = 0;
    for (size_t i = 0; i < N; i++)
        bad += i % 2 ? !(h1[i] >= exact[i] && h1[i] <= 10.0f) : h1[i] != exact[i];
    CHECK(bad == 0);
    orr_kdtree_free(&t);
    free(enough), free(h1), free(h2), free(exact);
    cloud_free(&c);
}

static void test_errors(void)
{
    float x[10], y[10], z[10], h[10];
    for (int i = 0; i < 10; i++)
        x[i] = y[i] = z[i] = (float)i;
    orr_error err = {0};
    CHECK(orr_smoothing_lengths(10, x, y, z, 0, 0.5f, h, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "k = 0");
    CHECK(orr_smoothing_lengths(10, x, y, z, -3, 0.5f, h, &err) == ORR_ERR_USAGE);
    CHECK(orr_smoothing_lengths(10, x, y, z, 32, 0.0f, h, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "factor");
    CHECK(orr_smoothing_lengths(10, x, y, z, 32, NAN, h, &err) == ORR_ERR_USAGE);
    CHECK(orr_smoothing_lengths(10, x, y, z, 32, INFINITY, h, &err) == ORR_ERR_USAGE);
    y[7] = NAN;
    z[9] = INFINITY;
    CHECK(orr_smoothing_lengths(10, x, y, z, 32, 0.5f, h, &err) == ORR_ERR_DATA);
    CHECK_CONTAINS(err.msg, "particle 7 ");
    CHECK_CONTAINS(err.msg, "non-finite");
    y[7] = 7.0f;
    CHECK(orr_smoothing_lengths(10, x, y, z, 32, 0.5f, h, &err) == ORR_ERR_DATA);
    CHECK_CONTAINS(err.msg, "particle 9 ");
    orr_kdtree t;
    CHECK(orr_kdtree_build(&t, ORR_KD_MAX_POINTS + 1, x, y, z, &err) == ORR_ERR_USAGE);
    CHECK(t.pts == NULL && t.box == NULL);
    orr_kdtree_free(&t);
}

int main(void)
{
    RUN(test_matches_brute_force);
    RUN(test_small_cases_by_hand);
    RUN(test_identical_positions);
    RUN(test_queries_off_the_points);
    RUN(test_tree_structure);
    RUN(test_ordered_inputs);
    RUN(test_thread_count_independence);
    RUN(test_bounded_lengths);
    RUN(test_bounded_threads);
    RUN(test_errors);
    return check_summary();
}
