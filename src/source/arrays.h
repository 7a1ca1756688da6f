/* A source over arrays in memory (orr_particle_arrays, declared in the
 * public header orrery.h): a running simulation's particles, handed over
 * each step without copying them whole. The source converts one chunk at a
 * time from the code's own layout. */
#ifndef ORR_SOURCE_ARRAYS_H
#define ORR_SOURCE_ARRAYS_H

#include <stddef.h>
#include <stdint.h>

#include "orrery.h"
#include "source/source.h"

/* Opens a source reading the arrays (which must stay valid and unchanged
 * until the source is closed), chunk_size particles at a time, of the types
 * in type_mask (0: all). `what` names it in messages. Fails on a missing
 * position array, an unknown dtype, or a field name that is too long. */
orr_status orr_arrays_source_open(const orr_particle_arrays *a, const char *what, size_t chunk_size,
                                  unsigned type_mask, orr_source **out, orr_error *err);

#endif
