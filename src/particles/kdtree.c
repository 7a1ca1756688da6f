#include "particles/kdtree.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Nodes with at least this many points build their left child as an OpenMP
 * task: below it a task costs more than it saves. */
#define KD_TASK_MIN 32768

/* Ranges this short are finished by insertion sort. */
#define KD_SMALL 16

/* ---- selection ------------------------------------------------------- */

static inline void kd_swap(orr_kdpoint *a, orr_kdpoint *b)
{
    orr_kdpoint t = *a;
    *a = *b;
    *b = t;
}

static void kd_sort_small(orr_kdpoint *a, size_t n, int axis)
{
    for (size_t i = 1; i < n; i++) {
        orr_kdpoint v = a[i];
        size_t j = i;
        for (; j > 0 && a[j - 1].p[axis] > v.p[axis]; j--)
            a[j] = a[j - 1];
        a[j] = v;
    }
}

static inline float kd_med3(float a, float b, float c)
{
    if (a > b) {
        float t = a;
        a = b;
        b = t;
    }
    /* now a <= b: the median is b clamped to [a, c] or c clamped to [a, b] */
    return c < a ? a : (c > b ? b : c);
}

/* A cheap pivot: the median of three medians of three, spread over the
 * range, so ranges already sorted or reversed split well. */
static float kd_pivot_ninther(const orr_kdpoint *a, size_t n, int axis)
{
    size_t s = n / 8, m = n / 2, l = n - 1;
#define V(i) a[(i)].p[axis]
    float lo = kd_med3(V(0), V(s), V(2 * s));
    float mid = kd_med3(V(m - s), V(m), V(m + s));
    float hi = kd_med3(V(l - 2 * s), V(l - s), V(l));
#undef V
    return kd_med3(lo, mid, hi);
}

static void kd_select(orr_kdpoint *a, size_t n, size_t kth, int axis);

/* A pivot with at least about 3/10 of the range on each side (median of the
 * medians of groups of five), used when the cheap pivot made little
 * progress: it keeps the selection linear on any input. The group medians
 * are gathered at the front of the range, which selection is free to do. */
static float kd_pivot_mom(orr_kdpoint *a, size_t n, int axis)
{
    size_t groups = n / 5;
    for (size_t g = 0; g < groups; g++) {
        kd_sort_small(a + 5 * g, 5, axis);
        kd_swap(&a[g], &a[5 * g + 2]);
    }
    kd_select(a, groups, groups / 2, axis);
    return a[groups / 2].p[axis];
}

/* Three-way partition around pivot: [0, *lt) < pivot, [*lt, *gt) == pivot,
 * [*gt, n) > pivot. The middle block takes all copies of the pivot at once,
 * so piles of identical positions cost no more than distinct ones. */
static void kd_partition3(orr_kdpoint *a, size_t n, int axis, float pivot, size_t *lt, size_t *gt)
{
    size_t l = 0, i = 0, g = n;
    while (i < g) {
        float v = a[i].p[axis];
        if (v < pivot)
            kd_swap(&a[l++], &a[i++]);
        else if (v > pivot)
            kd_swap(&a[i], &a[--g]);
        else
            i++;
    }
    *lt = l;
    *gt = g;
}

/* Reorders a[0, n) so that a[kth] holds the value sorted order would put
 * there, with nothing greater before it and nothing smaller after it. */
static void kd_select(orr_kdpoint *a, size_t n, size_t kth, int axis)
{
    size_t lo = 0, hi = n;
    int careful = 0;
    while (hi - lo > KD_SMALL) {
        size_t len = hi - lo, lt, gt;
        float pivot = careful ? kd_pivot_mom(a + lo, len, axis) : kd_pivot_ninther(a + lo, len, axis);
        kd_partition3(a + lo, len, axis, pivot, &lt, &gt);
        if (kth < lo + lt)
            hi = lo + lt;
        else if (kth >= lo + gt)
            lo += gt;
        else
            return; /* kth is one of the copies of the pivot */
        careful = hi - lo > len / 4 * 3;
    }
    kd_sort_small(a + lo, hi - lo, axis);
}

/* ---- build ----------------------------------------------------------- */

/* Levels below the root such that no leaf holds more than ORR_KD_LEAF_MAX
 * points. Halving [b, e) at orr_kd_mid gives leaves of floor or ceil of
 * n / 2^depth points, so the smallest depth also keeps leaves above half
 * the maximum. */
static int kd_depth(size_t n)
{
    int d = 0;
    while (((n + ((size_t)1 << d) - 1) >> d) > ORR_KD_LEAF_MAX)
        d++;
    return d;
}

static void kd_set_box(orr_kdbox *box, const orr_kdpoint *a, size_t n)
{
    for (int c = 0; c < 3; c++)
        box->lo[c] = box->hi[c] = n ? a[0].p[c] : 0.0f;
    for (size_t i = 1; i < n; i++)
        for (int c = 0; c < 3; c++) {
            float v = a[i].p[c];
            box->lo[c] = v < box->lo[c] ? v : box->lo[c];
            box->hi[c] = v > box->hi[c] ? v : box->hi[c];
        }
}

/* Splitting the widest extent keeps cells from turning into slivers, which
 * would make many more of them overlap a query's neighbourhood. */
static int kd_widest_axis(const orr_kdbox *box)
{
    int axis = 0;
    double best = -1.0;
    for (int c = 0; c < 3; c++) {
        double extent = (double)box->hi[c] - box->lo[c]; /* in double: no overflow */
        if (extent > best) {
            best = extent;
            axis = c;
        }
    }
    return axis;
}

/* Depth is below 32, so the recursion is shallow. Each node's work depends
 * only on its own points, so the tree is the same with any thread count. */
static void kd_build_node(orr_kdtree *t, size_t node, size_t b, size_t e, int level)
{
    orr_kdbox *box = &t->box[node];
    kd_set_box(box, t->pts + b, e - b);
    if (level == t->depth)
        return;
    size_t m = orr_kd_mid(b, e);
    kd_select(t->pts + b, e - b, m - b, kd_widest_axis(box));
    if (e - b >= KD_TASK_MIN) {
#pragma omp task default(none) firstprivate(t, node, b, m, level)
        kd_build_node(t, 2 * node + 1, b, m, level + 1);
    } else {
        kd_build_node(t, 2 * node + 1, b, m, level + 1);
    }
    kd_build_node(t, 2 * node + 2, m, e, level + 1);
}

/* Copies the positions into tree points; returns the index of the first
 * particle with a non-finite coordinate, or n. */
static size_t kd_copy_points(orr_kdpoint *pts, size_t n, const float *x, const float *y, const float *z)
{
    size_t bad = n;
#pragma omp parallel for schedule(static) reduction(min : bad) if (n >= KD_TASK_MIN)
    for (size_t i = 0; i < n; i++) {
        pts[i] = (orr_kdpoint){{x[i], y[i], z[i]}, (uint32_t)i};
        if (!(isfinite(x[i]) && isfinite(y[i]) && isfinite(z[i])) && i < bad)
            bad = i;
    }
    return bad;
}

orr_status orr_kdtree_build(orr_kdtree *t, size_t n, const float *x, const float *y, const float *z,
                            orr_error *err)
{
    memset(t, 0, sizeof *t);
    if (n > ORR_KD_MAX_POINTS)
        return orr_fail(err, ORR_ERR_USAGE, "%zu particles are too many for the k-d tree (at most %zu)",
                        n, ORR_KD_MAX_POINTS);
    t->n = n;
    t->depth = kd_depth(n);
    t->nnodes = ((size_t)2 << t->depth) - 1;
    t->pts = orr_malloc(n * sizeof *t->pts, "k-d tree points", err);
    t->box = t->pts ? orr_malloc(t->nnodes * sizeof *t->box, "k-d tree nodes", err) : NULL;
    if (!t->box) {
        orr_kdtree_free(t);
        return ORR_ERR_NOMEM;
    }
    size_t bad = kd_copy_points(t->pts, n, x, y, z);
    if (bad < n) {
        orr_kdtree_free(t);
        return orr_fail(err, ORR_ERR_DATA, "particle %zu has a non-finite position (%g, %g, %g)", bad,
                        (double)x[bad], (double)y[bad], (double)z[bad]);
    }
#pragma omp parallel if (n >= KD_TASK_MIN)
#pragma omp single
    kd_build_node(t, 0, 0, n, 0);
    return ORR_OK;
}

void orr_kdtree_free(orr_kdtree *t)
{
    free(t->pts);
    free(t->box);
    memset(t, 0, sizeof *t);
}

/* ---- queries --------------------------------------------------------- */

typedef struct kd_search {
    const orr_kdtree *t;
    const float *q;
    double *heap; /* max-heap of the k smallest squared distances so far */
    size_t k;
    double enough; /* stop once the k-th distance so far is at most this (-1: never) */
    int done;
} kd_search;

/* Squared distance from q to the box, a lower bound for its points. It is
 * evaluated like orr_kd_dist2 (double differences, squares summed x, y, z):
 * rounding is monotonic, so the bound never exceeds a point's computed
 * distance, and pruning with it cannot change the result. */
static inline double kd_box_dist2(const orr_kdbox *box, const float *q)
{
    double d[3];
    for (int c = 0; c < 3; c++) {
        double below = (double)box->lo[c] - q[c], above = (double)q[c] - box->hi[c];
        d[c] = below > 0 ? below : (above > 0 ? above : 0.0);
    }
    return d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
}

void orr_kd_heap_replace_top(double *heap, size_t k, double v)
{
    size_t i = 0;
    for (;;) {
        size_t c = 2 * i + 1;
        if (c >= k)
            break;
        if (c + 1 < k && heap[c + 1] > heap[c])
            c++;
        if (heap[c] <= v)
            break;
        heap[i] = heap[c];
        i = c;
    }
    heap[i] = v;
}

static void kd_scan_leaf(kd_search *s, size_t b, size_t e)
{
    const orr_kdpoint *pts = s->t->pts;
    for (size_t i = b; i < e; i++) {
        double d2 = orr_kd_dist2(s->q, pts[i].p);
        if (d2 < s->heap[0])
            orr_kd_heap_replace_top(s->heap, s->k, d2);
    }
}

/* Visits the nearer child first, so the bound tightens early, and skips a
 * child whose box is no closer than the current k-th distance (a point at
 * exactly that distance would not change the k smallest). */
static void kd_search_node(kd_search *s, size_t node, size_t b, size_t e, int level)
{
    if (s->done)
        return;
    if (level == s->t->depth) {
        kd_scan_leaf(s, b, e);
        s->done = s->heap[0] <= s->enough;
        return;
    }
    size_t m = orr_kd_mid(b, e), left = 2 * node + 1, right = left + 1;
    double dl = kd_box_dist2(&s->t->box[left], s->q), dr = kd_box_dist2(&s->t->box[right], s->q);
    if (dl <= dr) {
        if (dl < s->heap[0])
            kd_search_node(s, left, b, m, level + 1);
        if (dr < s->heap[0])
            kd_search_node(s, right, m, e, level + 1);
    } else {
        if (dr < s->heap[0])
            kd_search_node(s, right, m, e, level + 1);
        if (dl < s->heap[0])
            kd_search_node(s, left, b, m, level + 1);
    }
}

double orr_kdtree_kth_dist2_within(const orr_kdtree *t, const float q[3], size_t k, double enough, double *heap)
{
    if (k == 0)
        return 0.0;
    if (k > t->n)
        return INFINITY;
    for (size_t i = 0; i < k; i++)
        heap[i] = INFINITY;
    kd_search s = {t, q, heap, k, enough < INFINITY ? enough : DBL_MAX, 0};
    kd_search_node(&s, 0, 0, t->n, 0);
    return heap[0];
}

double orr_kdtree_kth_dist2(const orr_kdtree *t, const float q[3], size_t k, double *heap)
{
    return orr_kdtree_kth_dist2_within(t, q, k, -1.0, heap); /* -1: never stops early */
}
