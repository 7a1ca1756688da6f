/* A source yields particles chunk by chunk: a snapshot reader, the built-in
 * model generator, or (later) a running simulation. The renderer sees only
 * this interface. */
#ifndef ORR_SOURCE_SOURCE_H
#define ORR_SOURCE_SOURCE_H

#include <stdint.h>

#include "particles/chunk.h"

#define ORR_PATH_MAX 4096

typedef struct orr_source_info {
    char format[32];        /* "text", "model:mw-m31", ... */
    char path[ORR_PATH_MAX];/* the file read, or a description of the generator */
    int64_t count;          /* total particles, or -1 when unknown before reading */
    double time;            /* simulation time of the snapshot (0 when unknown) */
    int has_h, has_id, has_type;
    int nextra;
    char extra_names[ORR_MAX_EXTRA_FIELDS][ORR_FIELD_NAME_MAX];
} orr_source_info;

typedef struct orr_source orr_source;

typedef struct orr_source_ops {
    /* Refills src->chunk with the next particles; chunk.n == 0 means the end. */
    orr_status (*next)(orr_source *src, orr_error *err);
    /* Starts again from the first particle. */
    orr_status (*rewind)(orr_source *src, orr_error *err);
    void (*close)(orr_source *src);
} orr_source_ops;

struct orr_source {
    orr_source_info info;
    orr_chunk chunk;
    const orr_source_ops *ops;
    void *state;
};

/* Yields the next chunk in *out (valid until the next call); (*out)->n == 0
 * at the end of the particles. */
orr_status orr_source_next(orr_source *src, const orr_chunk **out, orr_error *err);
orr_status orr_source_rewind(orr_source *src, orr_error *err);
/* Frees everything the source holds; src may be NULL. */
void orr_source_close(orr_source *src);

/* Opens a particle file. format is "auto" (detect from the contents) or a
 * format name ("text"). chunk_size bounds the particles held at once. */
orr_status orr_source_open_file(const char *path, const char *format, size_t chunk_size,
                                orr_source **out, orr_error *err);

#endif
