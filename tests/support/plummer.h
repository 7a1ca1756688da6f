/* Positions drawn from a Plummer sphere of scale radius 1, for the
 * benchmarks (bench_knn, bench_snapshot). Particle i is a pure function of
 * (seed, i), as in the built-in model. */
#ifndef ORR_TEST_PLUMMER_H
#define ORR_TEST_PLUMMER_H

#include <stddef.h>
#include <stdint.h>

/* Fills x, y, z with n positions; radii beyond rmax (> 0) are not drawn
 * (the mass inside rmax is sampled, so every particle carries 1/n of it). */
void plummer_positions(size_t n, uint64_t seed, double rmax, float *x, float *y, float *z);

#endif
