/* A PNG's image data (its IDAT chunks) deflated in parallel: pigz's method.
 *
 * The rows are cut into bands whose size depends only on the image's size
 * (about 1 MiB of filtered bytes each, never on the thread count), each
 * band deflated by its own raw deflate stream primed with the 32 KiB of
 * filtered bytes before it (so the bands compress almost as one stream
 * would), ended with Z_SYNC_FLUSH (the last with Z_FINISH), the checksum
 * of the whole made from the bands' with adler32_combine. The file's bytes
 * are therefore the same on any number of threads. Every row uses the "up"
 * filter (the first, which has no row above, none) and zlib's run-length
 * strategy (Z_RLE: matches at distance 1 only), half level 3's CPU for
 * files within a few per cent of its size (docs/output.md#png). */
#ifndef ORR_ENCODE_PNG_IDAT_H
#define ORR_ENCODE_PNG_IDAT_H

#include <stdint.h>
#include <stdio.h>

#include "core/error.h"

/* Where the rows come from: the whole picture's values in memory, in
 * [0, 1] (clipped; NaN is 0) and rounded to codes by orr_code_of
 * (core/srgb_code.h); or a function that makes one row's codes on demand,
 * width * channels values in [0, 2^bits - 1] (called from several threads
 * at once, each row possibly more than once; scratch is room for width *
 * channels floats), so a picture need never be held whole. */
typedef void (*orr_png_row_fn)(void *ctx, int y, float *scratch, uint16_t *codes);

typedef struct orr_png_rows {
    int width, height, channels, bits; /* channels 3 or 4, bits 8 or 16 */
    const float *pixels;               /* width * height * channels values, row 0 at the top; or NULL */
    orr_png_row_fn row;                /* when pixels is NULL */
    void *ctx;
} orr_png_rows;

/* Writes the picture's zlib stream to fp as IDAT chunks (one per band).
 * ORR_ERR_NOMEM, or ORR_ERR_IO naming path when zlib or the write fails. */
orr_status orr_png_write_idat(FILE *fp, const orr_png_rows *src, const char *path, orr_error *err);

/* Writes one PNG chunk (length, type, data, CRC) to fp; 0 on a short write. */
int orr_png_write_chunk(FILE *fp, const char type[4], const unsigned char *data, size_t len);

#endif
