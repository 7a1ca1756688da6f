#include "post/sky_psf.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/vecmath.h"
#include "post/sky_psf_stamp.h"

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

/* The PSF with ORR_SKY_PSF_PAD zeros on every side (sky_psf_stamp.c
 * samples it without testing bounds). */
static orr_status pad_kernel(orr_sky_psf *sp, orr_error *err)
{
    const int w = sp->kernel.width, h = sp->kernel.height, pad = ORR_SKY_PSF_PAD;
    sp->padded_width = w + 2 * pad;
    sp->padded_height = h + 2 * pad;
    sp->padded = orr_calloc((size_t)sp->padded_width * (size_t)sp->padded_height, sizeof *sp->padded,
                            "the PSF's padded copy", err);
    if (!sp->padded)
        return ORR_ERR_NOMEM;
    for (int j = 0; j < h; j++)
        memcpy(sp->padded + (size_t)(j + pad) * sp->padded_width + pad, sp->kernel.data + (size_t)j * w,
               (size_t)w * sizeof *sp->padded);
    return ORR_OK;
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
    if ((st = pad_kernel(sp, err)))
        return st;
    for (int lane = 0; lane < ORR_SKY_PSF_LANES && max_stars > 0; lane++)
        if (!(sp->lane[lane] = orr_malloc((size_t)max_stars * sizeof(orr_sky_star), "spike stars", err)))
            return ORR_ERR_NOMEM;
    return ORR_OK;
}

void orr_sky_psf_free(orr_sky_psf *sp)
{
    orr_image_kernel_free(&sp->kernel);
    free(sp->padded);
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
 * populations' X, Y, Z (output.exr_population_layers) come last: each is
 * the star's or 0, so they rank only stars alike in every other field. */
#define STAR_RANK_FIELDS 11
#define STAR_POP_FIELDS (ORR_PLANES_MAX - 3)
#define STAR_FIELDS (STAR_RANK_FIELDS + STAR_POP_FIELDS)

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
    for (int k = 0; k < STAR_POP_FIELDS; k++)
        d[STAR_RANK_FIELDS + k] = s->w[3 + k];
}

static orr_sky_star star_unpack(const double *d)
{
    orr_sky_star s = {.key = (float)d[0], .x = (float)d[1], .y = (float)d[2], .z = (float)d[3],
                      .w = {(float)d[4], (float)d[5], (float)d[6]}, .h = (float)d[7], .px = (float)d[8],
                      .py = (float)d[9], .scale = (float)d[10]};
    for (int k = 0; k < STAR_POP_FIELDS; k++)
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
    while (sp->nstars > 0 && sp->stars[sp->nstars - 1].key < sp->spike_flux) /* brightest first */
        sp->nstars--;
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
    while (sp->nstars > 0 && sp->stars[sp->nstars - 1].key < sp->spike_flux) /* brightest first */
        sp->nstars--;
    return ORR_OK;
}

/* Stamps are made in parallel, this many at a time (one star a thread),
 * and added in parallel by rows of tiles, each pixel receiving the stars
 * in their order: the same bits on any number of threads. */
#define STAMP_BATCH 16

/* The first of a stamp's tiles at index `from` or beyond (they increase). */
static size_t first_tile_from(const orr_psf_stamp *st, int from)
{
    size_t lo = 0, hi = st->ntiles;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (st->tile[mid] < from)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* Adds the stamp's tiles of row ty, scaled to the star's flux. */
static void add_stamp_row(const orr_sph *sph, const orr_sky_star *s, const orr_psf_stamp *st, int ty,
                          orr_plane *planes, int nplanes)
{
    const int T = ORR_SPH_TILE, W = sph->proj.width, H = sph->proj.height, row = ty * sph->tiles_x;
    const int j0 = ty * T, j1 = j0 + T < H ? j0 + T : H;
    for (size_t k = first_tile_from(st, row); k < st->ntiles && st->tile[k] < row + sph->tiles_x; k++) {
        const int i0 = (st->tile[k] - row) * T, i1 = i0 + T < W ? i0 + T : W;
        const float *v = st->value + k * ORR_PSF_STAMP_TILE_PIXELS;
        for (int p = 0; p < nplanes; p++) {
            const double f = s->w[p] / st->total; /* the stamp holds exactly the star's flux */
            for (int j = j0; j < j1; j++) {
                float *out = planes[p].data + (size_t)j * W;
                for (int i = i0; i < i1; i++)
                    out[i] += (float)(f * v[(j - j0) * T + (i - i0)]);
            }
        }
    }
}

/* Undoes the cores of a batch's stars that have a stamp and adds their
 * stamps; stars with nothing of the PSF on the map keep their core. */
static void apply_stamps(const orr_sph *sph, const orr_sky_star *stars, const orr_psf_stamp *st, int count,
                         orr_plane *planes, int nplanes, int *drawn)
{
    for (int b = 0; b < count; b++)
        if (st[b].total > 0.0) {
            undo_core(sph, &stars[b], planes, nplanes);
            (*drawn)++;
        }
#pragma omp parallel for schedule(dynamic, 4)
    for (int ty = 0; ty < sph->tiles_y; ty++)
        for (int b = 0; b < count; b++)
            if (st[b].total > 0.0)
                add_stamp_row(sph, &stars[b], &st[b], ty, planes, nplanes);
}

orr_status orr_sky_psf_draw(orr_sky_psf *sp, const orr_sph *sph, orr_plane *planes, int nplanes, orr_error *err)
{
    sp->stars_drawn = 0;
    const orr_sky_star *stars = sp->stars;
    int n = stars ? sp->nstars : 0;
    const float faintest = n > 0 ? (float)(sp->min_flux * stars[0].key) : 0.0f;
    while (n > 0 && stars[n - 1].key < faintest)
        n--;
    orr_psf_stamp st[STAMP_BATCH];
    orr_error errs[STAMP_BATCH];
    orr_status status[STAMP_BATCH];
    memset(st, 0, sizeof st);
    orr_status result = ORR_OK;
    for (int first = 0; first < n && !result; first += STAMP_BATCH) {
        const int count = n - first < STAMP_BATCH ? n - first : STAMP_BATCH;
#pragma omp parallel for schedule(dynamic, 1)
        for (int b = 0; b < count; b++) {
            const orr_sky_star *s = &stars[first + b];
            status[b] = orr_psf_stamp_make(sp, sph, orr_v3_normalize(orr_v3(s->x, s->y, s->z)), &st[b], &errs[b]);
        }
        for (int b = 0; b < count && !result; b++)
            if ((result = status[b]) != ORR_OK && err)
                *err = errs[b];
        if (!result)
            apply_stamps(sph, stars + first, st, count, planes, nplanes, &sp->stars_drawn);
    }
    for (int b = 0; b < STAMP_BATCH; b++)
        orr_psf_stamp_free(&st[b]);
    return result;
}
