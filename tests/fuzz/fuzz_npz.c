/* Fuzz target for the .npz reader: the ZIP directory (ZIP64 included),
 * stored and deflated members read side by side, and each member's .npy
 * header. Each input is read twice, all of it in small chunks with a
 * rewind, then with a field list (the probe is not checked: an archive is
 * found from its end, whatever its first bytes). These abort: a chunk with n > capacity, a failed open that
 * hands out a source or says nothing, a read that does not deliver
 * info.count particles (unless a value the reader refuses stopped it, or
 * damaged deflated data found while reading), a rewind that reads
 * differently. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "fuzz_common.h"
#include "source/readers/formats.h"
#include "source/readers/npz_reader.h"
#include "source/source.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* Refused values say "row N: ..."; deflated data is only checked as it is
 * inflated, so a damaged member also stops a read part way (its message
 * names the member), the same way both times. */
static int read_with(const char *path, const orr_source_options *opt, int rewind)
{
    return fuzz_read_with(orr_npz_source_open, path, opt, rewind, ": member '");
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char path[64];
    fuzz_write_input(data, size, "fuzz.npz", path, sizeof path);
    orr_source_options all = {.format = "npz", .chunk_size = 7};
    int opened = read_with(path, &all, 1);
    static const char *const fields[] = {"age", "vel[1]"};
    orr_source_options some = {.format = "npz", .chunk_size = 1000, .fields = fields, .nfields = 2};
    if (read_with(path, &some, 0) != opened)
        abort(); /* every member's header is read at open, wanted or not */
    unlink(path);
    return 0;
}
