/* The body of every reader fuzz target: the input bytes are written to a
 * temporary file, opened with one reader and read to the end. Any crash,
 * sanitizer report, hang or leak is a bug; an error status is fine. */
#ifndef ORR_FUZZ_COMMON_H
#define ORR_FUZZ_COMMON_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
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

#endif
