/* Fixed random numbers for the tests and benchmarks, the same on every
 * run: a 64-bit linear congruential generator (the multiplier and
 * increment of Knuth's MMIX). */
#ifndef ORR_TEST_RANDOM_H
#define ORR_TEST_RANDOM_H

#include <stdint.h>

/* Advances *state and returns a double in [0, 1) from its top 53 bits. */
double test_uniform(uint64_t *state);

/* Advances *state and returns an integer in [0, n), n > 0. */
uint64_t test_below(uint64_t *state, uint64_t n);

#endif
