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
