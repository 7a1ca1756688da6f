/* Image metadata shared by every encoder, and writers that pick the format
 * from the file name's extension: .png (libpng), .fits/.fit/.fts (cfitsio),
 * .exr (OpenEXR's C API) and anything else through OpenImageIO.
 * docs/formats-out.md says where each piece of metadata goes in each format. */
#ifndef ORR_ENCODE_IMAGE_OUT_H
#define ORR_ENCODE_IMAGE_OUT_H

#include <stddef.h>

#include "core/error.h"
#include "core/plane.h"

#ifdef __cplusplus
extern "C" {
#endif

#define ORR_IMAGE_META_MAX_EXTRA 16
#define ORR_IMAGE_META_KEY_MAX 63 /* characters in an extra key */

/* What a frame is, for the files that have a place for it. A zeroed struct
 * is valid and says nothing but the software version; each has_ flag turns
 * its fields on. Strings are borrowed for the duration of the call; NULL or
 * "" leaves them out. No string may hold control characters (newlines
 * included), so that the "key=value" text form (orr_image_meta_text) stays
 * one line per item. */
typedef struct orr_image_meta {
    const char *scene;      /* scene name */
    const char *projection; /* projection name, e.g. "hammer-aitoff" */
    const char *software;   /* NULL: "orrery <version>" */
    int has_frame;
    long frame;             /* frame number */
    int has_time;
    double time;            /* simulation time of the frame */
    int has_camera;
    double cam_pos[3];      /* camera position, world (simulation) units */
    double cam_quat[4];     /* w, x, y, z: takes camera-frame vectors to world
                               vectors (frame/camera.h; need not be normalised) */
    /* A perspective view's lens as OpenEXR's screen window: the image's
     * extent on the plane one unit in front of the camera, in the camera
     * space of worldToCamera (x right, y up): width, and centre (0, 0)
     * unless the principal point is shifted. Written only to OpenEXR. */
    int has_screen_window;
    double screen_window_width;
    double screen_window_center[2];
    /* Free key/value pairs. Keys are 1 to ORR_IMAGE_META_KEY_MAX characters
     * of letters, digits, '_', '.' and '-'. */
    int nextra;
    const char *extra_key[ORR_IMAGE_META_MAX_EXTRA];
    const char *extra_value[ORR_IMAGE_META_MAX_EXTRA];
} orr_image_meta;

/* Checks the strings and counts in meta (NULL is valid: no metadata). path
 * is only for the message. ORR_ERR_USAGE when something is wrong. */
orr_status orr_image_meta_check(const orr_image_meta *meta, const char *path, orr_error *err);

/* The software string: meta->software, or "orrery <version>". */
const char *orr_image_meta_software(const orr_image_meta *meta);

/* The text form of meta: one "key=value" line per item, in this order:
 *   software=orrery 0.1.0
 *   scene=NAME
 *   frame=N
 *   time=T
 *   projection=NAME
 *   camera.position=X Y Z
 *   camera.quaternion=W X Y Z
 *   KEY=VALUE            (each extra pair)
 * lines separated by '\n' (none after the last); items not set are left
 * out. Numbers are written in the shortest form that reads back exactly.
 * Writes at most size bytes (always terminated when size > 0) and returns
 * the length of the whole text, like snprintf. */
size_t orr_image_meta_text(const orr_image_meta *meta, char *buf, size_t size);

typedef enum {
    ORR_IMAGE_PNG,  /* .png: src/encode/png.c */
    ORR_IMAGE_FITS, /* .fits .fit .fts: src/encode/fits.c */
    ORR_IMAGE_EXR,  /* .exr: src/encode/exr.c */
    ORR_IMAGE_OIIO  /* anything else: src/encode/oiio.cpp (OpenImageIO) */
} orr_image_format;

/* The writer for path, from its extension (case-insensitive). A name without
 * an extension is ORR_IMAGE_OIIO, which then reports it cannot tell. */
orr_image_format orr_image_format_for_path(const char *path);
const char *orr_image_format_name(orr_image_format f); /* "PNG", "FITS", ... */

/* Writes a display picture: rgb holds width*height*3 sRGB-encoded values in
 * [0, 1], interleaved, row 0 at the top (what orr_write_png_rgb takes).
 * bits is 8 or 16 (32 is also accepted for formats holding floats).
 *   PNG:   orr_write_png_rgb at `bits`, tEXt Software, Title (the scene)
 *          and Description (orr_image_meta_text).
 *   FITS:  three float planes R, G, B with the metadata as cards.
 *   EXR:   the values decoded from sRGB to linear light (OpenEXR holds
 *          linear values; viewers re-encode them for the screen), channels
 *          R, G, B as half (bits 8 or 16) or float (bits 32).
 *   other: orr_write_oiio at `bits`.
 * Written atomically, like every writer here. */
orr_status orr_write_image_rgb(const char *path, const float *rgb, int width, int height, int bits,
                               const orr_image_meta *meta, orr_error *err);

/* The picture with an alpha (output.alpha_mask): rgba holds width * height
 * * 4 values, the picture's RGB then the alpha in [0, 1]. PNG and the 8- and
 * 16-bit formats of OpenImageIO (TIFF, ...) get RGBA; the others, and any
 * format when rgba is NULL, get orr_write_image_rgb of rgb (a linear
 * OpenEXR's alpha comes with output.exr instead). */
orr_status orr_write_image_picture(const char *path, const float *rgb, const float *rgba, int width, int height,
                                   int bits, const orr_image_meta *meta, orr_error *err);

/* Writes linear planes (all the same size) unchanged, as float:
 *   FITS:  orr_write_fits, the metadata as cards.
 *   EXR:   orr_write_exr, one float channel per plane, named after it.
 *   other: orr_write_oiio with 32-bit float samples, channels in order
 *          (formats that cannot hold floats get OpenImageIO's conversion).
 *   PNG:   refused (ORR_ERR_USAGE): PNG holds display pictures.  */
orr_status orr_write_image_planes(const char *path, const orr_plane *planes, int nplanes,
                                  const orr_image_meta *meta, orr_error *err);

#ifdef __cplusplus
}
#endif

#endif
