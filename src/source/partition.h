/* One process's share of a source, for rendering on several MPI ranks:
 * the source's chunks are dealt out in turn, chunk k to part k mod nparts,
 * so every part sees about the same number of particles whatever their
 * order, and the parts together see each particle exactly once. Chunks of
 * other parts are skipped without loading where the source can (the
 * built-in model, in-memory arrays) and read and dropped otherwise. File
 * readers that seek to their share (source/readers/share.h) need no dealing. */
#ifndef ORR_SOURCE_PARTITION_H
#define ORR_SOURCE_PARTITION_H

#include "source/source.h"

/* Wraps inner (which the partition then owns and closes) as part `part` of
 * `nparts`. With nparts == 1, or when the reader already read only that
 * share (info.share_part and share_nparts), *out is inner itself. */
orr_status orr_source_partition(orr_source *inner, int part, int nparts, orr_source **out, orr_error *err);

#endif
