/* The .npz reader (npz_reader.h): each member an .npy array (npy_header.c)
 * inside a ZIP archive (zip_archive.c), decoded by npy_values.c. */
#include "source/readers/npz_reader.h"

#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "source/readers/npy_header.h"
#include "source/readers/npy_values.h"
#include "source/readers/share.h"
#include "source/readers/zip_archive.h"

#define NPZ_BUFFER_BYTES ((size_t)4 << 20) /* rows read per pass over the members: at most this many bytes */

/* One front-to-back read of rows: a C-order member's whole records, or
 * one column of a Fortran-order (N, k) member. */
typedef struct npz_run {
    orr_zip_reader zr;
    uint64_t start; /* the member's uncompressed offset of row 0 */
    size_t width;   /* bytes a row */
    unsigned char *buf;
} npz_run;

/* Where a member's rows are. */
typedef struct npz_layout {
    int fortran;         /* (N, k) stored column after column */
    int64_t data_offset; /* of row 0 in the member */
    size_t record;       /* bytes a row */
} npz_layout;

typedef struct npz_state {
    FILE *fp;
    orr_zip_member *members;
    int nmembers;
    int ncolumns;
    npy_column col[NPY_MAX_COLUMNS]; /* named as the renderer sees them: x, mass, vel[2], ... */
    int col_member[NPY_MAX_COLUMNS];
    int col_index[NPY_MAX_COLUMNS]; /* its column within the member */
    int role[NPY_MAX_COLUMNS], slot[NPY_MAX_COLUMNS];
    int col_run[NPY_MAX_COLUMNS];   /* -1: not read */
    npz_layout layout[NPY_MAX_COLUMNS]; /* of each column's member */
    int nruns;
    npz_run run[NPY_MAX_COLUMNS];
    int64_t rows;
    int rows_from;                  /* the column whose member set rows */
    orr_share share;
    int64_t row;
    size_t block;
} npz_state;

int orr_npz_probe(const unsigned char *head, size_t n) { return orr_zip_probe(head, n); }

/* Keys numpy gives (N, 3) positions under; their columns are x, y, z. */
static int is_positions_key(const char *key)
{
    static const char *const keys[] = {"pos", "position", "positions", "coordinates", "Coordinates", "xyz"};
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++)
        if (strcmp(key, keys[i]) == 0)
            return 1;
    return 0;
}

/* Reads an .npy member's preamble and header into h (any shape) and checks
 * its size against the shape. */
static orr_status read_member_header(const char *path, int fd, const orr_zip_member *m, npy_header *h,
                                     orr_error *err)
{
    orr_zip_reader zr;
    memset(h, 0, sizeof *h);
    orr_status s = orr_zip_reader_open(&zr, fd, path, m, err);
    unsigned char head[NPY_PREAMBLE_V2];
    size_t n = m->usize < sizeof head ? (size_t)m->usize : sizeof head;
    char why[512] = "";
    char *text = NULL;
    if (!s)
        s = orr_zip_read(&zr, head, n, err);
    if (!s && !npy_parse_preamble(head, n, h, why, sizeof why))
        s = orr_fail(err, ORR_ERR_FORMAT, "%s: not a readable .npy array: %s", zr.what, why);
    if (!s && h->data_offset > (int64_t)m->usize)
        s = orr_fail(err, ORR_ERR_FORMAT, "%s: it ends inside its %zu-byte .npy header", zr.what, h->header_len);
    if (!s && !(text = orr_malloc(h->header_len + 1, ".npy header", err)))
        s = ORR_ERR_NOMEM;
    if (!s)
        s = orr_zip_seek(&zr, (uint64_t)(h->data_offset - (int64_t)h->header_len), err);
    if (!s)
        s = orr_zip_read(&zr, text, h->header_len, err);
    h->any_shape = 1;
    if (!s && !npy_parse_dict(text, h->header_len, h, why, sizeof why))
        s = orr_fail(err, ORR_ERR_FORMAT, "%s: %s", zr.what, why);
    free(text);
    /* The parser bounds rows * record (no overflow) once it has succeeded. */
    int64_t want = s ? 0 : h->data_offset + h->rows * (int64_t)h->record;
    if (!s && (uint64_t)want != m->usize)
        s = orr_fail(err, ORR_ERR_FORMAT, "%s: its shape needs %" PRId64 " bytes but it has %" PRIu64, zr.what, want,
                     m->usize);
    orr_zip_reader_close(&zr);
    return s;
}

/* The member's key: its name without ".npy"; 0 when it is not an array. */
static int member_key(const orr_zip_member *m, char *key, size_t size)
{
    size_t len = strlen(m->name);
    if (len < 5 || strcmp(m->name + len - 4, ".npy") != 0)
        return 0;
    snprintf(key, size, "%.*s", (int)(len - 4), m->name);
    return 1;
}

/* Names one column of a member: a 1-D array's key, a structured array's
 * field, x/y/z for positions, else KEY[i]. */
static orr_status name_column(const char *what, const char *key, const npy_header *h, int i, npy_column *col,
                              orr_error *err)
{
    int uses_key = !h->structured && !(h->ndim == 2 && h->ncolumns == 3 && is_positions_key(key));
    if (uses_key && strlen(key) >= ORR_FIELD_NAME_MAX - (h->ndim == 2 ? 4 : 0))
        return orr_fail(err, ORR_ERR_FORMAT, "%s: the key '%s' is too long for a column name (at most %d "
                        "characters)", what, key, ORR_FIELD_NAME_MAX - 1 - (h->ndim == 2 ? 4 : 0));
    char name[ORR_FIELD_NAME_MAX + 16];
    if (h->structured)
        snprintf(name, sizeof name, "%.*s", ORR_FIELD_NAME_MAX, h->col[i].name);
    else if (!uses_key)
        snprintf(name, sizeof name, "%c", "xyz"[i]);
    else if (h->ndim == 1)
        snprintf(name, sizeof name, "%.*s", ORR_FIELD_NAME_MAX, key);
    else
        snprintf(name, sizeof name, "%.*s[%d]", ORR_FIELD_NAME_MAX, key, i);
    if (strlen(name) >= ORR_FIELD_NAME_MAX)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: column name '%s' is longer than %d characters", what, name,
                        ORR_FIELD_NAME_MAX - 1);
    memcpy(col->name, name, strlen(name) + 1); /* fits: checked above */
    return ORR_OK;
}

/* A scalar member (a time, a box size) is shown by `orrery info`; one
 * called time is the snapshot's time. */
static orr_status note_scalar(orr_source *src, npz_state *st, const orr_zip_member *m, const char *key,
                              const npy_header *h, orr_error *err)
{
    orr_zip_reader zr;
    unsigned char v[8];
    if (h->structured || h->record > sizeof v)
        return ORR_OK;
    orr_status s = orr_zip_reader_open(&zr, fileno(st->fp), src->info.path, m, err);
    if (!s)
        s = orr_zip_seek(&zr, (uint64_t)h->data_offset, err);
    if (!s)
        s = orr_zip_read(&zr, v, h->record, err);
    orr_zip_reader_close(&zr);
    if (s)
        return s;
    double value = npy_value(&h->col[0], v);
    orr_source_add_header(&src->info, key, "%.17g", value);
    if (strcmp(key, "time") == 0 && value == value && value - value == 0)
        src->info.time = value;
    return ORR_OK;
}

/* Adds one member's columns, after checking its rows agree with the
 * others'. */
static orr_status add_member(orr_source *src, npz_state *st, int k, const char *key, const npy_header *h,
                             orr_error *err)
{
    char what[ORR_PATH_MAX + ORR_ZIP_NAME_MAX + 16];
    snprintf(what, sizeof what, "%s: member '%s'", src->info.path, st->members[k].name);
    if (st->ncolumns > 0 && h->rows != st->rows)
        return orr_fail(err, ORR_ERR_FORMAT, "%s has %" PRId64 " rows but member '%s' has %" PRId64 ": every array "
                        "must have one row per particle", what, h->rows,
                        st->members[st->col_member[st->rows_from]].name, st->rows);
    if (st->ncolumns + h->ncolumns > NPY_MAX_COLUMNS)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: more than %d columns in the archive", what, NPY_MAX_COLUMNS);
    if (st->ncolumns == 0) {
        st->rows = h->rows;
        st->rows_from = 0;
    }
    for (int i = 0; i < h->ncolumns; i++) {
        int j = st->ncolumns++;
        st->col[j] = h->col[i];
        st->col_member[j] = k;
        st->col_index[j] = i;
        st->layout[j] = (npz_layout){.fortran = h->fortran, .data_offset = h->data_offset, .record = h->record};
        orr_status s = name_column(what, key, h, i, &st->col[j], err);
        if (s)
            return s;
    }
    return ORR_OK;
}

/* Every .npy member: arrays become columns, scalars header entries. */
static orr_status read_members(orr_source *src, npz_state *st, orr_error *err)
{
    int fd = fileno(st->fp);
    orr_status s = orr_zip_read_directory(fd, src->info.path, &st->members, &st->nmembers, err);
    for (int k = 0; !s && k < st->nmembers; k++) {
        char key[ORR_ZIP_NAME_MAX];
        if (!member_key(&st->members[k], key, sizeof key))
            continue; /* not an array: numpy writes none, other tools may */
        npy_header h;
        s = read_member_header(src->info.path, fd, &st->members[k], &h, err);
        if (!s)
            s = h.ndim == 0 ? note_scalar(src, st, &st->members[k], key, &h, err) : add_member(src, st, k, key, &h, err);
    }
    if (!s && st->ncolumns == 0)
        s = orr_fail(err, ORR_ERR_FORMAT, "%s: no arrays in the archive (an .npz of particles holds pos (N, 3) or x, "
                     "y, z)", src->info.path);
    return s;
}

/* A run for each member (or Fortran-order column) holding a column that
 * is read; members of skipped columns are never read. */
static orr_status plan_runs(orr_source *src, npz_state *st, orr_error *err)
{
    int member_of_run[NPY_MAX_COLUMNS];
    for (int j = 0; j < st->ncolumns; j++) {
        st->col_run[j] = -1;
        if (st->role[j] == NPY_R_SKIP)
            continue;
        const npz_layout *h = &st->layout[j];
        int shared = -1;
        for (int r = 0; r < st->nruns && !h->fortran; r++)
            if (member_of_run[r] == st->col_member[j])
                shared = r;
        if (shared >= 0) {
            st->col_run[j] = shared;
            continue;
        }
        npz_run *run = &st->run[st->nruns];
        size_t size = (size_t)st->col[j].size;
        run->width = h->fortran ? size : h->record;
        run->start = (uint64_t)h->data_offset +
                     (h->fortran ? (uint64_t)st->col_index[j] * (uint64_t)st->rows * (uint64_t)size : 0);
        if (h->fortran)
            st->col[j].offset = 0;
        member_of_run[st->nruns] = st->col_member[j];
        st->col_run[j] = st->nruns++;
        orr_status s = orr_zip_reader_open(&run->zr, fileno(st->fp), src->info.path, &st->members[st->col_member[j]],
                                           err);
        if (s)
            return s;
    }
    return ORR_OK;
}

/* Read buffers for a block of rows of every run (at most NPZ_BUFFER_BYTES
 * together). */
static orr_status alloc_buffers(orr_source *src, npz_state *st, const orr_source_options *opt, orr_error *err)
{
    orr_status s = orr_source_alloc_chunk(src, opt, err);
    size_t width = 0;
    for (int r = 0; r < st->nruns; r++)
        width += st->run[r].width;
    st->block = NPZ_BUFFER_BYTES / (width ? width : 1);
    if (st->block < 1)
        st->block = 1;
    if (st->block > src->chunk.capacity)
        st->block = src->chunk.capacity;
    for (int r = 0; !s && r < st->nruns; r++)
        if (!(st->run[r].buf = orr_malloc(st->block * st->run[r].width + 1, ".npz read buffer", err)))
            s = ORR_ERR_NOMEM;
    return s;
}

/* Reads k rows from st->row of every run, then decodes them column by
 * column into the chunk from c->n on. */
static orr_status read_block(orr_source *src, npz_state *st, orr_chunk *c, size_t k, orr_error *err)
{
    orr_status s = ORR_OK;
    for (int r = 0; r < st->nruns && !s; r++) {
        npz_run *run = &st->run[r];
        s = orr_zip_seek(&run->zr, run->start + (uint64_t)st->row * run->width, err);
        if (!s)
            s = orr_zip_read(&run->zr, run->buf, k * run->width, err);
    }
    int has_mass = 0;
    for (int j = 0; j < st->ncolumns; j++)
        has_mass |= st->role[j] == NPY_R_MASS;
    if (!s)
        npy_defaults(&src->info, has_mass, c, c->n, k, st->row);
    for (int j = 0; j < st->ncolumns && !s; j++) {
        if (st->col_run[j] < 0)
            continue;
        const npz_run *run = &st->run[st->col_run[j]];
        const unsigned char *base = run->buf + st->col[j].offset;
        float *out = npy_float_target(st->role[j], st->slot[j], c);
        size_t done = npy_copy_native_floats(&st->col[j], st->role[j], base, run->width, k, out ? out + c->n : NULL);
        for (size_t i = done; i < k && !s; i++)
            s = npy_store(run->zr.what, &st->col[j], st->role[j], st->slot[j], c, c->n + i, base + i * run->width,
                          st->row + (int64_t)i, err);
    }
    return s;
}

static orr_status npz_block(orr_source *src, size_t k, orr_error *err)
{
    return read_block(src, src->state, &src->chunk, k, err);
}

static orr_status npz_next(orr_source *src, orr_error *err)
{
    npz_state *st = src->state;
    return npy_fill_chunk(src, &st->share, st->block, &st->row, npz_block, err);
}

static orr_status npz_rewind(orr_source *src, orr_error *err)
{
    (void)err;
    npz_state *st = src->state;
    st->row = 0; /* the next read seeks each member back */
    return ORR_OK;
}

static void npz_close(orr_source *src)
{
    npz_state *st = src->state;
    if (!st)
        return;
    for (int r = 0; r < st->nruns; r++) {
        orr_zip_reader_close(&st->run[r].zr);
        free(st->run[r].buf);
    }
    if (st->fp)
        fclose(st->fp);
    orr_share_free(&st->share);
    free(st->members);
    free(st);
    src->state = NULL;
}

static const orr_source_ops npz_ops = {.next = npz_next, .rewind = npz_rewind, .close = npz_close};

orr_status orr_npz_source_open(const char *path, const orr_source_options *opt, orr_source **out, orr_error *err)
{
    orr_source *src;
    FILE *fp;
    orr_status s = orr_source_new_file("npz", path, &npz_ops, sizeof(npz_state), &src, &fp, err);
    if (s)
        return s;
    npz_state *st = src->state;
    st->fp = fp;
    s = read_members(src, st, err);
    if (!s)
        s = npy_assign_roles(path, "member", "a member pos of shape (N, 3), or members x, y, z", st->col,
                             st->ncolumns, st->role, st->slot, &src->info, opt, err);
    if (!s) {
        orr_source_add_header(&src->info, "npz", "%d members, %d columns, %" PRId64 " rows", st->nmembers,
                              st->ncolumns, st->rows);
        s = plan_runs(src, st, err);
    }
    if (!s)
        s = orr_share_alloc(&st->share, 1, err);
    if (!s) {
        st->share.hi[0] = st->rows;
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
