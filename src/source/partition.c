#include "source/partition.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct partition_state {
    orr_source *inner;
    int part, nparts;
    long next_chunk; /* index of the inner source's next chunk */
} partition_state;

/* The partition hands out the inner source's own chunk: src->chunk is a
 * copy of its pointers, never freed through the partition. */
static orr_status partition_next(orr_source *src, orr_error *err)
{
    partition_state *st = src->state;
    orr_source *in = st->inner;
    for (;;) {
        orr_status s;
        int mine = st->next_chunk % st->nparts == st->part;
        if (!mine && in->ops->skip_chunk) {
            s = in->ops->skip_chunk(in, err);
        } else {
            const orr_chunk *c;
            s = orr_source_next(in, &c, err);
            if (!s && c->n == 0) {
                src->chunk = in->chunk;
                return ORR_OK;
            }
        }
        if (s)
            return s;
        st->next_chunk++;
        if (mine) {
            src->chunk = in->chunk;
            return ORR_OK;
        }
        /* A skipped chunk past the end is the end: the next read says so. */
    }
}

static orr_status partition_rewind(orr_source *src, orr_error *err)
{
    partition_state *st = src->state;
    st->next_chunk = 0;
    return orr_source_rewind(st->inner, err);
}

static void partition_close(orr_source *src)
{
    partition_state *st = src->state;
    memset(&src->chunk, 0, sizeof src->chunk); /* the inner source's arrays */
    orr_source_close(st->inner);
    free(st);
    src->state = NULL;
}

static const orr_source_ops partition_ops = {
    .next = partition_next, .rewind = partition_rewind, .close = partition_close};

orr_status orr_source_partition(orr_source *inner, int part, int nparts, orr_source **out, orr_error *err)
{
    *out = NULL;
    if (nparts < 1 || part < 0 || part >= nparts) {
        orr_source_close(inner);
        return orr_fail(err, ORR_ERR_USAGE, "partition %d of %d: out of range", part, nparts);
    }
    int already = inner->info.share_nparts == nparts && inner->info.share_part == part;
    if (inner->info.share_nparts > 1 && !already) {
        int had = inner->info.share_nparts;
        orr_source_close(inner);
        return orr_fail(err, ORR_ERR_USAGE, "partition %d of %d of a source already read as a share of %d parts",
                        part, nparts, had);
    }
    if (nparts == 1 || already) {
        *out = inner;
        return ORR_OK;
    }
    orr_source *src = orr_source_new(inner->info.format, inner->info.path, &partition_ops, sizeof(partition_state), err);
    if (!src) {
        orr_source_close(inner);
        return ORR_ERR_NOMEM;
    }
    partition_state *st = src->state;
    st->inner = inner;
    st->part = part;
    st->nparts = nparts;
    src->info = inner->info; /* count, time, fields: of the whole source */
    src->chunk = inner->chunk;
    src->chunk.n = 0;
    *out = src;
    return ORR_OK;
}
