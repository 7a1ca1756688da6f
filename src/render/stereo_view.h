/* Stereo in the renderer (docs/stereo.md). A view with stereo.mode is
 * rendered as two eyes from one pass over the particles: the plan treats
 * each eye as a view of its own (a copy of the scene with stereo.eye set,
 * made by plan.c), so every chunk is splatted into both eyes' planes
 * before the next is read. This file holds what is particular to stereo:
 * naming the eyes' outputs, placing each eye's camera, the
 * omni-directional per-block transform's mask, and writing a pair as one
 * picture (side-by-side, over-under, anaglyph) with both eyes' planes in
 * FITS and EXR. */
#ifndef ORR_RENDER_STEREO_VIEW_H
#define ORR_RENDER_STEREO_VIEW_H

#include <stddef.h>
#include <stdint.h>

#include "encode/fits.h"
#include "encode/image_out.h"
#include "frame/camera_settings.h"
#include "frame/stereo.h"
#include "render/report.h"
#include "render/view_files.h"

/* Whether stereo mode m writes a pair as one picture (anaglyph,
 * side-by-side, over-under), not each eye as its own. */
int orr_stereo_is_pair_mode(orr_stereo_mode m);

/* The output name of eye (0: not an eye) of a view with stereo mode mode
 * named name: name-left or name-right when the eyes are written separately,
 * else name itself; an error (naming scene_path) when out (size bytes)
 * cannot hold it. */
orr_status orr_eye_output_name(orr_stereo_mode mode, const char *scene_path, const char *name, int eye, char *out,
                               size_t size, orr_error *err);

/* The convergence distance of a perspective pair whose centre camera is
 * at `position`: stereo.convergence, or with auto the distance to
 * camera.look_at. */
double orr_stereo_convergence(const orr_stereo_settings *stereo, const orr_camera_settings *camera,
                              orr_vec3 position);

/* Places the camera and projection of one eye (stereo->eye; a no-op when
 * 0; scene_path for messages): a perspective eye moves rep->camera and the
 * principal point (and sets rep->stereo_convergence); a sky map's eye sets
 * *use_ods and *ods for the per-block transform. proj must be set up and
 * rep->camera be the view's camera. */
orr_status orr_stereo_setup_eye(const orr_stereo_settings *stereo, const orr_camera_settings *camera,
                                const char *scene_path, orr_projection *proj, orr_render_report *rep,
                                orr_stereo_ods *ods, int *use_ods, orr_error *err);

/* How the driver adds output NAME.EXT of a view's files f to the frame's
 * outputs: the final path goes to rep->outputs[rep->noutputs] (counted by
 * the caller once written) and *write_path is the file to write now. */
typedef orr_status (*orr_output_stage_fn)(void *outputs, const view_files *f, orr_render_report *rep,
                                          const char *ext, const char **write_path, orr_error *err);

/* One stereo pair, ready to write as one picture. */
typedef struct orr_stereo_pair {
    const view_files *files;       /* the left eye's (its output.* keys apply) */
    const orr_plane *planes[2];    /* each eye's planes (linear, after the PSF) */
    int nplanes;                   /* per eye: 1, or X, Y, Z */
    int width, height;             /* of one eye's image */
    const float *rgb[2];           /* each eye's picture as graded for display, or NULL when
                                    * neither output.png nor output.image is asked for */
    int rgb_linear;                /* rgb holds linear values (colour with output.png_transfer: linear) */
    const orr_cards *cards;  /* the left eye's FITS cards */
    const orr_image_meta *meta;    /* for output.image and EXR */
    const char *desc;              /* what the picture shows, for PNG's Description */
    orr_output_stage_fn stage;
    void *outputs;                 /* the driver's list of the frame's outputs, for stage */
    const orr_projection *proj;    /* one eye's projection: the EXR's alpha */
} orr_stereo_pair;

/* The picture of a pair: side-by-side (2W x H, left eye on the left),
 * over-under (W x 2H, left eye on top) or a red-cyan anaglyph (W x H, from
 * the eyes' linear RGB: display-encoded sRGB input is decoded first and
 * the result encoded again). out has room for 2 W H * 3 values. */
void orr_stereo_picture(orr_stereo_mode mode, orr_anaglyph_kind kind, const float *left, const float *right,
                        int width, int height, int rgb_linear, float *out, int *out_width, int *out_height);

/* Writes the pair: NAME.fits (output.fits) and NAME.exr (output.exr) with
 * both eyes' planes, named left.NAME and right.NAME; NAME.png (output.png)
 * and NAME.EXT (output.image) with the picture of orr_stereo_picture.
 * Each file written is added to rep->outputs. */
orr_status orr_stereo_write_pair(const orr_stereo_pair *pair, orr_render_report *rep, orr_error *err);

#endif
