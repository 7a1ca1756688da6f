/* Times the renderer's splat on particles held in memory (the in-situ
 * arrays source), so that no reader or generator is timed with it: for the
 * benchmarks bench_threads and bench_inmemory. */
#ifndef ORR_TEST_FRAME_TIMER_H
#define ORR_TEST_FRAME_TIMER_H

#include "orrery.h"

/* Renders the scene (YAML text with input: {insitu: true}; outputs go to
 * /tmp, no PNG) from the arrays `repeats` times and returns the best wall
 * seconds from the frame's start to the end of its splat (the last progress
 * call: set-up, splat and the lanes' reduction included, outputs excluded);
 * *cpu: the process's CPU seconds over the same span of that repeat. Exits
 * with a message on any error. */
double frame_timer_best(const char *yaml, const orr_particle_arrays *a, int repeats, double *cpu);

#endif
