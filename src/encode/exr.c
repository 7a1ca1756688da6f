#include "encode/exr.h"

#include <math.h>
#include <openexr.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/vecmath.h"
#include "core/atomic.h"
#include "frame/camera.h"

/* Names longer than this need OpenEXR's "long names" flag, which readers
 * older than OpenEXR 1.7 do not understand; it is set only when needed. */
#define EXR_SHORT_NAME_MAX 31
#define EXR_MAX_CHANNELS 1024

/* OpenEXR reports errors through a callback, by default printing them. The
 * library never prints, so the callback keeps the first message of the
 * current write here. (With OpenEXR's own file I/O the context's user data
 * is its file handle, so the message cannot travel through it; writes on
 * different threads each have their own copy.) */
static _Thread_local char exr_message[512];

static void on_exr_error(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    (void)ctxt;
    if (!exr_message[0])
        snprintf(exr_message, sizeof exr_message, "%s", msg ? msg : exr_get_default_error_message(code));
}

/* The message for a failed call: OpenEXR's own, else its text for rv. */
static orr_status exr_fail(orr_error *err, const char *path, exr_result_t rv)
{
    return orr_fail(err, ORR_ERR_IO, "%s: cannot write OpenEXR file: %s", path,
                    exr_message[0] ? exr_message : exr_get_default_error_message(rv));
}

static orr_status check_args(const char *path, const orr_plane *const *channels, int nchannels,
                             orr_exr_pixel type, orr_exr_compression compression, const orr_image_meta *meta,
                             orr_error *err)
{
    if (!path || !path[0])
        return orr_fail(err, ORR_ERR_USAGE, "OpenEXR output: no file name given");
    if (type != ORR_EXR_HALF && type != ORR_EXR_FLOAT)
        return orr_fail(err, ORR_ERR_USAGE, "%s: unknown OpenEXR pixel type %d", path, (int)type);
    if (compression < ORR_EXR_ZIP || compression > ORR_EXR_NONE)
        return orr_fail(err, ORR_ERR_USAGE, "%s: unknown OpenEXR compression %d", path, (int)compression);
    if (nchannels < 1 || nchannels > EXR_MAX_CHANNELS || !channels)
        return orr_fail(err, ORR_ERR_USAGE, "%s: %d channels (1 to %d allowed)", path, nchannels, EXR_MAX_CHANNELS);
    for (int i = 0; i < nchannels; i++) {
        const orr_plane *p = channels[i];
        if (!p || !p->data || p->width <= 0 || p->height <= 0)
            return orr_fail(err, ORR_ERR_USAGE, "%s: channel %d is empty", path, i + 1);
        if (p->width != channels[0]->width || p->height != channels[0]->height)
            return orr_fail(err, ORR_ERR_USAGE, "%s: channel %s is %d x %d, channel %s %d x %d", path, p->name,
                            p->width, p->height, channels[0]->name, channels[0]->width, channels[0]->height);
        if (!p->name[0])
            return orr_fail(err, ORR_ERR_USAGE, "%s: channel %d has no name", path, i + 1);
        for (int k = 0; k < i; k++)
            if (!strcmp(channels[k]->name, p->name))
                return orr_fail(err, ORR_ERR_USAGE, "%s: two channels are named %s", path, p->name);
    }
    return orr_image_meta_check(meta, path, err);
}

static exr_compression_t exr_compression(orr_exr_compression c)
{
    switch (c) {
    case ORR_EXR_ZIPS: return EXR_COMPRESSION_ZIPS;
    case ORR_EXR_PIZ: return EXR_COMPRESSION_PIZ;
    case ORR_EXR_RLE: return EXR_COMPRESSION_RLE;
    case ORR_EXR_NONE: return EXR_COMPRESSION_NONE;
    case ORR_EXR_ZIP: break;
    }
    return EXR_COMPRESSION_ZIP;
}

/* OpenEXR's standard worldToCamera matrix (ImfStandardAttributes.h): camera
 * space has x to the right of the image, y up and z along the view, and
 * points are row vectors (p_camera = p_world * M). orrery's camera frame has
 * y down the image (frame/camera.h), so its y axis is flipped. */
static exr_attr_m44f_t world_to_camera(const orr_image_meta *meta)
{
    orr_camera cam = {
        .position = {meta->cam_pos[0], meta->cam_pos[1], meta->cam_pos[2]},
        .orientation = orr_quat_normalize(
            (orr_quat){meta->cam_quat[0], meta->cam_quat[1], meta->cam_quat[2], meta->cam_quat[3]}),
    };
    orr_mat3 a = orr_camera_world_to_camera(&cam); /* rows: right, down, forward */
    for (int j = 0; j < 3; j++)
        a.m[1][j] = -a.m[1][j]; /* down -> up */
    orr_vec3 t = orr_mat3_apply(a, cam.position);
    exr_attr_m44f_t m;
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++)
            m.m[4 * i + j] = (float)a.m[j][i];
        m.m[4 * i + 3] = 0;
    }
    m.m[12] = (float)-t.x;
    m.m[13] = (float)-t.y;
    m.m[14] = (float)-t.z;
    m.m[15] = 1;
    for (int i = 0; i < 16; i++)
        m.m[i] += 0.0f; /* -0 to 0, for tidier listings */
    return m;
}

static int quat_usable(const double q[4])
{
    double n = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    return isfinite(n) && n > 0;
}

/* A perspective view's screen window, replacing the required attributes'
 * defaults (width 1, centre (0, 0)). */
static exr_result_t set_screen_window(exr_context_t ctxt, int part, const orr_image_meta *meta)
{
    exr_attr_v2f_t centre = {.x = (float)meta->screen_window_center[0], .y = (float)meta->screen_window_center[1]};
    exr_result_t rv = exr_set_screen_window_width(ctxt, part, (float)meta->screen_window_width);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_set_screen_window_center(ctxt, part, &centre);
    return rv;
}

/* The header attributes for meta (docs/formats-out.md lists them). */
static exr_result_t set_attributes(exr_context_t ctxt, int part, const orr_image_meta *meta, const char *text)
{
    exr_result_t rv = exr_attr_set_string(ctxt, part, "software", orr_image_meta_software(meta));
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_attr_set_string(ctxt, part, "comments", text); /* OpenImageIO's ImageDescription */
    if (rv != EXR_ERR_SUCCESS || !meta)
        return rv;
    if (meta->scene && meta->scene[0])
        rv = exr_attr_set_string(ctxt, part, "orrery:scene", meta->scene);
    if (rv == EXR_ERR_SUCCESS && meta->projection && meta->projection[0])
        rv = exr_attr_set_string(ctxt, part, "orrery:projection", meta->projection);
    if (rv == EXR_ERR_SUCCESS && meta->has_frame)
        rv = exr_attr_set_int(ctxt, part, "orrery:frame", (int32_t)meta->frame);
    if (rv == EXR_ERR_SUCCESS && meta->has_time)
        rv = exr_attr_set_double(ctxt, part, "orrery:time", meta->time);
    if (rv == EXR_ERR_SUCCESS && meta->has_camera) {
        exr_attr_v3d_t pos = {.x = meta->cam_pos[0], .y = meta->cam_pos[1], .z = meta->cam_pos[2]};
        rv = exr_attr_set_v3d(ctxt, part, "orrery:cameraPosition", &pos);
        static const char *const quat_names[4] = {"orrery:cameraQuatW", "orrery:cameraQuatX",
                                                  "orrery:cameraQuatY", "orrery:cameraQuatZ"};
        for (int i = 0; i < 4 && rv == EXR_ERR_SUCCESS; i++)
            rv = exr_attr_set_double(ctxt, part, quat_names[i], meta->cam_quat[i]);
        if (rv == EXR_ERR_SUCCESS && quat_usable(meta->cam_quat)) {
            exr_attr_m44f_t m = world_to_camera(meta);
            rv = exr_attr_set_m44f(ctxt, part, "worldToCamera", &m);
        }
    }
    char name[8 + ORR_IMAGE_META_KEY_MAX + 1];
    for (int i = 0; i < meta->nextra && rv == EXR_ERR_SUCCESS; i++) {
        snprintf(name, sizeof name, "orrery:%s", meta->extra_key[i]);
        rv = exr_attr_set_string(ctxt, part, name, meta->extra_value[i]);
    }
    if (rv == EXR_ERR_SUCCESS && meta->has_screen_window)
        rv = set_screen_window(ctxt, part, meta);
    return rv;
}

/* Whether a channel holds colour: R, G, B or luminance Y, bare or as the
 * last part of a layer's name ("left.R"), not "xyz.Y". */
static int is_colour_channel(const char *name)
{
    const char *dot = strrchr(name, '.');
    const char *last = dot ? dot + 1 : name;
    if (dot && dot - name >= 3 && !strncmp(dot - 3, "xyz", 3))
        return 0;
    return !strcmp(last, "R") || !strcmp(last, "G") || !strcmp(last, "B") || !strcmp(last, "Y");
}

/* Every RGB orrery writes is linear light in Rec. 709 / sRGB primaries with
 * the D65 white (ITU-R BT.709, table 1.3-1.4): the chromaticities attribute
 * says so, so colour-managed compositors do not guess. */
static exr_result_t set_chromaticities(exr_context_t ctxt, int part, const orr_plane *const *channels,
                                       int nchannels)
{
    int colour = 0;
    for (int i = 0; i < nchannels && !colour; i++)
        colour = is_colour_channel(channels[i]->name);
    if (!colour)
        return EXR_ERR_SUCCESS;
    static const exr_attr_chromaticities_t rec709 = {
        .red_x = 0.64f, .red_y = 0.33f, .green_x = 0.30f, .green_y = 0.60f,
        .blue_x = 0.15f, .blue_y = 0.06f, .white_x = 0.3127f, .white_y = 0.3290f,
    };
    return exr_attr_set_chromaticities(ctxt, part, "chromaticities", &rec709);
}

static int needs_long_names(const orr_plane *const *channels, int nchannels, const orr_image_meta *meta)
{
    for (int i = 0; i < nchannels; i++)
        if (strlen(channels[i]->name) > EXR_SHORT_NAME_MAX)
            return 1;
    for (int i = 0; meta && i < meta->nextra; i++)
        if (strlen("orrery:") + strlen(meta->extra_key[i]) > EXR_SHORT_NAME_MAX)
            return 1;
    return 0;
}

/* Encodes and writes every block of scanlines. */
static exr_result_t write_pixels(exr_context_t ctxt, int part, const orr_plane *const *channels, int nchannels)
{
    int width = channels[0]->width, height = channels[0]->height;
    int32_t lines = 1;
    exr_result_t rv = exr_get_scanlines_per_chunk(ctxt, part, &lines);
    if (rv != EXR_ERR_SUCCESS)
        return rv;
    exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
    int started = 0;
    for (int y = 0; y < height && rv == EXR_ERR_SUCCESS; y += lines) {
        exr_chunk_info_t info;
        rv = exr_write_scanline_chunk_info(ctxt, part, y, &info);
        if (rv != EXR_ERR_SUCCESS)
            break;
        rv = started ? exr_encoding_update(ctxt, part, &info, &enc)
                     : exr_encoding_initialize(ctxt, part, &info, &enc);
        if (rv != EXR_ERR_SUCCESS)
            break;
        /* The pipeline lists the channels in the file's (sorted) order. */
        for (int c = 0; c < enc.channel_count; c++) {
            exr_coding_channel_info_t *ci = &enc.channels[c];
            const orr_plane *p = NULL;
            for (int k = 0; k < nchannels && !p; k++)
                if (!strcmp(channels[k]->name, ci->channel_name))
                    p = channels[k];
            if (!p)
                return EXR_ERR_INVALID_ARGUMENT; /* cannot happen: OpenEXR lists what was added */
            ci->user_data_type = EXR_PIXEL_FLOAT;
            ci->user_bytes_per_element = sizeof(float);
            ci->user_pixel_stride = sizeof(float);
            ci->user_line_stride = (int32_t)(sizeof(float) * (size_t)width);
            ci->encode_from_ptr = (const uint8_t *)(p->data + (size_t)info.start_y * (size_t)width);
        }
        if (!started) {
            rv = exr_encoding_choose_default_routines(ctxt, part, &enc);
            started = 1;
            if (rv != EXR_ERR_SUCCESS)
                break;
        }
        rv = exr_encoding_run(ctxt, part, &enc);
    }
    if (started) {
        exr_result_t rd = exr_encoding_destroy(ctxt, &enc);
        if (rv == EXR_ERR_SUCCESS)
            rv = rd;
    }
    return rv;
}

/* Everything between opening the temporary file and closing it. */
static orr_status encode(const char *temp_path, const char *path, const orr_plane *const *channels,
                         int nchannels, orr_exr_pixel type, orr_exr_compression compression,
                         const orr_image_meta *meta, const char *text, orr_error *err)
{
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = on_exr_error;
    exr_context_t ctxt = NULL;
    int part = 0;
    exr_result_t rv = exr_start_write(&ctxt, temp_path, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv != EXR_ERR_SUCCESS)
        return exr_fail(err, path, rv);
    if (needs_long_names(channels, nchannels, meta))
        rv = exr_set_longname_support(ctxt, 1);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_add_part(ctxt, NULL, EXR_STORAGE_SCANLINE, &part);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_initialize_required_attr_simple(ctxt, part, channels[0]->width, channels[0]->height,
                                                 exr_compression(compression));
    for (int c = 0; c < nchannels && rv == EXR_ERR_SUCCESS; c++)
        rv = exr_add_channel(ctxt, part, channels[c]->name, type == ORR_EXR_HALF ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT,
                             EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1);
    if (rv == EXR_ERR_SUCCESS)
        rv = set_attributes(ctxt, part, meta, text);
    if (rv == EXR_ERR_SUCCESS)
        rv = set_chromaticities(ctxt, part, channels, nchannels);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_write_header(ctxt);
    if (rv == EXR_ERR_SUCCESS)
        rv = write_pixels(ctxt, part, channels, nchannels);
    /* exr_finish writes the block offset table and closes the file. */
    exr_result_t rf = exr_finish(&ctxt);
    if (rv == EXR_ERR_SUCCESS)
        rv = rf;
    return rv == EXR_ERR_SUCCESS ? ORR_OK : exr_fail(err, path, rv);
}

orr_status orr_write_exr_compressed(const char *path, const orr_plane *const *channels, int nchannels,
                                    orr_exr_pixel type, orr_exr_compression compression,
                                    const orr_image_meta *meta, orr_error *err)
{
    orr_status st = check_args(path, channels, nchannels, type, compression, meta, err);
    if (st != ORR_OK)
        return st;
    size_t len = orr_image_meta_text(meta, NULL, 0);
    char *text = orr_malloc(len + 1, "OpenEXR comments", err);
    if (!text)
        return ORR_ERR_NOMEM;
    orr_image_meta_text(meta, text, len + 1);
    orr_atomic_file af;
    st = orr_atomic_begin(&af, path, err);
    if (st == ORR_OK) {
        exr_message[0] = '\0';
        st = encode(af.temp_path, path, channels, nchannels, type, compression, meta, text, err);
        if (st == ORR_OK)
            st = orr_atomic_commit(&af, err);
        else
            orr_atomic_abort(&af);
    }
    free(text);
    return st;
}

orr_status orr_write_exr(const char *path, const orr_plane *const *channels, int nchannels, orr_exr_pixel type,
                         const orr_image_meta *meta, orr_error *err)
{
    return orr_write_exr_compressed(path, channels, nchannels, type, ORR_EXR_ZIP, meta, err);
}
