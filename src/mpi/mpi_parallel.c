#include "mpi/mpi_parallel.h"

#include <stdlib.h>
#include <string.h>

static orr_status mpi_fail(int rc, orr_error *err, const char *what)
{
    char msg[MPI_MAX_ERROR_STRING];
    int len = 0;
    MPI_Error_string(rc, msg, &len);
    return orr_fail(err, ORR_ERR_INTERNAL, "MPI %s failed: %.*s", what, len, msg);
}

static orr_status allreduce_sum(void *user, double *v, size_t n, orr_error *err)
{
    MPI_Comm comm = *(MPI_Comm *)user;
    int rc = MPI_Allreduce(MPI_IN_PLACE, v, (int)n, MPI_DOUBLE, MPI_SUM, comm);
    return rc == MPI_SUCCESS ? ORR_OK : mpi_fail(rc, err, "all-reduce");
}

/* MPI_Reduce_scatter leaves each rank the sum of its tile of the group
 * (so the ranks share the additions, and no buffer of MPI's or ours holds
 * more than a group), then rank 0 gathers the tiles into its plane. The
 * last group's tiles are shorter, some perhaps empty. */
orr_status orr_mpi_reduce_plane(MPI_Comm comm, float *v, size_t n, size_t group_floats, orr_error *err)
{
    int rank, nranks;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &nranks);
    const size_t tile = group_floats / (size_t)nranks ? group_floats / (size_t)nranks : 1;
    int *count = orr_malloc(2 * (size_t)nranks * sizeof *count, "MPI tile counts", err);
    float *mine = count ? orr_malloc(tile * sizeof *mine, "MPI reduction tile", err) : NULL;
    if (!mine) {
        free(count);
        return ORR_ERR_NOMEM;
    }
    int *offset = count + nranks;
    orr_status st = ORR_OK;
    for (size_t group = 0; group < n && !st; group += tile * (size_t)nranks) {
        size_t at = group;
        for (int r = 0; r < nranks; r++) {
            size_t len = n - at < tile ? n - at : tile;
            count[r] = (int)len;
            offset[r] = (int)(at - group);
            at += len;
        }
        int rc = MPI_Reduce_scatter(v + group, mine, count, MPI_FLOAT, MPI_SUM, comm);
        if (rc == MPI_SUCCESS && rank == 0) {
            memcpy(v + group, mine, (size_t)count[0] * sizeof *mine); /* rank 0's tile is first */
            rc = MPI_Gatherv(MPI_IN_PLACE, count[0], MPI_FLOAT, v + group, count, offset, MPI_FLOAT, 0, comm);
        } else if (rc == MPI_SUCCESS) {
            rc = MPI_Gatherv(mine, count[rank], MPI_FLOAT, NULL, NULL, NULL, MPI_FLOAT, 0, comm);
        }
        if (rc != MPI_SUCCESS)
            st = mpi_fail(rc, err, "reduction of an image plane");
    }
    free(mine);
    free(count);
    return st;
}

static orr_status reduce_sum(void *user, float *v, size_t n, orr_error *err)
{
    return orr_mpi_reduce_plane(*(MPI_Comm *)user, v, n, ORR_MPI_TILE_FLOATS, err);
}

/* One rank's error stops them all: each says whether it failed, and all
 * learn whether any did, so none waits for a reduction that never comes. */
static orr_status any_failed(void *user, orr_status mine, orr_error *err)
{
    MPI_Comm comm = *(MPI_Comm *)user;
    int failed = mine != ORR_OK, any = 0;
    if (MPI_Allreduce(&failed, &any, 1, MPI_INT, MPI_MAX, comm) != MPI_SUCCESS)
        return orr_fail(err, ORR_ERR_INTERNAL, "MPI all-reduce of the error flags failed");
    if (mine)
        return mine;
    return any ? orr_fail(err, ORR_ERR_INTERNAL, "another MPI rank failed (its message is above)") : ORR_OK;
}

orr_parallel orr_mpi_parallel(MPI_Comm *comm)
{
    orr_parallel p = {0};
    MPI_Comm_rank(*comm, &p.rank);
    MPI_Comm_size(*comm, &p.nranks);
    p.allreduce_sum = allreduce_sum;
    p.reduce_sum = reduce_sum;
    p.any_failed = any_failed;
    p.user = comm;
    return p;
}
