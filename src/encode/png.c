#include "encode/png.h"

#include <errno.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/atomic.h"

#define PNG_KEY_MAX 79 /* the PNG specification's limit on tEXt keywords */

/* libpng reports errors through a callback that must not return; it keeps
 * the text here and jumps back to the setjmp in encode(). */
typedef struct png_failure {
    char msg[256];
} png_failure;

static void on_png_error(png_structp png, png_const_charp msg)
{
    png_failure *f = png_get_error_ptr(png);
    snprintf(f->msg, sizeof f->msg, "%s", msg);
    png_longjmp(png, 1);
}

/* The library never prints: libpng's warnings (none expected for what we
 * write) are dropped. */
static void on_png_warning(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg;
}

/* Clips to [0, 1] (NaN to 0) and rounds to the nearest code value; in
 * double so that 16-bit codes round exactly as the formula says. */
static unsigned quantize(float v, unsigned max)
{
    if (!(v > 0))
        return 0;
    if (v >= 1)
        return max;
    return (unsigned)((double)v * max + 0.5);
}

static void fill_row(const float *rgb, int width, int channels, int bits, png_bytep row)
{
    size_t n = (size_t)width * (size_t)channels;
    if (bits == 8) {
        for (size_t i = 0; i < n; i++)
            row[i] = (png_byte)quantize(rgb[i], 255);
        return;
    }
    for (size_t i = 0; i < n; i++) { /* PNG stores 16-bit samples big-endian */
        unsigned q = quantize(rgb[i], 65535);
        row[2 * i] = (png_byte)(q >> 8);
        row[2 * i + 1] = (png_byte)(q & 0xff);
    }
}

/* Everything libpng does happens in here, between one setjmp and the
 * destruction of the write structures. Every local used after a longjmp is
 * set before the setjmp and never changed afterwards, so none needs to be
 * volatile. */
static int encode(FILE *fp, int width, int height, const float *rgb, int channels, int bits, png_textp texts,
                  int ntext, png_bytep row, png_failure *fail)
{
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, fail, on_png_error, on_png_warning);
    if (!png) {
        snprintf(fail->msg, sizeof fail->msg, "libpng could not be initialised");
        return 0;
    }
    png_infop info = png_create_info_struct(png);
    if (!info) {
        png_destroy_write_struct(&png, NULL);
        snprintf(fail->msg, sizeof fail->msg, "libpng could not be initialised");
        return 0;
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return 0;
    }
    png_init_io(png, fp);
    png_set_IHDR(png, info, (png_uint_32)width, (png_uint_32)height, bits,
                 channels == 4 ? PNG_COLOR_TYPE_RGB_ALPHA : PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    /* The values are sRGB-encoded already: say so, for colour-managed viewers. */
    png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
    if (ntext > 0)
        png_set_text(png, info, texts, ntext);
    /* zlib level 3 and the "up" filter alone, not libpng's defaults (level
     * 6, every filter tried on every row): on Future Sky's 3600^2 dome
     * master 0.55 s of CPU instead of 1.95 s, for a file 9 % larger (8.7 MB,
     * not 8.0; bench/bench_png, docs/performance.md). A dome sequence writes
     * tens of thousands of these, and a video encoder reads them once. */
    png_set_compression_level(png, 3);
    png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_UP);
    png_write_info(png, info);
    for (int y = 0; y < height; y++) {
        fill_row(rgb + (size_t)y * (size_t)width * (size_t)channels, width, channels, bits, row);
        png_write_row(png, row);
    }
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    return 1;
}

static orr_status check_args(const char *path, int width, int height, const float *rgb, int channels, int bits,
                             const orr_png_text *text, int ntext, orr_error *err)
{
    if (!path || !path[0])
        return orr_fail(err, ORR_ERR_USAGE, "PNG output: no file name given");
    if (channels != 3 && channels != 4)
        return orr_fail(err, ORR_ERR_USAGE, "%s: PNG channels must be 3 (RGB) or 4 (RGBA), not %d", path, channels);
    if (bits != 8 && bits != 16)
        return orr_fail(err, ORR_ERR_USAGE, "%s: PNG bit depth must be 8 or 16, not %d", path, bits);
    if (width <= 0 || height <= 0 || !rgb)
        return orr_fail(err, ORR_ERR_USAGE, "%s: empty image (%d x %d)", path, width, height);
    if (ntext < 0 || (ntext > 0 && !text))
        return orr_fail(err, ORR_ERR_USAGE, "%s: bad text chunk list", path);
    for (int i = 0; i < ntext; i++) {
        size_t len = text[i].key ? strlen(text[i].key) : 0;
        if (len == 0 || len > PNG_KEY_MAX || !text[i].value)
            return orr_fail(err, ORR_ERR_USAGE, "%s: PNG text key %d must be 1 to %d characters with a value",
                            path, i + 1, PNG_KEY_MAX);
    }
    return ORR_OK;
}

/* libpng copies the texts; the casts only drop const for its old API. */
static png_textp make_texts(const orr_png_text *text, int ntext, orr_error *err)
{
    png_textp t = orr_calloc(ntext > 0 ? (size_t)ntext : 1, sizeof *t, "PNG text chunks", err);
    for (int i = 0; t && i < ntext; i++) {
        t[i].compression = PNG_TEXT_COMPRESSION_NONE; /* tEXt */
        t[i].key = (png_charp)text[i].key;
        t[i].text = (png_charp)text[i].value;
        t[i].text_length = strlen(text[i].value);
    }
    return t;
}

/* Encodes into the temporary file that orr_atomic_begin created. */
static orr_status write_temp(const char *temp_path, const char *path, int width, int height, const float *rgb,
                             int channels, int bits, png_textp texts, int ntext, orr_error *err)
{
    png_bytep row = orr_malloc((size_t)width * (size_t)channels * (size_t)(bits / 8), "PNG row", err);
    if (!row)
        return ORR_ERR_NOMEM;
    FILE *fp = fopen(temp_path, "wb");
    if (!fp) {
        int e = errno;
        free(row);
        return orr_fail(err, ORR_ERR_IO, "%s: cannot open %s: %s", path, temp_path, strerror(e));
    }
    png_failure fail = {""};
    int ok = encode(fp, width, height, rgb, channels, bits, texts, ntext, row, &fail);
    free(row);
    /* Write errors can surface only when the buffer is flushed at close. */
    int write_error = ferror(fp);
    int e = errno;
    if (fclose(fp) != 0) {
        write_error = 1;
        e = errno;
    }
    if (!ok)
        return orr_fail(err, ORR_ERR_IO, "%s: cannot write PNG file: %s%s%s", path, fail.msg,
                        write_error ? ": " : "", write_error ? strerror(e) : "");
    if (write_error)
        return orr_fail(err, ORR_ERR_IO, "%s: cannot write PNG file: %s", path, strerror(e));
    return ORR_OK;
}

orr_status orr_write_png(const char *path, int width, int height, const float *pixels, int channels, int bits,
                        const orr_png_text *text, int ntext, orr_error *err)
{
    orr_status st = check_args(path, width, height, pixels, channels, bits, text, ntext, err);
    if (st != ORR_OK)
        return st;
    png_textp texts = make_texts(text, ntext, err);
    if (!texts)
        return ORR_ERR_NOMEM;
    orr_atomic_file af;
    st = orr_atomic_begin(&af, path, err);
    if (st == ORR_OK) {
        st = write_temp(af.temp_path, path, width, height, pixels, channels, bits, texts, ntext, err);
        if (st == ORR_OK)
            st = orr_atomic_commit(&af, err);
        else
            orr_atomic_abort(&af);
    }
    free(texts);
    return st;
}

orr_status orr_write_png_rgb(const char *path, int width, int height, const float *rgb, int bits,
                             const orr_png_text *text, int ntext, orr_error *err)
{
    return orr_write_png(path, width, height, rgb, 3, bits, text, ntext, err);
}
