/* Images in any format OpenImageIO knows (TIFF, JPEG, PNG, OpenEXR, ...),
 * through a thin C++ shim (oiio.cpp) with this C interface. The format is
 * chosen from the file name's extension. Every C++ exception is caught and
 * becomes an orr_status; nothing is printed. */
#ifndef ORR_ENCODE_OIIO_H
#define ORR_ENCODE_OIIO_H

#include <stddef.h>

#include "core/error.h"
#include "encode/image_out.h"
#include "core/plane.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Writes pixels (width*height*nchannels floats, interleaved, row 0 at the
 * top) to path, atomically, in the format its extension names.
 *   bits 8 or 16: unsigned integer samples; values are display-encoded (sRGB)
 *     in [0, 1], clipped (NaN to 0) and rounded to the nearest code, as for
 *     PNG: floor(v * 255 + 0.5) or floor(v * 65535 + 0.5). The file is
 *     tagged sRGB where the format can say so.
 *   bits 32: float samples, written unchanged (linear light).
 * A format that cannot hold the depth asked for gets OpenImageIO's nearest
 * (JPEG is always 8-bit).
 * Channels are named R, G, B, A, then channel4, ... (OpenImageIO's default).
 * Metadata: ImageDescription (orr_image_meta_text), Software, DocumentName
 * (the scene) and orrery:* attributes for formats that keep any attribute.
 * An extension OpenImageIO has no writer for is ORR_ERR_USAGE, with its
 * message; nothing is created then. */
orr_status orr_write_oiio(const char *path, const float *pixels, int width, int height, int nchannels,
                          int bits, const orr_image_meta *meta, orr_error *err);

/* orr_write_oiio with the channels named: channel_names[c] for each c
 * (non-empty strings; NULL for the default names). */
orr_status orr_write_oiio_named(const char *path, const float *pixels, int width, int height, int nchannels,
                                const char *const *channel_names, int bits, const orr_image_meta *meta,
                                orr_error *err);

/* Reads the first subimage of any file OpenImageIO reads into float,
 * interleaved, row 0 at the top; *pixels is malloc'ed (free() it). Integer
 * samples come back scaled to [0, 1]. */
orr_status orr_read_oiio(const char *path, float **pixels, int *width, int *height, int *nchannels,
                         orr_error *err);

/* Reads every channel of the first subimage into planes named after the
 * channels (names cut to ORR_PLANE_NAME_MAX - 1 bytes). *planes is an array
 * of *nplanes planes: orr_plane_free each, then free() the array. */
orr_status orr_read_oiio_planes(const char *path, orr_plane **planes, int *nplanes, orr_error *err);

/* Copies the value of attribute `name` (case-insensitive, as OpenImageIO
 * names it: "ImageDescription", "Software", "orrery:frame",
 * "worldtocamera", ...) of path's first subimage into buf as text; numbers
 * and arrays as OpenImageIO formats them (elements separated by ", ",
 * e.g. "0.1, 0, 2"). Besides the file's own
 * attributes, "width", "height", "datawindow" and the like (OpenImageIO's
 * ImageSpec::find_attribute) and "format", the sample type as OpenImageIO
 * names it ("half", "float", "uint8", "uint16"). A missing attribute is
 * ORR_ERR_FORMAT; a value longer than size - 1 bytes is cut short. */
orr_status orr_oiio_get_attribute(const char *path, const char *name, char *buf, size_t size,
                                  orr_error *err);

#ifdef __cplusplus
}
#endif

#endif
