#include "mpi/mpi_parallel.h"

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

/* Sums every rank's plane into rank 0's, tile by tile. */
static orr_status reduce_sum(void *user, float *v, size_t n, orr_error *err)
{
    MPI_Comm comm = *(MPI_Comm *)user;
    int rank;
    MPI_Comm_rank(comm, &rank);
    for (size_t off = 0; off < n; off += ORR_MPI_TILE_FLOATS) {
        int len = (int)(n - off < ORR_MPI_TILE_FLOATS ? n - off : ORR_MPI_TILE_FLOATS);
        int rc = rank == 0 ? MPI_Reduce(MPI_IN_PLACE, v + off, len, MPI_FLOAT, MPI_SUM, 0, comm)
                           : MPI_Reduce(v + off, NULL, len, MPI_FLOAT, MPI_SUM, 0, comm);
        if (rc != MPI_SUCCESS)
            return mpi_fail(rc, err, "reduction of an image plane");
    }
    return ORR_OK;
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
