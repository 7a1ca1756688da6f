/* A source yields particles chunk by chunk: a snapshot reader, the built-in
 * model generator, or (later) a running simulation. The renderer sees only
 * this interface. */
#ifndef ORR_SOURCE_SOURCE_H
#define ORR_SOURCE_SOURCE_H

#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>

#include "core/limits.h"
#include "particles/chunk.h"

#define ORR_SOURCE_MAX_HEADER 64

/* One line of a file's header as `orrery info` shows it ("BoxSize", "50000"). */
typedef struct orr_header_entry {
    char key[48];
    char value[208];
} orr_header_entry;

typedef struct orr_source_info {
    char format[32];        /* "text", "gadget2", "model:mw-m31", ... */
    char path[ORR_PATH_MAX];/* the file read, or a description of the generator */
    int64_t count;          /* total particles, or -1 when unknown before reading */
    double time;            /* simulation time of the snapshot (0 when unknown) */
    int has_h, has_id, has_type;
    /* The radius where the file's SPH kernel reaches zero, in units of its
     * h: Gadget's HSML is that radius (1); SWIFT's h is 1/gamma of it; Tipsy
     * and text files use orrery's convention, support 2h (0 means 2). */
    double h_support;
    int nextra;             /* the extra fields loaded into every chunk */
    char extra_names[ORR_MAX_EXTRA_FIELDS][ORR_FIELD_NAME_MAX];
    /* A reader that divided the file itself (orr_source_options' part and
     * nparts) yields only part share_part of share_nparts, and count is
     * that part's; share_nparts 0: the whole source. */
    int share_part, share_nparts;
    /* The FITS units of the masses and lengths as read, when the file states
     * them as FITS can say them ("10**10 solMass", "kpc"; HDF5 snapshots:
     * readers/hdf5_units.c); "" unknown. Renders take them for BUNIT and
     * CUNIT where the scene names none (docs/output.md). */
    char mass_unit[32], length_unit[16];
    int nheader;            /* header values and units, for `orrery info` */
    orr_header_entry header[ORR_SOURCE_MAX_HEADER];
} orr_source_info;

/* Appends a header entry (printf-style value); silently ignores entries past
 * ORR_SOURCE_MAX_HEADER, which only shortens what `orrery info` shows. */
void orr_source_add_header(orr_source_info *info, const char *key, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* What the caller wants from a file. Readers may use fields and type_mask to
 * skip data nobody will look at. */
typedef struct orr_source_options {
    const char *format;        /* "auto" (detect from the contents) or a format name */
    size_t chunk_size;         /* particles held at once */
    unsigned type_mask;        /* bit t set: particles of type t are wanted (0 means all) */
    const char *const *fields; /* extra fields wanted by name; NULL means every field the file has */
    int nfields;
    /* Part `part` of `nparts` (nparts 0 or 1: the whole file). Readers that
     * can seek to their share (Gadget, HDF5, Tipsy: source/readers/share.h) read
     * only it and say so in info.share_nparts; the others ignore it and
     * orr_source_partition deals their chunks out instead. */
    int part, nparts;
} orr_source_options;

typedef struct orr_source orr_source;

typedef struct orr_source_ops {
    /* Refills src->chunk with the next particles; chunk.n == 0 means the end. */
    orr_status (*next)(orr_source *src, orr_error *err);
    /* Starts again from the first particle. */
    orr_status (*rewind)(orr_source *src, orr_error *err);
    void (*close)(orr_source *src);
    /* Optional: passes over the particles the next call of next() would
     * deliver, without loading them (a source partitioned among processes
     * skips the chunks other processes take). NULL: they are read and
     * dropped. */
    orr_status (*skip_chunk)(orr_source *src, orr_error *err);
    /* Optional: until the next rewind, particles of types outside mask
     * (bit t: type t; 0: every type) may be left out, for a pass that
     * drops them anyway (a generator then skips making them), counted in
     * left_out; only where the chunks' other particles stay as they were
     * (the built-in model: its gas, which comes after all the others), so a
     * splat's blocks, and its sums, are the same. NULL: every particle is
     * delivered. */
    void (*only_types)(orr_source *src, unsigned mask);
} orr_source_ops;

struct orr_source {
    orr_source_info info;
    orr_chunk chunk;
    const orr_source_ops *ops;
    void *state;
    /* When set, orr_source_next fails with ORR_ERR_CANCELLED once *cancel
     * is nonzero (orrery_cancel: the in-situ API's source). */
    const atomic_int *cancel;
    /* Particles this pass left out (orr_source_only_types) so far: those a
     * source without the hook would have delivered. 0 after a rewind. */
    uint64_t left_out;
};

/* Allocates a source of the named format reading path, with ops and a
 * zeroed reader state of state_size bytes in src->state; NULL (err set)
 * when memory runs out. Readers call it first in their open function. */
orr_source *orr_source_new(const char *format, const char *path, const orr_source_ops *ops, size_t state_size,
                           orr_error *err);

/* orr_source_new for the readers that seek in a file of their own (Tipsy,
 * npy; readers/open_file.c): refuses a stream (orr_source_refuse_stream) and opens path for
 * reading into *fp, which the caller keeps in its state. On failure
 * nothing is left open and *out is NULL. */
orr_status orr_source_new_file(const char *format, const char *path, const orr_source_ops *ops, size_t state_size,
                               orr_source **out, FILE **fp, orr_error *err);

/* Allocates src->chunk for the options' chunk size (default 2^20), no larger
 * than the source's known count (so small files stay small), with h when
 * info.has_h and the extra fields info names. */
orr_status orr_source_alloc_chunk(orr_source *src, const orr_source_options *opt, orr_error *err);

/* Yields the next chunk in *out (valid until the next call); (*out)->n == 0
 * at the end of the particles. */
orr_status orr_source_next(orr_source *src, const orr_chunk **out, orr_error *err);
orr_status orr_source_rewind(orr_source *src, orr_error *err);
/* Tells the source that this pass, up to the next rewind, drops every
 * particle whose type is outside mask (0: none dropped): it may leave them
 * out (orr_source_ops.only_types), or deliver them as before. The pass
 * must still test each particle's type. */
void orr_source_only_types(orr_source *src, unsigned mask);
/* Frees everything the source holds; src may be NULL. */
void orr_source_close(orr_source *src);

/* Opens a particle file with the reader its format names, or (format
 * "auto") the reader whose probe recognises the file's first bytes
 * (readers/open_file.c, with the format functions below). "-" is
 * standard input; it, FIFOs and character devices are streams, read once
 * from the front: their format is detected from bytes kept for the reader,
 * only text can be read from them (the binary formats seek), and a FIFO no
 * program writes to reads as empty instead of waiting for a writer. */
orr_status orr_source_open_file(const char *path, const orr_source_options *opt, orr_source **out,
                                orr_error *err);

/* For the readers that seek (Gadget, HDF5, Tipsy): refuses path, naming the
 * format, when it is a FIFO, device or socket, before anything opens it
 * (opening a FIFO waits for a writer, forever when there is none). A
 * missing file or a folder is left to the reader's own message. */
orr_status orr_source_refuse_stream(const char *path, const char *format, orr_error *err);

/* Space-separated names of the formats orr_source_open_file knows. */
const char *orr_source_format_names(void);
/* Whether name is one of those formats. */
int orr_source_format_known(const char *name);

/* Whether an options' field list asks for the named field. */
int orr_source_wants_field(const orr_source_options *opt, const char *name);

/* Whether name is one of the fields every source fills in its chunk's own
 * arrays (x y z mass h id type), or one of the n names of a reader's list. */
int orr_field_is_own(const char *name);
int orr_field_in_list(const char *name, const char *const *names, int n);

/* Splits a named field into the name of what holds it and a column: "Name"
 * gives (Name, -1), "Name[k]" (Name, k) with k decimal digits, at most
 * 1000000, nothing after the ']'. Returns 0 for "", a name that does not
 * fit in size, or a bad "[k]". (HDF5 datasets, Gadget blocks.) */
int orr_field_split_column(const char *field, char *name, size_t size, int *column);
/* Whether an options' type mask asks for type t. */
int orr_source_wants_type(const orr_source_options *opt, int type);

#endif
