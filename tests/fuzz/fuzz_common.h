/* The body of every reader fuzz target: the input bytes are written to a
 * temporary file, opened with one reader and read to the end. Any crash,
 * sanitizer report, hang or leak is a bug; an error status is fine. */
#ifndef ORR_FUZZ_COMMON_H
#define ORR_FUZZ_COMMON_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "source/source.h"

/* Writes the input to /tmp/orrery-fuzz-PID.EXT (the readers take files),
 * into path; the caller unlinks it. */
static inline void fuzz_write_input(const uint8_t *data, size_t size, const char *ext, char *path, size_t path_size)
{
    snprintf(path, path_size, "/tmp/orrery-fuzz-%ld.%s", (long)getpid(), ext);
    FILE *fp = fopen(path, "wb");
    if (!fp)
        abort();
    if (size && fwrite(data, 1, size, fp) != size)
        abort();
    fclose(fp);
}

static inline int fuzz_read_as(const char *format, const uint8_t *data, size_t size)
{
    char path[64];
    fuzz_write_input(data, size, "bin", path, sizeof path);
    orr_source_options opt = {.format = format, .chunk_size = 257};
    orr_source *src = NULL;
    orr_error err = {0};
    if (orr_source_open_file(path, &opt, &src, &err) == ORR_OK) {
        const orr_chunk *c;
        uint64_t total = 0;
        while (orr_source_next(src, &c, &err) == ORR_OK && c->n > 0) {
            if (c->n > c->capacity)
                abort(); /* a reader overran its own chunk */
            total += c->n;
        }
        (void)total;
        orr_source_close(src);
    }
    unlink(path);
    return 0;
}

/* Reads a source to its end; returns the particles read, -2 when the read
 * stopped on a value the reader refuses (its message holds refusal, e.g.
 * ": mass "), or -1 on any other error. A chunk beyond its capacity aborts. */
static inline long long fuzz_read_all(orr_source *src, const char *refusal)
{
    const orr_chunk *c;
    orr_error err = {0};
    long long total = 0;
    for (;;) {
        if (orr_source_next(src, &c, &err) != ORR_OK)
            return err.code == ORR_ERR_FORMAT && strstr(err.msg, refusal) ? -2 : -1;
        if (c->n == 0)
            return total;
        if (c->n > c->capacity)
            abort(); /* the reader overran its own chunk */
        total += (long long)c->n;
    }
}

typedef orr_status (*fuzz_open_fn)(const char *path, const orr_source_options *opt, orr_source **out,
                                   orr_error *err);

/* Opens path with a reader that checks the file's size when it opens
 * (Tipsy, npy) and reads it, then (rewind) again; returns 1 when it opened.
 * Aborts when a failed open leaves a source or says nothing, when fewer
 * particles than info.count arrive without a refused value, or when the
 * second read differs. */
static inline int fuzz_read_with(fuzz_open_fn open, const char *path, const orr_source_options *opt, int rewind,
                                 const char *refusal)
{
    orr_source *src = NULL;
    orr_error err = {0};
    if (open(path, opt, &src, &err) != ORR_OK) {
        if (src || err.code == ORR_OK || !err.msg[0])
            abort();
        return 0;
    }
    long long n = fuzz_read_all(src, refusal);
    if (n != src->info.count && n != -2)
        abort();
    if (rewind && (orr_source_rewind(src, &err) != ORR_OK || fuzz_read_all(src, refusal) != n))
        abort();
    orr_source_close(src);
    return 1;
}

#endif
