/* Fuzz target for the HDF5 snapshot reader. Like fuzz_common.h's
 * fuzz_read_as, but it calls the reader directly (so it does not depend on
 * the format registry) and writes the input twice, as files .0 and .1 of a
 * snapshot, so headers with NumFilesPerSnapshot = 2 take the multi-file path
 * too (more than 2 finds a file missing). The input size picks a type mask
 * and field list, to reach the skipping code without spoiling the bytes.
 *
 * Caution: libhdf5 1.10 itself crashes on some malformed files (see
 * docs/format-hdf5.md); crashes whose stack is inside libhdf5 are not ours. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "source/hdf5_reader.h"
#include "source/source.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void write_file(const char *base, int part, const uint8_t *data, size_t size)
{
    char path[96];
    snprintf(path, sizeof path, "%s.%d.hdf5", base, part);
    FILE *fp = fopen(path, "wb");
    if (!fp)
        abort();
    if (size && fwrite(data, 1, size, fp) != size)
        abort();
    fclose(fp);
}

static void read_all(orr_source *src)
{
    orr_error err = {0};
    const orr_chunk *c;
    while (orr_source_next(src, &c, &err) == ORR_OK && c->n > 0)
        if (c->n > c->capacity)
            abort(); /* the reader overran its own chunk */
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char base[64], first[96];
    snprintf(base, sizeof base, "/tmp/orrery-fuzz-hdf5-%ld", (long)getpid());
    write_file(base, 0, data, size);
    write_file(base, 1, data, size);
    snprintf(first, sizeof first, "%s.0.hdf5", base);
    static const char *const fields[] = {"vx", "u", "pot"};
    unsigned pick = (unsigned)(size % 97);
    orr_source_options opt = {.format = "hdf5", .chunk_size = 257, .type_mask = (pick & 1) ? 0x42 : 0,
                              .fields = (pick & 2) ? fields : NULL, .nfields = 3};
    orr_source *src = NULL;
    orr_error err = {0};
    if (orr_hdf5_source_open(first, &opt, &src, &err) == ORR_OK) {
        read_all(src);
        if (orr_source_rewind(src, &err) == ORR_OK)
            read_all(src);
        orr_source_close(src);
    } else if (src) {
        abort(); /* a failed open must not hand out a source */
    }
    for (int part = 0; part < 2; part++) {
        char path[96];
        snprintf(path, sizeof path, "%s.%d.hdf5", base, part);
        unlink(path);
    }
    return 0;
}
