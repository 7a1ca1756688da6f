/* The splat's deposit: a gathered, projected block into a lane's planes,
 * as points (NGP, CIC, SPH kernels; a sky map's PSF widening the kernels
 * and collecting its brightest stars), as motion blur's streaks, or as
 * the fused gather's pixel indices; and what each block adds to the
 * tally. */
#include "pass/splat_block.h"

#include <math.h>
#include <string.h>

#include "pass/motion_blur.h"
#include "post/view_psf.h"
#include "splat/sph.h"

/* The PSF's widening is planned here (orr_splat_plan_kernels), read here
 * (orr_splat_can_cull) and applied here, each frame (widen_for_psf). */

orr_status orr_splat_plan_kernels(orr_splat_view *v, orr_error *err)
{
    const int widens = v->psf.h_per_r > 0;
    v->use_sph = v->splat.deposit.kind == ORR_DEPOSIT_SPH || widens;
    if (!v->use_sph)
        return ORR_OK;
    orr_status st = orr_sph_init(&v->sph, &v->kernel, &v->proj, err);
    v->sph_ready = !st;
    /* Stars are drawn from stamps: widen_for_psf gives a star without a
     * length of its own h = k r, k the float of h_per_r: its angle h / r. */
    if (!st && widens)
        st = orr_sph_use_cores(&v->sph, (float)v->psf.h_per_r, err);
    return st;
}

int orr_splat_can_cull(const orr_splat_view *v)
{
    return !v->use_ods && !(v->psf.h_per_r > 0) && !v->splat.dims_from_observer;
}

/* A sky map's PSF widens every particle's kernel to the PSF's angular size
 * (in quadrature with its own smoothing length). */
static void widen_for_psf(const orr_splat_view *v, size_t n, block_buffers *b)
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
orr_ngp_batch orr_splat_place_indexed(const orr_splat_view *v, size_t n, block_buffers *b, block_tally *t)
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

static void add_stats(orr_deposit_stats *to, const orr_deposit_stats *from)
{
    to->deposited += from->deposited;
    to->outside += from->outside;
    to->culled += from->culled;
    to->n_particles += from->n_particles;
    to->n_culled += from->n_culled;
}

/* Deposits the block's n projected points into planes (a lane's: the
 * view's own or a private copy). The report's statistics are of the first
 * plane's weights (with colour, X; Y's are in the FITS header). */
static void deposit_points(const orr_splat_view *v, orr_plane *planes, int lane, size_t n, block_buffers *b,
                           block_tally *t)
{
    const orr_sph_block geom = {n, b->x, b->y, b->z, b->px, b->py, b->scale, b->visible, b->h, NULL};
    if (v->use_sph) {
        widen_for_psf(v, n, b);
        orr_deposit_stats st[ORR_PLANES_MAX], coarse[ORR_PLANES_MAX];
        double moved[ORR_PLANES_MAX];
        memset(st, 0, sizeof st);
        memset(coarse, 0, sizeof coarse);
        size_t wide = v->coarse ? orr_coarse_glow_split(v, lane, n, b, coarse, moved) : 0;
        orr_sph_deposit_planes(&v->sph, &geom, b->wp, planes, v->nplanes, st);
        for (int k = 0; k < v->nplanes && k < 2; k++) { /* (each a sum onto zeros: the same bits) */
            if (wide) { /* drawn on the coarse map, not culled */
                st[k].culled -= moved[k];
                st[k].n_culled -= wide;
                st[k].n_particles -= wide;
                add_stats(&st[k], &coarse[k]);
            }
            add_stats(&t->deposit[k], &st[k]);
        }
    } else {
        for (int k = 0; k < v->nplanes; k++) {
            orr_deposit_stats scratch = {0};
            orr_deposit_stats *st = k < 2 ? &t->deposit[k] : &scratch;
            orr_deposit(v->splat.deposit.kind, &planes[k], n, b->px, b->py, b->wp[k], b->visible, &v->proj, st);
        }
    }
    /* A sky map's hst/file PSF: the brightest stars are redrawn with the
     * whole PSF after the splat (post/sky_psf.h). */
    if (v->psf.sky)
        orr_sky_psf_collect(v->psf.sky, lane, &geom, b->wp, v->nplanes);
}

/* Projects and deposits the ns samples gathered in sb; returns 0, the
 * samples left in it. */
static size_t draw_samples(const orr_splat_view *v, orr_plane *planes, int lane, size_t ns, block_buffers *sb,
                           block_tally *t)
{
    if (ns) {
        orr_splat_project_points(v, ns, sb, t);
        deposit_points(v, planes, lane, ns, sb, t);
    }
    return 0;
}

/* Deposits the streaks of the block's n particles: each as its samples
 * (orr_motion_blur_samples of them, at the midpoints of equal steps along
 * the streak, each with an equal share of the weight and the particle's
 * smoothing length), projected and deposited a block of samples at a
 * time. */
static void deposit_streaks(const orr_splat_view *v, orr_plane *planes, int lane, size_t n, block_buffers *b,
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
void orr_splat_deposit_block(const orr_splat_view *v, orr_plane *planes, int lane, size_t n, block_buffers *b,
                             block_tally *t)
{
    if (b->indexed) {
        orr_ngp_batch nb = orr_splat_place_indexed(v, n, b, t);
        orr_ngp_add(&nb, planes);
    } else if (v->blur.active) {
        deposit_streaks(v, planes, lane, n, b, t);
    } else {
        deposit_points(v, planes, lane, n, b, t);
    }
}

/* Adds what one block added to the view's tally. */
void orr_splat_add_tally(orr_splat_tally *r, const block_tally *t)
{
    r->n_selected += t->n_selected;
    r->n_nonfinite += t->n_nonfinite;
    r->n_stereo_skipped += t->n_stereo_skipped;
    add_stats(&r->deposit, &t->deposit[0]);
    add_stats(&r->deposit_y, &t->deposit[1]);
}
