/* Shared by the Gadget reader's files: gadget_layout.c (header parsing and
 * the record walk that finds and checks every block of one file),
 * gadget_parts.c (the parts of a multi-file snapshot, the info) and gadget.c
 * (the orr_source and streaming). */
#ifndef ORR_SOURCE_GADGET_INTERNAL_H
#define ORR_SOURCE_GADGET_INTERNAL_H

#include <stdint.h>
#include <stdio.h>

#include "core/error.h"
#include "source/readers/share.h"
#include "source/source.h"

#define GADGET_NTYPES 6
#define GADGET_HEADER_BYTES 256

/* The blocks the reader uses; others are stepped over. */
typedef enum {
    BLK_POS,
    BLK_VEL,
    BLK_ID,
    BLK_MASS,
    BLK_U,
    BLK_RHO,
    BLK_HSML,
    BLK_POT,
    BLK_COUNT
} gadget_block_kind;

extern const char *const gadget_block_names[BLK_COUNT];

/* The 256-byte header (Gadget-2 io_header), decoded to native values. */
typedef struct gadget_header {
    int32_t npart[GADGET_NTYPES];
    double massarr[GADGET_NTYPES];
    double time, redshift;
    int32_t flag_sfr, flag_feedback;
    uint32_t npart_total[GADGET_NTYPES];
    int32_t flag_cooling, num_files;
    double box_size, omega0, omega_lambda, hubble_param;
    int32_t flag_stellarage, flag_metals;
    uint32_t npart_total_high[GADGET_NTYPES];
    int32_t flag_entropy;
} gadget_header;

/* Where one block's data starts in its file and how each element is stored. */
typedef struct gadget_block {
    int present;
    int64_t offset;   /* file offset of the first data byte */
    int64_t bytes;    /* data length (without the record markers) */
    int elem;         /* bytes per component: 4 (float / int32) or 8 */
} gadget_block;

/* SnapFormat 2 blocks with other labels (AGE, Z, NHP, SFR, a user's own):
 * at most this many per file are kept; later ones are stepped over. */
#define GADGET_MAX_NAMED 32
/* Values per particle a named block may hold: Gadget's metal blocks carry a
 * dozen elements; beyond this a layout is more likely a misreading. */
#define GADGET_NAMED_MAX_COMPONENTS 64

typedef struct gadget_named_block {
    char label[5];
    int64_t offset; /* file offset of the first data byte */
    int64_t bytes;  /* data length */
} gadget_named_block;

/* One file of a snapshot after its record walk. */
typedef struct gadget_file {
    gadget_header h;
    int64_t size;                 /* file length in bytes */
    int64_t n;                    /* particles in this file */
    int64_t type_start[GADGET_NTYPES]; /* index of each type's first particle */
    int64_t mass_start[GADGET_NTYPES]; /* its index in the MASS block (types with massarr 0) */
    gadget_block blk[BLK_COUNT];
    int nnamed;
    gadget_named_block named[GADGET_MAX_NAMED];
} gadget_file;

/* What the first file fixed for every other file of the snapshot. */
typedef struct gadget_encoding {
    int known;       /* 0 before the first file: detect instead of check */
    int swap;        /* the file's byte order differs from the host's */
    int big_endian;  /* the file's byte order */
    int snapformat;  /* 1 or 2 */
} gadget_encoding;

/* Reads the 4-byte Fortran record marker or int32 at p in the file's order. */
uint32_t gadget_u32(const unsigned char *p, int swap);

/* Opens path, walks its records and fills *f; on the first file (enc->known
 * 0) detects byte order and SnapFormat into enc, on later ones requires the
 * same. Every length is checked against the file size and the header's
 * counts; nothing is allocated. */
orr_status gadget_scan_file(const char *path, gadget_encoding *enc, gadget_file *f, orr_error *err);

/* ---- named blocks (gadget_named.c) ---- */

/* How a named block lies over a snapshot's particles, inferred from its
 * length in every part and the parts' npart: the types it has values for,
 * how many per particle, and their size (the snapshot's precision: POS's). */
typedef struct gadget_named_layout {
    char label[5];
    int ok;         /* 1: one layout fits every part */
    unsigned types; /* bit t: type t's particles have values */
    int ncomp;      /* values per particle */
    int elem;       /* bytes per value: 4 or 8 */
    char why[240];  /* when !ok: what does not fit, or the layouts that all fit */
} gadget_named_layout;

/* The block label's layout over the parts (see docs/format-gadget.md,
 * "Other blocks"): every set of the snapshot's non-empty types is tried;
 * one whose counts divide the block's length into the same whole number of
 * values per particle in every part (and with parts that have none of
 * those particles holding no values) fits. When several fit, the
 * conventional ones win (all types; gas; stars; gas and stars; black
 * holes; the types with massarr 0); when no or more than one layout wins,
 * ok is 0 and why says so. */
void gadget_named_infer(const gadget_file *files, int nfiles, const char *label, gadget_named_layout *out);

/* "type 4" or "types 0 4" of a set of types (bit t: type t). */
void gadget_type_list(unsigned types, char *buf, size_t size);

/* The block of that label in file f, or NULL. */
const gadget_named_block *gadget_named_find(const gadget_file *f, const char *label);

/* The row (of ncomp values) of particle `within` of type t of file f in
 * the block, which holds the layout's types in type order. */
int64_t gadget_named_row(const gadget_named_layout *l, const gadget_file *f, int t, int64_t within);

/* ---- the reader (gadget.c, gadget_parts.c) ---- */

/* The extra fields the reader can load. */
enum { X_VX, X_VY, X_VZ, X_U, X_RHO, X_POT, X_COUNT };

/* A field read from a named block: "AGE", or column k of "Z" as "Z[k]". */
typedef struct gadget_named_field {
    gadget_named_layout layout;
    int column;
    int slot; /* its chunk extra index */
} gadget_named_field;

typedef struct gadget_state {
    char base[ORR_PATH_MAX]; /* multi-file: the name before ".i"; else the file's path */
    int multi;
    int nfiles;
    gadget_file *files;
    gadget_encoding enc;
    int want_type[GADGET_NTYPES];
    /* This process's rows of each file and type (run file * GADGET_NTYPES +
     * type), none of the types not wanted. */
    orr_share share;
    int slot[X_COUNT]; /* chunk extra index of each field, -1 when not loaded */
    /* Fields from blocks with other labels (SnapFormat 2), asked for by name. */
    int nnamed;
    gadget_named_field named[ORR_MAX_EXTRA_FIELDS];
    int has_id, has_h;
    /* The read position: next particle is number `done` of type `type` in file `file`. */
    int file, type;
    int64_t done;
    uint64_t next_index;
    FILE *fp;
    int fp_file; /* the part fp has open, -1 for none */
    unsigned char *raw;
} gadget_state;

/* The name of part i of the snapshot (the file itself when it is one). */
void gadget_part_path(const gadget_state *st, int i, char *buf, size_t size);
/* Finds the parts of the snapshot path names, and has each scanned and
 * checked (gadget_scan_file). */
orr_status gadget_find_parts(const char *path, gadget_state *st, orr_error *err);
/* The info `orrery info` shows: header values, particle counts (sum: of
 * every part, by type), named blocks. */
void gadget_describe(orr_source *src, const gadget_state *st, const int64_t sum[GADGET_NTYPES]);

#endif
