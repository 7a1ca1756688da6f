#include "post/flat_psf.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Sub-samples per image pixel side: enough that a PSF pixel is sampled
 * about twice across, at most this many. */
#define MAX_SUBSAMPLES 4

orr_status orr_flat_psf_init(orr_sky_psf *sp, orr_image_kernel *psf, double core_fwhm_pixels, int max_stars,
                             double min_flux, int key_plane, orr_error *err)
{
    /* The sky PSF's set-up with image pixels for radians: rad_per_pixel
     * becomes image pixels per PSF pixel. */
    return orr_sky_psf_init(sp, psf, core_fwhm_pixels, max_stars, min_flux, key_plane, err);
}

/* Takes the star's deposit out of the planes: the same deposit with the
 * opposite weights (it cancels to float round-off). */
static void undo_deposit(const orr_flat_deposit *dep, const orr_sky_star *s, orr_plane *planes, int nplanes)
{
    const uint8_t visible = 1;
    for (int k = 0; k < nplanes; k++) {
        float neg = -s->w[k];
        orr_deposit_stats scratch = {0};
        if (dep->sph) {
            orr_sph_block b = {1, &s->x, &s->y, &s->z, &s->px, &s->py, &s->scale, &visible, &s->h, &neg};
            orr_sph_deposit(dep->sph, &b, &planes[k], &scratch);
        } else {
            orr_deposit(dep->kind, &planes[k], 1, &s->px, &s->py, &neg, &visible, dep->proj, &scratch);
        }
    }
}

/* A star's stamp: the PSF's light in each pixel of the square [i0, i0+side)
 * x [j0, j0+side), sampled at ns x ns points of each pixel. */
typedef struct stamp {
    int i0, j0, side, ns;
    double *value;
    size_t cap;
} stamp;

static orr_status make_stamp(const orr_sky_psf *sp, const orr_sky_star *s, stamp *st, orr_error *err)
{
    const double mag = sp->rad_per_pixel; /* image pixels per PSF pixel */
    const double reach = sp->reach_pixels * mag;
    st->i0 = (int)floor(s->px - reach);
    st->j0 = (int)floor(s->py - reach);
    st->side = (int)ceil(2.0 * reach) + 2;
    int ns = (int)ceil(2.0 / mag);
    st->ns = ns < 1 ? 1 : ns > MAX_SUBSAMPLES ? MAX_SUBSAMPLES : ns;
    const size_t n = (size_t)st->side * (size_t)st->side;
    if (n > st->cap) {
        double *v = realloc(st->value, n * sizeof *v);
        if (!v)
            return orr_fail(err, ORR_ERR_NOMEM, "out of memory for a star's PSF stamp (%zu pixels)", n);
        st->value = v;
        st->cap = n;
    }
    const double inv = 1.0 / mag;
    /* Rows are independent, and each pixel's value is computed alone:
     * the same numbers on any number of threads. */
#pragma omp parallel for schedule(static)
    for (int r = 0; r < st->side; r++) {
        for (int c = 0; c < st->side; c++) {
            double sum = 0.0;
            for (int b = 0; b < st->ns; b++) {
                const double oy = (st->j0 + r + (b + 0.5) / st->ns - s->py) * inv;
                for (int a = 0; a < st->ns; a++) {
                    const double ox = (st->i0 + c + (a + 0.5) / st->ns - s->px) * inv;
                    sum += orr_image_kernel_sample(&sp->kernel, ox, oy);
                }
            }
            st->value[(size_t)r * st->side + c] = sum;
        }
    }
    return ORR_OK;
}

/* Adds the stamp, scaled to the star's flux, to the planes; the part that
 * falls off the image is lost, as it would be from a convolution. (The
 * stamp covers the PSF's reach around the star, so it holds the PSF's
 * positive centre: its total is positive.) */
static void add_stamp(const orr_sky_star *s, const stamp *st, orr_plane *planes, int nplanes)
{
    double total = 0.0;
    const size_t n = (size_t)st->side * (size_t)st->side;
    for (size_t i = 0; i < n; i++)
        total += st->value[i];
    const int w = planes[0].width, h = planes[0].height;
    for (int p = 0; p < nplanes; p++) {
        const double f = s->w[p] / total; /* the whole stamp holds exactly the star's flux */
        for (int r = 0; r < st->side; r++) {
            const int j = st->j0 + r;
            if (j < 0 || j >= h)
                continue;
            for (int c = 0; c < st->side; c++) {
                const int i = st->i0 + c;
                if (i >= 0 && i < w)
                    planes[p].data[(size_t)j * w + i] += (float)(f * st->value[(size_t)r * st->side + c]);
            }
        }
    }
}

orr_status orr_flat_psf_draw(orr_sky_psf *sp, const orr_flat_deposit *dep, orr_convolver *core,
                             orr_plane *planes, int nplanes, orr_error *err)
{
    sp->stars_drawn = 0;
    int n = sp->stars ? sp->nstars : 0;
    const float faintest = n > 0 ? (float)(sp->min_flux * sp->stars[0].key) : 0.0f;
    while (n > 0 && sp->stars[n - 1].key < faintest)
        n--;
    for (int k = 0; k < n; k++)
        undo_deposit(dep, &sp->stars[k], planes, nplanes);
    orr_status st = ORR_OK;
    for (int p = 0; p < nplanes && !st; p++)
        st = orr_convolver_apply(core, &planes[p], err);
    stamp sm = {0};
    for (int k = 0; k < n && !st; k++) {
        if ((st = make_stamp(sp, &sp->stars[k], &sm, err)))
            break;
        add_stamp(&sp->stars[k], &sm, planes, nplanes);
        sp->stars_drawn++;
    }
    free(sm.value);
    return st;
}
