/* The .npy reader (npy_reader.h); the header is npy_header.c's. */
#include "source/npy_reader.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/bytes.h"

#include "source/mass_policy.h"
#include "source/npy_header.h"
#include "source/share.h"

#define NPY_BUFFER_BYTES ((size_t)4 << 20) /* rows read per fread: at most this many bytes */

/* What each column becomes. */
enum { R_X, R_Y, R_Z, R_MASS, R_H, R_ID, R_TYPE, R_EXTRA, R_SKIP };

typedef struct npy_state {
    FILE *fp;
    npy_header hdr;
    int role[NPY_MAX_COLUMNS];  /* R_*, and for R_EXTRA the chunk's extra index in slot[] */
    int slot[NPY_MAX_COLUMNS];
    orr_share share;            /* one run: the rows this process reads */
    int64_t row;                /* next row */
    unsigned char *buf;
    size_t block;               /* rows per read */
} npy_state;

int orr_npy_probe(const unsigned char *head, size_t n) { return npy_has_magic(head, n); }

/* One stored value's bits, in its byte order, sign-extended for a signed
 * integer narrower than 8 bytes. */
static uint64_t raw_at(const npy_column *c, const unsigned char *p)
{
    uint64_t u = 0;
    for (int i = 0; i < c->size; i++)
        u |= (uint64_t)p[c->big ? c->size - 1 - i : i] << (8 * i);
    if (c->kind == NPY_INT && c->size < 8 && (u >> (8 * c->size - 1) & 1))
        u |= ~(uint64_t)0 << (8 * c->size);
    return u;
}

/* One stored value as a double (integers of up to 8 bytes, floats). */
static double value_at(const npy_column *c, const unsigned char *p)
{
    uint64_t u = raw_at(c, p);
    if (c->kind == NPY_FLOAT && c->size == 4) {
        uint32_t w = (uint32_t)u;
        float f;
        memcpy(&f, &w, sizeof f);
        return f;
    }
    if (c->kind == NPY_FLOAT) {
        double d;
        memcpy(&d, &u, sizeof d);
        return d;
    }
    return c->kind == NPY_INT ? (double)(int64_t)u : (double)u;
}

/* An integer column's value exactly (ids beyond 2^53 stay exact). */
static int64_t integer_at(const npy_column *c, const unsigned char *p, int *negative)
{
    uint64_t u = raw_at(c, p);
    *negative = c->kind == NPY_INT && (int64_t)u < 0;
    return (int64_t)u;
}

static int role_of(const char *name)
{
    static const struct {
        const char *name;
        int role;
    } roles[] = {{"x", R_X}, {"y", R_Y}, {"z", R_Z}, {"mass", R_MASS}, {"m", R_MASS},
                 {"h", R_H}, {"id", R_ID}, {"type", R_TYPE}};
    for (size_t i = 0; i < sizeof roles / sizeof roles[0]; i++)
        if (strcmp(name, roles[i].name) == 0)
            return roles[i].role;
    return name[0] ? R_EXTRA : R_SKIP;
}

/* Gives every column its role; checks x, y, z are there, each role once,
 * ids and types integers. Extra fields not wanted are skipped. */
static orr_status assign_roles(orr_source *src, npy_state *st, const orr_source_options *opt, orr_error *err)
{
    const npy_header *h = &st->hdr;
    int seen[R_EXTRA] = {0};
    orr_source_info *info = &src->info;
    for (int i = 0; i < h->ncolumns; i++) {
        const npy_column *c = &h->col[i];
        int r = c->kind == NPY_PAD ? R_SKIP : role_of(c->name);
        if (r < R_EXTRA && seen[r]++)
            return orr_fail(err, ORR_ERR_FORMAT, "%s: field '%s': a second %s column", src->info.path, c->name,
                            r == R_MASS ? "mass (mass or m)" : c->name);
        if ((r == R_ID || r == R_TYPE) && c->kind == NPY_FLOAT)
            return orr_fail(err, ORR_ERR_FORMAT, "%s: field '%s' holds floats; %s are integers", src->info.path,
                            c->name, r == R_ID ? "ids" : "types");
        if (r == R_EXTRA && (!orr_source_wants_field(opt, c->name) || info->nextra >= ORR_MAX_EXTRA_FIELDS))
            r = R_SKIP;
        if (r == R_EXTRA) {
            st->slot[i] = info->nextra;
            snprintf(info->extra_names[info->nextra++], ORR_FIELD_NAME_MAX, "%s", c->name);
        }
        st->role[i] = r;
    }
    if (!seen[R_X] || !seen[R_Y] || !seen[R_Z])
        return orr_fail(err, ORR_ERR_FORMAT, "%s: the array has no field '%s' (positions are fields x, y, z)",
                        src->info.path, !seen[R_X] ? "x" : !seen[R_Y] ? "y" : "z");
    info->has_h = seen[R_H];
    info->has_id = seen[R_ID];
    info->has_type = seen[R_TYPE];
    return ORR_OK;
}

/* Reads the preamble and header dict and checks the file's size. */
static orr_status read_header(orr_source *src, npy_state *st, orr_error *err)
{
    const char *path = src->info.path;
    unsigned char head[NPY_PREAMBLE_V2];
    char why[512];
    size_t n = fread(head, 1, sizeof head, st->fp);
    if (!npy_parse_preamble(head, n, &st->hdr, why, sizeof why))
        return orr_fail(err, ORR_ERR_FORMAT, "%s: not a readable .npy file: %s", path, why);
    struct stat sb;
    if (fstat(fileno(st->fp), &sb) != 0 || !S_ISREG(sb.st_mode))
        return orr_fail(err, ORR_ERR_IO, "%s: not a regular file (.npy files are read with seeks)", path);
    if (st->hdr.data_offset > (int64_t)sb.st_size)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: the file ends inside its %zu-byte header", path,
                        st->hdr.header_len);
    int64_t preamble = st->hdr.version == 1 ? NPY_PREAMBLE_V1 : NPY_PREAMBLE_V2;
    char *text = orr_malloc(st->hdr.header_len + 1, ".npy header", err);
    if (!text)
        return ORR_ERR_NOMEM;
    int ok = fseeko(st->fp, (off_t)preamble, SEEK_SET) == 0 &&
             fread(text, 1, st->hdr.header_len, st->fp) == st->hdr.header_len &&
             npy_parse_dict(text, st->hdr.header_len, &st->hdr, why, sizeof why);
    free(text);
    if (!ok)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: %s", path, why[0] ? why : "cannot read the header");
    int64_t want = st->hdr.data_offset + st->hdr.rows * (int64_t)st->hdr.record;
    if (want != (int64_t)sb.st_size)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: shape (%" PRId64 ", ...) of %zu-byte rows needs %" PRId64
                        " bytes but the file has %lld (%s)", path, st->hdr.rows, st->hdr.record, want,
                        (long long)sb.st_size, want > (int64_t)sb.st_size ? "truncated" : "bytes after the array");
    return ORR_OK;
}

/* Reads k rows from st->row into the buffer: whole rows in C order, or
 * column by column (each at its own place) for a Fortran-order array. */
static orr_status read_rows(orr_source *src, npy_state *st, size_t k, orr_error *err)
{
    const npy_header *h = &st->hdr;
    int runs = h->fortran ? h->ncolumns : 1;
    size_t width = h->fortran ? (size_t)h->col[0].size : h->record;
    for (int r = 0; r < runs; r++) {
        int64_t at = h->fortran ? (int64_t)r * h->rows + st->row : st->row;
        off_t off = (off_t)(h->data_offset + at * (int64_t)width);
        unsigned char *to = st->buf + (size_t)r * k * width;
        if (fseeko(st->fp, off, SEEK_SET) != 0 || fread(to, width, k, st->fp) != k)
            return orr_fail(err, ORR_ERR_FORMAT, "%s: cannot read rows %" PRId64 " to %" PRId64 " (the file shrank?)",
                            src->info.path, st->row, st->row + (int64_t)k - 1);
    }
    return ORR_OK;
}

/* Where row i's column j is in the buffer just read (k rows). */
static const unsigned char *cell(const npy_state *st, size_t k, size_t i, int j)
{
    const npy_header *h = &st->hdr;
    if (h->fortran)
        return st->buf + ((size_t)j * k + i) * (size_t)h->col[j].size;
    return st->buf + i * h->record + h->col[j].offset;
}

/* One value into the chunk; refuses what the renderer must not be given. */
static orr_status store(orr_source *src, npy_state *st, orr_chunk *c, size_t at, int j, const unsigned char *p,
                        int64_t row, orr_error *err)
{
    const npy_column *col = &st->hdr.col[j];
    const char *path = src->info.path;
    int negative = 0;
    switch (st->role[j]) {
    case R_X: c->x[at] = (float)value_at(col, p); break;
    case R_Y: c->y[at] = (float)value_at(col, p); break;
    case R_Z: c->z[at] = (float)value_at(col, p); break;
    case R_MASS: {
        double m = value_at(col, p);
        const char *problem = orr_mass_problem(m);
        if (problem)
            return orr_fail(err, ORR_ERR_FORMAT, "%s: row %" PRId64 ": mass %g %s", path, row, m, problem);
        c->mass[at] = (float)m;
        break;
    }
    case R_H: {
        double h = value_at(col, p);
        if (!(h >= 0) || isinf(h))
            return orr_fail(err, ORR_ERR_FORMAT, "%s: row %" PRId64 ": h = %g is not finite and non-negative", path,
                            row, h);
        c->h[at] = (float)h;
        break;
    }
    case R_ID:
        c->id[at] = (uint64_t)integer_at(col, p, &negative);
        if (negative)
            return orr_fail(err, ORR_ERR_FORMAT, "%s: row %" PRId64 ": id %" PRId64 " is negative", path, row,
                            (int64_t)c->id[at]);
        break;
    case R_TYPE: {
        int64_t t = integer_at(col, p, &negative);
        if (negative || t > 5)
            return orr_fail(err, ORR_ERR_FORMAT, "%s: row %" PRId64 ": type %" PRId64 " is not from 0 to 5", path,
                            row, t);
        c->type[at] = (uint8_t)t;
        break;
    }
    case R_EXTRA: c->extra[st->slot[j]].data[at] = (float)value_at(col, p); break;
    default: break;
    }
    return ORR_OK;
}

/* Fills what the file does not give: mass 1, ids from the row, type 0. */
static void defaults(const orr_source *src, orr_chunk *c, size_t at, int64_t row)
{
    if (!src->info.has_id)
        c->id[at] = (uint64_t)row;
    if (!src->info.has_type)
        c->type[at] = 0;
}

/* The float array an unchecked column goes to (positions, extra fields),
 * or NULL for the columns whose values are checked one by one. */
static float *float_target(const npy_state *st, orr_chunk *c, int j)
{
    switch (st->role[j]) {
    case R_X: return c->x;
    case R_Y: return c->y;
    case R_Z: return c->z;
    case R_EXTRA: return c->extra[st->slot[j]].data;
    default: return NULL;
    }
}

/* Column j of the k rows just read into out, when it is a float in the
 * host's byte order: a copy per value, without the general decoding (most
 * files: np.save of float32 or float64 on the same kind of machine).
 * Returns 0 when the column needs the general path. */
static int copy_native_floats(const npy_state *st, size_t k, int j, float *out)
{
    const npy_column *col = &st->hdr.col[j];
    if (col->kind != NPY_FLOAT || col->big != orr_host_big_endian())
        return 0;
    for (size_t i = 0; i < k; i++) {
        const unsigned char *p = cell(st, k, i, j);
        if (col->size == 4) {
            memcpy(&out[i], p, sizeof(float));
        } else {
            double d;
            memcpy(&d, p, sizeof d);
            out[i] = (float)d;
        }
    }
    return 1;
}

/* Decodes the k rows just read into the chunk from c->n on, column by
 * column. */
static orr_status decode_rows(orr_source *src, npy_state *st, orr_chunk *c, size_t k, orr_error *err)
{
    int has_mass = 0;
    for (int j = 0; j < st->hdr.ncolumns; j++)
        has_mass |= st->role[j] == R_MASS;
    for (size_t i = 0; i < k; i++) {
        if (!has_mass)
            c->mass[c->n + i] = 1.0f;
        defaults(src, c, c->n + i, st->row + (int64_t)i);
    }
    orr_status s = ORR_OK;
    for (int j = 0; j < st->hdr.ncolumns && !s; j++) {
        float *out = float_target(st, c, j);
        if (out && copy_native_floats(st, k, j, out + c->n))
            continue;
        for (size_t i = 0; i < k && !s; i++)
            s = store(src, st, c, c->n + i, j, cell(st, k, i, j), st->row + (int64_t)i, err);
    }
    return s;
}

static orr_status npy_next(orr_source *src, orr_error *err)
{
    npy_state *st = src->state;
    orr_chunk *c = &src->chunk;
    if (st->row < st->share.lo[0])
        st->row = st->share.lo[0];
    c->first_index = (uint64_t)st->row;
    while (c->n < c->capacity && st->row < st->share.hi[0]) {
        size_t k = c->capacity - c->n;
        if (k > st->block)
            k = st->block;
        if ((int64_t)k > st->share.hi[0] - st->row)
            k = (size_t)(st->share.hi[0] - st->row);
        orr_status s = read_rows(src, st, k, err);
        if (!s)
            s = decode_rows(src, st, c, k, err);
        if (s)
            return s;
        c->n += k;
        st->row += (int64_t)k;
    }
    return ORR_OK;
}

static orr_status npy_rewind(orr_source *src, orr_error *err)
{
    (void)err;
    npy_state *st = src->state;
    st->row = 0;
    return ORR_OK;
}

static void npy_close(orr_source *src)
{
    npy_state *st = src->state;
    if (!st)
        return;
    if (st->fp)
        fclose(st->fp);
    orr_share_free(&st->share);
    free(st->buf);
    free(st);
    src->state = NULL;
}

static const orr_source_ops npy_ops = {.next = npy_next, .rewind = npy_rewind, .close = npy_close};

/* The chunk, and a read buffer of whole rows (at most NPY_BUFFER_BYTES). */
static orr_status alloc_buffers(orr_source *src, npy_state *st, const orr_source_options *opt, orr_error *err)
{
    orr_status s = orr_source_alloc_chunk(src, opt, err);
    if (s)
        return s;
    size_t record = st->hdr.record ? st->hdr.record : 1;
    st->block = NPY_BUFFER_BYTES / record;
    if (st->block < 1)
        st->block = 1;
    if (st->block > src->chunk.capacity)
        st->block = src->chunk.capacity;
    st->buf = orr_malloc(st->block * record, ".npy read buffer", err);
    return st->buf ? ORR_OK : ORR_ERR_NOMEM;
}

orr_status orr_npy_source_open(const char *path, const orr_source_options *opt, orr_source **out, orr_error *err)
{
    orr_source *src;
    FILE *fp;
    orr_status s = orr_source_new_file("npy", path, &npy_ops, sizeof(npy_state), &src, &fp, err);
    if (s)
        return s;
    npy_state *st = src->state;
    st->fp = fp;
    s = read_header(src, st, err);
    if (!s)
        s = assign_roles(src, st, opt, err);
    if (!s) {
        orr_source_add_header(&src->info, "npy", "version %d, %s%s, %" PRId64 " rows of %zu bytes", st->hdr.version,
                              st->hdr.structured ? "structured" : "plain (N, 3)",
                              st->hdr.fortran ? " in Fortran order" : "", st->hdr.rows, st->hdr.record);
        s = orr_share_alloc(&st->share, 1, err);
    }
    if (!s) {
        /* Particles of unwanted types are read and left to the renderer's
         * selection, like a text table's. */
        st->share.hi[0] = st->hdr.rows;
        s = orr_share_divide(&st->share, 1, src, opt, err);
        st->row = st->share.lo[0];
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
