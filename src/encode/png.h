/* PNG output through libpng, 8 or 16 bits per channel, RGB or RGBA, with a tEXt
 * chunk per key/value pair (Software, Description, ...). */
#ifndef ORR_ENCODE_PNG_H
#define ORR_ENCODE_PNG_H

#include "core/error.h"

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
orr_status orr_write_png_rgb(const char *path, int width, int height, const float *rgb, int bits,
                             const orr_png_text *text, int ntext, orr_error *err);

#endif
