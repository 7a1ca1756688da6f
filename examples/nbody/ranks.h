/* The processes orrery-nbody runs on: one (ranks_serial.c, orrery-nbody) or
 * the ranks of MPI_COMM_WORLD (ranks_mpi.c, orrery-nbody-mpi). Each rank
 * owns a contiguous slice of the particles, in rank order; the functions
 * below are collective: every rank calls them. */
#ifndef NBODY_RANKS_H
#define NBODY_RANKS_H

#include <stddef.h>
#include <stdint.h>

#include "orrery.h"

/* Starts the processes (MPI_Init) and says which this one is of how many. */
void ranks_start(int *argc, char ***argv, int *rank, int *size);
void ranks_finish(void);

/* Every rank's count, counts[0 .. size). Returns 0, or -1 (a message on
 * stderr) when MPI fails. */
int ranks_counts(size_t mine, size_t *counts);

/* Fills all[] (per doubles a particle, every rank's slice in rank order)
 * from each rank's own slice, which is already in place in all[] at its
 * offset. Returns 0, or -1 when MPI fails or a slice is too large for an
 * MPI count. */
int ranks_gather(double *all, size_t per, const size_t *counts);

/* Every rank's n values, all[r * n + k] for rank r, on every rank.
 * Returns 0, or -1 (a message on stderr) when MPI fails. */
int ranks_allgather_u64(const uint64_t *mine, int n, uint64_t *all);

/* Every rank sends send_bytes[r] bytes to rank r, the pieces one after the
 * other in send (rank order), and receives what every rank sends it into
 * *recv (allocated, rank order; free() it), recv_bytes[r] from rank r: the
 * domain decomposition's all-to-all (domain.c). Returns 0, or -1 (a message
 * on stderr) when MPI fails, memory runs out or a piece is too large for an
 * MPI count, on every rank alike. */
int ranks_exchange(const void *send, const size_t *send_bytes, void **recv, size_t *recv_bytes);

/* Exact sums of every rank's v[0 .. n) into v, on every rank. 0 or -1. */
int ranks_sum_u64(uint64_t *v, int n);

/* The least (take_max 0) or largest of every rank's v[0 .. n), on every
 * rank. 0 or -1. */
int ranks_extreme(double *v, int n, int take_max);

/* Whether any rank failed (failed != 0 on it). */
int ranks_any(int failed);

/* Makes r's renders collective over the ranks (orrery_use_mpi). */
int ranks_render_together(orrery_renderer *r);

#endif
