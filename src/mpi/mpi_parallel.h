/* MPI for the renderer: the back end of reduce/parallel.h, orr_parallel's
 * reductions over a communicator.
 * Built only when MPI is found (the library itself knows nothing of MPI). */
#ifndef ORR_MPI_MPI_PARALLEL_H
#define ORR_MPI_MPI_PARALLEL_H

#include <mpi.h>

#include "reduce/parallel.h"

/* Planes are reduced in groups of at most this many floats (a tile for
 * each rank), so MPI's buffers and ours stay bounded (16 MiB) however large
 * the image. */
#define ORR_MPI_TILE_FLOATS ((size_t)1 << 22)

/* Sums the n floats of v over the ranks of comm into rank 0's v, in
 * groups of at most group_floats (a tile of each group for each rank;
 * MPI_Reduce_scatter, then a gather onto rank 0). The other ranks' v are
 * left changed. Every rank must call it with the same n and group. */
orr_status orr_mpi_reduce_plane(MPI_Comm comm, float *v, size_t n, size_t group_floats, orr_error *err);

/* The reductions over comm (which must outlive the returned value). */
orr_parallel orr_mpi_parallel(MPI_Comm *comm);

#endif
