/* A rendered view's files: the planes masked off the map, FITS with the
 * frame's cards, the graded picture as PNG or another image format, EXR,
 * stereo pairs; each written to a temporary name in the frame's output
 * batch (encode/atomic.h), renamed with the frame's others. */
#include "render/view_state.h"
#include "core/numbers.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/atomic.h"
#include "encode/fits.h"
#include "encode/fits_read.h"
#include "encode/image_out.h"
#include "encode/png.h"
#include "post/brightness.h"
#include "post/colormap.h"
#include "post/grade.h"
#include "post/stretch.h"
#include "post/view_psf.h"
#include "render/exr_view.h"
#include "render/map_alpha.h"
#include "render/stereo_view.h"
#include "encode/wcs.h"
#include "scene/scene_output.h"


/* ---- outputs ---- */

void orr_view_add_frame_cards(const view_state *v, orr_fits_header *h)
{
    const orr_scene *s = v->scene;
    const orr_projection *p = &v->proj;
    const orr_render_report *rep = v->rep;
    const orr_camera *cam = &rep->camera;
    orr_fits_add_string(h, "CREATOR", "orrery " ORRERY_VERSION, "software that made this file");
    orr_fits_add_string(h, "ORRVERS", ORRERY_VERSION, "orrery version");
    orr_fits_add_string(h, "PROJTYPE", orr_projection_name(p->kind), "projection");
    if (p->kind == ORR_PROJ_ORTHOGRAPHIC)
        orr_fits_add_double(h, "ORTHOWID", p->ortho_width, "image width in simulation length units");
    if (p->kind == ORR_PROJ_PERSPECTIVE) {
        orr_fits_add_double(h, "FOV", p->fov_deg, "[deg] field of view along the wider axis");
        orr_fits_add_double(h, "NEAR", p->near, "near plane distance");
    }
    if (p->kind == ORR_PROJ_DOME) {
        orr_fits_add_double(h, "DOMEFOV", p->dome_fov_deg, "[deg] dome field of view");
        orr_fits_add_double(h, "DOMETILT", s->dome_tilt, "[deg] dome tilt toward the front");
        if (s->dome_profile[0])
            orr_fits_add_string(h, "DOMEPROF", s->dome_profile, "dome profile");
    }
    orr_fits_add_double(h, "CAMPOSX", cam->position.x, "camera position x");
    orr_fits_add_double(h, "CAMPOSY", cam->position.y, "camera position y");
    orr_fits_add_double(h, "CAMPOSZ", cam->position.z, "camera position z");
    orr_fits_add_double(h, "CAMQW", cam->orientation.w, "camera-to-world quaternion w");
    orr_fits_add_double(h, "CAMQX", cam->orientation.x, "camera-to-world quaternion x");
    orr_fits_add_double(h, "CAMQY", cam->orientation.y, "camera-to-world quaternion y");
    orr_fits_add_double(h, "CAMQZ", cam->orientation.z, "camera-to-world quaternion z");
    orr_fits_add_long(h, "IMGWIDTH", p->width, "[pixel] image width");
    orr_fits_add_long(h, "IMGHEIGH", p->height, "[pixel] image height");
    orr_fits_add_string(h, "DEPOSIT", orr_deposit_name(s->deposit), "deposit method");
    if (v->use_sph) {
        orr_fits_add_string(h, "KERNEL", orr_kernel_name(s->kernel), "SPH kernel (support 2h)");
        orr_fits_add_string(h, "HSOURCE", v->lengths ? "neighbours" : "file", "where smoothing lengths came from");
        if (v->lengths)
            orr_fits_add_long(h, "NNEIGH", s->neighbours, "h = half the distance to this neighbour");
        orr_fits_add_double(h, "HSCALE", s->h_scale, "smoothing lengths multiplied by this");
    }
    orr_fits_add_string(h, "PSF", orr_named_name(orr_psf_kind_names, (int)s->psf), "point spread function");
    if (s->psf == ORR_PSF_GAUSSIAN && orr_projection_is_sky(p))
        orr_fits_add_double(h, "PSFFWHM", v->psf.core_fwhm_arcmin, "[arcmin] PSF FWHM on the sky");
    else if (s->psf == ORR_PSF_GAUSSIAN)
        orr_fits_add_double(h, "PSFFWHM", s->psf_fwhm, "[pixel] PSF FWHM");
    else if (s->psf != ORR_PSF_NONE)
        orr_fits_add_double(h, "PSFSCALE", s->psf_arcsec_per_pixel, "[arcsec/pixel] image scale for the PSF");
    if (v->psf.core) {
        orr_fits_add_double(h, "PSFFWHM", s->psf_fwhm, "[pixel] the PSF core's FWHM");
        orr_fits_add_double(h, "PSFMAG", v->psf.sky->rad_per_pixel, "image pixels per PSF pixel");
        orr_fits_add_long(h, "PSFSTARS", v->psf.sky->stars_drawn, "stars drawn with the whole PSF");
    } else if (v->psf.sky) {
        orr_fits_add_double(h, "PSFFWHM", v->psf.core_fwhm_arcmin, "[arcmin] the PSF core's FWHM on the sky");
        orr_fits_add_double(h, "PSFSKYSC", v->psf.sky->rad_per_pixel * (180.0 * 3600.0 / ORR_PI),
                            "[arcsec] one PSF pixel on the sky");
        orr_fits_add_long(h, "PSFSTARS", v->psf.sky->stars_drawn, "stars drawn with the whole PSF");
    }
    orr_fits_add_string(h, "WEIGHT", s->weight, "particle field deposited");
    orr_fits_add_long(h, "NPART", (long long)rep->n_read, "particles read");
    orr_fits_add_long(h, "NSELECT", (long long)rep->n_selected, "particles of the selected types");
    orr_fits_add_long(h, "NSKIPPED", (long long)rep->n_nonfinite, "particles skipped as non-finite");
    orr_fits_add_long(h, "NCULLED", (long long)rep->deposit.n_culled, "particles not drawn (out of view)");
    if (rep->n_replicas) {
        orr_fits_add_double(h, "PERBOX", v->periodic.box, "periodic box side, drawn in copies");
        orr_fits_add_long(h, "NREPLIC", rep->n_replicas, "copies of the periodic box drawn");
        orr_fits_add_long(h, "NBLKCULL", (long long)rep->n_blocks_culled, "copies of blocks culled out of view");
    }
    orr_fits_add_double(h, "WIMAGE", rep->deposit.deposited, "weight deposited in the image");
    orr_fits_add_double(h, "WOUTSIDE", rep->deposit.outside, "weight that fell off the image");
    if (s->colour) {
        orr_fits_add_long(h, "NPOPS", s->populations.n, "colour populations");
        orr_fits_add_double(h, "YIMAGE", rep->deposit_y.deposited, "luminance Y deposited in the image");
        orr_fits_add_double(h, "YOUTSIDE", rep->deposit_y.outside, "luminance Y that fell off the image");
    }
    orr_fits_add_double(h, "SIMTIME", rep->sim_time, "simulation time of the snapshot");
    if (rep->nframes > 1) {
        orr_fits_add_long(h, "FRAME", rep->frame, "frame number (0-based)");
        orr_fits_add_long(h, "NFRAMES", rep->nframes, "frames in the run");
    }
    const char *slash = strrchr(rep->source, '/');
    orr_fits_add_string(h, "SOURCE", slash ? slash + 1 : rep->source, "particle source");
    if (s->has_observer) {
        orr_fits_add_long(h, "OBSID", (long long)s->observer_id, "observer particle id");
        orr_fits_add_long(h, "REFID", (long long)s->reference_id, "reference particle id (l = 0)");
        orr_fits_add_double(h, "NORMX", rep->sky.z.x, "disc normal n0 (b = 90) x");
        orr_fits_add_double(h, "NORMY", rep->sky.z.y, "disc normal n0 (b = 90) y");
        orr_fits_add_double(h, "NORMZ", rep->sky.z.z, "disc normal n0 (b = 90) z");
        orr_fits_add_bool(h, "DIMMED", s->dim, "weights divided by r^2 from the observer");
    } else if (s->camera_dim) {
        orr_fits_add_bool(h, "DIMMED", 1, "weights divided by r^2 from the camera");
    }
    orr_wcs_view wcs = {p, cam, &rep->sky, rep->has_sky_frame, scene_length_unit(s)};
    orr_wcs_add_cards(h, &wcs);
    h->scene = s->scene_yaml; /* every FITS file says how it was made */
    if (s->stereo)
        orr_stereo_add_cards(h, s, rep);
}

/* How the view's planes become its picture (post/grade.h): the colour
 * synthesis of X, Y, Z planes (colour populations, compose layers), a
 * weight plane in colour.tint's colour, or a weight plane stretched and
 * colour-mapped. */
static orr_grade view_grade(const view_state *v)
{
    const orr_scene *s = v->scene;
    orr_grade g = {s->colour || s->nlayers ? ORR_GRADE_SYNTHESIS : s->has_tint ? ORR_GRADE_TINT : ORR_GRADE_COLORMAP,
                   &s->synth, &s->tint, v->tint_t, s->png_linear, &s->stretch, s->colormap};
    return g;
}

/* The view's picture, sRGB-encoded RGB (post/grade.h); desc says how it
 * was made. */
orr_status orr_view_graded_rgb(const view_state *v, float *rgb, char *desc, size_t size, orr_error *err)
{
    const orr_scene *s = v->scene;
    orr_render_report *rep = v->rep;
    const orr_grade g = view_grade(v);
    orr_status st = orr_grade_picture(&g, v->planes, rgb, &rep->white, err);
    if (st)
        return st;
    if (s->nlayers)
        orr_snprintf(desc, size, "colour (CIE XYZ) blended from %d layers, %s projection, %s stretch, Y0 %g",
                     s->nlayers, orr_projection_name(v->proj.kind), orr_lum_stretch_name(s->synth.stretch),
                     rep->white);
    else if (s->colour)
        orr_snprintf(desc, size, "colour (CIE XYZ, %d populations) of %s, %s projection, %s stretch, Y0 %g",
                     s->populations.n, rep->source, orr_projection_name(v->proj.kind),
                     orr_lum_stretch_name(s->synth.stretch), rep->white);
    else if (s->has_tint)
        orr_snprintf(desc, size, "%s of %s tinted at t = %g of its colour path, %s projection, %s stretch, Y0 %g",
                     s->weight, rep->source, v->tint_t, orr_projection_name(v->proj.kind),
                     orr_lum_stretch_name(s->synth.stretch), rep->white);
    else
        orr_snprintf(desc, size, "%s of %s, %s projection, %s stretch, white %g, colour map %s", s->weight,
                     rep->source, orr_projection_name(v->proj.kind), orr_stretch_name(s->stretch.kind), rep->white,
                     orr_colormap_name(s->colormap));
    return ORR_OK;
}

static orr_status view_output(view_state *v, const char *ext, const char **write_path, orr_error *err);

/* What the other image formats record: the scene, projection, time, camera. */
/* Strings a view's metadata borrows: the description and the projection's
 * parameters as orrery's own attributes (docs/formats-out.md). */
typedef struct view_meta_text {
    const char *keys[4], *values[4];
    char numbers[3][32];
} view_meta_text;

/* The projection's parameters a file should carry: what orrery alone
 * defines (sky maps, orthographic), and for a perspective view OpenEXR's
 * screen window. */
static void projection_meta(const orr_projection *p, orr_image_meta *m, view_meta_text *t)
{
    const char *key = NULL;
    double value = 0;
    switch (p->kind) {
    case ORR_PROJ_ORTHOGRAPHIC: key = "orthoWidth", value = p->ortho_width; break;
    case ORR_PROJ_PERSPECTIVE:
        key = "fieldOfViewDeg", value = p->fov_deg;
        m->has_screen_window = 1;
        m->screen_window_width = p->width / p->focal;
        m->screen_window_center[0] = -p->shift_x / p->focal;
        m->screen_window_center[1] = 0;
        break;
    case ORR_PROJ_DOME: key = "domeFieldOfViewDeg", value = p->dome_fov_deg; break;
    case ORR_PROJ_HEALPIX: key = "healpixNside", value = p->healpix_nside; break;
    default: break;
    }
    if (key) {
        snprintf(t->numbers[0], sizeof t->numbers[0], "%.17g", value);
        t->keys[m->nextra] = key;
        t->values[m->nextra++] = t->numbers[0];
    }
    if (orr_projection_is_sky(p)) {
        t->keys[m->nextra] = "longitudeGrows";
        t->values[m->nextra++] = p->lon_sign > 0 ? "right" : "left"; /* dome, HEALPix: always left */
    }
}

static orr_image_meta view_meta(const view_state *v, const char *desc, view_meta_text *t)
{
    const orr_camera *cam = &v->rep->camera;
    orr_image_meta m = {0};
    m.scene = v->scene->out_name;
    m.projection = orr_projection_name(v->proj.kind);
    m.has_time = 1;
    m.time = v->rep->sim_time;
    m.has_camera = 1;
    m.cam_pos[0] = cam->position.x;
    m.cam_pos[1] = cam->position.y;
    m.cam_pos[2] = cam->position.z;
    m.cam_quat[0] = cam->orientation.w;
    m.cam_quat[1] = cam->orientation.x;
    m.cam_quat[2] = cam->orientation.y;
    m.cam_quat[3] = cam->orientation.z;
    t->keys[0] = "description";
    t->values[0] = desc;
    m.nextra = 1;
    projection_meta(&v->proj, &m, t);
    for (int k = 0; k < m.nextra; k++) {
        m.extra_key[k] = t->keys[k];
        m.extra_value[k] = t->values[k];
    }
    return m;
}

/* The graded picture as PNG (output.png) and as output.image (any format
 * OpenImageIO writes, by extension). */
orr_status orr_view_write_pictures(view_state *v, orr_error *err)
{
    const orr_scene *s = v->scene;
    orr_render_report *rep = v->rep;
    if (!s->write_png && !s->image_ext[0])
        return ORR_OK;
    size_t npix = (size_t)v->proj.width * (size_t)v->proj.height;
    float *rgb = orr_malloc(npix * 3 * sizeof(float), "picture pixels", err);
    if (!rgb)
        return ORR_ERR_NOMEM;
    char desc[ORR_PATH_MAX + 256];
    orr_status st = orr_view_graded_rgb(v, rgb, desc, sizeof desc, err);
    float *rgba = NULL; /* output.alpha_mask: the picture, transparent off the map */
    if (!st && s->alpha_mask)
        st = orr_map_rgba(&v->proj, rgb, &rgba, err);
    charge(v, ORR_STAGE_POST);
    const char *path;
    if (!st && s->write_png) {
        orr_png_text text[] = {{"Software", "orrery " ORRERY_VERSION}, {"Description", desc}};
        if (!(st = view_output(v, "png", &path, err)) &&
            !(st = orr_write_png(path, v->proj.width, v->proj.height, rgba ? rgba : rgb, rgba ? 4 : 3,
                                 s->png_bits, text, 2, err)))
            rep->noutputs++;
        charge(v, ORR_STAGE_PNG);
    }
    if (!st && s->image_ext[0]) {
        view_meta_text text;
        orr_image_meta meta = view_meta(v, desc, &text);
        if (!(st = view_output(v, s->image_ext, &path, err)) &&
            !(st = orr_write_image_picture(path, rgb, rgba, v->proj.width, v->proj.height, s->png_bits, &meta, err)))
            rep->noutputs++;
        charge(v, ORR_STAGE_IMAGE);
    }
    free(rgba);
    free(rgb);
    return st;
}

/* The linear planes as OpenEXR (output.exr), float, as compositors read it:
 * R, G, B, A and the layer xyz, or Y and A (render/exr_view.h). */
static orr_status write_exr(view_state *v, const orr_plane *av, orr_error *err)
{
    orr_render_report *rep = v->rep;
    const char *path;
    view_meta_text text;
    orr_image_meta meta = view_meta(v, "linear planes", &text);
    orr_exr_view ev;
    orr_status st = view_output(v, "exr", &path, err);
    if (!st && !(st = orr_exr_view_build(&ev, v->planes, v->nplanes, &v->proj, "", err))) {
        if (av)
            st = orr_exr_view_add(&ev, av, &v->proj, "extinction.A_V", err);
        if (!st)
            st = orr_exr_view_write(path, ev.channels, ev.n, v->scene->exr_half, &meta, err);
        orr_exr_view_free(&ev);
    }
    if (!st)
        rep->noutputs++;
    charge(v, ORR_STAGE_EXR);
    return st;
}

orr_status orr_view_output_path(const orr_scene *s, const char *ext, char *path, orr_error *err)
{
    int n = snprintf(path, ORR_PATH_MAX, "%s/%s.%s", s->out_dir, s->out_name, ext);
    if (n < 0 || n >= ORR_PATH_MAX)
        return orr_fail(err, ORR_ERR_USAGE, "output path %s/%s.%s is too long", s->out_dir, s->out_name, ext);
    return ORR_OK;
}

/* The output NAME.ext of scene s, added to the frame's outputs: its final
 * path goes into the report (not yet counted), and *write_path is where to
 * write it until the frame's outputs are all written. */
static orr_status stage_output(void *outputs, const orr_scene *s, orr_render_report *rep, const char *ext,
                               const char **write_path, orr_error *err)
{
    if (rep->noutputs >= ORR_RENDER_MAX_OUTPUTS)
        return orr_fail(err, ORR_ERR_INTERNAL, "too many outputs for one view");
    char *final_path = rep->outputs[rep->noutputs];
    orr_status st = orr_view_output_path(s, ext, final_path, err);
    return st ? st : orr_output_batch_add(outputs, final_path, write_path, err);
}

static orr_status view_output(view_state *v, const char *ext, const char **write_path, orr_error *err)
{
    return stage_output(v->outputs, v->scene, v->rep, ext, write_path, err);
}

/* Writes the view's planes, with the frame's cards, to NAME.EXT. */
orr_status orr_view_write_fits_planes(view_state *v, const char *ext, orr_error *err)
{
    orr_render_report *rep = v->rep;
    const char *path;
    orr_fits_header *h = orr_calloc(1, sizeof *h, "FITS header", err);
    if (!h)
        return ORR_ERR_NOMEM;
    orr_view_add_frame_cards(v, h);
    orr_status st = view_output(v, ext, &path, err);
    if (!st && v->proj.kind == ORR_PROJ_HEALPIX) {
        orr_wcs_view wcs = {&v->proj, &rep->camera, &rep->sky, rep->has_sky_frame, ""};
        orr_healpix_info info = {v->proj.healpix_nside, v->proj.healpix_nested, orr_wcs_healpix_coordsys(&wcs)};
        st = orr_write_healpix_fits(path, v->planes, fits_nplanes(v), &info, h, err);
    } else if (!st) {
        /* The raw planes stay uncompressed: orrery compose reads them. */
        orr_fits_compression c = strcmp(ext, "fits") == 0 ? (orr_fits_compression)v->scene->fits_compress
                                                           : ORR_FITS_UNCOMPRESSED;
        st = orr_write_fits_compressed(path, v->planes, fits_nplanes(v), h, c, err);
    }
    free(h);
    if (!st)
        rep->noutputs++;
    charge(v, ORR_STAGE_FITS);
    return st;
}

/* dust.extinction_plane: A_V to infinity per pixel (dust/dust.h), made once
 * for the FITS file and the EXR layer. */
static orr_status extinction_plane(view_state *v, orr_plane *av, orr_error *err)
{
    const orr_mat3 *r = &v->world_to_camera;
    orr_dust_eye eye = {v->rep->camera.position, v->proj.kind == ORR_PROJ_ORTHOGRAPHIC,
                        orr_v3(r->m[2][0], r->m[2][1], r->m[2][2])};
    return orr_dust_av_plane(v->dust, &eye, &v->proj, r, av, err);
}

/* The extinction plane as NAME.extinction.fits beside the light planes,
 * with the view's cards. */
static orr_status write_extinction(view_state *v, const orr_plane *av, orr_error *err)
{
    const char *path;
    orr_fits_header *h = orr_calloc(1, sizeof *h, "FITS header", err);
    orr_status st = h ? ORR_OK : ORR_ERR_NOMEM;
    if (!st) {
        orr_view_add_frame_cards(v, h);
        st = view_output(v, "extinction.fits", &path, err);
    }
    if (!st)
        st = orr_write_fits(path, av, 1, h, err);
    if (!st)
        v->rep->noutputs++;
    free(h);
    return st;
}

/* A stereo pair written as one picture (render/stereo_view.h): the right
 * eye (view k + 1 of eyes) is graded with the left eye's white level. */
orr_status orr_view_write_stereo_pair(view_state *l, view_state *r, orr_eye_views *eyes, int k, orr_error *err)
{
    const orr_scene *s = l->scene;
    orr_mask_outside_map(&l->proj, l->planes, l->nplanes);
    orr_mask_outside_map(&r->proj, r->planes, r->nplanes);
    size_t npix = (size_t)l->proj.width * (size_t)l->proj.height;
    int want_rgb = s->write_png || s->image_ext[0];
    float *rgb = want_rgb ? orr_malloc(2 * npix * 3 * sizeof *rgb, "stereo pictures", err) : NULL;
    orr_fits_header *h = orr_calloc(1, sizeof *h, "FITS header", err);
    orr_status st = !h || (want_rgb && !rgb) ? ORR_ERR_NOMEM : ORR_OK;
    char desc[ORR_PATH_MAX + 256] = "stereo pair", rdesc[ORR_PATH_MAX + 256];
    if (!st && want_rgb)
        st = orr_view_graded_rgb(l, rgb, desc, sizeof desc, err);
    if (!st && want_rgb) {
        orr_eye_views_share_white(eyes, k, l->rep->white);
        st = orr_view_graded_rgb(r, rgb + 3 * npix, rdesc, sizeof rdesc, err);
    }
    charge(l, ORR_STAGE_POST);
    if (!st) {
        orr_view_add_frame_cards(l, h);
        view_meta_text text;
        orr_image_meta meta = view_meta(l, desc, &text);
        /* One file holds both eyes, each shifted its own way: no one
         * screen window is right for it. */
        meta.has_screen_window = 0;
        orr_stereo_pair pair = {
            .scene = s, .planes = {l->planes, r->planes}, .nplanes = l->nplanes,
            .width = l->proj.width, .height = l->proj.height,
            .rgb = {want_rgb ? rgb : NULL, want_rgb ? rgb + 3 * npix : NULL},
            .rgb_linear = (s->colour || s->nlayers || s->has_tint) && s->png_linear,
            .cards = h, .meta = &meta, .desc = desc, .stage = stage_output, .outputs = l->outputs,
            .proj = &l->proj,
        };
        st = orr_stereo_write_pair(&pair, l->rep, err);
        charge(l, ORR_STAGE_STEREO);
    }
    free(rgb);
    free(h);
    return st;
}

orr_status orr_view_write_outputs(view_state *v, orr_error *err)
{
    const orr_scene *s = v->scene;
    orr_mask_outside_map(&v->proj, v->planes, v->nplanes);
    charge(v, ORR_STAGE_POST);
    orr_plane av = {0};
    int want_av = v->dust && s->dust.extinction_plane;
    orr_status st = want_av ? extinction_plane(v, &av, err) : ORR_OK;
    if (!st && s->write_fits)
        st = orr_view_write_fits_planes(v, "fits", err);
    if (!st && s->write_exr)
        st = write_exr(v, want_av ? &av : NULL, err);
    if (!st && want_av)
        st = write_extinction(v, &av, err);
    if (!st)
        st = orr_view_write_pictures(v, err);
    orr_plane_free(&av);
    return st;
}

