#include "particles/smoothing.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>

const orr_named orr_smoothing_source_names[] = {
    {"auto", ORR_LENGTHS_AUTO}, {"file", ORR_LENGTHS_FILE}, {"neighbours", ORR_LENGTHS_NEIGHBOURS}, {NULL, 0}};

/* Queries handed to a thread at a time. Points are in tree order, so a
 * block is a compact region whose searches share cached nodes; dynamic
 * scheduling evens out dense and sparse regions. */
#define QUERY_BLOCK 256

static orr_status check_parameters(int k, float factor, orr_error *err)
{
    if (k < 1)
        return orr_fail(err, ORR_ERR_USAGE, "smoothing neighbour count k = %d must be at least 1", k);
    if (!(isfinite(factor) && factor > 0.0f))
        return orr_fail(err, ORR_ERR_USAGE, "smoothing length factor %g must be finite and positive",
                        (double)factor);
    return ORR_OK;
}

/* The deepest level of the tree whose every node holds at least rank
 * points (halving gives a level's nodes n >> L points or one more). */
static int bound_level(const orr_kdtree *t, size_t rank)
{
    int level = t->depth;
    while (level > 0 && (t->n >> level) < rank)
        level--;
    return level;
}

/* The node at `level` holding tree point i: its number and range [*b, *e). */
static size_t node_of(const orr_kdtree *t, int level, size_t i, size_t *b, size_t *e)
{
    size_t node = 0, lo = 0, hi = t->n;
    for (int l = 0; l < level; l++) {
        size_t m = orr_kd_mid(lo, hi);
        node = 2 * node + (i < m ? 1 : 2);
        if (i < m)
            hi = m;
        else
            lo = m;
    }
    *b = lo, *e = hi;
    return node;
}

/* Squared distance from q to the box's farthest corner, each axis's
 * difference as orr_kd_dist2 takes it: rounding is monotonic, so it is at
 * least every point's computed distance in the box. */
static double box_far_dist2(const orr_kdbox *box, const float *q)
{
    double d[3];
    for (int c = 0; c < 3; c++) {
        double below = (double)q[c] - box->lo[c], above = (double)box->hi[c] - q[c];
        d[c] = below > above ? below : above;
    }
    return d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
}

/* An upper bound on tree point i's length within limit, or -1 when the
 * cheap bounds exceed it. The node at `level` holds at least rank points,
 * q among them, so the rank-th smallest distance over the whole tree is at
 * most the farthest of the node's: first its box's farthest corner, then
 * its points' farthest. sqrt, the product and the rounding to float are
 * monotonic, so a bound on the squared distance bounds the length. */
static float length_bound(const orr_kdtree *t, int level, size_t i, double f, float limit)
{
    const float *q = t->pts[i].p;
    size_t b, e;
    const size_t node = node_of(t, level, i, &b, &e);
    float h = (float)(f * sqrt(box_far_dist2(&t->box[node], q)));
    if (h <= limit)
        return h;
    double far = 0.0;
    for (size_t j = b; j < e; j++) {
        double d2 = orr_kd_dist2(q, t->pts[j].p);
        far = d2 > far ? d2 : far;
    }
    h = (float)(f * sqrt(far));
    return h <= limit ? h : -1.0f;
}

/* Tree point i's length, found as cheaply as limit allows: where it is at
 * most limit an upper bound within limit will do (*bounded = 1), first the
 * node's bounds, then a search that stops once the rank nearest points
 * found so far are all within it (orr_kdtree_kth_dist2_within); else the
 * exact length (*bounded = 0), which that search then found. */
static float bounded_length(const orr_kdtree *t, int level, size_t i, size_t rank, double f, float limit,
                            double *heap, int *bounded)
{
    const float *q = t->pts[i].p;
    float h = length_bound(t, level, i, f, limit);
    *bounded = h >= 0.0f;
    if (*bounded)
        return h;
    double stop = (double)limit / f;
    double d2 = orr_kdtree_kth_dist2_within(t, q, rank, stop * stop, heap);
    h = (float)(f * sqrt(d2));
    *bounded = d2 <= stop * stop && h <= limit;
    if (d2 <= stop * stop && !*bounded) /* (within stop^2, yet over limit once rounded: search it all) */
        h = (float)(f * sqrt(orr_kdtree_kth_dist2(t, q, rank, heap)));
    return h;
}

orr_status orr_smoothing_lengths_bounded(const orr_kdtree *tree, int k, float factor, const float *enough,
                                         float *h_out, size_t *skipped, orr_error *err)
{
    orr_status st = check_parameters(k, factor, err);
    size_t n_skipped = 0;
    if (skipped)
        *skipped = 0;
    if (st != ORR_OK)
        return st;
    size_t n = tree->n;
    if (n == 0)
        return ORR_OK;
    /* Each particle is its own nearest point (distance 0, counted once even
     * among duplicates), so its k-th neighbour is the tree's (k+1)-th
     * nearest point to it; with n <= k that is the farthest of all. */
    size_t rank = (size_t)k + 1 < n ? (size_t)k + 1 : n;
    const int level = bound_level(tree, rank);
    int nthreads = omp_get_max_threads();
    double *heaps = orr_malloc((size_t)nthreads * rank * sizeof *heaps, "neighbour search heaps", err);
    if (!heaps)
        return ORR_ERR_NOMEM;
    double f = factor;
#pragma omp parallel for schedule(dynamic, QUERY_BLOCK) reduction(+ : n_skipped) if (n > QUERY_BLOCK)
    for (size_t i = 0; i < n; i++) {
        double *heap = heaps + (size_t)omp_get_thread_num() * rank;
        const orr_kdpoint *p = &tree->pts[i];
        if (enough && enough[p->index] > 0.0f) { /* (NaN: exact) */
            int bounded;
            h_out[p->index] = bounded_length(tree, level, i, rank, f, enough[p->index], heap, &bounded);
            n_skipped += (size_t)bounded;
        } else {
            h_out[p->index] = (float)(f * sqrt(orr_kdtree_kth_dist2(tree, p->p, rank, heap)));
        }
    }
    free(heaps);
    if (skipped)
        *skipped = n_skipped;
    return ORR_OK;
}

orr_status orr_smoothing_lengths_tree(const orr_kdtree *tree, int k, float factor, float *h_out,
                                      orr_error *err)
{
    return orr_smoothing_lengths_bounded(tree, k, factor, NULL, h_out, NULL, err);
}

orr_status orr_smoothing_lengths(size_t n, const float *x, const float *y, const float *z, int k,
                                 float factor, float *h_out, orr_error *err)
{
    orr_status st = check_parameters(k, factor, err);
    if (st != ORR_OK)
        return st;
    orr_kdtree tree;
    st = orr_kdtree_build(&tree, n, x, y, z, err);
    if (st != ORR_OK)
        return st;
    st = orr_smoothing_lengths_tree(&tree, k, factor, h_out, err);
    orr_kdtree_free(&tree);
    return st;
}
