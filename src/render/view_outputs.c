/* A rendered view's files: the planes masked off the map, FITS with the
 * frame's cards, the graded picture as PNG or another image format, EXR,
 * stereo pairs; each written to a temporary name in the frame's output
 * batch (encode/atomic.h), renamed with the frame's others. */
#include "render/view_state.h"
#include "core/numbers.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/atomic.h"
#include "core/srgb_code.h"
#include "encode/fits.h"
#include "encode/fits_read.h"
#include "encode/image_out.h"
#include "encode/png.h"
#include "encode/view_meta.h"
#include "post/brightness.h"
#include "post/colormap.h"
#include "post/grade.h"
#include "post/stretch.h"
#include "post/view_psf.h"
#include "render/exr_view.h"
#include "render/map_alpha.h"
#include "render/stereo_view.h"
#include "encode/wcs.h"


/* ---- outputs ---- */

/* How the view's planes become its picture (post/grade.h): the colour
 * synthesis of X, Y, Z planes (colour populations, compose layers), a
 * weight plane in colour.tint's colour, or a weight plane stretched and
 * colour-mapped. */
static orr_grade view_grade(const view_state *v)
{
    const view_files *f = &v->files;
    orr_grade g = {f->colour.has_populations || f->compose.nlayers ? ORR_GRADE_SYNTHESIS : f->colour.has_tint ? ORR_GRADE_TINT : ORR_GRADE_COLORMAP,
                   &f->colour.synth, &f->colour.tint, v->tint_t, f->output.png_linear, &f->picture.stretch, f->picture.colormap};
    return g;
}

/* Begins grading the view's picture (post/grade.h): its white level goes
 * into the report, and desc says how the picture is made. */
static orr_status begin_grade(const view_state *v, orr_graded *gr, char *desc, size_t size, orr_error *err)
{
    const view_files *f = &v->files;
    orr_render_report *rep = v->rep;
    const orr_grade g = view_grade(v);
    orr_status st = orr_grade_begin(&g, v->pass.planes, gr, err);
    if (st)
        return st;
    rep->white = gr->white;
    if (f->compose.nlayers)
        orr_snprintf(desc, size, "colour (CIE XYZ) blended from %d layers, %s projection, %s stretch, Y0 %g",
                     f->compose.nlayers, orr_projection_name(v->pass.proj.settings.kind),
                     orr_lum_stretch_name(f->colour.synth.stretch), rep->white);
    else if (f->colour.has_populations)
        orr_snprintf(desc, size, "colour (CIE XYZ, %d populations) of %s, %s projection, %s stretch, Y0 %g",
                     f->colour.populations.n, rep->source, orr_projection_name(v->pass.proj.settings.kind),
                     orr_lum_stretch_name(f->colour.synth.stretch), rep->white);
    else if (f->colour.has_tint)
        orr_snprintf(desc, size, "%s of %s tinted at t = %g of its colour path, %s projection, %s stretch, Y0 %g",
                     f->weight, rep->source, v->tint_t, orr_projection_name(v->pass.proj.settings.kind),
                     orr_lum_stretch_name(f->colour.synth.stretch), rep->white);
    else
        orr_snprintf(desc, size, "%s of %s, %s projection, %s stretch, white %g, colour map %s", f->weight, rep->source,
                     orr_projection_name(v->pass.proj.settings.kind), orr_stretch_name(f->picture.stretch.kind),
                     rep->white, orr_colormap_name(f->picture.colormap));
    return ORR_OK;
}

/* The view's picture, sRGB-encoded RGB (post/grade.h); desc says how it
 * was made. */
orr_status orr_view_graded_rgb(const view_state *v, float *rgb, char *desc, size_t size, orr_error *err)
{
    orr_graded gr;
    orr_status st = begin_grade(v, &gr, desc, size, err);
    if (!st)
        orr_graded_picture(&gr, rgb);
    return st;
}

static orr_status view_output(view_state *v, const char *ext, const char **write_path, orr_error *err);

/* What the other image formats record (encode/view_meta.h): the scene,
 * projection, time, camera, and desc. */
static orr_image_meta view_meta(const view_state *v, const char *desc, orr_view_meta_text *t)
{
    return orr_view_image_meta(v->files.output.name, &v->pass.proj, v->rep->sim_time, &v->rep->camera, desc, t);
}

/* The PNG encoder's rows (encode/png_idat.h) graded as it asks for them,
 * each with its alpha when output.alpha_mask wants one (the values
 * orr_map_rgba gives the whole picture). */
typedef struct picture_rows {
    const orr_graded *graded;
    const orr_projection *proj;
    int alpha, bits;
} picture_rows;

static void picture_row(void *ctx, int y, float *scratch, uint16_t *codes)
{
    const picture_rows *p = ctx;
    orr_graded_row_codes(p->graded, y, p->bits, scratch, codes);
    if (!p->alpha)
        return;
    /* From RGB to RGBA in place, from the end: pixel i's four codes start
     * at 4 i, after the three of every pixel before it, still unread. The
     * alpha is the pixel's coverage of the map, coded as the colours are
     * (into scratch, which the grading is done with). */
    float *coverage = scratch;
    orr_map_row_coverage(p->proj, y, coverage);
    for (int i = p->proj->width - 1; i >= 0; i--) {
        uint16_t r = codes[3 * i], g = codes[3 * i + 1], b = codes[3 * i + 2], alpha;
        orr_codes_of(&coverage[i], 1, p->bits, &alpha);
        codes[4 * i] = coverage[i] > 0 ? r : 0;
        codes[4 * i + 1] = coverage[i] > 0 ? g : 0;
        codes[4 * i + 2] = coverage[i] > 0 ? b : 0;
        codes[4 * i + 3] = alpha;
    }
}

/* The graded picture as PNG (output.png) and as output.image (any format
 * OpenImageIO writes, by extension). Only output.image needs the picture
 * whole: the PNG alone is graded a row at a time as it is encoded (its
 * grading is then charged to the png stage), so a frame never holds a
 * float copy of its picture, 800 MB at 8192^2. */
orr_status orr_view_write_pictures(view_state *v, orr_error *err)
{
    const view_files *f = &v->files;
    orr_render_report *rep = v->rep;
    if (!f->output.write_png && !f->output.image_ext[0])
        return ORR_OK;
    char desc[ORR_PATH_MAX + 256];
    orr_graded gr;
    orr_status st = begin_grade(v, &gr, desc, sizeof desc, err);
    float *rgb = NULL, *rgba = NULL; /* rgba: output.alpha_mask, transparent off the map */
    if (!st && f->output.image_ext[0]) {
        size_t npix = (size_t)v->pass.proj.width * (size_t)v->pass.proj.height;
        rgb = orr_malloc(npix * 3 * sizeof(float), "picture pixels", err);
        st = rgb ? ORR_OK : ORR_ERR_NOMEM;
        if (rgb)
            orr_graded_picture(&gr, rgb);
        if (!st && f->output.alpha_mask)
            st = orr_map_rgba(&v->pass.proj, rgb, &rgba, err);
    }
    charge(v, ORR_STAGE_POST);
    const char *path;
    if (!st && f->output.write_png) {
        orr_png_text text[] = {{"Software", "orrery " ORRERY_VERSION}, {"Description", desc}};
        picture_rows rows = {&gr, &v->pass.proj, f->output.alpha_mask, f->output.png_bits};
        int channels = f->output.alpha_mask ? 4 : 3;
        orr_png_rows src = {v->pass.proj.width, v->pass.proj.height, channels, f->output.png_bits, rgba ? rgba : rgb,
                            picture_row, &rows};
        if (!(st = view_output(v, "png", &path, err)) && !(st = orr_write_png_rows(path, &src, text, 2, err)))
            rep->noutputs++;
        charge(v, ORR_STAGE_PNG);
    }
    if (!st && f->output.image_ext[0]) {
        orr_view_meta_text text;
        orr_image_meta meta = view_meta(v, desc, &text);
        if (!(st = view_output(v, f->output.image_ext, &path, err)) &&
            !(st = orr_write_image_picture(path, rgb, rgba, v->pass.proj.width, v->pass.proj.height, f->output.png_bits,
                                           &meta, err)))
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
    orr_view_meta_text text;
    orr_image_meta meta = view_meta(v, "linear planes", &text);
    orr_exr_view ev;
    orr_status st = view_output(v, "exr", &path, err);
    if (!st && !(st = orr_exr_view_build(&ev, v->pass.planes, v->pass.nplanes, &v->pass.proj, "", err))) {
        if (av)
            st = orr_exr_view_add(&ev, av, &v->pass.proj, "extinction.V", err); /* A_V: V is the band */
        if (!st)
            st = orr_exr_view_write(path, ev.channels, ev.n, v->files.output.exr_half, &meta, err);
        orr_exr_view_free(&ev);
    }
    if (!st)
        rep->noutputs++;
    charge(v, ORR_STAGE_EXR);
    return st;
}

orr_status orr_view_output_path(const orr_output_settings *o, const char *ext, char *path, orr_error *err)
{
    int n = snprintf(path, ORR_PATH_MAX, "%s/%s.%s", o->dir, o->name, ext);
    if (n < 0 || n >= ORR_PATH_MAX)
        return orr_fail(err, ORR_ERR_USAGE, "output path %s/%s.%s is too long", o->dir, o->name, ext);
    return ORR_OK;
}

/* The output NAME.ext of a view's files f, added to the frame's outputs:
 * its final path goes into the report (not yet counted), and *write_path
 * is where to write it until the frame's outputs are all written. */
static orr_status stage_output(void *outputs, const view_files *f, orr_render_report *rep, const char *ext,
                               const char **write_path, orr_error *err)
{
    if (rep->noutputs >= ORR_RENDER_MAX_OUTPUTS)
        return orr_fail(err, ORR_ERR_INTERNAL, "too many outputs for one view");
    char *final_path = rep->outputs[rep->noutputs];
    orr_status st = orr_view_output_path(&f->output, ext, final_path, err);
    return st ? st : orr_output_batch_add(outputs, final_path, write_path, err);
}

static orr_status view_output(view_state *v, const char *ext, const char **write_path, orr_error *err)
{
    return stage_output(v->outputs, &v->files, v->rep, ext, write_path, err);
}

orr_healpix_info orr_view_healpix_info(const view_state *v)
{
    orr_wcs_view wcs = {&v->pass.proj, &v->rep->camera, &v->rep->sky, v->rep->has_sky_frame, ""};
    const orr_projection_settings *map = &v->pass.proj.settings;
    return (orr_healpix_info){map->healpix_nside, map->healpix_nested, orr_wcs_healpix_coordsys(&wcs)};
}

/* The view's planes, with the frame's cards, written to path: a HEALPix
 * map's as its table, any other's as images. Reads the view only, so it may
 * run beside the pictures' encoding (fits_writer). */
static orr_status write_planes_to(const view_state *v, const char *ext, const char *path, orr_error *err)
{
    const orr_cards *h = &v->frame_cards;
    if (orr_projection_traits_of(v->pass.proj.settings.kind).pixel_table) {
        orr_healpix_info info = orr_view_healpix_info(v);
        return orr_write_healpix_fits(path, v->pass.planes, fits_nplanes(v), &info, h, err);
    }
    /* The raw planes stay uncompressed: orrery compose reads them. */
    orr_fits_compression c = strcmp(ext, "fits") == 0 ? (orr_fits_compression)v->files.output.fits_compress
                                                       : ORR_FITS_UNCOMPRESSED;
    return orr_write_fits_compressed(path, v->pass.planes, fits_nplanes(v), h, c, err);
}

/* Writes the view's planes, with the frame's cards, to NAME.EXT. */
orr_status orr_view_write_fits_planes(view_state *v, const char *ext, orr_error *err)
{
    const char *path;
    orr_status st = view_output(v, ext, &path, err);
    if (!st)
        st = write_planes_to(v, ext, path, err);
    if (!st)
        v->rep->noutputs++;
    charge(v, ORR_STAGE_FITS);
    return st;
}

/* NAME.fits written on a thread of its own while the view's pictures are
 * graded and encoded. Writing it is mostly the kernel copying the planes
 * into the page cache on one core (805 MB at 8192^2), while the PNG's
 * grading and deflate run on every thread: side by side the frame takes
 * about the longer of the two rather than their sum. */
typedef struct fits_writer {
    const view_state *v;
    char path[ORR_PATH_MAX];
    pthread_t thread;
    int started;
    orr_status st;
    orr_error err;
    double cpu;             /* the thread's own CPU seconds */
    orr_stage_times before; /* the frame's timings when it started */
} fits_writer;

static void *fits_writer_run(void *arg)
{
    fits_writer *w = arg;
    double cpu0 = orr_thread_cpu_seconds();
    w->st = write_planes_to(w->v, "fits", w->path, &w->err);
    w->cpu = orr_thread_cpu_seconds() - cpu0;
    return NULL;
}

/* Stages NAME.fits among the frame's outputs and starts its thread (or,
 * when no thread can be had or cfitsio is not thread-safe, writes it here
 * and now). */
static orr_status fits_writer_start(view_state *v, fits_writer *w, orr_error *err)
{
    memset(w, 0, sizeof *w);
    w->v = v;
    const char *path;
    orr_status st = view_output(v, "fits", &path, err);
    if (st)
        return st;
    v->rep->noutputs++; /* its slot in the report, before the pictures take the next */
    snprintf(w->path, sizeof w->path, "%s", path);
    if (v->pass.timer)
        w->before = v->pass.timer->times;
    w->started = orr_fits_thread_safe() && pthread_create(&w->thread, NULL, fits_writer_run, w) == 0;
    if (w->started)
        return ORR_OK;
    fits_writer_run(w);
    charge(v, ORR_STAGE_FITS);
    if (w->st)
        *err = w->err;
    return w->st;
}

/* Waits for the thread; its time goes to the fits stage, its CPU taken
 * off the stages charged meanwhile (core/timings.h). st is the frame's
 * status so far: the FITS file's failure is reported when nothing else
 * failed first. */
static orr_status fits_writer_finish(view_state *v, fits_writer *w, orr_status st, orr_error *err)
{
    if (!w->started)
        return st;
    pthread_join(w->thread, NULL);
    charge(v, ORR_STAGE_FITS); /* the wait */
    if (v->pass.timer)
        orr_stage_charge_beside(&v->pass.timer->times, &w->before, ORR_STAGE_FITS, w->cpu);
    if (!st && w->st)
        *err = w->err;
    return st ? st : w->st;
}

/* dust.extinction_plane: A_V to infinity per pixel (dust/dust.h), made once
 * for the FITS file and the EXR layer. */
static orr_status extinction_plane(view_state *v, orr_plane *av, orr_error *err)
{
    const orr_mat3 *r = &v->pass.world_to_camera;
    orr_dust_eye eye = {v->rep->camera.position, orr_projection_traits_of(v->pass.proj.settings.kind).parallel,
                        orr_v3(r->m[2][0], r->m[2][1], r->m[2][2])};
    return orr_dust_av_plane(v->pass.dust, &eye, &v->pass.proj, r, av, err);
}

/* The extinction plane as NAME.extinction.fits beside the light planes,
 * with the view's cards. */
static orr_status write_extinction(view_state *v, const orr_plane *av, orr_error *err)
{
    const char *path;
    orr_status st = view_output(v, "extinction.fits", &path, err);
    if (!st)
        st = orr_write_fits(path, av, 1, &v->frame_cards, err);
    if (!st)
        v->rep->noutputs++;
    return st;
}

void orr_view_share_white(const view_state *l, view_state *r)
{
    const double white = l->rep->white;
    if (l->files.eye != ORR_EYE_LEFT || !(white > 0))
        return;
    r->files.picture.stretch.white = white;
    r->files.colour.synth.y0 = white;
}

/* A stereo pair written as one picture (render/stereo_view.h): the right
 * eye is graded with the left eye's white level. */
orr_status orr_view_write_stereo_pair(view_state *l, view_state *r, orr_error *err)
{
    const view_files *f = &l->files;
    orr_mask_outside_map(&l->pass.proj, l->pass.planes, l->pass.nplanes);
    orr_mask_outside_map(&r->pass.proj, r->pass.planes, r->pass.nplanes);
    size_t npix = (size_t)l->pass.proj.width * (size_t)l->pass.proj.height;
    int want_rgb = f->output.write_png || f->output.image_ext[0];
    float *rgb = want_rgb ? orr_malloc(2 * npix * 3 * sizeof *rgb, "stereo pictures", err) : NULL;
    orr_status st = want_rgb && !rgb ? ORR_ERR_NOMEM : ORR_OK;
    char desc[ORR_PATH_MAX + 256] = "stereo pair", rdesc[ORR_PATH_MAX + 256];
    if (!st && want_rgb)
        st = orr_view_graded_rgb(l, rgb, desc, sizeof desc, err);
    if (!st && want_rgb) {
        orr_view_share_white(l, r);
        st = orr_view_graded_rgb(r, rgb + 3 * npix, rdesc, sizeof rdesc, err);
    }
    charge(l, ORR_STAGE_POST);
    if (!st) {
        orr_view_meta_text text;
        orr_image_meta meta = view_meta(l, desc, &text);
        /* One file holds both eyes, each shifted its own way: no one
         * screen window is right for it. */
        meta.has_screen_window = 0;
        orr_stereo_pair pair = {
            .files = f, .planes = {l->pass.planes, r->pass.planes}, .nplanes = l->pass.nplanes,
            .width = l->pass.proj.width, .height = l->pass.proj.height,
            .rgb = {want_rgb ? rgb : NULL, want_rgb ? rgb + 3 * npix : NULL},
            .rgb_linear = (f->colour.has_populations || f->compose.nlayers || f->colour.has_tint) && f->output.png_linear,
            .cards = &l->frame_cards, .meta = &meta, .desc = desc, .stage = stage_output, .outputs = l->outputs,
            .proj = &l->pass.proj,
        };
        st = orr_stereo_write_pair(&pair, l->rep, err);
        charge(l, ORR_STAGE_STEREO);
    }
    free(rgb);
    return st;
}

/* NAME.stars.fits: the stars the view drew one by one (stars.list). */
static orr_status write_star_list(view_state *v, orr_error *err)
{
    orr_star_table table;
    void *columns = NULL;
    const char *path;
    orr_status st = orr_frame_stars_view_table(v->pass.stars, &v->pass, &table, &columns, err);
    if (!st)
        st = view_output(v, "stars.fits", &path, err);
    if (!st)
        st = orr_write_star_table(path, &table, NULL, err);
    if (!st)
        v->rep->noutputs++;
    free(columns);
    charge(v, ORR_STAGE_FITS);
    return st;
}

orr_status orr_view_write_outputs(view_state *v, orr_error *err)
{
    const view_files *f = &v->files;
    orr_mask_outside_map(&v->pass.proj, v->pass.planes, v->pass.nplanes);
    charge(v, ORR_STAGE_POST);
    orr_plane av = {0};
    int want_av = v->pass.dust && f->extinction_plane;
    orr_status st = want_av ? extinction_plane(v, &av, err) : ORR_OK;
    fits_writer fits = {0};
    if (!st && f->output.write_fits)
        st = fits_writer_start(v, &fits, err);
    if (!st && f->output.write_exr)
        st = write_exr(v, want_av ? &av : NULL, err);
    if (!st && want_av)
        st = write_extinction(v, &av, err);
    if (!st)
        st = orr_view_write_pictures(v, err);
    if (!st && v->pass.stars && f->stars_list && v->pass.stars->whole_list)
        st = write_star_list(v, err);
    st = fits_writer_finish(v, &fits, st, err);
    orr_plane_free(&av);
    return st;
}

