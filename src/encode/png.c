#include "encode/png.h"

#include <errno.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/atomic.h"
#include "encode/png_idat.h"

#define PNG_KEY_MAX 79 /* the PNG specification's limit on tEXt keywords */

/* libpng reports errors through a callback that must not return; it keeps
 * the text here and jumps back to the setjmp in write_header(). */
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

/* libpng writes the signature and the chunks before the image data
 * (IHDR, sRGB, gAMA, cHRM, tEXt), between one setjmp and the destruction
 * of its write structures; the image data and IEND are ours
 * (encode/png_idat.h). Every local used after a longjmp is set before the
 * setjmp and never changed afterwards, so none needs to be volatile. */
static int write_header(FILE *fp, const orr_png_rows *src, png_textp texts, int ntext, png_failure *fail)
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
    png_set_IHDR(png, info, (png_uint_32)src->width, (png_uint_32)src->height, src->bits,
                 src->channels == 4 ? PNG_COLOR_TYPE_RGB_ALPHA : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    /* The values are sRGB-encoded already: say so, for colour-managed viewers. */
    png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
    if (ntext > 0)
        png_set_text(png, info, texts, ntext);
    png_write_info(png, info); /* writes the tEXt chunks too: they are all set by now */
    png_destroy_write_struct(&png, &info);
    return 1;
}

static orr_status check_args(const char *path, const orr_png_rows *src, const orr_png_text *text, int ntext,
                             orr_error *err)
{
    int width = src->width, height = src->height, channels = src->channels, bits = src->bits;
    if (!path || !path[0])
        return orr_fail(err, ORR_ERR_USAGE, "PNG output: no file name given");
    if (channels != 3 && channels != 4)
        return orr_fail(err, ORR_ERR_USAGE, "%s: PNG channels must be 3 (RGB) or 4 (RGBA), not %d", path, channels);
    if (bits != 8 && bits != 16)
        return orr_fail(err, ORR_ERR_USAGE, "%s: PNG bit depth must be 8 or 16, not %d", path, bits);
    if (width <= 0 || height <= 0 || (!src->pixels && !src->row))
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
static orr_status write_temp(const char *temp_path, const char *path, const orr_png_rows *src, png_textp texts,
                             int ntext, orr_error *err)
{
    FILE *fp = fopen(temp_path, "wb");
    if (!fp) {
        int e = errno;
        return orr_fail(err, ORR_ERR_IO, "%s: cannot open %s: %s", path, temp_path, strerror(e));
    }
    png_failure fail = {""};
    orr_status st = write_header(fp, src, texts, ntext, &fail)
                        ? ORR_OK
                        : orr_fail(err, ORR_ERR_IO, "%s: cannot write PNG file: %s", path, fail.msg);
    if (!st)
        st = orr_png_write_idat(fp, src, path, err);
    if (!st && !orr_png_write_chunk(fp, "IEND", NULL, 0))
        st = orr_fail(err, ORR_ERR_IO, "%s: cannot write PNG file", path);
    /* Write errors can surface only when the buffer is flushed at close. */
    int write_error = ferror(fp);
    int e = errno;
    if (fclose(fp) != 0) {
        write_error = 1;
        e = errno;
    }
    if (write_error) /* the system's reason is the one worth giving */
        return orr_fail(err, ORR_ERR_IO, "%s: cannot write PNG file: %s", path, strerror(e));
    return st;
}

orr_status orr_write_png_rows(const char *path, const orr_png_rows *src, const orr_png_text *text, int ntext,
                              orr_error *err)
{
    orr_status st = check_args(path, src, text, ntext, err);
    if (st != ORR_OK)
        return st;
    png_textp texts = make_texts(text, ntext, err);
    if (!texts)
        return ORR_ERR_NOMEM;
    orr_atomic_file af;
    st = orr_atomic_begin(&af, path, err);
    if (st == ORR_OK) {
        st = write_temp(af.temp_path, path, src, texts, ntext, err);
        if (st == ORR_OK)
            st = orr_atomic_commit(&af, err);
        else
            orr_atomic_abort(&af);
    }
    free(texts);
    return st;
}

orr_status orr_write_png(const char *path, int width, int height, const float *pixels, int channels, int bits,
                        const orr_png_text *text, int ntext, orr_error *err)
{
    if (!pixels)
        return orr_fail(err, ORR_ERR_USAGE, "%s: empty image (%d x %d)", path ? path : "PNG output", width, height);
    orr_png_rows src = {width, height, channels, bits, pixels, NULL, NULL};
    return orr_write_png_rows(path, &src, text, ntext, err);
}

orr_status orr_write_png_rgb(const char *path, int width, int height, const float *rgb, int bits,
                             const orr_png_text *text, int ntext, orr_error *err)
{
    return orr_write_png(path, width, height, rgb, 3, bits, text, ntext, err);
}
