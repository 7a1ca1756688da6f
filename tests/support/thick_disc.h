/* Particles for the benchmarks: a thick disc 30 units across and 2 thick,
 * centred on the origin, the same for every run (test_random.h). */
#ifndef ORR_TEST_THICK_DISC_H
#define ORR_TEST_THICK_DISC_H

#include <stddef.h>

void thick_disc(size_t n, float *x, float *y, float *z);

#endif
