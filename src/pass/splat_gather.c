/* The splat's gather: a block of a chunk's particles taken into the camera
 * frame (a periodic copy's shift, the dimming, the periodic sphere's
 * taper, the glow's lengths, motion blur's streaks), checked, and
 * projected. Blocks that take every particle go through straight loops
 * without a branch a particle, or for NGP the fused gather
 * (pass/ngp_gather.h). */
#include "pass/splat_block.h"
#include "core/fastmath.h"
#include "core/numbers.h"
#include "core/simd.h"

#include <math.h>
#include <string.h>

#include "pass/camera_transform.h"
#include "pass/lengths.h"
#include "pass/motion_blur.h"
#include "pass/ngp_gather.h"

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
static int block_selects_all(const orr_splat_view *v, const orr_chunk *c, size_t start, size_t end)
{
    const orr_splat_settings *set = &v->splat;
    if (v->lengths || (v->stars && !v->drawing_stars)) /* (the stars' glows take their own dimming) */
        return 0;
    /* Blocks mostly hold one type: checked with a byte loop that vectorises;
     * otherwise each particle's type against the mask. */
    const uint8_t *type = c->type, first_type = type[start];
    uint8_t differ = 0;
    for (size_t i = start; i < end; i++)
        differ |= type[i] ^ first_type;
    if (!differ) {
        if (first_type > 31 || !(set->type_mask & (1u << first_type)))
            return 0;
    } else {
        uint32_t types = 0;
        for (size_t i = start; i < end; i++)
            types |= type[i] > 31 ? ~0u : 1u << type[i];
        if (types & ~set->type_mask)
            return 0;
    }
    if (set->skip_observer) {
        const uint64_t observer = set->observer_id;
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

/* A spawned star's flux grows as 1/r^2 down to this distance, parsecs. */
#define STAR_DIM_NEAR_PC 0.01

/* The camera transform of a copy moved by shift; fading: the weights
 * taper within the periodic sphere (the copy's block is across it). */
static orr_camera_transform transform_of(const orr_splat_view *v, orr_vec3 shift, int fading)
{
    const orr_splat_settings *set = &v->splat;
    orr_camera_transform t = orr_camera_transform_at(v->camera_position, &v->world_to_camera, shift);
    if (fading) {
        const orr_replica_sphere *sp = &v->periodic.sphere;
        t.fade = 1;
        t.outer = (float)sp->radius;
        t.inner = (float)(sp->radius - sp->fade);
        t.inner2 = t.inner * t.inner;
        t.outer2 = t.outer * t.outer;
    }
    t.dim = set->dim;
    double near = set->dim_near;
    if (v->drawing_stars) /* a spawned star is a star: its flux is its own distance's */
        near = STAR_DIM_NEAR_PC / v->stars->stage.set.length_unit;
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

/* The plane whose weights are checked for finiteness: the weight, or
 * with colour Z. */
static int checked_plane(const orr_splat_view *v)
{
    return v->nplanes >= 3 ? 2 : 0;
}

/* The weights of a block taken whole, particles [start, start + n): the
 * source's arrays themselves, or with dimming (observer.dim, camera.dim;
 * NULL without) the dimmed copies in b->w. */
static void take_weights(const orr_splat_view *v, const float *const *wsrcs, size_t start, size_t n,
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
static size_t gather_all(const orr_splat_view *v, const orr_chunk *c, const float *const *wsrcs, size_t start,
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

/* The fused gather (pass/ngp_gather.h) of a block that takes every
 * particle: indices into b->share_pixel. Returns 0 when the block has a
 * non-finite value (b->indexed 0). */
static int ngp_gather_all(const orr_splat_view *v, const orr_chunk *c, const float *const *wsrcs, size_t start,
                          size_t end, const orr_camera_transform *t, block_buffers *b)
{
    const size_t n = end - start;
    orr_ngp_gather_out out = {b->share_pixel, b->px, b->py, b->scale};
    if (!orr_ngp_gather(&v->proj, &v->outline, t, n, c->x + start, c->y + start, c->z + start,
                        wsrcs[checked_plane(v)] + start, &out))
        return 0;
    take_weights(v, wsrcs, start, n, t->dim ? out.dimming : NULL, b);
    b->indexed = 1;
    return 1;
}

/* The weight a periodic sphere's taper takes from particle i (fade < 1),
 * counted as not drawn, so that what is drawn, falls off and is not drawn
 * still adds up to every copy's weight; a particle beyond the radius
 * (fade 0) is not drawn at all. */
static void count_faded(const orr_splat_view *v, const float *const *wsrcs, size_t i, float dimming, float fade,
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
static float glow_length(const orr_splat_settings *set, float h, float r2, float flux)
{
    const float max_h = (float)(0.5 * set->glow_max_arcmin * ORR_PI / (180.0 * 60.0));
    return h * glow_taper(h, max_h) * glow_taper(flux, (float)set->glow_threshold) * sqrtf(r2);
}

/* The glow of a particle whose bright stars are drawn one by one: the
 * light they leave is the faint crowd spread over the particle's kernel,
 * never narrower than the kernel itself seen from here (so the nearest
 * particles' glow spreads wide over the sky instead of standing out as a
 * patch), nor than its neighbours' angle on the sky; no limits by flux or
 * width, which would make it a point. h: the angular length. */
static float stars_glow_length(const orr_splat_view *v, float h, float r2, float mass)
{
    const float r = sqrtf(r2), own = (float)orr_stars_kernel_length(&v->stars->stage, mass);
    const float widest = (float)(v->stars->stage.set.glow_max_deg * ORR_PI / 180.0) * r;
    float length = h * r > own ? h * r : own;
    return length < widest ? length : widest;
}

/* ---- motion blur (pass/motion_blur.h) ---- */

/* The velocities motion blur moves the chunk's particles by (NULLs when
 * the shutter holds them still), or an error naming the field missing. */
static orr_status blur_velocities(const orr_splat_view *v, const orr_source *src, const orr_chunk *c,
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
                            v->splat.path, 2 * v->blur.half_time, src->info.path, names[a]);
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
 * returns how many, or -1 (err set) on a bad particle when input.nonfinite
 * says to fail. What it counts goes into *t. The observer particle is left out, and with
 * observer.dim or camera.dim weights fall off as 1/r^2 from the camera. */
static long gather_block(const orr_splat_view *v, const orr_source *src, const orr_chunk *c, const float *const *wsrcs,
                         size_t start, size_t end, orr_vec3 shift, int fading, size_t lengths_next,
                         block_buffers *b, block_tally *t, orr_error *err)
{
    /* Checked for finiteness: the weight, or with colour Z
     * (orr_population_assign already refuses a luminance or colour that is
     * not finite, so a particle's X, Y and Z, and its population's Y, are
     * finite together) */
    const float *wsrc = wsrcs[checked_plane(v)];
    const orr_splat_settings *set = &v->splat;
    const orr_camera_transform tf = transform_of(v, shift, fading);
    for (int k = 0; k < ORR_PLANES_MAX; k++)
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
    const int skip_observer = set->skip_observer;
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
            if (orr_lengths_counts(set->type_mask, c, i) && lengths_next < v->lengths->n)
                h = v->lengths->h[lengths_next++] * v->h_scale;
        } else if (c->h) {
            h = c->h[i] * v->h_scale;
        }
        if (!(set->type_mask & (1u << c->type[i])) || (skip_observer && c->id[i] == set->observer_id))
            continue;
        t->n_selected++;
        if (!isfinite(c->x[i]) || !isfinite(c->y[i]) || !isfinite(c->z[i]) || !isfinite(wsrc[i]) ||
            (vel[0] && !velocity_finite(vel, i))) {
            if (!set->skip_nonfinite) {
                nonfinite_error(src, c, i, wsrc[i], vel[0] ? vel : NULL, err);
                return -1;
            }
            t->n_nonfinite++;
            continue;
        }
        orr_camera_point p = orr_to_camera(&tf, c->x[i], c->y[i], c->z[i]);
        float dimming = tf.dim ? orr_camera_dimming(&tf, p.r2) : 1.0f;
        float fade = tf.fade ? orr_camera_fade(&tf, p.r2) : 1.0f;
        if (v->stars && !v->drawing_stars && orr_stars_spawns(&v->stars->stage, c->type[i])) { /* what its stars left */
            h = stars_glow_length(v, h, p.r2, c->mass[i]);
            /* ... whose light is spread over the kernel: its flux the
             * kernel's mean of 1/s^2 over the stars left, not 1/r^2 */
            if (tf.dim)
                dimming = v->stars->glow_dimming[i];
        } else if (set->has_glow) /* an angle from the lengths, a point when bright */
            h = glow_length(set, h, p.r2, wsrcs[v->nplanes >= 3 ? 1 : 0][i] * dimming);
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
void orr_splat_project_points(const orr_splat_view *v, size_t n, block_buffers *b, block_tally *t)
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
long orr_splat_project_block(const orr_splat_view *v, const orr_source *src, const orr_chunk *c,
                             const float *const *wts, size_t start, size_t end, orr_vec3 shift, int fading,
                             size_t lengths_next, block_buffers *b, block_tally *t, orr_error *err)
{
    long n = gather_block(v, src, c, wts, start, end, shift, fading, lengths_next, b, t, err);
    if (n < 0 || b->indexed || v->blur.active) /* streaks: their samples are projected as drawn */
        return n;
    orr_splat_project_points(v, (size_t)n, b, t);
    return n;
}
