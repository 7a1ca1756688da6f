#include "post/sky_psf.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/vecmath.h"

/* Sub-samples per map pixel side are at most this many (when a PSF pixel
 * is much smaller than a map pixel). */
#define MAX_SUBSAMPLES 4

orr_status orr_psf_core_fwhm(const orr_image_kernel *psf, double *fwhm_pixels, orr_error *err)
{
    const float peak = psf->data[(size_t)(psf->height / 2) * psf->width + psf->width / 2];
    /* The pixel-integrated Gaussian's centre value falls as its FWHM grows:
     * bisect for the PSF's. */
    double lo = 0.05, hi = 0.5 * (psf->width < psf->height ? psf->width : psf->height);
    for (int it = 0; it < 40; it++) {
        double mid = 0.5 * (lo + hi);
        orr_image_kernel g = {0};
        orr_status st = orr_image_kernel_gaussian(&g, mid, err);
        if (st)
            return st;
        float centre = g.data[(size_t)(g.height / 2) * g.width + g.width / 2];
        orr_image_kernel_free(&g);
        if (centre > peak)
            lo = mid;
        else
            hi = mid;
    }
    *fwhm_pixels = 0.5 * (lo + hi);
    return ORR_OK;
}

/* The distance from the centre of the farthest pixel with light, plus the
 * one pixel over which bilinear sampling falls to zero: a tapered PSF is
 * round, so its square's corners need not be visited. */
static double light_reach(const orr_image_kernel *k)
{
    double far2 = 0.0;
    for (int j = 0; j < k->height; j++)
        for (int i = 0; i < k->width; i++) {
            double dx = i - k->width / 2, dy = j - k->height / 2;
            if (k->data[(size_t)j * k->width + i] != 0.0f && dx * dx + dy * dy > far2)
                far2 = dx * dx + dy * dy;
        }
    return sqrt(far2) + 1.5;
}

orr_status orr_sky_psf_init(orr_sky_psf *sp, orr_image_kernel *psf, double core_fwhm_rad, int max_stars,
                            double min_flux, int key_plane, orr_error *err)
{
    memset(sp, 0, sizeof *sp);
    sp->kernel = *psf;
    memset(psf, 0, sizeof *psf);
    sp->max_stars = max_stars;
    sp->min_flux = min_flux;
    sp->key_plane = key_plane;
    double fwhm_pixels;
    orr_status st = orr_psf_core_fwhm(&sp->kernel, &fwhm_pixels, err);
    if (st)
        return st;
    sp->rad_per_pixel = core_fwhm_rad / fwhm_pixels;
    sp->reach_pixels = light_reach(&sp->kernel);
    for (int lane = 0; lane < ORR_SKY_PSF_LANES && max_stars > 0; lane++)
        if (!(sp->lane[lane] = orr_malloc((size_t)max_stars * sizeof(orr_sky_star), "spike stars", err)))
            return ORR_ERR_NOMEM;
    return ORR_OK;
}

void orr_sky_psf_free(orr_sky_psf *sp)
{
    orr_image_kernel_free(&sp->kernel);
    for (int lane = 0; lane < ORR_SKY_PSF_LANES; lane++)
        free(sp->lane[lane]);
    free(sp->stars);
    memset(sp, 0, sizeof *sp);
}

void orr_sky_psf_begin_frame(orr_sky_psf *sp)
{
    for (int lane = 0; lane < ORR_SKY_PSF_LANES; lane++)
        sp->nlane[lane] = 0;
    sp->nstars = 0;
    sp->stars_drawn = 0;
}

/* ---- the brightest stars ---- */

/* A star's fields as doubles (exactly: they are floats), brightness first:
 * the order stars are ranked in (star_cmp, the first STAR_RANK_FIELDS) and
 * the slots they are shared between processes in (orr_sky_psf_share). The
 * populations' Y (output.exr_population_layers) come last: each is the
 * star's Y or 0, so they rank only stars alike in every other field. */
#define STAR_RANK_FIELDS 11
#define STAR_FIELDS (STAR_RANK_FIELDS + ORR_POPULATION_LAYERS_MAX)

static void star_pack_ranked(const orr_sky_star *s, double *d)
{
    const float f[STAR_RANK_FIELDS] = {s->key,  s->x, s->y,  s->z,  s->w[0],  s->w[1],
                                       s->w[2], s->h, s->px, s->py, s->scale};
    for (int k = 0; k < STAR_RANK_FIELDS; k++)
        d[k] = f[k];
}

static void star_pack(const orr_sky_star *s, double *d)
{
    star_pack_ranked(s, d);
    for (int k = 0; k < ORR_POPULATION_LAYERS_MAX; k++)
        d[STAR_RANK_FIELDS + k] = s->w[3 + k];
}

static orr_sky_star star_unpack(const double *d)
{
    orr_sky_star s = {.key = (float)d[0], .x = (float)d[1], .y = (float)d[2], .z = (float)d[3],
                      .w = {(float)d[4], (float)d[5], (float)d[6]}, .h = (float)d[7], .px = (float)d[8],
                      .py = (float)d[9], .scale = (float)d[10]};
    for (int k = 0; k < ORR_POPULATION_LAYERS_MAX; k++)
        s.w[3 + k] = (float)d[STAR_RANK_FIELDS + k];
    return s;
}

/* A total order (brightness first), so which stars win and in what order
 * they are drawn never depends on the order they arrived in. */
static int star_cmp(const orr_sky_star *a, const orr_sky_star *b)
{
    double fa[STAR_RANK_FIELDS], fb[STAR_RANK_FIELDS];
    star_pack_ranked(a, fa);
    star_pack_ranked(b, fb);
    for (int k = 0; k < STAR_RANK_FIELDS; k++)
        if (fa[k] != fb[k])
            return fa[k] < fb[k] ? -1 : 1;
    for (int k = 3; k < ORR_PLANES_MAX; k++) /* two stars alike but for their population */
        if (a->w[k] != b->w[k])
            return a->w[k] < b->w[k] ? -1 : 1;
    return 0;
}

static int brighter_first(const void *a, const void *b) { return star_cmp(b, a); }

/* Min-heap: the faintest kept star at the root. */
static void sift_down(orr_sky_star *h, int n, int i)
{
    for (;;) {
        int l = 2 * i + 1, r = l + 1, m = i;
        if (l < n && star_cmp(&h[l], &h[m]) < 0)
            m = l;
        if (r < n && star_cmp(&h[r], &h[m]) < 0)
            m = r;
        if (m == i)
            return;
        orr_sky_star t = h[i];
        h[i] = h[m], h[m] = t;
        i = m;
    }
}

static void sift_up(orr_sky_star *h, int i)
{
    while (i > 0) {
        int p = (i - 1) / 2;
        if (star_cmp(&h[i], &h[p]) >= 0)
            return;
        orr_sky_star t = h[i];
        h[i] = h[p], h[p] = t;
        i = p;
    }
}

void orr_sky_psf_collect(orr_sky_psf *sp, int lane, const orr_sph_block *b, const float *const *w, int nplanes)
{
    if (sp->max_stars <= 0)
        return;
    orr_sky_star *heap = sp->lane[lane];
    int *n = &sp->nlane[lane];
    const float *key = w[sp->key_plane < nplanes ? sp->key_plane : 0];
    for (size_t i = 0; i < b->n; i++) {
        if (!b->visible[i] || !(key[i] > 0.0f))
            continue;
        if (*n == sp->max_stars && !(key[i] >= heap[0].key))
            continue; /* the common case: fainter than every kept star */
        orr_sky_star s = {key[i], b->x[i], b->y[i], b->z[i], b->px[i], b->py[i], b->scale[i],
                          b->h ? b->h[i] : 0.0f, {0, 0, 0}};
        for (int k = 0; k < nplanes; k++)
            s.w[k] = w[k][i];
        if (*n < sp->max_stars) {
            heap[*n] = s;
            sift_up(heap, (*n)++);
        } else if (star_cmp(&s, &heap[0]) > 0) {
            heap[0] = s;
            sift_down(heap, *n, 0);
        }
    }
}

/* ---- the stamp ---- */

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

/* Pixels touched by one stamp and their values, reused from star to star. */
typedef struct stamp {
    size_t n, cap;
    size_t *pixel;
    double *value;
} stamp;

static int stamp_push(stamp *st, size_t pixel, double value, orr_error *err)
{
    if (st->n == st->cap) {
        size_t cap = st->cap ? 2 * st->cap : 4096;
        size_t *p = realloc(st->pixel, cap * sizeof *p);
        if (p)
            st->pixel = p;
        double *v = p ? realloc(st->value, cap * sizeof *v) : NULL;
        if (!v)
            return orr_fail(err, ORR_ERR_NOMEM, "out of memory for a star's PSF stamp (%zu pixels)", cap);
        st->value = v;
        st->cap = cap;
    }
    st->pixel[st->n] = pixel;
    st->value[st->n++] = value;
    return ORR_OK;
}

/* The PSF's light in map pixel (i, j): the PSF sampled in the tangent plane
 * (gnomonic coordinates) at ns x ns points of the pixel, each standing for
 * its share of the pixel's solid angle; a solid angle dOmega at angle rho
 * from the star covers dOmega / cos^3 rho of the tangent plane. */
static double pixel_light(const orr_sky_psf *sp, const orr_projection *p, const tangent *t, double cos_reach,
                          int i, int j, int ns)
{
    const double inv = 1.0 / sp->rad_per_pixel;
    double sum = 0.0;
    for (int sy = 0; sy < ns; sy++)
        for (int sx = 0; sx < ns; sx++) {
            orr_vec3 d;
            if (!orr_unproject(p, i + (sx + 0.5) / ns, j + (sy + 0.5) / ns, &d))
                continue;
            double c = orr_v3_dot(d, t->s);
            if (c < cos_reach)
                continue;
            orr_vec3 off = orr_v3_sub(orr_v3_scale(d, 1.0 / c), t->s);
            double ox = orr_v3_dot(off, t->east) * inv, oy = orr_v3_dot(off, t->north) * inv;
            sum += orr_image_kernel_sample(&sp->kernel, ox, -oy) / (c * c * c);
        }
    if (sum == 0.0)
        return 0.0;
    orr_vec3 d;
    double x, y, scale;
    if (!orr_unproject(p, i + 0.5, j + 0.5, &d) || !orr_project_point(p, d, &x, &y, &scale) || !(scale > 0))
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
 * off the map) is done pixel by pixel. */

/* Where the PSF samples a direction: its PSF-plane position (pixels, x
 * east, y down the PSF image) and the weight of a sample there per unit of
 * map area: the pixel's solid angle over cos^3 rho (0 beyond the reach). */
typedef struct psf_point {
    double x, y, g;
} psf_point;

static int psf_point_at(const orr_sky_psf *sp, const orr_projection *p, const tangent *t, double cos_reach, double x,
                        double y, psf_point *out)
{
    orr_vec3 d;
    double px, py, scale;
    if (!orr_unproject(p, x, y, &d) || !orr_project_point(p, d, &px, &py, &scale) || !(scale > 0))
        return 0;
    const double c = orr_v3_dot(d, t->s), inv = 1.0 / sp->rad_per_pixel;
    if (!(c > 0))
        return 0; /* the far hemisphere: no tangent plane */
    orr_vec3 off = orr_v3_sub(orr_v3_scale(d, 1.0 / c), t->s);
    *out = (psf_point){orr_v3_dot(off, t->east) * inv, -orr_v3_dot(off, t->north) * inv,
                       c < cos_reach ? 0.0 : 1.0 / (c * c * c * scale * scale)};
    return 1;
}

/* The four corners of a tile's box, mapped; 0 when one is off the map or
 * the interpolation misses the exact mapping at the box's centre by more
 * than TILE_TOL PSF pixels (or 1e-3 in weight). */
#define TILE_TOL 0.02
static int tile_corners(const orr_sky_psf *sp, const orr_projection *p, const tangent *t, double cos_reach, int i0,
                        int i1, int j0, int j1, psf_point q[4])
{
    for (int k = 0; k < 4; k++)
        if (!psf_point_at(sp, p, t, cos_reach, k & 1 ? i1 : i0, k & 2 ? j1 : j0, &q[k]))
            return 0;
    psf_point mid;
    if (!psf_point_at(sp, p, t, cos_reach, 0.5 * (i0 + i1), 0.5 * (j0 + j1), &mid))
        return 0;
    const double x = 0.25 * (q[0].x + q[1].x + q[2].x + q[3].x), y = 0.25 * (q[0].y + q[1].y + q[2].y + q[3].y);
    const double g = 0.25 * (q[0].g + q[1].g + q[2].g + q[3].g);
    return fabs(x - mid.x) <= TILE_TOL && fabs(y - mid.y) <= TILE_TOL && fabs(g - mid.g) <= 1e-3 * mid.g &&
           mid.g > 0 && q[0].g > 0 && q[1].g > 0 && q[2].g > 0 && q[3].g > 0;
}

/* The light of pixel (i, j) of a tile whose box [i0, i1] x [j0, j1] maps
 * to corners q, at ns x ns points of the pixel. */
static double tile_pixel_light(const orr_sky_psf *sp, const psf_point q[4], int i0, int i1, int j0, int j1, int i,
                               int j, int ns)
{
    const double sx = 1.0 / (i1 - i0), sy = 1.0 / (j1 - j0);
    double sum = 0.0;
    for (int b = 0; b < ns; b++) {
        const double v = (j + (b + 0.5) / ns - j0) * sy;
        for (int a = 0; a < ns; a++) {
            const double u = (i + (a + 0.5) / ns - i0) * sx;
            const double w00 = (1 - u) * (1 - v), w10 = u * (1 - v), w01 = (1 - u) * v, w11 = u * v;
            const double x = w00 * q[0].x + w10 * q[1].x + w01 * q[2].x + w11 * q[3].x;
            const double y = w00 * q[0].y + w10 * q[1].y + w01 * q[2].y + w11 * q[3].y;
            const double g = w00 * q[0].g + w10 * q[1].g + w01 * q[2].g + w11 * q[3].g;
            sum += orr_image_kernel_sample(&sp->kernel, x, y) * g;
        }
    }
    return sum / (ns * ns);
}

/* One tile of the stamp's pixels: interpolated when the corners allow,
 * else pixel by pixel. */
static orr_status stamp_tile(const orr_sky_psf *sp, const orr_projection *p, const tangent *t, double cos_reach,
                             int tx, int ty, int ns, stamp *st, orr_error *err)
{
    const int T = ORR_SPH_TILE, i0 = tx * T, j0 = ty * T;
    const int i1 = i0 + T < p->width ? i0 + T : p->width, j1 = j0 + T < p->height ? j0 + T : p->height;
    psf_point q[4];
    const int smooth = tile_corners(sp, p, t, cos_reach, i0, i1, j0, j1, q);
    for (int j = j0; j < j1; j++)
        for (int i = i0; i < i1; i++) {
            if (!orr_projection_pixel_in_map(p, i, j))
                continue;
            double v = smooth ? tile_pixel_light(sp, q, i0, i1, j0, j1, i, j, ns)
                              : pixel_light(sp, p, t, cos_reach, i, j, ns);
            if (v > 0.0 && stamp_push(st, (size_t)j * p->width + i, v, err))
                return ORR_ERR_NOMEM;
        }
    return ORR_OK;
}

/* The star's stamp over every map pixel within the PSF's reach, found
 * through the deposit's tile index (which knows the seams, poles and rims). */
static orr_status make_stamp(const orr_sky_psf *sp, const orr_sph *sph, orr_vec3 dir, stamp *st, orr_error *err)
{
    const orr_projection *p = &sph->proj;
    const tangent t = tangent_at(p, dir);
    const double reach = sp->reach_pixels * sp->rad_per_pixel;
    const double pixel_rad = 1.0 / p->focal;
    const double cap = fmin(reach + 2.0 * pixel_rad, ORR_PI);
    const double cos_cap = cos(cap), sin_cap = sin(cap), cos_reach = cos(fmin(reach, 0.5 * ORR_PI));
    int ns = (int)ceil(pixel_rad / sp->rad_per_pixel);
    ns = ns < 1 ? 1 : ns > MAX_SUBSAMPLES ? MAX_SUBSAMPLES : ns;
    const int G = ORR_SPH_GROUP;
    st->n = 0;
    for (int gy = 0; gy < sph->groups_y; gy++)
        for (int gx = 0; gx < sph->groups_x; gx++) {
            if (!cap_meets(dir, cos_cap, sin_cap, &sph->groups[(size_t)gy * sph->groups_x + gx]))
                continue;
            for (int ty = gy * G; ty < (gy + 1) * G && ty < sph->tiles_y; ty++)
                for (int tx = gx * G; tx < (gx + 1) * G && tx < sph->tiles_x; tx++)
                    if (cap_meets(dir, cos_cap, sin_cap, &sph->tiles[(size_t)ty * sph->tiles_x + tx]) &&
                        stamp_tile(sp, p, &t, cos_reach, tx, ty, ns, st, err))
                        return ORR_ERR_NOMEM;
        }
    return ORR_OK;
}

/* Takes the star's core away again: the deposit that drew it, with the
 * opposite weights. */
static void undo_core(const orr_sph *sph, const orr_sky_star *s, orr_plane *planes, int nplanes)
{
    const uint8_t visible = 1;
    for (int k = 0; k < nplanes; k++) {
        float neg = -s->w[k];
        orr_sph_block b = {1, &s->x, &s->y, &s->z, &s->px, &s->py, &s->scale, &visible, &s->h, &neg};
        orr_deposit_stats scratch = {0};
        orr_sph_deposit(sph, &b, &planes[k], &scratch);
    }
}

orr_status orr_sky_psf_select(orr_sky_psf *sp, orr_error *err)
{
    int n = 0;
    for (int lane = 0; lane < ORR_SKY_PSF_LANES; lane++)
        n += sp->nlane[lane];
    free(sp->stars);
    sp->nstars = 0;
    if (!(sp->stars = orr_malloc((size_t)(n ? n : 1) * sizeof *sp->stars, "spike stars", err)))
        return ORR_ERR_NOMEM;
    for (int lane = 0; lane < ORR_SKY_PSF_LANES; lane++) {
        memcpy(sp->stars + sp->nstars, sp->lane[lane], (size_t)sp->nlane[lane] * sizeof *sp->stars);
        sp->nstars += sp->nlane[lane];
        sp->nlane[lane] = 0;
    }
    qsort(sp->stars, (size_t)sp->nstars, sizeof *sp->stars, brighter_first);
    if (sp->nstars > sp->max_stars)
        sp->nstars = sp->max_stars;
    return ORR_OK;
}

orr_status orr_sky_psf_share(orr_sky_psf *sp, const orr_parallel *par, orr_error *err)
{
    const int rank = par->rank, nranks = par->nranks;
    /* An all-gather by summing: each process fills its own slots, zeros
     * elsewhere (a slot with key 0 is empty: stars are brighter than 0). */
    const size_t per = (size_t)sp->max_stars * STAR_FIELDS, n = per * (size_t)nranks;
    double *all = orr_calloc(n ? n : 1, sizeof *all, "spike stars of every process", err);
    orr_sky_star *stars = all ? orr_malloc((size_t)(sp->max_stars ? sp->max_stars : 1) * (size_t)nranks *
                                               sizeof *stars, "spike stars of every process", err)
                              : NULL;
    if (!stars) {
        free(all);
        return ORR_ERR_NOMEM;
    }
    for (int k = 0; k < sp->nstars; k++)
        star_pack(&sp->stars[k], all + (size_t)rank * per + (size_t)k * STAR_FIELDS);
    orr_status st = par->allreduce_sum(par->user, all, n, err);
    int count = 0;
    for (size_t k = 0; !st && k < n / STAR_FIELDS; k++)
        if (all[k * STAR_FIELDS] > 0)
            stars[count++] = star_unpack(all + k * STAR_FIELDS);
    free(all);
    if (st) {
        free(stars);
        return st;
    }
    qsort(stars, (size_t)count, sizeof *stars, brighter_first);
    free(sp->stars);
    sp->stars = stars;
    sp->nstars = count < sp->max_stars ? count : sp->max_stars;
    return ORR_OK;
}

/* Stamps are made in parallel, this many at a time, and added in order. */
#define STAMP_BATCH 16

/* Undoes the star's core and adds its stamp, scaled to the star's flux. */
static void apply_stamp(const orr_sph *sph, const orr_sky_star *s, const stamp *st, orr_plane *planes, int nplanes,
                        int *drawn)
{
    double total = 0.0;
    for (size_t i = 0; i < st->n; i++)
        total += st->value[i];
    if (!(total > 0.0))
        return; /* nothing of the PSF on the map: the core stays */
    undo_core(sph, s, planes, nplanes);
    for (int p = 0; p < nplanes; p++) {
        const double f = s->w[p] / total; /* the stamp holds exactly the star's flux */
        float *data = planes[p].data;
        for (size_t i = 0; i < st->n; i++)
            data[st->pixel[i]] += (float)(f * st->value[i]);
    }
    (*drawn)++;
}

orr_status orr_sky_psf_draw(orr_sky_psf *sp, const orr_sph *sph, orr_plane *planes, int nplanes, orr_error *err)
{
    sp->stars_drawn = 0;
    const orr_sky_star *stars = sp->stars;
    int n = stars ? sp->nstars : 0;
    const float faintest = n > 0 ? (float)(sp->min_flux * stars[0].key) : 0.0f;
    while (n > 0 && stars[n - 1].key < faintest)
        n--;
    stamp st[STAMP_BATCH];
    orr_error errs[STAMP_BATCH];
    orr_status status[STAMP_BATCH];
    memset(st, 0, sizeof st);
    orr_status result = ORR_OK;
    for (int first = 0; first < n && !result; first += STAMP_BATCH) {
        const int count = n - first < STAMP_BATCH ? n - first : STAMP_BATCH;
#pragma omp parallel for schedule(dynamic, 1)
        for (int b = 0; b < count; b++) {
            const orr_sky_star *s = &stars[first + b];
            status[b] = make_stamp(sp, sph, orr_v3_normalize(orr_v3(s->x, s->y, s->z)), &st[b], &errs[b]);
        }
        for (int b = 0; b < count && !result; b++) {
            if ((result = status[b]) != ORR_OK && err)
                *err = errs[b];
            else if (!result)
                apply_stamp(sph, &stars[first + b], &st[b], planes, nplanes, &sp->stars_drawn);
        }
    }
    for (int b = 0; b < STAMP_BATCH; b++) {
        free(st[b].pixel);
        free(st[b].value);
    }
    return result;
}
