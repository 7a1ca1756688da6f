/* The renderer's plan (render/plan.h): each view planned once for a run,
 * then each frame's observer frame, cameras, smoothing lengths (kept from
 * frame to frame when the particles are those of one file), dust and
 * periodic copies, the splat pass (pass/splat_pass.c), the reduction over
 * processes and the views' files (view_outputs.c). */
#include "render/plan.h"
#include "render/plan_view.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/atomic.h"
#include "dust/dust.h"
#include "post/brightness.h"
#include "post/grade.h"
#include "render/frame_names.h"
#include "scene/scene.h"
#include "source/partition.h"

/* ---- the views as rendered: a stereo view's two eyes ---- */

/* The scenes of the views as the plan renders them, while it plans them: a
 * stereo view becomes its left eye followed by its right eye, each a copy
 * of the scene that knows which eye it is. Freed once the plan is made:
 * the plan keeps no scene. */
typedef struct orr_eye_views {
    int n;                   /* views to plan */
    const orr_scene **scene; /* [n] the scene of each (the caller's, or an eye's copy) */
    orr_scene *copies;       /* the eyes' scenes, copies with strings of their own */
    int ncopies;             /* ... how many (zeroed until copied: freed whole) */
} orr_eye_views;

static void eye_views_finish(orr_eye_views *ev)
{
    free(ev->scene);
    for (int k = 0; k < ev->ncopies; k++)
        orr_scene_free(&ev->copies[k]);
    free(ev->copies);
    memset(ev, 0, sizeof *ev);
}

/* The scene of one eye: a copy that knows which eye it is. */
static orr_status eye_scene(const orr_scene *s, int eye, orr_scene *out, orr_error *err)
{
    orr_status st = orr_scene_copy(out, s, err);
    out->stereo.eye = eye;
    return st;
}

/* Room in ev for n views, of which `pairs` stereo views' eye copies. */
static orr_status eye_views_alloc(orr_eye_views *ev, int n, int pairs, orr_error *err)
{
    ev->scene = orr_calloc((size_t)n, sizeof *ev->scene, "stereo views", err);
    ev->copies = pairs ? orr_calloc(2 * (size_t)pairs, sizeof *ev->copies, "stereo eye scenes", err) : NULL;
    ev->ncopies = ev->copies ? 2 * pairs : 0;
    if (!ev->scene || (pairs && !ev->copies)) {
        eye_views_finish(ev);
        return ORR_ERR_NOMEM;
    }
    return ORR_OK;
}

/* Expands scenes[0..nscenes) into eyes. */
static orr_status eye_views_expand(const orr_scene *const *scenes, int nscenes, orr_eye_views *ev, orr_error *err)
{
    memset(ev, 0, sizeof *ev);
    int pairs = 0;
    for (int k = 0; k < nscenes; k++)
        pairs += scenes[k]->stereo.mode != ORR_STEREO_NONE;
    orr_status st = eye_views_alloc(ev, nscenes + pairs, pairs, err);
    for (int k = 0, pair = 0; k < nscenes && !st; k++) {
        if (scenes[k]->stereo.mode == ORR_STEREO_NONE) {
            ev->scene[ev->n++] = scenes[k];
            continue;
        }
        orr_scene *left = &ev->copies[2 * pair++], *right = left + 1;
        st = eye_scene(scenes[k], ORR_EYE_LEFT, left, err);
        if (!st)
            st = eye_scene(scenes[k], ORR_EYE_RIGHT, right, err);
        if (st) {
            eye_views_finish(ev);
            return st;
        }
        ev->scene[ev->n++] = left;
        ev->scene[ev->n++] = right;
    }
    return st;
}

struct orr_plan {
    orr_plan_purpose purpose;
    int nscenes;             /* the views as given */
    int n;                   /* the views as rendered: a stereo view is two eyes (purpose render) */
    int *origin;             /* [n] the view given that each renders */
    /* What the views share, view 0's input.* and observer.*: copies, with
     * strings of their own. */
    orr_input_settings input;
    orr_periodic_settings periodic;
    char fields[ORR_RENDER_MAX_FIELDS][ORR_FIELD_NAME_MAX]; /* the extra fields the frames read */
    orr_source_request source; /* what the frames ask of the particles: points into the above */
    orr_observer_settings observer;
    int observer_velocities; /* the observer's pass reads velocities (its spin normal, a blur) */
    double fps;              /* animation.fps: a still's time */
    /* Where each view reports in a frame: a right eye into a report of its
     * own, whose outputs go to its left eye's after the frame; every other
     * view into the caller's report of the view given it renders. */
    orr_render_report **report; /* [n] */
    orr_render_report *right;   /* [n] the right eyes' own */
    view_state *views;       /* [n] */
    orr_splat_view **passes; /* [n] each view's part for the splat pass: &views[k].pass */
    int planned;             /* views[0..planned) hold plan-time state, to free */
    orr_psf_kernels kernels; /* the Hubble PSFs made, shared by the views that ask for the same one */
    orr_frame_timer timer;   /* the frame being executed */
    orr_lengths kept_lengths; /* smoothing lengths kept from frame to frame (kept_lengths_key) */
    char kept_lengths_key[ORR_PATH_MAX + 128]; /* the particles they belong to; empty: none kept */
    frame_stars stars;       /* stars.limit: the stars spawned from the particles (pass/star_pass.c) */
    int has_stars;
    double seconds;          /* orr_plan_create's time */
    orr_clock planning;      /* ... wall and CPU, charged to the first frame executed (then zero) */
};

/* Whether view k is the left eye of a pair written as one picture
 * (anaglyph, side-by-side, over-under); view k + 1 is then its right eye. */
static int pair_at(const orr_plan *plan, int k)
{
    const view_files *f = &plan->views[k].files;
    return k + 1 < plan->n && f->eye == ORR_EYE_LEFT && orr_stereo_is_pair_mode(f->stereo_mode);
}

/* Where each view reports in this frame (orr_plan.report). */
static void frame_reports_begin(orr_plan *plan, orr_render_report *reports)
{
    for (int k = 0; k < plan->n; k++)
        plan->report[k] = plan->views[k].files.eye == ORR_EYE_RIGHT ? &plan->right[k] : &reports[plan->origin[k]];
}

/* Adds each right eye's outputs to its view's report, its left eye's. */
static void frame_reports_finish(orr_plan *plan)
{
    for (int k = 1; k < plan->n; k++) {
        if (plan->views[k].files.eye != ORR_EYE_RIGHT)
            continue;
        orr_render_report *l = plan->report[k - 1];
        const orr_render_report *r = plan->report[k];
        for (int i = 0; i < r->noutputs && l->noutputs < ORR_RENDER_MAX_OUTPUTS; i++)
            memcpy(l->outputs[l->noutputs++], r->outputs[i], ORR_PATH_MAX);
    }
}

/* ---- what the frames ask of the particle source ---- */

/* Appends name to r's fields unless it is empty, mass or h (never extra
 * fields), already there, or there is no room. */
static void add_field(orr_source_request *r, const char *name)
{
    if (!name[0] || strcmp(name, "mass") == 0 || strcmp(name, "h") == 0 || r->nfields >= ORR_RENDER_MAX_FIELDS)
        return;
    for (int i = 0; i < r->nfields; i++)
        if (strcmp(r->fields[i], name) == 0)
            return;
    r->fields[r->nfields++] = name;
}

/* The fields a colour population reads besides positions and weights:
 * readers that load only the fields asked for (HDF5) must load these, or a
 * population choosing by stellar age would find no ages. */
static void add_population_fields(orr_source_request *r, const orr_population *p)
{
    add_field(r, p->select.range_field);
    add_field(r, p->select.prob_field);
    if (p->colour.kind != ORR_POPCOLOUR_FIXED)
        add_field(r, p->colour.field);
    if (p->colour.kind == ORR_POPCOLOUR_SSP)
        add_field(r, p->colour.ssp.metallicity_field);
    if (p->lum.kind == ORR_POPLUM_FIELD || p->lum.kind == ORR_POPLUM_MAGNITUDE)
        add_field(r, p->lum.field);
}

/* The extra fields a frame of the scene asks its source for (orr_source_request.fields). */
static void add_frame_fields(orr_source_request *r, const orr_scene *s)
{
    add_field(r, s->input.weight);
    for (int i = 0; s->colour.has_populations && i < s->colour.populations.n; i++)
        add_population_fields(r, &s->colour.populations.pop[i]);
    if (s->dust.types)
        add_field(r, s->dust.metallicity);
    if ((s->observer.has_id && s->observer.normal_types) || orr_scene_blur_moves_particles(s)) {
        add_field(r, "vx");
        add_field(r, "vy");
        add_field(r, "vz");
    }
}

void orr_plan_source_request(const orr_scene *s, orr_source_request *r)
{
    memset(r, 0, sizeof *r);
    r->scene_path = s->path;
    r->input = &s->input;
    r->periodic = &s->periodic;
    /* The observer and reference particles may be of types the scene does
     * not draw: then the reader must not drop them (the splat selects
     * input.types itself); nor the dust (dust.types). */
    r->reader_types = s->observer.has_id ? 0 : s->input.type_mask | s->dust.types;
    /* A model generates only the types some pass reads (the markers always
     * are): the drawn stars, the dust, the particles whose spin gives the
     * observer's normal. With input.types: [2, 3] that leaves out the dark
     * halos, two thirds of the particles. */
    r->model_types = s->input.type_mask | s->dust.types | s->observer.normal_types;
    r->sequence_types = r->reader_types;
    add_frame_fields(r, s);
}

/* ---- what a run's frames and their markers read of a view ---- */

orr_output_place orr_plan_output_place(const orr_scene *s)
{
    return (orr_output_place){s->output.dir, s->output.name, orr_frame_naming_of(&s->output)};
}

orr_view_making orr_plan_view_making(const orr_scene *s)
{
    return (orr_view_making){
        .settings = s->settings,
        .settings_digest = s->settings_digest,
        .input_file = s->input.file,
        .psf_file = s->psf.kind == ORR_PSF_FILE ? s->psf.file : NULL, /* the other PSFs read no file */
        .camera_path_file = s->camera.path_file,
    };
}

/* ---- what a run of frames reads of its views ---- */

orr_run_settings orr_plan_run_settings(const orr_scene *s)
{
    const orr_animation_settings *a = &s->animation;
    return (orr_run_settings){
        .scene_path = s->path,
        .frames = a->frames,
        .fps = a->fps,
        .has_time = a->has_time,
        .time = {a->time[0], a->time[1]},
        .white_smoothing = a->white_smoothing,
    };
}

orr_status orr_plan_frame_scene(const orr_scene *view, long frame, orr_scene *out, orr_error *err)
{
    orr_status st = orr_scene_copy(out, view, err);
    if (st)
        return st;
    const orr_frame_naming naming = orr_frame_naming_of(&view->output);
    return orr_frame_name(&naming, view->output.name, frame, view->animation.frames, out->output.name,
                          sizeof out->output.name, err);
}

int orr_plan_psf_in_raw_planes(const orr_scene *s, int *sky)
{
    *sky = orr_projection_traits_of(s->projection.kind).sky;
    return *sky || orr_psf_flat_stars(&s->psf, *sky);
}

/* ---- what a camera path's table and overview read of a scene ---- */

void orr_plan_path_scene(const orr_scene *s, orr_path_scene *ps)
{
    ps->scene_path = s->path;
    ps->frames = s->animation.frames;
    ps->has_camera_path = s->camera.has_path;
    ps->camera_path = &s->camera.path;
    orr_plan_source_request(s, &ps->source);
    ps->stretch = &s->picture.stretch;
}

/* ---- the plan ---- */

void orr_plan_destroy(orr_plan *plan)
{
    if (!plan)
        return;
    for (int k = 0; k < plan->planned; k++)
        orr_view_free(&plan->views[k]);
    free(plan->views);
    free(plan->passes);
    free(plan->origin);
    free(plan->report);
    free(plan->right);
    orr_input_settings_free(&plan->input);
    orr_psf_kernels_free(&plan->kernels);
    orr_lengths_free(&plan->kept_lengths);
    if (plan->has_stars)
        orr_frame_stars_free(&plan->stars);
    free(plan);
}

/* The views the plan renders: for a render, each stereo view's two eyes;
 * for a compose, the views as given. */
static orr_status expand_views(orr_plan_purpose purpose, const orr_scene *const *scenes, int n, orr_eye_views *eyes,
                               orr_error *err)
{
    if (purpose == ORR_PLAN_RENDER)
        return eye_views_expand(scenes, n, eyes, err);
    memset(eyes, 0, sizeof *eyes);
    if (!(eyes->scene = orr_calloc((size_t)n, sizeof *eyes->scene, "views", err)))
        return ORR_ERR_NOMEM;
    for (int k = 0; k < n; k++)
        eyes->scene[k] = scenes[k];
    eyes->n = n;
    return ORR_OK;
}

/* A view's output folder made, or found unwritable. A compose reads the
 * raw planes it re-grades from it: they must be there. */
static orr_status check_output_dir(orr_plan_purpose purpose, const char *dir, int compose_layers, orr_error *err)
{
    orr_status st = ORR_OK;
    if (purpose == ORR_PLAN_COMPOSE)
        st = orr_compose_check_raw_dir(dir, compose_layers, err);
    return st ? st : orr_check_output_dir(dir, err);
}

/* What the views share, copied from view 0's scene: the particles the
 * frames read (input.*, the fields), the observer, a still's time. */
static orr_status plan_shared(orr_plan *plan, const orr_scene *s, orr_error *err)
{
    orr_plan_source_request(s, &plan->source); /* (pointing into s until repointed below) */
    orr_status st = orr_input_settings_copy(&plan->input, &s->input, err);
    plan->periodic = s->periodic;
    plan->source.input = &plan->input;
    plan->source.periodic = &plan->periodic;
    for (int i = 0; i < plan->source.nfields; i++) {
        snprintf(plan->fields[i], sizeof plan->fields[i], "%s", plan->source.fields[i]);
        plan->source.fields[i] = plan->fields[i];
    }
    plan->source.scene_path = NULL; /* view 0's own path, once it is planned (orr_plan_create) */
    plan->observer = s->observer;
    plan->observer_velocities = s->observer.normal_types != 0 || orr_scene_blur_moves_particles(s);
    plan->fps = s->animation.fps;
    return st;
}

/* The plan's per-view arrays, and which view given each view renders. */
static orr_status alloc_views(orr_plan *plan, const orr_scene *const *scenes, orr_error *err)
{
    const size_t n = (size_t)plan->n;
    plan->views = orr_calloc(n, sizeof *plan->views, "views", err);
    plan->passes = orr_calloc(n, sizeof *plan->passes, "views", err);
    plan->origin = orr_calloc(n, sizeof *plan->origin, "views", err);
    plan->report = orr_calloc(n, sizeof *plan->report, "views", err);
    plan->right = orr_calloc(n, sizeof *plan->right, "views", err);
    if (!plan->views || !plan->passes || !plan->origin || !plan->report || !plan->right)
        return ORR_ERR_NOMEM;
    for (int i = 0, k = 0; i < plan->nscenes; i++) {
        plan->origin[k++] = i;
        if (plan->purpose == ORR_PLAN_RENDER && scenes[i]->stereo.mode != ORR_STEREO_NONE)
            plan->origin[k++] = i;
    }
    for (size_t k = 0; k < n; k++)
        plan->passes[k] = &plan->views[k].pass;
    return ORR_OK;
}

/* Plans each view from its scene (an eye's copy for a stereo view), and
 * the stars the views share. */
static orr_status plan_views(orr_plan *plan, const orr_eye_views *eyes, orr_error *err)
{
    orr_status st = ORR_OK;
    for (; !st && plan->planned < plan->n; plan->planned++)
        st = orr_plan_view(&plan->views[plan->planned], eyes->scene[plan->planned], &plan->kernels, err);
    if (st)
        return st;
    const orr_scene *s0 = eyes->scene[0];
    plan->source.scene_path = plan->views[0].files.path;
    if (plan->purpose == ORR_PLAN_RENDER && s0->stars.enabled &&
        !(st = orr_frame_stars_prepare(&plan->stars, &s0->stars, s0->observer.id, plan->views[0].files.path, err)))
        plan->has_stars = 1;
    for (int k = 0; k < plan->n && !st && plan->has_stars; k++) /* the stars' glows span degrees */
        st = orr_coarse_glow_plan(&plan->views[k].pass, err);
    return st;
}

orr_status orr_plan_create(orr_plan **out, const orr_scene *const *scenes, int n, orr_plan_purpose purpose,
                           orr_error *err)
{
    *out = NULL;
    if (n < 1)
        return orr_fail(err, ORR_ERR_USAGE, "no view to %s", purpose == ORR_PLAN_RENDER ? "render" : "compose");
    const orr_clock start = orr_clock_now();
    orr_plan *plan = orr_calloc(1, sizeof *plan, "render plan", err);
    if (!plan)
        return ORR_ERR_NOMEM;
    plan->purpose = purpose;
    plan->nscenes = n;
    /* Fail on an unwritable output folder before any slow work. */
    orr_status st = ORR_OK;
    for (int k = 0; k < n && !st; k++)
        st = check_output_dir(purpose, scenes[k]->output.dir, scenes[k]->compose.nlayers, err);
    if (!st)
        st = plan_shared(plan, scenes[0], err);
    orr_eye_views eyes = {0};
    if (!st)
        st = expand_views(purpose, scenes, n, &eyes, err);
    plan->n = eyes.n;
    if (!st)
        st = alloc_views(plan, scenes, err);
    if (!st)
        st = plan_views(plan, &eyes, err);
    eye_views_finish(&eyes);
    if (st) {
        orr_plan_destroy(plan);
        return st;
    }
    const orr_clock end = orr_clock_now();
    plan->seconds = end.wall - start.wall;
    plan->planning = (orr_clock){end.wall - start.wall, end.cpu - start.cpu};
    *out = plan;
    return ORR_OK;
}

double orr_plan_seconds(const orr_plan *plan)
{
    return plan ? plan->seconds : 0;
}

/* Each view's output folder, checked again each frame (a stat): a long
 * run's folder may have gone since, and this is before any slow work. */
static orr_status check_view_dirs(const orr_plan *plan, orr_error *err)
{
    orr_status st = ORR_OK;
    for (int k = 0; k < plan->n && !st; k++)
        st = check_output_dir(plan->purpose, plan->views[k].files.output.dir, plan->views[k].files.compose.nlayers,
                              err);
    return st;
}

/* ---- a frame ---- */

/* After a frame, view k points at nothing of it: its report, lengths, dust
 * and outputs. */
static void forget_frame(orr_plan *plan, int k)
{
    view_state *v = &plan->views[k];
    v->rep = NULL;
    v->pass.lengths = NULL;
    v->pass.dust = NULL;
    v->outputs = NULL;
}

/* This process's share of the scene's input, when several processes render
 * the frame: with the fields the sky frame and the weight need. */
static orr_status open_share(const orr_source_request *r, const orr_parallel *par, orr_source **out, orr_error *err)
{
    orr_source *whole = NULL;
    /* File readers that can seek read only this rank's share; the others,
     * and the generators, are dealt out by chunks. */
    orr_status st = orr_source_request_open_share(r, r->fields, r->nfields, par->rank, par->nranks, &whole, err);
    return st ? st : orr_source_partition(whole, par->rank, par->nranks, out, err);
}

/* Sums what every process splatted onto rank 0: the planes, and the counts
 * of the reports (reduce/parallel.h). */
static orr_status reduce_views(view_state *views, int n, const orr_parallel *par, orr_error *err)
{
    orr_status st = ORR_OK;
    for (int k = 0; k < n && !st; k++) {
        view_state *v = &views[k];
        orr_render_report *r = v->rep;
        orr_sums sums = {0};
        orr_sums_count(&sums, &r->n_read);
        orr_sums_count(&sums, &r->n_selected);
        orr_sums_count(&sums, &r->n_nonfinite);
        orr_sums_deposit(&sums, &r->deposit);
        orr_sums_deposit(&sums, &r->deposit_y);
        orr_sums_count(&sums, &r->n_replicas_culled); /* a periodic box's culled copies and blocks */
        orr_sums_count(&sums, &r->n_blocks);
        orr_sums_count(&sums, &r->n_blocks_culled);
        if (!(st = orr_parallel_sum_planes(par, v->pass.planes, v->pass.nplanes, err)))
            st = orr_parallel_sum(par, &sums, err);
        if (!st && v->pass.psf.sky) /* rank 0 draws the whole frame's brightest stars */
            st = orr_sky_psf_share(v->pass.psf.sky, par, err);
    }
    return st;
}

/* The bound on the glow's lengths (pass/lengths.h) that lets the search
 * skip the particles whose own kernel is the wider, when every view that
 * takes the lengths glows with the frame's stars from centre with no
 * periodic copies; else none (stars NULL). */
static orr_lengths_bound lengths_bound(const view_state *views, int n, const orr_vec3 *centre)
{
    orr_lengths_bound b = {NULL, 0.0f};
    const char *exact = getenv("ORRERY_EXACT_LENGTHS"); /* 1: every length searched (the tests compare) */
    if (exact && strcmp(exact, "1") == 0)
        return b;
    for (int k = 0; k < n; k++) {
        const orr_splat_view *p = &views[k].pass;
        if (!p->stars || !p->splat.has_glow || p->splat.periodic.replicas > 1 ||
            orr_v3_norm(orr_v3_sub(p->camera_position, *centre)) > 0 || (b.stars && b.stars != &p->stars->stage))
            return (orr_lengths_bound){NULL, 0.0f};
        b.stars = &p->stars->stage;
        const float h_scale = (float)p->splat.deposit.h_scale; /* (as prepare_lengths sets it) */
        b.h_scale = h_scale > b.h_scale ? h_scale : b.h_scale;
    }
    return b;
}

/* Smoothing lengths from the neighbours, computed once for every view that
 * needs them (views share input.*, so the same particles take them). */
static orr_status prepare_lengths(view_state *views, int n, orr_source *src, const orr_parallel *par,
                                  orr_lengths *lengths, orr_error *err)
{
    for (int k = 0; k < n; k++) {
        view_state *v = &views[k];
        int needed;
        orr_status st = orr_lengths_needed(&v->pass.splat, src, &needed, err);
        if (st)
            return st;
        /* orrery's h is half the kernel's support: convert the file's. */
        double support = src->info.h_support > 0 ? src->info.h_support : 2.0;
        v->pass.h_scale = (float)(v->pass.splat.deposit.h_scale * support / 2.0);
        if (!needed)
            continue;
        /* The glow's lengths are angles seen from the camera (glow_length). */
        const orr_vec3 *centre = v->pass.splat.has_glow ? &v->rep->camera.position : NULL;
        if (par && !centre)
            return orr_fail(err, ORR_ERR_USAGE,
                            "%s: smoothing lengths from the neighbours need every particle in one process; with "
                            "%d MPI ranks use lengths from the file (smoothing.lengths: file)",
                            v->pass.splat.path, par->nranks);
        v->pass.h_scale = (float)v->pass.splat.deposit.h_scale;
        if (!lengths->h && !lengths->angular) { /* (computed, but none here: a process's share may be empty) */
            const orr_lengths_bound bound = centre ? lengths_bound(views, n, centre) : (orr_lengths_bound){0};
            if ((st = orr_lengths_compute_bounded(&v->pass.splat, src, centre, par, &bound, lengths, err)))
                return st;
        }
        if (lengths->angular != (centre != NULL) ||
            (centre && orr_v3_norm(orr_v3_sub(lengths->centre, *centre)) > 0))
            return orr_fail(err, ORR_ERR_USAGE,
                            "%s: the views of a frame share one set of smoothing lengths, but view %d %s; give "
                            "every view glow.threshold from the same place, or none of them",
                            v->pass.splat.path, k, centre ? "glows from another camera position" : "has no glow");
        v->pass.lengths = lengths;
        v->rep->n_lengths = lengths->n;
        v->rep->n_lengths_bounded = lengths->skipped;
    }
    return ORR_OK;
}

/* A periodic box's copies around the view's camera, those out of view
 * skipped when the pass allows it (orr_splat_can_cull). */
static orr_status setup_periodic(view_state *v, const orr_source_info *info, orr_error *err)
{
    orr_status st = orr_periodic_view_setup(&v->pass.periodic, &v->pass.splat, info, &v->pass.proj, &v->rep->camera,
                                            orr_splat_can_cull(&v->pass), err);
    v->rep->n_replicas = v->pass.periodic.active ? v->pass.periodic.replicas.n : 0;
    return st;
}

/* The planes before the PSF (for orrery compose), the PSF, and the outputs. */
/* Hands view k's final planes, its graded picture and its cards to the
 * frame's keeper (orr_frame_input.keep): a HEALPix map's with the map's
 * keywords its FITS table has (NSIDE, ORDERING, COORDSYS, ...). */
static orr_status keep_view(view_state *v, int k, const orr_frame_input *in, orr_error *err)
{
    size_t npix = (size_t)v->pass.proj.width * (size_t)v->pass.proj.height;
    float *rgb = orr_malloc(npix * 3 * sizeof *rgb, "kept picture", err);
    orr_status st = rgb ? ORR_OK : ORR_ERR_NOMEM;
    const orr_cards *cards = &v->frame_cards;
    orr_cards *map_cards = NULL;
    if (!st && orr_projection_traits_of(v->pass.proj.settings.kind).pixel_table) {
        map_cards = orr_malloc(sizeof *map_cards, "HEALPix map cards", err);
        st = map_cards ? ORR_OK : ORR_ERR_NOMEM;
        if (!st) {
            *map_cards = v->frame_cards;
            orr_healpix_info info = orr_view_healpix_info(v);
            orr_fits_add_healpix(map_cards, &info);
            cards = map_cards;
        }
    }
    char desc[ORR_PATH_MAX + 256];
    if (!st)
        st = orr_view_graded_rgb(v, rgb, desc, sizeof desc, err);
    if (!st)
        st = in->keep(in->keep_user, k, v->pass.planes, fits_nplanes(v), rgb, cards, err);
    free(map_cards);
    free(rgb);
    return st;
}

/* A sky map's, or a flat view's given psf.fwhm, brightest stars with the
 * whole PSF (post/sky_psf.h, post/flat_psf.h). */
static orr_status draw_bright_stars(view_state *v, orr_error *err)
{
    if (!v->pass.psf.sky)
        return ORR_OK;
    if (!v->pass.psf.core)
        return orr_sky_psf_draw(v->pass.psf.sky, &v->pass.sph, v->pass.planes, v->pass.nplanes, err);
    orr_flat_deposit dep = {v->pass.splat.deposit.kind, &v->pass.proj, v->pass.use_sph ? &v->pass.sph : NULL};
    return orr_flat_psf_draw(v->pass.psf.sky, &dep, v->pass.psf.core, v->pass.planes, v->pass.nplanes, err);
}

static orr_status finish_views(const orr_plan *plan, const orr_frame_input *in, orr_error *err)
{
    view_state *views = plan->views;
    const int n = plan->n, keep = in && in->keep;
    orr_status st = ORR_OK;
    for (int k = 0; k < n && !st; k++) /* bright stars' PSFs: part of the raw planes, as the cores */
        st = draw_bright_stars(&views[k], err);
    charge(&views[0], ORR_STAGE_PSF);
    for (int k = 0; k < n && !st; k++) /* the frame's cards: its counts, stars and camera are final */
        orr_view_frame_cards(&views[k]);
    for (int k = 0; k < n && !st; k++) /* flux per pixel to flux per steradian (or area) */
        orr_to_surface_brightness(&views[k].pass.proj, views[k].pass.planes, views[k].pass.nplanes);
    charge(&views[0], ORR_STAGE_POST);
    for (int k = 0; k < n && !st; k++)
        if (views[k].files.output.write_raw) {
            orr_mask_outside_map(&views[k].pass.proj, views[k].pass.planes, views[k].pass.nplanes);
            charge(&views[k], ORR_STAGE_POST);
            st = orr_view_write_fits_planes(&views[k], "raw.fits", err);
        }
    for (int k = 0; k < n && !st; k++)
        for (int j = 0; j < views[k].pass.nplanes && !st; j++)
            st = orr_view_psf_apply(&views[k].pass.psf, &views[k].pass.planes[j], err);
    charge(&views[0], ORR_STAGE_PSF);
    for (int k = 0; k < n && !st; k++) {
        if (pair_at(plan, k)) {
            st = orr_view_write_stereo_pair(&views[k], &views[k + 1], err);
            if (!st && keep && !(st = keep_view(&views[k], k, in, err)))
                st = keep_view(&views[k + 1], k + 1, in, err);
            k++; /* the right eye was written with the left */
            continue;
        }
        st = orr_view_write_outputs(&views[k], err);
        if (k + 1 < n) /* separate eyes: grade the right alike */
            orr_view_share_white(&views[k], &views[k + 1]);
        if (!st && keep)
            st = keep_view(&views[k], k, in, err);
    }
    return st;
}

/* The plan's own time goes to the set-up of the first frame it draws (a
 * still's timings show the PSF's generation, as before there was a plan),
 * frame and stages alike, so the stages still add up to the frame. */
static void charge_planning(orr_plan *plan)
{
    orr_stage_times *t = &plan->timer.times;
    t->wall[ORR_STAGE_SETUP] += plan->planning.wall, t->total_wall += plan->planning.wall;
    t->cpu[ORR_STAGE_SETUP] += plan->planning.cpu, t->total_cpu += plan->planning.cpu;
    plan->planning = (orr_clock){0, 0};
}

/* The frame's particles: the caller's (rewound), or the scene's input
 * opened with the fields the frame needs. */
static orr_status frame_particles(const orr_source_request *r, orr_source *given, orr_source **src, orr_error *err)
{
    if (given) {
        *src = given;
        return orr_source_rewind(given, err);
    }
    return orr_source_request_open(r, r->fields, r->nfields, src, err);
}

/* The units the scene leaves open are the frame's source's when it states
 * them (an HDF5 snapshot's, source.h): each view's planes' BUNIT and the
 * length unit of its WCS (view_cards.c). Set every frame, since a run's
 * frames may read other files. */
static void frame_units(orr_plan *plan, const orr_source *src)
{
    const char *mass = src ? src->info.mass_unit : "", *length = src ? src->info.length_unit : "";
    for (int k = 0; k < plan->n; k++) {
        view_state *v = &plan->views[k];
        const view_units *u = &v->units;
        snprintf(v->length_unit, sizeof v->length_unit, "%s", u->length_from_file ? length : u->length);
        char unit[ORR_PLANE_NAME_MAX];
        orr_brightness_unit(&v->pass.proj, u->weight_from_file ? mass : u->weight, v->length_unit, unit, sizeof unit);
        for (int j = 0; j < v->pass.nplanes; j++)
            snprintf(v->pass.planes[j].unit, sizeof v->pass.planes[j].unit, "%s", unit);
    }
}

/* Sets up each view's frame; returns how many were begun (their outputs
 * belong to the frame's batch). */
static orr_status begin_frame(orr_plan *plan, const orr_sky_frame *observer, orr_vec3 observer_velocity,
                              const orr_frame_time *when, int *begun, orr_error *err)
{
    orr_status st = ORR_OK;
    for (*begun = 0; !st && *begun < plan->n; (*begun)++)
        st = orr_view_begin_frame(&plan->views[*begun], observer, observer_velocity, when, plan->report[*begun], err);
    return st;
}

/* Each view's output name in this frame: its view's output.name with the
 * frame's number (none in a still), then an eye's -left or -right. */
static orr_status name_frame_outputs(orr_plan *plan, const orr_frame_time *when, orr_error *err)
{
    for (int k = 0; k < plan->n; k++) {
        view_files *f = &plan->views[k].files;
        char numbered[sizeof f->output.name];
        const orr_frame_naming naming = orr_frame_naming_of(&f->output);
        orr_status st = orr_frame_name(&naming, f->planned_name, when->frame, when->nframes, numbered,
                                       sizeof numbered, err);
        if (!st)
            st = orr_eye_output_name(f->stereo_mode, f->path, numbered, f->eye, f->output.name,
                                     sizeof f->output.name, err);
        if (st)
            return st;
    }
    return ORR_OK;
}

/* The frame's observer frame (view_camera.c), found in a pass of its own:
 * over the given particles, rewound, or the scene's input opened with only
 * the velocities the spin normal or motion blur needs. */
static orr_status observer_frame(const orr_plan *plan, orr_source *given, long frame, const orr_parallel *par,
                                 orr_sky_frame *f, orr_vec3 *velocity, orr_error *err)
{
    static const char *const velocity_fields[3] = {"vx", "vy", "vz"};
    orr_source *src = given;
    orr_status st = given ? orr_source_rewind(given, err)
                          : orr_source_request_open(&plan->source, velocity_fields, plan->observer_velocities ? 3 : 0,
                                                    &src, err);
    st = orr_view_sky_frame(&plan->observer, plan->source.scene_path, src, st, frame, par, f, velocity, err);
    if (src != given)
        orr_source_close(src);
    return st;
}

/* Commits the frame's files, all of them or none. */
static orr_status commit_outputs(orr_output_batch *outputs, orr_status st, orr_error *err)
{
    if (!st)
        st = orr_output_batch_commit(outputs, err);
    else
        orr_output_batch_name_finals(outputs, err);
    orr_output_batch_abort(outputs);
    return st;
}

/* The frame's dust (pass/dust_view.c), shared by every view. Every process dims
 * its share of the stars by all of the dust: on MPI ranks each reads the
 * whole input for it (a simulation's in-situ share cannot be). */
static orr_status prepare_dust(const orr_plan *plan, orr_source *src, const orr_parallel *par, orr_dust_frame *dust,
                               orr_error *err)
{
    orr_source *whole = NULL;
    if (par && plan->input.insitu)
        return orr_fail(err, ORR_ERR_USAGE, "%s: dust.types: in situ on %d MPI ranks each process holds only its "
                        "share of the dust (docs/dust.md#limitations)", plan->source.scene_path, par->nranks);
    if (par) {
        orr_status st = orr_source_request_open(&plan->source, plan->source.fields, plan->source.nfields, &whole, err);
        if (st)
            return st;
    }
    orr_status st = orr_dust_view_prepare(plan->passes, plan->n, whole ? whole : src, dust, err);
    orr_source_close(whole);
    return st;
}

/* What the splat pass counted, into the view's report. */
static void tally_into_report(const orr_splat_tally *t, orr_render_report *r)
{
    r->n_read = t->n_read;
    r->n_stars = t->n_stars;
    r->stars_capped = t->stars_capped;
    r->n_selected = t->n_selected;
    r->n_nonfinite = t->n_nonfinite;
    r->n_stereo_skipped = t->n_stereo_skipped;
    r->n_replicas_culled = t->n_replicas_culled;
    r->n_blocks = t->n_blocks;
    r->n_blocks_culled = t->n_blocks_culled;
    r->deposit = t->deposit;
    r->deposit_y = t->deposit_y;
}

/* From the particles to the views' planes: the smoothing lengths, the dust,
 * a periodic box's copies around this frame's cameras, the splat, and the
 * sums over processes. st is how the frame went so far: with several
 * processes every one must reach the collective check, whatever happened
 * before it. */
static orr_status splat_frame(orr_plan *plan, orr_status st, orr_source *src, const orr_parallel *par,
                              orr_lengths *lengths, orr_dust_frame *dust, int *have_dust, orr_progress_fn progress,
                              void *progress_user, orr_error *err)
{
    view_state *views = plan->views;
    const int n = plan->n;
    for (int k = 0; k < n && !st; k++) {
        snprintf(views[k].rep->source, sizeof views[k].rep->source, "%s", src->info.path);
        views[k].rep->sim_time = src->info.time;
    }
    if (!st) {
        st = prepare_lengths(views, n, src, par, lengths, err);
        charge(&views[0], ORR_STAGE_LENGTHS);
    }
    if (!st && views[0].pass.splat.dust.types) {
        st = prepare_dust(plan, src, par, dust, err);
        *have_dust = !st;
    }
    for (int k = 0; k < n && !st; k++)
        st = setup_periodic(&views[k], &src->info, err);
    if (!st) {
        st = orr_splat_views(plan->passes, n, src, progress, progress_user, err);
        for (int k = 0; k < n; k++) /* (a failed splat's counts too, as far as it went) */
            tally_into_report(&views[k].pass.tally, views[k].rep);
    }
    if (par && !(st = par->any_failed(par->user, st, err)))
        st = reduce_views(views, n, par, err);
    return st;
}

/* Which particles a frame's smoothing lengths from the neighbours belong
 * to, when every frame of a run may share them: the particles come from
 * one file (not a model, a sequence in time or a running simulation, whose
 * particles move), on one process, and no view's glow measures them from
 * its camera. The file's size and modification time are part of it, so a
 * file rewritten during a run is searched again. Returns 0 (no key) when
 * the frame's lengths must be its own. */
static int lengths_key(const orr_plan *plan, const orr_source *given, const orr_parallel *par, char *key, size_t cap)
{
    const orr_input_settings *in = &plan->input;
    if (given || par || !in->file || in->sequence.pattern || in->sequence.nfiles)
        return 0;
    for (int k = 0; k < plan->n; k++)
        if (plan->views[k].pass.splat.has_glow)
            return 0;
    struct stat st;
    if (stat(in->file, &st) != 0)
        return 0;
    int n = snprintf(key, cap, "%s|%s|%u|%d|%d|%lld|%lld.%09ld", in->file, in->format, in->type_mask,
                     in->skip_nonfinite, plan->views[0].pass.splat.deposit.neighbours, (long long)st.st_size, (long long)st.st_mtim.tv_sec,
                     (long)st.st_mtim.tv_nsec);
    return n > 0 && (size_t)n < cap;
}

/* Drops the lengths kept for the run, so the next frame finds its own. */
static void forget_kept_lengths(orr_plan *plan)
{
    orr_lengths_free(&plan->kept_lengths);
    plan->kept_lengths_key[0] = '\0';
}

/* The lengths this frame splats with: the plan's kept ones when the frame
 * draws the same particles as the frame that found them (lengths_key),
 * else frame_lengths, the frame's own. */
static orr_lengths *frame_lengths_for(orr_plan *plan, const orr_source *given, const orr_parallel *par,
                                      orr_lengths *frame_lengths)
{
    char key[sizeof plan->kept_lengths_key];
    if (!lengths_key(plan, given, par, key, sizeof key)) {
        forget_kept_lengths(plan);
        return frame_lengths;
    }
    if (strcmp(key, plan->kept_lengths_key) != 0) { /* other particles: found again, then kept */
        forget_kept_lengths(plan);
        snprintf(plan->kept_lengths_key, sizeof plan->kept_lengths_key, "%s", key);
    }
    return &plan->kept_lengths;
}

orr_status orr_plan_execute(orr_plan *plan, const orr_frame_input *in, orr_render_report *reports,
                            orr_progress_fn progress, void *progress_user, orr_error *err)
{
    if (plan->purpose != ORR_PLAN_RENDER)
        return orr_fail(err, ORR_ERR_INTERNAL, "a compose plan renders no particles");
    orr_frame_timer *timer = &plan->timer;
    memset(timer, 0, sizeof *timer);
    timer->at = orr_clock_now();
    const orr_clock start = timer->at;
    view_state *views = plan->views;
    for (int k = 0; k < plan->n; k++)
        views[k].pass.timer = timer;
    const orr_frame_time still = orr_frame_at(0, 1, plan->fps, 0, 0);
    const orr_frame_time *when = in ? &in->time : &still;
    const orr_parallel *par = in && in->parallel && in->parallel->nranks > 1 ? in->parallel : NULL;
    orr_source *given = in ? in->source : NULL, *src = NULL;
    orr_status st = check_view_dirs(plan, err);
    if (!st && par && !given && !(st = open_share(&plan->source, par, &src, err)))
        given = src;
    /* A built-in model is opened once for the observer's pass and the
     * frame's: opening one builds its tables (a quarter of a second of CPU
     * for mw-m31), and it makes every field whichever are asked for. A
     * file's observer pass opens its own, reading only the velocities. */
    if (!st && !given && plan->observer.has_id && plan->input.model.name[0])
        st = frame_particles(&plan->source, NULL, &src, err);
    /* The observer's frame moves with the particles: found every frame, by
     * a pass over them (reading, as the splat's). */
    orr_sky_frame observer;
    orr_vec3 observer_velocity = orr_v3(0, 0, 0);
    if (!st && plan->observer.has_id)
        st = observer_frame(plan, given ? given : src, when->frame, par, &observer, &observer_velocity, err);
    orr_stage_charge(&timer->times, ORR_STAGE_SOURCE, &timer->at);
    /* A stereo view renders as two views, its eyes, each reporting into
     * its view's report (the right eye's outputs added to the left's). */
    frame_reports_begin(plan, reports);
    int begun = 0;
    if (!st && !(st = begin_frame(plan, plan->observer.has_id ? &observer : NULL, observer_velocity, when, &begun, err)))
        st = name_frame_outputs(plan, when, err);
    if (!st && plan->has_stars) { /* the stars are seen from the observer (scene_check.c) */
        orr_frame_stars_begin(&plan->stars, &observer);
        plan->stars.whole_list = par == NULL; /* on ranks, each has its own share's stars */
        for (int k = 0; k < plan->n; k++)
            views[k].pass.stars = &plan->stars;
    }
    charge(&views[0], ORR_STAGE_SETUP);
    if (!st)
        st = frame_particles(&plan->source, given ? given : src, &src, err); /* (src: the model opened above) */
    if (!st)
        frame_units(plan, src);
    charge(&views[0], ORR_STAGE_SOURCE);
    orr_lengths own_lengths = {0};
    orr_lengths *lengths = frame_lengths_for(plan, given, par, &own_lengths);
    orr_dust_frame dust;
    int have_dust = 0;
    st = splat_frame(plan, st, src, par, lengths, &dust, &have_dust, progress, progress_user, err);
    if (st && lengths == &plan->kept_lengths) /* a frame that failed keeps nothing for the next */
        forget_kept_lengths(plan);
    charge(&views[0], ORR_STAGE_REDUCE);
    orr_output_batch outputs;
    orr_output_batch_init(&outputs);
    for (int k = 0; k < begun; k++)
        views[k].outputs = &outputs;
    if (!st && (!par || par->rank == 0))
        st = finish_views(plan, in, err);
    st = commit_outputs(&outputs, st, err);
    charge(&views[0], ORR_STAGE_COMMIT);
    if (!in || src != in->source)
        orr_source_close(src);
    orr_lengths_free(&own_lengths);
    if (have_dust)
        orr_dust_frame_free(&dust);
    for (int k = 0; k < plan->n; k++) /* the frame's, freed above and below */
        forget_frame(plan, k);
    frame_reports_finish(plan);
    orr_stage_times_finish(&timer->times, start);
    charge_planning(plan);
    for (int k = 0; k < plan->nscenes && !st; k++)
        reports[k].times = timer->times;
    return st;
}

orr_status orr_plan_compose(orr_plan *plan, const orr_compose_frame *frame, orr_render_report *reports,
                            orr_error *err)
{
    if (plan->purpose != ORR_PLAN_COMPOSE)
        return orr_fail(err, ORR_ERR_INTERNAL, "a render plan does not compose");
    /* No particles, so no observer frame: the world's stands in (the camera
     * matters only for FITS cards, and compose writes PNGs). */
    orr_sky_frame observer = orr_sky_frame_world(orr_v3(0, 0, 0));
    const orr_frame_time still = orr_frame_at(0, 1, plan->fps, 0, 0);
    const orr_frame_time *when = frame ? &frame->time : &still;
    /* As a render does: the output folder is made, or found unwritable,
     * before any work. */
    orr_status st = check_view_dirs(plan, err);
    int begun = 0;
    for (int k = 0; k < plan->n; k++)
        plan->views[k].pass.timer = NULL;
    frame_reports_begin(plan, reports);
    if (!st && !(st = begin_frame(plan, plan->observer.has_id ? &observer : NULL, orr_v3(0, 0, 0), when, &begun, err)))
        st = name_frame_outputs(plan, when, err);
    for (int k = 0; k < plan->n && frame && frame->white; k++)
        if (isfinite(frame->white[plan->origin[k]]))
            orr_view_regrade_final(&plan->views[k].files, frame->white[plan->origin[k]]);
    orr_output_batch outputs;
    orr_output_batch_init(&outputs);
    for (int k = 0; k < begun; k++)
        plan->views[k].outputs = &outputs;
    for (int k = 0; k < plan->n && !st; k++)
        st = orr_view_compose(&plan->views[k], err);
    st = commit_outputs(&outputs, st, err);
    for (int k = 0; k < plan->n; k++)
        forget_frame(plan, k);
    frame_reports_finish(plan);
    return st;
}
