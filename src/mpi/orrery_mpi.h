/* The in-situ API on MPI ranks (docs/insitu.md): the second public header,
 * for simulation codes that run on MPI. Link liborrery_mpi as well. */
#ifndef ORRERY_MPI_H
#define ORRERY_MPI_H

#include <mpi.h>

#include "orrery.h"

#ifdef __cplusplus
extern "C" {
#endif

/* From now on each orrery_render on this renderer is collective over comm:
 * every rank calls it with its own particles (its share of the simulation),
 * each splats its share, the image planes are summed onto rank 0, and rank 0
 * writes the frame. The observer and reference particles may be on any
 * rank. Errors on any rank are reported on every rank. comm must stay valid
 * while the renderer is used. */
int orrery_use_mpi(orrery_renderer *r, MPI_Comm comm);

#ifdef __cplusplus
}
#endif

#endif
