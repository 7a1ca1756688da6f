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
#include "source/readers/formats.h"
#include "source/readers/npy_reader.h"
#include "source/source.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* Values the reader refuses (a mass, h, id or type) say "row N: ...". */
static int read_with(const char *path, const orr_source_options *opt, int rewind)
{
    return fuzz_read_with(orr_npy_source_open, path, opt, rewind, ": row ");
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
