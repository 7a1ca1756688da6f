/* One process's share of a snapshot file, read by the reader itself: the
 * particles, in the order the reader delivers them (file by file, type by
 * type), are cut into nparts contiguous ranges of nearly equal size, and
 * part p reads only range p. The reader describes its particles as runs
 * (one per file and type, in reading order, unwanted types counted 0); the
 * share then says which rows of each run are this part's, so the reader
 * seeks to them and never reads the others. A multi-file snapshot thus
 * splits by file into contiguous groups balanced by the headers' counts (a
 * file on a boundary is shared by two parts), and a single file by ranges
 * within each block. */
#ifndef ORR_SOURCE_SHARE_H
#define ORR_SOURCE_SHARE_H

#include <stddef.h>
#include <stdint.h>

#include "source/source.h"

/* Part `part` of `nparts` of n things in a row: [*first, *end). Sizes
 * differ by at most one and the parts follow each other without gap. */
void orr_share_bounds(int64_t n, int part, int nparts, int64_t *first, int64_t *end);

/* The rows of each run that are part `part`'s: row r of run i is its when
 * lo[i] <= r < hi[i] (lo == hi: none). counts may be hi itself. Returns the
 * index, in the whole reading order, of the share's first particle. */
int64_t orr_share_runs(const int64_t *counts, size_t nruns, int part, int nparts, int64_t *lo, int64_t *hi);

/* A reader's share: its rows of each run. */
typedef struct orr_share {
    int64_t *lo, *hi;
    uint64_t first; /* index of the share's first particle in the whole reading order */
} orr_share;

/* Allocates nruns runs; the reader then sets hi[i] to run i's particle
 * count (0 for a type not wanted) and calls orr_share_divide. */
orr_status orr_share_alloc(orr_share *sh, size_t nruns, orr_error *err);
/* Cuts the runs to the share the options ask for (part and nparts; the
 * whole file without them), marks src as holding only that share (so
 * orr_source_partition passes it through) and sets src->info.count to its
 * size. An error names src's path when part is out of range. */
orr_status orr_share_divide(orr_share *sh, size_t nruns, orr_source *src, const orr_source_options *opt,
                            orr_error *err);
void orr_share_free(orr_share *sh);

#endif
