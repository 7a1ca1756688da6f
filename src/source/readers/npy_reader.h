/* NumPy .npy files as particle input (docs/input.md#numpy-npy-files): a
 * structured array whose fields name the columns as a text table's header
 * does (x, y, z, mass, h, id, type, any other a named field), or a plain
 * (N, 3) array of positions. Read a chunk at a time with seeks, so files of
 * any size stream in bounded memory. */
#ifndef ORR_SOURCE_NPY_READER_H
#define ORR_SOURCE_NPY_READER_H

#include <stddef.h>

#include "source/source.h"

/* Whether files are memory-mapped (1) or read a block at a time with
 * fread (0, the default). Mapping was measured no faster on cached files
 * (bench/bench_npy_read.c, docs/python.md#measured) and a file truncated
 * while mapped would end the process with SIGBUS, where fread reports an
 * error: it stays for that benchmark and the tests that compare both.
 * Not thread-safe. */
#define NPY_MAP_DEFAULT 0
void orr_npy_set_mapping(int on);

int orr_npy_probe(const unsigned char *head, size_t n);
orr_status orr_npy_source_open(const char *path, const orr_source_options *opt, orr_source **out, orr_error *err);

#endif
