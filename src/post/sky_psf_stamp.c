/* A spike star's stamp on a sky map: the PSF sampled in the star's tangent
 * plane over every map pixel within its reach (docs/psf.md, "Sky maps and
 * dome masters"). */
#include "post/sky_psf_stamp.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/simd.h"
#include "core/vecmath.h"

/* Sub-samples per map pixel side are at most this many (when a PSF pixel
 * is much smaller than a map pixel). */
#define MAX_SUBSAMPLES 4
#define T ORR_SPH_TILE

/* The star's tangent plane: its direction and the unit vectors east and
 * north there (sky_psf.h). */
typedef struct tangent {
    orr_vec3 s, east, north;
} tangent;

static tangent tangent_at(const orr_projection *p, orr_vec3 s)
{
    /* East at the map's centre is the image's +x: its sign along the
     * camera's x (the maps draw longitude either way). */
    orr_vec3 c0, c1;
    double east_sign = 1.0;
    if (orr_unproject(p, p->cx, p->cy, &c0) && orr_unproject(p, p->cx + 1.0, p->cy, &c1))
        east_sign = c1.x - c0.x < 0 ? -1.0 : 1.0;
    orr_vec3 up = orr_v3(0, -1, 0);
    if (orr_v3_norm(orr_v3_cross(s, up)) < 1e-9)
        up = orr_v3(0, 0, 1); /* a star at the pole itself: any north will do */
    orr_vec3 north = orr_v3_normalize(orr_v3_sub(up, orr_v3_scale(s, orr_v3_dot(s, up))));
    orr_vec3 east = orr_v3_scale(orr_v3_cross(s, north), east_sign);
    return (tangent){s, east, north};
}

/* Whether a cap of angle r around the unit vector s meets a tile's cone. */
static int cap_meets(orr_vec3 s, double cos_r, double sin_r, const orr_sph_tile *t)
{
    if (!(t->cos_r <= 1.0f))
        return 0; /* a tile with no pixel on the map */
    double cos_sum = cos_r * t->cos_r - sin_r * t->sin_r; /* cos(r + the tile's radius) */
    if (sin_r * t->cos_r + cos_r * t->sin_r < 0 && cos_sum < 0)
        return 1; /* the sum passes pi: every direction */
    return s.x * t->x + s.y * t->y + s.z * t->z >= cos_sum;
}

/* What every tile of one star's stamp needs. */
typedef struct stamp_ctx {
    const orr_sky_psf *sp;
    const orr_projection *p;
    tangent t;
    double cos_reach;
    int ns;
} stamp_ctx;

/* ---- the exact mapping ---- */

/* The PSF's light in map pixel (i, j): the PSF sampled in the tangent plane
 * (gnomonic coordinates) at ns x ns points of the pixel, each standing for
 * its share of the pixel's solid angle; a solid angle dOmega at angle rho
 * from the star covers dOmega / cos^3 rho of the tangent plane. */
static double pixel_light(const stamp_ctx *x, int i, int j)
{
    const orr_sky_psf *sp = x->sp;
    const orr_projection *p = x->p;
    const double inv = 1.0 / sp->rad_per_pixel;
    const int ns = x->ns;
    double sum = 0.0;
    for (int sy = 0; sy < ns; sy++)
        for (int sx = 0; sx < ns; sx++) {
            orr_vec3 d;
            if (!orr_unproject(p, i + (sx + 0.5) / ns, j + (sy + 0.5) / ns, &d))
                continue;
            double c = orr_v3_dot(d, x->t.s);
            if (c < x->cos_reach)
                continue;
            orr_vec3 off = orr_v3_sub(orr_v3_scale(d, 1.0 / c), x->t.s);
            double ox = orr_v3_dot(off, x->t.east) * inv, oy = orr_v3_dot(off, x->t.north) * inv;
            sum += orr_image_kernel_sample(&sp->kernel, ox, -oy) / (c * c * c);
        }
    if (sum == 0.0)
        return 0.0;
    orr_vec3 d;
    double px, py, scale;
    if (!orr_unproject(p, i + 0.5, j + 0.5, &d) || !orr_project_point(p, d, &px, &py, &scale) || !(scale > 0))
        scale = p->focal;
    return sum / (scale * scale * ns * ns); /* the pixel's solid angle: 1 / scale^2 */
}

/* ---- a tile's pixels from its corners ----
 *
 * A stamp covers tens of thousands of map pixels (the automatic core makes
 * a PSF pixel 7' on a 3600^2 dome, and the PSF 10 degrees across), and
 * mapping every one back to the sky (pixel_light: an inverse projection
 * for its direction, a projection for its solid angle) was most of a
 * spike star's cost. Over one 8 x 8 tile the map is smooth, so the
 * PSF-plane position of a point and its weight (solid angle / cos^3) are
 * found at the tile's corners and interpolated bilinearly between them;
 * the interpolation is checked at the tile's centre against the exact
 * mapping, and a tile that misses (a seam, a pole, the map's rim, a corner
 * off the map) is done pixel by pixel. Inside a tile the interpolation is
 * linear along each row, and the PSF is sampled from a copy with a border
 * of zeros (sky_psf.h), in single precision without a branch: the rows
 * vectorise. */

/* Where the PSF samples a direction: its PSF-plane position (pixels, x
 * east, y down the PSF image) and the weight of a sample there per unit of
 * map area: the pixel's solid angle over cos^3 rho. (Unlike pixel_light,
 * no cut at the PSF's reach: the PSF is zero beyond it, and a tile across
 * the reach's edge is interpolated like any other.) */
typedef struct psf_point {
    double x, y, g;
} psf_point;

static int psf_point_at(const stamp_ctx *x, double px, double py, psf_point *out)
{
    orr_vec3 d;
    double ix, iy, scale;
    if (!orr_unproject(x->p, px, py, &d) || !orr_project_point(x->p, d, &ix, &iy, &scale) || !(scale > 0))
        return 0;
    const double c = orr_v3_dot(d, x->t.s), inv = 1.0 / x->sp->rad_per_pixel;
    if (!(c > 0))
        return 0; /* the far hemisphere: no tangent plane */
    orr_vec3 off = orr_v3_sub(orr_v3_scale(d, 1.0 / c), x->t.s);
    *out = (psf_point){orr_v3_dot(off, x->t.east) * inv, -orr_v3_dot(off, x->t.north) * inv,
                       1.0 / (c * c * c * scale * scale)};
    return 1;
}

/* Tile corners are shared by four tiles: each is mapped once, when a
 * tile first asks for it, and kept in one of two rows (the top and bottom
 * corners of the row of tiles being stamped). */
typedef struct orr_psf_corner {
    psf_point q;
    int state; /* 0: not mapped yet, 1: mapped, -1: off the map */
} psf_corner;

typedef struct corner_rows {
    psf_corner *row[2]; /* corners (tx T, ty T) and (tx T, (ty + 1) T), tx = 0 .. tiles_x */
    int ty;             /* the row of tiles they are for */
} corner_rows;

static int corner_at(const stamp_ctx *x, psf_corner *c, double px, double py, psf_point *q)
{
    if (!c->state)
        c->state = psf_point_at(x, px, py, &c->q) ? 1 : -1;
    *q = c->q;
    return c->state > 0;
}

/* The four corners of a tile's box, mapped; 0 when one is off the map or
 * the interpolation misses the exact mapping at the box's centre by more
 * than TILE_TOL PSF pixels (or 1e-3 in weight). */
#define TILE_TOL 0.02
static int tile_corners(const stamp_ctx *x, corner_rows *cr, int tx, int i0, int i1, int j0, int j1,
                        psf_point q[4])
{
    for (int k = 0; k < 4; k++)
        if (!corner_at(x, &cr->row[k >> 1][tx + (k & 1)], k & 1 ? i1 : i0, k & 2 ? j1 : j0, &q[k]))
            return 0;
    psf_point mid;
    if (!psf_point_at(x, 0.5 * (i0 + i1), 0.5 * (j0 + j1), &mid))
        return 0;
    const double cx = 0.25 * (q[0].x + q[1].x + q[2].x + q[3].x), cy = 0.25 * (q[0].y + q[1].y + q[2].y + q[3].y);
    const double g = 0.25 * (q[0].g + q[1].g + q[2].g + q[3].g);
    return fabs(cx - mid.x) <= TILE_TOL && fabs(cy - mid.y) <= TILE_TOL && fabs(g - mid.g) <= 1e-3 * mid.g &&
           mid.g > 0 && q[0].g > 0 && q[1].g > 0 && q[2].g > 0 && q[3].g > 0;
}

/* The PSF's padded copy (sky_psf.h) as the rows sample it: positions are
 * clamped into its border, two zeros wide, so a point off the PSF reads
 * zeros without a branch. */
typedef struct padded_psf {
    const float *data;
    int width;
    float cx, cy, xmax, ymax; /* the PSF's centre in the copy; the largest positions read */
} padded_psf;

/* Adds to acc[c] the PSF's bilinear value at the sample u = (c + u0) sx of
 * the row whose PSF-plane position is (ax + bx u, ay + by u), times its
 * weight ag + bg u, for the T pixels c of a tile's row: one vector loop. */
static ORR_ALWAYS_INLINE void sample_row(const padded_psf *k, float ax, float bx, float ay, float by, float ag,
                                         float bg, float u0, float sx, float *acc)
{
    const float *data = k->data;
    const int w = k->width;
#pragma omp simd
    for (int c = 0; c < T; c++) {
        const float u = ((float)c + u0) * sx;
        float px = ax + bx * u + k->cx, py = ay + by * u + k->cy;
        px = px > 0.0f ? px : 0.0f;
        px = px < k->xmax ? px : k->xmax;
        py = py > 0.0f ? py : 0.0f;
        py = py < k->ymax ? py : k->ymax;
        const int x0 = (int)px, y0 = (int)py, i = y0 * w + x0;
        const float fx = px - (float)x0, fy = py - (float)y0;
        const float top = (1.0f - fx) * data[i] + fx * data[i + 1];
        const float bottom = (1.0f - fx) * data[i + w] + fx * data[i + w + 1];
        acc[c] += ((1.0f - fy) * top + fy * bottom) * (ag + bg * u);
    }
}

/* A smooth tile's T x T values: its box [0, w] x [0, h] (pixels from the
 * tile's corner) maps to corners q; ns x ns sub-samples a pixel. Rows and
 * columns beyond w, h are filled too (the caller clears them). */
static ORR_VECTOR_CLONES void smooth_tile(const orr_sky_psf *sp, const psf_point q[4], int w, int h, int ns,
                                          float *out)
{
    const padded_psf k = {sp->padded, sp->padded_width, (float)(sp->kernel.width / 2 + ORR_SKY_PSF_PAD),
                          (float)(sp->kernel.height / 2 + ORR_SKY_PSF_PAD), (float)(sp->padded_width - 2),
                          (float)(sp->padded_height - 2)};
    const float sx = 1.0f / (float)w, sy = 1.0f / (float)h, step = 1.0f / (float)ns;
    const float norm = 1.0f / (float)(ns * ns);
    const float x0 = (float)q[0].x, x1 = (float)q[1].x, x2 = (float)q[2].x, x3 = (float)q[3].x;
    const float y0 = (float)q[0].y, y1 = (float)q[1].y, y2 = (float)q[2].y, y3 = (float)q[3].y;
    const float g0 = (float)q[0].g, g1 = (float)q[1].g, g2 = (float)q[2].g, g3 = (float)q[3].g;
    for (int r = 0; r < T; r++) {
        float acc[T] = {0};
        for (int b = 0; b < ns; b++) {
            /* Along the row the bilinear map is linear: value = a + b u. */
            const float v = ((float)r + ((float)b + 0.5f) * step) * sy, v1 = 1.0f - v;
            const float ax = v1 * x0 + v * x2, bx = v1 * (x1 - x0) + v * (x3 - x2);
            const float ay = v1 * y0 + v * y2, by = v1 * (y1 - y0) + v * (y3 - y2);
            const float ag = v1 * g0 + v * g2, bg = v1 * (g1 - g0) + v * (g3 - g2);
            for (int a = 0; a < ns; a++)
                sample_row(&k, ax, bx, ay, by, ag, bg, ((float)a + 0.5f) * step, sx, acc);
        }
        for (int c = 0; c < T; c++)
            out[r * T + c] = acc[c] * norm;
    }
}

/* Clears the values of a tile's pixels off the map (or beyond the image's
 * edge). The maps' outlines are convex: when the four corner pixels are on
 * the map, all are. */
static void clear_off_map(const orr_projection *p, int i0, int j0, float *out)
{
    if (orr_projection_pixel_in_map(p, i0, j0) && orr_projection_pixel_in_map(p, i0 + T - 1, j0) &&
        orr_projection_pixel_in_map(p, i0, j0 + T - 1) && orr_projection_pixel_in_map(p, i0 + T - 1, j0 + T - 1))
        return;
    for (int r = 0; r < T; r++)
        for (int c = 0; c < T; c++)
            if (!orr_projection_pixel_in_map(p, i0 + c, j0 + r))
                out[r * T + c] = 0.0f;
}

/* One tile of the stamp: interpolated when the corners allow (and the PSF
 * is not asked to be exact), else pixel by pixel. */
static void stamp_tile(const stamp_ctx *x, corner_rows *cr, int tx, int ty, float *out)
{
    const orr_projection *p = x->p;
    const int i0 = tx * T, j0 = ty * T;
    const int i1 = i0 + T < p->width ? i0 + T : p->width, j1 = j0 + T < p->height ? j0 + T : p->height;
    psf_point q[4];
    if (!x->sp->exact && tile_corners(x, cr, tx, i0, i1, j0, j1, q)) {
        smooth_tile(x->sp, q, i1 - i0, j1 - j0, x->ns, out);
    } else {
        for (int r = 0; r < T; r++)
            for (int c = 0; c < T; c++)
                out[r * T + c] = j0 + r < j1 && i0 + c < i1 && orr_projection_pixel_in_map(p, i0 + c, j0 + r)
                                     ? (float)pixel_light(x, i0 + c, j0 + r)
                                     : 0.0f;
    }
    clear_off_map(p, i0, j0, out);
}

/* ---- the stamp ---- */

static orr_status stamp_reserve(orr_psf_stamp *st, size_t ntiles, orr_error *err)
{
    if (ntiles <= st->cap)
        return ORR_OK;
    size_t cap = st->cap ? 2 * st->cap : 256;
    cap = cap < ntiles ? ntiles : cap;
    int *tile = realloc(st->tile, cap * sizeof *tile);
    if (tile)
        st->tile = tile;
    float *value = tile ? realloc(st->value, cap * ORR_PSF_STAMP_TILE_PIXELS * sizeof *value) : NULL;
    if (!value)
        return orr_fail(err, ORR_ERR_NOMEM, "out of memory for a star's PSF stamp (%zu tiles)", cap);
    st->value = value;
    st->cap = cap;
    return ORR_OK;
}

static orr_status stamp_add_tile(const stamp_ctx *x, const orr_sph *sph, corner_rows *cr, int tx, int ty,
                                 orr_psf_stamp *st, orr_error *err)
{
    if (stamp_reserve(st, st->ntiles + 1, err))
        return ORR_ERR_NOMEM;
    float *out = st->value + st->ntiles * ORR_PSF_STAMP_TILE_PIXELS;
    stamp_tile(x, cr, tx, ty, out);
    double sum = 0.0;
    for (int k = 0; k < ORR_PSF_STAMP_TILE_PIXELS; k++)
        sum += out[k];
    st->total += sum;
    st->tile[st->ntiles++] = ty * sph->tiles_x + tx;
    return ORR_OK;
}

/* Moves the corner rows on to tile row ty: the bottom corners of the row
 * above are the top ones of this. */
static void next_corner_row(corner_rows *cr, int ty, size_t ncorners)
{
    psf_corner *top = cr->row[0];
    if (cr->ty == ty - 1) {
        cr->row[0] = cr->row[1];
        cr->row[1] = top;
    } else {
        memset(top, 0, ncorners * sizeof *top);
    }
    memset(cr->row[1], 0, ncorners * sizeof *cr->row[1]);
    cr->ty = ty;
}

orr_status orr_psf_stamp_make(const orr_sky_psf *sp, const orr_sph *sph, orr_vec3 dir, orr_psf_stamp *st,
                              orr_error *err)
{
    const orr_projection *p = &sph->proj;
    const double reach = sp->reach_pixels * sp->rad_per_pixel;
    const double pixel_rad = 1.0 / p->focal;
    const double cap = fmin(reach + 2.0 * pixel_rad, ORR_PI);
    const double cos_cap = cos(cap), sin_cap = sin(cap);
    stamp_ctx x = {sp, p, tangent_at(p, dir), cos(fmin(reach, 0.5 * ORR_PI)), (int)ceil(pixel_rad / sp->rad_per_pixel)};
    x.ns = x.ns < 1 ? 1 : x.ns > MAX_SUBSAMPLES ? MAX_SUBSAMPLES : x.ns;
    const int G = ORR_SPH_GROUP;
    st->ntiles = 0;
    st->total = 0.0;
    free(st->meets);
    free(st->corners);
    st->corners = NULL;
    const size_t ncorners = (size_t)sph->tiles_x + 1;
    if (!(st->meets = orr_malloc((size_t)sph->groups_x * sizeof *st->meets, "a star's PSF stamp", err)) ||
        !(st->corners = orr_malloc(2 * ncorners * sizeof *st->corners, "a star's PSF stamp", err)))
        return ORR_ERR_NOMEM;
    corner_rows cr = {{st->corners, st->corners + ncorners}, -2};
    /* Tile rows top to bottom, each left to right: the order the stamp is
     * added in (orr_sky_psf_draw finds a row's tiles by bisection). */
    for (int gy = 0; gy < sph->groups_y; gy++) {
        int any = 0;
        for (int gx = 0; gx < sph->groups_x; gx++)
            any |= st->meets[gx] = cap_meets(dir, cos_cap, sin_cap, &sph->groups[(size_t)gy * sph->groups_x + gx]);
        for (int ty = gy * G; any && ty < (gy + 1) * G && ty < sph->tiles_y; ty++) {
            next_corner_row(&cr, ty, ncorners);
            for (int gx = 0; gx < sph->groups_x; gx++)
                for (int tx = gx * G; st->meets[gx] && tx < (gx + 1) * G && tx < sph->tiles_x; tx++)
                    if (cap_meets(dir, cos_cap, sin_cap, &sph->tiles[(size_t)ty * sph->tiles_x + tx]) &&
                        stamp_add_tile(&x, sph, &cr, tx, ty, st, err))
                        return ORR_ERR_NOMEM;
        }
    }
    return ORR_OK;
}

void orr_psf_stamp_free(orr_psf_stamp *st)
{
    free(st->tile);
    free(st->value);
    free(st->meets);
    free(st->corners);
    memset(st, 0, sizeof *st);
}
