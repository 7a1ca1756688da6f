/* The wide glows on coarser copies of a sky map (view_state.h,
 * "coarse_glow"). A glow many pixels wide (the faint stars a nearby
 * particle leaves, stars.*; the glow of a near particle) covers thousands
 * to hundreds of thousands of a dome master's pixels, yet varies over few
 * of them: drawn on a map F times coarser each way, it costs F^2 less, and
 * the coarse map's surface brightness, interpolated, is added to every
 * pixel of the view once a frame. Each kernel goes to the coarsest map on
 * which its h still spans MIN_COARSE_PIXELS pixels. A coarse map is the
 * same projection at 1/F of the size, so a point's coarse pixel
 * coordinates are its fine ones over F; each lane draws into planes of its
 * own, added in lane order, so the result does not depend on the threads. */
#include "render/splat_block.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Fine pixels per coarse pixel, each way, coarsest first: a 3600^2 dome
 * master's widest glows on a 450^2 map (0.4 degrees a pixel), the next
 * on a 900^2 one. */
static const int FACTORS[ORR_COARSE_LEVELS] = {8, 4};
/* Kernels whose h spans this many coarse pixels or more go coarse: their
 * support (2h) is then 8 coarse pixels across or more, sampled finely
 * enough that interpolating the coarse map is smooth to the eye. */
#define MIN_COARSE_PIXELS 2.0f

static void free_level(coarse_level *l)
{
    for (int lane = 0; lane < ORR_MAX_LANES; lane++)
        for (int k = 0; k < 3; k++)
            orr_plane_free(&l->planes[lane][k]);
    if (l->sph_ready)
        orr_sph_free(&l->sph);
    free(l->reach);
    free(l->col0);
    free(l->col_a);
}

void orr_coarse_glow_free(view_state *v)
{
    coarse_glow *g = v->coarse;
    if (!g)
        return;
    for (int k = 0; k < g->nlevels; k++)
        free_level(&g->level[k]);
    free(g->buffers);
    free(g);
    v->coarse = NULL;
}

/* Where fine coordinate x (pixel centres at k + 0.5) falls between the
 * centres of a coarse map n pixels wide: the lower index and the upper
 * one's weight, clamped at the edges. */
static int coarse_between(int k, int factor, int n, float *a)
{
    double u = (k + 0.5) / factor - 0.5;
    u = u < 0 ? 0 : u > n - 1 ? n - 1 : u;
    int i0 = (int)u;
    if (i0 > n - 2)
        i0 = n > 1 ? n - 2 : 0;
    *a = (float)(u - i0);
    return i0;
}

/* The fine map's measure (solid angle) each coarse pixel's unit of
 * brightness reaches through the interpolation, summed over the fine
 * pixels on the map: what the coarse plane gives the fine one is then its
 * brightness dotted with these, without a pass over the fine map. Each
 * coarse row is summed by one thread in fine-row order: the same bits on
 * any number of threads. */
static orr_status level_reach(const view_state *v, coarse_level *l, orr_error *err)
{
    const int cw = l->proj.width, ch = l->proj.height, W = v->proj.width, H = v->proj.height, F = l->factor;
    l->reach = orr_calloc((size_t)cw * ch, sizeof *l->reach, "coarse glow", err);
    l->col0 = orr_malloc(sizeof *l->col0 * (size_t)W, "coarse glow", err);
    l->col_a = orr_malloc(sizeof *l->col_a * (size_t)W, "coarse glow", err);
    if (!l->reach || !l->col0 || !l->col_a)
        return ORR_ERR_NOMEM;
    for (int i = 0; i < W; i++)
        l->col0[i] = coarse_between(i, F, cw, &l->col_a[i]);
    int fail = 0;
#pragma omp parallel
    {
        double *measure = malloc(sizeof *measure * (size_t)W);
#pragma omp for schedule(dynamic, 4)
        for (int t = 0; t < ch; t++) {
            if (!measure) {
#pragma omp atomic write
                fail = 1;
                continue;
            }
            double *out = l->reach + (size_t)t * cw;
            /* The fine rows whose interpolation reads coarse row t. */
            int j_lo = (t - 1) * F, j_hi = (t + 2) * F;
            for (int j = j_lo < 0 ? 0 : j_lo; j < H && j < j_hi; j++) {
                float c;
                int t0 = coarse_between(j, F, ch, &c);
                double row_w = t0 == t ? 1.0 - c : t0 + 1 == t ? c : 0.0;
                if (row_w == 0.0)
                    continue;
                orr_pixel_measure_row(&v->proj, j, measure);
                for (int i = 0; i < W; i++)
                    if (measure[i] > 0) {
                        double m = row_w * measure[i];
                        out[l->col0[i]] += m * (1.0 - l->col_a[i]);
                        out[l->col0[i] + 1] += m * l->col_a[i];
                    }
            }
        }
        free(measure);
    }
    return fail ? orr_fail(err, ORR_ERR_NOMEM, "out of memory for the coarse glow of a %d x %d map", W, H) : ORR_OK;
}

static orr_status plan_level(view_state *v, coarse_level *l, int factor, orr_error *err)
{
    l->factor = factor;
    l->proj = v->base_proj;
    l->proj.width = v->base_proj.width / factor;
    l->proj.height = v->base_proj.height / factor;
    orr_status st = orr_projection_setup(&l->proj, err);
    if (!st && !(st = orr_sph_init(&l->sph, &v->kernel, &l->proj, err)))
        l->sph_ready = 1;
    for (int lane = 0; lane < ORR_MAX_LANES && !st; lane++)
        for (int k = 0; k < 3 && !st; k++)
            st = orr_plane_alloc(&l->planes[lane][k], l->proj.width, l->proj.height, "glow", "", err);
    return st ? st : level_reach(v, l, err);
}

orr_status orr_coarse_glow_plan(view_state *v, orr_error *err)
{
    const orr_projection_traits traits = orr_projection_traits_of(v->base_proj.kind);
    const int w = v->base_proj.width, h = v->base_proj.height;
    /* Sky maps in colour that glow with the kernel deposit, no stereo eye;
     * the levels that divide the map and leave it 8 coarse pixels across
     * or more. Else the view draws every glow itself. */
    if (!traits.sky || traits.pixel_table || !v->use_sph || v->nplanes != 3 || v->scene->stereo.mode)
        return ORR_OK;
    int factors[ORR_COARSE_LEVELS], n = 0;
    for (int k = 0; k < ORR_COARSE_LEVELS; k++)
        if (w % FACTORS[k] == 0 && h % FACTORS[k] == 0 && w / FACTORS[k] >= 8 && h / FACTORS[k] >= 8)
            factors[n++] = FACTORS[k];
    if (!n)
        return ORR_OK;
    coarse_glow *g = orr_calloc(1, sizeof *g, "coarse glow", err);
    if (!g)
        return ORR_ERR_NOMEM;
    v->coarse = g;
    orr_status st = ORR_OK;
    for (int k = 0; k < n && !st; k++, g->nlevels++)
        st = plan_level(v, &g->level[k], factors[k], err);
    if (!st && !(g->buffers = orr_malloc(ORR_MAX_LANES * sizeof *g->buffers, "coarse glow blocks", err)))
        st = ORR_ERR_NOMEM;
    if (st)
        orr_coarse_glow_free(v);
    return st;
}

void orr_coarse_glow_begin(view_state *v)
{
    coarse_glow *g = v->coarse;
    if (!g)
        return;
    for (int L = 0; L < g->nlevels; L++) {
        coarse_level *l = &g->level[L];
        const size_t npix = (size_t)l->proj.width * l->proj.height;
        for (int lane = 0; lane < ORR_MAX_LANES; lane++)
            for (int k = 0; k < 3; k++)
                memset(l->planes[lane][k].data, 0, npix * sizeof(float));
    }
}

/* Moves the block's kernels wide enough for level l (visible, h at least
 * MIN_COARSE_PIXELS of its pixels) into cb, in its pixel coordinates, and
 * out of b (not visible there); returns how many, and adds the weight of
 * each plane moved. */
static size_t take_wide(const view_state *v, const coarse_level *l, size_t n, block_buffers *b, block_buffers *cb,
                        double *moved)
{
    const float f = 1.0f / l->factor, min_hpix = MIN_COARSE_PIXELS * l->factor;
    size_t m = 0;
    for (size_t i = 0; i < n; i++) {
        if (!b->visible[i] || !(b->h[i] * b->scale[i] >= min_hpix))
            continue;
        cb->x[m] = b->x[i], cb->y[m] = b->y[i], cb->z[m] = b->z[i], cb->h[m] = b->h[i];
        cb->px[m] = b->px[i] * f, cb->py[m] = b->py[i] * f, cb->scale[m] = b->scale[i] * f;
        cb->visible[m] = 1;
        for (int k = 0; k < v->nplanes; k++) {
            cb->w[k][m] = b->wp[k][i];
            moved[k] += b->wp[k][i];
        }
        b->visible[i] = 0;
        m++;
    }
    return m;
}

size_t orr_coarse_glow_split(const view_state *v, int lane, size_t n, block_buffers *b, orr_deposit_stats *coarse,
                             double *moved)
{
    coarse_glow *g = v->coarse;
    block_buffers *cb = &g->buffers[lane];
    for (int k = 0; k < v->nplanes; k++)
        moved[k] = 0.0;
    size_t taken = 0;
    for (int L = 0; L < g->nlevels; L++) { /* coarsest first: each kernel to the coarsest that suits it */
        coarse_level *l = &g->level[L];
        size_t m = take_wide(v, l, n, b, cb, moved);
        if (!m)
            continue;
        const orr_sph_block geom = {m, cb->x, cb->y, cb->z, cb->px, cb->py, cb->scale, cb->visible, cb->h, NULL};
        const float *w[3] = {cb->w[0], cb->w[1], cb->w[2]};
        orr_sph_deposit_planes(&l->sph, &geom, w, l->planes[lane], v->nplanes, coarse);
        taken += m;
    }
    return taken;
}

/* Level l's plane k as surface brightness, scaled so that the fine map
 * gets the coarse plane's weight exactly (the lanes' planes added first,
 * in lane order). Returns NULL without memory. */
static float *level_brightness(coarse_level *l, int k)
{
    const int w = l->proj.width, h = l->proj.height;
    const size_t npix = (size_t)w * h;
    orr_plane *sum = &l->planes[0][k];
    for (int lane = 1; lane < ORR_MAX_LANES; lane++)
        for (size_t p = 0; p < npix; p++)
            sum->data[p] += l->planes[lane][k].data[p];
    float *sb = malloc(npix * sizeof *sb);
    if (!sb)
        return NULL;
    double want = 0.0, got = 0.0;
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            const size_t p = (size_t)j * w + i;
            double m = orr_pixel_measure(&l->proj, i, j);
            sb[p] = m > 0 ? (float)(sum->data[p] / m) : 0.0f;
            want += sum->data[p];
            got += sb[p] * l->reach[p];
        }
    const float scale = got > 0 ? (float)(want / got) : 0.0f;
    for (size_t p = 0; p < npix; p++)
        sb[p] *= scale;
    return sb;
}

/* Level l's brightness sb at the centres of fine row j, bilinear. */
static void level_row(const coarse_level *l, const float *sb, int j, int W, float *out)
{
    float c;
    const int t0 = coarse_between(j, l->factor, l->proj.height, &c), cw = l->proj.width;
    const float *r0 = sb + (size_t)t0 * cw, *r1 = r0 + (l->proj.height > 1 ? cw : 0);
    for (int i = 0; i < W; i++) {
        const int i0 = l->col0[i], i1 = cw > 1 ? i0 + 1 : i0;
        const float a = l->col_a[i];
        out[i] += (1 - c) * ((1 - a) * r0[i0] + a * r0[i1]) + c * ((1 - a) * r1[i0] + a * r1[i1]);
    }
}

/* Adds every level's plane k to the view's plane: each fine pixel on the
 * map its measure times the levels' interpolated brightness. */
static orr_status add_plane(view_state *v, int k, orr_error *err)
{
    coarse_glow *g = v->coarse;
    const int W = v->proj.width, H = v->proj.height;
    float *sb[ORR_COARSE_LEVELS] = {NULL};
    int fail = 0;
    for (int L = 0; L < g->nlevels; L++)
        fail |= !(sb[L] = level_brightness(&g->level[L], k));
    float *fine = v->planes[k].data;
    if (!fail)
#pragma omp parallel
    {
        double *measure = malloc(sizeof *measure * (size_t)W);
        float *row = malloc(sizeof *row * (size_t)W);
#pragma omp for schedule(static)
        for (int j = 0; j < H; j++) {
            if (!measure || !row) {
#pragma omp atomic write
                fail = 1;
                continue;
            }
            orr_pixel_measure_row(&v->proj, j, measure);
            memset(row, 0, sizeof *row * (size_t)W);
            for (int L = 0; L < g->nlevels; L++)
                level_row(&g->level[L], sb[L], j, W, row);
            for (int i = 0; i < W; i++)
                if (measure[i] > 0)
                    fine[(size_t)j * W + i] += (float)(measure[i] * row[i]);
        }
        free(measure);
        free(row);
    }
    for (int L = 0; L < g->nlevels; L++)
        free(sb[L]);
    return fail ? orr_fail(err, ORR_ERR_NOMEM, "out of memory for the coarse glow of a %d x %d map", W, H) : ORR_OK;
}

orr_status orr_coarse_glow_finish(view_state *v, orr_error *err)
{
    if (!v->coarse)
        return ORR_OK;
    orr_status st = ORR_OK;
    for (int k = 0; k < v->nplanes && !st; k++)
        st = add_plane(v, k, err);
    return st;
}
