/* The splat pass: every chunk of particles into each view's planes. A
 * chunk's weights are found once (colour populations), then each view
 * gathers its blocks of particles into the camera frame (periodic copies,
 * dimming, the glow's lengths, motion blur's streaks), projects and
 * deposits them, in lanes or bands whose order never depends on the
 * threads (render/view_state.h). */
#include "render/view_state.h"
#include "core/fastmath.h"
#include "core/numbers.h"
#include "core/simd.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "render/camera_transform.h"
#include "render/lengths.h"
#include "render/motion_blur.h"
#include "render/ngp_gather.h"
#include "render/periodic_view.h"
#include "render/stereo_view.h"
#include "render/view_psf.h"
#include "reduce/lanes.h"
#include "splat/bands.h"
#include "splat/sph.h"


/* Particles are processed in blocks of this many: the block's scratch arrays
 * (about 100 KiB) stay in L2 cache between the gather, project and deposit
 * passes. */
#define BLOCK 4096

/* The splat's reductions (reduce/lanes.h): lanes for most views, bands for
 * point deposits into large images. */
#define MAX_LANES ORR_MAX_LANES
_Static_assert(MAX_LANES <= ORR_SKY_PSF_LANES, "a sky PSF collects stars in every lane");

typedef struct block_buffers {
    float x[BLOCK], y[BLOCK], z[BLOCK], h[BLOCK];
    float w[ORR_PLANES_MAX][BLOCK]; /* the weight, or X, Y, Z with colour */
    float px[BLOCK], py[BLOCK], scale[BLOCK];
    uint8_t visible[BLOCK];
    uint8_t keep[BLOCK]; /* omni-directional stereo: 0 inside the eye circle */
    /* Point deposits: the block's shares, before they are sorted by band. */
    int32_t share_pixel[ORR_MAX_SHARES_PER_POINT * BLOCK];
    float share_w[ORR_PLANES_MAX][ORR_MAX_SHARES_PER_POINT * BLOCK];
    uint32_t band_cursor[ORR_MAX_BANDS];
    /* The block's weights, as the deposits read them: the source's arrays
     * themselves for a block taken whole (take_weights), otherwise w. */
    const float *wp[ORR_PLANES_MAX];
    /* A block of the fused NGP gather (render/ngp_gather.h): its pixel
     * indices are in share_pixel. */
    int indexed;
    /* Motion blur: x, y, z hold where each streak starts and sx, sy, sz
     * the vector to its end (camera frame); the streaks' samples are
     * drawn from the buffers of *samples, a block at a time. */
    float sx[BLOCK], sy[BLOCK], sz[BLOCK];
    struct block_buffers *samples;
} block_buffers;

/* What one block added to the report, kept per block and summed in block
 * order, so the sums do not depend on which thread took which block. */
typedef struct block_tally {
    uint64_t n_selected, n_nonfinite, n_stereo_skipped;
    orr_deposit_stats deposit[2]; /* of the first two planes: the report's deposit and deposit_y */
} block_tally;

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
    orr_camera_transform t = orr_camera_transform_at(v->rep->camera.position, &v->world_to_camera, shift);
    if (fading) {
        const orr_replica_sphere *sp = &v->periodic.sphere;
        t.fade = 1;
        t.outer = (float)sp->radius;
        t.inner = (float)(sp->radius - sp->fade);
        t.inner2 = t.inner * t.inner;
        t.outer2 = t.outer * t.outer;
    }
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

/* The plane whose weights are checked for finiteness: the weight, or
 * with colour Z. */
static int checked_plane(const view_state *v)
{
    return v->nplanes >= 3 ? 2 : 0;
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
    /* Checked for finiteness: the weight, or with colour Z
     * (orr_population_assign already refuses a luminance or colour that is
     * not finite, so a particle's X, Y and Z, and its population's Y, are
     * finite together) */
    const float *wsrc = wsrcs[checked_plane(v)];
    const orr_scene *s = v->scene;
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
            h = glow_length(s, h, p.r2, wsrcs[v->nplanes >= 3 ? 1 : 0][i] * dimming);
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
    orr_deposit_stats st[ORR_PLANES_MAX];
    memset(st, 0, sizeof st);
    orr_ngp_batch nb = {n, b->share_pixel, b->px, b->py, {NULL}, v->nplanes, 0};
    for (int k = 0; k < v->nplanes; k++)
        nb.w[k] = b->wp[k];
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

/* Projects and deposits the ns samples gathered in sb; returns 0, the
 * samples left in it. */
static size_t draw_samples(const view_state *v, orr_plane *planes, int lane, size_t ns, block_buffers *sb,
                           block_tally *t)
{
    if (ns) {
        project_points(v, ns, sb, t);
        deposit_points(v, planes, lane, ns, sb, t);
    }
    return 0;
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
    for (int p = 0; p < ORR_PLANES_MAX; p++)
        sb->wp[p] = sb->w[p];
    size_t ns = 0;
    for (size_t i = 0; i < n; i++) {
        const float q0[3] = {b->x[i], b->y[i], b->z[i]}, sv[3] = {b->sx[i], b->sy[i], b->sz[i]};
        const int m = orr_motion_blur_samples(&v->blur, q0, sv);
        const float share = 1.0f / (float)m;
        for (int k = 0; k < m; k++) {
            if (ns == BLOCK)
                ns = draw_samples(v, planes, lane, ns, sb, t);
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
    draw_samples(v, planes, lane, ns, sb, t);
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

/* How many lanes the view splats in (reduce/lanes.h), for a source of
 * count particles (-1 when unknown). */
static int lanes_for(const view_state *v, int64_t count)
{
    int shares_per_particle = v->use_sph                                  ? 0
                              : v->scene->deposit == ORR_DEPOSIT_NGP ? 1
                                                                     : ORR_MAX_SHARES_PER_POINT;
    return orr_lanes_for(v->proj.width, v->proj.height, v->nplanes, shares_per_particle, count);
}

static orr_status alloc_lanes(view_state *v, int64_t count, orr_error *err)
{
    return orr_lanes_alloc(&v->lanes, lanes_for(v, count), v->nplanes, v->proj.width, v->proj.height, err);
}

/* The bands of a point deposit: a window of blocks of a chunk of up to
 * capacity particles, each block's shares in a region of its own. */
static orr_status alloc_bands(view_state *v, size_t capacity, orr_error *err)
{
    v->lanes.n = 1;
    size_t nblocks = (capacity + BLOCK - 1) / BLOCK;
    size_t window = nblocks < ORR_BAND_WINDOW_BLOCKS ? nblocks : ORR_BAND_WINDOW_BLOCKS;
    size_t per_point = v->scene->deposit == ORR_DEPOSIT_NGP ? 1 : ORR_MAX_SHARES_PER_POINT;
    size_t npix = (size_t)v->proj.width * (size_t)v->proj.height;
    return orr_bands_init(&v->bands, npix, v->nplanes, window ? window : 1, per_point * BLOCK, err);
}

void orr_splat_free_lanes(view_state *v)
{
    orr_lanes_free(&v->lanes);
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
    /* output.exr_population_layers: the planes after X, Y, Z (one Y per
     * population), and each particle's population; 0 and NULL without. */
    int npop_planes;
    int32_t *pop_of;
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
    orr_plane *planes = orr_lane_planes(&v->lanes, v->planes, lane);
    double at = orr_thread_cpu_seconds();
    for (size_t blk = (size_t)lane; blk < nblocks; blk += (size_t)v->lanes.n) {
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
    const int nlanes = v->lanes.n;
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
            orr_shares shares = {b->share_pixel, {NULL}, 0};
            for (int k = 0; k < v->nplanes; k++)
                shares.w[k] = b->share_w[k];
            if (b->indexed) {
                orr_ngp_batch nb = place_indexed(v, (size_t)n, b, t);
                orr_ngp_shares(&nb, &shares);
            } else {
                orr_deposit_stats st[ORR_PLANES_MAX];
                memset(st, 0, sizeof st);
                orr_point_batch pb = {(size_t)n, b->px, b->py, b->visible, {NULL}, v->nplanes};
                for (int k = 0; k < v->nplanes; k++)
                    pb.w[k] = b->wp[k];
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

/* Each particle's Y into its population's plane (xyz[3 + p]) and 0 into
 * the others', particles [start, start + count). A particle of no
 * population (pop < 0) has X = Y = Z = 0 and is in none. So the planes
 * sum, pixel by pixel, to the Y plane. */
static void split_y_by_population(float *const *xyz, int npop, const int32_t *pop, size_t start, size_t count)
{
    for (int p = 0; p < npop; p++) {
        const float *restrict y = xyz[1] + start;
        float *restrict out = xyz[3 + p] + start;
        for (size_t i = 0; i < count; i++)
            out[i] = pop[i] == p ? y[i] : 0.0f;
    }
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
        int32_t *pop = work->pop_of ? work->pop_of + start : NULL;
        st_part[part] = orr_population_assign_at(&s->populations, src->info.time, c, start, count, s->only, pop,
                                                 xyz[0] + start, xyz[1] + start, xyz[2] + start,
                                                 &work->lane_err[part]);
        if (pop && !st_part[part])
            split_y_by_population(xyz, work->npop_planes, pop, start, count);
    }
    for (int part = 0; part < MAX_LANES; part++)
        if (st_part[part]) {
            if (err)
                *err = work->lane_err[part];
            orr_fail_prefix(err, "%s: colour.populations: ", s->path);
            return st_part[part];
        }
    for (int k = 0; k < 3 + work->npop_planes; k++)
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
    const float *w[ORR_PLANES_MAX] = {NULL};
    orr_status st = chunk_weights(views[0].scene, src, c, xyz, w, work, err);
    charge(&views[0], ORR_STAGE_GATHER);
    memset(work->split, 0, sizeof work->split);
    for (int k = 0; k < nviews && !st; k++) {
        const float *wv[ORR_PLANES_MAX];
        memcpy(wv, w, sizeof wv);
        if (views[k].dust) { /* dimmed by the dust between the view's eye and each star (dust/dust.h) */
            const orr_mat3 *r = &views[k].world_to_camera; /* its third row: the view axis */
            orr_dust_eye eye = {views[k].rep->camera.position, views[k].proj.kind == ORR_PROJ_ORTHOGRAPHIC,
                                orr_v3(r->m[2][0], r->m[2][1], r->m[2][2])};
            st = orr_dust_weights(views[k].dust, &eye, c, wv, views[k].nplanes, err);
        }
        if (!st)
            st = views[k].periodic.active
                     ? splat_chunk_periodic(&views[k], src, c, wv, &work->buffers[0], work->split[0], err)
                     : splat_view(&views[k], src, c, wv, work, err);
    }
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

/* Room for a chunk's colour weights: X, Y, Z, and with population planes
 * (nplanes > 3) each population's Y and each particle's population. */
static orr_status alloc_colour_weights(splat_work *w, int nplanes, size_t cap, float **xyz, orr_error *err)
{
    for (int k = 0; k < nplanes; k++)
        if (!(xyz[k] = orr_malloc(cap * sizeof(float), "colour weights", err)))
            return ORR_ERR_NOMEM;
    w->npop_planes = nplanes - 3;
    if (w->npop_planes > 0 && !(w->pop_of = orr_malloc(cap * sizeof *w->pop_of, "colour populations", err)))
        return ORR_ERR_NOMEM;
    return ORR_OK;
}

static void free_work(splat_work *w)
{
    free(w->buffers);
    free(w->samples);
    free(w->lengths_first);
    free(w->tally);
    free(w->pop_of);
}

orr_status orr_splat_views(view_state *views, int nviews, orr_source *src, orr_progress_fn progress,
                               void *progress_user, orr_error *err)
{
    splat_work *work = orr_malloc(sizeof *work, "splat work", err);
    if (!work)
        return ORR_ERR_NOMEM;
    int blur = 0;
    for (int k = 0; k < nviews; k++)
        blur |= views[k].blur.active;
    orr_status st = alloc_work(work, src->chunk.capacity, blur, err);
    /* With colour, a chunk's X, Y, Z weights (and each population's Y). */
    float *xyz[ORR_PLANES_MAX] = {NULL};
    size_t cap = views[0].scene->colour ? src->chunk.capacity : 0;
    if (!st && cap)
        st = alloc_colour_weights(work, views[0].nplanes, cap, xyz, err);
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
            orr_lanes_merge(&views[k].lanes, views[k].planes,
                            (size_t)views[k].proj.width * (size_t)views[k].proj.height);
    }
    for (int k = 0; k < nviews && !st; k++)
        if (views[k].psf.sky)
            st = orr_sky_psf_select(views[k].psf.sky, err);
    charge(&views[0], ORR_STAGE_REDUCE);
    for (int k = 0; k < ORR_PLANES_MAX; k++)
        free(xyz[k]);
    free_work(work);
    free(work);
    return st;
}

/* How the view is splatted: in bands or lanes, and whether NGP blocks take
 * the fused gather. (A sky PSF collects its stars per lane: it keeps
 * lanes; streaks are drawn as their samples are made: in lanes.) */
void orr_splat_choose_path(view_state *v)
{
    const orr_scene *s = v->scene;
    v->banded = !v->use_sph && !v->psf.sky && !v->blur.active &&
                orr_lanes_use_bands((size_t)v->proj.width * (size_t)v->proj.height);
    v->ngp_fused = s->deposit == ORR_DEPOSIT_NGP && !v->use_sph && !v->psf.sky && !v->use_ods && !v->blur.active;
}
