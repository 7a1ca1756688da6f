/* A chunk of n particles for tests: at the origin, mass 1, ids 1..n,
 * type 0, every extra field 0 (tests then set what they need). Exits on
 * an allocation failure. */
#ifndef ORR_TEST_CHUNK_H
#define ORR_TEST_CHUNK_H

#include <stddef.h>

#include "particles/chunk.h"

orr_chunk test_chunk(size_t n, const char *const *extra, int nextra);

#endif
