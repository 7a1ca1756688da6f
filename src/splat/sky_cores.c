#include "splat/sky_cores.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "splat/sph.h"

#define STEPS ORR_SKY_CORE_STEPS
#define NODES (STEPS + 1)
/* Stamps reaching further than this many pixels from the star's own are
 * not made (the automatic core reaches about 6, 9 where a dome stretches
 * it): such kernels are drawn one by one. */
#define MAX_REACH 24
/* A particle's kernel is the core when its angle is the core's to this:
 * h = sqrt(0 + k^2 r^2) divided by r again is the core's angle to float
 * rounding (~1e-7); a smoothing length of its own that widens the core by
 * less than 1e-5 changes nothing visible. */
#define SAME_THETA 1e-5
/* A cell's stamps are made with the ellipse at its centre; where the map's
 * distortion changes the ellipse by more than this (relative to its size)
 * between the centre and a corner, its stars are drawn one by one. A star's
 * peak scales with the ellipse's area, so this bounds the table's pixel
 * error to about this fraction of the star's peak (measured with
 * bench_sky_cores: docs/psf.md). */
#define SHAPE_TOL 0.05

/* One cell's stamps: the star's pixel and rx, ry pixels either side. */
typedef struct core_cell {
    int rx, ry;
    double reach;   /* the ellipse's larger half-extent, pixels */
    size_t size;    /* floats a stamp: (2 rx + 1)(2 ry + 1), row by row */
    float stamps[]; /* NODES x NODES stamps: node (i, j) is offset (i, j) / STEPS in the star's pixel */
} core_cell;

/* Cells come in two sizes: blocks of ORR_SKY_CORE_CELL pixels, and where
 * the map's distortion changes too fast across a block (the
 * Hammer-Aitoff's shear away from its centre, a dome's rim) cells of half
 * that, each with its own stamps. Each fine cell points at its block's
 * stamps, at its own, or at &unusable. */
typedef struct grid {
    int size, nx, ny;
    core_cell **cell; /* made by the first star to land there */
} grid;

struct orr_sky_cores {
    double theta;
    int width, height;
    grid blocks, fine;
};

/* A cell the table does not draw (off the map, across its outline or a
 * seam, where the affine model does not hold). */
static core_cell unusable;

orr_status orr_sky_cores_create(orr_sky_cores **out, const orr_sph *s, double theta, orr_error *err)
{
    *out = NULL;
    orr_sky_cores *c = orr_calloc(1, sizeof *c, "sky PSF core table", err);
    if (!c)
        return ORR_ERR_NOMEM;
    c->theta = theta;
    c->width = s->proj.width;
    c->height = s->proj.height;
    grid *g[2] = {&c->blocks, &c->fine};
    for (int k = 0; k < 2; k++) {
        g[k]->size = k ? ORR_SKY_CORE_CELL / 2 : ORR_SKY_CORE_CELL;
        g[k]->nx = (c->width + g[k]->size - 1) / g[k]->size;
        g[k]->ny = (c->height + g[k]->size - 1) / g[k]->size;
        g[k]->cell = orr_calloc((size_t)g[k]->nx * (size_t)g[k]->ny, sizeof *g[k]->cell, "sky PSF core table", err);
    }
    *out = c;
    if (c->blocks.cell && c->fine.cell)
        return ORR_OK;
    orr_sky_cores_free(c);
    *out = NULL;
    return ORR_ERR_NOMEM;
}

/* The block a fine cell lies in. */
static core_cell *block_of(const orr_sky_cores *c, size_t fine)
{
    const int r = ORR_SKY_CORE_CELL / c->fine.size;
    const size_t bx = fine % (size_t)c->fine.nx / (size_t)r, by = fine / (size_t)c->fine.nx / (size_t)r;
    return __atomic_load_n(&c->blocks.cell[by * (size_t)c->blocks.nx + bx], __ATOMIC_ACQUIRE);
}

void orr_sky_cores_free(orr_sky_cores *c)
{
    if (!c)
        return;
    /* Fine cells first: those sharing their block's stamps leave them to it. */
    for (size_t k = 0; c->fine.cell && c->blocks.cell && k < (size_t)c->fine.nx * (size_t)c->fine.ny; k++)
        if (c->fine.cell[k] != &unusable && c->fine.cell[k] != block_of(c, k))
            free(c->fine.cell[k]);
    for (size_t k = 0; c->blocks.cell && k < (size_t)c->blocks.nx * (size_t)c->blocks.ny; k++)
        if (c->blocks.cell[k] != &unusable)
            free(c->blocks.cell[k]);
    free(c->fine.cell);
    free(c->blocks.cell);
    free(c);
}

/* Each stamp normalised to 1, in double: the blend then carries exactly
 * the star's weight, to float round-off. */
static int make_stamps(const orr_sph *s, const orr_sph_core_shape *sh, core_cell *cell)
{
    const int sw = 2 * cell->rx + 1, shh = 2 * cell->ry + 1;
    for (int j = 0; j < NODES; j++)
        for (int i = 0; i < NODES; i++) {
            float *st = cell->stamps + (size_t)(j * NODES + i) * cell->size;
            double sum = orr_sph_core_stamp(s, sh, cell->rx + (double)i / STEPS, cell->ry + (double)j / STEPS, sw,
                                            shh, st);
            if (!(sum > 0))
                return 0;
            for (size_t k = 0; k < cell->size; k++)
                st[k] = (float)(st[k] / sum);
        }
    return 1;
}

/* The largest eigenvalue's size of the symmetric [[a, b], [b, c]]. */
static double spectral(double a, double b, double c)
{
    return fabs(0.5 * (a + c)) + sqrt(0.25 * (a - c) * (a - c) + b * b);
}

/* Whether the ellipses at the corners of pixels [x0, x1) x [y0, y1) are
 * within SHAPE_TOL of the centre's: the change of the ellipse's matrix
 * (its largest eigenvalue) over the centre's smaller eigenvalue (all on
 * the map, the model holding). */
static int shape_steady(const orr_sky_cores *c, const orr_sph *s, const orr_sph_core_shape *mid, int x0, int x1,
                        int y0, int y1)
{
    const double small = 0.5 * (mid->a + mid->c) - sqrt(0.25 * (mid->a - mid->c) * (mid->a - mid->c) + mid->b * mid->b);
    for (int k = 0; k < 4; k++) {
        orr_sph_core_shape at;
        double x = k & 1 ? x1 - 0.5 : x0 + 0.5, y = k & 2 ? y1 - 0.5 : y0 + 0.5;
        if (!orr_sph_core_ellipse(s, x, y, c->theta, &at) ||
            !(spectral(at.a - mid->a, at.b - mid->b, at.c - mid->c) <= SHAPE_TOL * small))
            return 0;
    }
    return 1;
}

/* The stamps of cell (cx, cy) of grid g, with the ellipse at the centre of
 * its pixels. Out of memory, the cell is drawn one by one (then, and only
 * then, which thread got there first could change the image). */
static core_cell *build_cell(const orr_sky_cores *c, const orr_sph *s, const grid *g, int cx, int cy)
{
    const int C = g->size, x0 = cx * C, y0 = cy * C;
    const int x1 = x0 + C < c->width ? x0 + C : c->width, y1 = y0 + C < c->height ? y0 + C : c->height;
    orr_sph_core_shape sh;
    if (!orr_sph_core_ellipse(s, 0.5 * (x0 + x1), 0.5 * (y0 + y1), c->theta, &sh) ||
        !(sh.ex < MAX_REACH && sh.ey < MAX_REACH) || !shape_steady(c, s, &sh, x0, x1, y0, y1))
        return &unusable;
    const int rx = (int)sh.ex + 1, ry = (int)sh.ey + 1; /* floor(offset +- extent), offsets in [0, 1] */
    const size_t size = (size_t)(2 * rx + 1) * (size_t)(2 * ry + 1);
    core_cell *cell = malloc(sizeof *cell + sizeof(float) * NODES * NODES * size);
    if (!cell)
        return &unusable;
    *cell = (core_cell){rx, ry, fmax(sh.ex, sh.ey), size};
    if (!make_stamps(s, &sh, cell)) {
        free(cell);
        return &unusable;
    }
    return cell;
}

/* Puts made into an empty slot, unless another thread got there first:
 * then made (when it is new: own) is dropped and the first one kept (they
 * are the same). */
static core_cell *publish(core_cell **slot, core_cell *made, int own)
{
    core_cell *first = NULL;
    if (__atomic_compare_exchange_n(slot, &first, made, 0, __ATOMIC_ACQ_REL, __ATOMIC_ACQUIRE))
        return made;
    if (own && made != &unusable)
        free(made);
    return first;
}

/* Cell (cx, cy) of grid g, made if it is not yet. */
static core_cell *grid_cell(const orr_sky_cores *c, const orr_sph *s, const grid *g, int cx, int cy)
{
    core_cell **slot = &g->cell[(size_t)cy * (size_t)g->nx + (size_t)cx];
    core_cell *cell = __atomic_load_n(slot, __ATOMIC_ACQUIRE);
    return cell ? cell : publish(slot, build_cell(c, s, g, cx, cy), 1);
}

/* The stamps for image point (px, py): its block's, or its fine cell's
 * where the block is not steady enough. */
static const core_cell *cell_at(orr_sky_cores *c, const orr_sph *s, double px, double py)
{
    const int fx = (int)(px / c->fine.size), fy = (int)(py / c->fine.size);
    core_cell **slot = &c->fine.cell[(size_t)fy * (size_t)c->fine.nx + (size_t)fx];
    core_cell *cell = __atomic_load_n(slot, __ATOMIC_ACQUIRE);
    if (cell)
        return cell;
    core_cell *block = grid_cell(c, s, &c->blocks, (int)(px / c->blocks.size), (int)(py / c->blocks.size));
    if (block != &unusable)
        return publish(slot, block, 0);
    return publish(slot, build_cell(c, s, &c->fine, fx, fy), 1);
}

/* row[m] += the blend of stamps a, b, c, d with weights f[0..3]. */
static void blend_row(float *restrict row, const float *restrict a, const float *restrict b,
                      const float *restrict c, const float *restrict d, const float *f, int n)
{
    const float fa = f[0], fb = f[1], fc = f[2], fd = f[3];
    for (int m = 0; m < n; m++)
        row[m] += fa * a[m] + fb * b[m] + fc * c[m] + fd * d[m];
}

/* Whether the stamp's pixels [i0, i0 + nx) x [j0, j0 + ny) all lie on the
 * image and the map (convex outlines: the corners decide). */
static int stamp_on_map(const orr_sky_cores *c, const orr_sph *s, int i0, int j0, int nx, int ny)
{
    const int i1 = i0 + nx - 1, j1 = j0 + ny - 1;
    return i0 >= 0 && j0 >= 0 && i1 < c->width && j1 < c->height && orr_projection_pixel_in_map(&s->proj, i0, j0) &&
           orr_projection_pixel_in_map(&s->proj, i1, j0) && orr_projection_pixel_in_map(&s->proj, i0, j1) &&
           orr_projection_pixel_in_map(&s->proj, i1, j1);
}

/* Where the table draws a star: the four stamps around its offset, the
 * blend's weights for a weight of 1 (before the star's own), and the
 * stamps' place on the image. */
typedef struct placed {
    const float *a, *b, *c, *d;
    float tx, ty;
    int i0, j0, nx, ny;
} placed;

/* 0 when the table may not draw the star (orr_sky_cores_draw). */
static int place(orr_sky_cores *c, const orr_sph *s, double px, double py, double theta, placed *at)
{
    if (!(fabs(theta - c->theta) <= SAME_THETA * c->theta) || !(px >= 0 && py >= 0 && px < c->width &&
                                                                 py < c->height))
        return 0;
    const core_cell *cell = cell_at(c, s, px, py);
    const int ix = (int)px, iy = (int)py; /* px, py >= 0: truncation is floor */
    const int i0 = ix - cell->rx, j0 = iy - cell->ry, nx = 2 * cell->rx + 1, ny = 2 * cell->ry + 1;
    if (cell == &unusable || !stamp_on_map(c, s, i0, j0, nx, ny) || !(cell->reach <= orr_sph_affine_reach(s, px, py)))
        return 0;
    const double gx = (px - ix) * STEPS, gy = (py - iy) * STEPS;
    const int kx = (int)gx < STEPS ? (int)gx : STEPS - 1, ky = (int)gy < STEPS ? (int)gy : STEPS - 1;
    at->tx = (float)(gx - kx);
    at->ty = (float)(gy - ky);
    at->a = cell->stamps + (size_t)(ky * NODES + kx) * cell->size;
    at->b = at->a + cell->size;
    at->c = at->a + NODES * cell->size;
    at->d = at->c + cell->size;
    at->i0 = i0, at->j0 = j0, at->nx = nx, at->ny = ny;
    return 1;
}

int orr_sky_cores_draw_planes(orr_sky_cores *c, const struct orr_sph *s, double px, double py, double theta,
                              const float *w, orr_plane *planes, int nplanes)
{
    placed at;
    if (nplanes > ORR_PLANES_MAX || !place(c, s, px, py, theta, &at))
        return 0;
    float f[ORR_PLANES_MAX][4];
    for (int k = 0; k < nplanes; k++) {
        const float tx = at.tx, ty = at.ty;
        f[k][0] = w[k] * (1.0f - tx) * (1.0f - ty);
        f[k][1] = w[k] * tx * (1.0f - ty);
        f[k][2] = w[k] * (1.0f - tx) * ty;
        f[k][3] = w[k] * tx * ty;
    }
    /* Row by row, every plane: the stamps' row is read once. */
    for (int l = 0; l < at.ny; l++) {
        const size_t o = (size_t)l * (size_t)at.nx;
        const size_t pixel = (size_t)(at.j0 + l) * (size_t)planes[0].width + (size_t)at.i0;
        for (int k = 0; k < nplanes; k++)
            blend_row(planes[k].data + pixel, at.a + o, at.b + o, at.c + o, at.d + o, f[k], at.nx);
    }
    return 1;
}

int orr_sky_cores_draw(orr_sky_cores *c, const orr_sph *s, double px, double py, double theta, float w,
                       orr_plane *plane)
{
    return orr_sky_cores_draw_planes(c, s, px, py, theta, &w, plane, 1);
}

void orr_sky_cores_usage(const orr_sky_cores *c, long *cells, size_t *bytes)
{
    *cells = 0;
    *bytes = 0;
    for (int g = 0; c && g < 2; g++) {
        const grid *gr = g ? &c->fine : &c->blocks;
        for (size_t k = 0; k < (size_t)gr->nx * (size_t)gr->ny; k++) {
            const core_cell *cell = __atomic_load_n(&gr->cell[k], __ATOMIC_ACQUIRE);
            if (cell && cell != &unusable && (g == 0 || cell != block_of(c, k))) {
                (*cells)++;
                *bytes += sizeof *cell + sizeof(float) * NODES * NODES * cell->size;
            }
        }
    }
}
