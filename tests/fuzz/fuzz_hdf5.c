/* Structure-aware fuzz target for the HDF5 snapshot reader.
 *
 * Why structure-aware: orrery leaves the bytes of an HDF5 file to libhdf5,
 * and libhdf5 (1.10, as Debian 12 ships it) is not robust against crafted
 * files: fed raw fuzz bytes it overflows heap buffers, uses freed memory and
 * leaks inside its own parser (H5O__msg_iterate_real, H5C_protect, ...).
 * Those are libhdf5's bugs, which orrery cannot fix, and they drown
 * everything else. So this target never hands libhdf5 corrupt bytes: it
 * decodes the fuzz input into a description of a snapshot that is
 * well-formed HDF5 but hostile as a Gadget/SWIFT snapshot, writes it with
 * the test writer (tests/support/hdf5_writer.c) through libhdf5 itself, and
 * fuzzes what orrery does on its own: the checks of the snapshot's
 * structure (counts, shapes, types, files) and the streaming.
 *
 * The input decodes as follows (every take_* returns a default once the
 * bytes run out, and the defaults make a valid snapshot: one Gadget file, 2
 * types, 5 particles of type 0 with Coordinates and Masses). The files in
 * corpus/hdf5/ are inputs in this encoding, not HDF5 files: changing the
 * decoding changes what they mean.
 *   layout byte: style (Gadget/SWIFT), ntypes (2, 6, 7), Gadget-4 units,
 *                files written (1..3), numbered or single name;
 *   read options: type mask, field list, chunk size, name opened;
 *   header: NumFilesPerSnapshot claimed, pos/id file types, Time, Redshift,
 *           BoxSize, MassTable, NumPart_Total (true sums or made up);
 *   per file, per type: count (0..40), datasets left out, values (NaN,
 *           inf, huge, negative, raw doubles, ...); then up to 5 edits of
 *           the written file: objects deleted, datasets replaced by wrong
 *           shapes/types/storage (rows not matching the counts, wrong
 *           columns, scalars, strings, chunked datasets claiming 2^40 rows
 *           with a few written), Header attributes rewritten with wrong
 *           lengths/types/values or removed, groups and (dangling) links
 *           added.
 * The snapshot is then opened with orr_hdf5_source_open, read to the end,
 * rewound and read again. Errors are fine; these abort:
 *   - a chunk with n > capacity;
 *   - a failed open that still hands out a source;
 *   - a successful read whose rewind read fails or differs (particle count
 *     or content), or whose count differs from info.count;
 *   - a particle of a type not asked for, or with a mass or smoothing length
 *     that is not finite and non-negative (docs/format-hdf5.md);
 *   - an HDF5 identifier still open after the source is closed. */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "hdf5_writer.h"
#include "source/readers/hdf5_reader.h"
#include "source/source.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* ---- Consuming the input ---------------------------------------------- */

typedef struct bytes {
    const uint8_t *p;
    size_t n;
} bytes;

static unsigned take_u8(bytes *b)
{
    if (b->n == 0)
        return 0;
    b->n--;
    return *b->p++;
}

static unsigned take_below(bytes *b, unsigned n)
{
    return take_u8(b) % n;
}

static uint64_t take_u64(bytes *b)
{
    uint64_t v = 0;
    for (int i = 0; i < 8; i++)
        v = v << 8 | take_u8(b);
    return v;
}

static double take_raw_double(bytes *b)
{
    uint64_t bits = take_u64(b);
    double v;
    memcpy(&v, &bits, sizeof v);
    return v;
}

/* A value: mostly small and non-negative (0 when the bytes have run out),
 * else one of the values that break naive code. */
static double take_value(bytes *b)
{
    unsigned s = take_u8(b);
    if (s < 192)
        return s * 0.25;
    switch (s) {
    case 192: return -1.0;
    case 193: return NAN;
    case 194: return INFINITY;
    case 195: return -INFINITY;
    case 196: return 1e300;
    case 197: return -1e300;
    case 198: return 1e39; /* finite as a double, inf as a float */
    case 199: return 1e-45;
    case 200: return -0.0;
    case 201: return DBL_MAX;
    case 202: return DBL_MIN;
    case 203: return -1e-30;
    case 204: return 4294967296.0;
    case 205: return 2147483648.0;
    case 206: return 9.3e18;
    case 207: return 18446744073709551616.0;
    case 208: return take_raw_double(b);
    case 209: return 3.4028235e38;
    case 210: return -2147483649.0;
    default: return -(double)(s - 210);
    }
}

/* n values: a ramp, a constant, one value each, or a ramp with one odd value. */
static void take_array(bytes *b, double *out, size_t n)
{
    unsigned mode = take_below(b, 4);
    double a = mode == 2 ? 0 : take_value(b), step = mode == 0 ? take_value(b) : mode == 3 ? 1.0 : 0.0;
    for (size_t i = 0; i < n; i++)
        out[i] = mode == 2 ? take_value(b) : a + step * (double)i;
    if (mode == 3 && n > 0)
        out[take_u8(b) % n] = take_value(b);
}

/* v as a count: NaN and negatives 0, too large the largest (a plain cast
 * would be undefined). */
static uint64_t to_u64(double v)
{
    if (!(v >= 0))
        return 0;
    return v >= 18446744073709551616.0 ? UINT64_MAX : (uint64_t)v;
}

static void take_ids(bytes *b, uint64_t *out, size_t n, uint64_t first)
{
    unsigned mode = take_below(b, 4);
    uint64_t v = mode == 1 ? take_u64(b) : mode == 3 ? (UINT64_C(1) << 63) - 3 : first;
    for (size_t i = 0; i < n; i++)
        out[i] = mode == 1 ? v : mode == 2 ? take_u64(b) : v + i;
}

/* ---- The snapshot description ----------------------------------------- */

#define MAX_FILES 3
#define MAX_PART 40
#define MAX_EDITS 5
#define HUGE_CHUNK_ROWS 64

enum { K_POS, K_VEL, K_ID, K_MASS, K_H, K_U, K_RHO, K_POT, K_COUNT };

/* Dataset names: Gadget's spellings, then SWIFT's plurals. */
static const char *const ds_names[] = {"Coordinates",     "Velocities",     "ParticleIDs", "Masses",
                                       "SmoothingLength", "InternalEnergy", "Density",     "Potential",
                                       "SmoothingLengths", "InternalEnergies", "Densities", "Potentials"};
#define N_DS_NAMES (sizeof ds_names / sizeof ds_names[0])

static const char *const header_attrs[] = {"NumPart_ThisFile", "NumPart_Total", "NumPart_Total_HighWord",
                                           "MassTable",        "NumFilesPerSnapshot", "Time",
                                           "Redshift",         "BoxSize",       "NumPartTypes",
                                           "Code"};
#define N_HEADER_ATTRS (sizeof header_attrs / sizeof header_attrs[0])

typedef struct part_data {
    double pos[3 * MAX_PART], vel[3 * MAX_PART], mass[MAX_PART], h[MAX_PART], u[MAX_PART], rho[MAX_PART],
        pot[MAX_PART];
    uint64_t id[MAX_PART];
} part_data;

static part_data parts[MAX_FILES][H5W_MAX_TYPES];

typedef struct run {
    bytes in;
    int nwritten, numbered, ntypes, swift;
    char base[64], base_ext[64]; /* /tmp/orrery-fuzz-hdf5-PID and that .hdf5 */
    char path[MAX_FILES][64];     /* the files written */
    uint64_t count[H5W_MAX_TYPES]; /* NumPart_ThisFile of the file being edited, as edits leave it */
    double mass_table[H5W_MAX_TYPES];
} run;

static const char *style_name(const run *r, int kind)
{
    return ds_names[kind >= K_H && r->swift ? kind + 4 : kind];
}

/* ---- Edits of a written file ------------------------------------------ */

/* "PartTypeT" or "PartTypeT/<dataset>" for a type up to a few past ntypes. */
static void take_object(run *r, char *buf, size_t size, int with_dataset)
{
    unsigned t = take_below(&r->in, (unsigned)r->ntypes + 2);
    if (with_dataset)
        snprintf(buf, size, "PartType%u/%s", t, ds_names[take_below(&r->in, N_DS_NAMES)]);
    else
        snprintf(buf, size, "PartType%u", t);
}

static hid_t take_numeric_type(bytes *b)
{
    static const hid_t *const types[] = {&H5T_IEEE_F32LE_g, &H5T_IEEE_F64LE_g, &H5T_STD_I64LE_g, &H5T_STD_U32LE_g,
                                         &H5T_STD_I8LE_g,   &H5T_STD_U64BE_g,  &H5T_IEEE_F32BE_g, &H5T_STD_I32BE_g};
    return *types[take_below(b, sizeof types / sizeof types[0])];
}

/* Rewrites a Header attribute: its current value (or zeros) with a few
 * entries changed, any length, any numeric type, or a scalar or null. */
static void edit_header_attr(run *r, hid_t file)
{
    bytes *b = &r->in;
    unsigned which = take_below(b, N_HEADER_ATTRS);
    hid_t type = take_numeric_type(b);
    static const int ranks[] = {1, 1, 0, -1};
    int rank = ranks[take_below(b, 4)];
    int n = rank == 1 ? (int)((take_u8(b) + (unsigned)r->ntypes) % 18) : 1;
    double v[18] = {0};
    for (int i = 0; i < n && i < r->ntypes; i++)
        v[i] = which == 0 ? (double)r->count[i] : which == 3 ? r->mass_table[i] : 0.0;
    for (unsigned k = take_below(b, 3); k > 0 && n > 0; k--) {
        unsigned i = take_u8(b) % (unsigned)n;
        v[i] = take_value(b);
    }
    h5w_set_attr(file, "Header", header_attrs[which], type, rank, v, n);
}

/* Claims a huge (or merely large) count for a type: one dataset becomes a
 * chunked one of that many rows with only the first chunk written (or, in
 * HDF5 chunks of over 256 MiB, none), and NumPart_ThisFile says so too. */
static void edit_huge(run *r, hid_t file)
{
    bytes *b = &r->in;
    /* The first two are stored densely enough to be read (as fill values
     * after the first chunk); the others are refused. */
    static const uint64_t rows[] = {300, 600, UINT64_C(1) << 20, UINT64_C(1) << 32, UINT64_C(1) << 40,
                                    UINT64_C(1) << 62};
    unsigned t = take_below(b, (unsigned)r->ntypes);
    int kind = (int)take_below(b, K_COUNT);
    uint64_t n = rows[take_below(b, sizeof rows / sizeof rows[0])];
    double value = take_value(b);
    int big_chunks = (int)take_below(b, 4) == 3;
    char object[64];
    snprintf(object, sizeof object, "PartType%u", t);
    if (r->count[t] == 0)
        h5w_add_group(file, object);
    snprintf(object, sizeof object, "PartType%u/%s", t, style_name(r, kind));
    int cols = kind == K_POS || kind == K_VEL;
    h5w_dataset_spec spec = {.type = kind == K_ID ? H5T_STD_U64LE : H5T_IEEE_F32LE,
                             .rank = cols ? 2 : 1,
                             .dims = {n, 3},
                             .chunk_rows = big_chunks ? UINT64_C(1) << 27 : HUGE_CHUNK_ROWS,
                             .write_rows = big_chunks ? 0 : HUGE_CHUNK_ROWS,
                             .values = &value,
                             .nvalues = 1};
    h5w_replace_dataset_spec(file, object, &spec);
    r->count[t] = n;
    double v[H5W_MAX_TYPES];
    for (int i = 0; i < r->ntypes; i++)
        v[i] = (double)r->count[i];
    h5w_set_attr(file, "Header", "NumPart_ThisFile", H5T_STD_U64LE, 1, v, r->ntypes);
}

/* Replaces a dataset by one of the wrong shape, type or storage. */
static void edit_dataset(run *r, hid_t file, int odd)
{
    bytes *b = &r->in;
    unsigned t = take_below(b, (unsigned)r->ntypes);
    char object[64];
    snprintf(object, sizeof object, "PartType%u", t);
    if (r->count[t] == 0)
        h5w_add_group(file, object);
    snprintf(object, sizeof object, "PartType%u/%s", t, ds_names[take_below(b, N_DS_NAMES)]);
    uint64_t n = r->count[t] < MAX_PART + 3 ? r->count[t] : MAX_PART;
    int delta = (int)take_below(b, 7) - 3;
    uint64_t rows = (int64_t)n + delta < 0 ? 0 : n + (uint64_t)(int64_t)delta;
    static const int cols[] = {0, 3, 1, 2, 4};
    int c = cols[take_below(b, 5)];
    double values[4];
    for (int i = 0; i < 4; i++)
        values[i] = take_value(b);
    h5w_dataset_spec spec = {.type = take_numeric_type(b), .rank = c ? 2 : 1, .dims = {rows, (hsize_t)c},
                             .write_rows = rows, .values = values, .nvalues = 4};
    hid_t own = -1;
    if (odd) {
        /* Not a plain table: a scalar, a null space, three dimensions,
         * strings or bit fields, or chunks with rows left unwritten. */
        switch (take_below(b, 6)) {
        case 0: spec.rank = 0; break;
        case 1: spec.rank = -1; break;
        case 2: spec.rank = 3, spec.dims[1] = 3, spec.dims[2] = 2; break;
        case 3:
            own = H5Tcopy(H5T_C_S1);
            H5Tset_size(own, 8);
            spec.type = own;
            break;
        case 4: spec.type = H5T_NATIVE_B8; break;
        case 5:
            spec.chunk_rows = 1 + take_below(b, 8);
            spec.write_rows = take_below(b, (unsigned)rows + 1);
            break;
        }
    }
    h5w_replace_dataset_spec(file, object, &spec);
    if (own >= 0)
        H5Tclose(own);
}

static void edit_link(run *r, hid_t file)
{
    static const char *const targets[] = {"/PartType0", "/PartType1", "/Header", "/nowhere",
                                          "/PartType0/Coordinates", "/PartType1/Masses"};
    char name[64];
    take_object(r, name, sizeof name, (int)take_below(&r->in, 2));
    const char *target = targets[take_below(&r->in, sizeof targets / sizeof targets[0])];
    h5w_add_link(file, name, target, (int)take_below(&r->in, 2));
}

static void edit_file(run *r, hid_t file)
{
    bytes *b = &r->in;
    char object[64];
    static const char *const others[] = {"Header", "Units", "Code", "Parameters"};
    switch (take_below(b, 10)) {
    case 0: /* delete a group, a dataset or another top-level group */
        switch (take_below(b, 3)) {
        case 0: take_object(r, object, sizeof object, 0); break;
        case 1: take_object(r, object, sizeof object, 1); break;
        default: snprintf(object, sizeof object, "%s", others[take_below(b, 4)]); break;
        }
        h5w_delete_in(file, object);
        break;
    case 1: edit_dataset(r, file, 0); break;
    case 2: edit_dataset(r, file, 1); break;
    case 3: edit_huge(r, file); break;
    case 4:
    case 5: edit_header_attr(r, file); break;
    case 6: {
        const char *name = header_attrs[take_below(b, N_HEADER_ATTRS)];
        h5w_set_string_attr(file, "Header", name, "junk", (int)take_below(b, 2));
        break;
    }
    case 7: h5w_delete_attr(file, "Header", header_attrs[take_below(b, N_HEADER_ATTRS)]); break;
    case 8: /* a group where a group or dataset is expected (or past ntypes) */
        take_object(r, object, sizeof object, (int)take_below(b, 2));
        h5w_add_group(file, object);
        break;
    case 9: edit_link(r, file); break;
    }
}

/* ---- Writing the snapshot --------------------------------------------- */

/* The particles of type t in a file. */
static void take_part(run *r, int file, int t, h5w_part *p, uint64_t *first_id)
{
    bytes *b = &r->in;
    part_data *d = &parts[file][t];
    /* Default: 5 particles of type 0 and none of the others. */
    size_t n = (take_u8(b) + (t == 0 ? 5 : 0)) % (MAX_PART + 1);
    /* Default (bits clear): Coordinates and Masses, the least a valid group
     * needs; the datasets are where the time goes. */
    unsigned omit = take_u8(b) ^ (0xffu & ~(1u << K_POS | 1u << K_MASS));
    take_array(b, d->pos, 3 * n);
    *p = (h5w_part){.n = n};
    if (!(omit & 1u << K_POS))
        p->pos = d->pos;
    if (!(omit & 1u << K_VEL))
        take_array(b, d->vel, 3 * n), p->vel = d->vel;
    if (!(omit & 1u << K_ID))
        take_ids(b, d->id, n, *first_id), p->id = d->id;
    if (!(omit & 1u << K_MASS))
        take_array(b, d->mass, n), p->mass = d->mass;
    if (!(omit & 1u << K_H))
        take_array(b, d->h, n), p->h = d->h;
    if (!(omit & 1u << K_U))
        take_array(b, d->u, n), p->u = d->u;
    if (!(omit & 1u << K_RHO))
        take_array(b, d->rho, n), p->rho = d->rho;
    if (!(omit & 1u << K_POT))
        take_array(b, d->pot, n), p->pot = d->pot;
    *first_id += n;
}

static void write_snapshot(run *r, h5w_snapshot *s)
{
    bytes *b = &r->in;
    static const int nfiles_claims[] = {-1, 0, 1, 2, 3, 4, 100000, 100001, 2147483647};
    unsigned claim = take_u8(b);
    int nfiles = claim == 0 ? r->nwritten : nfiles_claims[(claim - 1) % (sizeof nfiles_claims / sizeof nfiles_claims[0])];
    static const hid_t *const pos_types[] = {&H5T_IEEE_F32LE_g, &H5T_IEEE_F64LE_g, &H5T_IEEE_F32BE_g,
                                             &H5T_IEEE_F64BE_g, &H5T_STD_I32LE_g,  &H5T_STD_U16LE_g};
    static const hid_t *const id_types[] = {&H5T_STD_U64LE_g, &H5T_STD_U32LE_g, &H5T_STD_I32LE_g, &H5T_STD_I64LE_g,
                                            &H5T_STD_U64BE_g, &H5T_STD_U8LE_g,  &H5T_IEEE_F32LE_g, &H5T_IEEE_F64LE_g};
    s->pos_type = *pos_types[take_below(b, sizeof pos_types / sizeof pos_types[0])];
    s->id_type = *id_types[take_below(b, sizeof id_types / sizeof id_types[0])];
    s->time = take_value(b);
    s->redshift = take_value(b);
    s->box = take_value(b);
    for (int t = 0; t < r->ntypes; t++)
        r->mass_table[t] = s->mass_table[t] = take_value(b);
    int made_up_totals = (int)take_below(b, 4) == 3;
    uint64_t first_id = 1;
    h5w_part written[MAX_FILES][H5W_MAX_TYPES];
    uint64_t sums[H5W_MAX_TYPES] = {0};
    for (int f = 0; f < r->nwritten; f++)
        for (int t = 0; t < r->ntypes; t++) {
            take_part(r, f, t, &written[f][t], &first_id);
            sums[t] += written[f][t].n;
        }
    for (int t = 0; t < r->ntypes; t++)
        s->total[t] = made_up_totals ? to_u64(take_value(b)) : sums[t];
    for (int f = 0; f < r->nwritten; f++) {
        s->nfiles = nfiles;
        memcpy(s->part, written[f], sizeof s->part);
        hid_t file;
        h5w_write_open(r->path[f], s, &file);
        for (int t = 0; t < r->ntypes; t++)
            r->count[t] = written[f][t].n;
        unsigned edits = take_below(b, MAX_EDITS + 1);
        for (; edits > 0 && file >= 0; edits--)
            edit_file(r, file);
        if (file >= 0)
            H5Fclose(file);
    }
}

/* ---- Reading it back --------------------------------------------------- */

typedef struct pass {
    int ok;          /* read to the end without an error */
    uint64_t total;  /* particles delivered */
    uint64_t digest; /* of everything delivered */
} pass;

static uint64_t mix(uint64_t h, uint64_t v)
{
    h ^= v + UINT64_C(0x9e3779b97f4a7c15) + (h << 6) + (h >> 2);
    return h;
}

static uint64_t float_bits(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

/* ORRERY_FUZZ_VERBOSE set: say what happened to each input (for checking
 * what the corpus reaches). */
static int verbose = -1;

static pass read_all(orr_source *src, unsigned type_mask)
{
    orr_error err = {0};
    const orr_chunk *c;
    pass p = {0, 0, 0};
    for (;;) {
        if (orr_source_next(src, &c, &err) != ORR_OK) {
            if (verbose)
                fprintf(stderr, "read failed after %llu particles: %s\n", (unsigned long long)p.total, err.msg);
            return p;
        }
        if (c->n == 0)
            break;
        if (c->n > c->capacity)
            abort(); /* the reader overran its own chunk */
        for (size_t i = 0; i < c->n; i++) {
            if (c->type[i] >= 32 || (type_mask && !(type_mask >> c->type[i] & 1u)))
                abort(); /* a type nobody asked for */
            if (!(c->mass[i] >= 0) || isinf(c->mass[i]) || (c->h && (!(c->h[i] >= 0) || isinf(c->h[i]))))
                abort(); /* documented: masses and h are finite and non-negative */
            uint64_t h = mix(p.digest, float_bits(c->x[i]));
            h = mix(h, float_bits(c->y[i]));
            h = mix(h, float_bits(c->z[i]));
            h = mix(h, float_bits(c->mass[i]));
            if (c->h)
                h = mix(h, float_bits(c->h[i]));
            h = mix(h, c->id[i]);
            h = mix(h, c->type[i]);
            for (int e = 0; e < c->nextra; e++)
                h = mix(h, float_bits(c->extra[e].data[i]));
            p.digest = h;
        }
        p.total += c->n;
    }
    p.ok = 1;
    if (verbose)
        fprintf(stderr, "read %llu particles\n", (unsigned long long)p.total);
    return p;
}

static void remove_files(const run *r)
{
    for (int f = 0; f < MAX_FILES; f++)
        unlink(r->path[f]);
    unlink(r->base_ext);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static run r0;
    run *r = &r0;
    memset(r, 0, sizeof *r);
    r->in = (bytes){data, size};
    static int started;
    if (!started) {
        H5open(); /* sets the H5T_* globals the tables below point at */
        H5Eset_auto2(H5E_DEFAULT, NULL, NULL); /* the writer's edits fail often */
        /* Speed: every file open allocates (and every close frees) libhdf5's
         * half-megabyte metadata cache; ASan serves each from a fresh mmap.
         * With no limits on its free lists libhdf5 reuses them instead
         * (ten times faster). The memory stays reachable, so LSan is not
         * affected. */
        H5set_free_list_limits(-1, -1, -1, -1, -1, -1);
        verbose = getenv("ORRERY_FUZZ_VERBOSE") != NULL;
        started = 1;
    }
    long pid = (long)getpid();
    snprintf(r->base, sizeof r->base, "/tmp/orrery-fuzz-hdf5-%ld", pid);
    snprintf(r->base_ext, sizeof r->base_ext, "/tmp/orrery-fuzz-hdf5-%ld.hdf5", pid);

    unsigned layout = take_u8(&r->in);
    static const int ntypes_choice[] = {2, 6, 7, 6};
    r->swift = layout & 1;
    r->ntypes = ntypes_choice[layout >> 1 & 3];
    r->numbered = !(layout & 0x40);
    r->nwritten = r->numbered ? 1 + (int)((layout >> 4 & 3) % MAX_FILES) : 1;
    for (int f = 0; f < MAX_FILES; f++)
        if (r->numbered)
            snprintf(r->path[f], sizeof r->path[f], "/tmp/orrery-fuzz-hdf5-%ld.%d.hdf5", pid, f);
        else
            memcpy(r->path[f], r->base_ext, sizeof r->path[f]);

    static const unsigned masks[] = {0, 0x1, 0x2, 0x42, 0x3f, 0x80, 0x10000};
    static const char *const fields_a[] = {"vx", "u", "pot"};
    /* Named fields (src/source/readers/hdf5_named.c): a column of a 2-D dataset, a
     * 1-D dataset read as a field of its own, a name no group has. */
    static const char *const fields_b[] = {"rho", "vz", "vy", "Coordinates[2]"};
    static const char *const fields_c[] = {"h", "mass", "u", "Masses"};
    static const char *const fields_d[] = {"vx", "ParticleIDs", "nonexistent"};
    static const char *const *const field_lists[] = {NULL, fields_a, fields_a, fields_b, fields_c, fields_d};
    static const int nfields[] = {0, 3, 0, 4, 4, 3};
    /* Small chunks split groups and files; 0 is the reader's default. Not
     * smaller: each chunk is a read of every dataset, and time is short. */
    static const size_t chunk_sizes[] = {257, 7, 64, 0};
    unsigned pick = take_below(&r->in, 8);
    unsigned type_mask = pick < 7 ? masks[pick] : take_u8(&r->in);
    unsigned fl = take_below(&r->in, 6);
    orr_source_options opt = {.format = "hdf5",
                              .chunk_size = chunk_sizes[take_below(&r->in, 4)],
                              .type_mask = type_mask,
                              .fields = field_lists[fl],
                              .nfields = nfields[fl]};
    unsigned name_pick = take_below(&r->in, 4);

    h5w_snapshot snap = {.style = r->swift ? H5W_SWIFT : H5W_GADGET, .ntypes = r->ntypes,
                         .gadget4_units = (layout >> 3) & 1};
    write_snapshot(r, &snap);

    /* Numbered files are opened by the first's or the last's name, or by the
     * base name with or without .hdf5 (neither exists: the reader looks for
     * base.0.hdf5). */
    const char *name = !r->numbered || name_pick == 0 ? r->path[0]
                       : name_pick == 1               ? r->path[r->nwritten - 1]
                       : name_pick == 2               ? r->base_ext
                                                      : r->base;

    orr_source *src = NULL;
    orr_error err = {0};
    if (orr_hdf5_source_open(name, &opt, &src, &err) == ORR_OK) {
        pass first = read_all(src, type_mask);
        if (first.ok && src->info.count >= 0 && first.total != (uint64_t)src->info.count)
            abort(); /* info.count promised another number of particles */
        if (orr_source_rewind(src, &err) == ORR_OK) {
            pass again = read_all(src, type_mask);
            if (first.ok && (!again.ok || again.total != first.total || again.digest != first.digest))
                abort(); /* the same files read differently after a rewind */
        } else if (first.ok) {
            abort();
        }
        orr_source_close(src);
    } else if (src) {
        abort(); /* a failed open must not hand out a source */
    } else if (verbose) {
        fprintf(stderr, "open failed: %s\n", err.msg);
    }
    if (H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL) != 0)
        abort(); /* an HDF5 file, group, dataset or attribute left open */
    remove_files(r);
    return 0;
}
