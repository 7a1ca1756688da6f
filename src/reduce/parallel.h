/* How the processes rendering one frame together combine their work (MPI
 * ranks; src/mpi/ is the back end, over a communicator). Each process
 * splats its share of the particles; the sums are reduced onto rank 0,
 * which alone post-processes and writes. The library itself knows nothing
 * of MPI: it sees only the three reductions below. */
#ifndef ORR_REDUCE_PARALLEL_H
#define ORR_REDUCE_PARALLEL_H

#include <stddef.h>
#include <stdint.h>

#include "core/error.h"
#include "core/plane.h"
#include "splat/deposit.h"

typedef struct orr_parallel {
    int rank, nranks;
    /* Sums v[0..n) over the processes; every process gets the sums. */
    orr_status (*allreduce_sum)(void *user, double *v, size_t n, orr_error *err);
    /* Sums v[0..n) of every process into rank 0's v; the others' v is left as it was. */
    orr_status (*reduce_sum)(void *user, float *v, size_t n, orr_error *err);
    /* Collective: returns mine, or an error when any other process failed. */
    orr_status (*any_failed)(void *user, orr_status mine, orr_error *err);
    void *user;
} orr_parallel;

/* Sums planes[0..n) of every process into rank 0's (reduce_sum, plane by
 * plane, in the back end's order). Collective. */
orr_status orr_parallel_sum_planes(const orr_parallel *par, orr_plane *planes, int n, orr_error *err);

/* Counters of the caller's summed over the processes in one collective
 * call (allreduce_sum of doubles: counts are exact below 2^53): each entry
 * points at a count or a weight, which gets the sum on every process. */
#define ORR_SUMS_MAX 32
typedef struct orr_sums {
    int n;
    uint64_t *count[ORR_SUMS_MAX]; /* entry i is *count[i], or when NULL *weight[i] */
    double *weight[ORR_SUMS_MAX];
} orr_sums;

/* Adds an entry (more than ORR_SUMS_MAX are a programming error, ignored). */
void orr_sums_count(orr_sums *s, uint64_t *count);
void orr_sums_weight(orr_sums *s, double *weight);
/* A deposit's weights and counts: deposited, outside, culled, n_particles, n_culled. */
void orr_sums_deposit(orr_sums *s, orr_deposit_stats *d);

/* Sums the entries over the processes. Collective. */
orr_status orr_parallel_sum(const orr_parallel *par, orr_sums *s, orr_error *err);

#endif
