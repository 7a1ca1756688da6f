#include "splat/sph.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/simd.h"
#include "splat/healpix_kernel.h"
#include "splat/kernel_row.h"
#include "splat/sky_cores.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__)) && !defined(ORR_NO_CLONES)
#define HAVE_SEPARABLE_AVX512 1
#include <immintrin.h>
#endif

/* How a particle is drawn (docs/smoothing.md has the measurements behind
 * the thresholds):
 *
 * - h_pix below CUMULATIVE_MAX: the exact pixel integrals of F, as
 *   differences of the cumulative table at the pixel corners. The corner
 *   sums telescope, so a whole kernel adds up to exactly 1 and the share
 *   that falls off the image is known without visiting it. Kernels of up
 *   to 7 pixels a side inside a flat image take fixed-size grids; larger
 *   ones wholly inside a flat image take the kernel's separable expansion
 *   instead (pixels as outer products, no table reads per pixel).
 * - larger: F (plus a Laplacian correction for the pixel's area) at pixel
 *   centres. From 10 pixels per h this midpoint rule is more accurate than
 *   the table's differences (whose float round-off grows as h_pix^2 over
 *   the pixel values), and its sum over a whole footprint is 1 to float
 *   round-off, so no normalising pass is needed. On flat images a block's
 *   large kernels are drawn band by band, to keep the image in cache.
 * - sky maps, h_pix below SKY_LOCAL_MIN: the first method with the local
 *   isotropic scale, folding shares off the map back onto it.
 * - sky maps, larger: the midpoint rule (sub-sampling pixels below 3
 *   pixels per h) over an ellipse from the map's local affine model, the
 *   inverse projection's derivatives, where the model holds (known from an
 *   index of the map, or checked on the support's edge); elsewhere (large
 *   caps, poles, strong distortion, the Hammer-Aitoff seam) every pixel the
 *   cap can reach is mapped back to its direction on the sphere. */
#define CUMULATIVE_MAX 10
#define SKY_LOCAL_MIN 2.0
/* The affine model is trusted when it places the support's edge within
 * AFFINE_TOL units of q (or half a pixel, if more) of where the inverse
 * projection puts it, and the pixels' solid angle there is within
 * AFFINE_AREA_TOL of the centre's. */
#define AFFINE_TOL 0.05
#define AFFINE_AREA_TOL 0.02
/* Corners per side of a footprint drawn from the cumulative table. */
#define MAX_CORNERS (4 * CUMULATIVE_MAX + 8)
/* Pixels computed at once in a row of a large footprint. */
#define ROW_SEGMENT 512

/* Where shares go: the planes, and for sky maps the projection that folds
 * shares off the map back onto it. A sky map's planes (a colour view's X,
 * Y and Z) take the same footprint, each with its own weight: the pixels'
 * weights are found once for all of them. Flat images draw one plane. */
typedef struct target {
    orr_plane *plane;           /* the first plane; the others follow it */
    int nplanes;
    const orr_projection *proj; /* sky maps only */
    const orr_kernel *kernel;
    int fold;                   /* this footprint touches pixels off the map */
    int drop;                   /* ... and those get nothing (the rest is renormalised) */
    double in;                  /* weight added to the first plane (the flat images' tally) */
    const int *row_on_map;      /* the sky map's runs on the map (orr_sph.row_on_map), or NULL */
} target;

/* Whether pixel (i, j) is on the target's map: orr_projection_pixel_in_map,
 * from the map's table of runs when it has one (a call and a test of
 * doubles per pixel of a footprint crossing the dome's rim was 2.5 % of
 * the 8K dome master's CPU time). */
static inline int on_map(const target *t, int i, int j)
{
    if (!t->row_on_map)
        return orr_projection_pixel_in_map(t->proj, i, j);
    if (j < 0 || j >= t->plane->height)
        return 0;
    const int *run = t->row_on_map + 2 * (size_t)j;
    return i >= run[0] && i < run[1];
}

/* Adds scale * wt[m] to pixels (i0 + m, j) of plane p, m < n. The sums of
 * what was added are worked out by the callers, mostly without a pass over
 * the pixels, so this loop is a plain vectorised multiply-add. */
static void emit_plane_row(const target *t, orr_plane *p, int j, int i0, int n, const float *restrict wt,
                           float scale)
{
    float *data = p->data;
    const int W = p->width;
    if (!t->fold) {
        float *restrict row = data + (size_t)j * (size_t)W + (size_t)i0;
        for (int m = 0; m < n; m++)
            row[m] += scale * wt[m];
        return;
    }
    for (int m = 0; m < n; m++) {
        float s = scale * wt[m];
        if (s == 0.0f)
            continue;
        int i = i0 + m, jj = j;
        if (!on_map(t, i, jj)) {
            if (t->drop)
                continue;
            orr_projection_fold(t->proj, &i, &jj);
        }
        data[(size_t)jj * (size_t)W + (size_t)i] += s;
    }
}

/* The same weights into every plane, plane k scaled by scale[k]. */
static void emit_row(const target *t, int j, int i0, int n, const float *restrict wt, const float *scale)
{
    for (int k = 0; k < t->nplanes; k++)
        emit_plane_row(t, &t->plane[k], j, i0, n, wt, scale[k]);
}

/* Each plane's scale: its weight over the footprint's sum of weights. */
static void plane_scales(const target *t, const float *w, double sum, float *scale)
{
    for (int k = 0; k < t->nplanes; k++)
        scale[k] = (float)(w[k] / sum);
}

/* A footprint's pixel range, [i0, i1] x [j0, j1]. */
typedef struct box {
    int i0, i1, j0, j1;
} box;

/* Whether every pixel of the box is on the map: the maps' outlines
 * (rectangle, ellipse, circle) are convex, so the four corners decide. */
static int box_in_map(const orr_projection *p, box b)
{
    return orr_projection_pixel_in_map(p, b.i0, b.j0) && orr_projection_pixel_in_map(p, b.i1, b.j0) &&
           orr_projection_pixel_in_map(p, b.i0, b.j1) && orr_projection_pixel_in_map(p, b.i1, b.j1);
}

/* box_in_map on the target's map, by its table when it has one. */
static int box_on_map(const target *t, box b)
{
    return on_map(t, b.i0, b.j0) && on_map(t, b.i1, b.j0) && on_map(t, b.i0, b.j1) && on_map(t, b.i1, b.j1);
}

/* Ternaries, not fmin/fmax: those are library calls (for their NaN rules)
 * in this build, and these values are never NaN. */
static inline double clamp(double v, double lo, double hi)
{
    return v < lo ? lo : v > hi ? hi : v;
}

/* The pixels covering [c - r, c + r] on both axes; 0 when that lies wholly
 * off the image (or is not a number). On a sky map nothing is clipped:
 * pixels off the image are folded back, and the range is small there. */
static int footprint(const target *t, double cx, double cy, double rx, double ry, box *b, box *full)
{
    const double W = t->plane->width, H = t->plane->height;
    double x0 = floor(cx - rx), x1 = floor(cx + rx), y0 = floor(cy - ry), y1 = floor(cy + ry);
    if (!(x1 >= 0 && x0 < W && y1 >= 0 && y0 < H))
        return 0;
    if (t->proj) {
        /* Sky: the caller keeps footprints within about a map's size. */
        b->i0 = (int)clamp(x0, -W, 2 * W), b->i1 = (int)clamp(x1, -W, 2 * W);
        b->j0 = (int)clamp(y0, -H, 2 * H), b->j1 = (int)clamp(y1, -H, 2 * H);
        *full = *b;
        return 1;
    }
    /* Flat: clip, converting in double so far-off edges cannot overflow. */
    full->i0 = (int)clamp(x0, -1e9, 1e9), full->i1 = (int)clamp(x1, -1e9, 1e9);
    full->j0 = (int)clamp(y0, -1e9, 1e9), full->j1 = (int)clamp(y1, -1e9, 1e9);
    b->i0 = (int)clamp(x0, 0, W - 1), b->i1 = (int)clamp(x1, 0, W - 1);
    b->j0 = (int)clamp(y0, 0, H - 1), b->j1 = (int)clamp(y1, 0, H - 1);
    return 1;
}

/* ---- exact pixel integrals from the cumulative table ---- */

/* One axis of a footprint's corner grid: for corner k (image coordinate
 * e0 + k) the table cell, fraction and sign of (e0 + k - centre) / h. */
typedef struct corner_axis {
    int n;
    int cell[MAX_CORNERS];
    float frac[MAX_CORNERS], sign[MAX_CORNERS];
} corner_axis;

/* first_edge / last_edge: the first / last corner is the footprint's own
 * edge, at or beyond the support, and is set exactly there so the whole
 * kernel adds up to exactly 4 G(2, 2) = 1 whatever the rounding. */
static void corner_axis_setup(corner_axis *a, double c, double inv_h, int e0, int n, int first_edge,
                              int last_edge)
{
    a->n = n;
    for (int k = 0; k < n; k++) {
        double x = (e0 + k - c) * inv_h;
        if ((k == 0 && first_edge) || x < -ORR_KERNEL_SUPPORT)
            x = -ORR_KERNEL_SUPPORT;
        if ((k == n - 1 && last_edge) || x > ORR_KERNEL_SUPPORT)
            x = ORR_KERNEL_SUPPORT;
        double g = fabs(x) * (ORR_KERNEL_NG / ORR_KERNEL_SUPPORT);
        int i = g < ORR_KERNEL_NG ? (int)g : ORR_KERNEL_NG - 1;
        a->cell[k] = i;
        a->frac[k] = (float)(g - i);
        a->sign[k] = x < 0 ? -1.0f : 1.0f;
    }
}

/* The signed cumulative integral at the corners of row l of the grid.
 * Plain arrays with restrict, so GCC vectorises the loop. */
static void corner_row(const orr_kernel *k, const corner_axis *ax, const corner_axis *ay, int l,
                       float *restrict out)
{
    const float *restrict g0 = k->cumulative + (size_t)ay->cell[l] * (ORR_KERNEL_NG + 1);
    const float *restrict g1 = g0 + ORR_KERNEL_NG + 1;
    const int *restrict cell = ax->cell;
    const float *restrict frac = ax->frac, *restrict sign = ax->sign;
    const float fy = ay->frac[l], sy = ay->sign[l];
    const int n = ax->n;
    for (int m = 0; m < n; m++) {
        const int i = cell[m];
        const float fx = frac[m];
        const float lo = g0[i] + fx * (g0[i + 1] - g0[i]);
        const float hi = g1[i] + fx * (g1[i + 1] - g1[i]);
        out[m] = sy * sign[m] * (lo + fy * (hi - lo));
    }
}

/* A disc kernel of h pixels (h < CUMULATIVE_MAX) at (cx, cy), weight w[k]
 * into plane k. */
static void disc_cumulative(target *t, double cx, double cy, double h, const float *w)
{
    box b, full;
    const double r = ORR_KERNEL_SUPPORT * h;
    if (!footprint(t, cx, cy, r, r, &b, &full))
        return;
    if (t->proj)
        t->fold = !box_on_map(t, b);
    corner_axis ax, ay;
    const double inv_h = 1.0 / h;
    corner_axis_setup(&ax, cx, inv_h, b.i0, b.i1 - b.i0 + 2, b.i0 == full.i0, b.i1 == full.i1);
    corner_axis_setup(&ay, cy, inv_h, b.j0, b.j1 - b.j0 + 2, b.j0 == full.j0, b.j1 == full.j1);
    /* All corner rows first, then the differences: reading a row shifted
     * by one corner right after the vector stores that wrote it would stall
     * on store forwarding, row after row. */
    float grid[MAX_CORNERS * MAX_CORNERS], wt[MAX_CORNERS];
    const int n = ax.n - 1;
    for (int l = 0; l < ay.n; l++)
        corner_row(t->kernel, &ax, &ay, l, grid + l * ax.n);
    for (int l = 1; l < ay.n; l++) {
        const float *prev = grid + (l - 1) * ax.n, *cur = grid + l * ax.n;
        for (int m = 0; m < n; m++)
            wt[m] = (cur[m + 1] - cur[m]) - (prev[m + 1] - prev[m]);
        emit_row(t, b.j0 + l - 1, b.i0, n, wt, w);
    }
    /* The drawn pixels' weights telescope to the corners of the box: 1 for
     * a whole kernel, the share on the image for a clipped one. On a sky
     * map everything lands (folded). */
    const float *top = grid, *bottom = grid + (ay.n - 1) * ax.n;
    t->in += t->proj ? w[0] : w[0] * (((double)bottom[n] - bottom[0]) - ((double)top[n] - top[0]));
}

/* ---- small kernels on flat images: fixed-size corner grids ----
 *
 * Most particles of a dense region are smaller than a pixel or two. For
 * them the general path's set-up (footprint, clipping, variable-length
 * loops, a call a row) costs more than the corners themselves, so a
 * footprint of at most 1, 2, FIXED_SMALL - 1, FIXED_MID - 1 or
 * FIXED_LARGE - 1 pixels a side, inside the image, takes a corner grid of
 * the next of those widths (the narrower the grid, the fewer padding
 * corners; 6 rather than 8 was 10-25 % faster at h_pix = 0.6-1.1, docs/
 * performance.md "Seventh reading"): loops of known
 * length that GCC unrolls and vectorises, in float (the positions are
 * floats already). Only the footprint's own rows are computed and touched
 * (each row is a cache line to fetch); its columns are padded to the fixed
 * width with corners beyond the support, which read the same table entry
 * as the support's edge, so the padding pixels get exactly 0. Same table,
 * same corner formula, same telescoping as disc_cumulative: the whole
 * kernel adds up to exactly 1. */
#define FIXED_SMALL 4
#define FIXED_MID 6
#define FIXED_LARGE 8

/* Corners k < n of one axis, at image coordinates e0 + k, in units of h
 * from the centre c: table cell, fraction and sign. Corner 0 and corners
 * from `edge` on lie on or beyond the support's edge (the caller checked)
 * and are set exactly there, whatever the rounding. */
static inline void fixed_axis(float c, float inv_h, float e0, int n, int edge, int *restrict cell,
                              float *restrict frac, float *restrict sign)
{
    const float to_cell = (float)(ORR_KERNEL_NG / ORR_KERNEL_SUPPORT), support = (float)ORR_KERNEL_SUPPORT;
    for (int k = 0; k < n; k++) {
        float x = (e0 + (float)k - c) * inv_h;
        x = k == 0 ? -support : k >= edge ? support : x < -support ? -support : x > support ? support : x;
        const float g = (x < 0.0f ? -x : x) * to_cell;
        const int i = (int)g < ORR_KERNEL_NG - 1 ? (int)g : ORR_KERNEL_NG - 1;
        cell[k] = i;
        frac[k] = g - (float)i;
        sign[k] = x < 0.0f ? -1.0f : 1.0f;
    }
}

/* Deposits a kernel of r = 2 h pixels' support at (cx, cy), whose
 * footprint is nx x ny pixels from (x0, y0), all on the image, with a
 * corner grid n wide (nx < n, ny < n). */
static inline void disc_fixed(target *t, float cx, float cy, float h, float w, int x0, int y0, int nx, int ny,
                              const int n)
{
    ny = ny < n ? ny : n - 1; /* (it is: the bound is for the compiler) */
    int cell_x[FIXED_LARGE], cell_y[FIXED_LARGE];
    float frac_x[FIXED_LARGE], frac_y[FIXED_LARGE], sign_x[FIXED_LARGE], sign_y[FIXED_LARGE];
    const float inv_h = 1.0f / h;
    fixed_axis(cx, inv_h, (float)x0, n, nx, cell_x, frac_x, sign_x);
    fixed_axis(cy, inv_h, (float)y0, n, ny, cell_y, frac_y, sign_y);
    float grid[FIXED_LARGE][FIXED_LARGE];
    const float *table = t->kernel->cumulative;
    for (int l = 1; l <= ny; l++) {
        const float *g0 = table + (size_t)cell_y[l] * (ORR_KERNEL_NG + 1), *g1 = g0 + ORR_KERNEL_NG + 1;
        const float fy = frac_y[l], sy = sign_y[l];
        for (int m = 0; m < n; m++) {
            const int i = cell_x[m];
            const float fx = frac_x[m];
            const float lo = g0[i] + fx * (g0[i + 1] - g0[i]);
            const float hi = g1[i] + fx * (g1[i + 1] - g1[i]);
            grid[l][m] = sy * sign_x[m] * (lo + fy * (hi - lo));
        }
    }
    /* The first and last rows of corners both lie on the support's edge,
     * at the same table entry with opposite signs: the first is the last
     * negated, bit for bit. */
    for (int m = 0; m < n; m++)
        grid[0][m] = -grid[ny][m];
    const int width = t->plane->width;
    float *row = t->plane->data + (size_t)y0 * (size_t)width + (size_t)x0;
    for (int l = 0; l < ny; l++, row += width)
        for (int m = 0; m + 1 < n; m++)
            row[m] += w * ((grid[l + 1][m + 1] - grid[l + 1][m]) - (grid[l][m + 1] - grid[l][m]));
    t->in += w;
}

/* A footprint wholly on a flat image: nx x ny pixels from (x0, y0). */
typedef struct flat_footprint {
    int x0, y0, nx, ny;
} flat_footprint;

/* Whether the support of a kernel of h pixels at (cx, cy) lies wholly on a
 * flat image (the fast paths below take only such kernels), and its
 * pixels. */
static int on_flat_image(const target *t, float cx, float cy, float h, flat_footprint *f)
{
    const float r = (float)ORR_KERNEL_SUPPORT * h;
    /* floor(c - r) as a truncation (floorf is a library call without
     * SSE4.1), once c - r is known to be on the image. */
    if (t->proj || !(cx - r >= 0.0f && cy - r >= 0.0f && cx + r < (float)t->plane->width &&
                     cy + r < (float)t->plane->height))
        return 0;
    f->x0 = (int)(cx - r);
    f->y0 = (int)(cy - r);
    f->nx = (int)(cx + r) - f->x0 + 1;
    f->ny = (int)(cy + r) - f->y0 + 1;
    return 1;
}

/* Deposits a kernel of h pixels with footprint f by a fixed-size grid when
 * it fits one; returns 0, having done nothing, when it does not. */
static int disc_small(target *t, float cx, float cy, float h, float w, const flat_footprint *f)
{
    const int n = f->nx > f->ny ? f->nx : f->ny, width = t->plane->width;
    if (!((float)ORR_KERNEL_SUPPORT * h < 0.5f * FIXED_LARGE))
        return 0;
    if (n == 1)
        disc_fixed(t, cx, cy, h, w, f->x0, f->y0, f->nx, f->ny, 2);
    else if (n == 2)
        disc_fixed(t, cx, cy, h, w, f->x0, f->y0, f->nx, f->ny, 3);
    else if (n < FIXED_SMALL && f->x0 + FIXED_SMALL - 1 <= width)
        disc_fixed(t, cx, cy, h, w, f->x0, f->y0, f->nx, f->ny, FIXED_SMALL);
    else if (n < FIXED_MID && f->x0 + FIXED_MID - 1 <= width)
        disc_fixed(t, cx, cy, h, w, f->x0, f->y0, f->nx, f->ny, FIXED_MID);
    else if (n < FIXED_LARGE && f->x0 + FIXED_LARGE - 1 <= width)
        disc_fixed(t, cx, cy, h, w, f->x0, f->y0, f->nx, f->ny, FIXED_LARGE);
    else
        return 0;
    return 1;
}

/* ---- mid-sized kernels on flat images: the separable expansion ----
 *
 * From a couple of pixels per h up, the corner grid's bilinear table reads
 * (four a corner, about one corner a pixel) are most of a kernel's cost.
 * The kernel's separable expansion (splat/kernel.h) turns its pixel
 * integrals into an outer product: a pixel is the sum over k of
 * s_k dE_k(column) dE_k(row), with the differences of E_k between
 * neighbouring corners worked out once per column and once per row, so a
 * pixel costs ORR_KERNEL_SEP_RANK multiply-adds, sixteen pixels at once,
 * with no table reads. The expansion holds F to about 1e-5 of its peak
 * (docs/smoothing.md): it may dip that far below zero near the support's
 * edge, so weights are clamped at zero, and the kernel is normalised by
 * the sum of what it draws, so it adds exactly its weight (to float
 * round-off). Only footprints wholly on a flat image: the rest take the
 * cumulative table, which also gives a clipped kernel's share. */
#define SEP_RANK ORR_KERNEL_SEP_RANK
#define SEP_LANES 16
/* Columns of a footprint row, padded to whole vectors of SEP_LANES: at
 * most 4 CUMULATIVE_MAX + 1 pixels. */
#define SEP_ROW ((4 * CUMULATIVE_MAX + 1 + SEP_LANES - 1) / SEP_LANES * SEP_LANES)

/* Along one axis, the differences of E_k between the n + 1 corners at
 * image coordinates e0 + m (in units of h from the centre c): d[m * SEP_RANK
 * + k], m < n. All the corners' values first, then the differences, so
 * both loops run over contiguous arrays. */
static ORR_ALWAYS_INLINE void separable_axis(const orr_kernel *k, float c, float inv_h, int e0, int n,
                                             float *restrict d)
{
    float e[(SEP_ROW + 1) * SEP_RANK];
    for (int m = 0; m <= n; m++)
        orr_kernel_separable_at(k, ((float)(e0 + m) - c) * inv_h, e + m * SEP_RANK);
    for (int i = 0; i < n * SEP_RANK; i++)
        d[i] = e[i + SEP_RANK] - e[i];
}

/* Draws the kernel of disc_separable, whose footprint is nx x ny pixels
 * from (x0, y0): the columns' differences of E_k, transposed to a[k *
 * SEP_ROW + m] (zero past nx), the rows' b[l * SEP_RANK + k] (signs
 * included), the weights into buf (clamped at zero), then scale times them
 * into the image, scale = w / (their sum). The sum runs in SEP_LANES fixed
 * partial sums, so every vector width adds in the same order and gives the
 * same bits. Returns 0, having drawn nothing, if the sum is not positive. */
ORR_WIDE_VECTOR_CLONES
static int separable_draw(const orr_kernel *k, float cx, float cy, float inv_h, int x0, int y0, int nx, int ny,
                          orr_plane *plane, float w)
{
    float dx[SEP_ROW * SEP_RANK], b[SEP_ROW * SEP_RANK];
    float a[SEP_RANK * SEP_ROW], buf[SEP_ROW * SEP_ROW];
    separable_axis(k, cx, inv_h, x0, nx, dx);
    separable_axis(k, cy, inv_h, y0, ny, b);
    const int nxp = (nx + SEP_LANES - 1) / SEP_LANES * SEP_LANES;
    for (int r = 0; r < SEP_RANK; r++) {
        for (int m = 0; m < nx; m++)
            a[r * SEP_ROW + m] = dx[m * SEP_RANK + r];
        for (int m = nx; m < nxp; m++)
            a[r * SEP_ROW + m] = 0.0f;
    }
    for (int l = 0; l < ny; l++)
        for (int r = 0; r < SEP_RANK; r++)
            b[l * SEP_RANK + r] *= k->separable_sign[r];
    float acc[SEP_LANES] = {0};
    for (int l = 0; l < ny; l++) {
        const float *restrict bl = b + l * SEP_RANK;
        float *restrict out = buf + l * SEP_ROW;
        for (int m0 = 0; m0 < nxp; m0 += SEP_LANES)
            for (int j = 0; j < SEP_LANES; j++) {
                const int m = m0 + j;
                float v = a[m] * bl[0];
                for (int r = 1; r < SEP_RANK; r++)
                    v += a[r * SEP_ROW + m] * bl[r];
                v = v > 0.0f ? v : 0.0f;
                out[m] = v;
                acc[j] += v;
            }
    }
    double total = 0.0;
    for (int j = 0; j < SEP_LANES; j++)
        total += acc[j];
    if (!(total > 0.0))
        return 0;
    const float scale = (float)(w / total);
    for (int l = 0; l < ny; l++) {
        float *restrict row = plane->data + (size_t)(y0 + l) * (size_t)plane->width + (size_t)x0;
        const float *restrict in = buf + l * SEP_ROW;
        for (int m = 0; m < nx; m++)
            row[m] += scale * in[m];
    }
    return 1;
}

#ifdef HAVE_SEPARABLE_AVX512
/* separable_draw with AVX-512 written out. The compiler's version stores
 * each corner's E_k as one 8-float vector and reads them back as 16-float
 * vectors (the differences, the transpose of the columns, the rows'
 * signs), each such read spanning two stores, which the core cannot
 * forward; and it leaves the transpose (128 scalar moves) and each image
 * row's tail to scalar loops. Here the corners' differences stay in
 * registers, the columns are turned round by three rounds of two-register
 * permutes, and a row goes into the image as masked 16-pixel vectors. The
 * weights, their clamping, the sixteen partial sums and the image
 * additions are the same operations in the same order: the same bits
 * (checked on the pair's 10^7-particle image and the tests' images). */

/* orr_kernel_separable_at at x, as one vector. */
__attribute__((target("avx512f"))) static inline __m256 separable_at8(const orr_kernel *k, float x)
{
    const float support = (float)ORR_KERNEL_SUPPORT;
    const float ax = x < 0.0f ? (x > -support ? -x : support) : (x < support ? x : support);
    const float t = ax * (float)(ORR_KERNEL_SEP_N / ORR_KERNEL_SUPPORT);
    const int i = (int)t;
    const float *row = k->separable + (size_t)i * ORR_KERNEL_SEP_RANK;
    const __m256 lo = _mm256_loadu_ps(row), hi = _mm256_loadu_ps(row + ORR_KERNEL_SEP_RANK);
    const __m256 f = _mm256_set1_ps(t - (float)i), sign = _mm256_set1_ps(x < 0.0f ? -1.0f : 1.0f);
    return _mm256_mul_ps(sign, _mm256_add_ps(lo, _mm256_mul_ps(f, _mm256_sub_ps(hi, lo))));
}

/* idx of one output of a transpose round: lane L takes lane (L with bit j
 * set to `to`) of the first input (L's bit j clear) or of the second. */
__attribute__((target("avx512f"))) static inline __m512i swap_index(int j, int to)
{
    int v[16];
    for (int L = 0; L < 16; L++)
        v[L] = (L >> j & 1 ? 16 : 0) + (to ? L | 1 << j : L & ~(1 << j));
    return _mm512_loadu_si512(v);
}

/* The last round also puts the columns in order: output lane (m3 m2 m1 m0)
 * of rank half `to` from input lane (m0, to, m2, m1) of the input with m3. */
__attribute__((target("avx512f"))) static inline __m512i last_index(int to)
{
    int v[16];
    for (int L = 0; L < 16; L++)
        v[L] = (L >> 3 & 1 ? 16 : 0) + ((L & 1) << 3 | to << 2 | (L >> 2 & 1) << 1 | (L >> 1 & 1));
    return _mm512_loadu_si512(v);
}

/* Columns m0 .. m0 + 15 of the footprint (nx columns; the last corner's E
 * in *prev on entry and exit): the differences of E_k between their
 * corners into a[r * SEP_ROW + m0 + j], zero from column nx on. */
__attribute__((target("avx512f"))) static void separable_columns(const orr_kernel *k, float cx, float inv_h, int x0,
                                                                int m0, int nx, __m256 *prev, float *a)
{
    __m256 d[SEP_LANES];
    for (int j = 0; j < SEP_LANES; j++) {
        const int m = m0 + j;
        if (m >= nx) {
            d[j] = _mm256_setzero_ps();
            continue;
        }
        const __m256 cur = separable_at8(k, ((float)(x0 + m + 1) - cx) * inv_h);
        d[j] = _mm256_sub_ps(cur, *prev);
        *prev = cur;
    }
    /* Register p holds columns 2p and 2p + 1: registers (m3 m2 m1), lanes
     * (m0 r2 r1 r0). Swap m1 with r0, m2 with r1, then m3 with r2, ending
     * in registers (r2 r1 r0), lanes m. */
    __m512 z[8], t[8];
    for (int p = 0; p < 8; p++)
        z[p] = _mm512_castpd_ps(_mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_castps_pd(d[2 * p])),
                                                   _mm256_castps_pd(d[2 * p + 1]), 1));
    for (int j = 0; j < 2; j++) {
        const __m512i lo = swap_index(j, 0), hi = swap_index(j, 1);
        for (int p = 0; p < 8; p++)
            if (!(p >> j & 1)) {
                t[p] = _mm512_permutex2var_ps(z[p], lo, z[p | 1 << j]);
                t[p | 1 << j] = _mm512_permutex2var_ps(z[p], hi, z[p | 1 << j]);
            }
        for (int p = 0; p < 8; p++)
            z[p] = t[p];
    }
    const __m512i lo = last_index(0), hi = last_index(1);
    for (int p = 0; p < 4; p++) {
        _mm512_storeu_ps(a + (size_t)p * SEP_ROW + m0, _mm512_permutex2var_ps(z[p], lo, z[p | 4]));
        _mm512_storeu_ps(a + (size_t)(p | 4) * SEP_ROW + m0, _mm512_permutex2var_ps(z[p], hi, z[p | 4]));
    }
}

__attribute__((target("avx512f"))) static int separable_draw_avx512(const orr_kernel *k, float cx, float cy,
                                                                   float inv_h, int x0, int y0, int nx, int ny,
                                                                   orr_plane *plane, float w)
{
    /* The image's rows are mostly misses of the core's caches (a 1024^2
     * image is twice its L2): asked for now, they arrive while the weights
     * are worked out. */
    for (int l = 0; l < ny; l++) {
        const float *row = plane->data + (size_t)(y0 + l) * (size_t)plane->width + (size_t)x0;
        ORR_PREFETCH_FOR_WRITE(row);
        ORR_PREFETCH_FOR_WRITE(row + nx - 1);
    }
    float b[SEP_ROW * SEP_RANK], a[SEP_RANK * SEP_ROW], buf[SEP_ROW * SEP_ROW];
    const __m256 sign = _mm256_loadu_ps(k->separable_sign);
    __m256 prev = separable_at8(k, ((float)y0 - cy) * inv_h);
    for (int l = 0; l < ny; l++) {
        const __m256 cur = separable_at8(k, ((float)(y0 + l + 1) - cy) * inv_h);
        _mm256_storeu_ps(b + l * SEP_RANK, _mm256_mul_ps(_mm256_sub_ps(cur, prev), sign));
        prev = cur;
    }
    const int nxp = (nx + SEP_LANES - 1) / SEP_LANES * SEP_LANES;
    prev = separable_at8(k, ((float)x0 - cx) * inv_h);
    for (int m0 = 0; m0 < nxp; m0 += SEP_LANES)
        separable_columns(k, cx, inv_h, x0, m0, nx, &prev, a);
    const __m512 zero = _mm512_setzero_ps();
    __m512 acc = zero;
    for (int l = 0; l < ny; l++) {
        const float *bl = b + l * SEP_RANK;
        for (int m0 = 0; m0 < nxp; m0 += SEP_LANES) {
            __m512 v = _mm512_mul_ps(_mm512_loadu_ps(a + m0), _mm512_set1_ps(bl[0]));
            for (int r = 1; r < SEP_RANK; r++)
                v = _mm512_add_ps(v, _mm512_mul_ps(_mm512_loadu_ps(a + r * SEP_ROW + m0), _mm512_set1_ps(bl[r])));
            v = _mm512_maskz_mov_ps(_mm512_cmp_ps_mask(v, zero, _CMP_GT_OQ), v);
            _mm512_storeu_ps(buf + l * SEP_ROW + m0, v);
            acc = _mm512_add_ps(acc, v);
        }
    }
    float sums[SEP_LANES];
    _mm512_storeu_ps(sums, acc);
    double total = 0.0;
    for (int j = 0; j < SEP_LANES; j++)
        total += sums[j];
    if (!(total > 0.0))
        return 0;
    const __m512 scale = _mm512_set1_ps((float)(w / total));
    for (int l = 0; l < ny; l++) {
        float *row = plane->data + (size_t)(y0 + l) * (size_t)plane->width + (size_t)x0;
        for (int m0 = 0; m0 < nx; m0 += SEP_LANES) {
            const int left = nx - m0;
            const __mmask16 live = left >= SEP_LANES ? (__mmask16)0xffff : (__mmask16)((1u << left) - 1u);
            const __m512 o = _mm512_maskz_loadu_ps(live, row + m0);
            const __m512 add = _mm512_mul_ps(scale, _mm512_loadu_ps(buf + l * SEP_ROW + m0));
            _mm512_mask_storeu_ps(row + m0, live, _mm512_add_ps(o, add));
        }
    }
    return 1;
}
#endif

/* Deposits a kernel of h pixels (h < CUMULATIVE_MAX) at (cx, cy), with
 * footprint f, by the separable expansion; returns 0, having done nothing,
 * if it does not fit the buffers (it always should). */
static int disc_separable(target *t, float cx, float cy, float h, float w, const flat_footprint *f)
{
    if (!(h < (float)CUMULATIVE_MAX) || f->nx > 4 * CUMULATIVE_MAX + 1 || f->ny > 4 * CUMULATIVE_MAX + 1)
        return 0;
#ifdef HAVE_SEPARABLE_AVX512
    if (__builtin_cpu_supports("avx512f")) {
        if (!separable_draw_avx512(t->kernel, cx, cy, 1.0f / h, f->x0, f->y0, f->nx, f->ny, t->plane, w))
            return 0;
        t->in += w;
        return 1;
    }
#endif
    if (!separable_draw(t->kernel, cx, cy, 1.0f / h, f->x0, f->y0, f->nx, f->ny, t->plane, w))
        return 0;
    t->in += w;
    return 1;
}

/* ---- midpoint rule over an ellipse ---- */

/* A kernel whose footprint is the ellipse u = a dx^2 + 2 b dx dy + c dy^2
 * < 4 (u = q^2; dx, dy in pixels from the centre). Each pixel's weight is
 * the mean over ns x ns sub-pixels of F(u) + lap lap_F(u): the midpoint
 * rule with its leading error term, (sub-pixel area / 24) times the
 * Laplacian of F, taken for a circle of the ellipse's mean size. */
typedef struct ellipse {
    double cx, cy, a, b, c;
    double det, inv_a; /* a c - b^2, 1 / a */
    double ex, ey;   /* half-extents in x and y */
    double hmin;     /* the narrower semi-axis of u = 1, in pixels */
    float lap;
    int ns;
} ellipse;

static void ellipse_setup(ellipse *e, double cx, double cy, double a, double b, double c)
{
    double det = a * c - b * b;
    e->cx = cx, e->cy = cy, e->a = a, e->b = b, e->c = c;
    e->det = det, e->inv_a = 1.0 / a;
    e->ex = ORR_KERNEL_SUPPORT * sqrt(c / det);
    e->ey = ORR_KERNEL_SUPPORT * sqrt(a / det);
    double lmax = 0.5 * (a + c) + sqrt(0.25 * (a - c) * (a - c) + b * b);
    e->hmin = 1.0 / sqrt(lmax);
    /* The narrower axis sets how finely pixels are sampled. Only sky maps
     * draw ellipses under 10 pixels per h (flat maps use the cumulative
     * table there), and their affine model holds to about 1 % (AFFINE_TOL):
     * the corrected midpoint rule, within 1.3e-3 of the peak pixel from 3
     * pixels per h and about 6e-3 at 2 (a dome's kernel against the pixel
     * integral: 5.6e-3, sub-sampled 2 x 2 4.1e-3, test_sph's sky shapes),
     * is sub-sampled only below 2, where it would not hold. (Sampled 2 x 2
     * from 2 to 3 pixels per h, the glows' kernels cost four samples a
     * pixel: a fifth of the main job's deposit.) */
    e->ns = e->hmin >= 2.0 ? 1 : e->hmin >= 1.5 ? 2 : e->hmin >= 0.75 ? 4 : 8;
    e->lap = (float)(0.5 * (a + c) / (24.0 * e->ns * e->ns));
}

/* Where the row at dy (from the centre) crosses the support: dx in
 * [*x0, *x1]; 0 when it misses it. */
static int support_chord(const ellipse *e, double dy, double *x0, double *x1)
{
    double disc = ORR_KERNEL_SUPPORT * ORR_KERNEL_SUPPORT * e->a - e->det * dy * dy;
    if (!(disc >= 0))
        return 0;
    double mid = -e->b * dy * e->inv_a, half = sqrt(disc) * e->inv_a;
    *x0 = mid - half;
    *x1 = mid + half;
    return 1;
}

/* The pixel columns of row j the ellipse can reach (any sub-row): with
 * one sample a pixel, those whose centres are inside; sub-sampled, those
 * overlapping the support. Called once a row; the results are kept within
 * +-1e9 so they convert to int. */
static int ellipse_row_range(const ellipse *e, int j, int *lo, int *hi)
{
    double xmin = HUGE_VAL, xmax = -HUGE_VAL, x0, x1;
    for (int s = 0; s < e->ns; s++)
        if (support_chord(e, j + (s + 0.5) / e->ns - e->cy, &x0, &x1)) {
            xmin = x0 < xmin ? x0 : xmin;
            xmax = x1 > xmax ? x1 : xmax;
        }
    if (xmin > xmax)
        return 0;
    double c0 = e->cx + xmin, c1 = e->cx + xmax;
    c0 = e->ns == 1 ? ceil(c0 - 0.5) : floor(c0);
    c1 = floor(e->ns == 1 ? c1 - 0.5 : c1);
    c0 = c0 > -1e9 ? c0 : -1e9;
    c1 = c1 < 1e9 ? c1 : 1e9;
    *lo = (int)c0;
    *hi = (int)c1;
    return *lo <= *hi;
}

/* The samples of the ellipse's row at dy, columns [m0, m1), into out
 * (orr_sample_span's terms of u = (a dx + bdy) dx + cdy). */
static inline orr_sample_span ellipse_span(const ellipse *e, float dy, int m0, int m1, float *out)
{
    const float b2 = (float)(2.0 * e->b), c = (float)e->c;
    return (orr_sample_span){b2 * dy, c * dy * dy, m0, m1, out};
}

/* Adds (or stores, or scales and adds: mode) F(u) + lap lap_F(u) at
 * samples dx0 + m (m in [m0, m1)) of the row at dy to out[m]. The callers
 * choose the range so every sample lies in the support, up to float
 * rounding, where the samples are zero. */
static inline void add_samples(const orr_sample_poly *poly, const ellipse *e, float dy, float dx0, int m0, int m1,
                               float *restrict out, orr_sample_mode mode, float scale)
{
    const orr_sample_span s = ellipse_span(e, dy, m0, m1, out);
    orr_sample_row(poly, (float)e->a, s.bdy, s.cdy, dx0, m0, m1, out, mode, scale);
}

/* Weights of pixels i0 .. i0 + n - 1 of row j: the mean over ns x ns
 * sub-pixels, each sub-row and sub-column sampled only where it is inside
 * the support. */
static void ellipse_weights(const orr_sample_poly *poly, const ellipse *e, int j, int i0, int n, float *restrict out)
{
    const int ns = e->ns;
    const double step = 1.0 / ns;
    /* One sample a pixel: the row range already holds the centres inside,
     * so the samples are stored, not added to zeros (which would cost a
     * memset's start-up on every short row). */
    if (ns == 1) {
        double x0, x1, dy = j + 0.5 - e->cy, base = i0 + 0.5 - e->cx;
        int m0 = 0, m1 = 0;
        if (support_chord(e, dy, &x0, &x1)) {
            double lo = ceil(x0 - base), hi = floor(x1 - base);
            m0 = lo > 0 ? (lo < n ? (int)lo : n) : 0;
            m1 = hi < n - 1 ? (hi >= 0 ? (int)hi + 1 : 0) : n;
            m1 = m1 > m0 ? m1 : m0;
        }
        for (int m = 0; m < m0; m++)
            out[m] = 0.0f;
        add_samples(poly, e, (float)dy, (float)base, m0, m1, out, ORR_SAMPLES_SET, 1.0f);
        for (int m = m1; m < n; m++)
            out[m] = 0.0f;
        return;
    }
    for (int m = 0; m < n; m++)
        out[m] = 0.0f;
    for (int sy = 0; sy < ns; sy++) {
        const double dy = j + (sy + 0.5) * step - e->cy;
        double x0, x1;
        if (!support_chord(e, dy, &x0, &x1))
            continue;
        for (int sx = 0; sx < ns; sx++) {
            /* Sample m sits at dx = i0 + m + off - cx. */
            const double base = i0 + (sx + 0.5) * step - e->cx;
            double lo = ceil(x0 - base), hi = floor(x1 - base);
            int m0 = lo > 0 ? (lo < n ? (int)lo : n) : 0, m1 = hi < n - 1 ? (hi >= 0 ? (int)hi + 1 : 0) : n;
            if (m0 < m1)
                add_samples(poly, e, (float)dy, (float)base, m0, m1, out, ORR_SAMPLES_ADD, 1.0f);
        }
    }
    const float inv = 1.0f / (float)(ns * ns);
    for (int m = 0; m < n; m++)
        out[m] *= inv;
}

/* Calls row(j, i, n, weights) for every stretch of at most ROW_SEGMENT
 * pixels of the ellipse within the box. When the target drops pixels off
 * the map, their weights are zeroed first, so sums count only the map. */
typedef struct row_visitor {
    void (*fn)(struct row_visitor *v, int j, int i, int n, const float *wt);
} row_visitor;

static void ellipse_visit(const target *t, const ellipse *e, box b, row_visitor *v)
{
    orr_sample_poly poly;
    orr_sample_poly_make(&poly, t->kernel, e->lap);
    float wt[ROW_SEGMENT];
    for (int j = b.j0; j <= b.j1; j++) {
        int lo, hi;
        if (!ellipse_row_range(e, j, &lo, &hi))
            continue;
        lo = lo > b.i0 ? lo : b.i0;
        hi = hi < b.i1 ? hi : b.i1;
        for (int i = lo; i <= hi; i += ROW_SEGMENT) {
            int n = hi - i + 1 < ROW_SEGMENT ? hi - i + 1 : ROW_SEGMENT;
            ellipse_weights(&poly, e, j, i, n, wt);
            if (t->drop)
                for (int m = 0; m < n; m++)
                    if (!on_map(t, i + m, j))
                        wt[m] = 0.0f;
            v->fn(v, j, i, n, wt);
        }
    }
}

/* The sum of a row's weights, in eight partial sums so the additions
 * pipeline (and vectorise) instead of waiting on each other. */
static double row_sum(const float *wt, int n)
{
    float part[8] = {0};
    int m = 0;
    for (; m + 8 <= n; m += 8)
        for (int k = 0; k < 8; k++)
            part[k] += wt[m + k];
    float rest = 0.0f;
    for (; m < n; m++)
        rest += wt[m];
    return (double)rest + ((part[0] + part[1]) + (part[2] + part[3])) + ((part[4] + part[5]) + (part[6] + part[7]));
}

typedef struct summer {
    row_visitor v;
    double sum;
} summer;

static void sum_row(row_visitor *v, int j, int i, int n, const float *wt)
{
    (void)j, (void)i;
    ((summer *)v)->sum += row_sum(wt, n);
}

typedef struct drawer {
    row_visitor v;
    target *t;
    float scale[ORR_PLANES_MAX]; /* each plane's */
    int clipped;
    double drawn; /* sum of the weights drawn, kept only when clipped */
} drawer;

static void draw_row(row_visitor *v, int j, int i, int n, const float *wt)
{
    drawer *d = (drawer *)v;
    emit_row(d->t, j, i, n, wt, d->scale);
    if (d->clipped)
        d->drawn += row_sum(wt, n);
}

/* Footprints up to this many pixels are computed once into a buffer and
 * drawn from it; larger ones that need a sum are computed twice. */
#define BUFFERED_MAX 4096

typedef struct buffer {
    row_visitor v;
    float wt[BUFFERED_MAX];
    int row[BUFFERED_MAX / 4][3]; /* j, i, n of each stretch */
    int used, rows, full;
    double sum;
} buffer;

static void buffer_row(row_visitor *v, int j, int i, int n, const float *wt)
{
    buffer *b = (buffer *)v;
    if (b->full || b->used + n > BUFFERED_MAX || b->rows == BUFFERED_MAX / 4) {
        b->full = 1;
        return;
    }
    memcpy(b->wt + b->used, wt, sizeof(float) * (size_t)n);
    b->row[b->rows][0] = j, b->row[b->rows][1] = i, b->row[b->rows][2] = n;
    b->used += n;
    b->rows++;
    b->sum += row_sum(wt, n);
}

/* Deposits weight w[k] over the ellipse into plane k, normalised so the
 * whole footprint carries exactly w[k]. From 10 pixels per h the midpoint
 * sum over the footprint equals the table's integral (exactly 1 per unit
 * area, see splat/kernel.c) to 3 parts in 10^8, below float round-off
 * (measured over random centres for each kernel, docs/smoothing.md), so it
 * is used as is for a footprint wholly on the map, whether or not the
 * image's edge clips it (a clipped one then costs only its pixels on the
 * image). Others are summed first: from a buffer when the footprint is
 * small and whole, else by computing the weights twice. */
static int ellipse_deposit(target *t, const ellipse *e, const float *w)
{
    box b, full;
    if (!footprint(t, e->cx, e->cy, e->ex, e->ey, &b, &full))
        return 1;
    if (t->proj)
        t->fold = !box_on_map(t, b);
    const int clipped = b.i0 != full.i0 || b.i1 != full.i1 || b.j0 != full.j0 || b.j1 != full.j1;
    const int analytic = !t->fold && e->hmin >= 10.0;
    double sum = 1.0 / sqrt(e->a * e->c - e->b * e->b);
    if (!analytic && !clipped) {
        buffer buf; /* 28 KiB of stack */
        buf.v.fn = buffer_row;
        buf.used = buf.rows = buf.full = 0;
        buf.sum = 0.0;
        ellipse_visit(t, e, b, &buf.v);
        if (!buf.full) {
            if (!(buf.sum > 0))
                return 0;
            float scale[ORR_PLANES_MAX];
            plane_scales(t, w, buf.sum, scale);
            for (int r = 0, at = 0; r < buf.rows; at += buf.row[r][2], r++)
                emit_row(t, buf.row[r][0], buf.row[r][1], buf.row[r][2], buf.wt + at, scale);
            t->in += w[0];
            return 1;
        }
    }
    if (!analytic && !(clipped && (full.i1 - full.i0 + 1.0) * (full.j1 - full.j0 + 1.0) > 65536.0)) {
        summer sm = {{sum_row}, 0.0};
        ellipse_visit(t, e, full, &sm.v);
        sum = sm.sum;
    }
    if (!(sum > 0))
        return 0;
    drawer d = {{draw_row}, t, {0}, clipped, 0.0};
    plane_scales(t, w, sum, d.scale);
    ellipse_visit(t, e, b, &d.v);
    t->in += clipped ? d.drawn * d.scale[0] : w[0];
    return 1;
}

/* A disc kernel of h pixels as an ellipse. */
static void disc_ellipse(ellipse *e, double cx, double cy, double h)
{
    const double a = 1.0 / (h * h);
    ellipse_setup(e, cx, cy, a, 0.0, a);
}

/* A disc kernel of h pixels by whichever method suits its size, weight
 * w[k] into plane k (the fixed grids and the separable expansion draw flat
 * images, one plane). */
static void disc_deposit(target *t, double cx, double cy, double h, const float *w)
{
    if (h < CUMULATIVE_MAX) {
        const float fx = (float)cx, fy = (float)cy, fh = (float)h;
        flat_footprint f;
        if (!on_flat_image(t, fx, fy, fh, &f) ||
            !(disc_small(t, fx, fy, fh, w[0], &f) || disc_separable(t, fx, fy, fh, w[0], &f)))
            disc_cumulative(t, cx, cy, h, w);
        return;
    }
    ellipse e;
    disc_ellipse(&e, cx, cy, h);
    ellipse_deposit(t, &e, w);
}

/* ---- large kernels on flat images, band by band ----
 *
 * A kernel of 10 or more pixels per h adds into hundreds of pixels over
 * dozens of rows, and on an image larger than the core's cache every row
 * comes from memory: the image update was 40 % of a Plummer sphere's time
 * (docs/splash.md). So a block's large kernels are collected and drawn a
 * band of image rows (about BAND_BYTES) at a time, the band staying in
 * cache while every kernel crossing it is drawn there. Each pixel's weight
 * is its own midpoint sample, normalised analytically (ellipse_deposit),
 * so a kernel drawn in pieces has the same pixels as drawn at once; only
 * the order in which kernels add into a pixel changes, and that is set by
 * the block, not by the threads. */
#define BAND_BYTES (128 * 1024)
#define BAND_MIN_ROWS 8
/* Rows of a kernel's piece handed to orr_sample_spans_draw at once. */
#define SPANS 64

typedef struct large_kernel {
    double cx, cy, h;
    float w;
    int j0, j1; /* the image rows its footprint covers */
} large_kernel;

/* Room for a whole block's kernels: the fewer lists, the fewer passes
 * over the bands. */
typedef struct large_list {
    large_kernel *k;
    size_t n;
} large_list;

/* Rows j0 .. j1 of a large kernel's footprint. */
static void draw_large_piece(target *t, const large_kernel *k, int j0, int j1)
{
    ellipse e;
    disc_ellipse(&e, k->cx, k->cy, k->h);
    box b, full;
    if (!footprint(t, e.cx, e.cy, e.ex, e.ey, &b, &full))
        return;
    const int clipped = b.i0 != full.i0 || b.i1 != full.i1 || b.j0 != full.j0 || b.j1 != full.j1;
    /* A whole kernel lands whole: counted once, with its first piece. */
    if (!clipped && j0 <= b.j0 && b.j0 <= j1)
        t->in += k->w;
    b.j0 = b.j0 > j0 ? b.j0 : j0;
    b.j1 = b.j1 < j1 ? b.j1 : j1;
    if (b.j0 > b.j1)
        return;
    const float scale = (float)(k->w * sqrt(e.a * e.c - e.b * e.b));
    if (clipped) {
        drawer d = {{draw_row}, t, {scale}, 1, 0.0};
        ellipse_visit(t, &e, b, &d.v);
        t->in += d.drawn * d.scale[0];
        return;
    }
    /* Whole: nothing to add up, so each row's samples go straight into the
     * image (one sample a pixel, the centres inside the support), the rows
     * handed over SPANS at a time to be computed side by side. */
    orr_sample_poly poly;
    orr_sample_poly_make(&poly, t->kernel, e.lap);
    const int width = t->plane->width;
    const float a = (float)e.a, dx0 = (float)(0.5 - e.cx);
    orr_sample_span spans[SPANS];
    int n = 0;
    for (int j = b.j0; j <= b.j1; j++) {
        const double dy = j + 0.5 - e.cy;
        double x0, x1;
        if (!support_chord(&e, dy, &x0, &x1))
            continue;
        const double lo = ceil(e.cx + x0 - 0.5), hi = floor(e.cx + x1 - 0.5);
        const int m0 = lo > b.i0 ? (int)lo : b.i0, m1 = hi < b.i1 ? (int)hi + 1 : b.i1 + 1;
        if (m0 >= m1)
            continue;
        spans[n++] = ellipse_span(&e, (float)dy, m0, m1, t->plane->data + (size_t)j * (size_t)width);
        if (n == SPANS) {
            orr_sample_spans_draw(&poly, a, dx0, spans, n, scale);
            n = 0;
        }
    }
    orr_sample_spans_draw(&poly, a, dx0, spans, n, scale);
}

static void draw_large(target *t, large_list *list)
{
    const int width = t->plane->width;
    int rows = BAND_BYTES / (int)sizeof(float) / (width > 0 ? width : 1);
    rows = rows > BAND_MIN_ROWS ? rows : BAND_MIN_ROWS;
    int lo = t->plane->height, hi = -1;
    for (size_t k = 0; k < list->n; k++) {
        lo = list->k[k].j0 < lo ? list->k[k].j0 : lo;
        hi = list->k[k].j1 > hi ? list->k[k].j1 : hi;
    }
    for (int band = lo - lo % rows; band <= hi; band += rows)
        for (size_t k = 0; k < list->n; k++)
            if (list->k[k].j0 < band + rows && list->k[k].j1 >= band)
                draw_large_piece(t, &list->k[k], band, band + rows - 1);
    list->n = 0;
}

/* Adds a large kernel to the list, with the rows draw_large_piece will
 * find for it; kernels wholly off the image are dropped (nothing lands). */
static void defer_large(target *t, large_list *list, double cx, double cy, double h, float w)
{
    ellipse e;
    disc_ellipse(&e, cx, cy, h);
    box b, full;
    if (footprint(t, e.cx, e.cy, e.ex, e.ey, &b, &full))
        list->k[list->n++] = (large_kernel){cx, cy, h, w, b.j0, b.j1};
}

/* ---- sky maps: the local affine model ---- */

static double chord2(orr_vec3 a, orr_vec3 b)
{
    orr_vec3 d = orr_v3_sub(a, b);
    return orr_v3_dot(d, d);
}

/* The change of direction per pixel along x and y at (px, py), whose
 * direction is centre: one-sided differences over half a pixel, toward
 * whichever side is on the map. */
static int pixel_tangents(const orr_projection *p, double px, double py, orr_vec3 centre, orr_vec3 *tx,
                          orr_vec3 *ty)
{
    orr_vec3 d;
    for (int axis = 0; axis < 2; axis++) {
        double sx = axis == 0 ? 0.5 : 0.0, sy = axis == 0 ? 0.0 : 0.5;
        orr_vec3 *t = axis == 0 ? tx : ty;
        if (orr_unproject(p, px + sx, py + sy, &d))
            *t = orr_v3_scale(orr_v3_sub(d, centre), 2.0);
        else if (orr_unproject(p, px - sx, py - sy, &d))
            *t = orr_v3_scale(orr_v3_sub(centre, d), 2.0);
        else
            return 0;
    }
    return 1;
}

/* The solid angle of the pixel at direction d: the projection's scale at
 * unit distance is the isotropic pixels per radian there. */
static double pixel_solid_angle(const orr_sph *s, orr_vec3 d)
{
    if (s->omega > 0)
        return s->omega;
    double x, y, sc;
    if (!orr_project_point(&s->proj, d, &x, &y, &sc) || !(sc > 0))
        sc = s->proj.focal;
    return 1.0 / (sc * sc);
}

/* How the local affine model fits a kernel. */
typedef enum { AFFINE_NO, AFFINE_INSIDE, AFFINE_CROSSING } affine_fit;

/* Checks the model against the inverse projection at eight points of the
 * support's edge, for the distance to the centre and the pixels' solid
 * angle: AFFINE_INSIDE when all are on the map and within tolerance,
 * AFFINE_CROSSING when the ones on the map are (at least half of them) and
 * the rest are off it, AFFINE_NO otherwise. Off the equirectangular
 * image's sides a point is looked up across the seam, where the map
 * continues. */
static affine_fit affine_check(const orr_sph *s, const ellipse *e, orr_vec3 centre, double theta)
{
    const orr_projection *p = &s->proj;
    /* Points with u = 4 under the model: (dx, dy) = 2 R^-1 (cos phi, sin phi)
     * with M = R^T R (Cholesky). */
    double r11 = sqrt(e->a), r12 = e->b / r11, r22 = sqrt(e->c - r12 * r12);
    double omega = pixel_solid_angle(s, centre);
    double tol = fmax(AFFINE_TOL, 0.5 / e->hmin);
    int off = 0;
    for (int k = 0; k < 8; k++) {
        double cs = cos(k * ORR_PI / 4), sn = sin(k * ORR_PI / 4);
        double vy = sn / r22, vx = (cs - r12 * vy) / r11;
        double x = e->cx + ORR_KERNEL_SUPPORT * vx, y = e->cy + ORR_KERNEL_SUPPORT * vy;
        if (orr_projection_traits_of(p->settings.kind).wraps_longitude)
            x = x < 0 ? x + p->width : x > p->width ? x - p->width : x;
        orr_vec3 d;
        if (!orr_unproject(p, x, y, &d)) {
            off++;
            continue;
        }
        double q = sqrt(chord2(d, centre)) / theta;
        if (!(fabs(q - ORR_KERNEL_SUPPORT) <= tol) ||
            !(fabs(pixel_solid_angle(s, d) / omega - 1.0) <= AFFINE_AREA_TOL))
            return AFFINE_NO;
    }
    return off == 0 ? AFFINE_INSIDE : off <= 4 ? AFFINE_CROSSING : AFFINE_NO;
}

/* The local affine model of the map around the particle's image position:
 * u(dx, dy) = |tx dx + ty dy|^2 / theta^2 with tx, ty the direction's change
 * per pixel, every pixel with the solid angle of the centre's. Where the
 * map's index says the model holds over the whole support and the
 * footprint is on the map, it is taken as it is; elsewhere it is checked
 * (affine_check). */
static affine_fit sky_affine(const orr_sph *s, double px, double py, double theta, ellipse *e)
{
    const orr_projection *p = &s->proj;
    orr_vec3 centre, tx, ty;
    if (!orr_unproject(p, px, py, &centre) || !pixel_tangents(p, px, py, centre, &tx, &ty))
        return AFFINE_NO;
    double t2 = theta * theta;
    double a = orr_v3_dot(tx, tx) / t2, b = orr_v3_dot(tx, ty) / t2, c = orr_v3_dot(ty, ty) / t2;
    if (!(a * c - b * b > 0) || !(a > 0))
        return AFFINE_NO;
    ellipse_setup(e, px, py, a, b, c);
    /* Kernels a good part of the map across are no longer local. */
    if (!(e->ex < 0.25 * p->width && e->ey < 0.25 * p->height))
        return AFFINE_NO;
    int ci = (int)(px / ORR_SPH_CELL), cj = (int)(py / ORR_SPH_CELL);
    ci = ci < 0 ? 0 : ci >= s->cells_x ? s->cells_x - 1 : ci;
    cj = cj < 0 ? 0 : cj >= s->cells_y ? s->cells_y - 1 : cj;
    double reach = e->ex > e->ey ? e->ex : e->ey;
    box bb = {(int)floor(px - e->ex), (int)floor(px + e->ex), (int)floor(py - e->ey), (int)floor(py + e->ey)};
    if (reach <= s->safe[(size_t)cj * s->cells_x + ci] && box_in_map(p, bb))
        return AFFINE_INSIDE;
    return affine_check(s, e, centre, theta);
}

/* ---- sky maps: the PSF cores' stamps (splat/sky_cores.h) ---- */

int orr_sph_core_ellipse(const orr_sph *s, double px, double py, double theta, orr_sph_core_shape *shape)
{
    ellipse e;
    if (!s->sky || sky_affine(s, px, py, theta, &e) != AFFINE_INSIDE)
        return 0;
    *shape = (orr_sph_core_shape){e.a, e.b, e.c, e.ex, e.ey};
    return 1;
}

/* Rows of an ellipse's weights copied into a stamp whose pixel (0, 0) is
 * the image's (0, 0). */
typedef struct stamp_writer {
    row_visitor v;
    float *out;
    int width;
} stamp_writer;

static void stamp_row(row_visitor *v, int j, int i, int n, const float *wt)
{
    stamp_writer *sw = (stamp_writer *)v;
    memcpy(sw->out + (size_t)j * (size_t)sw->width + (size_t)i, wt, sizeof(float) * (size_t)n);
}

double orr_sph_core_stamp(const orr_sph *s, const orr_sph_core_shape *shape, double cx, double cy, int width,
                          int height, float *out)
{
    ellipse e;
    ellipse_setup(&e, cx, cy, shape->a, shape->b, shape->c);
    target t = {NULL, 1, NULL, s->kernel, 0, 0, 0.0, NULL};
    stamp_writer sw = {{stamp_row}, out, width};
    memset(out, 0, sizeof(float) * (size_t)width * (size_t)height);
    ellipse_visit(&t, &e, (box){0, width - 1, 0, height - 1}, &sw.v);
    double sum = 0.0;
    for (int j = 0; j < height; j++)
        sum += row_sum(out + (size_t)j * (size_t)width, width);
    return sum;
}

float orr_sph_affine_reach(const orr_sph *s, double px, double py)
{
    int ci = (int)(px / ORR_SPH_CELL), cj = (int)(py / ORR_SPH_CELL);
    if (!s->safe || ci < 0 || cj < 0 || ci >= s->cells_x || cj >= s->cells_y)
        return 0.0f;
    return s->safe[(size_t)cj * s->cells_x + ci];
}

/* ---- sky maps: the exact path ---- */

/* The cap of a kernel on the sphere of directions. */
typedef struct cap {
    orr_vec3 dir;
    double theta;        /* h / r */
    double cos_r, sin_r; /* of the support's angular radius */
    int all;             /* the support covers the whole sphere */
} cap;

/* Whether the cap can reach a tile: the angle between their centres is at
 * most the sum of their radii, cos(R + r) = cos R cos r - sin R sin r,
 * unless R + r reaches pi. */
static int reachable(const cap *c, const orr_sph_tile *t)
{
    if (!(t->cos_r <= 1.0f))
        return 0;
    if (c->all)
        return 1;
    double sin_sum = c->sin_r * t->cos_r + c->cos_r * t->sin_r, cos_sum = c->cos_r * t->cos_r - c->sin_r * t->sin_r;
    if (sin_sum < 0 || (sin_sum <= 0 && cos_sum < 0))
        return 1;
    double dot = t->x * c->dir.x + t->y * c->dir.y + t->z * c->dir.z;
    return dot >= cos_sum - 1e-6; /* the tiles' floats, with margin */
}

/* The direction of pixel (i, j)'s centre on an equirectangular map, from
 * the tables: the same products of the same sines and cosines as
 * orr_unproject forms, so the same bits. */
static orr_vec3 equirect_direction(const orr_sph *s, int i, int j)
{
    const double *lon = s->eq_lon + 2 * (size_t)i, *lat = s->eq_lat + 2 * (size_t)j;
    return orr_v3(lat[0] * lon[0], lat[1], lat[0] * lon[1]);
}

/* Weight of pixel (i, j) for the cap: F at the pixel's angular distance
 * (as a chord) times the pixel's solid angle, with the Laplacian term for
 * the pixel's size. 0 off the map and beyond the support. */
static double cap_pixel_weight(const orr_sph *s, const cap *c, int i, int j)
{
    orr_vec3 d;
    double omega;
    if (s->px_omega) {
        const size_t k = (size_t)j * s->proj.width + i;
        if (!((omega = s->px_omega[k]) > 0))
            return 0.0;
        d = orr_v3(s->px_dir[3 * k], s->px_dir[3 * k + 1], s->px_dir[3 * k + 2]);
    } else {
        if (!orr_projection_pixel_in_map(&s->proj, i, j) || !orr_unproject(&s->proj, i + 0.5, j + 0.5, &d))
            return 0.0;
        omega = pixel_solid_angle(s, d);
    }
    double u = chord2(d, c->dir) / (c->theta * c->theta);
    if (!(u < ORR_KERNEL_SUPPORT * ORR_KERNEL_SUPPORT))
        return 0.0;
    float lf;
    double f = orr_kernel_column_u(s->kernel, (float)u, &lf);
    return omega * (f + omega / (24.0 * c->theta * c->theta) * lf);
}

/* cap_pixel_weight for the ORR_SPH_TILE pixels from (i0, j) on of an
 * equirectangular map, from its tables (padded past the last column): the
 * same operations in the same order (equirect_direction, chord2,
 * orr_kernel_column_u), so the same bits, in loops of fixed length that
 * the compiler does in vector registers but for the table's reads (whose
 * index is clamped where the weight is 0 anyway). */
ORR_VECTOR_CLONES
static void equirect_row_weights(const orr_sph *s, const cap *c, int i0, int j, double *wt)
{
    enum { T = ORR_SPH_TILE };
    const double *lon = s->eq_lon + 2 * (size_t)i0, *omega = s->eq_omega + (size_t)j * s->proj.width + i0;
    const double cos_b = s->eq_lat[2 * (size_t)j], dy = s->eq_lat[2 * (size_t)j + 1] - c->dir.y;
    const double theta2 = c->theta * c->theta, lap_scale = 24.0 * c->theta * c->theta;
    double u[T];
    float t[T];
    int in[T];
    for (int k = 0; k < T; k++) {
        const double dx = cos_b * lon[2 * k] - c->dir.x, dz = cos_b * lon[2 * k + 1] - c->dir.z;
        u[k] = (dx * dx + dy * dy + dz * dz) / theta2;
        t[k] = (float)u[k] * (float)(ORR_KERNEL_NU / 4.0);
        in[k] = (u[k] < ORR_KERNEL_SUPPORT * ORR_KERNEL_SUPPORT) & (t[k] < (float)ORR_KERNEL_NU);
    }
    for (int k = 0; k < T; k++) {
        const int e = in[k] ? (int)t[k] : 0;
        const float x = t[k] - (float)e, *cf = s->kernel->column + 2 * e;
        const float lf = cf[1] + x * (cf[3] - cf[1]), f = cf[0] + x * (cf[2] - cf[0]);
        wt[k] = in[k] ? omega[k] * ((double)f + omega[k] / lap_scale * lf) : 0.0;
    }
}

/* cap_pixel_weight for the ORR_SPH_TILE pixels from (i0, j) on of a map
 * with per-pixel tables (the coarse glow's, whose widest kernels are
 * mapped pixel by pixel: 7 % of the 8K frame's CPU time at 2e6
 * particles): the same operations in the same order (the tables' direction
 * and solid angle, chord2, orr_kernel_column_u), so the same bits, in
 * loops of fixed length that the compiler does in vector registers.
 * Columns from n on (past the map's edge) read the row's last pixel; their
 * weights are not used. */
ORR_VECTOR_CLONES
static void table_row_weights(const orr_sph *s, const cap *c, int i0, int j, int n, double *wt)
{
    enum { T = ORR_SPH_TILE };
    const size_t base = (size_t)j * s->proj.width + i0;
    const double theta2 = c->theta * c->theta, lap_scale = 24.0 * c->theta * c->theta;
    double u[T], omega[T];
    float t[T];
    int in[T];
    for (int k = 0; k < T; k++) {
        const size_t at = base + (size_t)(k < n ? k : n - 1);
        const double *d = s->px_dir + 3 * at;
        const double dx = d[0] - c->dir.x, dy = d[1] - c->dir.y, dz = d[2] - c->dir.z;
        omega[k] = s->px_omega[at];
        u[k] = (dx * dx + dy * dy + dz * dz) / theta2;
        t[k] = (float)u[k] * (float)(ORR_KERNEL_NU / 4.0);
        in[k] = (omega[k] > 0) & (u[k] < ORR_KERNEL_SUPPORT * ORR_KERNEL_SUPPORT) & (t[k] < (float)ORR_KERNEL_NU);
    }
    for (int k = 0; k < T; k++) {
        const int e = in[k] ? (int)t[k] : 0;
        const float x = t[k] - (float)e, *cf = s->kernel->column + 2 * e;
        const float lf = cf[1] + x * (cf[3] - cf[1]), f = cf[0] + x * (cf[2] - cf[0]);
        wt[k] = in[k] ? omega[k] * ((double)f + omega[k] / lap_scale * lf) : 0.0;
    }
}

/* The weights of the pixels the cap reaches, collected once (when there is
 * memory to keep them) so they need not be computed twice. */
typedef struct cap_weights {
    size_t *pixel; /* index in the plane */
    float *weight;
    size_t n, room;
    int overflow; /* no memory: the caller computes the weights again */
} cap_weights;

static void cap_weights_add(cap_weights *cw, size_t pixel, double wt)
{
    if (cw->overflow)
        return;
    if (cw->n == cw->room) {
        size_t room = cw->room ? 2 * cw->room : 4096;
        size_t *p = realloc(cw->pixel, room * sizeof *p);
        if (p)
            cw->pixel = p;
        float *w = p ? realloc(cw->weight, room * sizeof *w) : NULL;
        if (w)
            cw->weight = w;
        if (!p || !w) {
            cw->overflow = 1;
            return;
        }
        cw->room = room;
    }
    cw->pixel[cw->n] = pixel;
    cw->weight[cw->n++] = (float)wt;
}

/* One pass over the pixels of every tile the cap can reach: returns the
 * sum of their weights, and either keeps them (cw) or adds scale times
 * each to the plane. */
static double cap_pass(const orr_sph *s, const cap *c, cap_weights *cw, orr_plane *plane, double scale)
{
    const int T = ORR_SPH_TILE, G = ORR_SPH_GROUP, W = s->proj.width, H = s->proj.height;
    double sum = 0.0;
    for (int gy = 0; gy < s->groups_y; gy++)
        for (int gx = 0; gx < s->groups_x; gx++) {
            if (!reachable(c, &s->groups[(size_t)gy * s->groups_x + gx]))
                continue;
            for (int ty = gy * G; ty < (gy + 1) * G && ty < s->tiles_y; ty++)
                for (int tx = gx * G; tx < (gx + 1) * G && tx < s->tiles_x; tx++) {
                    if (!reachable(c, &s->tiles[(size_t)ty * s->tiles_x + tx]))
                        continue;
                    const int i0 = tx * T, n = i0 + T < W ? T : W - i0;
                    for (int j = ty * T; j < (ty + 1) * T && j < H; j++) {
                        double wts[ORR_SPH_TILE];
                        if (s->eq_omega)
                            equirect_row_weights(s, c, i0, j, wts);
                        else if (s->px_omega)
                            table_row_weights(s, c, i0, j, n, wts);
                        else
                            for (int k = 0; k < n; k++)
                                wts[k] = cap_pixel_weight(s, c, i0 + k, j);
                        for (int k = 0; k < n; k++) {
                            const double wt = wts[k];
                            if (wt == 0.0)
                                continue;
                            sum += wt;
                            if (cw)
                                cap_weights_add(cw, (size_t)j * W + i0 + k, wt);
                            else
                                plane->data[(size_t)j * W + i0 + k] += (float)(scale * wt);
                        }
                    }
                }
        }
    return sum;
}

/* The exact path: every pixel the cap can reach, mapped back to its
 * direction. Returns 0 (nothing deposited) when no pixel centre on the map
 * lies inside the support. */
static int sky_exact(const orr_sph *s, target *t, orr_vec3 dir, double theta, const float *w)
{
    cap c = {dir, theta, 0, 0, theta >= 1.0};
    double r = c.all ? ORR_PI : 2.0 * asin(theta);
    c.cos_r = cos(r);
    c.sin_r = sin(r);
    cap_weights cw = {NULL, NULL, 0, 0, 0};
    double sum = cap_pass(s, &c, &cw, NULL, 0.0);
    for (int k = 0; k < t->nplanes && sum > 0; k++) {
        if (cw.overflow) {
            cap_pass(s, &c, NULL, &t->plane[k], w[k] / sum);
            continue;
        }
        const float scale = (float)(w[k] / sum);
        float *data = t->plane[k].data;
        for (size_t m = 0; m < cw.n; m++)
            data[cw.pixel[m]] += scale * cw.weight[m];
    }
    free(cw.pixel);
    free(cw.weight);
    return sum > 0;
}

/* A sky kernel of h_pix pixels (local isotropic scale). Small ones are
 * drawn flat with the local scale; larger ones with the local affine
 * model where it fits: wholly on the map; across the dome's rim (the
 * azimuthal-equidistant map continues smoothly there) dropping the part
 * off the map and renormalising the rest, as the exact path does; across
 * the equirectangular seam, where the map continues on the other side;
 * across the Hammer-Aitoff seam only while small (under 4 pixels per h),
 * folded to the other side, because the map's edge there is sheared
 * differently on the two sides. Everything else is mapped pixel by pixel.
 * Weight w[k] goes into plane k. */
static void sky_particle(const orr_sph *s, target *t, const orr_sph_block *b, size_t i, double hpix, const float *w)
{
    const double px = b->px[i], py = b->py[i];
    t->fold = t->drop = 0;
    if (hpix < SKY_LOCAL_MIN || !b->x || !b->y || !b->z) {
        disc_deposit(t, px, py, hpix, w);
        return;
    }
    orr_vec3 pos = orr_v3(b->x[i], b->y[i], b->z[i]);
    double r = orr_v3_norm(pos);
    double theta = b->h[i] / r;
    if (s->cores && orr_sky_cores_draw_planes(s->cores, s, px, py, theta, w, t->plane, t->nplanes))
        return;
    ellipse e;
    affine_fit fit = theta < 0.5 ? sky_affine(s, px, py, theta, &e) : AFFINE_NO;
    if (fit == AFFINE_CROSSING) {
        const orr_projection_traits proj = orr_projection_traits_of(s->proj.settings.kind);
        if (proj.rim)
            t->drop = 1;
        else if (!(proj.sheared_seam && e.hmin < 4.0))
            fit = AFFINE_NO;
    }
    if (fit != AFFINE_NO && ellipse_deposit(t, &e, w))
        return;
    t->fold = t->drop = 0;
    if (sky_exact(s, t, orr_v3_scale(pos, 1.0 / r), theta, w))
        return;
    /* No pixel centre on the map within the support (a kernel at the
     * map's edge, between centres): drawn small where it projects. */
    disc_deposit(t, px, py, fmin(hpix, SKY_LOCAL_MIN), w);
}

/* ---- sky maps: the index ---- */

/* The extent of the pixels [i0, i1) x [j0, j1) on the map: the direction
 * at their centre and the angle r within which all their centres lie.
 * Wholly on the map, a tile's 3 x 3 corner, edge and centre pixels are
 * measured and r enlarged by a tenth, which covers the pixels between on
 * any of the maps over 8 pixels; crossing the map's outline, every pixel
 * is. Returns 0 when no pixel is on the map. */
static int tile_extent(const orr_projection *p, int i0, int i1, int j0, int j1, orr_sph_tile *t)
{
    box b = {i0, i1 - 1, j0, j1 - 1};
    const int whole = box_in_map(p, b);
    /* Whole: columns i0, the middle and i1 - 1 (likewise rows); else all. */
    const int ni = whole ? 3 : i1 - i0, nj = whole ? 3 : j1 - j0;
    orr_vec3 d[ORR_SPH_TILE * ORR_SPH_TILE], sum = orr_v3(0, 0, 0);
    int n = 0;
    for (int sj = 0; sj < nj; sj++)
        for (int si = 0; si < ni; si++) {
            int i = whole ? (si == 0 ? i0 : si == 1 ? (i0 + i1 - 1) / 2 : i1 - 1) : i0 + si;
            int j = whole ? (sj == 0 ? j0 : sj == 1 ? (j0 + j1 - 1) / 2 : j1 - 1) : j0 + sj;
            if (orr_projection_pixel_in_map(p, i, j) && orr_unproject(p, i + 0.5, j + 0.5, &d[n]))
                sum = orr_v3_add(sum, d[n++]);
        }
    if (n == 0)
        return 0;
    orr_vec3 c = orr_v3_normalize(sum);
    double far = 0.0;
    for (int k = 0; k < n; k++)
        far = fmax(far, chord2(d[k], c));
    double r = fmin(ORR_PI, 2.0 * asin(fmin(1.0, 0.5 * sqrt(far))) * (whole ? 1.1 : 1.0) + 1e-5);
    *t = (orr_sph_tile){(float)c.x, (float)c.y, (float)c.z, (float)cos(r), (float)sin(r)};
    return 1;
}

/* A coarse tile from its tiles: the mean direction, and the largest angle
 * to a tile's centre plus that tile's radius. */
static void group_extent(const orr_sph *s, int gx, int gy, orr_sph_tile *g)
{
    const int G = ORR_SPH_GROUP;
    orr_vec3 sum = orr_v3(0, 0, 0);
    int any = 0;
    for (int pass = 0; pass < 2; pass++) {
        double r = 0.0;
        for (int ty = gy * G; ty < (gy + 1) * G && ty < s->tiles_y; ty++)
            for (int tx = gx * G; tx < (gx + 1) * G && tx < s->tiles_x; tx++) {
                const orr_sph_tile *t = &s->tiles[(size_t)ty * s->tiles_x + tx];
                if (!(t->cos_r <= 1.0f))
                    continue;
                orr_vec3 d = orr_v3(t->x, t->y, t->z);
                if (pass == 0) {
                    sum = orr_v3_add(sum, d);
                    any = 1;
                } else {
                    double a = 2.0 * asin(fmin(1.0, 0.5 * sqrt(chord2(d, orr_v3(g->x, g->y, g->z)))));
                    r = fmax(r, a + atan2(t->sin_r, t->cos_r));
                }
            }
        if (pass == 0) {
            orr_vec3 c = orr_v3_normalize(sum);
            *g = (orr_sph_tile){(float)c.x, (float)c.y, (float)c.z, 2.0f, 0.0f};
            if (!any)
                return;
        } else {
            r = fmin(ORR_PI, r + 1e-5);
            g->cos_r = (float)cos(r);
            g->sin_r = (float)sin(r);
        }
    }
}

/* The map's local metric at pixel position (x, y): the squared changes of
 * direction per pixel (a = |tx|^2, b = tx.ty, c = |ty|^2) and the solid
 * angle per pixel |tx x ty|; 0 when not wholly on the map. */
static int metric_at(const orr_projection *p, double x, double y, double m[4])
{
    orr_vec3 xp, xm, yp, ym;
    if (!orr_unproject(p, x + 0.5, y, &xp) || !orr_unproject(p, x - 0.5, y, &xm) ||
        !orr_unproject(p, x, y + 0.5, &yp) || !orr_unproject(p, x, y - 0.5, &ym))
        return 0;
    orr_vec3 tx = orr_v3_sub(xp, xm), ty = orr_v3_sub(yp, ym);
    m[0] = orr_v3_dot(tx, tx);
    m[1] = orr_v3_dot(tx, ty);
    m[2] = orr_v3_dot(ty, ty);
    m[3] = orr_v3_norm(orr_v3_cross(tx, ty));
    return m[0] > 0 && m[2] > 0 && m[3] > 0;
}

/* The relative change of the metric (dm) and of the pixels' solid angle
 * (da) between two neighbouring grid points. */
static void metric_change(const double *m, const double *n, float *dm, float *da)
{
    double scale = sqrt(m[0] * m[2]);
    double d = fmax(fabs(log(n[0] / m[0])), fmax(fabs(log(n[2] / m[2])), fabs(n[1] - m[1]) / scale));
    *dm = (float)fmax(*dm, d);
    *da = (float)fmax(*da, fabs(log(n[3] / m[3])));
}

/* Per cell, how far the local affine model may reach: the metric is
 * sampled on a grid of ORR_SPH_CELL pixels; within two cells of a cell its
 * largest change between neighbouring samples, per pixel, bounds how far
 * the model stays within AFFINE_TOL in q and AFFINE_AREA_TOL in area (as
 * the per-particle check measures them), up to the two cells the samples
 * cover. Cells near the map's outline get 0: always checked. */
static orr_status build_cells(orr_sph *s, orr_error *err)
{
    const int C = ORR_SPH_CELL, W = s->proj.width, H = s->proj.height;
    const int nx = s->cells_x + 1, ny = s->cells_y + 1;
    const size_t ng = (size_t)nx * ny;
    double *grid = orr_malloc(sizeof(double) * 4 * ng, "sky metric grid", err);
    float *dm = orr_calloc(ng, sizeof(float), "sky metric grid", err);
    float *da = orr_calloc(ng, sizeof(float), "sky metric grid", err);
    uint8_t *ok = orr_malloc(ng, "sky metric grid", err);
    orr_status st = grid && dm && da && ok ? ORR_OK : ORR_ERR_NOMEM;
    if (!st) /* each grid point alone */
#pragma omp parallel for schedule(static)
        for (size_t g = 0; g < ng; g++) {
            double x = clamp((double)(g % nx) * C, 1.0, W - 1.0), y = clamp((double)(g / nx) * C, 1.0, H - 1.0);
            ok[g] = (uint8_t)metric_at(&s->proj, x, y, grid + 4 * g);
        }
    /* Each grid point's changes toward its right and lower neighbours. */
    for (size_t g = 0; !st && g < ng; g++) {
        if (!ok[g])
            continue;
        if (g % nx + 1 < (size_t)nx && ok[g + 1])
            metric_change(grid + 4 * g, grid + 4 * (g + 1), &dm[g], &da[g]);
        if (g / nx + 1 < (size_t)ny && ok[g + nx])
            metric_change(grid + 4 * g, grid + 4 * (g + nx), &dm[g], &da[g]);
    }
    for (int cy = 0; !st && cy < s->cells_y; cy++)
        for (int cx = 0; cx < s->cells_x; cx++) {
            float gm = 0.0f, ga = 0.0f;
            int whole = cx >= 2 && cy >= 2 && cx + 3 < nx && cy + 3 < ny;
            for (int gy = cy - 2; whole && gy <= cy + 3; gy++)
                for (int gx = cx - 2; gx <= cx + 3; gx++) {
                    size_t g = (size_t)gy * nx + gx;
                    whole &= ok[g];
                    gm = dm[g] > gm ? dm[g] : gm;
                    ga = da[g] > ga ? da[g] : ga;
                }
            /* A relative change g per pixel in the squared lengths moves the
             * support's edge by about g R / 4 of q = 2 at radius R. */
            double reach = 2.0 * C;
            if (gm > 0)
                reach = fmin(reach, 2.0 * AFFINE_TOL * C / gm);
            if (ga > 0)
                reach = fmin(reach, AFFINE_AREA_TOL * C / ga);
            s->safe[(size_t)cy * s->cells_x + cx] = whole ? (float)reach : 0.0f;
        }
    free(grid);
    free(dm);
    free(da);
    free(ok);
    return st;
}

/* Whether the map is equal-area (Hammer-Aitoff): the pixels' solid angle,
 * from the projection's scale, the same at a spread of points. */
static double equal_area_omega(const orr_projection *p)
{
    double lo = HUGE_VAL, hi = 0.0;
    for (int k = 0; k < 64; k++) {
        /* Points scattered over the image (a Lissajous figure). */
        double x = p->width * (0.5 + 0.45 * cos(k * 2.4)), y = p->height * (0.5 + 0.45 * sin(k * 1.7)), sc;
        orr_vec3 d;
        if (!orr_unproject(p, x, y, &d) || !orr_project_point(p, d, &x, &y, &sc))
            continue;
        lo = fmin(lo, 1.0 / (sc * sc));
        hi = fmax(hi, 1.0 / (sc * sc));
    }
    return hi > 0 && hi <= lo * (1 + 1e-9) ? hi : 0.0;
}

/* The equirectangular map's tables (orr_sph.eq_*): a column's direction
 * on the equator (b = 0) is (-sin l, 0, cos l) and a row's on the central
 * meridian (l = 0) is (0, -sin b, cos b), both from orr_unproject itself;
 * pixel (i, j)'s direction is then their products, and its solid angle
 * what pixel_solid_angle gives for that direction (the scale's last bits
 * vary along a row, so it is kept per pixel, 8 bytes each). */
static orr_status build_equirect_tables(orr_sph *s, orr_error *err)
{
    const orr_projection *p = &s->proj;
    const int W = p->width, H = p->height;
    /* Padded by a tile's row, which equirect_row_weights reads past the last column. */
    s->eq_lon = orr_calloc(2 * ((size_t)W + ORR_SPH_TILE), sizeof(double), "equirectangular pixel directions", err);
    s->eq_lat = orr_malloc(sizeof(double) * 2 * (size_t)H, "equirectangular pixel directions", err);
    double *omega = orr_calloc((size_t)W * H + ORR_SPH_TILE, sizeof(double), "equirectangular pixel solid angles", err);
    if (!s->eq_lon || !s->eq_lat || !omega) {
        free(omega);
        return ORR_ERR_NOMEM;
    }
    orr_vec3 d;
    for (int i = 0; i < W; i++) {
        orr_unproject(p, i + 0.5, p->cy, &d);
        s->eq_lon[2 * i] = d.x, s->eq_lon[2 * i + 1] = d.z;
    }
    for (int j = 0; j < H; j++) {
        orr_unproject(p, p->cx, j + 0.5, &d);
        s->eq_lat[2 * j] = d.z, s->eq_lat[2 * j + 1] = d.y;
    }
    s->eq_omega = omega; /* set before use: equirect_direction reads the tables */
    for (int j = 0; j < H; j++)
        for (int i = 0; i < W; i++)
            omega[(size_t)j * W + i] = pixel_solid_angle(s, equirect_direction(s, i, j));
    return ORR_OK;
}

/* The pixel tables of a small sky map (orr_sph.px_*): what cap_pixel_weight
 * would compute for each pixel, once. A pixel off the map, or whose centre
 * maps to no direction, gets solid angle 0, which the weight reads as
 * "nothing here", as it reads those tests. */
static orr_status build_pixel_tables(orr_sph *s, orr_error *err)
{
    const orr_projection *p = &s->proj;
    const int W = p->width, H = p->height;
    s->px_dir = orr_malloc(3 * sizeof(double) * (size_t)W * H, "sky map pixel directions", err);
    s->px_omega = s->px_dir ? orr_malloc(sizeof(double) * (size_t)W * H, "sky map pixel solid angles", err) : NULL;
    if (!s->px_omega)
        return ORR_ERR_NOMEM;
#pragma omp parallel for schedule(static)
    for (int j = 0; j < H; j++)
        for (int i = 0; i < W; i++) {
            const size_t k = (size_t)j * W + i;
            orr_vec3 d = orr_v3(0, 0, 0);
            int on = orr_projection_pixel_in_map(p, i, j) && orr_unproject(p, i + 0.5, j + 0.5, &d);
            s->px_dir[3 * k] = d.x, s->px_dir[3 * k + 1] = d.y, s->px_dir[3 * k + 2] = d.z;
            s->px_omega[k] = on ? pixel_solid_angle(s, d) : 0.0;
        }
    return ORR_OK;
}

/* The map's run of pixels on it, row by row (orr_sph.row_on_map): maps
 * with an outline only, whose footprints crossing it test their pixels. */
static orr_status build_row_runs(orr_sph *s, orr_error *err)
{
    const int H = s->proj.height;
    if (!orr_projection_traits_of(s->proj.settings.kind).elliptic_map)
        return ORR_OK;
    s->row_on_map = orr_malloc(2 * sizeof *s->row_on_map * (size_t)H, "sky map outline", err);
    if (!s->row_on_map)
        return ORR_ERR_NOMEM;
    for (int j = 0; j < H; j++)
        orr_projection_row_in_map(&s->proj, j, &s->row_on_map[2 * j], &s->row_on_map[2 * j + 1]);
    return ORR_OK;
}

static orr_status build_sky_index(orr_sph *s, orr_error *err)
{
    const int T = ORR_SPH_TILE, G = ORR_SPH_GROUP, W = s->proj.width, H = s->proj.height;
    s->omega = equal_area_omega(&s->proj);
    s->tiles_x = (W + T - 1) / T, s->tiles_y = (H + T - 1) / T;
    s->groups_x = (s->tiles_x + G - 1) / G, s->groups_y = (s->tiles_y + G - 1) / G;
    s->cells_x = (W + ORR_SPH_CELL - 1) / ORR_SPH_CELL, s->cells_y = (H + ORR_SPH_CELL - 1) / ORR_SPH_CELL;
    s->tiles = orr_malloc(sizeof *s->tiles * (size_t)s->tiles_x * s->tiles_y, "sky tile index", err);
    s->groups = orr_malloc(sizeof *s->groups * (size_t)s->groups_x * s->groups_y, "sky tile index", err);
    s->safe = orr_malloc(sizeof *s->safe * (size_t)s->cells_x * s->cells_y, "sky cell index", err);
    if (!s->tiles || !s->groups || !s->safe)
        return ORR_ERR_NOMEM;
    /* Each tile alone (its edge tiles, crossing the map's outline, map every
     * pixel): the threads share the rows of tiles, each writing its own. */
#pragma omp parallel for schedule(dynamic, 4)
    for (int ty = 0; ty < s->tiles_y; ty++)
        for (int tx = 0; tx < s->tiles_x; tx++) {
            orr_sph_tile *t = &s->tiles[(size_t)ty * s->tiles_x + tx];
            *t = (orr_sph_tile){0, 0, 1, 2.0f, 0.0f};
            tile_extent(&s->proj, tx * T, (tx + 1) * T < W ? (tx + 1) * T : W, ty * T,
                        (ty + 1) * T < H ? (ty + 1) * T : H, t);
        }
    for (int gy = 0; gy < s->groups_y; gy++)
        for (int gx = 0; gx < s->groups_x; gx++)
            group_extent(s, gx, gy, &s->groups[(size_t)gy * s->groups_x + gx]);
    orr_status st = build_cells(s, err);
    if (!st)
        st = build_row_runs(s, err);
    if (!st && s->proj.settings.kind == ORR_PROJ_EQUIRECTANGULAR)
        st = build_equirect_tables(s, err);
    else if (!st && (size_t)W * H <= ORR_SPH_PIXEL_TABLE_MAX)
        st = build_pixel_tables(s, err);
    return st;
}

/* ---- the interface ---- */

orr_status orr_sph_init(orr_sph *s, const orr_kernel *k, const orr_projection *proj, orr_error *err)
{
    memset(s, 0, sizeof *s);
    s->kernel = k;
    s->proj = *proj;
    s->sky = orr_projection_is_sky(proj);
    if (orr_projection_traits_of(proj->settings.kind).pixel_table) { /* HEALPix has its own search: healpix_deposit */
        s->healpix_budget = orr_calloc(1, sizeof *s->healpix_budget, "HEALPix work limit", err);
        if (s->healpix_budget)
            orr_healpix_budget_start(s->healpix_budget, UINT64_MAX, 0);
        return s->healpix_budget ? ORR_OK : ORR_ERR_NOMEM;
    }
    if (!s->sky)
        return ORR_OK;
    orr_status st = build_sky_index(s, err);
    if (st)
        orr_sph_free(s);
    return st;
}

orr_status orr_sph_use_cores(orr_sph *s, double theta, orr_error *err)
{
    if (!s->sky)
        return ORR_OK;
    orr_sky_cores_free(s->cores);
    return orr_sky_cores_create(&s->cores, s, theta, err);
}

void orr_sph_free(orr_sph *s)
{
    orr_sky_cores_free(s->cores);
    s->cores = NULL;
    free(s->healpix_budget);
    s->healpix_budget = NULL;
    free(s->tiles);
    free(s->groups);
    free(s->safe);
    free(s->eq_lon);
    free(s->eq_lat);
    free(s->eq_omega);
    free(s->px_dir);
    free(s->px_omega);
    free(s->row_on_map);
    s->row_on_map = NULL;
    s->px_dir = s->px_omega = NULL;
    s->tiles = s->groups = NULL;
    s->safe = NULL;
    s->eq_lon = s->eq_lat = s->eq_omega = NULL;
}

/* Particles without a smoothing length: cloud-in-cell, as orr_deposit;
 * weight w[k] into plane k. */
static void deposit_cic_one(const orr_sph *s, const orr_sph_block *b, size_t i, target *t, const float *w)
{
    uint8_t one = 1;
    for (int k = 0; k < t->nplanes; k++) {
        orr_deposit_stats st = {0};
        orr_deposit(ORR_DEPOSIT_CIC, &t->plane[k], 1, b->px + i, b->py + i, w + k, &one, &s->proj, &st);
        if (k == 0)
            t->in += st.deposited;
    }
}

/* A block's weight as orr_deposit_stats counts it: the visible particles'
 * and the culled ones'. */
typedef struct block_tally {
    double total, culled;
    uint64_t n_culled;
} block_tally;

/* Counts particle i; 1 when it is to be drawn. */
static int tally_visible(const orr_sph_block *b, size_t i, block_tally *t)
{
    if (!b->visible[i]) {
        t->culled += b->w[i];
        t->n_culled++;
        return 0;
    }
    t->total += b->w[i];
    return 1;
}

static void add_tally(orr_deposit_stats *stats, const block_tally *t, size_t n)
{
    stats->culled += t->culled;
    stats->n_culled += t->n_culled;
    stats->n_particles += n;
}

/* The camera-frame distance of a block's particle i (0 without positions). */
static double particle_distance(const orr_sph_block *b, size_t i)
{
    return b->x && b->y && b->z
               ? sqrt((double)b->x[i] * b->x[i] + (double)b->y[i] * b->y[i] + (double)b->z[i] * b->z[i])
               : 0.0;
}

/* The block's kernel samples estimated before any is drawn, so that a
 * frame far beyond the work limit is refused at its first block. */
static int foresee_healpix_work(const orr_sph *s, const orr_sph_block *b)
{
    if (!s->healpix_budget)
        return 1;
    uint64_t samples = 0;
    for (size_t i = 0; i < b->n; i++) {
        const double h = b->h ? b->h[i] : 0.0, r = particle_distance(b, i);
        if (b->visible[i] && h > 0 && isfinite(h) && r > 0)
            samples += orr_healpix_kernel_cost(s->proj.settings.healpix_nside, h / r);
    }
    return orr_healpix_budget_foresee(s->healpix_budget, samples, b->n);
}

/* A HEALPix map (splat/healpix_kernel.h): each kernel integrated over the
 * map's own pixels; a particle without a smoothing length goes whole into
 * its pixel, as deposit: ngp puts it. */
static void healpix_deposit(const orr_sph *s, const orr_sph_block *b, orr_plane *plane, orr_deposit_stats *stats)
{
    const orr_projection_settings *map = &s->proj.settings;
    const orr_healpix_target t = {s->kernel, map->healpix_nside, map->healpix_nested, plane->data, s->healpix_budget};
    orr_healpix_scratch scratch = {0};
    block_tally tally = {0};
    if (!foresee_healpix_work(s, b))
        return; /* beyond the frame's work limit: it is refused */
    for (size_t i = 0; i < b->n; i++) {
        if (!tally_visible(b, i, &tally))
            continue;
        const double h = b->h ? b->h[i] : 0.0;
        const double r = particle_distance(b, i);
        if (h > 0 && isfinite(h) && r > 0) {
            /* HEALPix's frame (frame/projection.h): the pole the camera's up (-y), phi = 0 its view (+z). */
            const double dir[3] = {b->z[i] / r, -b->x[i] / r, -b->y[i] / r};
            int done = orr_healpix_kernel_deposit(&t, dir, h / r, b->w[i], &scratch);
            if (done < 0)
                break; /* beyond the frame's work limit: it is refused */
            if (done)
                continue;
        }
        orr_deposit_stats one_stats = {0};
        uint8_t one = 1;
        orr_deposit(ORR_DEPOSIT_NGP, plane, 1, b->px + i, b->py + i, b->w + i, &one, &s->proj, &one_stats);
    }
    orr_healpix_scratch_free(&scratch);
    stats->deposited += tally.total; /* the whole sky: nothing falls off */
    add_tally(stats, &tally, b->n);
}

/* A block's kernels land anywhere on the image, and a 1024^2 image is
 * twice a core's L2 cache, so the rows of a small kernel's footprint are
 * mostly misses: they are asked for PREFETCH_AHEAD particles ahead.
 * Kernels of the fixed grids only (support under PREFETCH_SUPPORT pixels:
 * at most 9 rows); larger ones ask for their own rows (separable_draw). */
#define PREFETCH_AHEAD 4
#define PREFETCH_SUPPORT 4.0f
static void prefetch_footprint(const orr_plane *plane, const orr_sph_block *b, size_t i)
{
    if (!b->visible[i])
        return;
    const float r = (float)ORR_KERNEL_SUPPORT * b->h[i] * b->scale[i], px = b->px[i], py = b->py[i];
    if (!(r < PREFETCH_SUPPORT && px - r >= 0.0f && py - r >= 0.0f && px + r < (float)plane->width &&
          py + r < (float)plane->height))
        return;
    const int i0 = (int)(px - r), i1 = (int)(px + r), j1 = (int)(py + r);
    for (int j = (int)(py - r); j <= j1; j++) {
        const float *row = plane->data + (size_t)j * (size_t)plane->width;
        ORR_PREFETCH_FOR_WRITE(row + i0);
        ORR_PREFETCH_FOR_WRITE(row + i1);
    }
}

void orr_sph_deposit(const orr_sph *s, const orr_sph_block *b, orr_plane *plane, orr_deposit_stats *stats)
{
    if (orr_projection_traits_of(s->proj.settings.kind).pixel_table) {
        healpix_deposit(s, b, plane, stats);
        return;
    }
    if (!b->h) {
        orr_deposit(ORR_DEPOSIT_CIC, plane, b->n, b->px, b->py, b->w, b->visible, &s->proj, stats);
        return;
    }
    target t = {plane, 1, s->sky ? &s->proj : NULL, s->kernel, 0, 0, 0.0, s->sky ? s->row_on_map : NULL};
    /* Without memory for the list, large kernels are drawn one by one. */
    large_list list = {s->sky || !b->n ? NULL : malloc(b->n * sizeof *list.k), 0};
    block_tally tally = {0};
    for (size_t i = 0; i < b->n; i++) {
        if (!s->sky && i + PREFETCH_AHEAD < b->n)
            prefetch_footprint(plane, b, i + PREFETCH_AHEAD);
        if (!tally_visible(b, i, &tally))
            continue;
        double hpix = (double)b->h[i] * b->scale[i];
        if (!(hpix > 0) || !isfinite(hpix))
            deposit_cic_one(s, b, i, &t, &b->w[i]);
        else if (s->sky)
            sky_particle(s, &t, b, i, hpix, &b->w[i]);
        else if (list.k && hpix >= CUMULATIVE_MAX)
            defer_large(&t, &list, b->px[i], b->py[i], hpix, b->w[i]);
        else
            disc_deposit(&t, b->px[i], b->py[i], hpix, &b->w[i]);
    }
    draw_large(&t, &list);
    free(list.k);
    /* Flat maps: what did not land fell off the image. Sky maps fold
     * everything onto the map (the difference is round-off). */
    stats->deposited += s->sky ? tally.total : t.in;
    stats->outside += s->sky ? 0.0 : tally.total - t.in;
    add_tally(stats, &tally, b->n);
}

/* Stars land anywhere on the map, so every row of a core's stamp is a
 * cache miss in each plane: the next star's rows (the automatic core
 * reaches about 7 pixels either side) are asked for while this one is
 * drawn. */
#define PREFETCH_REACH 7
static void prefetch_core(float px, float py, orr_plane *planes, int nplanes)
{
    const int w = planes[0].width, h = planes[0].height;
    if (!(px >= 0 && py >= 0 && px < w && py < h))
        return;
    const int ix = (int)px, iy = (int)py;
    const int i0 = ix > PREFETCH_REACH ? ix - PREFETCH_REACH : 0;
    const int i1 = ix + PREFETCH_REACH < w ? ix + PREFETCH_REACH : w - 1;
    const int j0 = iy > PREFETCH_REACH ? iy - PREFETCH_REACH : 0;
    const int j1 = iy + PREFETCH_REACH < h ? iy + PREFETCH_REACH : h - 1;
    for (int k = 0; k < nplanes; k++)
        for (int j = j0; j <= j1; j++) {
            const float *row = planes[k].data + (size_t)j * w;
            ORR_PREFETCH_FOR_WRITE(row + i0);
            ORR_PREFETCH_FOR_WRITE(row + i1);
        }
}

void orr_sph_deposit_planes(const orr_sph *s, const orr_sph_block *b, const float *const *w, orr_plane *planes,
                            int nplanes, orr_deposit_stats *stats)
{
    orr_sph_block one[ORR_PLANES_MAX];
    for (int k = 0; k < nplanes && k < ORR_PLANES_MAX; k++) {
        one[k] = *b;
        one[k].w = w[k];
    }
    if (!s->sky || !b->h || !b->x || !b->y || !b->z || nplanes < 2 || nplanes > ORR_PLANES_MAX ||
        orr_projection_traits_of(s->proj.settings.kind).pixel_table) {
        for (int k = 0; k < nplanes; k++)
            orr_sph_deposit(s, &one[k], &planes[k], &stats[k]);
        return;
    }
    /* Plane k sees the kernels in the same order, drawn the same way, as
     * orr_sph_deposit would draw them: the same bits. Only the footprint's
     * weights (the affine model, the kernel's samples, the exact path's
     * pixels, the star table's look-up) are found once for all planes. */
    target t = {planes, nplanes, &s->proj, s->kernel, 0, 0, 0.0, s->row_on_map};
    block_tally tally[ORR_PLANES_MAX];
    memset(tally, 0, sizeof tally);
    for (size_t i = 0; i < b->n; i++) {
        if (s->cores && i + 1 < b->n && b->visible[i + 1])
            prefetch_core(b->px[i + 1], b->py[i + 1], planes, nplanes);
        int visible = 0;
        for (int k = 0; k < nplanes; k++)
            visible = tally_visible(&one[k], i, &tally[k]);
        if (!visible)
            continue;
        float wi[ORR_PLANES_MAX];
        for (int k = 0; k < nplanes; k++)
            wi[k] = w[k][i];
        const double hpix = (double)b->h[i] * b->scale[i];
        if (!(hpix > 0) || !isfinite(hpix))
            deposit_cic_one(s, b, i, &t, wi);
        else
            sky_particle(s, &t, b, i, hpix, wi);
    }
    for (int k = 0; k < nplanes; k++) {
        stats[k].deposited += tally[k].total; /* the whole sky: nothing falls off */
        add_tally(&stats[k], &tally[k], b->n);
    }
}
