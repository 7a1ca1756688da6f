#include "mpi/orrery_mpi.h"

#include "insitu/insitu_internal.h"
#include "mpi/mpi_parallel.h"

int orrery_use_mpi(orrery_renderer *r, MPI_Comm comm)
{
    if (!r)
        return ORRERY_ERR_USAGE;
    /* The renderer keeps its own copy of the communicator's handle. */
    orr_parallel par = orr_mpi_parallel(&comm);
    return orr_insitu_set_parallel(r, &par, &comm, sizeof comm);
}
