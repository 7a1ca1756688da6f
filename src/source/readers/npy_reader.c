/* The .npy reader (npy_reader.h); the header is npy_header.c's. */
#include "source/readers/npy_reader.h"

#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>

#include "source/readers/npy_header.h"
#include "source/readers/npy_values.h"
#include "source/readers/share.h"

#define NPY_BUFFER_BYTES ((size_t)4 << 20) /* rows read per fread: at most this many bytes */

typedef struct npy_state {
    FILE *fp;
    npy_header hdr;
    int role[NPY_MAX_COLUMNS];  /* NPY_R_*, and for NPY_R_EXTRA the chunk's extra index in slot[] */
    int slot[NPY_MAX_COLUMNS];
    orr_share share;            /* one run: the rows this process reads */
    int64_t row;                /* next row */
    unsigned char *buf;
    size_t block;               /* rows per read */
    const unsigned char *map;   /* the whole file mapped (orr_npy_set_mapping), or NULL: read into buf */
    size_t map_size;
} npy_state;

static int use_mapping = NPY_MAP_DEFAULT;

void orr_npy_set_mapping(int on) { use_mapping = on; }

int orr_npy_probe(const unsigned char *head, size_t n) { return npy_has_magic(head, n); }

/* Gives every column its role (npy_values.h). */
static orr_status assign_roles(orr_source *src, npy_state *st, const orr_source_options *opt, orr_error *err)
{
    return npy_assign_roles(src->info.path, "field", "fields x, y, z", st->hdr.col, st->hdr.ncolumns, st->role,
                            st->slot, &src->info, opt, err);
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
    if (st->map)
        return ORR_OK; /* decoded where they are */
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

/* Where column j of the k rows from st->row is: in the buffer just read,
 * or in the mapped file. Its next row is column_stride bytes further. */
static const unsigned char *column_base(const npy_state *st, size_t k, int j)
{
    const npy_header *h = &st->hdr;
    size_t size = (size_t)h->col[j].size;
    if (st->map && h->fortran)
        return st->map + h->data_offset + ((size_t)j * (size_t)h->rows + (size_t)st->row) * size;
    if (st->map)
        return st->map + h->data_offset + (size_t)st->row * h->record + h->col[j].offset;
    if (h->fortran)
        return st->buf + (size_t)j * k * size;
    return st->buf + h->col[j].offset;
}

static size_t column_stride(const npy_state *st, int j)
{
    return st->hdr.fortran ? (size_t)st->hdr.col[j].size : st->hdr.record;
}

/* Decodes the k rows just read into the chunk from c->n on, column by
 * column. */
static orr_status decode_rows(orr_source *src, npy_state *st, orr_chunk *c, size_t k, orr_error *err)
{
    const npy_header *h = &st->hdr;
    int has_mass = 0;
    for (int j = 0; j < h->ncolumns; j++)
        has_mass |= st->role[j] == NPY_R_MASS;
    npy_defaults(&src->info, has_mass, c, c->n, k, st->row);
    orr_status s = ORR_OK;
    for (int j = 0; j < h->ncolumns && !s; j++) {
        float *out = npy_float_target(st->role[j], st->slot[j], c);
        const unsigned char *base = column_base(st, k, j);
        size_t stride = column_stride(st, j);
        size_t done = npy_copy_native_floats(&h->col[j], st->role[j], base, stride, k, out ? out + c->n : NULL);
        for (size_t i = done; i < k && !s; i++)
            s = npy_store(src->info.path, &h->col[j], st->role[j], st->slot[j], c, c->n + i, base + i * stride,
                          st->row + (int64_t)i, err);
    }
    return s;
}

static orr_status npy_block(orr_source *src, size_t k, orr_error *err)
{
    orr_status s = read_rows(src, src->state, k, err);
    return s ? s : decode_rows(src, src->state, &src->chunk, k, err);
}

static orr_status npy_next(orr_source *src, orr_error *err)
{
    npy_state *st = src->state;
    return npy_fill_chunk(src, &st->share, st->block, &st->row, npy_block, err);
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
    if (st->map)
        munmap((void *)st->map, st->map_size);
    orr_share_free(&st->share);
    free(st->buf);
    free(st);
    src->state = NULL;
}

static const orr_source_ops npy_ops = {.next = npy_next, .rewind = npy_rewind, .close = npy_close};

/* Maps the whole file when asked to; on any failure the rows are read
 * into the buffer instead. The size was checked against the header. */
static void map_file(npy_state *st)
{
    int64_t size = st->hdr.data_offset + st->hdr.rows * (int64_t)st->hdr.record;
    if (!use_mapping || st->hdr.rows == 0 || (uint64_t)size > SIZE_MAX)
        return;
    void *p = mmap(NULL, (size_t)size, PROT_READ, MAP_PRIVATE, fileno(st->fp), 0);
    if (p == MAP_FAILED)
        return;
    posix_madvise(p, (size_t)size, POSIX_MADV_SEQUENTIAL);
    st->map = p;
    st->map_size = (size_t)size;
}

/* The chunk, and a read buffer of whole rows (at most NPY_BUFFER_BYTES;
 * none for a mapped file). */
static orr_status alloc_buffers(orr_source *src, npy_state *st, const orr_source_options *opt, orr_error *err)
{
    orr_status s = orr_source_alloc_chunk(src, opt, err);
    if (s)
        return s;
    map_file(st);
    size_t record = st->hdr.record ? st->hdr.record : 1;
    st->block = NPY_BUFFER_BYTES / record;
    if (st->block < 1)
        st->block = 1;
    if (st->block > src->chunk.capacity)
        st->block = src->chunk.capacity;
    if (st->map)
        return ORR_OK;
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
