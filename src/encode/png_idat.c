/* A PNG's IDAT chunks deflated band by band in parallel (encode/png_idat.h). */
#include "encode/png_idat.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "core/srgb_code.h"

enum {
    BAND_BYTES = 1 << 20, /* filtered bytes in a band, about: large enough that the
                           * flushes and the priming cost little, small enough
                           * that two threads share even a small picture's bands */
    WINDOW = 32768,       /* deflate's window, what each band's stream is primed with */
    RUN = 4,              /* bands a thread takes in a row, the later ones primed by rows it has */
    WAVE = 64,            /* bands deflated before their chunks are written: bounds the memory
                           * (only the pages their deflated bytes touch are used), and
                           * few waves leave threads few barriers to wait at */
    LEVEL = 3,            /* zlib's RLE strategy (any level but 0 is the same) and the "up"
                           * filter: docs/output.md#png, docs/performance.md */
    FILTER_NONE = 0,
    FILTER_UP = 2,
};

/* The zlib header of a stream with a 32 KiB window made with the RLE
 * strategy (FLEVEL 0, "fastest", as zlib writes it for that strategy), its
 * check bits making it a multiple of 31 (RFC 1950). */
#define ZLIB_CMF 0x78
#define ZLIB_FLG (31 - (ZLIB_CMF << 8) % 31)

/* How the rows are cut: the same for any thread count. */
typedef struct layout {
    size_t row_bytes;  /* a filtered row: its filter byte, then its samples */
    int rows_per_band; /* the last band may have fewer */
    int nbands;
    int prime_rows;    /* rows before a band whose filtered bytes prime its stream */
    size_t slot_bytes; /* room for one band's deflated bytes, the zlib header and the checksum */
} layout;

static layout make_layout(const orr_png_rows *src)
{
    layout l;
    l.row_bytes = 1 + (size_t)src->width * (size_t)src->channels * (size_t)(src->bits / 8);
    size_t rows = BAND_BYTES / l.row_bytes;
    l.rows_per_band = rows < 1 ? 1 : rows > (size_t)src->height ? src->height : (int)rows;
    l.nbands = (src->height + l.rows_per_band - 1) / l.rows_per_band;
    l.prime_rows = (int)((WINDOW + l.row_bytes - 1) / l.row_bytes);
    /* compressBound: stored blocks at worst; then a sync flush's marker. */
    l.slot_bytes = 2 + compressBound((uLong)(l.row_bytes * (size_t)l.rows_per_band)) + 64 + 4;
    return l;
}

/* A row's codes as PNG samples: 16-bit ones big-endian, as PNG requires. */
static void pack_row(const uint16_t *codes, size_t n, int bits, unsigned char *out)
{
    if (bits == 8) {
        for (size_t i = 0; i < n; i++)
            out[i] = (unsigned char)codes[i];
        return;
    }
    for (size_t i = 0; i < n; i++) {
        out[2 * i] = (unsigned char)(codes[i] >> 8);
        out[2 * i + 1] = (unsigned char)(codes[i] & 0xff);
    }
}

/* One thread's tools: its deflate stream and scratch rows. */
typedef struct worker {
    z_stream z;
    int z_ready;
    unsigned char *filtered; /* the priming rows and the band's, filtered */
    unsigned char *samples[2]; /* a row's samples, and the row above's */
    uint16_t *codes;         /* a row's codes */
    float *scratch;          /* room for src->row */
    int done_from, done_to;  /* the rows in filtered, the last one's samples in samples[1] */
} worker;

static int worker_init(worker *w, const orr_png_rows *src, const layout *l)
{
    memset(w, 0, sizeof *w);
    size_t n = l->row_bytes - 1;
    w->filtered = malloc(l->row_bytes * (size_t)(l->prime_rows + l->rows_per_band));
    w->samples[0] = malloc(n);
    w->samples[1] = malloc(n);
    size_t values = (size_t)src->width * (size_t)src->channels;
    w->codes = malloc(values * sizeof *w->codes);
    w->scratch = src->pixels ? NULL : malloc(values * sizeof *w->scratch);
    w->done_from = w->done_to = -1;
    w->z_ready = deflateInit2(&w->z, LEVEL, Z_DEFLATED, -15, 8, Z_RLE) == Z_OK;
    return w->filtered && w->samples[0] && w->samples[1] && w->codes && (src->pixels || w->scratch) && w->z_ready;
}

static void worker_free(worker *w)
{
    if (w->z_ready)
        deflateEnd(&w->z);
    free(w->filtered);
    free(w->samples[0]);
    free(w->samples[1]);
    free(w->codes);
    free(w->scratch);
}

/* Row y's samples into out. */
static void row_samples(const orr_png_rows *src, worker *w, int y, unsigned char *out)
{
    size_t n = (size_t)src->width * (size_t)src->channels;
    if (src->pixels)
        orr_codes_of(src->pixels + (size_t)y * n, n, src->bits, w->codes);
    else
        src->row(src->ctx, y, w->scratch, w->codes);
    pack_row(w->codes, n, src->bits, out);
}

/* Filters rows [from, to) into out, each against the row above: the one in
 * w->samples[1] when have_above, else made here. */
static void filter_rows(const orr_png_rows *src, worker *w, const layout *l, int from, int to, unsigned char *out,
                        int have_above)
{
    size_t n = l->row_bytes - 1;
    if (from > 0 && !have_above)
        row_samples(src, w, from - 1, w->samples[1]);
    for (int y = from; y < to; y++, out += l->row_bytes) {
        unsigned char *cur = w->samples[0], *above = w->samples[1];
        row_samples(src, w, y, cur);
        out[0] = y == 0 ? FILTER_NONE : FILTER_UP;
        if (y == 0)
            memcpy(out + 1, cur, n);
        else
            for (size_t i = 0; i < n; i++)
                out[1 + i] = (unsigned char)(cur[i] - above[i]);
        w->samples[0] = above;
        w->samples[1] = cur;
    }
}

/* Rows [from, to) filtered into w->filtered. A thread given the band after
 * its last one (the bands are handed out a few in a row) moves that band's
 * last rows, which prime this one, to the front instead of grading them
 * again, and has their last row's samples for the row above. */
static void filter_band(const orr_png_rows *src, worker *w, const layout *l, int from, int y0, int to)
{
    int kept = 0;
    if (w->done_to == y0 && w->done_from <= from) {
        kept = y0 - from;
        memmove(w->filtered, w->filtered + (size_t)(from - w->done_from) * l->row_bytes,
                (size_t)kept * l->row_bytes);
    }
    filter_rows(src, w, l, from + kept, to, w->filtered + (size_t)kept * l->row_bytes, kept > 0);
    w->done_from = from;
    w->done_to = to;
}

/* A band's deflated bytes, and the checksum and length of its filtered
 * bytes, for the chunk writer. */
typedef struct band_out {
    unsigned char *slot; /* 2 bytes left for the zlib header, the deflated bytes, 4 for the checksum */
    size_t len;
    uLong adler;
    size_t raw_len;
} band_out;

/* Filters and deflates band b into *out; 0 when zlib fails. */
static int deflate_band(const orr_png_rows *src, worker *w, const layout *l, int b, band_out *out)
{
    int y0 = b * l->rows_per_band, y1 = y0 + l->rows_per_band;
    if (y1 > src->height)
        y1 = src->height;
    int from = y0 > l->prime_rows ? y0 - l->prime_rows : 0;
    filter_band(src, w, l, from, y0, y1);
    size_t before = (size_t)(y0 - from) * l->row_bytes, prime = before > WINDOW ? WINDOW : before;
    unsigned char *data = w->filtered + before;
    out->raw_len = (size_t)(y1 - y0) * l->row_bytes;
    out->adler = adler32(adler32(0L, Z_NULL, 0), data, (uInt)out->raw_len);
    int last = b == l->nbands - 1;
    z_stream *z = &w->z;
    if (deflateReset(z) != Z_OK || (prime && deflateSetDictionary(z, data - prime, (uInt)prime) != Z_OK))
        return 0;
    size_t room = l->slot_bytes - 2 - 4;
    z->next_in = data;
    z->avail_in = (uInt)out->raw_len;
    z->next_out = out->slot + 2;
    z->avail_out = (uInt)room;
    int rc = deflate(z, last ? Z_FINISH : Z_SYNC_FLUSH);
    if (last ? rc != Z_STREAM_END : (rc != Z_OK || z->avail_in != 0 || z->avail_out == 0))
        return 0;
    out->len = room - z->avail_out;
    return 1;
}

static void put_u32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)(v >> 24);
    p[1] = (unsigned char)(v >> 16);
    p[2] = (unsigned char)(v >> 8);
    p[3] = (unsigned char)v;
}

int orr_png_write_chunk(FILE *fp, const char type[4], const unsigned char *data, size_t len)
{
    unsigned char head[8], tail[4];
    put_u32(head, (uint32_t)len);
    memcpy(head + 4, type, 4);
    uLong crc = crc32(crc32(0L, Z_NULL, 0), head + 4, 4);
    if (len)
        crc = crc32(crc, data, (uInt)len);
    put_u32(tail, (uint32_t)crc);
    return fwrite(head, 1, 8, fp) == 8 && (!len || fwrite(data, 1, len, fp) == len) && fwrite(tail, 1, 4, fp) == 4;
}

/* Writes bands [first, first + n) as IDAT chunks, the first with the zlib
 * header, the last with the checksum of the whole; *adler runs over them. */
static int write_bands(FILE *fp, const layout *l, int first, int n, band_out *bands, uLong *adler)
{
    for (int k = 0; k < n; k++) {
        band_out *o = &bands[k];
        int b = first + k;
        *adler = adler32_combine(*adler, o->adler, (z_off_t)o->raw_len);
        unsigned char *start = o->slot + 2, *end = o->slot + 2 + o->len;
        if (b == 0) {
            start -= 2;
            start[0] = ZLIB_CMF;
            start[1] = ZLIB_FLG;
        }
        if (b == l->nbands - 1) {
            put_u32(end, (uint32_t)*adler);
            end += 4;
        }
        if (!orr_png_write_chunk(fp, "IDAT", start, (size_t)(end - start)))
            return 0;
    }
    return 1;
}

enum { OK = 0, NOMEM, ZLIB, WRITE };

orr_status orr_png_write_idat(FILE *fp, const orr_png_rows *src, const char *path, orr_error *err)
{
    layout l = make_layout(src);
    unsigned char *slots = malloc(WAVE * l.slot_bytes);
    if (!slots)
        return orr_fail(err, ORR_ERR_NOMEM, "%s: out of memory for the PNG's compressed bands", path);
    band_out bands[WAVE];
    for (int k = 0; k < WAVE; k++)
        bands[k].slot = slots + (size_t)k * l.slot_bytes;
    uLong adler = adler32(0L, Z_NULL, 0);
    int failed = OK;
#pragma omp parallel
    {
        worker w;
        if (!worker_init(&w, src, &l)) {
#pragma omp atomic write
            failed = NOMEM;
        }
        /* Every thread walks the waves alike; the barriers at the end of
         * the for and the single keep them in step, and make `failed`
         * the same for all when it is read. */
#pragma omp barrier
        for (int first = 0; first < l.nbands && failed == OK; first += WAVE) {
            int n = l.nbands - first < WAVE ? l.nbands - first : WAVE;
#pragma omp for schedule(dynamic, RUN)
            for (int k = 0; k < n; k++)
                if (!deflate_band(src, &w, &l, first + k, &bands[k])) {
#pragma omp atomic write
                    failed = ZLIB;
                }
#pragma omp single
            if (failed == OK && !write_bands(fp, &l, first, n, bands, &adler))
                failed = WRITE;
        }
        worker_free(&w);
    }
    free(slots);
    switch (failed) {
    case NOMEM:
        return orr_fail(err, ORR_ERR_NOMEM, "%s: out of memory for the PNG encoder", path);
    case ZLIB:
        return orr_fail(err, ORR_ERR_IO, "%s: zlib could not deflate the PNG's rows", path);
    case WRITE:
        return orr_fail(err, ORR_ERR_IO, "%s: cannot write PNG file", path);
    }
    return ORR_OK;
}
