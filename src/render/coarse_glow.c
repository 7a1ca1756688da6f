/* The widest glows on a coarser copy of a sky map (view_state.h,
 * "coarse_glow"). A glow tens of degrees wide (the faint stars a nearby
 * particle leaves, stars.*) covers hundreds of thousands of a dome
 * master's pixels, yet varies over none of them: drawn on a map FACTOR
 * times coarser each way, it costs FACTOR^2 less, and the coarse map's
 * surface brightness, interpolated, is added to every pixel of the view
 * once a frame. The coarse map is the same projection at 1/FACTOR of the
 * size, so a point's coarse pixel coordinates are its fine ones over
 * FACTOR; each lane draws into planes of its own, added in lane order, so
 * the result does not depend on the threads. */
#include "render/splat_block.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Fine pixels per coarse pixel, each way: a 3600^2 dome master's glows on
 * a 450^2 map, 0.4 degrees a pixel. */
#define FACTOR 8
/* Kernels whose h spans this many coarse pixels or more go coarse: their
 * support (2h) is then 8 coarse pixels across or more, sampled finely
 * enough that interpolating the coarse map is smooth to the eye. */
#define MIN_COARSE_PIXELS 2.0f

static void free_planes(coarse_glow *g)
{
    for (int lane = 0; lane < ORR_MAX_LANES; lane++)
        for (int k = 0; k < 3; k++)
            orr_plane_free(&g->planes[lane][k]);
}

void orr_coarse_glow_free(view_state *v)
{
    coarse_glow *g = v->coarse;
    if (!g)
        return;
    free_planes(g);
    if (g->sph_ready)
        orr_sph_free(&g->sph);
    free(g->buffers);
    free(g);
    v->coarse = NULL;
}

orr_status orr_coarse_glow_plan(view_state *v, orr_error *err)
{
    const orr_projection_traits traits = orr_projection_traits_of(v->base_proj.kind);
    const int w = v->base_proj.width, h = v->base_proj.height;
    /* Sky maps in colour that glow with the kernel deposit, no stereo eye,
     * at least 8 coarse pixels across; else the view draws every glow
     * itself. */
    if (!traits.sky || traits.pixel_table || !v->use_sph || v->nplanes != 3 || v->scene->stereo.mode ||
        w % FACTOR || h % FACTOR || w / FACTOR < 8 || h / FACTOR < 8)
        return ORR_OK;
    coarse_glow *g = orr_calloc(1, sizeof *g, "coarse glow", err);
    if (!g)
        return ORR_ERR_NOMEM;
    v->coarse = g;
    g->proj = v->base_proj;
    g->proj.width = w / FACTOR;
    g->proj.height = h / FACTOR;
    orr_status st = orr_projection_setup(&g->proj, err);
    if (!st && !(st = orr_sph_init(&g->sph, &v->kernel, &g->proj, err)))
        g->sph_ready = 1;
    for (int lane = 0; lane < ORR_MAX_LANES && !st; lane++)
        for (int k = 0; k < 3 && !st; k++)
            st = orr_plane_alloc(&g->planes[lane][k], g->proj.width, g->proj.height, "glow", "", err);
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
    const size_t npix = (size_t)g->proj.width * g->proj.height;
    for (int lane = 0; lane < ORR_MAX_LANES; lane++)
        for (int k = 0; k < 3; k++)
            memset(g->planes[lane][k].data, 0, npix * sizeof(float));
}

/* Moves the block's wide kernels (visible, h at least MIN_COARSE_PIXELS
 * coarse pixels) into cb, in coarse pixel coordinates, and out of b (not
 * visible there); returns how many, and the weight of each plane moved. */
static size_t take_wide(const view_state *v, size_t n, block_buffers *b, block_buffers *cb, double *moved)
{
    const float f = 1.0f / FACTOR, min_hpix = MIN_COARSE_PIXELS * FACTOR;
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
    size_t m = take_wide(v, n, b, cb, moved);
    if (!m)
        return 0;
    const orr_sph_block geom = {m, cb->x, cb->y, cb->z, cb->px, cb->py, cb->scale, cb->visible, cb->h, NULL};
    const float *w[3] = {cb->w[0], cb->w[1], cb->w[2]};
    orr_sph_deposit_planes(&g->sph, &geom, w, g->planes[lane], v->nplanes, coarse);
    return m;
}

/* Coarse pixel (i, j)'s surface brightness: its weight over its solid
 * angle (0 off the map). */
static float *coarse_brightness(const coarse_glow *g, const orr_plane *p)
{
    const int w = g->proj.width, h = g->proj.height;
    float *sb = malloc((size_t)w * h * sizeof *sb);
    if (!sb)
        return NULL;
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            double m = orr_pixel_measure(&g->proj, i, j);
            sb[(size_t)j * w + i] = m > 0 ? (float)(p->data[(size_t)j * w + i] / m) : 0.0f;
        }
    return sb;
}

/* The coarse brightness at fine pixel (i, j)'s centre, bilinear. */
static double interpolated(const float *sb, int w, int h, int i, int j)
{
    double u = (i + 0.5) / FACTOR - 0.5, t = (j + 0.5) / FACTOR - 0.5;
    u = u < 0 ? 0 : u > w - 1 ? w - 1 : u;
    t = t < 0 ? 0 : t > h - 1 ? h - 1 : t;
    int i0 = (int)u, j0 = (int)t, i1 = i0 + 1 < w ? i0 + 1 : i0, j1 = j0 + 1 < h ? j0 + 1 : j0;
    double a = u - i0, c = t - j0;
    const float *r0 = sb + (size_t)j0 * w, *r1 = sb + (size_t)j1 * w;
    return (1 - c) * ((1 - a) * r0[i0] + a * r0[i1]) + c * ((1 - a) * r1[i0] + a * r1[i1]);
}

/* Adds the coarse plane to the view's plane: each fine pixel its solid
 * angle times the coarse brightness there, scaled so the view gets the
 * coarse plane's weight exactly. */
static orr_status add_plane(const view_state *v, const orr_plane *coarse, orr_plane *fine, orr_error *err)
{
    const coarse_glow *g = v->coarse;
    const int cw = g->proj.width, ch = g->proj.height, W = v->proj.width, H = v->proj.height;
    float *sb = coarse_brightness(g, coarse);
    double *row_sum = calloc((size_t)H, sizeof *row_sum), *measure = malloc((size_t)W * H * sizeof *measure);
    if (!sb || !row_sum || !measure) {
        free(sb), free(row_sum), free(measure);
        return orr_fail(err, ORR_ERR_NOMEM, "out of memory for the coarse glow of a %d x %d map", W, H);
    }
    double want = 0.0;
    for (size_t k = 0; k < (size_t)cw * ch; k++)
        want += coarse->data[k];
#pragma omp parallel for schedule(static)
    for (int j = 0; j < H; j++) {
        orr_pixel_measure_row(&v->proj, j, measure + (size_t)j * W);
        double s = 0.0;
        for (int i = 0; i < W; i++) {
            double m = measure[(size_t)j * W + i];
            s += m > 0 ? m * interpolated(sb, cw, ch, i, j) : 0.0;
        }
        row_sum[j] = s;
    }
    double got = 0.0;
    for (int j = 0; j < H; j++)
        got += row_sum[j];
    const double scale = got > 0 ? want / got : 0.0;
#pragma omp parallel for schedule(static)
    for (int j = 0; j < H; j++)
        for (int i = 0; i < W; i++) {
            double m = measure[(size_t)j * W + i];
            if (m > 0)
                fine->data[(size_t)j * W + i] += (float)(scale * m * interpolated(sb, cw, ch, i, j));
        }
    free(sb), free(row_sum), free(measure);
    return ORR_OK;
}

orr_status orr_coarse_glow_finish(view_state *v, orr_error *err)
{
    coarse_glow *g = v->coarse;
    if (!g)
        return ORR_OK;
    const size_t npix = (size_t)g->proj.width * g->proj.height;
    for (int k = 0; k < v->nplanes; k++) {
        /* The lanes' planes, added in lane order. */
        for (int lane = 1; lane < ORR_MAX_LANES; lane++)
            for (size_t p = 0; p < npix; p++)
                g->planes[0][k].data[p] += g->planes[lane][k].data[p];
        orr_status st = add_plane(v, &g->planes[0][k], &v->planes[k], err);
        if (st)
            return st;
    }
    return ORR_OK;
}
