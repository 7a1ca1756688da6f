/* A view of the plan (render/plan_view.h): planned once from its scene,
 * begun every frame, freed with the plan. With plan.c, the only reader of
 * the scene in render/. */
#include "render/plan_view.h"

#include <stdio.h>
#include <string.h>

#include "core/numbers.h"
#include "core/owned.h"
#include "dust/dust.h"
#include "post/brightness.h"
#include "scene/scene.h"
#include "scene/scene_output.h"

/* Plane k's name: the weight, or X, Y, Z with colour, then NAME.X,
 * NAME.Y, NAME.Z for each population (output.exr_population_layers; the
 * EXR makes its layer NAME.R, NAME.G, NAME.B, NAME.A of them). */
static void plane_name(const orr_scene *s, int k, char *name, size_t size)
{
    static const char *const xyz_names[3] = {"X", "Y", "Z"};
    if (!s->colour.has_populations)
        orr_snprintf(name, size, "%s", s->input.weight);
    else if (k < 3)
        orr_snprintf(name, size, "%s", xyz_names[k]);
    else
        orr_snprintf(name, size, "%s.%s", s->colour.populations.pop[(k - 3) / 3].name, xyz_names[(k - 3) % 3]);
}

/* The view's PSF (post/view_psf.h): made once per run. */
static orr_status plan_psf(view_state *v, const orr_scene *s, orr_psf_kernels *kernels, orr_error *err)
{
    int colour = s->colour.has_populations || s->compose.nlayers;
    orr_status st = orr_view_psf_setup(&v->pass.psf, &s->psf, colour, &v->pass.proj, &v->pass.kernel, kernels, err);
    return st ? orr_fail_prefix(err, "%s: psf: ", s->path) : ORR_OK;
}

/* What the splat pass reads of the view's scene (pass/splat_settings.h). */
static orr_status splat_settings_of(const orr_scene *s, const char *path, orr_splat_settings *set, orr_error *err)
{
    set->path = path;
    set->type_mask = s->input.type_mask;
    set->skip_nonfinite = s->input.skip_nonfinite;
    snprintf(set->weight, sizeof set->weight, "%s", s->input.weight);
    set->skip_observer = s->observer.has_id;
    set->observer_id = s->observer.id;
    set->dims_from_observer = s->observer.has_id && s->observer.dim;
    set->dim = set->dims_from_observer || s->camera.dim;
    set->dim_near = s->camera.dim ? s->camera.dim_near : s->observer.dim_near;
    set->has_glow = s->psf.has_glow;
    set->glow_max_arcmin = s->psf.glow_max_arcmin;
    set->glow_threshold = s->psf.glow_threshold;
    set->deposit = s->deposit;
    set->periodic = s->periodic;
    orr_status st = orr_dust_settings_copy(&set->dust, &s->dust, err);
    set->has_populations = s->colour.has_populations;
    set->populations = s->colour.populations;
    set->only_index = s->colour.only_index;
    set->stereo = s->stereo.mode != ORR_STEREO_NONE;
    return st;
}

/* The frame's grading starts as planned (a compose's re-grade and a stereo
 * pair's shared white level change it). */
static void begin_frame_grading(view_files *f)
{
    f->picture = f->planned_picture;
    f->colour = f->planned_colour;
    f->regrade_final = 0;
}

/* What the view's files are (render/view_files.h), the frame's part as
 * planned. */
static orr_status view_files_of(const orr_scene *s, view_files *f, orr_error *err)
{
    snprintf(f->weight, sizeof f->weight, "%s", s->input.weight);
    f->stereo_mode = s->stereo.mode;
    f->eye = s->stereo.eye;
    f->extinction_plane = s->dust.extinction_plane;
    f->stars_list = s->stars.list;
    snprintf(f->scene_yaml, sizeof f->scene_yaml, "%s", s->scene_yaml);
    snprintf(f->planned_name, sizeof f->planned_name, "%s", s->output.name);
    f->planned_picture = s->picture;
    f->planned_colour = s->colour;
    begin_frame_grading(f); /* the cards the plan makes describe the planned picture */
    orr_status st = orr_owned_set(&f->path, s->path, err);
    if (!st)
        st = orr_output_settings_copy(&f->output, &s->output, err);
    return st ? st : orr_compose_settings_copy(&f->compose, &s->compose, err);
}

/* Re-grades the view's final planes (NAME.fits, after the PSF) with the
 * white level white, as animation.white_smoothing does. */
void orr_view_regrade_final(view_files *f, double white)
{
    f->regrade_final = 1;
    f->colour.synth.y0 = white;
    f->picture.stretch.white = white;
}

/* The units the scene states, or leaves to each frame's file (view_units). */
static void units_of(const orr_scene *s, view_units *u)
{
    static const char from_file[] = ""; /* passed as the file's unit: returned when the scene states none */
    const char *weight = scene_weight_unit(s, from_file), *length = scene_length_unit(s, from_file);
    u->weight_from_file = weight == from_file;
    u->length_from_file = length == from_file;
    snprintf(u->weight, sizeof u->weight, "%s", weight);
    snprintf(u->length, sizeof u->length, "%s", length);
}

/* How the view's camera is found each frame (view_state.h). */
static orr_status camera_plan_of(const orr_scene *s, const char *path, view_camera_plan *c, orr_error *err)
{
    c->path = path;
    c->kind = s->projection.kind;
    c->stereo = s->stereo;
    c->shutter = s->animation.shutter;
    c->has_frame_interval = s->animation.has_frame_interval;
    c->frame_interval = s->animation.frame_interval;
    c->blur_moves_particles = orr_scene_blur_moves_particles(s);
    return orr_camera_settings_copy(&c->camera, &s->camera, err);
}

orr_status orr_plan_view(view_state *v, const orr_scene *s, orr_psf_kernels *kernels, orr_error *err)
{
    orr_status st = view_files_of(s, &v->files, err);
    if (!st)
        st = splat_settings_of(s, v->files.path, &v->pass.splat, err);
    if (!st)
        st = camera_plan_of(s, v->files.path, &v->camera_plan, err);
    if (st)
        return st; /* out of memory */
    st = orr_projection_plan(&v->pass.proj, &s->projection, err);
    if (st)
        return orr_fail_prefix(err, "%s: ", s->path);
    v->pass.nplanes = s->colour.has_populations || s->compose.nlayers ? 3 : 1;
    if (s->colour.has_populations && s->output.exr_population_layers)
        v->pass.nplanes += 3 * s->colour.populations.n;
    units_of(s, &v->units);
    char unit[ORR_PLANE_NAME_MAX];
    orr_brightness_unit(&v->pass.proj, v->units.weight, v->units.length, unit, sizeof unit);
    for (int k = 0; k < v->pass.nplanes && !st; k++) {
        char name[ORR_PLANE_NAME_MAX];
        plane_name(s, k, name, sizeof name);
        st = orr_plane_alloc(&v->pass.planes[k], v->pass.proj.width, v->pass.proj.height, name, unit, err);
    }
    v->planes_zeroed = !st;
    /* The kernel's tables take milliseconds to build: only for kernel
     * deposits and PSFs (a sky map's is drawn with the kernel). */
    int needs_kernel = s->deposit.kind == ORR_DEPOSIT_SPH || s->psf.kind != ORR_PSF_NONE;
    if (!st && needs_kernel)
        st = orr_kernel_init(&v->pass.kernel, s->deposit.kernel, err);
    v->pass.kernel_ready = !st && needs_kernel;
    /* The PSF needs the image's size and scale, which a stereo eye's
     * shifted principal point leaves as they are. */
    if (!st)
        st = plan_psf(v, s, kernels, err);
    if (!st) /* the kernels the deposit and the PSF's widening draw */
        st = orr_splat_plan_kernels(&v->pass, err);
    if (!st)
        orr_view_plan_cards(v, &s->input, &s->observer); /* after the deposit and the PSF, which they describe */
    return st;
}

/* The planes zeroed for the frame: on every thread (an 8192^2 dome
 * master's are 805 MB), and not at all in the first, whose planes are
 * fresh. */
static void clear_planes(view_state *v)
{
    if (!v->planes_zeroed)
        for (int k = 0; k < v->pass.nplanes; k++)
            orr_plane_clear(&v->pass.planes[k]);
    v->planes_zeroed = 0;
}

/* Forgets what the last frame left in the view (a failed frame may have
 * left lanes): each frame starts from the planned state. */
static void reset_frame_state(view_state *v)
{
    orr_splat_free_lanes(&v->pass);
    orr_bands_free(&v->pass.bands);
    v->pass.lanes.n = 1;
    memset(&v->pass.blur, 0, sizeof v->pass.blur);
    memset(&v->pass.periodic, 0, sizeof v->pass.periodic);
    v->pass.use_ods = 0;
    v->pass.lengths = NULL;
    v->pass.lengths_next = 0;
    v->pass.h_scale = 0;
    v->pass.dust = NULL;
    v->pass.stars = NULL;
    memset(&v->pass.tally, 0, sizeof v->pass.tally);
    v->outputs = NULL;
    if (v->pass.psf.sky)
        orr_sky_psf_begin_frame(v->pass.psf.sky);
    clear_planes(v);
    orr_coarse_glow_begin(&v->pass);
}

/* The frame's part of a planned view: its report, the camera (a path, the
 * observer's sky frame), a stereo eye's camera and principal point (the
 * convergence may follow the camera), motion blur's shutter cameras. */
orr_status orr_view_begin_frame(view_state *v, const orr_sky_frame *observer, orr_vec3 observer_velocity,
                                const orr_frame_time *when, orr_render_report *rep, orr_error *err)
{
    reset_frame_state(v);
    memset(rep, 0, sizeof *rep);
    rep->frame = when->frame;
    rep->nframes = when->nframes;
    v->rep = rep;
    begin_frame_grading(&v->files);
    v->tint_t = v->files.colour.tint_run ? when->u : v->files.colour.tint_t;
    const view_camera_plan *c = &v->camera_plan;
    orr_status st = orr_view_camera(c, observer, when, &rep->camera, &rep->sky, err);
    if (st)
        return orr_fail_prefix(err, "%s: ", v->files.path);
    if ((st = orr_stereo_setup_eye(&c->stereo, &c->camera, c->path, &v->pass.proj, rep, &v->pass.ods,
                                   &v->pass.use_ods, err)) ||
        (st = orr_view_plan_blur(v, observer, observer_velocity, when, err)))
        return st;
    rep->has_sky_frame = observer != NULL;
    v->pass.world_to_camera = orr_camera_world_to_camera(&rep->camera);
    v->pass.camera_position = rep->camera.position;
    /* The deposit keeps a copy of the projection, refreshed to this frame's:
     * a perspective stereo eye is planned again each frame, its principal
     * point shifted by a convergence distance that follows the camera when
     * stereo.convergence is not given (render/stereo_view.c). The flat
     * deposit reads no principal point today, so the copy is for
     * consistency; a sky map's index depends on the map alone, which no eye
     * moves. */
    if (v->pass.sph_ready)
        v->pass.sph.proj = v->pass.proj;
    v->pass.outline = orr_map_outline_of(&v->pass.proj, v->pass.proj.width, v->pass.proj.height);
    orr_splat_choose_path(&v->pass); /* after the eye and the shutter, which it asks about */
    return ORR_OK;
}

void orr_view_free(view_state *v)
{
    orr_coarse_glow_free(&v->pass);
    orr_splat_free_lanes(&v->pass);
    orr_bands_free(&v->pass.bands);
    for (int k = 0; k < ORR_PLANES_MAX; k++)
        orr_plane_free(&v->pass.planes[k]);
    orr_view_psf_free(&v->pass.psf);
    if (v->pass.sph_ready)
        orr_sph_free(&v->pass.sph);
    if (v->pass.kernel_ready)
        orr_kernel_free(&v->pass.kernel);
    /* The copies of the scene's settings, with their strings. */
    orr_dust_settings_free(&v->pass.splat.dust);
    orr_compose_settings_free(&v->files.compose);
    orr_output_settings_free(&v->files.output);
    orr_owned_free(&v->files.path);
    orr_camera_settings_free(&v->camera_plan.camera);
}

