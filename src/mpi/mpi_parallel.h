/* MPI for the renderer: the reductions of orr_parallel over a communicator.
 * Built only when MPI is found (the library itself knows nothing of MPI). */
#ifndef ORR_MPI_MPI_PARALLEL_H
#define ORR_MPI_MPI_PARALLEL_H

#include <mpi.h>

#include "render/render.h"

/* Planes are reduced in tiles of at most this many floats, so MPI's own
 * buffers stay bounded (16 MiB) however large the image. */
#define ORR_MPI_TILE_FLOATS ((size_t)1 << 22)

/* The reductions over comm (which must outlive the returned value). */
orr_parallel orr_mpi_parallel(MPI_Comm *comm);

#endif
