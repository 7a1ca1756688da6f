/* OpenEXR output through OpenEXR's C API (OpenEXRCore): one scanline part,
 * one channel per plane, half or float samples, written atomically, with
 * the frame's metadata as header attributes (docs/formats-out.md). */
#ifndef ORR_ENCODE_EXR_H
#define ORR_ENCODE_EXR_H

#include "core/error.h"
#include "encode/image_out.h"
#include "core/plane.h"

typedef enum { ORR_EXR_HALF, ORR_EXR_FLOAT } orr_exr_pixel;

/* Lossless compressions only: the files hold data, not just pictures. */
typedef enum {
    ORR_EXR_ZIP = 0, /* zlib, 16 scanlines per block: the default */
    ORR_EXR_ZIPS,    /* zlib, one scanline per block */
    ORR_EXR_PIZ,     /* wavelet, 32 scanlines per block: best on noisy images */
    ORR_EXR_RLE,     /* run length */
    ORR_EXR_NONE
} orr_exr_compression;

/* Writes the channels (all the same size, row 0 at the top) to path. Each
 * channel is named after its plane: "R", "G", "B" make an RGB image that
 * every viewer shows; any other names ("mass", "X", "Y", "Z") are kept as
 * they are. Names must be non-empty and distinct. OpenEXR stores channels
 * sorted by name, whatever the order given. Half samples round to the
 * nearest half; values beyond +-65504 become infinite. ZIP compression. */
orr_status orr_write_exr(const char *path, const orr_plane *const *channels, int nchannels, orr_exr_pixel type,
                         const orr_image_meta *meta, orr_error *err);

/* orr_write_exr with another compression. */
orr_status orr_write_exr_compressed(const char *path, const orr_plane *const *channels, int nchannels,
                                    orr_exr_pixel type, orr_exr_compression compression,
                                    const orr_image_meta *meta, orr_error *err);

#endif
