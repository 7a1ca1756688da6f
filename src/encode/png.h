/* PNG output, 8 or 16 bits per channel, RGB or RGBA, with a tEXt chunk per
 * key/value pair (Software, Description, ...): libpng writes the chunks
 * before the image data, which is deflated band by band on every thread
 * (encode/png_idat.h), the same bytes on any number of threads. */
#ifndef ORR_ENCODE_PNG_H
#define ORR_ENCODE_PNG_H

#include "core/error.h"
#include "encode/png_idat.h"

typedef struct orr_png_text {
    const char *key;
    const char *value;
} orr_png_text;

/* rgb holds width*height*3 values in [0, 1] (clipped), sRGB-encoded, row 0 at
 * the top. bits is 8 or 16. Written atomically. */
/* The same with `channels` 3 (RGB) or 4 (RGBA: the fourth value of each
 * pixel is its alpha, 0 transparent to 1 opaque, not premultiplied, as PNG
 * defines it). */
orr_status orr_write_png(const char *path, int width, int height, const float *pixels, int channels, int bits,
                         const orr_png_text *text, int ntext, orr_error *err);
/* The same from an orr_png_rows: the picture in memory, or made a row at a
 * time by its row function (on several threads at once). */
orr_status orr_write_png_rows(const char *path, const orr_png_rows *src, const orr_png_text *text, int ntext,
                              orr_error *err);
orr_status orr_write_png_rgb(const char *path, int width, int height, const float *rgb, int bits,
                             const orr_png_text *text, int ntext, orr_error *err);

#endif
