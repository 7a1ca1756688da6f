#include "encode/image_out.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "core/numbers.h"
#include "encode/exr.h"
#include "encode/fits.h"
#include "encode/oiio.h"
#include "encode/png.h"

/* ---- choosing a writer --------------------------------------------------- */

orr_image_format orr_image_format_for_path(const char *path)
{
    const char *slash = path ? strrchr(path, '/') : NULL;
    const char *base = slash ? slash + 1 : path;
    const char *dot = base ? strrchr(base, '.') : NULL;
    if (!dot || dot == base) /* no extension, or a dot file such as ".png" */
        return ORR_IMAGE_OIIO;
    const char *ext = dot + 1;
    if (!strcasecmp(ext, "png"))
        return ORR_IMAGE_PNG;
    if (!strcasecmp(ext, "fits") || !strcasecmp(ext, "fit") || !strcasecmp(ext, "fts"))
        return ORR_IMAGE_FITS;
    if (!strcasecmp(ext, "exr"))
        return ORR_IMAGE_EXR;
    return ORR_IMAGE_OIIO;
}

const char *orr_image_format_name(orr_image_format f)
{
    switch (f) {
    case ORR_IMAGE_PNG: return "PNG";
    case ORR_IMAGE_FITS: return "FITS";
    case ORR_IMAGE_EXR: return "OpenEXR";
    case ORR_IMAGE_OIIO: return "OpenImageIO";
    }
    return "unknown";
}

/* The metadata as FITS cards, with the names the renderer's FITS files use
 * (src/render/render.c); extra pairs whose key is a valid FITS keyword of
 * at most 8 characters (letters, digits, '_', '-') go in too. */
static void meta_cards(const orr_image_meta *meta, orr_cards *h)
{
    memset(h, 0, sizeof *h);
    orr_cards_add_string(h, "CREATOR", orr_image_meta_software(meta), "software that made this file");
    if (!meta)
        return;
    if (meta->scene && meta->scene[0])
        orr_cards_add_string(h, "OBJECT", meta->scene, "scene");
    if (meta->has_frame)
        orr_cards_add_long(h, "FRAME", meta->frame, "frame number");
    if (meta->has_time)
        orr_cards_add_double(h, "SIMTIME", meta->time, "simulation time of the frame");
    if (meta->projection && meta->projection[0])
        orr_cards_add_string(h, "PROJTYPE", meta->projection, "projection");
    if (meta->has_camera) {
        static const char *const pos[3] = {"CAMPOSX", "CAMPOSY", "CAMPOSZ"};
        static const char *const quat[4] = {"CAMQW", "CAMQX", "CAMQY", "CAMQZ"};
        static const char *const pos_c[3] = {"camera position x", "camera position y", "camera position z"};
        static const char *const quat_c[4] = {"camera-to-world quaternion w", "camera-to-world quaternion x",
                                              "camera-to-world quaternion y", "camera-to-world quaternion z"};
        for (int i = 0; i < 3; i++)
            orr_cards_add_double(h, pos[i], meta->cam_pos[i], pos_c[i]);
        for (int i = 0; i < 4; i++)
            orr_cards_add_double(h, quat[i], meta->cam_quat[i], quat_c[i]);
    }
    for (int i = 0; i < meta->nextra; i++) {
        const char *k = meta->extra_key[i];
        if (strlen(k) > 8 || strchr(k, '.'))
            continue;
        orr_cards_add_string(h, k, meta->extra_value[i], NULL);
    }
}

/* sRGB-encoded value to linear light (IEC 61966-2-1), clipped to [0, 1]
 * first (NaN to 0) like the PNG writer. */
static float srgb_to_linear(float v)
{
    if (!(v > 0))
        return 0;
    if (v >= 1)
        return 1;
    return v <= 0.04045f ? v / 12.92f : powf((v + 0.055f) / 1.055f, 2.4f);
}

/* Splits interleaved RGB into three planes named R, G, B; linear turns on
 * the sRGB decoding. */
static orr_status split_rgb(const float *rgb, int width, int height, int linear, orr_plane planes[3],
                            orr_error *err)
{
    static const char *const names[3] = {"R", "G", "B"};
    memset(planes, 0, 3 * sizeof *planes);
    for (int c = 0; c < 3; c++) {
        orr_status st = orr_plane_alloc(&planes[c], width, height, names[c], "", err);
        if (st != ORR_OK) {
            for (int k = 0; k < c; k++)
                orr_plane_free(&planes[k]);
            return st;
        }
        size_t n = (size_t)width * (size_t)height;
        for (size_t i = 0; i < n; i++) {
            float v = rgb[3 * i + (size_t)c];
            planes[c].data[i] = linear ? srgb_to_linear(v) : v;
        }
    }
    return ORR_OK;
}

static orr_status write_rgb_png(const char *path, const float *rgb, int channels, int width, int height, int bits,
                                const orr_image_meta *meta, orr_error *err)
{
    size_t len = orr_image_meta_text(meta, NULL, 0);
    char *text = orr_malloc(len + 1, "PNG description", err);
    if (!text)
        return ORR_ERR_NOMEM;
    orr_image_meta_text(meta, text, len + 1);
    orr_png_text chunks[3];
    int n = 0;
    chunks[n++] = (orr_png_text){"Software", orr_image_meta_software(meta)};
    if (meta && meta->scene && meta->scene[0])
        chunks[n++] = (orr_png_text){"Title", meta->scene};
    chunks[n++] = (orr_png_text){"Description", text};
    orr_status st = orr_write_png(path, width, height, rgb, channels, bits, chunks, n, err);
    free(text);
    return st;
}

orr_status orr_write_image_rgb(const char *path, const float *rgb, int width, int height, int bits,
                               const orr_image_meta *meta, orr_error *err)
{
    if (!path || !path[0])
        return orr_fail(err, ORR_ERR_USAGE, "image output: no file name given");
    if (width <= 0 || height <= 0 || !rgb)
        return orr_fail(err, ORR_ERR_USAGE, "%s: empty image (%d x %d)", path, width, height);
    orr_status st = orr_image_meta_check(meta, path, err);
    if (st != ORR_OK)
        return st;
    orr_image_format f = orr_image_format_for_path(path);
    if (f == ORR_IMAGE_PNG)
        return write_rgb_png(path, rgb, 3, width, height, bits, meta, err);
    if (f == ORR_IMAGE_OIIO && bits != 32)
        return orr_write_oiio(path, rgb, width, height, 3, bits, meta, err);
    if (bits != 8 && bits != 16 && bits != 32)
        return orr_fail(err, ORR_ERR_USAGE, "%s: bits per sample must be 8, 16 or 32 (float), not %d", path, bits);

    /* FITS gets the values as they are; float files linear light. */
    orr_plane planes[3];
    st = split_rgb(rgb, width, height, f != ORR_IMAGE_FITS, planes, err);
    if (st != ORR_OK)
        return st;
    if (f == ORR_IMAGE_FITS) {
        orr_cards *h = orr_malloc(sizeof *h, "FITS header", err);
        st = h ? ORR_OK : ORR_ERR_NOMEM;
        if (h) {
            meta_cards(meta, h);
            st = orr_write_fits(path, planes, 3, h, err);
            free(h);
        }
    } else if (f == ORR_IMAGE_EXR) {
        const orr_plane *ch[3] = {&planes[0], &planes[1], &planes[2]};
        st = orr_write_exr(path, ch, 3, bits == 32 ? ORR_EXR_FLOAT : ORR_EXR_HALF, meta, err);
    } else { /* OpenImageIO, float samples */
        size_t n = (size_t)width * (size_t)height;
        float *lin = orr_malloc(n * 3 * sizeof *lin, "linear RGB", err);
        st = lin ? ORR_OK : ORR_ERR_NOMEM;
        if (lin) {
            for (size_t i = 0; i < n; i++)
                for (int c = 0; c < 3; c++)
                    lin[3 * i + (size_t)c] = planes[c].data[i];
            st = orr_write_oiio(path, lin, width, height, 3, 32, meta, err);
            free(lin);
        }
    }
    for (int c = 0; c < 3; c++)
        orr_plane_free(&planes[c]);
    return st;
}

orr_status orr_write_image_picture(const char *path, const float *rgb, const float *rgba, int width, int height,
                                   int bits, const orr_image_meta *meta, orr_error *err)
{
    orr_image_format f = path ? orr_image_format_for_path(path) : ORR_IMAGE_PNG;
    int with_alpha = rgba && (f == ORR_IMAGE_PNG || (f == ORR_IMAGE_OIIO && bits != 32));
    if (!with_alpha)
        return orr_write_image_rgb(path, rgb, width, height, bits, meta, err);
    if (width <= 0 || height <= 0)
        return orr_fail(err, ORR_ERR_USAGE, "%s: empty image (%d x %d)", path, width, height);
    orr_status st = orr_image_meta_check(meta, path, err);
    if (st != ORR_OK)
        return st;
    if (f == ORR_IMAGE_PNG)
        return write_rgb_png(path, rgba, 4, width, height, bits, meta, err);
    return orr_write_oiio(path, rgba, width, height, 4, bits, meta, err);
}

orr_status orr_write_image_planes(const char *path, const orr_plane *planes, int nplanes,
                                  const orr_image_meta *meta, orr_error *err)
{
    if (!path || !path[0])
        return orr_fail(err, ORR_ERR_USAGE, "image output: no file name given");
    if (nplanes <= 0 || !planes)
        return orr_fail(err, ORR_ERR_USAGE, "%s: no planes to write", path);
    orr_status st = orr_image_meta_check(meta, path, err);
    if (st != ORR_OK)
        return st;
    orr_image_format f = orr_image_format_for_path(path);
    if (f == ORR_IMAGE_PNG)
        return orr_fail(err, ORR_ERR_USAGE,
                        "%s: PNG holds display pictures, not linear planes: use .fits, .exr or .tif", path);
    if (f == ORR_IMAGE_FITS) {
        orr_cards *h = orr_malloc(sizeof *h, "FITS header", err);
        if (!h)
            return ORR_ERR_NOMEM;
        meta_cards(meta, h);
        st = orr_write_fits(path, planes, nplanes, h, err);
        free(h);
        return st;
    }
    if (f == ORR_IMAGE_EXR) {
        const orr_plane **ch = orr_malloc((size_t)nplanes * sizeof *ch, "plane list", err);
        if (!ch)
            return ORR_ERR_NOMEM;
        for (int i = 0; i < nplanes; i++)
            ch[i] = &planes[i];
        st = orr_write_exr(path, ch, nplanes, ORR_EXR_FLOAT, meta, err);
        free(ch);
        return st;
    }
    /* OpenImageIO wants the channels interleaved. */
    int w = planes[0].width, h = planes[0].height;
    for (int i = 0; i < nplanes; i++)
        if (planes[i].width != w || planes[i].height != h || !planes[i].data || w <= 0 || h <= 0)
            return orr_fail(err, ORR_ERR_USAGE, "%s: plane %d is empty or not the size of the first", path, i + 1);
    size_t n = (size_t)w * (size_t)h;
    float *pix = orr_malloc(n * (size_t)nplanes * sizeof *pix, "interleaved planes", err);
    const char **names = orr_malloc((size_t)nplanes * sizeof *names, "channel names", err);
    if (!pix || !names) {
        free(pix);
        free(names);
        return ORR_ERR_NOMEM;
    }
    int named = 1;
    for (int c = 0; c < nplanes; c++) {
        names[c] = planes[c].name;
        named = named && planes[c].name[0];
        for (size_t i = 0; i < n; i++)
            pix[i * (size_t)nplanes + (size_t)c] = planes[c].data[i];
    }
    st = orr_write_oiio_named(path, pix, w, h, nplanes, named ? names : NULL, 32, meta, err);
    free(pix);
    free(names);
    return st;
}
