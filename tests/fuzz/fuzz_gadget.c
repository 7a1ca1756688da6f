/* Fuzz target for the Gadget-1/2 snapshot reader. Like fuzz_common.h's
 * fuzz_read_as, but it calls the reader directly (so it does not depend on
 * the format registry) and writes the input twice, as parts .0 and .1 of a
 * snapshot opened by its base name, so headers with num_files = 2 take the
 * multi-file path too (num_files > 2 finds a part missing). Byte 300 of the
 * input also picks a type mask and field list, to reach the skipping code
 * and the named blocks' layouts. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "source/readers/gadget.h"
#include "source/source.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void write_part(const char *base, int part, const uint8_t *data, size_t size)
{
    char path[96];
    snprintf(path, sizeof path, "%s.%d", base, part);
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
    char base[64];
    snprintf(base, sizeof base, "/tmp/orrery-fuzz-gadget-%ld", (long)getpid());
    write_part(base, 0, data, size);
    write_part(base, 1, data, size);
    /* Bit 7 of the pick asks for fields of named blocks (SnapFormat 2's
     * AGE and Z of the seeds), bit 6 for standard ones only. */
    static const char *const standard[] = {"vx", "u", "pot"};
    static const char *const named[] = {"vx", "AGE", "Z[1]"};
    unsigned pick = size > 300 ? data[300] : 0;
    orr_source_options opt = {.format = "gadget", .chunk_size = 257, .type_mask = pick & 0x3f,
                              .fields = (pick & 0x80) ? named : (pick & 0x40) ? standard : NULL, .nfields = 3};
    orr_source *src = NULL;
    orr_error err = {0};
    if (orr_gadget_source_open(base, &opt, &src, &err) == ORR_OK) {
        read_all(src);
        if (orr_source_rewind(src, &err) == ORR_OK)
            read_all(src);
        orr_source_close(src);
    } else if (src) {
        abort(); /* a failed open must not hand out a source */
    }
    char path[96];
    for (int part = 0; part < 2; part++) {
        snprintf(path, sizeof path, "%s.%d", base, part);
        unlink(path);
    }
    return 0;
}
