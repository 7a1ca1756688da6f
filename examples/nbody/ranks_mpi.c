/* orrery-nbody-mpi: the ranks of MPI_COMM_WORLD. */
#include <limits.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "mpi/orrery_mpi.h"
#include "ranks.h"

void ranks_start(int *argc, char ***argv, int *rank, int *size)
{
    MPI_Init(argc, argv);
    MPI_Comm_rank(MPI_COMM_WORLD, rank);
    MPI_Comm_size(MPI_COMM_WORLD, size);
}

void ranks_finish(void)
{
    MPI_Finalize();
}

int ranks_counts(size_t mine, size_t *counts)
{
    uint64_t m = mine;
    int size;
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    uint64_t *all = malloc((size_t)size * sizeof *all);
    int ok = all && MPI_Allgather(&m, 1, MPI_UINT64_T, all, 1, MPI_UINT64_T, MPI_COMM_WORLD) == MPI_SUCCESS;
    for (int r = 0; ok && r < size; r++)
        counts[r] = (size_t)all[r];
    free(all);
    if (!ok)
        fprintf(stderr, "orrery-nbody-mpi: gathering the ranks' particle counts failed\n");
    return ok ? 0 : -1;
}

int ranks_gather(double *all, size_t per, const size_t *counts)
{
    int size;
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    int *count = malloc((size_t)size * sizeof *count), *offset = malloc((size_t)size * sizeof *offset);
    int ok = count && offset;
    size_t at = 0;
    for (int r = 0; ok && r < size; r++) {
        /* MPI counts are int: this simple scheme is for demonstration. */
        ok = counts[r] * per <= INT_MAX && at <= INT_MAX;
        if (ok) {
            count[r] = (int)(counts[r] * per);
            offset[r] = (int)at;
        }
        at += counts[r] * per;
    }
    if (!ok)
        fprintf(stderr, "orrery-nbody-mpi: more values than an MPI count holds (%zu): use more ranks\n", at);
    else if (MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, all, count, offset, MPI_DOUBLE, MPI_COMM_WORLD) !=
             MPI_SUCCESS) {
        fprintf(stderr, "orrery-nbody-mpi: gathering the positions failed\n");
        ok = 0;
    }
    free(count);
    free(offset);
    return ok ? 0 : -1;
}

int ranks_allgather_u64(const uint64_t *mine, int n, uint64_t *all)
{
    if (MPI_Allgather(mine, n, MPI_UINT64_T, all, n, MPI_UINT64_T, MPI_COMM_WORLD) != MPI_SUCCESS) {
        fprintf(stderr, "orrery-nbody-mpi: gathering the ranks' fingerprints failed\n");
        return -1;
    }
    return 0;
}

/* Byte counts as MPI's int counts and offsets; 0 when one does not fit. */
static int as_counts(const size_t *bytes, int size, int *count, int *offset)
{
    size_t at = 0;
    for (int r = 0; r < size; r++) {
        if (bytes[r] > INT_MAX || at > INT_MAX)
            return 0;
        count[r] = (int)bytes[r];
        offset[r] = (int)at;
        at += bytes[r];
    }
    return 1;
}

int ranks_exchange(const void *send, const size_t *send_bytes, void **recv, size_t *recv_bytes)
{
    int size;
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    uint64_t *sent = malloc(2 * (size_t)size * sizeof *sent);
    int *counts = malloc(4 * (size_t)size * sizeof *counts);
    int ok = sent && counts;
    *recv = NULL;
    if (ranks_any(!ok)) {
        free(sent);
        free(counts);
        fprintf(stderr, "orrery-nbody-mpi: out of memory for the exchange\n");
        return -1;
    }
    uint64_t *got = sent + size;
    for (int r = 0; r < size; r++)
        sent[r] = send_bytes[r];
    ok = MPI_Alltoall(sent, 1, MPI_UINT64_T, got, 1, MPI_UINT64_T, MPI_COMM_WORLD) == MPI_SUCCESS;
    size_t total = 0;
    for (int r = 0; r < size; r++)
        total += recv_bytes[r] = ok ? (size_t)got[r] : 0;
    int *scount = counts, *soff = counts + size, *rcount = counts + 2 * size, *roff = counts + 3 * size;
    ok = ok && as_counts(send_bytes, size, scount, soff) && as_counts(recv_bytes, size, rcount, roff);
    ok = ok && (*recv = malloc(total + 1)) != NULL;
    if (ranks_any(!ok)) {
        fprintf(stderr, "orrery-nbody-mpi: the particles' exchange failed (out of memory, or more than an MPI count "
                        "holds: use more ranks)\n");
        free(*recv);
        *recv = NULL;
        free(sent);
        free(counts);
        return -1;
    }
    ok = MPI_Alltoallv(send, scount, soff, MPI_BYTE, *recv, rcount, roff, MPI_BYTE, MPI_COMM_WORLD) == MPI_SUCCESS;
    free(sent);
    free(counts);
    if (!ok) {
        fprintf(stderr, "orrery-nbody-mpi: the particles' exchange failed\n");
        free(*recv);
        *recv = NULL;
        return -1;
    }
    return 0;
}

int ranks_sum_u64(uint64_t *v, int n)
{
    if (MPI_Allreduce(MPI_IN_PLACE, v, n, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD) != MPI_SUCCESS) {
        fprintf(stderr, "orrery-nbody-mpi: summing over the ranks failed\n");
        return -1;
    }
    return 0;
}

int ranks_extreme(double *v, int n, int take_max)
{
    if (MPI_Allreduce(MPI_IN_PLACE, v, n, MPI_DOUBLE, take_max ? MPI_MAX : MPI_MIN, MPI_COMM_WORLD) != MPI_SUCCESS) {
        fprintf(stderr, "orrery-nbody-mpi: reducing over the ranks failed\n");
        return -1;
    }
    return 0;
}

int ranks_any(int failed)
{
    int mine = failed != 0, any = 1;
    MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    return any;
}

int ranks_render_together(orrery_renderer *r)
{
    return orrery_use_mpi(r, MPI_COMM_WORLD);
}
