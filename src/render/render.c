/* The renderer's driver: a frame's sources, the observer frame and the
 * cameras, each view's set-up (projection, PSF, kernel, motion blur), the
 * smoothing lengths, then the splat pass (splat_pass.c), the reduction over
 * processes and the views' files (view_outputs.c); and compose, which
 * re-grades raw planes. */
#include "render/render.h"
#include "render/view_state.h"
#include "core/numbers.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/atomic.h"
#include "encode/fits.h"
#include "encode/fits_read.h"
#include "post/brightness.h"
#include "render/lengths.h"
#include "render/motion_blur.h"
#include "render/periodic_view.h"
#include "render/stereo_view.h"
#include "render/view_psf.h"
#include "scene/scene_output.h"
#include "source/king.h"
#include "source/model.h"
#include "source/partition.h"
#include "source/sequence.h"
#include "splat/sph.h"


orr_status orr_scene_open_source(const orr_scene *s, const char *const *fields, int nfields, orr_source **out,
                                 orr_error *err)
{
    return orr_scene_open_share(s, fields, nfields, 0, 1, out, err);
}

/* The types a reader keeps. The observer and reference particles may be of
 * types the scene does not draw: then the reader must not drop them (the
 * splat selects input.types itself); nor the dust (dust.types). */
static unsigned reader_types(const orr_scene *s)
{
    return s->has_observer ? 0 : s->type_mask | s->dust.types;
}

orr_status orr_scene_open_share(const orr_scene *s, const char *const *fields, int nfields, int part, int nparts,
                                orr_source **out, orr_error *err)
{
    if (orr_scene_has_sequence(s)) {
        /* A sequence's frames come from orr_render_animation, which opens it
         * once for the run; alone (a path overview), its first snapshot. */
        char first[ORR_PATH_MAX];
        orr_status st = ORR_OK;
        if (s->seq_nfiles > 0)
            snprintf(first, sizeof first, "%s", orr_scene_sequence_file(s, 0));
        else
            st = orr_sequence_pattern_path(s->seq_pattern, s->seq_first, first, sizeof first, err);
        orr_source_options opt = {s->input_format, (size_t)s->chunk_size, reader_types(s), fields, nfields, 0, 1};
        return st ? st : orr_source_open_file(first, &opt, out, err);
    }
    if (!s->model_name[0] && !s->input_file[0])
        return orr_fail(err, ORR_ERR_USAGE,
                        "%s: an in-situ scene (input.insitu) has no particles of its own: a running simulation "
                        "hands them over through orrery.h; set input.file or input.model.name to render it here",
                        s->path);
    if (strcmp(s->model_name, "king") == 0) {
        orr_king_params kp = {s->model_particles, s->model_seed, s->model_w0, s->model_core_radius, s->model_mass};
        return orr_king_source_open(&kp, (size_t)s->chunk_size, out, err);
    }
    if (s->model_name[0]) {
        orr_model_params mp = {s->model_particles, s->model_seed, s->model_separation, s->model_galaxies,
                               s->model_disc_q};
        return orr_model_source_open_dust(&mp, s->model_dust_particles, (size_t)s->chunk_size, out, err);
    }
    orr_source_options opt = {s->input_format, (size_t)s->chunk_size, reader_types(s), fields, nfields, part, nparts};
    return orr_source_open_file(s->input_file, &opt, out, err);
}

/* ---- the observer frame ---- */

typedef struct markers {
    int have_observer, have_reference;
    orr_vec3 observer, reference;
    orr_vec3 observer_velocity; /* (0 when the source has no velocities) */
} markers;

/* Particle i's velocity, or 0 when the chunk has none. */
static orr_vec3 chunk_velocity(const orr_chunk *c, size_t i)
{
    const float *vx = orr_chunk_field(c, "vx"), *vy = orr_chunk_field(c, "vy"), *vz = orr_chunk_field(c, "vz");
    return vx && vy && vz ? orr_v3(vx[i], vy[i], vz[i]) : orr_v3(0, 0, 0);
}

/* One pass over the source for the observer and reference particles. */
static orr_status find_markers(const orr_scene *s, orr_source *src, markers *m, orr_error *err)
{
    memset(m, 0, sizeof *m);
    for (;;) {
        const orr_chunk *c;
        orr_status st = orr_source_next(src, &c, err);
        if (st || c->n == 0)
            return st;
        for (size_t i = 0; i < c->n; i++) {
            orr_vec3 p = orr_v3(c->x[i], c->y[i], c->z[i]);
            if (c->id[i] == s->observer_id) {
                m->observer = p;
                m->observer_velocity = chunk_velocity(c, i);
                m->have_observer = 1;
            } else if (c->id[i] == s->reference_id) {
                m->reference = p;
                m->have_reference = 1;
            }
        }
    }
}

/* The disc normal from the spin of the chosen particles within
 * normal_radius of the reference: L = sum m (r - c) x (v - <v>). */
static orr_status spin_normal(const orr_scene *s, orr_source *src, orr_vec3 centre, const orr_parallel *par,
                              orr_vec3 *n0, orr_error *err)
{
    orr_vec3 mr_x_v = {0, 0, 0}, mr = {0, 0, 0}, mv = {0, 0, 0};
    double mass = 0, r2max = s->normal_radius * s->normal_radius;
    for (;;) {
        const orr_chunk *c;
        orr_status st = orr_source_next(src, &c, err);
        if (st)
            return st;
        if (c->n == 0)
            break;
        const float *vx = orr_chunk_field(c, "vx"), *vy = orr_chunk_field(c, "vy"), *vz = orr_chunk_field(c, "vz");
        if (!vx || !vy || !vz)
            return orr_fail(err, ORR_ERR_USAGE, "%s: observer.normal_from needs velocities (vx, vy, vz), which %s lacks",
                            s->path, src->info.path);
        for (size_t i = 0; i < c->n; i++) {
            if (!(s->normal_types & (1u << c->type[i])))
                continue;
            orr_vec3 r = orr_v3_sub(orr_v3(c->x[i], c->y[i], c->z[i]), centre), v = orr_v3(vx[i], vy[i], vz[i]);
            if (!(orr_v3_dot(r, r) <= r2max))
                continue;
            double m = c->mass[i];
            mr_x_v = orr_v3_add(mr_x_v, orr_v3_scale(orr_v3_cross(r, v), m));
            mr = orr_v3_add(mr, orr_v3_scale(r, m));
            mv = orr_v3_add(mv, orr_v3_scale(v, m));
            mass += m;
        }
    }
    if (par && par->nranks > 1) {
        double v[10] = {mr_x_v.x, mr_x_v.y, mr_x_v.z, mr.x, mr.y, mr.z, mv.x, mv.y, mv.z, mass};
        orr_status st = par->allreduce_sum(par->user, v, 10, err);
        if (st)
            return st;
        mr_x_v = orr_v3(v[0], v[1], v[2]);
        mr = orr_v3(v[3], v[4], v[5]);
        mv = orr_v3(v[6], v[7], v[8]);
        mass = v[9];
    }
    if (!(mass > 0))
        return orr_fail(err, ORR_ERR_DATA, "%s: no particle of the observer.normal_from types lies within %g of the reference particle",
                        s->path, s->normal_radius);
    /* Removing the mean velocity: sum m r x (v - <v>) = sum m r x v - (sum m r) x <v>. */
    orr_vec3 L = orr_v3_sub(mr_x_v, orr_v3_scale(orr_v3_cross(mr, mv), 1.0 / mass));
    if (!(orr_v3_norm(L) > 0))
        return orr_fail(err, ORR_ERR_DATA, "%s: the observer.normal_from particles have no net spin", s->path);
    *n0 = orr_v3_scale(orr_v3_normalize(L), s->normal_sign);
    return ORR_OK;
}

/* With several processes, each found what its share holds: sum the finds
 * (a particle is in exactly one share). */
static orr_status combine_markers(const orr_parallel *par, markers *m, orr_error *err)
{
    if (!par || par->nranks <= 1)
        return ORR_OK;
    double v[11] = {m->have_observer, m->have_reference, m->observer.x, m->observer.y, m->observer.z,
                    m->reference.x, m->reference.y, m->reference.z,
                    m->observer_velocity.x, m->observer_velocity.y, m->observer_velocity.z};
    orr_status st = par->allreduce_sum(par->user, v, 11, err);
    m->have_observer = v[0] > 0;
    m->have_reference = v[1] > 0;
    m->observer = orr_v3(v[2], v[3], v[4]);
    m->reference = orr_v3(v[5], v[6], v[7]);
    m->observer_velocity = orr_v3(v[8], v[9], v[10]);
    return st;
}

/* Finds the observer and reference particles (and the spin normal when
 * asked) in a pass of their own, with only the fields that needs. */
static orr_status build_sky_frame(const orr_scene *s, orr_source *given, long frame, const orr_parallel *par,
                                  orr_sky_frame *f, orr_vec3 *velocity, orr_error *err)
{
    static const char *const velocity_fields[3] = {"vx", "vy", "vz"};
    int want_spin = s->normal_types != 0;
    orr_source *src = given;
    orr_status st = given ? orr_source_rewind(given, err)
                          : orr_scene_open_source(s, velocity_fields, want_spin || orr_blur_moves_particles(s) ? 3 : 0,
                                                  &src, err);
    markers m;
    if (!st)
        st = find_markers(s, src, &m, err);
    if (par && par->nranks > 1 && !(st = par->any_failed(par->user, st, err)))
        st = combine_markers(par, &m, err);
    if (!st && (!m.have_observer || !m.have_reference))
        st = orr_fail(err, ORR_ERR_DATA, "%s: %s particle id %llu (observer.%s in %s) not found, frame %ld",
                      src->info.path, m.have_observer ? "reference" : "observer",
                      (unsigned long long)(m.have_observer ? s->reference_id : s->observer_id),
                      m.have_observer ? "reference_id" : "id", s->path, frame);
    orr_vec3 n0 = s->observer_normal;
    if (!st && want_spin && !(st = orr_source_rewind(src, err)))
        st = spin_normal(s, src, m.reference, par, &n0, err);
    *velocity = m.observer_velocity;
    if (!st && (st = orr_sky_frame_build(f, m.observer, m.reference, n0, err)))
        orr_fail_prefix(err, "%s: observer id %llu, reference id %llu, frame %ld: ", s->path,
                        (unsigned long long)s->observer_id, (unsigned long long)s->reference_id, frame);
    if (src != given)
        orr_source_close(src);
    return st;
}

/* ---- cameras ---- */

static int has_orientation(const orr_scene *s)
{
    return s->has_quaternion || s->has_look_at || s->has_direction;
}

static orr_status scene_camera(const orr_scene *s, const orr_frame_time *when, orr_camera *cam, orr_error *err)
{
    if (s->has_path)
        return orr_path_camera(&s->camera_path, when, cam, err);
    return orr_scene_static_camera(s, cam, err);
}

/* The camera of a view. From an observer, or for a sky map without an
 * orientation of its own, the camera follows the sky frame: the map centred
 * on l = 0 with north up, or the dome's zenith and front. */
static orr_status view_camera(const orr_scene *s, const orr_sky_frame *observer, const orr_frame_time *when,
                              orr_camera *cam, orr_sky_frame *sky, orr_error *err)
{
    /* A camera path moves and turns the camera frame by frame, sky maps
     * included (scenes with a path have no observer: scene_check). */
    if (s->has_path) {
        orr_status st = scene_camera(s, when, cam, err);
        *sky = orr_sky_frame_world(cam->position);
        return st;
    }
    int sky_map = orr_projection_is_sky(&s->projection);
    if (!observer && (!sky_map || has_orientation(s))) {
        *sky = orr_sky_frame_world(s->camera_position);
        return scene_camera(s, when, cam, err);
    }
    *sky = observer ? *observer : orr_sky_frame_world(s->camera_position);
    if (s->projection.kind == ORR_PROJ_DOME)
        return orr_sky_camera_dome(cam, sky, s->zenith_lb, s->front_lb, s->dome_tilt, err);
    return orr_sky_camera_centre(cam, sky, s->camera_roll, err);
}

/* ---- the driver ---- */

/* The view's camera dframe frames from this one (motion blur's shutter
 * opening and closing): along the camera path, or from an observer moved
 * by observer_step; a perspective stereo eye set as in this frame. */
static orr_status camera_at(const view_state *v, const orr_sky_frame *observer, orr_vec3 observer_step,
                            const orr_frame_time *when, double dframe, orr_camera *cam, orr_error *err)
{
    const orr_scene *s = v->scene;
    orr_status st;
    if (s->has_path) {
        double u = when->nframes > 1 ? when->u + dframe / (double)(when->nframes - 1) : when->u;
        st = orr_path_eval(&s->camera_path, (double)when->frame + dframe, u, cam, err);
    } else {
        orr_sky_frame moved, sky;
        if (observer) {
            moved = *observer;
            moved.origin = orr_v3_add(moved.origin, observer_step);
        }
        st = view_camera(s, observer ? &moved : NULL, when, cam, &sky, err);
    }
    if (!st && s->stereo_eye && v->proj.kind == ORR_PROJ_PERSPECTIVE) {
        orr_projection p = s->projection;
        if (!(st = orr_projection_setup(&p, err)))
            st = orr_stereo_perspective_eye(cam, &p, s->stereo_eye, s->eye_separation, v->rep->stereo_convergence,
                                            err);
    }
    return st ? orr_fail_prefix(err, "%s: animation.shutter: ", s->path) : ORR_OK;
}

/* Motion blur's plan (animation.shutter): the cameras when the shutter
 * opens and closes, half a shutter before and after the frame, and the
 * simulation time the particles move over (the frame interval's share). */
static orr_status setup_blur(view_state *v, const orr_sky_frame *observer, orr_vec3 observer_velocity,
                             const orr_frame_time *when, orr_error *err)
{
    const orr_scene *s = v->scene;
    if (!(s->shutter > 0))
        return ORR_OK;
    const double interval = !orr_blur_moves_particles(s) ? 0 : s->has_frame_interval ? s->frame_interval
                                                                                      : when->interval;
    const double half_time = 0.5 * s->shutter * interval, half_frame = 0.5 * s->shutter;
    const orr_vec3 step = orr_v3_scale(observer_velocity, half_time);
    orr_camera open, close;
    orr_status st = camera_at(v, observer, orr_v3_scale(step, -1), when, -half_frame, &open, err);
    if (!st)
        st = camera_at(v, observer, step, when, half_frame, &close, err);
    if (!st)
        orr_motion_blur_plan(&v->blur, half_time, &open, &close, &v->proj);
    return st;
}

static orr_status setup_view(view_state *v, const orr_scene *s, const orr_sky_frame *observer,
                             orr_vec3 observer_velocity, const orr_frame_time *when, orr_render_report *rep,
                             orr_error *err)
{
    memset(rep, 0, sizeof *rep);
    rep->frame = when->frame;
    rep->nframes = when->nframes;
    v->scene = s;
    v->rep = rep;
    v->proj = s->projection;
    v->tint_t = s->tint_run ? when->u : s->tint_t;
    orr_status st = orr_projection_setup(&v->proj, err);
    if (!st)
        st = view_camera(s, observer, when, &rep->camera, &rep->sky, err);
    if (st)
        return orr_fail_prefix(err, "%s: ", s->path);
    if ((st = orr_stereo_setup_eye(s, &v->proj, rep, &v->ods, &v->use_ods, err)) ||
        (st = setup_blur(v, observer, observer_velocity, when, err)))
        return st;
    rep->has_sky_frame = observer != NULL;
    v->world_to_camera = orr_camera_world_to_camera(&rep->camera);
    static const char *const xyz_names[3] = {"X", "Y", "Z"};
    v->nplanes = s->colour || s->nlayers ? 3 : 1;
    st = ORR_OK;
    char unit[ORR_PLANE_NAME_MAX];
    orr_brightness_unit(&v->proj, scene_weight_unit(s), scene_length_unit(s), unit, sizeof unit);
    for (int k = 0; k < v->nplanes && !st; k++)
        st = orr_plane_alloc(&v->planes[k], v->proj.width, v->proj.height, s->colour ? xyz_names[k] : s->weight,
                             unit, err);
    /* The kernel's tables take milliseconds to build: only for kernel
     * deposits and PSFs (a sky map's is drawn with the kernel). */
    int needs_kernel = s->deposit == ORR_DEPOSIT_SPH || s->psf != ORR_PSF_NONE;
    if (!st && needs_kernel)
        st = orr_kernel_init(&v->kernel, s->kernel, err);
    v->kernel_ready = !st && needs_kernel;
    if (!st)
        st = orr_view_psf_setup(&v->psf, s, &v->proj, &v->kernel, err);
    v->use_sph = s->deposit == ORR_DEPOSIT_SPH || v->psf.h_per_r > 0;
    orr_splat_choose_path(v);
    v->outline = orr_map_outline_of(&v->proj, v->proj.width, v->proj.height);
    if (!st && v->use_sph)
        st = orr_sph_init(&v->sph, &v->kernel, &v->proj, err);
    v->sph_ready = !st && v->use_sph;
    /* A sky map's PSF cores: stars are drawn from stamps (splat/sky_cores.h).
     * widen_for_psf gives a star without a length of its own h = k r, k the
     * float of h_per_r: its angle h / r. */
    if (!st && v->use_sph && v->psf.h_per_r > 0)
        st = orr_sph_use_cores(&v->sph, (float)v->psf.h_per_r, err);
    return st;
}

static void free_view(view_state *v)
{
    orr_splat_free_lanes(v);
    orr_bands_free(&v->bands);
    for (int k = 0; k < 3; k++)
        orr_plane_free(&v->planes[k]);
    orr_view_psf_free(&v->psf);
    if (v->sph_ready)
        orr_sph_free(&v->sph);
    if (v->kernel_ready)
        orr_kernel_free(&v->kernel);
}

/* Smoothing lengths from the neighbours, computed once for every view that
 * needs them (views share input.*, so the same particles take them). */
static orr_status prepare_lengths(view_state *views, int n, orr_source *src, const orr_parallel *par,
                                  orr_lengths *lengths, orr_error *err)
{
    for (int k = 0; k < n; k++) {
        view_state *v = &views[k];
        int needed;
        orr_status st = orr_lengths_needed(v->scene, src, &needed, err);
        if (st)
            return st;
        /* orrery's h is half the kernel's support: convert the file's. */
        double support = src->info.h_support > 0 ? src->info.h_support : 2.0;
        v->h_scale = (float)(v->scene->h_scale * support / 2.0);
        if (!needed)
            continue;
        /* The glow's lengths are angles seen from the camera (glow_length). */
        const orr_vec3 *centre = v->scene->has_glow ? &v->rep->camera.position : NULL;
        if (par && !centre)
            return orr_fail(err, ORR_ERR_USAGE,
                            "%s: smoothing lengths from the neighbours need every particle in one process; with "
                            "%d MPI ranks use lengths from the file (smoothing.lengths: file)",
                            v->scene->path, par->nranks);
        v->h_scale = (float)v->scene->h_scale;
        if (!lengths->h && !lengths->angular && /* (computed, but none here: a process's share may be empty) */
            (st = orr_lengths_compute(v->scene, src, centre, par, lengths, err)))
            return st;
        if (lengths->angular != (centre != NULL) ||
            (centre && orr_v3_norm(orr_v3_sub(lengths->centre, *centre)) > 0))
            return orr_fail(err, ORR_ERR_USAGE,
                            "%s: the views of a frame share one set of smoothing lengths, but view %d %s; give "
                            "every view glow.threshold from the same place, or none of them",
                            v->scene->path, k, centre ? "glows from another camera position" : "has no glow");
        v->lengths = lengths;
    }
    return ORR_OK;
}

/* A periodic box's copies around the view's camera. Skipping what is out
 * of view needs particles drawn where they are: not with omni-directional
 * stereo, a sky map's PSF widening kernels, or weights dimmed with distance. */
static orr_status setup_periodic(view_state *v, const orr_source_info *info, orr_error *err)
{
    const orr_scene *s = v->scene;
    int can_cull = !v->use_ods && !(v->psf.h_per_r > 0) && !(s->has_observer && s->dim);
    orr_status st = orr_periodic_view_setup(&v->periodic, s, info, &v->proj, &v->rep->camera, can_cull, err);
    v->rep->n_replicas = v->periodic.active ? v->periodic.replicas.n : 0;
    return st;
}

orr_status orr_render_views(const orr_scene *const *scenes, int n, orr_render_report *reports,
                            orr_progress_fn progress, void *progress_user, orr_error *err)
{
    return orr_render_frame(scenes, n, NULL, reports, progress, progress_user, err);
}

/* This process's share of the scene's input, when several processes render
 * the frame: with the fields the sky frame and the weight need. */
/* Appends name to fields[0..*n) unless it is empty, mass or h (never extra
 * fields), already there, or there is no room. */
static void add_field(const char **fields, int *n, const char *name)
{
    if (!name[0] || strcmp(name, "mass") == 0 || strcmp(name, "h") == 0 || *n >= ORR_RENDER_MAX_FIELDS)
        return;
    for (int i = 0; i < *n; i++)
        if (strcmp(fields[i], name) == 0)
            return;
    fields[(*n)++] = name;
}

int orr_render_fields(const orr_scene *s, const char *fields[ORR_RENDER_MAX_FIELDS])
{
    int nfields = 0;
    add_field(fields, &nfields, s->weight);
    /* Readers that load only the fields asked for (HDF5) must load these,
     * or a population choosing by stellar age would find no ages. */
    for (int i = 0; s->colour && i < s->populations.n; i++) {
        const orr_population *p = &s->populations.pop[i];
        add_field(fields, &nfields, p->select.range_field);
        add_field(fields, &nfields, p->select.prob_field);
        if (p->colour.kind != ORR_POPCOLOUR_FIXED)
            add_field(fields, &nfields, p->colour.field);
        if (p->colour.kind == ORR_POPCOLOUR_SSP)
            add_field(fields, &nfields, p->colour.ssp.metallicity_field);
        if (p->lum.kind == ORR_POPLUM_FIELD || p->lum.kind == ORR_POPLUM_MAGNITUDE)
            add_field(fields, &nfields, p->lum.field);
    }
    if (s->dust.types)
        add_field(fields, &nfields, s->dust.metallicity);
    if ((s->has_observer && s->normal_types) || orr_blur_moves_particles(s)) {
        add_field(fields, &nfields, "vx");
        add_field(fields, &nfields, "vy");
        add_field(fields, &nfields, "vz");
    }
    return nfields;
}

static orr_status open_share(const orr_scene *s, const orr_parallel *par, orr_source **out, orr_error *err)
{
    const char *fields[ORR_RENDER_MAX_FIELDS];
    int nfields = orr_render_fields(s, fields);
    orr_source *whole = NULL;
    /* File readers that can seek read only this rank's share; the others,
     * and the generators, are dealt out by chunks. */
    orr_status st = orr_scene_open_share(s, fields, nfields, par->rank, par->nranks, &whole, err);
    return st ? st : orr_source_partition(whole, par->rank, par->nranks, out, err);
}

/* Sums what every process splatted onto rank 0: the planes, and the counts
 * of the reports. */
static orr_status reduce_views(view_state *views, int n, const orr_parallel *par, orr_error *err)
{
    orr_status st = ORR_OK;
    for (int k = 0; k < n && !st; k++) {
        view_state *v = &views[k];
        for (int j = 0; j < v->nplanes && !st; j++)
            st = par->reduce_sum(par->user, v->planes[j].data, (size_t)v->proj.width * (size_t)v->proj.height, err);
        orr_render_report *r = v->rep;
        orr_deposit_stats *d[2] = {&r->deposit, &r->deposit_y};
        double sums[3 + 2 * 5 + 3] = {(double)r->n_read, (double)r->n_selected, (double)r->n_nonfinite};
        for (int i = 0; i < 2; i++) {
            double *t = &sums[3 + 5 * i];
            t[0] = d[i]->deposited, t[1] = d[i]->outside, t[2] = d[i]->culled;
            t[3] = (double)d[i]->n_particles, t[4] = (double)d[i]->n_culled;
        }
        double *culling = &sums[3 + 2 * 5]; /* a periodic box's culled copies and blocks */
        culling[0] = (double)r->n_replicas_culled, culling[1] = (double)r->n_blocks;
        culling[2] = (double)r->n_blocks_culled;
        if (!st)
            st = par->allreduce_sum(par->user, sums, sizeof sums / sizeof sums[0], err);
        r->n_read = (uint64_t)sums[0], r->n_selected = (uint64_t)sums[1], r->n_nonfinite = (uint64_t)sums[2];
        for (int i = 0; i < 2; i++) {
            const double *t = &sums[3 + 5 * i];
            d[i]->deposited = t[0], d[i]->outside = t[1], d[i]->culled = t[2];
            d[i]->n_particles = (uint64_t)t[3], d[i]->n_culled = (uint64_t)t[4];
        }
        r->n_replicas_culled = (uint64_t)culling[0], r->n_blocks = (uint64_t)culling[1];
        r->n_blocks_culled = (uint64_t)culling[2];
        if (!st && v->psf.sky) /* rank 0 draws the whole frame's brightest stars */
            st = orr_sky_psf_share(v->psf.sky, par->rank, par->nranks, par->allreduce_sum, par->user, err);
    }
    return st;
}

/* The planes before the PSF (for orrery compose), the PSF, and the outputs. */
/* Hands view k's final planes, its graded picture and its cards to the
 * frame's keeper (orr_frame_input.keep). */
static orr_status keep_view(view_state *v, int k, const orr_frame_input *in, orr_error *err)
{
    size_t npix = (size_t)v->proj.width * (size_t)v->proj.height;
    float *rgb = orr_malloc(npix * 3 * sizeof *rgb, "kept picture", err);
    orr_fits_header *h = rgb ? orr_calloc(1, sizeof *h, "FITS header", err) : NULL;
    orr_status st = h ? ORR_OK : ORR_ERR_NOMEM;
    char desc[ORR_PATH_MAX + 256];
    if (!st)
        st = orr_view_graded_rgb(v, rgb, desc, sizeof desc, err);
    if (!st) {
        orr_view_add_frame_cards(v, h);
        st = in->keep(in->keep_user, k, v->planes, v->nplanes, rgb, h, err);
    }
    free(rgb);
    free(h);
    return st;
}

/* A sky map's, or a flat view's given psf.fwhm, brightest stars with the
 * whole PSF (render/sky_psf.h, render/flat_psf.h). */
static orr_status draw_bright_stars(view_state *v, orr_error *err)
{
    if (!v->psf.sky)
        return ORR_OK;
    if (!v->psf.core)
        return orr_sky_psf_draw(v->psf.sky, &v->sph, v->planes, v->nplanes, err);
    orr_flat_deposit dep = {v->scene->deposit, &v->proj, v->use_sph ? &v->sph : NULL};
    return orr_flat_psf_draw(v->psf.sky, &dep, v->psf.core, v->planes, v->nplanes, err);
}

static orr_status finish_views(view_state *views, int n, orr_eye_views *eyes, const orr_frame_input *in,
                               orr_error *err)
{
    int keep = in && in->keep;
    orr_status st = ORR_OK;
    for (int k = 0; k < n && !st; k++) /* bright stars' PSFs: part of the raw planes, as the cores */
        st = draw_bright_stars(&views[k], err);
    charge(&views[0], ORR_STAGE_PSF);
    for (int k = 0; k < n && !st; k++) /* flux per pixel to flux per steradian (or area) */
        orr_to_surface_brightness(&views[k].proj, views[k].planes, views[k].nplanes);
    charge(&views[0], ORR_STAGE_POST);
    for (int k = 0; k < n && !st; k++)
        if (views[k].scene->write_raw) {
            orr_view_mask_outside_map(&views[k]);
            charge(&views[k], ORR_STAGE_POST);
            st = orr_view_write_fits_planes(&views[k], "raw.fits", err);
        }
    for (int k = 0; k < n && !st; k++)
        for (int j = 0; j < views[k].nplanes && !st; j++)
            st = orr_view_psf_apply(&views[k].psf, &views[k].planes[j], err);
    charge(&views[0], ORR_STAGE_PSF);
    for (int k = 0; k < n && !st; k++) {
        if (orr_eye_views_pair_at(eyes, k)) {
            st = orr_view_write_stereo_pair(&views[k], &views[k + 1], eyes, k, err);
            if (!st && keep && !(st = keep_view(&views[k], k, in, err)))
                st = keep_view(&views[k + 1], k + 1, in, err);
            k++; /* the right eye was written with the left */
            continue;
        }
        st = orr_view_write_outputs(&views[k], err);
        orr_eye_views_share_white(eyes, k, views[k].rep->white); /* separate eyes: grade the right alike */
        if (!st && keep)
            st = keep_view(&views[k], k, in, err);
    }
    return st;
}

orr_status orr_render_frame(const orr_scene *const *scenes, int n, const orr_frame_input *in,
                            orr_render_report *reports, orr_progress_fn progress, void *progress_user,
                            orr_error *err)
{
    if (n < 1)
        return orr_fail(err, ORR_ERR_USAGE, "no view to render");
    const int nscenes = n;
    frame_timer timer;
    memset(&timer, 0, sizeof timer);
    timer.at = orr_clock_now();
    const orr_clock start = timer.at;
    const orr_scene *s0 = scenes[0];
    const orr_frame_time still = orr_frame_at(0, 1, s0->anim_fps, 0, 0);
    const orr_frame_time *when = in ? &in->time : &still;
    const orr_parallel *par = in && in->parallel && in->parallel->nranks > 1 ? in->parallel : NULL;
    orr_source *given = in ? in->source : NULL, *src = NULL;
    orr_status st = ORR_OK;
    /* Fail on an unwritable output folder before any slow work. */
    for (int k = 0; k < n && !st; k++)
        st = orr_check_output_dir(scenes[k]->out_dir, err);
    if (!st && par && !given && !(st = open_share(s0, par, &src, err)))
        given = src;
    orr_sky_frame observer;
    orr_vec3 observer_velocity = orr_v3(0, 0, 0);
    if (!st && s0->has_observer)
        st = build_sky_frame(s0, given, when->frame, par, &observer, &observer_velocity, err);
    /* The observer's frame is found by a pass over the particles (or with
     * them opened for this process's share): reading, as the splat's. */
    orr_stage_charge(&timer.times, ORR_STAGE_SOURCE, &timer.at);
    /* A stereo view renders as two views, its eyes. */
    orr_eye_views eyes = {0};
    if (!st)
        st = orr_eye_views_expand(scenes, n, reports, &eyes, err);
    n = eyes.n;
    view_state *views = st ? NULL : orr_calloc((size_t)n, sizeof *views, "views", err);
    if (!st && !views)
        st = ORR_ERR_NOMEM;
    int ready = 0;
    for (; !st && ready < n; ready++) {
        views[ready].timer = &timer;
        st = setup_view(&views[ready], eyes.scene[ready], s0->has_observer ? &observer : NULL, observer_velocity,
                        when, eyes.report[ready], err);
    }
    if (views)
        charge(&views[0], ORR_STAGE_SETUP);
    orr_lengths lengths = {0};
    if (!st && given) {
        src = given;
        st = orr_source_rewind(src, err);
    } else if (!st) {
        const char *fields[ORR_RENDER_MAX_FIELDS];
        int nfields = orr_render_fields(s0, fields);
        st = orr_scene_open_source(s0, fields, nfields, &src, err);
    }
    if (views)
        charge(&views[0], ORR_STAGE_SOURCE);
    if (!st) {
        for (int k = 0; k < n; k++) {
            snprintf(views[k].rep->source, sizeof views[k].rep->source, "%s", src->info.path);
            views[k].rep->sim_time = src->info.time;
        }
        st = prepare_lengths(views, n, src, par, &lengths, err);
        charge(&views[0], ORR_STAGE_LENGTHS);
    }
    orr_dust_frame dust;
    int have_dust = 0;
    if (!st && s0->dust.types) {
        st = orr_dust_view_prepare(views, n, src, par, &dust, err);
        have_dust = !st;
    }
    for (int k = 0; k < n && !st; k++)
        st = setup_periodic(&views[k], &src->info, err);
    if (!st)
        st = orr_splat_views(views, n, src, progress, progress_user, err);
    if (par && !(st = par->any_failed(par->user, st, err)))
        st = reduce_views(views, n, par, err);
    if (views)
        charge(&views[0], ORR_STAGE_REDUCE);
    orr_output_batch outputs;
    orr_output_batch_init(&outputs);
    for (int k = 0; k < ready; k++)
        views[k].outputs = &outputs;
    if (!st && (!par || par->rank == 0))
        st = finish_views(views, n, &eyes, in, err);
    /* All of the frame's files, or none of them. */
    if (!st)
        st = orr_output_batch_commit(&outputs, err);
    else
        orr_output_batch_name_finals(&outputs, err);
    orr_output_batch_abort(&outputs);
    if (views)
        charge(&views[0], ORR_STAGE_COMMIT);
    if (!in || src != in->source)
        orr_source_close(src);
    orr_lengths_free(&lengths);
    if (have_dust)
        orr_dust_frame_free(&dust);
    for (int k = 0; k < ready && views; k++)
        free_view(&views[k]);
    free(views);
    orr_eye_views_finish(&eyes);
    /* The frees above belong to no stage: the totals include them. */
    orr_stage_times_finish(&timer.times, start);
    for (int k = 0; k < nscenes && !st; k++)
        reports[k].times = timer.times;
    return st;
}

/* One view's raw planes into its planes: the file must hold what the scene
 * renders (one weight plane, or X, Y, Z) at the scene's image size. */
static orr_status load_raw(view_state *v, orr_error *err)
{
    orr_render_report *rep = v->rep;
    char path[ORR_PATH_MAX];
    orr_status st = orr_view_output_path(v->scene, v->scene->regrade_final ? "fits" : "raw.fits", path, err);
    orr_plane raw[3];
    int n = 0;
    if (!st)
        st = orr_read_fits_planes(path, raw, 3, &n, err);
    if (!st && (n != v->nplanes || raw[0].width != v->proj.width || raw[0].height != v->proj.height))
        st = orr_fail(err, ORR_ERR_DATA,
                      "%s: holds %d plane(s) of %d x %d, but %s renders %d of %d x %d (was it rendered from "
                      "another scene?)",
                      path, n, raw[0].width, raw[0].height, v->scene->path, v->nplanes, v->proj.width,
                      v->proj.height);
    for (int k = 0; !st && k < n; k++)
        memcpy(v->planes[k].data, raw[k].data, (size_t)v->proj.width * (size_t)v->proj.height * sizeof(float));
    for (int k = 0; k < n; k++)
        orr_plane_free(&raw[k]);
    if (!st)
        snprintf(rep->source, sizeof rep->source, "%s", path);
    return st;
}

/* Adds one layer to the view's X, Y, Z planes: a luminance plane times its
 * colour, or X, Y, Z planes as they are, times the gain. */
static orr_status add_layer(view_state *v, const struct orr_compose_layer *l, orr_error *err)
{
    orr_plane raw[3];
    int n = 0;
    orr_status st = orr_read_fits_planes(l->file, raw, 3, &n, err);
    if (!st && (raw[0].width != v->proj.width || raw[0].height != v->proj.height))
        st = orr_fail(err, ORR_ERR_DATA, "%s: compose.layers: the planes are %d x %d, the scene's image %d x %d",
                      l->file, raw[0].width, raw[0].height, v->proj.width, v->proj.height);
    if (!st && n != 1 && n != 3)
        st = orr_fail(err, ORR_ERR_DATA, "%s: compose.layers: %d planes; a layer is one luminance plane or X, Y, Z",
                      l->file, n);
    if (!st && n == 1 && !l->has_colour)
        st = orr_fail(err, ORR_ERR_USAGE, "%s: compose.layers: a single-plane layer needs a colour", l->file);
    double xyz[3] = {1, 1, 1};
    if (!st && n == 1 && (st = orr_colour_xyz(&l->colour, xyz, err)) == ORR_OK)
        orr_xyz_normalise(xyz);
    size_t npix = (size_t)v->proj.width * (size_t)v->proj.height;
    for (int k = 0; !st && k < 3; k++) {
        const float *src = raw[n == 1 ? 0 : k].data;
        float f = (float)(l->gain * (n == 1 ? xyz[k] : 1.0));
        for (size_t i = 0; i < npix; i++)
            v->planes[k].data[i] += f * src[i];
    }
    for (int k = 0; k < n; k++)
        orr_plane_free(&raw[k]);
    return st;
}

static orr_status load_layers(view_state *v, orr_error *err)
{
    const orr_scene *s = v->scene;
    orr_status st = ORR_OK;
    for (int k = 0; k < s->nlayers && !st; k++)
        st = add_layer(v, &s->layers[k], err);
    if (!st)
        snprintf(v->rep->source, sizeof v->rep->source, "%d layers (%.200s, ...)", s->nlayers, s->layers[0].file);
    return st;
}

orr_status orr_compose_views(const orr_scene *const *scenes, int n, orr_render_report *reports, orr_error *err)
{
    if (n < 1)
        return orr_fail(err, ORR_ERR_USAGE, "no view to compose");
    /* No particles, so no observer frame: the world's stands in (the camera
     * matters only for FITS cards, and compose writes PNGs). */
    orr_sky_frame observer = orr_sky_frame_world(orr_v3(0, 0, 0));
    const orr_frame_time still = orr_frame_at(0, 1, scenes[0]->anim_fps, 0, 0);
    view_state *views = orr_calloc((size_t)n, sizeof *views, "views", err);
    if (!views)
        return ORR_ERR_NOMEM;
    orr_status st = ORR_OK;
    /* As a render does: the output folder is made, or found unwritable,
     * before any work (a compose's layers may be read from elsewhere). */
    for (int k = 0; k < n && !st; k++)
        st = orr_check_output_dir(scenes[k]->out_dir, err);
    orr_output_batch outputs;
    orr_output_batch_init(&outputs);
    int ready = 0;
    for (; !st && ready < n; ready++) {
        st = setup_view(&views[ready], scenes[ready], scenes[0]->has_observer ? &observer : NULL, orr_v3(0, 0, 0),
                        &still, &reports[ready], err);
        views[ready].outputs = &outputs;
    }
    for (int k = 0; k < n && !st; k++) {
        view_state *v = &views[k];
        if ((st = v->scene->nlayers ? load_layers(v, err) : load_raw(v, err)))
            break;
        for (int j = 0; j < v->nplanes && !st && !v->scene->regrade_final; j++) /* NAME.fits has its PSF */
            st = orr_view_psf_apply(&v->psf, &v->planes[j], err);
        orr_view_mask_outside_map(v);
        if (!st)
            st = orr_view_write_pictures(v, err);
    }
    if (!st)
        st = orr_output_batch_commit(&outputs, err);
    else
        orr_output_batch_name_finals(&outputs, err);
    orr_output_batch_abort(&outputs);
    for (int k = 0; k < ready; k++)
        free_view(&views[k]);
    free(views);
    return st;
}

orr_status orr_render_scene(const orr_scene *scene, orr_render_report *report, orr_progress_fn progress,
                            void *progress_user, orr_error *err)
{
    return orr_render_views(&scene, 1, report, progress, progress_user, err);
}
