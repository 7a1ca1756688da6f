/* NumPy .npy files as particle input (docs/input.md#numpy-npy-files): a
 * structured array whose fields name the columns as a text table's header
 * does (x, y, z, mass, h, id, type, any other a named field), or a plain
 * (N, 3) array of positions. Read a chunk at a time with seeks, so files of
 * any size stream in bounded memory. */
#ifndef ORR_SOURCE_NPY_READER_H
#define ORR_SOURCE_NPY_READER_H

#include <stddef.h>

#include "source/source.h"

int orr_npy_probe(const unsigned char *head, size_t n);
orr_status orr_npy_source_open(const char *path, const orr_source_options *opt, orr_source **out, orr_error *err);

#endif
