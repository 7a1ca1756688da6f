/* Clocks for the benchmarks: wall seconds (monotonic) and the CPU seconds
 * of all this process's threads (on a shared machine, what the work cost,
 * whatever the wall clock says). */
#ifndef ORR_TEST_CLOCKS_H
#define ORR_TEST_CLOCKS_H

double wall_seconds(void);
double cpu_seconds(void);

#endif
