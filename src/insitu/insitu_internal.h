/* What the in-situ API's MPI glue (src/mpi/insitu_mpi.c) needs of the
 * renderer, which itself knows nothing of MPI. */
#ifndef ORR_INSITU_INSITU_INTERNAL_H
#define ORR_INSITU_INSITU_INTERNAL_H

#include "orrery.h"
#include "render/render.h"

/* From now on every frame is rendered by the processes of par together:
 * each hands over its own particles, rank 0 writes. The renderer keeps a
 * copy of user[0..user_size) (e.g. an MPI communicator handle, at most 64
 * bytes) and points par->user at it. */
int orr_insitu_set_parallel(orrery_renderer *r, const orr_parallel *par, const void *user, size_t user_size);

#endif
