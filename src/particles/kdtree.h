/* A k-d tree over float positions, for k-nearest-neighbour distances.
 *
 * The tree is balanced and implicit: every node splits its range of points
 * at the middle (by count), on the axis where its bounding box is widest,
 * so the shape depends only on N. Nodes are numbered as in a binary heap
 * (the children of node i are 2i+1 and 2i+2) and a node's range of points is
 * found by halving on the way down, so a node costs only its bounding box.
 * All leaves sit at the same depth and hold 8 to 16 points (fewer when
 * N < 8). The depth is below 32 for any N the tree accepts, which bounds
 * every recursion in the build and the queries.
 *
 * Memory: 16 bytes per point (a copy of the position and the point's index)
 * plus 24 bytes per node, one to two nodes per 8 points: 19 to 22 bytes
 * per point. Built in O(N log N) (linear-time selection on each level), in
 * parallel below the top levels with OpenMP tasks; the tree is the same for
 * any number of threads. */
#ifndef ORR_PARTICLES_KDTREE_H
#define ORR_PARTICLES_KDTREE_H

#include <stddef.h>
#include <stdint.h>

#include "core/error.h"

/* Leaves hold at most this many points: enough to amortise the box tests,
 * few enough that a leaf scan stays short. */
#define ORR_KD_LEAF_MAX 16

/* Point indices are 32-bit to keep a point at 16 bytes. */
#define ORR_KD_MAX_POINTS ((size_t)UINT32_MAX)

typedef struct orr_kdpoint {
    float p[3];
    uint32_t index; /* position in the arrays the tree was built from */
} orr_kdpoint;

typedef struct orr_kdbox {
    float lo[3], hi[3]; /* tight bounds of the node's points */
} orr_kdbox;

typedef struct orr_kdtree {
    size_t n;         /* points */
    int depth;        /* levels below the root; every leaf is at this depth */
    size_t nnodes;    /* 2^(depth+1) - 1 */
    orr_kdpoint *pts; /* the points in tree order: each node owns a contiguous range */
    orr_kdbox *box;   /* per node, heap numbering */
} orr_kdtree;

/* Builds the tree over n points. Every coordinate must be finite: the first
 * particle that is not is named in an ORR_ERR_DATA error. n may be 0;
 * n > ORR_KD_MAX_POINTS is a usage error. On failure t is left empty (safe
 * to free). */
orr_status orr_kdtree_build(orr_kdtree *t, size_t n, const float *x, const float *y, const float *z,
                            orr_error *err);
void orr_kdtree_free(orr_kdtree *t);

/* Where a node spanning points [b, e) splits: its left child takes [b, mid)
 * and its right child [mid, e). */
static inline size_t orr_kd_mid(size_t b, size_t e) { return b + (e - b) / 2; }

/* Squared distance in double. Squares of float differences can overflow or
 * underflow in float (coordinates in cm, or particles 1e-20 apart), and
 * double keeps distinct distances distinct. Queries and the tests both use
 * this one expression, so results can be compared exactly. */
static inline double orr_kd_dist2(const float a[3], const float b[3])
{
    double dx = (double)a[0] - b[0], dy = (double)a[1] - b[1], dz = (double)a[2] - b[2];
    return dx * dx + dy * dy + dz * dz;
}

/* The k smallest values seen, kept in heap[0 .. k) as a max-heap (the
 * largest at heap[0]; start with k INFINITY): replaces the largest by v,
 * which must be smaller, and restores the heap. */
void orr_kd_heap_replace_top(double *heap, size_t k, double v);

/* The squared distance from q to its k-th nearest point of the tree, as
 * orr_kd_dist2 computes it: the k-th smallest of the n distances, so a tree
 * point at q itself counts as a neighbour at distance 0. heap is scratch
 * space for k doubles. Returns INFINITY when k > n, and 0 when k == 0.
 * Exact and deterministic: the value does not depend on the order of the
 * search, so it equals a brute-force sort of the same distances. */
double orr_kdtree_kth_dist2(const orr_kdtree *t, const float q[3], size_t k, double *heap);

/* The same search, stopped once the k smallest distances found so far are
 * all at most `enough`: then it returns their largest, an upper bound on
 * the k-th distance (any k of the points bound it) that is at most enough;
 * otherwise the exact k-th distance, as above. For callers that need the
 * distance only where it exceeds some limit. */
double orr_kdtree_kth_dist2_within(const orr_kdtree *t, const float q[3], size_t k, double enough, double *heap);

#endif
