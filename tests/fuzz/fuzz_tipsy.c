/* Fuzz target for the Tipsy reader. It opens the reader directly (like
 * fuzz_common.h's fuzz_read_as, which goes through the format registry) so
 * it works before "tipsy" is registered; once it is, the first read could be
 * fuzz_read_as("tipsy", data, size). Each input is read twice: all of it in
 * small chunks with a rewind, then with a type mask and a field list, and
 * the probe must agree with the reader on small files. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "fuzz_common.h"
#include "source/readers/formats.h"
#include "source/readers/tipsy.h"
#include "source/source.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* A mass breaking the mass policy (docs/input.md) is the only value the
 * reader refuses. */
static int read_with(const char *path, const orr_source_options *opt, int rewind)
{
    return fuzz_read_with(orr_tipsy_source_open, path, opt, rewind, ": mass ");
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char path[64];
    fuzz_write_input(data, size, "tipsy.bin", path, sizeof path);

    orr_source_options all = {.format = "tipsy", .chunk_size = 257};
    int opened = read_with(path, &all, 1);
    static const char *const fields[] = {"rho", "eps", "tform"};
    orr_source_options some = {.format = "tipsy", .chunk_size = 3, .type_mask = 1u << 1 | 1u << 4, .fields = fields, .nfields = 3};
    if (read_with(path, &some, 0) != opened)
        abort();
    /* Below ORR_PROBE_BYTES the probe sees the whole file: what it accepts
     * must open (it may reject more, e.g. a non-finite time). */
    size_t n = size < ORR_PROBE_BYTES ? size : ORR_PROBE_BYTES;
    if (orr_tipsy_probe(data, n) && size < ORR_PROBE_BYTES && !opened)
        abort();
    unlink(path);
    return 0;
}
