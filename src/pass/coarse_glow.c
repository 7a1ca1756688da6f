/* The wide glows on coarser copies of a sky map (splat_view.h,
 * "coarse_glow"). A glow many pixels wide (the faint stars a nearby
 * particle leaves, stars.*; the glow of a near particle) covers thousands
 * to hundreds of thousands of a dome master's pixels, yet varies over few
 * of them: drawn on a map F times coarser each way, it costs F^2 less, and
 * the coarse map's surface brightness, interpolated, is added to every
 * pixel of the view once a frame. Each kernel goes to the coarsest map on
 * which its h still spans MIN_PIXELS of its pixels. A coarse map is the
 * same projection at 1/F of the size, so a point's coarse pixel
 * coordinates are its fine ones over F; each lane draws into planes of its
 * own, added in lane order, so the result does not depend on the threads. */
#include "pass/splat_block.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Fine pixels per coarse pixel, each way, coarsest first (the ones that
 * divide the map): a 3600^2 dome master's widest glows on a 225^2 map
 * (0.8 degrees a pixel), the next on 450^2 and 900^2 ones. */
static const int FACTORS[ORR_COARSE_LEVELS] = {32, 16, 8, 4};
/* The narrowest kernel each level takes, h in its pixels. At 2 a
 * kernel's support (2h) is 8 coarse pixels across or more, sampled finely
 * enough that interpolating the coarse map is smooth to the eye; the two
 * coarsest maps take only the widest glows (16: a 3600^2 dome master's
 * kernels of 13 degrees and more), which on the 8-times map cover tens of
 * thousands of pixels each and are mapped pixel by pixel (too wide for the
 * local affine model). */
static const float MIN_PIXELS[ORR_COARSE_LEVELS] = {16, 16, 2, 2};
/* The most a level's planes may take (every lane's): a 3600^2 dome
 * master's 4-times map takes 39 MB, an 8192^2 one's would take 201 MB,
 * which the 8K frame's memory goal (2 GB) has no room for; there the
 * glows of 8 to 16 pixels stay on the view's own map. */
#define MAX_LEVEL_BYTES ((size_t)64 << 20)

static void free_level(coarse_level *l)
{
    for (int lane = 0; lane < ORR_MAX_LANES; lane++)
        for (int k = 0; k < 3; k++)
            orr_plane_free(&l->planes[lane][k]);
    if (l->sph_ready)
        orr_sph_free(&l->sph);
    free(l->col0);
    free(l->col_a);
    free(l->on_map);
    free(l->norm);
}

void orr_coarse_glow_free(orr_splat_view *v)
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

/* The end of the run of fine columns from i, before `to`, that share
 * their left coarse column. */
static int column_run_end(const coarse_level *l, int i, int to)
{
    const int i0 = l->col0[i];
    int end = i + 1;
    while (end < to && l->col0[end] == i0)
        end++;
    return end;
}

/* A fine row's pixels on the map, [i0, i1): only they take light (off the
 * map it would be lost), so the passes over the fine map visit only them:
 * a dome master's corners, a fifth of its pixels, cost neither a measure
 * (a sine) nor an on-map test each. */
typedef struct fine_span {
    int i0, i1;
} fine_span;

/* Fine row j's span on the map and the measures of its pixels, m[i] for i
 * in the span. */
static fine_span map_measure_row(const orr_projection *p, int j, double *m)
{
    fine_span s;
    orr_projection_row_in_map(p, j, &s.i0, &s.i1);
    orr_pixel_measure_span(p, j, s.i0, s.i1, m);
    return s;
}

/* The fine rows read together when the levels' reach is summed: a
 * multiple of every factor, so a band's rows feed whole coarse rows. */
#define BAND_ROWS 32

/* Adds fine row j (its measure m over span s) to what it reaches on level
 * l, into out, whose first row is coarse row t_first. */
static void reach_row(const coarse_level *l, int j, const double *m, fine_span sp, double *out, int t_first)
{
    float c;
    const int cw = l->proj.width, t0 = coarse_between(j, l->factor, l->proj.height, &c);
    double *r0 = out + (size_t)(t0 - t_first) * cw, *r1 = r0 + cw;
    /* A run of fine columns between the same two coarse ones adds to the
     * same four sums, kept in registers over the run: each sum takes the
     * same terms in the same order, so the same bits. (A level is at least
     * 8 coarse pixels each way, orr_coarse_glow_plan: the four are
     * distinct.) */
    for (int i = sp.i0; i < sp.i1;) {
        const int i0 = l->col0[i], end = column_run_end(l, i, sp.i1);
        double s00 = r0[i0], s01 = r0[i0 + 1], s10 = r1[i0], s11 = r1[i0 + 1];
        for (int k = i; k < end; k++)
            if (m[k] > 0) {
                const double a = l->col_a[k], lo = m[k] * (1.0 - c), hi = m[k] * c;
                s00 += lo * (1.0 - a), s01 += lo * a;
                s10 += hi * (1.0 - a), s11 += hi * a;
            }
        r0[i0] = s00, r0[i0 + 1] = s01, r1[i0] = s10, r1[i0 + 1] = s11;
        i = end;
    }
}

/* The coarse rows a band of fine rows reaches on level l: [*first, last]. */
static int band_rows(const coarse_level *l, int j0, int j1, int *first)
{
    float c;
    *first = coarse_between(j0, l->factor, l->proj.height, &c);
    int last = coarse_between(j1 - 1, l->factor, l->proj.height, &c) + 1;
    return (last < l->proj.height ? last : l->proj.height - 1) - *first + 1;
}

/* Fine row j (its measures m over span sp), of the band of rows [j0, j1),
 * into that band's partial sums `out`, every level's. */
static void reach_band_row(const coarse_glow *g, int j0, int j1, int j, const double *m, fine_span sp, double *out)
{
    for (int L = 0; L < g->nlevels; L++) {
        const coarse_level *l = &g->level[L];
        int first;
        band_rows(l, j0, j1, &first);
        reach_row(l, j, m, sp, out, first);
        out += (size_t)(BAND_ROWS / l->factor + 2) * l->proj.width;
    }
}

/* Band b of fine rows into its partial sums, each row's measures found
 * into rows (BAND_ROWS rows of the width) and kept there. */
static void reach_band(const orr_projection *p, const coarse_glow *g, int b, double *rows, double *out)
{
    const int W = p->width, j0 = b * BAND_ROWS, j1 = j0 + BAND_ROWS < p->height ? j0 + BAND_ROWS : p->height;
    for (int j = j0; j < j1; j++) {
        double *m = rows + (size_t)(j - j0) * W;
        reach_band_row(g, j0, j1, j, m, map_measure_row(p, j, m), out);
    }
}

/* Band b's mirror band (rows H - 1 - j of band b's, in the order of their
 * own rows) from the measures reach_band left in rows: a dome's mirror rows
 * have the same measures bit for bit (orr_pixel_measure_twin_row), so the
 * sines of half the map's rows are not computed again. */
static void reach_mirror_band(const orr_projection *p, const coarse_glow *g, int b, double *rows, double *out)
{
    const int W = p->width, H = p->height, j0 = H - (b + 1) * BAND_ROWS, j1 = j0 + BAND_ROWS;
    for (int j = j0; j < j1; j++) {
        const int twin = H - 1 - j;
        double *m = rows + (size_t)(twin - b * BAND_ROWS) * W;
        fine_span sp;
        orr_projection_row_in_map(p, j, &sp.i0, &sp.i1);
        fine_span tw;
        orr_projection_row_in_map(p, twin, &tw.i0, &tw.i1);
        if (sp.i0 != tw.i0 || sp.i1 != tw.i1) /* (mirror rows: never, but then its own measures) */
            sp = map_measure_row(p, j, m);
        reach_band_row(g, j0, j1, j, m, sp, out);
    }
}

/* Whether the bands of fine rows come in mirror pairs (band b and
 * nbands - 1 - b, row j and H - 1 - j) whose rows share their measures. */
static int bands_mirror(const orr_projection *p)
{
    return p->height % BAND_ROWS == 0 && p->height >= 2 && orr_pixel_measure_twin_row(p, 0) == p->height - 1;
}

/* The fine map's measure (solid angle) each coarse pixel's unit of
 * brightness reaches through the interpolation, summed over the fine
 * pixels on the map, for every level at once, into its norm (level_norm
 * then adds the off-map neighbours' shares), found once a run, so each
 * frame's brightness needs no pass over the fine map to keep the light.
 * Each band of fine rows is summed by one thread into
 * its own rows, and the bands are added in order: the same bits on any
 * number of threads. */
static orr_status levels_reach(const orr_splat_view *v, coarse_glow *g, orr_error *err)
{
    const int W = v->proj.width, H = v->proj.height, nbands = (H + BAND_ROWS - 1) / BAND_ROWS;
    size_t per_band = 0; /* doubles a band's partial sums take, every level */
    for (int L = 0; L < g->nlevels; L++) {
        coarse_level *l = &g->level[L];
        l->norm = orr_calloc((size_t)l->proj.width * l->proj.height, sizeof *l->norm, "coarse glow", err);
        l->col0 = orr_malloc(sizeof *l->col0 * (size_t)W, "coarse glow", err);
        l->col_a = orr_malloc(sizeof *l->col_a * (size_t)W, "coarse glow", err);
        if (!l->norm || !l->col0 || !l->col_a)
            return ORR_ERR_NOMEM;
        for (int i = 0; i < W; i++)
            l->col0[i] = coarse_between(i, l->factor, l->proj.width, &l->col_a[i]);
        per_band += (size_t)(BAND_ROWS / l->factor + 2) * l->proj.width;
    }
    double *partial = orr_calloc(per_band * (size_t)nbands, sizeof *partial, "coarse glow", err);
    if (!partial)
        return ORR_ERR_NOMEM;
    int fail = 0;
    /* Mirror bands in pairs, from one band's measures; a middle band that
     * is its own mirror, alone. */
    const int mirror = bands_mirror(&v->proj), nwork = mirror ? (nbands + 1) / 2 : nbands;
#pragma omp parallel
    {
        double *rows = malloc(sizeof *rows * (size_t)W * BAND_ROWS);
#pragma omp for schedule(dynamic, 1)
        for (int b = 0; b < nwork; b++) {
            if (!rows) {
#pragma omp atomic write
                fail = 1;
                continue;
            }
            reach_band(&v->proj, g, b, rows, partial + per_band * (size_t)b);
            if (mirror && nbands - 1 - b != b)
                reach_mirror_band(&v->proj, g, b, rows, partial + per_band * (size_t)(nbands - 1 - b));
        }
        free(rows);
    }
    for (int b = 0; b < nbands && !fail; b++) { /* the bands in order */
        const int j0 = b * BAND_ROWS, j1 = j0 + BAND_ROWS < H ? j0 + BAND_ROWS : H;
        const double *in = partial + per_band * (size_t)b;
        for (int L = 0; L < g->nlevels; L++) {
            coarse_level *l = &g->level[L];
            int first, rows = band_rows(l, j0, j1, &first);
            const size_t n = (size_t)rows * l->proj.width;
            double *to = l->norm + (size_t)first * l->proj.width;
            for (size_t k = 0; k < n; k++)
                to[k] += in[k];
            in += (size_t)(BAND_ROWS / l->factor + 2) * l->proj.width;
        }
    }
    free(partial);
    return fail ? orr_fail(err, ORR_ERR_NOMEM, "out of memory for the coarse glow of a %d x %d map", W, H) : ORR_OK;
}

/* The on-map neighbours of coarse pixel (i, j) (its 3 x 3 block): calls
 * visit(neighbour's index, share / their number, user) for each (visit may
 * be NULL) and returns how many. */
static int on_map_neighbours(const coarse_level *l, int i, int j, void (*visit)(size_t, double, void *), double share,
                             void *user)
{
    const int w = l->proj.width, h = l->proj.height;
    int n = 0;
    for (int pass = 0; pass < 2; pass++) {
        if (pass == 1 && !visit)
            break;
        for (int dj = -1; dj <= 1; dj++)
            for (int di = -1; di <= 1; di++) {
                const int a = i + di, b = j + dj;
                if (a < 0 || a >= w || b < 0 || b >= h || !l->on_map[(size_t)b * w + a])
                    continue;
                if (pass == 0)
                    n++;
                else
                    visit((size_t)b * w + a, share / n, user);
            }
    }
    return n;
}

static void add_share(size_t p, double share, void *user)
{
    ((double *)user)[p] += share;
}

/* Each coarse pixel's light reaches the fine map through a fixed linear
 * map, the same for every frame and every process, so light is kept
 * exactly and the processes' planes (MPI) add up to one process's: its
 * brightness is its light over norm[p], the fine measure its unit
 * brightness reaches (levels_reach, which leaves it in norm), and off the map (where no light is
 * deposited) a coarse pixel takes its on-map neighbours' mean brightness,
 * so the fine pixels just inside the map's edge keep the edge's
 * brightness instead of fading towards 0 (up to half a coarse pixel, 16
 * fine pixels on the coarsest map). norm[p] therefore also counts, for an
 * on-map pixel, its share of what its off-map neighbours reach. */
static void level_norm(coarse_level *l)
{
    const int w = l->proj.width, h = l->proj.height;
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            const size_t p = (size_t)j * w + i;
            /* (only on-map entries grow: an off-map one still holds its reach) */
            if (!l->on_map[p] && l->norm[p] > 0)
                on_map_neighbours(l, i, j, add_share, l->norm[p], l->norm);
        }
}

static orr_status plan_level(orr_splat_view *v, coarse_level *l, int factor, float min_pixels, int nlanes,
                             orr_error *err)
{
    l->factor = factor;
    l->min_pixels = min_pixels;
    orr_projection_settings coarse = v->proj.settings;
    coarse.width = v->proj.width / factor;
    coarse.height = v->proj.height / factor;
    orr_status st = orr_projection_plan(&l->proj, &coarse, err);
    if (!st && !(st = orr_sph_init(&l->sph, &v->kernel, &l->proj, err)))
        l->sph_ready = 1;
    for (int lane = 0; lane < nlanes && !st; lane++) /* (the lanes the view never splats in, none) */
        for (int k = 0; k < 3 && !st; k++)
            st = orr_plane_alloc(&l->planes[lane][k], l->proj.width, l->proj.height, "glow", "", err);
    if (!st && !(l->on_map = orr_malloc((size_t)l->proj.width * l->proj.height, "coarse glow", err)))
        st = ORR_ERR_NOMEM;
    for (int j = 0; j < l->proj.height && !st; j++)
        for (int i = 0; i < l->proj.width; i++)
            l->on_map[(size_t)j * l->proj.width + i] = (uint8_t)orr_projection_pixel_in_map(&l->proj, i, j);
    return st;
}

orr_status orr_coarse_glow_plan(orr_splat_view *v, orr_error *err)
{
    const orr_projection_traits traits = orr_projection_traits_of(v->proj.settings.kind);
    const int w = v->proj.width, h = v->proj.height;
    /* Sky maps in colour that glow with the kernel deposit, no stereo eye;
     * the levels that divide the map and leave it 8 coarse pixels across
     * or more. Else the view draws every glow itself. */
    if (!traits.sky || traits.pixel_table || !v->use_sph || v->nplanes != 3 || v->splat.stereo)
        return ORR_OK;
    int levels[ORR_COARSE_LEVELS], n = 0;
    for (int k = 0; k < ORR_COARSE_LEVELS; k++) {
        const int cw = w / FACTORS[k], ch = h / FACTORS[k];
        const size_t bytes = (size_t)cw * ch * sizeof(float) * 3 * ORR_MAX_LANES;
        if (w % FACTORS[k] == 0 && h % FACTORS[k] == 0 && cw >= 8 && ch >= 8 && bytes <= MAX_LEVEL_BYTES)
            levels[n++] = k;
    }
    if (!n)
        return ORR_OK;
    coarse_glow *g = orr_calloc(1, sizeof *g, "coarse glow", err);
    if (!g)
        return ORR_ERR_NOMEM;
    v->coarse = g;
    /* A kernel deposit's lanes: its share of the particles is 0, so the
     * count does not matter (lanes_for in splat_pass.c). */
    g->nlanes = orr_lanes_for(w, h, v->nplanes, 0, -1);
    orr_status st = ORR_OK;
    for (int k = 0; k < n && !st; k++, g->nlevels++)
        st = plan_level(v, &g->level[k], FACTORS[levels[k]], MIN_PIXELS[levels[k]], g->nlanes, err);
    if (!st)
        st = levels_reach(v, g, err);
    for (int k = 0; k < g->nlevels && !st; k++)
        level_norm(&g->level[k]);
    if (!st && !(g->buffers = orr_malloc(ORR_MAX_LANES * sizeof *g->buffers, "coarse glow blocks", err)))
        st = ORR_ERR_NOMEM;
    if (st)
        orr_coarse_glow_free(v);
    return st;
}

void orr_coarse_glow_begin(orr_splat_view *v)
{
    coarse_glow *g = v->coarse;
    if (!g)
        return;
    for (int L = 0; L < g->nlevels; L++) {
        coarse_level *l = &g->level[L];
        const size_t npix = (size_t)l->proj.width * l->proj.height;
        for (int lane = 0; lane < g->nlanes; lane++)
            for (int k = 0; k < 3; k++)
                memset(l->planes[lane][k].data, 0, npix * sizeof(float));
    }
}

/* Moves the block's kernels wide enough for level l (visible, h at least
 * the level's min_pixels of its pixels) into cb, in its pixel coordinates, and
 * out of b (not visible there); returns how many, and adds the weight of
 * each plane moved. */
static size_t take_wide(const orr_splat_view *v, const coarse_level *l, size_t n, block_buffers *b, block_buffers *cb,
                        double *moved)
{
    const float f = 1.0f / l->factor, min_hpix = l->min_pixels * l->factor;
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

size_t orr_coarse_glow_split(const orr_splat_view *v, int lane, size_t n, block_buffers *b, orr_deposit_stats *coarse,
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

typedef struct extension {
    const float *sb;
    double sum;
} extension;

static void add_brightness(size_t p, double share, void *user)
{
    extension *e = user;
    e->sum += share * e->sb[p];
}

/* Level l's plane k as surface brightness (level_norm; the nlanes lanes'
 * planes added first, in lane order). Returns NULL without memory. */
static float *level_brightness(coarse_level *l, int nlanes, int k)
{
    const int w = l->proj.width, h = l->proj.height;
    const size_t npix = (size_t)w * h;
    orr_plane *sum = &l->planes[0][k];
    for (int lane = 1; lane < nlanes; lane++)
        for (size_t p = 0; p < npix; p++)
            sum->data[p] += l->planes[lane][k].data[p];
    if (nlanes < ORR_MAX_LANES) /* as the lanes of zeros once added were: a -0 turns +0, all else stays */
        for (size_t p = 0; p < npix; p++)
            sum->data[p] += 0.0f;
    float *sb = malloc(npix * sizeof *sb);
    if (!sb)
        return NULL;
    for (size_t p = 0; p < npix; p++)
        sb[p] = l->norm[p] > 0 ? (float)(sum->data[p] / l->norm[p]) : 0.0f;
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            const size_t p = (size_t)j * w + i;
            extension e = {sb, 0.0};
            if (!l->on_map[p] && on_map_neighbours(l, i, j, add_brightness, 1.0, &e))
                sb[p] += (float)e.sum; /* (reads on-map pixels only, which this loop leaves alone) */
        }
    return sb;
}

/* Level l's brightness sb at the centres of fine row j, bilinear, over
 * span sp. A run of fine columns between the same two coarse ones reads
 * the same four values: loaded once, and the run's loop vectorises (each
 * pixel's expression as it was, so the same bits). */
static void level_row(const coarse_level *l, const float *sb, int j, fine_span sp, float *restrict out)
{
    float c;
    const int t0 = coarse_between(j, l->factor, l->proj.height, &c), cw = l->proj.width;
    const float *r0 = sb + (size_t)t0 * cw, *r1 = r0 + (l->proj.height > 1 ? cw : 0);
    const float *restrict col_a = l->col_a;
    const float c0 = 1 - c;
    for (int i = sp.i0; i < sp.i1;) {
        const int i0 = l->col0[i], i1 = cw > 1 ? i0 + 1 : i0, end = column_run_end(l, i, sp.i1);
        const float p = r0[i0], q = r0[i1], u = r1[i0], w = r1[i1];
        for (int k = i; k < end; k++) {
            const float a = col_a[k];
            out[k] += c0 * ((1 - a) * p + a * q) + c * ((1 - a) * u + a * w);
        }
        i = end;
    }
}

/* Adds every level's brightness sb[k] to fine row j of plane k, each pixel
 * of span sp its measure times the levels' interpolated brightness (row:
 * scratch of the width). */
static void add_fine_row(orr_splat_view *v, float *sb[3][ORR_COARSE_LEVELS], int j, fine_span sp,
                         const double *measure, float *row)
{
    const int W = v->proj.width;
    for (int k = 0; k < v->nplanes; k++) {
        float *fine = v->planes[k].data + (size_t)j * W;
        memset(row + sp.i0, 0, sizeof *row * (size_t)(sp.i1 - sp.i0));
        for (int L = 0; L < v->coarse->nlevels; L++)
            level_row(&v->coarse->level[L], sb[k][L], j, sp, row);
        for (int i = sp.i0; i < sp.i1; i++)
            if (measure[i] > 0)
                fine[i] += (float)(measure[i] * row[i]);
    }
}

/* Adds every level's planes to the view's planes (v->nplanes, 3): each
 * fine pixel on the map its measure times the levels' interpolated
 * brightness; a row's measures found once for all three planes, and for
 * its mirror row (a dome's, orr_pixel_measure_twin_row) too. */
static orr_status add_planes(orr_splat_view *v, orr_error *err)
{
    coarse_glow *g = v->coarse;
    const int W = v->proj.width, H = v->proj.height, np = v->nplanes;
    float *sb[3][ORR_COARSE_LEVELS] = {{NULL}};
    int fail = 0;
    for (int k = 0; k < np; k++)
        for (int L = 0; L < g->nlevels; L++)
            fail |= !(sb[k][L] = level_brightness(&g->level[L], g->nlanes, k));
    if (!fail)
#pragma omp parallel
    {
        double *measure = malloc(sizeof *measure * (size_t)W);
        float *row = malloc(sizeof *row * (size_t)W);
#pragma omp for schedule(dynamic, 8)
        for (int j = 0; j < H; j++) {
            const int twin = orr_pixel_measure_twin_row(&v->proj, j);
            if (twin >= 0 && twin < j)
                continue; /* drawn with its twin */
            if (!measure || !row) {
#pragma omp atomic write
                fail = 1;
                continue;
            }
            const fine_span sp = map_measure_row(&v->proj, j, measure);
            add_fine_row(v, sb, j, sp, measure, row);
            if (twin < 0)
                continue;
            fine_span tw;
            orr_projection_row_in_map(&v->proj, twin, &tw.i0, &tw.i1);
            if (tw.i0 != sp.i0 || tw.i1 != sp.i1) /* (mirror rows: never, but then its own measures) */
                tw = map_measure_row(&v->proj, twin, measure);
            add_fine_row(v, sb, twin, tw, measure, row);
        }
        free(measure);
        free(row);
    }
    for (int k = 0; k < np; k++)
        for (int L = 0; L < g->nlevels; L++)
            free(sb[k][L]);
    return fail ? orr_fail(err, ORR_ERR_NOMEM, "out of memory for the coarse glow of a %d x %d map", W, H) : ORR_OK;
}

orr_status orr_coarse_glow_finish(orr_splat_view *v, orr_error *err)
{
    return v->coarse ? add_planes(v, err) : ORR_OK;
}
