/* Every particle of a snapshot file in memory, for the benchmarks that time
 * rendering without reading (bench_inmemory, bench_plain_ngp). Exits with a
 * message on any failure: these are benchmarks, not library code. */
#ifndef ORR_TEST_SNAPSHOT_LOAD_H
#define ORR_TEST_SNAPSHOT_LOAD_H

#include <stddef.h>

typedef struct loaded_snapshot {
    size_t n;
    float *x, *y, *z, *mass, *h; /* h: orrery's convention (support 2h); NULL without lengths */
} loaded_snapshot;

/* Reads every particle of path; with need_h, fails when it has no
 * smoothing lengths. */
void load_snapshot(const char *path, int need_h, loaded_snapshot *p);
void free_snapshot(loaded_snapshot *p);

#endif
