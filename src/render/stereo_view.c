#include "render/stereo_view.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "encode/png.h"
#include "post/anaglyph.h"
#include "post/colour.h"
#include "render/exr_view.h"

/* ---- the eyes ---- */

int orr_stereo_is_pair_mode(orr_stereo_mode m)
{
    return m == ORR_STEREO_ANAGLYPH || m == ORR_STEREO_SIDE_BY_SIDE || m == ORR_STEREO_OVER_UNDER;
}

orr_status orr_eye_output_name(orr_stereo_mode mode, const char *scene_path, const char *name, int eye, char *out,
                               size_t size, orr_error *err)
{
    const int separate = eye && mode == ORR_STEREO_SEPARATE;
    int len = separate ? snprintf(out, size, "%s-%s", name, orr_eye_name(eye)) : snprintf(out, size, "%s", name);
    if (len < 0 || (size_t)len >= size)
        return orr_fail(err, ORR_ERR_USAGE, "%s: output.name '%s' is too long to add -%s for stereo", scene_path,
                        name, orr_eye_name(eye));
    return ORR_OK;
}

double orr_stereo_convergence(const orr_stereo_settings *stereo, const orr_camera_settings *camera,
                              orr_vec3 position)
{
    if (stereo->convergence > 0)
        return stereo->convergence;
    orr_vec3 target;
    return orr_camera_settings_look_target(camera, &target) ? orr_v3_norm(orr_v3_sub(target, position)) : 0.0;
}

orr_status orr_stereo_setup_eye(const orr_stereo_settings *stereo, const orr_camera_settings *camera,
                                const char *scene_path, orr_projection *proj, orr_render_report *rep,
                                orr_stereo_ods *ods, int *use_ods, orr_error *err)
{
    *use_ods = 0;
    if (!stereo->eye)
        return ORR_OK;
    orr_status st;
    if (orr_projection_traits_of(proj->settings.kind).off_axis_stereo) {
        rep->stereo_convergence = orr_stereo_convergence(stereo, camera, rep->camera.position);
        st = orr_stereo_perspective_eye(&rep->camera, proj, stereo->eye, stereo->eye_separation,
                                        rep->stereo_convergence, err);
    } else {
        st = orr_stereo_ods_setup(ods, proj, stereo->eye, stereo->eye_separation, stereo->zenith_fade, err);
        *use_ods = !st;
    }
    if (st)
        return orr_fail_prefix(err, "%s: %s eye: ", scene_path, orr_eye_name(stereo->eye));
    return ORR_OK;
}

/* ---- the picture of a pair ---- */

static void decode_srgb(const float *in, float *out, size_t n)
{
    for (size_t i = 0; i < n; i++)
        out[i] = (float)orr_srgb_decode(in[i]);
}

void orr_stereo_picture(orr_stereo_mode mode, orr_anaglyph_kind kind, const float *left, const float *right,
                        int width, int height, int rgb_linear, float *out, int *out_width, int *out_height)
{
    const size_t row = (size_t)width * 3, npix = (size_t)width * (size_t)height;
    if (mode == ORR_STEREO_ANAGLYPH) {
        /* The anaglyph mixes light, so it works on linear values: the left
         * eye's in out's first half, the right eye's in its second. */
        float *l = out, *r = out + 3 * npix;
        if (rgb_linear) {
            memcpy(l, left, 3 * npix * sizeof *l);
            memcpy(r, right, 3 * npix * sizeof *r);
        } else {
            decode_srgb(left, l, 3 * npix);
            decode_srgb(right, r, 3 * npix);
        }
        orr_anaglyph_compose(kind, l, r, npix, out);
        if (!rgb_linear)
            orr_srgb_encode_buffer(out, 3 * npix);
        *out_width = width;
        *out_height = height;
        return;
    }
    if (mode == ORR_STEREO_OVER_UNDER) {
        memcpy(out, left, 3 * npix * sizeof *out);
        memcpy(out + 3 * npix, right, 3 * npix * sizeof *out);
        *out_width = width;
        *out_height = 2 * height;
        return;
    }
    for (int j = 0; j < height; j++) { /* side by side */
        memcpy(out + 2 * row * j, left + row * j, row * sizeof *out);
        memcpy(out + 2 * row * j + row, right + row * j, row * sizeof *out);
    }
    *out_width = 2 * width;
    *out_height = height;
}

/* ---- writing a pair ---- */

/* Both eyes' planes, sharing their pixels, renamed left.NAME and right.NAME. */
static void pair_planes(const orr_stereo_pair *p, orr_plane out[6])
{
    for (int e = 0; e < 2; e++)
        for (int k = 0; k < p->nplanes; k++) {
            orr_plane *o = &out[e * p->nplanes + k];
            *o = p->planes[e][k];
            snprintf(o->name, sizeof o->name, "%s.%.*s", e == 0 ? "left" : "right",
                     (int)(sizeof o->name - 8), p->planes[e][k].name);
        }
}

static orr_status add_output(const orr_stereo_pair *p, const char *ext, orr_render_report *rep, const char **path,
                             orr_error *err)
{
    return p->stage(p->outputs, p->files, rep, ext, path, err);
}

/* Both eyes' compositing channels (render/exr_view.h) in one file, each
 * eye a layer: left.R, ..., right.A. */
static orr_status write_pair_exr(const orr_stereo_pair *p, const char *path, orr_error *err)
{
    orr_exr_view eyes[2];
    orr_status st = orr_exr_view_build(&eyes[0], p->planes[0], p->nplanes, p->proj, "left.", err);
    if (st)
        return st;
    st = orr_exr_view_build(&eyes[1], p->planes[1], p->nplanes, p->proj, "right.", err);
    if (!st) {
        orr_plane all[2 * ORR_EXR_VIEW_MAX];
        for (int e = 0; e < 2; e++)
            memcpy(all + e * eyes[0].n, eyes[e].channels, (size_t)eyes[e].n * sizeof all[0]);
        st = orr_exr_view_write(path, all, eyes[0].n + eyes[1].n, p->files->output.exr_half, p->meta, err);
        orr_exr_view_free(&eyes[1]);
    }
    orr_exr_view_free(&eyes[0]);
    return st;
}

static orr_status write_pair_planes(const orr_stereo_pair *p, orr_render_report *rep, orr_error *err)
{
    const view_files *f = p->files;
    orr_plane planes[6];
    pair_planes(p, planes);
    const char *path = NULL;
    orr_status st = ORR_OK;
    if (f->output.write_fits && !(st = add_output(p, "fits", rep, &path, err)) &&
        !(st = orr_write_fits_compressed(path, planes, 2 * p->nplanes, p->cards,
                                         (orr_fits_compression)f->output.fits_compress, err)))
        rep->noutputs++;
    if (!st && f->output.write_exr && !(st = add_output(p, "exr", rep, &path, err)) &&
        !(st = write_pair_exr(p, path, err)))
        rep->noutputs++;
    return st;
}

static orr_status write_pair_picture(const orr_stereo_pair *p, orr_render_report *rep, orr_error *err)
{
    const view_files *f = p->files;
    if (!p->rgb[0] || !p->rgb[1] || (!f->output.write_png && !f->output.image_ext[0]))
        return ORR_OK;
    size_t npix = (size_t)p->width * (size_t)p->height;
    float *pic = orr_malloc(2 * npix * 3 * sizeof *pic, "stereo picture", err);
    if (!pic)
        return ORR_ERR_NOMEM;
    int w, h;
    orr_stereo_picture(f->stereo_mode, f->picture.anaglyph, p->rgb[0], p->rgb[1], p->width, p->height, p->rgb_linear, pic, &w,
                       &h);
    char desc[ORR_PATH_MAX + 384];
    snprintf(desc, sizeof desc, "stereo %s%s%s: %s", orr_stereo_mode_name(f->stereo_mode),
             f->stereo_mode == ORR_STEREO_ANAGLYPH ? " " : "",
             f->stereo_mode == ORR_STEREO_ANAGLYPH ? orr_anaglyph_name(f->picture.anaglyph) : "", p->desc);
    const char *path = NULL;
    orr_status st = ORR_OK;
    if (f->output.write_png && !(st = add_output(p, "png", rep, &path, err))) {
        orr_png_text text[] = {{"Software", "orrery " ORRERY_VERSION}, {"Description", desc}};
        if (!(st = orr_write_png_rgb(path, w, h, pic, f->output.png_bits, text, 2, err)))
            rep->noutputs++;
    }
    if (!st && f->output.image_ext[0] && !(st = add_output(p, f->output.image_ext, rep, &path, err)) &&
        !(st = orr_write_image_rgb(path, pic, w, h, f->output.png_bits, p->meta, err)))
        rep->noutputs++;
    free(pic);
    return st;
}

orr_status orr_stereo_write_pair(const orr_stereo_pair *pair, orr_render_report *rep, orr_error *err)
{
    orr_status st = write_pair_planes(pair, rep, err);
    return st ? st : write_pair_picture(pair, rep, err);
}
