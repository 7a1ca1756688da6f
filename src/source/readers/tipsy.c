#include "source/readers/tipsy.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>

#include "core/bytes.h"
#include "source/readers/formats.h"
#include "source/readers/mass_policy.h"
#include "source/readers/share.h"
#include "source/readers/tipsy_iord.h"

/* Particle families in file order: gas, dark, star. */
enum { GAS, DARK, STAR, NFAMILIES };

static const char *const family_name[NFAMILIES] = {"gas", "dark", "star"};
static const uint8_t family_type[NFAMILIES] = {0, 1, 4}; /* Gadget convention */
static const int record_floats[NFAMILIES] = {12, 9, 11};

#define TIPSY_MAX_FLOATS 12
#define TIPSY_MIN_HEADER 28 /* double time + five ints, unpadded */
#define TIPSY_PADDED_HEADER 32
/* Records decoded per fread: large enough to amortise the call, small enough
 * that the I/O buffer (48 bytes a record) stays a few megabytes. */
#define TIPSY_BLOCK_RECORDS 65536

/* Quantities in the records and their column in each family's record
 * (-1: that family has no such quantity). */
enum { Q_MASS, Q_X, Q_Y, Q_Z, Q_VX, Q_VY, Q_VZ, Q_RHO, Q_TEMP, Q_HSMOOTH, Q_METALS, Q_TFORM, Q_EPS, Q_PHI, NQ };

static const signed char column_of[NFAMILIES][NQ] = {
    /*          m  x  y  z vx vy vz rho temp hsm met tform eps phi */
    [GAS] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, -1, -1, 11},
    [DARK] = {0, 1, 2, 3, 4, 5, 6, -1, -1, -1, -1, -1, 7, 8},
    [STAR] = {0, 1, 2, 3, 4, 5, 6, -1, -1, -1, 7, 8, 9, 10},
};

/* The extra fields a Tipsy file can offer, in the order they are loaded. */
static const struct {
    const char *name;
    int quantity;
} tipsy_extras[] = {
    {"vx", Q_VX},         {"vy", Q_VY},       {"vz", Q_VZ},   {"rho", Q_RHO}, {"temp", Q_TEMP},
    {"metals", Q_METALS}, {"tform", Q_TFORM}, {"eps", Q_EPS}, {"phi", Q_PHI},
};
#define TIPSY_NEXTRAS ((int)(sizeof tipsy_extras / sizeof tipsy_extras[0]))

typedef struct tipsy_header {
    double time;
    int32_t nbodies, ndim, count[NFAMILIES];
    int big_endian;
    int header_size; /* 32 (padded, standard) or 28 */
} tipsy_header;

typedef struct tipsy_state {
    FILE *fp;
    tipsy_header hdr;
    int wanted[NFAMILIES];
    orr_share share;    /* the records of each family this process reads */
    int extra_column[NFAMILIES][ORR_MAX_EXTRA_FIELDS]; /* -1: fill 0 */
    int family;         /* family being read */
    int64_t index;      /* next record within that family */
    int positioned;     /* whether fp is at that record */
    long long file_size;
    unsigned char *buf; /* TIPSY_BLOCK_RECORDS records at most */
    size_t block;       /* records per fread */
    int has_iord;       /* ids from SNAPSHOT.iord (tipsy_iord.h), not file positions */
    orr_tipsy_iord iord;
} tipsy_state;

/* Tipsy files say which byte order they are in; the loaders want whether
 * that is the reverse of the host's. */
static int swapped(int big_endian)
{
    return big_endian != orr_host_big_endian();
}

/* Decodes the first 28 bytes of head in one byte order. */
static void decode_header(const unsigned char *head, int big_endian, tipsy_header *h)
{
    h->time = orr_load_f64(head, swapped(big_endian));
    h->nbodies = orr_load_i32(head + 8, swapped(big_endian));
    h->ndim = orr_load_i32(head + 12, swapped(big_endian));
    for (int f = 0; f < NFAMILIES; f++)
        h->count[f] = orr_load_i32(head + 16 + 4 * f, swapped(big_endian));
    h->big_endian = big_endian;
    h->header_size = TIPSY_PADDED_HEADER;
}

static const char *order_name(int big_endian)
{
    return big_endian ? "big-endian" : "little-endian";
}

/* Returns 0 when the counts are consistent; otherwise 1 with the first
 * problem described in why. */
static int header_problem(const tipsy_header *h, char *why, size_t size)
{
    static const char *const count_name[NFAMILIES] = {"nsph", "ndark", "nstar"};
    if (h->ndim != 3) {
        snprintf(why, size, "ndim is %d, not 3", (int)h->ndim);
        return 1;
    }
    if (h->nbodies < 0) {
        snprintf(why, size, "negative nbodies %d", (int)h->nbodies);
        return 1;
    }
    for (int f = 0; f < NFAMILIES; f++)
        if (h->count[f] < 0) {
            snprintf(why, size, "negative %s %d", count_name[f], (int)h->count[f]);
            return 1;
        }
    int64_t sum = (int64_t)h->count[GAS] + h->count[DARK] + h->count[STAR];
    if (sum != h->nbodies) {
        snprintf(why, size, "nbodies %d is not nsph %d + ndark %d + nstar %d = %lld", (int)h->nbodies,
                 (int)h->count[GAS], (int)h->count[DARK], (int)h->count[STAR], (long long)sum);
        return 1;
    }
    return 0;
}

static long long record_bytes(int family)
{
    return 4LL * record_floats[family];
}

/* Counts are below 2^31, so the size stays far below 2^63. */
static long long expected_size(const tipsy_header *h, int header_size)
{
    long long size = header_size;
    for (int f = 0; f < NFAMILIES; f++)
        size += record_bytes(f) * h->count[f];
    return size;
}

/* Finds the byte order whose header is consistent and, when file_size is
 * known (>= 0), the header size that makes the records fill the file
 * exactly. Returns 1 with *h filled, or 0 with the reason in why. */
static int detect_layout(const unsigned char *head, size_t n, long long file_size, tipsy_header *h, char *why,
                         size_t size)
{
    if (n < TIPSY_MIN_HEADER) {
        snprintf(why, size, "%zu bytes is shorter than a Tipsy header (28 or 32 bytes)", n);
        return 0;
    }
    char problem[2][160];
    /* ndim == 3 holds in at most one byte order, so at most one passes. */
    for (int big = 1; big >= 0; big--) {
        tipsy_header t;
        decode_header(head, big, &t);
        if (header_problem(&t, problem[big], sizeof problem[big]))
            continue;
        long long padded = expected_size(&t, TIPSY_PADDED_HEADER);
        long long unpadded = expected_size(&t, TIPSY_MIN_HEADER);
        if (file_size >= 0 && file_size != padded && file_size != unpadded) {
            snprintf(why, size,
                     "the %s header (nbodies %d = nsph %d + ndark %d + nstar %d) needs a file of %lld bytes "
                     "(%lld with the unpadded 28-byte header), but the file has %lld bytes: truncated, or "
                     "not a Tipsy file",
                     order_name(big), (int)t.nbodies, (int)t.count[GAS], (int)t.count[DARK], (int)t.count[STAR],
                     padded, unpadded, file_size);
            return 0;
        }
        *h = t;
        h->header_size = file_size == unpadded ? TIPSY_MIN_HEADER : TIPSY_PADDED_HEADER;
        return 1;
    }
    snprintf(why, size, "the header is not consistent in either byte order (big-endian: %s; little-endian: %s)",
             problem[1], problem[0]);
    return 0;
}

int orr_tipsy_probe(const unsigned char *head, size_t n)
{
    /* Below ORR_PROBE_BYTES the probe saw the whole file, so its size must
     * match as well; a larger file is checked in full when opened. */
    long long file_size = n < ORR_PROBE_BYTES ? (long long)n : -1;
    tipsy_header h;
    char why[512];
    if (!detect_layout(head, n, file_size, &h, why, sizeof why))
        return 0;
    return isfinite(h.time); /* a real snapshot time; guards against other binaries */
}

/* Offset in the file of a family's first record. */
static long long family_offset(const tipsy_header *h, int family)
{
    long long off = h->header_size;
    for (int f = 0; f < family; f++)
        off += record_bytes(f) * h->count[f];
    return off;
}

/* File index of a family's first particle (Tipsy has no ids, so the index
 * is the id). */
static int64_t family_base(const tipsy_header *h, int family)
{
    int64_t base = 0;
    for (int f = 0; f < family; f++)
        base += h->count[f];
    return base;
}

/* Moves to the next family to read, or past the last one. */
static void next_family(tipsy_state *st)
{
    st->family++;
    st->index = 0;
    st->positioned = 0;
}

static orr_status seek_record(orr_source *src, tipsy_state *st, orr_error *err)
{
    long long off = family_offset(&st->hdr, st->family) + st->index * record_bytes(st->family);
    if (fseeko(st->fp, (off_t)off, SEEK_SET) != 0)
        return orr_fail(err, ORR_ERR_IO, "%s: cannot seek to the %s particles (byte %lld): %s", src->info.path,
                        family_name[st->family], off, strerror(errno));
    st->positioned = 1;
    return ORR_OK;
}

/* Decodes k records of the current family from st->buf into the chunk from
 * slot c->n on. */
static void decode_records(tipsy_state *st, orr_chunk *c, size_t k)
{
    const int fam = st->family, big = st->hdr.big_endian, nf = record_floats[fam];
    const int64_t first_id = family_base(&st->hdr, fam) + st->index;
    for (size_t r = 0; r < k; r++) {
        const unsigned char *rec = st->buf + r * (size_t)record_bytes(fam);
        float v[TIPSY_MAX_FLOATS];
        for (int j = 0; j < nf; j++)
            v[j] = orr_load_f32(rec + 4 * j, swapped(big));
        size_t at = c->n + r;
        c->mass[at] = v[Q_MASS];
        c->x[at] = v[Q_X];
        c->y[at] = v[Q_Y];
        c->z[at] = v[Q_Z];
        /* Only gas has a smoothing length; 0 marks it unknown for the rest. */
        if (c->h)
            c->h[at] = fam == GAS ? v[column_of[GAS][Q_HSMOOTH]] : 0.0f;
        c->id[at] = (uint64_t)(first_id + (int64_t)r);
        c->type[at] = family_type[fam];
        for (int e = 0; e < c->nextra; e++) {
            int col = st->extra_column[fam][e];
            c->extra[e].data[at] = col >= 0 ? v[col] : 0.0f;
        }
    }
}

/* The mass policy on the k masses just decoded into the chunk from c->n on
 * (Tipsy stores floats, so these are the file's values). */
static orr_status check_masses(const orr_source *src, const tipsy_state *st, const orr_chunk *c, size_t k,
                               orr_error *err)
{
    for (size_t r = 0; r < k; r++) {
        const char *problem = orr_mass_problem(c->mass[c->n + r]);
        if (problem) {
            int64_t index = st->index + (int64_t)r;
            return orr_fail(err, ORR_ERR_FORMAT, "%s: %s particle %lld (particle %lld of the file): mass %g %s",
                            src->info.path, family_name[st->family], (long long)index,
                            (long long)(family_base(&st->hdr, st->family) + index), (double)c->mass[c->n + r],
                            problem);
        }
    }
    return ORR_OK;
}

static orr_status read_block(orr_source *src, tipsy_state *st, size_t k, orr_error *err)
{
    size_t got = fread(st->buf, (size_t)record_bytes(st->family), k, st->fp);
    if (got == k)
        return ORR_OK;
    if (ferror(st->fp))
        return orr_fail(err, ORR_ERR_IO, "%s: read error in the %s particles: %s", src->info.path,
                        family_name[st->family], strerror(errno));
    /* The size was checked when opening, so the file shrank since. */
    return orr_fail(err, ORR_ERR_FORMAT,
                    "%s: unexpected end of file in %s particle %lld (expected %lld bytes, as when the file was "
                    "opened)",
                    src->info.path, family_name[st->family], (long long)(st->index + (int64_t)got),
                    st->file_size);
}

static orr_status tipsy_next(orr_source *src, orr_error *err)
{
    tipsy_state *st = src->state;
    orr_chunk *c = &src->chunk;
    int64_t first_index = 0; /* the file position of the chunk's first particle (ids may be .iord's) */
    while (c->n < c->capacity && st->family < NFAMILIES) {
        if (st->index < st->share.lo[st->family])
            st->index = st->share.lo[st->family]; /* the records before are other processes' */
        int64_t left = st->share.hi[st->family] - st->index;
        if (left <= 0) {
            next_family(st); /* unwanted families and others' records are skipped without reading */
            continue;
        }
        orr_status s;
        if (!st->positioned && (s = seek_record(src, st, err)))
            return s;
        size_t k = c->capacity - c->n;
        if (k > st->block)
            k = st->block;
        if ((int64_t)k > left)
            k = (size_t)left;
        if ((s = read_block(src, st, k, err)))
            return s;
        if (c->n == 0)
            first_index = family_base(&st->hdr, st->family) + st->index;
        decode_records(st, c, k);
        if ((s = check_masses(src, st, c, k, err)))
            return s;
        if (st->has_iord &&
            (s = orr_tipsy_iord_read(&st->iord, family_base(&st->hdr, st->family) + st->index, k, c->id + c->n, err)))
            return s;
        c->n += k;
        st->index += (int64_t)k;
    }
    c->first_index = (uint64_t)first_index;
    return ORR_OK;
}

static orr_status tipsy_rewind(orr_source *src, orr_error *err)
{
    (void)err;
    tipsy_state *st = src->state;
    st->family = 0;
    st->index = 0;
    st->positioned = 0; /* the next read seeks */
    return ORR_OK;
}

static void tipsy_close(orr_source *src)
{
    tipsy_state *st = src->state;
    if (!st)
        return;
    if (st->fp)
        fclose(st->fp);
    orr_tipsy_iord_close(&st->iord);
    orr_share_free(&st->share);
    free(st->buf);
    free(st);
    src->state = NULL;
}

static const orr_source_ops tipsy_ops = {.next = tipsy_next, .rewind = tipsy_rewind, .close = tipsy_close};

/* Reads the header and checks it against the file size. */
static orr_status read_header(const char *path, tipsy_state *st, orr_error *err)
{
    struct stat sb;
    if (fstat(fileno(st->fp), &sb) != 0)
        return orr_fail(err, ORR_ERR_IO, "%s: cannot stat: %s", path, strerror(errno));
    if (!S_ISREG(sb.st_mode))
        return orr_fail(err, ORR_ERR_IO, "%s: not a regular file (Tipsy files are read with seeks)", path);
    st->file_size = (long long)sb.st_size;
    unsigned char head[TIPSY_PADDED_HEADER];
    size_t n = fread(head, 1, sizeof head, st->fp);
    if (ferror(st->fp))
        return orr_fail(err, ORR_ERR_IO, "%s: read error: %s", path, strerror(errno));
    char why[512];
    if (!detect_layout(head, n, st->file_size, &st->hdr, why, sizeof why))
        return orr_fail(err, ORR_ERR_FORMAT, "%s: not a readable Tipsy file: %s", path, why);
    /* The probe refuses such a time, but a named format skips the probe;
     * the time goes into every image's FITS header. */
    if (!isfinite(st->hdr.time))
        return orr_fail(err, ORR_ERR_FORMAT, "%s: header time = %g is not a finite number", path, st->hdr.time);
    return ORR_OK;
}

/* Whether any family to be read has the quantity. */
static int read_families_have(const tipsy_state *st, int quantity)
{
    for (int f = 0; f < NFAMILIES; f++)
        if (st->wanted[f] && column_of[f][quantity] >= 0)
            return 1;
    return 0;
}

/* Picks the families and extra fields to load, and describes them in info. */
static void choose_contents(orr_source *src, tipsy_state *st, const orr_source_options *opt)
{
    orr_source_info *info = &src->info;
    info->count = 0;
    for (int f = 0; f < NFAMILIES; f++) {
        st->wanted[f] = st->hdr.count[f] > 0 && orr_source_wants_type(opt, family_type[f]);
        if (st->wanted[f])
            info->count += st->hdr.count[f];
    }
    /* Fields no family being read has would be all zeros: leave them out,
     * so asking for one is reported as "not a field" downstream. */
    for (int e = 0; e < TIPSY_NEXTRAS; e++) {
        int q = tipsy_extras[e].quantity;
        if (!orr_source_wants_field(opt, tipsy_extras[e].name) || !read_families_have(st, q))
            continue;
        int slot = info->nextra++;
        snprintf(info->extra_names[slot], ORR_FIELD_NAME_MAX, "%s", tipsy_extras[e].name);
        for (int f = 0; f < NFAMILIES; f++)
            st->extra_column[f][slot] = column_of[f][q];
    }
    info->has_h = st->wanted[GAS];
    info->has_id = st->has_iord; /* else ids are file indices */
    info->has_type = 1;
    info->time = st->hdr.time;
}

static void add_header_entries(orr_source_info *info, const tipsy_header *h)
{
    orr_source_add_header(info, "byte order", "%s%s", order_name(h->big_endian),
                          h->big_endian ? " (standard XDR)" : " (native)");
    orr_source_add_header(info, "header size", "%d bytes%s", h->header_size,
                          h->header_size == TIPSY_PADDED_HEADER ? " (padded)" : " (unpadded)");
    orr_source_add_header(info, "nbodies", "%d", (int)h->nbodies);
    orr_source_add_header(info, "nsph", "%d", (int)h->count[GAS]);
    orr_source_add_header(info, "ndark", "%d", (int)h->count[DARK]);
    orr_source_add_header(info, "nstar", "%d", (int)h->count[STAR]);
    orr_source_add_header(info, "time", "%.17g", h->time);
}

/* Which records of each family this process reads: a range of each, as the
 * records have a fixed size. */
static orr_status choose_share(orr_source *src, tipsy_state *st, const orr_source_options *opt, orr_error *err)
{
    orr_status s = orr_share_alloc(&st->share, NFAMILIES, err);
    if (s)
        return s;
    for (int f = 0; f < NFAMILIES; f++)
        st->share.hi[f] = st->wanted[f] ? st->hdr.count[f] : 0;
    return orr_share_divide(&st->share, NFAMILIES, src, opt, err);
}

/* Allocates the chunk and the I/O buffer, both bounded by the chunk size
 * (and by the particle count, so small files stay small). */
static orr_status alloc_buffers(orr_source *src, tipsy_state *st, const orr_source_options *opt, orr_error *err)
{
    orr_status s = orr_source_alloc_chunk(src, opt, err);
    if (s)
        return s;
    size_t capacity = src->chunk.capacity;
    st->block = capacity < TIPSY_BLOCK_RECORDS ? capacity : TIPSY_BLOCK_RECORDS;
    st->buf = orr_malloc(st->block * (size_t)record_bytes(GAS), "Tipsy read buffer", err);
    return st->buf ? ORR_OK : ORR_ERR_NOMEM;
}

orr_status orr_tipsy_source_open(const char *path, const orr_source_options *opt, orr_source **out,
                                 orr_error *err)
{
    orr_source *src;
    FILE *fp;
    orr_status s = orr_source_new_file("tipsy", path, &tipsy_ops, sizeof(tipsy_state), &src, &fp, err);
    if (s)
        return s;
    tipsy_state *st = src->state;
    st->fp = fp;
    s = read_header(path, st, err);
    if (!s)
        s = orr_tipsy_iord_open(&st->iord, path, st->hdr.nbodies, &st->has_iord, err);
    if (!s) {
        choose_contents(src, st, opt);
        add_header_entries(&src->info, &st->hdr);
        if (st->has_iord)
            orr_source_add_header(&src->info, "ids", "%s (%s)", st->iord.path,
                                  st->iord.binary ? (st->iord.width == 4 ? "binary, 32-bit" : "binary, 64-bit")
                                                  : "ASCII");
        s = choose_share(src, st, opt, err);
    }
    if (!s)
        s = alloc_buffers(src, st, opt, err);
    if (s) {
        orr_source_close(src);
        return s;
    }
    *out = src;
    return ORR_OK;
}
