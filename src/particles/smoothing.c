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

orr_status orr_smoothing_lengths_tree(const orr_kdtree *tree, int k, float factor, float *h_out,
                                      orr_error *err)
{
    orr_status st = check_parameters(k, factor, err);
    if (st != ORR_OK)
        return st;
    size_t n = tree->n;
    if (n == 0)
        return ORR_OK;
    /* Each particle is its own nearest point (distance 0, counted once even
     * among duplicates), so its k-th neighbour is the tree's (k+1)-th
     * nearest point to it; with n <= k that is the farthest of all. */
    size_t rank = (size_t)k + 1 < n ? (size_t)k + 1 : n;
    int nthreads = omp_get_max_threads();
    double *heaps = orr_malloc((size_t)nthreads * rank * sizeof *heaps, "neighbour search heaps", err);
    if (!heaps)
        return ORR_ERR_NOMEM;
    double f = factor;
#pragma omp parallel for schedule(dynamic, QUERY_BLOCK) if (n > QUERY_BLOCK)
    for (size_t i = 0; i < n; i++) {
        double *heap = heaps + (size_t)omp_get_thread_num() * rank;
        const orr_kdpoint *p = &tree->pts[i];
        h_out[p->index] = (float)(f * sqrt(orr_kdtree_kth_dist2(tree, p->p, rank, heap)));
    }
    free(heaps);
    return ORR_OK;
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
