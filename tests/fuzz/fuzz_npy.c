/* Fuzz target for the .npy reader: the header's dict parser (npy_header.c)
 * and the streaming of rows. Each input is read twice, all of it in small
 * chunks with a rewind, then with a field list; the probe must agree with
 * the reader's magic. These abort: a chunk with n > capacity, a failed open
 * that hands out a source or says nothing, a read that does not deliver
 * info.count particles (unless a value the reader refuses stopped it), a
 * rewind that reads differently. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "fuzz_common.h"
#include "source/formats.h"
#include "source/npy_reader.h"
#include "source/source.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* Reads to the end; the particles read, -2 when a value was refused (a
 * mass, h, id or type: "row N: ..."), -1 on any other error. */
static long long read_all(orr_source *src)
{
    const orr_chunk *c;
    orr_error err = {0};
    long long total = 0;
    for (;;) {
        if (orr_source_next(src, &c, &err) != ORR_OK)
            return err.code == ORR_ERR_FORMAT && strstr(err.msg, ": row ") ? -2 : -1;
        if (c->n == 0)
            return total;
        if (c->n > c->capacity)
            abort();
        total += (long long)c->n;
    }
}

static int read_with(const char *path, const orr_source_options *opt, int rewind)
{
    orr_source *src = NULL;
    orr_error err = {0};
    if (orr_npy_source_open(path, opt, &src, &err) != ORR_OK) {
        if (src || err.code == ORR_OK || !err.msg[0])
            abort();
        return 0;
    }
    long long n = read_all(src);
    if (n != src->info.count && n != -2)
        abort(); /* the size was checked when opening: every row is there */
    if (rewind && (orr_source_rewind(src, &err) != ORR_OK || read_all(src) != n))
        abort();
    orr_source_close(src);
    return 1;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char path[64];
    fuzz_write_input(data, size, "fuzz.npy", path, sizeof path);
    orr_source_options all = {.format = "npy", .chunk_size = 7};
    int opened = read_with(path, &all, 1);
    static const char *const fields[] = {"age", "vx"};
    orr_source_options some = {.format = "npy", .chunk_size = 1000, .fields = fields, .nfields = 2};
    if (read_with(path, &some, 0) != opened)
        abort();
    if (opened && !orr_npy_probe(data, size))
        abort(); /* the reader opened something without the magic */
    unlink(path);
    return 0;
}
