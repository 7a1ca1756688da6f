#include "render/render.h"
#include "core/fastmath.h"
#include "core/numbers.h"
#include "core/simd.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "encode/atomic.h"
#include "encode/fits.h"
#include "encode/fits_read.h"
#include "encode/image_out.h"
#include "encode/png.h"
#include "post/brightness.h"
#include "post/colormap.h"
#include "post/stretch.h"
#include "render/camera_transform.h"
#include "render/exr_view.h"
#include "render/lengths.h"
#include "render/map_alpha.h"
#include "render/motion_blur.h"
#include "render/ngp_gather.h"
#include "render/periodic_view.h"
#include "render/stereo_view.h"
#include "render/view_psf.h"
#include "render/wcs.h"
#include "scene/scene_output.h"
#include "source/king.h"
#include "source/model.h"
#include "source/partition.h"
#include "source/sequence.h"
#include "splat/bands.h"
#include "splat/sph.h"

/* Particles are processed in blocks of this many: the block's scratch arrays
 * (about 100 KiB) stay in L2 cache between the gather, project and deposit
 * passes. */
#define BLOCK 4096

/* Threads splat a chunk's blocks in lanes: block b goes to lane b % nlanes,
 * each lane deposits its blocks in order into planes of its own, and at the
 * end of the frame the lanes are added pixel by pixel in lane order. The
 * number of lanes comes from the image size alone, never from the number of
 * threads, so every pixel sums the same terms in the same order whatever
 * OMP_NUM_THREADS is: the planes come out bit for bit the same. Lanes past
 * the first cost a copy of the view's planes each; they are kept within
 * LANE_BUDGET bytes per view (a 3600 x 3600 dome master gets 4 lanes, with
 * colour 2; an image too large for even one extra lane is splatted by one
 * thread). */
#define MAX_LANES 4
_Static_assert(MAX_LANES <= ORR_SKY_PSF_LANES, "a sky PSF collects stars in every lane");
#define LANE_BUDGET ((size_t)256 << 20)
#define LANE_SHARES_PER_PIXEL 4 /* point deposits: lanes_for */

/* Point deposits (NGP, CIC, on flat images and sky maps) into images of
 * more than BAND_MIN_PIXELS pixels are not splatted in lanes but in bands
 * (splat/bands.h): threads compute the shares of up to WINDOW_BLOCKS
 * blocks at once, then add them band by band. A lane's copy of such an
 * image would not fit in the cache (16 MB a plane at the threshold), nor
 * would the image itself: the bands keep the pixels being added to in
 * cache, and need no copies. Below it, lanes cost less than sorting the
 * shares (docs/performance.md). */
#define BAND_MIN_PIXELS ((size_t)1 << 22)
/* A window is a quarter of a million particles. A band's pixels come from
 * main memory about once a window, so larger windows bring each more
 * shares (measured at 10^7 particles on a dome master, before the bands
 * prefetched: 256 blocks 15 % faster than 64); with the prefetch
 * (bands.c) 64, 128, 256 and 512 blocks run within 4 % of each other,
 * and 64 keeps the window's shares to 2 MB for NGP, 8 MB for CIC (one
 * plane; 4 and 16 MB with colour). */
#define WINDOW_BLOCKS 64

typedef struct block_buffers {
    float x[BLOCK], y[BLOCK], z[BLOCK], h[BLOCK];
    float w[3][BLOCK]; /* the weight, or X, Y, Z with colour */
    float px[BLOCK], py[BLOCK], scale[BLOCK];
    uint8_t visible[BLOCK];
    uint8_t keep[BLOCK]; /* omni-directional stereo: 0 inside the eye circle */
    /* Point deposits: the block's shares, before they are sorted by band. */
    int32_t share_pixel[ORR_MAX_SHARES_PER_POINT * BLOCK];
    float share_w[3][ORR_MAX_SHARES_PER_POINT * BLOCK];
    uint32_t band_cursor[ORR_MAX_BANDS];
    /* The block's weights, as the deposits read them: the source's arrays
     * themselves for a block taken whole (take_weights), otherwise w. */
    const float *wp[3];
    /* A block of the fused NGP gather (render/ngp_gather.h): its pixel
     * indices are in share_pixel. */
    int indexed;
    /* Motion blur: x, y, z hold where each streak starts and sx, sy, sz
     * the vector to its end (camera frame); the streaks' samples are
     * drawn from the buffers of *samples, a block at a time. */
    float sx[BLOCK], sy[BLOCK], sz[BLOCK];
    struct block_buffers *samples;
} block_buffers;

/* One view being rendered. */
typedef struct view_state {
    const orr_scene *scene;
    orr_projection proj;
    orr_mat3 world_to_camera;
    orr_plane planes[3]; /* the weight plane, or CIE X, Y, Z with colour */
    int nplanes;
    orr_render_report *rep;
    /* Kernel deposit (deposit: sph, or a sky map's PSF): its kernel, the
     * deposit's set-up, and where the smoothing lengths come from. */
    int use_sph, kernel_ready, sph_ready;
    orr_kernel kernel;
    orr_sph sph;
    const orr_lengths *lengths; /* lengths from the neighbours, or NULL: the file's */
    size_t lengths_next;        /* the next of them in source order */
    float h_scale;              /* file lengths: to orrery's h (support 2h), times smoothing.h_scale */
    orr_view_psf psf;
    double tint_t;      /* the position along colour.tint.path in this frame */
    int use_ods;        /* an eye of omni-directional stereo: its per-block transform */
    orr_stereo_ods ods;
    orr_periodic_view periodic; /* input.periodic: the box's copies and what is culled */
    orr_motion_blur blur;       /* animation.shutter: particles drawn as streaks */
    int banded;                 /* a point deposit, splatted in bands (WINDOW_BLOCKS above) */
    int ngp_fused;              /* NGP blocks taken whole go through the fused gather */
    orr_map_outline outline;    /* the image's map, for NGP indices */
    orr_bands bands;
    int nlanes;                 /* lanes of the splat (MAX_LANES above) */
    orr_plane *lane_planes;     /* lanes 1 .. nlanes-1: nplanes planes each; lane 0 is planes[] */
    orr_output_batch *outputs;  /* the frame's outputs, renamed into place together */
    struct frame_timer *timer;  /* the frame's stage timings (every view's), or NULL: not measured */
} view_state;

/* A frame's stage timings and the clock reading the last stage ended at:
 * each stage is charged the time since then (render/timings.h). */
typedef struct frame_timer {
    orr_stage_times times;
    orr_clock at;
} frame_timer;

static void charge(const view_state *v, orr_stage s)
{
    if (v->timer)
        orr_stage_charge(&v->timer->times, s, &v->timer->at);
}

/* What one block added to the report, kept per block and summed in block
 * order, so the sums do not depend on which thread took which block. */
typedef struct block_tally {
    uint64_t n_selected, n_nonfinite, n_stereo_skipped;
    orr_deposit_stats deposit[2]; /* of the first two planes: the report's deposit and deposit_y */
} block_tally;

orr_status orr_scene_open_source(const orr_scene *s, const char *const *fields, int nfields, orr_source **out,
                                 orr_error *err)
{
    return orr_scene_open_share(s, fields, nfields, 0, 1, out, err);
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
        orr_source_options opt = {s->input_format, (size_t)s->chunk_size, s->has_observer ? 0 : s->type_mask,
                                  fields, nfields, 0, 1};
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
        return orr_model_source_open(&mp, (size_t)s->chunk_size, out, err);
    }
    /* The observer and reference particles may be of types the scene does
     * not draw: then the reader must not drop them (the splat selects
     * input.types itself). */
    unsigned types = s->has_observer ? 0 : s->type_mask;
    orr_source_options opt = {s->input_format, (size_t)s->chunk_size, types, fields, nfields, part, nparts};
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

/* ---- the splat pass ---- */

/* The weight array of a chunk, or an error listing the fields there are. */
static orr_status weight_field(const orr_scene *s, const orr_source *src, const orr_chunk *c,
                               const float **w, orr_error *err)
{
    *w = orr_chunk_field(c, s->weight);
    if (*w)
        return ORR_OK;
    char have[512] = "mass";
    if (c->h)
        strncat(have, ", h", sizeof have - strlen(have) - 1);
    for (int i = 0; i < c->nextra; i++) {
        strncat(have, ", ", sizeof have - strlen(have) - 1);
        strncat(have, c->extra[i].name, sizeof have - strlen(have) - 1);
    }
    return orr_fail(err, ORR_ERR_USAGE, "%s: input.weight '%s' is not a field of %s (fields: %s)", s->path,
                    s->weight, src->info.path, have);
}

/* Names the value that is not finite: the position, the weight, or else
 * (vel: motion blur's, NULL without) the velocity. */
static orr_status nonfinite_error(const orr_source *src, const orr_chunk *c, size_t i, double weight,
                                  const float *const *vel, orr_error *err)
{
    char what[128];
    if (!isfinite(c->x[i]) || !isfinite(c->y[i]) || !isfinite(c->z[i]))
        orr_snprintf(what, sizeof what, "position (%g, %g, %g)", (double)c->x[i], (double)c->y[i], (double)c->z[i]);
    else if (!isfinite(weight) || !vel)
        orr_snprintf(what, sizeof what, "weight (%g)", weight);
    else
        orr_snprintf(what, sizeof what, "velocity (vx, vy, vz) = (%g, %g, %g), which animation.shutter moves it by",
                     (double)vel[0][i], (double)vel[1][i], (double)vel[2][i]);
    return orr_fail(err, ORR_ERR_DATA, "%s: particle %llu (id %llu) has a non-finite %s; "
                    "set input.nonfinite: skip to leave such particles out",
                    src->info.path, (unsigned long long)(c->first_index + i), (unsigned long long)c->id[i], what);
}

/* 1 when every float of a[start, end) is finite: an OR over the block
 * that the compiler vectorises (isfinite() would be a branch a particle). */
ORR_VECTOR_CLONES
static int all_finite(const float *a, size_t start, size_t end)
{
    int bad = 0;
    for (size_t i = start; i < end; i++)
        bad |= orr_not_finite_f(a[i]);
    return bad == 0;
}

/* 1 when the gather may select every particle of c[start, end): no
 * neighbour lengths to count, every type drawn, no observer among them.
 * This is by far the common block, and (when its particles are finite
 * too) its gather is a straight loop without a branch a particle:
 * gather_all, or for NGP the fused gather. */
static int block_selects_all(const view_state *v, const orr_chunk *c, size_t start, size_t end)
{
    const orr_scene *s = v->scene;
    if (v->lengths)
        return 0;
    /* Blocks mostly hold one type: checked with a byte loop that vectorises;
     * otherwise each particle's type against the mask. */
    const uint8_t *type = c->type, first_type = type[start];
    uint8_t differ = 0;
    for (size_t i = start; i < end; i++)
        differ |= type[i] ^ first_type;
    if (!differ) {
        if (first_type > 31 || !(s->type_mask & (1u << first_type)))
            return 0;
    } else {
        uint32_t types = 0;
        for (size_t i = start; i < end; i++)
            types |= type[i] > 31 ? ~0u : 1u << type[i];
        if (types & ~s->type_mask)
            return 0;
    }
    if (s->has_observer) {
        const uint64_t observer = s->observer_id;
        int found = 0;
        for (size_t i = start; i < end; i++)
            found |= c->id[i] == observer;
        if (found)
            return 0;
    }
    return 1;
}

static int block_all_finite(const orr_chunk *c, const float *wsrc, size_t start, size_t end)
{
    return all_finite(c->x, start, end) && all_finite(c->y, start, end) && all_finite(c->z, start, end) &&
           all_finite(wsrc, start, end);
}

/* The camera transform of a copy moved by shift; fading: the weights
 * taper within the periodic sphere (the copy's block is across it). */
static orr_camera_transform transform_of(const view_state *v, orr_vec3 shift, int fading)
{
    const orr_scene *s = v->scene;
    const orr_vec3 origin = orr_v3_sub(v->rep->camera.position, shift); /* p + shift - camera */
    orr_camera_transform t = {.ox = origin.x, .oy = origin.y, .oz = origin.z};
    if (fading) {
        const orr_replica_sphere *sp = &v->periodic.sphere;
        t.fade = 1;
        t.outer = (float)sp->radius;
        t.inner = (float)(sp->radius - sp->fade);
        t.inner2 = t.inner * t.inner;
        t.outer2 = t.outer * t.outer;
    }
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++)
            t.r[a][b] = (float)v->world_to_camera.m[a][b];
    t.dim = (s->has_observer && s->dim) || s->camera_dim;
    const double near = s->camera_dim ? s->camera_dim_near : s->dim_near;
    t.near2 = (float)(near * near);
    return t;
}

/* Positions of c[start, start + n) into the camera frame, and with dim
 * the 1/r^2 dimming of each (into dimming); dim is a constant at each call,
 * so the compiler makes a loop without the division for views that do not
 * dim. */
static inline void transform_positions(const orr_chunk *c, size_t start, size_t n, const orr_camera_transform *t,
                                       const int dim, block_buffers *b, float *restrict dimming)
{
    const orr_camera_transform tt = *t;
    const float *restrict x = c->x + start, *restrict y = c->y + start, *restrict z = c->z + start;
    float *restrict bx = b->x, *restrict by = b->y, *restrict bz = b->z;
    for (size_t i = 0; i < n; i++) {
        orr_camera_point p = orr_to_camera(&tt, x[i], y[i], z[i]);
        bx[i] = p.x;
        by[i] = p.y;
        bz[i] = p.z;
        if (dim)
            dimming[i] = orr_camera_dimming(&tt, p.r2);
    }
}

ORR_VECTOR_CLONES
static void transform_dimmed(const orr_chunk *c, size_t start, size_t n, const orr_camera_transform *t,
                             block_buffers *b, float *dimming)
{
    transform_positions(c, start, n, t, 1, b, dimming);
}

ORR_VECTOR_CLONES
static void transform_undimmed(const orr_chunk *c, size_t start, size_t n, const orr_camera_transform *t,
                               block_buffers *b)
{
    transform_positions(c, start, n, t, 0, b, NULL);
}

/* The weights of a block taken whole, particles [start, start + n): the
 * source's arrays themselves, or with dimming (observer.dim, camera.dim;
 * NULL without) the dimmed copies in b->w. */
static void take_weights(const view_state *v, const float *const *wsrcs, size_t start, size_t n,
                         const float *restrict dimming, block_buffers *b)
{
    for (int k = 0; k < v->nplanes; k++) {
        const float *restrict w = wsrcs[k] + start;
        if (!dimming) {
            b->wp[k] = w;
            continue;
        }
        float *restrict bw = b->w[k];
        for (size_t i = 0; i < n; i++)
            bw[i] = w[i] * dimming[i];
        b->wp[k] = bw;
    }
}

/* The gather of a block that takes every particle (block_selects_all and
 * finite): positions, weights and the file's smoothing lengths, one
 * vectorised loop per array. */
static size_t gather_all(const view_state *v, const orr_chunk *c, const float *const *wsrcs, size_t start,
                         size_t end, const orr_camera_transform *t, block_buffers *b)
{
    const size_t n = end - start;
    float *dimming = b->scale; /* free until the projection fills it */
    if (t->dim)
        transform_dimmed(c, start, n, t, b, dimming);
    else
        transform_undimmed(c, start, n, t, b);
    take_weights(v, wsrcs, start, n, t->dim ? dimming : NULL, b);
    if (c->h) {
        const float *restrict h = c->h + start;
        const float hs = v->h_scale;
        for (size_t i = 0; i < n; i++)
            b->h[i] = h[i] * hs;
    } else {
        memset(b->h, 0, n * sizeof *b->h);
    }
    return n;
}

/* The fused gather (render/ngp_gather.h) of a block that takes every
 * particle: indices into b->share_pixel. Returns 0 when the block has a
 * non-finite value (b->indexed 0). */
static int ngp_gather_all(const view_state *v, const orr_chunk *c, const float *const *wsrcs, size_t start,
                          size_t end, const orr_camera_transform *t, block_buffers *b)
{
    const size_t n = end - start;
    orr_ngp_gather_out out = {b->share_pixel, b->px, b->py, b->scale};
    if (!orr_ngp_gather(&v->proj, &v->outline, t, n, c->x + start, c->y + start, c->z + start,
                        wsrcs[v->nplanes - 1] + start, &out))
        return 0;
    take_weights(v, wsrcs, start, n, t->dim ? out.dimming : NULL, b);
    b->indexed = 1;
    return 1;
}

/* The weight a periodic sphere's taper takes from particle i (fade < 1),
 * counted as not drawn, so that what is drawn, falls off and is not drawn
 * still adds up to every copy's weight; a particle beyond the radius
 * (fade 0) is not drawn at all. */
static void count_faded(const view_state *v, const float *const *wsrcs, size_t i, float dimming, float fade,
                        block_tally *t)
{
    for (int k = 0; k < v->nplanes && k < 2; k++) {
        t->deposit[k].culled += (double)wsrcs[k][i] * dimming * (1.0f - fade);
        if (fade == 0.0f) {
            t->deposit[k].n_culled++;
            t->deposit[k].n_particles++;
        }
    }
}

/* ---- the glow (glow.threshold) ---- */

/* 1 up to half of the limit, 0 from the limit on, the smoothstep between. */
static float glow_taper(float x, float limit)
{
    float s = 2.0f * (limit - x) / limit;
    return s >= 1.0f ? 1.0f : s <= 0.0f ? 0.0f : s * s * (3.0f - 2.0f * s);
}

/* A star's kernel in the glow: its angular length (h, from the lengths in
 * direction, times smoothing.h_scale) as a length at its distance, so its
 * kernel spans that angle on the sky. A star stays a point, drawn as the
 * PSF's core, where it stands out: its flux at the camera (luminance with
 * colour) reaches glow.threshold, or its kernel would be wider than
 * glow.max_arcmin across (its support, 2h), where stars are few on the sky
 * and a glow would be a fog. From half of either limit to the limit the
 * kernel shrinks smoothly to the point, so no edge runs across the sky
 * between glow and points, and a star brightening as the camera nears it
 * draws in to a point instead of popping. */
static float glow_length(const orr_scene *s, float h, float r2, float flux)
{
    const float max_h = (float)(0.5 * s->glow_max_arcmin * ORR_PI / (180.0 * 60.0));
    return h * glow_taper(h, max_h) * glow_taper(flux, (float)s->glow_threshold) * sqrtf(r2);
}

/* ---- motion blur (render/motion_blur.h) ---- */

/* The velocities motion blur moves the chunk's particles by (NULLs when
 * the shutter holds them still), or an error naming the field missing. */
static orr_status blur_velocities(const view_state *v, const orr_source *src, const orr_chunk *c,
                                  const float *vel[3], orr_error *err)
{
    static const char *const names[3] = {"vx", "vy", "vz"};
    for (int a = 0; a < 3; a++)
        vel[a] = NULL;
    if (v->blur.half_time == 0)
        return ORR_OK;
    for (int a = 0; a < 3; a++)
        if (!(vel[a] = orr_chunk_field(c, names[a])))
            return orr_fail(err, ORR_ERR_USAGE,
                            "%s: animation.shutter: the particles move by their velocities while the shutter "
                            "is open (%g of simulation time), but %s has no field %s; give velocities, or set "
                            "animation.frame_interval: 0 to blur only the camera's motion",
                            v->scene->path, 2 * v->blur.half_time, src->info.path, names[a]);
    return ORR_OK;
}

static int velocity_finite(const float *const *vel, size_t i)
{
    return isfinite(vel[0][i]) && isfinite(vel[1][i]) && isfinite(vel[2][i]);
}

/* Particle i's streak into slot n of the block: its start over the
 * gathered position, the vector to its end in sx, sy, sz. */
static void put_streak(const orr_motion_blur *mb, const orr_camera_transform *open,
                       const orr_camera_transform *close, const orr_chunk *c, const float *const *vel, size_t i,
                       block_buffers *b, size_t n)
{
    const float p[3] = {c->x[i], c->y[i], c->z[i]};
    const float u[3] = {vel[0] ? vel[0][i] : 0.0f, vel[1] ? vel[1][i] : 0.0f, vel[2] ? vel[2][i] : 0.0f};
    float q0[3], sv[3];
    orr_motion_blur_streak(mb, open, close, p, u, q0, sv);
    b->x[n] = q0[0], b->y[n] = q0[1], b->z[n] = q0[2];
    b->sx[n] = sv[0], b->sy[n] = sv[1], b->sz[n] = sv[2];
}

/* Gathers the view's particles of c[start, end) into the block, moved by
 * shift (a periodic box's copy; fading: across its sphere, so each weight
 * tapers with the distance from the camera) and into the camera frame,
 * their smoothing lengths from the neighbours' starting at lengths_next;
 * returns how many, or -1 (err set) on a bad particle when the scene says
 * to fail. What it counts goes into *t. The observer particle is left out, and with
 * observer.dim or camera.dim weights fall off as 1/r^2 from the camera. */
static long gather_block(const view_state *v, const orr_source *src, const orr_chunk *c, const float *const *wsrcs,
                         size_t start, size_t end, orr_vec3 shift, int fading, size_t lengths_next,
                         block_buffers *b, block_tally *t, orr_error *err)
{
    /* Checked for finiteness: the weight, or with colour Z, the last plane
     * (orr_population_assign already refuses a luminance or colour that is
     * not finite, so a particle's X, Y and Z are finite together) */
    const float *wsrc = wsrcs[v->nplanes - 1];
    const orr_scene *s = v->scene;
    const orr_camera_transform tf = transform_of(v, shift, fading);
    for (int k = 0; k < 3; k++)
        b->wp[k] = b->w[k];
    b->indexed = 0;
    if (!fading && !v->blur.active && block_selects_all(v, c, start, end)) {
        if (v->ngp_fused && ngp_gather_all(v, c, wsrcs, start, end, &tf, b)) {
            t->n_selected += end - start;
            return (long)(end - start);
        }
        if (block_all_finite(c, wsrc, start, end)) {
            t->n_selected += end - start;
            return (long)gather_all(v, c, wsrcs, start, end, &tf, b);
        }
    }
    const int skip_observer = s->has_observer;
    const float *vel[3] = {NULL, NULL, NULL};
    orr_camera_transform open, close;
    if (v->blur.active) {
        if (blur_velocities(v, src, c, vel, err))
            return -1;
        orr_motion_blur_transforms(&v->blur, shift, &open, &close);
    }
    long n = 0;
    for (size_t i = start; i < end; i++) {
        float h = 0.0f;
        if (v->lengths) { /* counted before any skip, as the neighbour pass counted them */
            if (orr_lengths_counts(s, c, i) && lengths_next < v->lengths->n)
                h = v->lengths->h[lengths_next++] * v->h_scale;
        } else if (c->h) {
            h = c->h[i] * v->h_scale;
        }
        if (!(s->type_mask & (1u << c->type[i])) || (skip_observer && c->id[i] == s->observer_id))
            continue;
        t->n_selected++;
        if (!isfinite(c->x[i]) || !isfinite(c->y[i]) || !isfinite(c->z[i]) || !isfinite(wsrc[i]) ||
            (vel[0] && !velocity_finite(vel, i))) {
            if (!s->skip_nonfinite) {
                nonfinite_error(src, c, i, wsrc[i], vel[0] ? vel : NULL, err);
                return -1;
            }
            t->n_nonfinite++;
            continue;
        }
        orr_camera_point p = orr_to_camera(&tf, c->x[i], c->y[i], c->z[i]);
        float dimming = tf.dim ? orr_camera_dimming(&tf, p.r2) : 1.0f;
        float fade = tf.fade ? orr_camera_fade(&tf, p.r2) : 1.0f;
        if (s->has_glow) /* an angle from the lengths, a point when bright */
            h = glow_length(s, h, p.r2, wsrcs[v->nplanes == 3 ? 1 : 0][i] * dimming);
        if (fade < 1.0f)
            count_faded(v, wsrcs, i, dimming, fade, t);
        if (fade == 0.0f)
            continue;
        b->x[n] = p.x;
        b->y[n] = p.y;
        b->z[n] = p.z;
        if (v->blur.active)
            put_streak(&v->blur, &open, &close, c, vel, i, b, (size_t)n);
        for (int k = 0; k < v->nplanes; k++)
            b->w[k][n] = wsrcs[k][i] * dimming * fade;
        b->h[n] = h;
        n++;
    }
    return n;
}

/* Projects the block's n points (camera frame): positions in pixels and
 * what the projection (and an eye of omni-directional stereo) draws. */
static void project_points(const view_state *v, size_t n, block_buffers *b, block_tally *t)
{
    if (v->use_ods)
        t->n_stereo_skipped += orr_stereo_ods_apply(&v->ods, n, b->x, b->y, b->z, b->keep);
    orr_project_batch(&v->proj, n, b->x, b->y, b->z, b->px, b->py, b->scale, b->visible);
    if (v->use_ods)
        orr_stereo_mask(n, b->visible, b->keep);
}

/* Gathers particles [start, end) of c (moved by shift) into the block and
 * projects them: positions in pixels and what the projection (and an eye
 * of omni-directional stereo) draws. Returns how many, or -1 (err set). */
static long project_block(const view_state *v, const orr_source *src, const orr_chunk *c, const float *const *wts,
                          size_t start, size_t end, orr_vec3 shift, int fading, size_t lengths_next,
                          block_buffers *b, block_tally *t, orr_error *err)
{
    long n = gather_block(v, src, c, wts, start, end, shift, fading, lengths_next, b, t, err);
    if (n < 0 || b->indexed || v->blur.active) /* streaks: their samples are projected as drawn */
        return n;
    project_points(v, (size_t)n, b, t);
    return n;
}

/* A sky map's PSF widens every particle's kernel to the PSF's angular size
 * (in quadrature with its own smoothing length). */
static void widen_for_psf(const view_state *v, size_t n, block_buffers *b)
{
    const float k = (float)v->psf.h_per_r;
    if (k <= 0.0f)
        return;
    for (size_t i = 0; i < n; i++) {
        float r2 = b->x[i] * b->x[i] + b->y[i] * b->y[i] + b->z[i] * b->z[i];
        b->h[i] = sqrtf(b->h[i] * b->h[i] + k * k * r2);
    }
}

/* A block of the fused gather as an NGP batch, its indices completed (a
 * sky map's rim folded) and its report in t. */
static orr_ngp_batch place_indexed(const view_state *v, size_t n, block_buffers *b, block_tally *t)
{
    orr_deposit_stats st[3];
    memset(st, 0, sizeof st);
    orr_ngp_batch nb = {n, b->share_pixel, b->px, b->py, {b->wp[0], b->wp[1], b->wp[2]}, v->nplanes, 0};
    orr_ngp_place(&v->proj, &v->outline, &nb, st);
    t->deposit[0] = st[0];
    t->deposit[1] = st[1];
    return nb;
}

/* Deposits the block's n projected points into planes (a lane's: the
 * view's own or a private copy). The report's statistics are of the first
 * plane's weights (with colour, X; Y's are in the FITS header). */
static void deposit_points(const view_state *v, orr_plane *planes, int lane, size_t n, block_buffers *b,
                           block_tally *t)
{
    if (v->use_sph)
        widen_for_psf(v, n, b);
    for (int k = 0; k < v->nplanes; k++) {
        orr_deposit_stats scratch = {0};
        orr_deposit_stats *st = k < 2 ? &t->deposit[k] : &scratch;
        if (!v->use_sph) {
            orr_deposit(v->scene->deposit, &planes[k], n, b->px, b->py, b->wp[k], b->visible, &v->proj, st);
            continue;
        }
        orr_sph_block blk = {n, b->x, b->y, b->z, b->px, b->py, b->scale, b->visible, b->h, b->wp[k]};
        orr_sph_deposit(&v->sph, &blk, &planes[k], st);
    }
    /* A sky map's hst/file PSF: the brightest stars are redrawn with the
     * whole PSF after the splat (render/sky_psf.h). */
    if (v->psf.sky) {
        orr_sph_block geom = {n, b->x, b->y, b->z, b->px, b->py, b->scale, b->visible, b->h, NULL};
        orr_sky_psf_collect(v->psf.sky, lane, &geom, b->wp, v->nplanes);
    }
}

/* Deposits the streaks of the block's n particles: each as its samples
 * (orr_motion_blur_samples of them, at the midpoints of equal steps along
 * the streak, each with an equal share of the weight and the particle's
 * smoothing length), projected and deposited a block of samples at a
 * time. */
static void deposit_streaks(const view_state *v, orr_plane *planes, int lane, size_t n, block_buffers *b,
                            block_tally *t)
{
    block_buffers *sb = b->samples;
    for (int p = 0; p < 3; p++)
        sb->wp[p] = sb->w[p];
    size_t ns = 0;
    for (size_t i = 0; i < n; i++) {
        const float q0[3] = {b->x[i], b->y[i], b->z[i]}, sv[3] = {b->sx[i], b->sy[i], b->sz[i]};
        const int m = orr_motion_blur_samples(&v->blur, q0, sv);
        const float share = 1.0f / (float)m;
        for (int k = 0; k < m; k++) {
            if (ns == BLOCK) {
                project_points(v, ns, sb, t);
                deposit_points(v, planes, lane, ns, sb, t);
                ns = 0;
            }
            const float f = ((float)k + 0.5f) * share;
            sb->x[ns] = q0[0] + f * sv[0];
            sb->y[ns] = q0[1] + f * sv[1];
            sb->z[ns] = q0[2] + f * sv[2];
            sb->h[ns] = b->h[i];
            for (int p = 0; p < v->nplanes; p++)
                sb->w[p][ns] = b->wp[p][i] * share;
            ns++;
        }
    }
    if (ns) {
        project_points(v, ns, sb, t);
        deposit_points(v, planes, lane, ns, sb, t);
    }
}

/* Deposits the gathered block: as the fused gather's pixels, as streaks,
 * or as its projected points. */
static void deposit_block(const view_state *v, orr_plane *planes, int lane, size_t n, block_buffers *b,
                          block_tally *t)
{
    if (b->indexed) {
        orr_ngp_batch nb = place_indexed(v, n, b, t);
        orr_ngp_add(&nb, planes);
    } else if (v->blur.active) {
        deposit_streaks(v, planes, lane, n, b, t);
    } else {
        deposit_points(v, planes, lane, n, b, t);
    }
}

/* How many lanes a view splats in: as many as MAX_LANES allows within
 * LANE_BUDGET bytes of extra planes, and for point deposits no more than
 * the source's particles per pixel; a function of the image and the input
 * (count: the source's particles, -1 when unknown), never of the threads. */
static int lanes_for(const view_state *v, int64_t count)
{
    size_t npix = (size_t)v->proj.width * (size_t)v->proj.height;
    size_t lane_bytes = npix * sizeof(float) * (size_t)v->nplanes;
    size_t extra = lane_bytes ? LANE_BUDGET / lane_bytes : 0;
    int lanes = extra + 1 < MAX_LANES ? (int)extra + 1 : MAX_LANES;
    /* A lane's planes are zeroed and merged every frame, passes over every
     * pixel that cost about as much as adding four shares to it (measured:
     * 10^7 particles NGP on 1024^2, two threads, splat 7-20 % faster on 2
     * lanes than on 4; 4e6 particles on a 3600^2 dome slower on 4 lanes
     * than on 1; docs/performance.md). So point deposits take a lane for
     * every four shares a pixel (NGP one a particle, CIC four). Kernels
     * cost many pixels a particle, so SPH keeps its lanes. The particle
     * count is the source's, not the threads': the result still does not
     * depend on them. */
    if (!v->use_sph && count >= 0 && npix > 0) {
        const int64_t shares = v->scene->deposit == ORR_DEPOSIT_NGP ? count : ORR_MAX_SHARES_PER_POINT * count;
        int64_t by_count = shares / (LANE_SHARES_PER_PIXEL * (int64_t)npix);
        if (by_count < lanes)
            lanes = by_count > 1 ? (int)by_count : 1;
    }
    return lanes;
}

static orr_status alloc_lanes(view_state *v, int64_t count, orr_error *err)
{
    v->nlanes = lanes_for(v, count);
    if (v->nlanes == 1)
        return ORR_OK;
    size_t n = (size_t)(v->nlanes - 1) * (size_t)v->nplanes;
    v->lane_planes = orr_calloc(n, sizeof *v->lane_planes, "splat lanes", err);
    if (!v->lane_planes)
        return ORR_ERR_NOMEM;
    orr_status st = ORR_OK;
    for (size_t i = 0; i < n && !st; i++)
        st = orr_plane_alloc(&v->lane_planes[i], v->proj.width, v->proj.height, "lane", "", err);
    return st;
}

/* The bands of a point deposit: a window of blocks of a chunk of up to
 * capacity particles, each block's shares in a region of its own. */
static orr_status alloc_bands(view_state *v, size_t capacity, orr_error *err)
{
    v->nlanes = 1;
    size_t nblocks = (capacity + BLOCK - 1) / BLOCK, window = nblocks < WINDOW_BLOCKS ? nblocks : WINDOW_BLOCKS;
    size_t per_point = v->scene->deposit == ORR_DEPOSIT_NGP ? 1 : ORR_MAX_SHARES_PER_POINT;
    size_t npix = (size_t)v->proj.width * (size_t)v->proj.height;
    return orr_bands_init(&v->bands, npix, v->nplanes, window ? window : 1, per_point * BLOCK, err);
}

static void free_lanes(view_state *v)
{
    if (v->lane_planes)
        for (int i = 0; i < (v->nlanes - 1) * v->nplanes; i++)
            orr_plane_free(&v->lane_planes[i]);
    free(v->lane_planes);
    v->lane_planes = NULL;
}

static orr_plane *lane_planes(view_state *v, int lane)
{
    return lane == 0 ? v->planes : &v->lane_planes[(size_t)(lane - 1) * (size_t)v->nplanes];
}

/* Adds the lanes into the view's planes, in lane order at every pixel (the
 * ordered reduction: the same sums whatever the threads). */
static void merge_lanes(view_state *v)
{
    if (v->nlanes == 1)
        return;
    const long npix = (long)v->proj.width * v->proj.height;
    const int nlanes = v->nlanes;
    for (int k = 0; k < v->nplanes; k++) {
        float *out = v->planes[k].data;
        const float *lane_data[MAX_LANES] = {NULL};
        for (int lane = 1; lane < nlanes; lane++)
            lane_data[lane] = lane_planes(v, lane)[k].data;
#pragma omp parallel for schedule(static)
        for (long i = 0; i < npix; i++) {
            float sum = out[i];
            for (int lane = 1; lane < nlanes; lane++)
                sum += lane_data[lane][i];
            out[i] = sum;
        }
    }
    free_lanes(v);
    v->nlanes = 1;
}

/* The scratch of a chunk's splat: block buffers and an error per lane, and
 * per block where its smoothing lengths start and what it added. */
typedef struct splat_work {
    block_buffers *buffers; /* MAX_LANES */
    block_buffers *samples; /* MAX_LANES, with motion blur: buffers[k].samples */
    orr_error lane_err[MAX_LANES];
    size_t failed[MAX_LANES]; /* the block at which a lane stopped, or SIZE_MAX */
    size_t nblocks_cap;
    size_t *lengths_first; /* per block */
    block_tally *tally;    /* per block */
    /* Per worker, seconds spent gathering and projecting (0) and depositing
     * (1): the threads interleave the two, so the chunk's splat time is
     * shared between the stages in this proportion (--timings). */
    double split[MAX_LANES][2];
} splat_work;

/* Where each block's neighbour smoothing lengths start: they are taken in
 * source order by the particles orr_lengths_counts counts, so each block's
 * start is the count before it (a serial pass, cheap beside the splat). */
static void lengths_starts(view_state *v, const orr_chunk *c, size_t nblocks, size_t *first)
{
    size_t next = v->lengths_next;
    for (size_t blk = 0; blk < nblocks; blk++) {
        first[blk] = next;
        if (!v->lengths)
            continue; /* the file's lengths, or none: nothing to count */
        size_t end = (blk + 1) * BLOCK < c->n ? (blk + 1) * BLOCK : c->n;
        for (size_t i = blk * BLOCK; i < end; i++)
            if (orr_lengths_counts(v->scene, c, i) && next < v->lengths->n)
                next++;
    }
    v->lengths_next = next;
}

/* Gathers and projects block blk of the chunk into b for worker k (a lane,
 * or a thread of the bands), its report in *t, freshly zeroed. Returns the
 * particles gathered, or -1 on a bad particle, recorded in w->failed[k]
 * and w->lane_err[k]. */
static long take_block(const view_state *v, const orr_source *src, const orr_chunk *c, const float *const *wts,
                       size_t blk, splat_work *w, int k, block_buffers *b, block_tally **t)
{
    size_t start = blk * BLOCK, end = start + BLOCK < c->n ? start + BLOCK : c->n;
    *t = &w->tally[blk];
    memset(*t, 0, sizeof **t);
    long n = project_block(v, src, c, wts, start, end, orr_v3(0, 0, 0), 0, w->lengths_first[blk], b, *t,
                           &w->lane_err[k]);
    if (n < 0)
        w->failed[k] = blk;
    return n;
}

/* Adds this thread's CPU time since `since` to split[part]; returns now. */
static double split_mark(double *split, int part, double since)
{
    double now = orr_thread_cpu_seconds();
    split[part] += now - since;
    return now;
}

/* One lane's blocks of the chunk, in order; stops at a bad particle,
 * recording the block in w->failed[lane] and the error in w->lane_err. */
static void splat_lane(view_state *v, const orr_source *src, const orr_chunk *c, const float *const *wts,
                       size_t nblocks, int lane, splat_work *w)
{
    block_buffers *b = &w->buffers[lane];
    orr_plane *planes = lane_planes(v, lane);
    double at = orr_thread_cpu_seconds();
    for (size_t blk = (size_t)lane; blk < nblocks; blk += (size_t)v->nlanes) {
        block_tally *t;
        long n = take_block(v, src, c, wts, blk, w, lane, b, &t);
        if (n < 0)
            return;
        at = split_mark(w->split[lane], 0, at);
        deposit_block(v, planes, lane, (size_t)n, b, t);
        at = split_mark(w->split[lane], 1, at);
    }
}

static void add_stats(orr_deposit_stats *to, const orr_deposit_stats *from)
{
    to->deposited += from->deposited;
    to->outside += from->outside;
    to->culled += from->culled;
    to->n_particles += from->n_particles;
    to->n_culled += from->n_culled;
}

/* Adds what one block added to the report. */
static void add_tally(orr_render_report *r, const block_tally *t)
{
    r->n_selected += t->n_selected;
    r->n_nonfinite += t->n_nonfinite;
    r->n_stereo_skipped += t->n_stereo_skipped;
    add_stats(&r->deposit, &t->deposit[0]);
    add_stats(&r->deposit_y, &t->deposit[1]);
}

/* The error of the first bad block, as a single thread would have met it:
 * each worker records the block it stopped at (or SIZE_MAX). */
static orr_status first_failure(const splat_work *w, int nworkers, orr_error *err)
{
    int bad = -1;
    for (int k = 0; k < nworkers; k++)
        if (w->failed[k] != SIZE_MAX && (bad < 0 || w->failed[k] < w->failed[bad]))
            bad = k;
    if (bad < 0)
        return ORR_OK;
    if (err)
        *err = w->lane_err[bad];
    return w->lane_err[bad].code ? w->lane_err[bad].code : ORR_ERR_DATA;
}

/* Adds the chunk's blocks to the report, in block order. */
static void add_chunk_tally(view_state *v, const orr_chunk *c, const splat_work *w, size_t nblocks)
{
    for (size_t blk = 0; blk < nblocks; blk++)
        add_tally(v->rep, &w->tally[blk]);
    v->rep->n_read += c->n;
}

/* Splats the chunk into one view, its lanes in parallel; the report's sums
 * are taken in block order afterwards. On a bad particle the error is that
 * of the first bad block, as a single thread would have found it. */
static orr_status splat_view_lanes(view_state *v, const orr_source *src, const orr_chunk *c, const float *const *wts,
                                   splat_work *w, orr_error *err)
{
    size_t nblocks = (c->n + BLOCK - 1) / BLOCK;
    lengths_starts(v, c, nblocks, w->lengths_first);
    for (int lane = 0; lane < MAX_LANES; lane++)
        w->failed[lane] = SIZE_MAX;
    const int nlanes = v->nlanes;
#pragma omp parallel for schedule(dynamic, 1)
    for (int lane = 0; lane < nlanes; lane++)
        splat_lane(v, src, c, wts, nblocks, lane, w);
    orr_status st = first_failure(w, nlanes, err);
    if (!st)
        add_chunk_tally(v, c, w, nblocks);
    return st;
}

/* Threads of the splat: the machine's, at most MAX_LANES (the work's
 * buffers). */
static int splat_threads(void)
{
    int n = omp_get_max_threads();
    return n < MAX_LANES ? n : MAX_LANES;
}

/* The shares of blocks [first, first + count) of the chunk, sorted by band
 * into regions 0 .. count-1, the blocks shared out among the threads. A
 * thread stops at a bad particle (w->failed); its later blocks are all
 * after it, so the first failure is the one a single thread would meet. */
static void window_shares(view_state *v, const orr_source *src, const orr_chunk *c, const float *const *wts,
                          size_t first, size_t count, splat_work *w, int nthreads)
{
    const int W = v->proj.width, H = v->proj.height;
#pragma omp parallel num_threads(nthreads)
    {
        const int me = omp_get_thread_num();
        block_buffers *b = &w->buffers[me];
#pragma omp for schedule(dynamic, 1)
        for (size_t q = 0; q < count; q++) {
            if (w->failed[me] != SIZE_MAX)
                continue;
            block_tally *t;
            long n = take_block(v, src, c, wts, first + q, w, me, b, &t);
            if (n < 0)
                continue;
            orr_shares shares = {b->share_pixel, {b->share_w[0], b->share_w[1], b->share_w[2]}, 0};
            if (b->indexed) {
                orr_ngp_batch nb = place_indexed(v, (size_t)n, b, t);
                orr_ngp_shares(&nb, &shares);
            } else {
                orr_deposit_stats st[3];
                memset(st, 0, sizeof st);
                orr_point_batch pb = {(size_t)n, b->px, b->py, b->visible, {b->wp[0], b->wp[1], b->wp[2]},
                                      v->nplanes};
                orr_deposit_shares(v->scene->deposit, &pb, &v->proj, W, H, &shares, st);
                t->deposit[0] = st[0];
                t->deposit[1] = st[1];
            }
            orr_bands_put(&v->bands, q, &shares, b->band_cursor);
        }
    }
}

/* Splats the chunk into a view of point deposits: window by window, the
 * blocks' shares in parallel, then the bands in parallel (splat/bands.h:
 * the same sums in the same order whatever the threads). */
static orr_status splat_view_banded(view_state *v, const orr_source *src, const orr_chunk *c,
                                    const float *const *wts, splat_work *w, orr_error *err)
{
    const size_t nblocks = (c->n + BLOCK - 1) / BLOCK, window = v->bands.nregions;
    const int nthreads = splat_threads(), nbands = v->bands.nbands;
    lengths_starts(v, c, nblocks, w->lengths_first);
    for (int k = 0; k < MAX_LANES; k++)
        w->failed[k] = SIZE_MAX;
    for (size_t first = 0; first < nblocks; first += window) {
        size_t count = nblocks - first < window ? nblocks - first : window;
        orr_clock at = orr_clock_now();
        window_shares(v, src, c, wts, first, count, w, nthreads);
        orr_status st = first_failure(w, nthreads, err);
        if (st)
            return st;
        orr_clock mid = orr_clock_now();
        /* Runs of eight consecutive bands: each band prefetches the next. */
#pragma omp parallel for schedule(dynamic, 8) num_threads(nthreads)
        for (int band = 0; band < nbands; band++)
            orr_bands_apply(&v->bands, band, count, v->planes);
        /* The two phases follow each other: their wall times split the splat. */
        w->split[0][0] += mid.wall - at.wall;
        w->split[0][1] += orr_clock_now().wall - mid.wall;
    }
    add_chunk_tally(v, c, w, nblocks);
    return ORR_OK;
}

static orr_status splat_view(view_state *v, const orr_source *src, const orr_chunk *c, const float *const *wts,
                             splat_work *w, orr_error *err)
{
    return v->banded ? splat_view_banded(v, src, c, wts, w, err) : splat_view_lanes(v, src, c, wts, w, err);
}

/* The per-particle weights of a chunk: the scene's weight field, or with
 * colour the X, Y, Z of each particle's population (into xyz, room for the
 * chunk's capacity), assigned in MAX_LANES parallel stretches; an error is
 * the first stretch's that failed, as one thread would have met it. */
static orr_status chunk_weights(const orr_scene *s, const orr_source *src, const orr_chunk *c, float *const *xyz,
                                const float **w, splat_work *work, orr_error *err)
{
    if (!s->colour)
        return weight_field(s, src, c, &w[0], err);
    orr_status st_part[MAX_LANES];
    const size_t n = c->n, per = (n + MAX_LANES - 1) / MAX_LANES;
#pragma omp parallel for schedule(static, 1)
    for (int part = 0; part < MAX_LANES; part++) {
        size_t start = (size_t)part * per < n ? (size_t)part * per : n;
        size_t count = start + per < n ? per : n - start;
        st_part[part] = orr_population_assign(&s->populations, c, start, count, s->only, NULL, xyz[0] + start,
                                              xyz[1] + start, xyz[2] + start, &work->lane_err[part]);
    }
    for (int part = 0; part < MAX_LANES; part++)
        if (st_part[part]) {
            if (err)
                *err = work->lane_err[part];
            orr_fail_prefix(err, "%s: colour.populations: ", s->path);
            return st_part[part];
        }
    for (int k = 0; k < 3; k++)
        w[k] = xyz[k];
    return ORR_OK;
}

/* ---- periodic boxes ---- */

/* Gathers, projects and deposits particles [start, end) of c, moved by
 * shift (fading: across the copies' sphere), into the view's own planes,
 * starting at smoothing length lengths_next; what the block added goes
 * into the report. */
static orr_status draw_block(view_state *v, const orr_source *src, const orr_chunk *c, const float *const *w,
                             size_t start, size_t end, orr_vec3 shift, int fading, size_t lengths_next,
                             block_buffers *b, double *split, orr_error *err)
{
    block_tally t;
    memset(&t, 0, sizeof t);
    double at = orr_thread_cpu_seconds();
    long n = project_block(v, src, c, w, start, end, shift, fading, lengths_next, b, &t, err);
    if (n < 0)
        return err ? err->code : ORR_ERR_DATA;
    at = split_mark(split, 0, at);
    deposit_block(v, v->planes, 0, (size_t)n, b, &t);
    split_mark(split, 1, at);
    add_tally(v->rep, &t);
    return ORR_OK;
}

/* A copy of a block (or of a whole chunk) skipped out of view: its weight
 * counts as not drawn, as the projection would have counted it. */
static void count_culled(view_state *v, const orr_block_summary *sum)
{
    orr_deposit_stats *d[2] = {&v->rep->deposit, &v->rep->deposit_y};
    v->rep->n_selected += sum->n;
    for (int k = 0; k < v->nplanes && k < 2; k++) {
        d[k]->culled += sum->w[k];
        d[k]->n_culled += sum->n;
        d[k]->n_particles += sum->n;
    }
}

/* Whether a copy (by shift) of the particles summarised in sum is skipped
 * whole: beyond the periodic sphere, or out of view. (Never with a
 * particle the gather must see, nor with culling off.) */
static int copy_skipped(const orr_periodic_view *pv, const orr_block_summary *sum, orr_vec3 shift)
{
    if (sum->must_gather)
        return 0;
    if (pv->cull_sphere && orr_replica_sphere_box(&pv->sphere, sum->lo, sum->hi, shift) == ORR_SPHERE_BEYOND)
        return 1;
    return pv->cull && orr_view_cull_box(&pv->view, sum->lo, sum->hi, shift, sum->radius);
}

/* Whether a drawn copy of a block has particles in the sphere's taper or
 * beyond it, so that each is weighed by its distance (else it is drawn
 * whole, on the fast path). */
static int copy_fades(const orr_periodic_view *pv, const orr_block_summary *sum, orr_vec3 shift)
{
    return pv->sphere.radius > 0 && (sum->must_gather || sum->n == 0 ||
                                     orr_replica_sphere_box(&pv->sphere, sum->lo, sum->hi, shift) != ORR_SPHERE_INSIDE);
}

/* A periodic box: the chunk drawn once per copy of the box. Each block is
 * summarised once (bounds, largest kernel, weights); then a copy of the
 * chunk wholly out of view is skipped, and within the others each copy of
 * a block out of view, before their particles are touched. Drawn on one
 * thread into the view's own planes, in block order (in a fly-through the
 * culling, not threads, is what saves the time). */
static orr_status splat_chunk_periodic(view_state *v, const orr_source *src, const orr_chunk *c,
                                       const float *const *w, block_buffers *b, double *split, orr_error *err)
{
    const orr_periodic_view *pv = &v->periodic;
    const size_t nblocks = (c->n + BLOCK - 1) / BLOCK, first_length = v->lengths_next;
    orr_block_summary *sum = orr_malloc((nblocks ? nblocks : 1) * sizeof *sum, "block summaries", err), whole;
    if (!sum)
        return ORR_ERR_NOMEM;
    orr_block_lengths bl = {v->lengths, first_length, v->h_scale, v->use_sph};
    memset(&whole, 0, sizeof whole);
    for (size_t q = 0; q < nblocks; q++) {
        size_t end = (q + 1) * BLOCK < c->n ? (q + 1) * BLOCK : c->n;
        orr_block_summarise(v->scene, c, q * BLOCK, end, &bl, w, v->nplanes, &sum[q]);
        bl.next += sum[q].lengths_used;
        orr_block_summary_merge(&whole, &sum[q]);
    }
    orr_status st = ORR_OK;
    for (int r = 0; r < pv->replicas.n && !st; r++) {
        const orr_vec3 shift = pv->replicas.offset[r];
        v->rep->n_blocks += nblocks;
        if (copy_skipped(pv, &whole, shift)) {
            count_culled(v, &whole);
            v->rep->n_replicas_culled++;
            v->rep->n_blocks_culled += nblocks;
            continue;
        }
        size_t next = first_length; /* every copy takes the same lengths */
        for (size_t q = 0; q < nblocks && !st; q++) {
            size_t end = (q + 1) * BLOCK < c->n ? (q + 1) * BLOCK : c->n;
            if (copy_skipped(pv, &sum[q], shift)) {
                count_culled(v, &sum[q]);
                v->rep->n_blocks_culled++;
            } else {
                st = draw_block(v, src, c, w, q * BLOCK, end, shift, copy_fades(pv, &sum[q], shift), next, b, split,
                                err);
            }
            next += sum[q].lengths_used;
        }
    }
    v->lengths_next = first_length + whole.lengths_used;
    v->rep->n_read += c->n;
    free(sum);
    return st;
}

/* Splats a chunk into every view; its time goes to the
 * gather and deposit stages (the weights to the gather; the splat shared
 * as the workers' own clocks say). */
static orr_status splat_chunk(view_state *views, int nviews, const orr_source *src, const orr_chunk *c,
                              splat_work *work, float *const *xyz, orr_error *err)
{
    const float *w[3] = {NULL, NULL, NULL};
    orr_status st = chunk_weights(views[0].scene, src, c, xyz, w, work, err);
    charge(&views[0], ORR_STAGE_GATHER);
    memset(work->split, 0, sizeof work->split);
    for (int k = 0; k < nviews && !st; k++)
        st = views[k].periodic.active
                 ? splat_chunk_periodic(&views[k], src, c, w, &work->buffers[0], work->split[0], err)
                 : splat_view(&views[k], src, c, w, work, err);
    double part[2] = {0.0, 0.0};
    for (int k = 0; k < MAX_LANES; k++)
        part[0] += work->split[k][0], part[1] += work->split[k][1];
    if (views[0].timer)
        orr_stage_charge_split(&views[0].timer->times, ORR_STAGE_GATHER, ORR_STAGE_DEPOSIT,
                               part[0] / (part[0] + part[1]), &views[0].timer->at);
    return st;
}

/* Room for the per-block records of a chunk of n particles. */
static orr_status reserve_blocks(splat_work *w, size_t n, orr_error *err)
{
    size_t nblocks = (n + BLOCK - 1) / BLOCK;
    if (nblocks <= w->nblocks_cap && w->tally)
        return ORR_OK;
    nblocks = nblocks ? nblocks : 1;
    free(w->lengths_first);
    free(w->tally);
    w->lengths_first = orr_malloc(nblocks * sizeof *w->lengths_first, "splat blocks", err);
    w->tally = w->lengths_first ? orr_malloc(nblocks * sizeof *w->tally, "splat blocks", err) : NULL;
    w->nblocks_cap = w->tally ? nblocks : 0;
    return w->tally ? ORR_OK : ORR_ERR_NOMEM;
}

static orr_status alloc_work(splat_work *w, size_t capacity, int blur, orr_error *err)
{
    memset(w, 0, sizeof *w);
    w->buffers = orr_malloc(MAX_LANES * sizeof *w->buffers, "splat block buffers", err);
    if (!w->buffers)
        return ORR_ERR_NOMEM;
    if (blur) {
        if (!(w->samples = orr_malloc(MAX_LANES * sizeof *w->samples, "motion blur samples", err)))
            return ORR_ERR_NOMEM;
        for (int k = 0; k < MAX_LANES; k++)
            w->buffers[k].samples = &w->samples[k];
    }
    return reserve_blocks(w, capacity, err);
}

static void free_work(splat_work *w)
{
    free(w->buffers);
    free(w->samples);
    free(w->lengths_first);
    free(w->tally);
}

static orr_status splat_source(view_state *views, int nviews, orr_source *src, orr_progress_fn progress,
                               void *progress_user, orr_error *err)
{
    splat_work *work = orr_malloc(sizeof *work, "splat work", err);
    if (!work)
        return ORR_ERR_NOMEM;
    int blur = 0;
    for (int k = 0; k < nviews; k++)
        blur |= views[k].blur.active;
    orr_status st = alloc_work(work, src->chunk.capacity, blur, err);
    /* With colour, a chunk's X, Y, Z weights. */
    float *xyz[3] = {NULL, NULL, NULL};
    size_t cap = views[0].scene->colour ? src->chunk.capacity : 0;
    for (int k = 0; k < 3 && cap && !st; k++)
        if (!(xyz[k] = orr_malloc(cap * sizeof(float), "colour weights", err)))
            st = ORR_ERR_NOMEM;
    for (int k = 0; k < nviews && !st; k++)
        st = views[k].banded && !views[k].periodic.active ? alloc_bands(&views[k], src->chunk.capacity, err)
                             : alloc_lanes(&views[k], src->info.count, err);
    charge(&views[0], ORR_STAGE_SETUP); /* the lanes' planes, zeroed */
    while (!st) {
        const orr_chunk *c;
        st = orr_source_next(src, &c, err);
        charge(&views[0], ORR_STAGE_SOURCE);
        if (st || c->n == 0)
            break;
        if ((st = reserve_blocks(work, c->n, err)) || (st = splat_chunk(views, nviews, src, c, work, xyz, err)))
            break;
        /* From this thread alone, between chunks. */
        if (progress)
            progress(progress_user, views[0].rep->n_read, src->info.count);
    }
    for (int k = 0; k < nviews; k++) {
        orr_bands_free(&views[k].bands);
        if (!st)
            merge_lanes(&views[k]);
    }
    for (int k = 0; k < nviews && !st; k++)
        if (views[k].psf.sky)
            st = orr_sky_psf_select(views[k].psf.sky, err);
    charge(&views[0], ORR_STAGE_REDUCE);
    for (int k = 0; k < 3; k++)
        free(xyz[k]);
    free_work(work);
    free(work);
    return st;
}
/* ---- outputs ---- */

/* Pixels outside a sky map hold no sky: NaN marks them blank in FITS (and
 * the stretch shows them black). Deposits never put weight there. */
static void mask_outside_map(view_state *v)
{
    const orr_projection *p = &v->proj;
    if (!orr_projection_is_sky(p))
        return;
    /* A row's pixels on the map are one run about the centre column (the
     * outline is an ellipse, a circle or the whole image): its ends are
     * found by bisection with the projection's own test, and only the
     * pixels outside are visited. */
    const int W = p->width, centre = (int)lround(p->cx - 0.5);
    for (int j = 0; j < p->height; j++) {
        int first = W, last = -1; /* the run [first, last], empty when last < first */
        if (centre >= 0 && centre < W && orr_projection_pixel_in_map(p, centre, j)) {
            int lo = 0, hi = centre; /* the first inside is in [lo, hi] */
            while (lo < hi) {
                int mid = lo + (hi - lo) / 2;
                if (orr_projection_pixel_in_map(p, mid, j))
                    hi = mid;
                else
                    lo = mid + 1;
            }
            first = lo;
            lo = centre, hi = W - 1; /* the last inside is in [lo, hi] */
            while (lo < hi) {
                int mid = hi - (hi - lo) / 2;
                if (orr_projection_pixel_in_map(p, mid, j))
                    lo = mid;
                else
                    hi = mid - 1;
            }
            last = lo;
        }
        const int left_end = first < W ? first : W, right_start = last + 1 > left_end ? last + 1 : left_end;
        for (int k = 0; k < v->nplanes; k++) {
            float *row = v->planes[k].data + (size_t)j * (size_t)W;
            for (int i = 0; i < left_end; i++)
                row[i] = NAN;
            for (int i = right_start; i < W; i++)
                row[i] = NAN;
        }
    }
}

static void add_frame_cards(const view_state *v, orr_fits_header *h)
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
    static const char *const psf_names[] = {"none", "gaussian", "hst", "file"};
    orr_fits_add_string(h, "PSF", psf_names[s->psf], "point spread function");
    if (s->psf == ORR_PSF_GAUSSIAN && orr_projection_is_sky(p))
        orr_fits_add_double(h, "PSFFWHM", v->psf.core_fwhm_arcmin, "[arcmin] PSF FWHM on the sky");
    else if (s->psf == ORR_PSF_GAUSSIAN)
        orr_fits_add_double(h, "PSFFWHM", s->psf_fwhm, "[pixel] PSF FWHM");
    else if (s->psf != ORR_PSF_NONE)
        orr_fits_add_double(h, "PSFSCALE", s->psf_arcsec_per_pixel, "[arcsec/pixel] image scale for the PSF");
    if (v->psf.sky) {
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
    if (s->stereo)
        orr_stereo_add_cards(h, s, rep);
}

/* The view's picture, sRGB-encoded RGB: the colour synthesis of its X, Y, Z
 * planes, or its weight plane stretched and colour-mapped; desc says how. */
static orr_status graded_rgb(const view_state *v, float *rgb, char *desc, size_t size, orr_error *err)
{
    const orr_scene *s = v->scene;
    orr_render_report *rep = v->rep;
    size_t npix = (size_t)v->proj.width * (size_t)v->proj.height;
    if (s->colour || s->nlayers || s->has_tint) {
        double xyz[3];
        orr_status st = ORR_OK;
        if (s->colour || s->nlayers)
            st = orr_colour_synthesise(&s->synth, &v->planes[0], &v->planes[1], &v->planes[2], rgb, &rep->white,
                                       err);
        else if (!(st = orr_colour_path_xyz(&s->tint, v->tint_t, xyz, err)))
            st = orr_colour_synthesise_mono(&s->synth, &v->planes[0], xyz, rgb, &rep->white, err);
        if (!st && !s->png_linear)
            orr_srgb_encode_buffer(rgb, npix * 3);
        if (!st && s->nlayers)
            orr_snprintf(desc, size, "colour (CIE XYZ) blended from %d layers, %s projection, %s stretch, Y0 %g",
                     s->nlayers, orr_projection_name(v->proj.kind), orr_lum_stretch_name(s->synth.stretch),
                     rep->white);
        else if (!st && s->colour)
            orr_snprintf(desc, size, "colour (CIE XYZ, %d populations) of %s, %s projection, %s stretch, Y0 %g",
                     s->populations.n, rep->source, orr_projection_name(v->proj.kind),
                     orr_lum_stretch_name(s->synth.stretch), rep->white);
        else if (!st)
            orr_snprintf(desc, size, "%s of %s tinted at t = %g of its colour path, %s projection, %s stretch, Y0 %g",
                     s->weight, rep->source, v->tint_t, orr_projection_name(v->proj.kind),
                     orr_lum_stretch_name(s->synth.stretch), rep->white);
        return st;
    }
    float *t = orr_malloc(npix * sizeof(float), "stretched image", err);
    if (!t)
        return ORR_ERR_NOMEM;
    orr_status st = orr_stretch_apply(&s->stretch, &v->planes[0], t, &rep->white, err);
    if (!st) {
#pragma omp parallel for schedule(static)
        for (size_t i = 0; i < npix; i++)
            orr_colormap_lookup(s->colormap, t[i], &rgb[3 * i]);
    }
    if (!st)
        orr_snprintf(desc, size, "%s of %s, %s projection, %s stretch, white %g, colour map %s", s->weight,
                 rep->source, orr_projection_name(v->proj.kind), orr_stretch_name(s->stretch.kind), rep->white,
                 orr_colormap_name(s->colormap));
    free(t);
    return st;
}

static orr_status view_output(view_state *v, const char *ext, const char **write_path, orr_error *err);

/* What the other image formats record: the scene, projection, time, camera. */
static orr_image_meta view_meta(const view_state *v, const char *desc, const char **keys, const char **values)
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
    keys[0] = "description";
    values[0] = desc;
    m.nextra = 1;
    for (int k = 0; k < m.nextra; k++) {
        m.extra_key[k] = keys[k];
        m.extra_value[k] = values[k];
    }
    return m;
}

/* The graded picture as PNG (output.png) and as output.image (any format
 * OpenImageIO writes, by extension). */
static orr_status write_pictures(view_state *v, orr_error *err)
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
    orr_status st = graded_rgb(v, rgb, desc, sizeof desc, err);
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
        const char *keys[1], *values[1];
        orr_image_meta meta = view_meta(v, desc, keys, values);
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
static orr_status write_exr(view_state *v, orr_error *err)
{
    orr_render_report *rep = v->rep;
    const char *path;
    const char *keys[1], *values[1];
    orr_image_meta meta = view_meta(v, "linear planes", keys, values);
    orr_exr_view ev;
    orr_status st = view_output(v, "exr", &path, err);
    if (!st && !(st = orr_exr_view_build(&ev, v->planes, v->nplanes, &v->proj, "", err))) {
        st = orr_write_image_planes(path, ev.channels, ev.n, &meta, err);
        orr_exr_view_free(&ev);
    }
    if (!st)
        rep->noutputs++;
    charge(v, ORR_STAGE_EXR);
    return st;
}

static orr_status output_path(const orr_scene *s, const char *ext, char *path, orr_error *err)
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
    orr_status st = output_path(s, ext, final_path, err);
    return st ? st : orr_output_batch_add(outputs, final_path, write_path, err);
}

static orr_status view_output(view_state *v, const char *ext, const char **write_path, orr_error *err)
{
    return stage_output(v->outputs, v->scene, v->rep, ext, write_path, err);
}

/* Writes the view's planes, with the frame's cards, to NAME.EXT. */
static orr_status write_fits_planes(view_state *v, const char *ext, orr_error *err)
{
    orr_render_report *rep = v->rep;
    const char *path;
    orr_fits_header *h = orr_calloc(1, sizeof *h, "FITS header", err);
    if (!h)
        return ORR_ERR_NOMEM;
    add_frame_cards(v, h);
    orr_status st = view_output(v, ext, &path, err);
    if (!st && v->proj.kind == ORR_PROJ_HEALPIX) {
        orr_wcs_view wcs = {&v->proj, &rep->camera, &rep->sky, rep->has_sky_frame, ""};
        orr_healpix_info info = {v->proj.healpix_nside, v->proj.healpix_nested, orr_wcs_healpix_coordsys(&wcs)};
        st = orr_write_healpix_fits(path, v->planes, v->nplanes, &info, h, err);
    } else if (!st) {
        st = orr_write_fits(path, v->planes, v->nplanes, h, err);
    }
    free(h);
    if (!st)
        rep->noutputs++;
    charge(v, ORR_STAGE_FITS);
    return st;
}

/* A stereo pair written as one picture (render/stereo_view.h): the right
 * eye (view k + 1 of eyes) is graded with the left eye's white level. */
static orr_status write_stereo_pair(view_state *l, view_state *r, orr_eye_views *eyes, int k, orr_error *err)
{
    const orr_scene *s = l->scene;
    mask_outside_map(l);
    mask_outside_map(r);
    size_t npix = (size_t)l->proj.width * (size_t)l->proj.height;
    int want_rgb = s->write_png || s->image_ext[0];
    float *rgb = want_rgb ? orr_malloc(2 * npix * 3 * sizeof *rgb, "stereo pictures", err) : NULL;
    orr_fits_header *h = orr_calloc(1, sizeof *h, "FITS header", err);
    orr_status st = !h || (want_rgb && !rgb) ? ORR_ERR_NOMEM : ORR_OK;
    char desc[ORR_PATH_MAX + 256] = "stereo pair", rdesc[ORR_PATH_MAX + 256];
    if (!st && want_rgb)
        st = graded_rgb(l, rgb, desc, sizeof desc, err);
    if (!st && want_rgb) {
        orr_eye_views_share_white(eyes, k, l->rep->white);
        st = graded_rgb(r, rgb + 3 * npix, rdesc, sizeof rdesc, err);
    }
    charge(l, ORR_STAGE_POST);
    if (!st) {
        add_frame_cards(l, h);
        const char *keys[1], *values[1];
        orr_image_meta meta = view_meta(l, desc, keys, values);
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

static orr_status write_outputs(view_state *v, orr_error *err)
{
    const orr_scene *s = v->scene;
    orr_status st;
    mask_outside_map(v);
    charge(v, ORR_STAGE_POST);
    if (s->write_fits && (st = write_fits_planes(v, "fits", err)))
        return st;
    if (s->write_exr && (st = write_exr(v, err)))
        return st;
    return write_pictures(v, err);
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
        orr_sky_frame moved = observer ? *observer : orr_sky_frame_world(s->camera_position), sky;
        moved.origin = orr_v3_add(moved.origin, observer_step);
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
    /* (A sky PSF collects its stars per lane: it keeps lanes.) */
    /* (Streaks are drawn as their samples are made: in lanes.) */
    v->banded = !v->use_sph && !v->psf.sky && !v->blur.active &&
                (size_t)v->proj.width * (size_t)v->proj.height > BAND_MIN_PIXELS;
    v->ngp_fused = s->deposit == ORR_DEPOSIT_NGP && !v->use_sph && !v->psf.sky && !v->use_ods && !v->blur.active;
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
    free_lanes(v);
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
            (st = par ? orr_lengths_compute_shared(v->scene, src, centre, par, lengths, err)
                                     : orr_lengths_compute(v->scene, src, centre, lengths, err)))
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
        if (p->lum.kind == ORR_POPLUM_FIELD || p->lum.kind == ORR_POPLUM_MAGNITUDE)
            add_field(fields, &nfields, p->lum.field);
    }
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
        st = graded_rgb(v, rgb, desc, sizeof desc, err);
    if (!st) {
        add_frame_cards(v, h);
        st = in->keep(in->keep_user, k, v->planes, v->nplanes, rgb, h, err);
    }
    free(rgb);
    free(h);
    return st;
}

static orr_status finish_views(view_state *views, int n, orr_eye_views *eyes, const orr_frame_input *in,
                               orr_error *err)
{
    int keep = in && in->keep;
    orr_status st = ORR_OK;
    for (int k = 0; k < n && !st; k++) /* a sky map's bright stars: part of the raw planes, as their cores */
        if (views[k].psf.sky)
            st = orr_sky_psf_draw(views[k].psf.sky, &views[k].sph, views[k].planes, views[k].nplanes, err);
    charge(&views[0], ORR_STAGE_PSF);
    for (int k = 0; k < n && !st; k++) /* flux per pixel to flux per steradian (or area) */
        orr_to_surface_brightness(&views[k].proj, views[k].planes, views[k].nplanes);
    charge(&views[0], ORR_STAGE_POST);
    for (int k = 0; k < n && !st; k++)
        if (views[k].scene->write_raw) {
            mask_outside_map(&views[k]);
            charge(&views[k], ORR_STAGE_POST);
            st = write_fits_planes(&views[k], "raw.fits", err);
        }
    for (int k = 0; k < n && !st; k++)
        for (int j = 0; j < views[k].nplanes && !st; j++)
            st = orr_view_psf_apply(&views[k].psf, &views[k].planes[j], err);
    charge(&views[0], ORR_STAGE_PSF);
    for (int k = 0; k < n && !st; k++) {
        if (orr_eye_views_pair_at(eyes, k)) {
            st = write_stereo_pair(&views[k], &views[k + 1], eyes, k, err);
            if (!st && keep && !(st = keep_view(&views[k], k, in, err)))
                st = keep_view(&views[k + 1], k + 1, in, err);
            k++; /* the right eye was written with the left */
            continue;
        }
        st = write_outputs(&views[k], err);
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
    for (int k = 0; k < n && !st; k++)
        st = setup_periodic(&views[k], &src->info, err);
    if (!st)
        st = splat_source(views, n, src, progress, progress_user, err);
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
    orr_status st = output_path(v->scene, v->scene->regrade_final ? "fits" : "raw.fits", path, err);
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
        mask_outside_map(v);
        if (!st)
            st = write_pictures(v, err);
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
