/* Where a frame's views look from: the observer frame (a pass over the
 * particles for the observer and reference particles, and the spin normal),
 * each view's camera (a camera path, the sky frame, a scene's static
 * camera) and motion blur's cameras at the shutter's opening and closing.
 * All of this follows the particles or the frame's time, so the renderer's
 * plan (render/plan.h) redoes it every frame. */
#include "render/view_state.h"

#include <string.h>


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

/* The observer and reference particles among a chunk's. */
static void mark_chunk(const orr_observer_settings *o, const orr_chunk *c, markers *m)
{
    for (size_t i = 0; i < c->n; i++) {
        orr_vec3 p = orr_v3(c->x[i], c->y[i], c->z[i]);
        if (c->id[i] == o->id) {
            m->observer = p;
            m->observer_velocity = chunk_velocity(c, i);
            m->have_observer = 1;
        } else if (c->id[i] == o->reference_id) {
            m->reference = p;
            m->have_reference = 1;
        }
    }
}

/* A pass over the source for the observer and reference particles. It
 * stops at the chunk that holds the last of the two: ids are unique, and
 * every later pass rewinds. For the built-in model, whose markers are its
 * first particles, that is one chunk instead of every particle generated a
 * second time (half of a 10^7-particle frame's source stage). */
static orr_status find_markers(const orr_observer_settings *o, orr_source *src, markers *m, orr_error *err)
{
    memset(m, 0, sizeof *m);
    const orr_chunk *c;
    orr_status st = ORR_OK;
    while (!(m->have_observer && m->have_reference) && !(st = orr_source_next(src, &c, err)) && c->n > 0)
        mark_chunk(o, c, m);
    return m->have_observer && m->have_reference ? ORR_OK : st;
}

/* The disc normal from the spin of the chosen particles within
 * normal_radius of the reference: L = sum m (r - c) x (v - <v>). */
static orr_status spin_normal(const orr_observer_settings *o, const char *scene_path, orr_source *src, orr_vec3 centre,
                              const orr_parallel *par, orr_vec3 *n0, orr_error *err)
{
    orr_vec3 mr_x_v = {0, 0, 0}, mr = {0, 0, 0}, mv = {0, 0, 0};
    double mass = 0, r2max = o->normal_radius * o->normal_radius;
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
                            scene_path, src->info.path);
        for (size_t i = 0; i < c->n; i++) {
            if (!(o->normal_types & (1u << c->type[i])))
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
                        scene_path, o->normal_radius);
    /* Removing the mean velocity: sum m r x (v - <v>) = sum m r x v - (sum m r) x <v>. */
    orr_vec3 L = orr_v3_sub(mr_x_v, orr_v3_scale(orr_v3_cross(mr, mv), 1.0 / mass));
    if (!(orr_v3_norm(L) > 0))
        return orr_fail(err, ORR_ERR_DATA, "%s: the observer.normal_from particles have no net spin", scene_path);
    *n0 = orr_v3_scale(orr_v3_normalize(L), o->normal_sign);
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

orr_status orr_view_sky_frame(const orr_observer_settings *o, const char *scene_path, orr_source *src, orr_status st,
                              long frame, const orr_parallel *par, orr_sky_frame *f, orr_vec3 *velocity, orr_error *err)
{
    markers m = {0}; /* (read below even when opening the source failed) */
    if (!st)
        st = find_markers(o, src, &m, err);
    if (par && par->nranks > 1 && !(st = par->any_failed(par->user, st, err)))
        st = combine_markers(par, &m, err);
    if (!st && (!m.have_observer || !m.have_reference))
        st = orr_fail(err, ORR_ERR_DATA, "%s: %s particle id %llu (observer.%s in %s) not found, frame %ld",
                      src->info.path, m.have_observer ? "reference" : "observer",
                      (unsigned long long)(m.have_observer ? o->reference_id : o->id),
                      m.have_observer ? "reference_id" : "id", scene_path, frame);
    orr_vec3 n0 = o->normal;
    if (!st && o->normal_types && !(st = orr_source_rewind(src, err)))
        st = spin_normal(o, scene_path, src, m.reference, par, &n0, err);
    *velocity = m.observer_velocity;
    if (!st && (st = orr_sky_frame_build(f, m.observer, m.reference, n0, err)))
        orr_fail_prefix(err, "%s: observer id %llu, reference id %llu, frame %ld: ", scene_path,
                        (unsigned long long)o->id, (unsigned long long)o->reference_id, frame);
    return st;
}

/* ---- cameras ---- */

static int has_orientation(const orr_camera_settings *c)
{
    return c->has_quaternion || c->has_look_at || c->has_direction;
}

static orr_status scene_camera(const orr_camera_settings *c, const orr_frame_time *when, orr_camera *cam,
                               orr_error *err)
{
    if (c->has_path)
        return orr_path_camera(&c->path, when, cam, err);
    return orr_camera_settings_static(c, cam, err);
}

/* The camera of a view. From an observer, or for a sky map without an
 * orientation of its own, the camera follows the sky frame: the map centred
 * on l = 0 with north up, or the dome's zenith and front. */
orr_status orr_view_camera(const view_camera_plan *c, const orr_sky_frame *observer, const orr_frame_time *when,
                           orr_camera *cam, orr_sky_frame *sky, orr_error *err)
{
    const orr_camera_settings *cs = &c->camera;
    /* A camera path moves and turns the camera frame by frame, sky maps
     * included (scenes with a path have no observer: scene_check). */
    if (cs->has_path) {
        orr_status st = scene_camera(cs, when, cam, err);
        *sky = orr_sky_frame_world(cam->position);
        return st;
    }
    const orr_projection_traits traits = orr_projection_traits_of(c->kind);
    if (!observer && (!traits.sky || has_orientation(cs))) {
        *sky = orr_sky_frame_world(cs->position);
        return scene_camera(cs, when, cam, err);
    }
    *sky = observer ? *observer : orr_sky_frame_world(cs->position);
    if (traits.zenith_centred)
        return orr_sky_camera_dome(cam, sky, cs->zenith_lb, cs->front_lb, cs->dome_tilt, err);
    return orr_sky_camera_centre(cam, sky, cs->roll, err);
}

/* ---- motion blur ---- */

/* The view's camera dframe frames from this one (motion blur's shutter
 * opening and closing): along the camera path, or from an observer moved
 * by observer_step; a perspective stereo eye set as in this frame (on the
 * view's projection, whose principal point the eye's shift sets anew). */
static orr_status camera_at(const view_state *v, const orr_sky_frame *observer, orr_vec3 observer_step,
                            const orr_frame_time *when, double dframe, orr_camera *cam, orr_error *err)
{
    const view_camera_plan *c = &v->camera_plan;
    orr_status st;
    if (c->camera.has_path) {
        double u = when->nframes > 1 ? when->u + dframe / (double)(when->nframes - 1) : when->u;
        st = orr_path_eval(&c->camera.path, (double)when->frame + dframe, u, cam, err);
    } else {
        orr_sky_frame moved, sky;
        if (observer) {
            moved = *observer;
            moved.origin = orr_v3_add(moved.origin, observer_step);
        }
        st = orr_view_camera(c, observer ? &moved : NULL, when, cam, &sky, err);
    }
    if (!st && c->stereo.eye && orr_projection_traits_of(v->pass.proj.settings.kind).off_axis_stereo) {
        orr_projection p = v->pass.proj;
        st = orr_stereo_perspective_eye(cam, &p, c->stereo.eye, c->stereo.eye_separation, v->rep->stereo_convergence,
                                        err);
    }
    return st ? orr_fail_prefix(err, "%s: animation.shutter: ", c->path) : ORR_OK;
}

/* Motion blur's plan (animation.shutter): the cameras when the shutter
 * opens and closes, half a shutter before and after the frame, and the
 * simulation time the particles move over (the frame interval's share). */
orr_status orr_view_plan_blur(view_state *v, const orr_sky_frame *observer, orr_vec3 observer_velocity,
                              const orr_frame_time *when, orr_error *err)
{
    const view_camera_plan *c = &v->camera_plan;
    if (!(c->shutter > 0))
        return ORR_OK;
    const double interval = !c->blur_moves_particles ? 0 : c->has_frame_interval ? c->frame_interval : when->interval;
    const double half_time = 0.5 * c->shutter * interval, half_frame = 0.5 * c->shutter;
    const orr_vec3 step = orr_v3_scale(observer_velocity, half_time);
    orr_camera open, close;
    orr_status st = camera_at(v, observer, orr_v3_scale(step, -1), when, -half_frame, &open, err);
    if (!st)
        st = camera_at(v, observer, step, when, half_frame, &close, err);
    if (!st)
        orr_motion_blur_plan(&v->pass.blur, half_time, &open, &close, &v->pass.proj);
    return st;
}
