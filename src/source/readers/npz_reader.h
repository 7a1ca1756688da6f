/* NumPy .npz archives as particle input (docs/input.md#numpy-npz-archives):
 * np.savez (members stored) and np.savez_compressed (deflated) files whose
 * members are the columns, named by their keys: pos (N, 3) or x, y, z,
 * mass, h, id, type, any other a named field, (N, k) arrays as NAME[i]. The
 * members are read side by side a chunk at a time, so archives of any size
 * stream in bounded memory. */
#ifndef ORR_SOURCE_NPZ_READER_H
#define ORR_SOURCE_NPZ_READER_H

#include <stddef.h>

#include "source/source.h"

int orr_npz_probe(const unsigned char *head, size_t n);
orr_status orr_npz_source_open(const char *path, const orr_source_options *opt, orr_source **out, orr_error *err);

#endif
