/* The Tipsy binary snapshot reader (PKDGRAV, ChaNGa, Gasoline): standard
 * big-endian (XDR) files and native little-endian ones, with the padded
 * 32-byte header or the unpadded 28-byte one. See docs/format-tipsy.md. */
#ifndef ORR_SOURCE_TIPSY_H
#define ORR_SOURCE_TIPSY_H

#include <stddef.h>

#include "source/source.h"

/* Returns 1 when the first n bytes (n <= ORR_PROBE_BYTES) hold a Tipsy
 * header whose counts are consistent in one byte order; when n is below
 * ORR_PROBE_BYTES the whole file was seen, and its size must match too. */
int orr_tipsy_probe(const unsigned char *head, size_t n);

/* Opens a Tipsy file. Particles come gas first, then dark, then star, with
 * types 0, 1 and 4 and ids equal to their index in the file. */
orr_status orr_tipsy_source_open(const char *path, const orr_source_options *opt, orr_source **out,
                                 orr_error *err);

#endif
