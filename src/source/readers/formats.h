/* The registry of file formats: each reader contributes a probe, which
 * recognises its files from their first bytes, and an open function. The
 * order matters: the text probe accepts almost anything printable, so binary
 * formats come first. */
#ifndef ORR_SOURCE_FORMATS_H
#define ORR_SOURCE_FORMATS_H

#include <stddef.h>

#include "source/source.h"

#define ORR_PROBE_BYTES 4096

typedef struct orr_format {
    const char *name;
    /* Returns 1 when the first n bytes of a file (n may be less than
     * ORR_PROBE_BYTES for short files) look like this format. */
    int (*probe)(const unsigned char *head, size_t n);
    orr_status (*open)(const char *path, const orr_source_options *opt, orr_source **out, orr_error *err);
} orr_format;

extern const orr_format orr_formats[];
extern const int orr_nformats;

#endif
