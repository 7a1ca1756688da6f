#include "post/view_psf.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/vecmath.h"

#define ARCMIN (3.14159265358979323846 / (180.0 * 60.0))

double orr_kernel_half_max_q(const orr_kernel *k)
{
    /* F falls monotonically from q = 0 to the support's edge: bisect. */
    double half = 0.5 * orr_kernel_column_exact(k, 0.0), lo = 0.0, hi = ORR_KERNEL_SUPPORT;
    for (int it = 0; it < 60; it++) {
        double mid = 0.5 * (lo + hi);
        if (orr_kernel_column_exact(k, mid) > half)
            lo = mid;
        else
            hi = mid;
    }
    return 0.5 * (lo + hi);
}

/* psf.spike_gain: the light of the spikes, a band SPIKE_BAND PSF pixels
 * either side of their axes, is multiplied by gain beyond two core widths
 * from the centre, rising smoothly from 1 between one and two (no step
 * around the core). Diffraction puts a fraction of a percent of a star's
 * light into them, so over the unresolved light of a crowded cluster only
 * Hubble's saturated stars show them; a gain shows them on the bright
 * stars of a frame of modest size. The caller renormalises, so a star
 * keeps its flux (its core dims by the light moved into the spikes). */
#define SPIKE_BAND 1.5
static orr_status boost_spikes(orr_image_kernel *k, double angle_deg, double gain, orr_error *err)
{
    double core;
    orr_status st = orr_psf_core_fwhm(k, &core, err);
    if (st)
        return st;
    const double a = angle_deg * ORR_PI / 180.0, ca = cos(a), sa = sin(a);
    for (int j = 0; j < k->height; j++)
        for (int i = 0; i < k->width; i++) {
            /* (x, y) with y up, turned so the spikes lie along the axes */
            const double x = i - k->width / 2, y = k->height / 2 - j;
            const double u = fabs(x * ca + y * sa), v = fabs(-x * sa + y * ca);
            const double r = hypot(x, y), ramp = fmin(fmax(r / core - 1.0, 0.0), 1.0);
            if (fmin(u, v) <= SPIKE_BAND)
                k->data[(size_t)j * k->width + i] *= (float)(1.0 + (gain - 1.0) * ramp);
        }
    return ORR_OK;
}

/* The Hubble PSF for a single-channel plane: the three colour bands'
 * kernels averaged (a flat spectrum over 400-700 nm). */
static orr_status hst_kernel(const orr_psf_settings *ps, orr_image_kernel *out, orr_error *err)
{
    orr_psf_params p;
    orr_psf_hst_defaults(&p);
    p.pupil.angle_deg = ps->angle;
    p.pupil.spider_width = ps->vane_width;
    p.arcsec_per_pixel = ps->arcsec_per_pixel > 0 ? ps->arcsec_per_pixel : p.arcsec_per_pixel;
    p.size = ps->size;
    orr_image_kernel bands[ORR_PSF_MAX_BANDS];
    memset(bands, 0, sizeof bands);
    orr_status st = orr_psf_generate(&p, bands, NULL, err);
    if (!st)
        st = orr_image_kernel_alloc(out, p.size, p.size, err);
    for (int b = 0; !st && b < p.nbands; b++)
        for (size_t i = 0; i < (size_t)p.size * (size_t)p.size; i++)
            out->data[i] += bands[b].data[i] / (float)p.nbands;
    for (int b = 0; b < p.nbands; b++)
        orr_image_kernel_free(&bands[b]);
    if (!st && ps->spike_gain != 1.0)
        st = boost_spikes(out, ps->angle, ps->spike_gain, err);
    if (!st)
        st = orr_image_kernel_normalise(out, err);
    return st;
}

static orr_status file_kernel(const orr_psf_settings *ps, orr_image_kernel *out, orr_error *err)
{
    orr_psf_fits_options opt = {0};
    opt.subsample = ps->file_subsample;
    opt.arcsec_per_pixel = ps->arcsec_per_pixel;
    opt.size = ps->size;
    opt.centre = ORR_PSF_CENTRE_PEAK;
    opt.taper = 0.3; /* soft wings, as the generated PSF's */
    return orr_psf_load_fits(ps->file, &opt, out, NULL, err);
}

/* Generating the Hubble PSF takes 0.3-2 s, and every view of a run may
 * ask for the same one (the eyes of a stereo view, a dome and a panorama):
 * the plan's memo (render/plan.h) keeps each kernel made, with what it
 * depends on, for the life of the plan, so a run makes it once. The memo
 * belongs to one plan, used by one thread at a time: no lock. */
static int hst_key_equal(const orr_psf_kernel_memo *m, const orr_psf_settings *ps)
{
    return m->angle == ps->angle && m->vane_width == ps->vane_width && m->spike_gain == ps->spike_gain &&
           m->arcsec_per_pixel == ps->arcsec_per_pixel && m->size == ps->size;
}

static orr_status kernel_copy(const orr_image_kernel *from, orr_image_kernel *to, orr_error *err)
{
    orr_status st = orr_image_kernel_alloc(to, from->width, from->height, err);
    if (!st) {
        memcpy(to->data, from->data, (size_t)from->width * (size_t)from->height * sizeof(float));
        to->arcsec_per_pixel = from->arcsec_per_pixel;
    }
    return st;
}

static orr_status hst_kernel_memo(const orr_psf_settings *ps, orr_psf_kernels *memo, orr_image_kernel *out,
                                  orr_error *err)
{
    for (int i = 0; memo && i < memo->n; i++)
        if (hst_key_equal(&memo->kernel[i], ps))
            return kernel_copy(&memo->kernel[i].kernel, out, err);
    orr_status st = hst_kernel(ps, out, err);
    if (st || !memo || memo->n == ORR_PSF_KERNELS_MAX)
        return st; /* (a full memo: the kernel is made again, not lost) */
    orr_psf_kernel_memo *m = &memo->kernel[memo->n];
    *m = (orr_psf_kernel_memo){ps->angle, ps->arcsec_per_pixel, ps->vane_width, ps->spike_gain, ps->size,
                               {0, 0, NULL, 0}};
    st = kernel_copy(out, &m->kernel, err);
    memo->n += !st;
    return st;
}

void orr_psf_kernels_free(orr_psf_kernels *memo)
{
    for (int i = 0; i < memo->n; i++)
        orr_image_kernel_free(&memo->kernel[i].kernel);
    memo->n = 0;
}

orr_status orr_view_psf_kernel(const orr_psf_settings *ps, orr_psf_kernels *memo, orr_image_kernel *out,
                               orr_error *err)
{
    return ps->kind == ORR_PSF_HST ? hst_kernel_memo(ps, memo, out, err) : file_kernel(ps, out, err);
}

/* Flat views given psf.fwhm: every star a Gaussian core psf.fwhm pixels
 * wide, the brightest the whole PSF magnified to that core. */
static orr_status flat_stars_setup(orr_view_psf *vp, const orr_psf_settings *ps, int colour,
                                   const orr_projection *proj, orr_image_kernel *k, orr_error *err)
{
    orr_status st = orr_convolver_create_gaussian(&vp->core, proj->width, proj->height, ps->fwhm, NULL, err);
    if (!st && !(vp->sky = orr_calloc(1, sizeof *vp->sky, "flat PSF", err)))
        st = ORR_ERR_NOMEM;
    if (!st)
        st = orr_flat_psf_init(vp->sky, k, ps->fwhm, ps->spike_stars, ps->spike_min_flux, colour ? 1 : 0, err);
    return st;
}

static orr_status flat_setup(orr_view_psf *vp, const orr_psf_settings *ps, int colour, const orr_projection *proj,
                             orr_psf_kernels *memo, orr_error *err)
{
    if (ps->kind == ORR_PSF_GAUSSIAN)
        return orr_convolver_create_gaussian(&vp->conv, proj->width, proj->height, ps->fwhm, NULL, err);
    orr_image_kernel k = {0};
    orr_status st = orr_view_psf_kernel(ps, memo, &k, err);
    if (!st && orr_psf_flat_stars(ps, orr_projection_is_sky(proj)))
        st = flat_stars_setup(vp, ps, colour, proj, &k, err);
    else if (!st)
        st = orr_convolver_create(&vp->conv, proj->width, proj->height, &k, NULL, err);
    orr_image_kernel_free(&k);
    return st;
}

/* Sky maps, hst or file: the whole PSF for the brightest stars, scaled so
 * its core is as wide as the kernels the other stars are drawn with. */
static orr_status sky_setup(orr_view_psf *vp, const orr_psf_settings *ps, int colour, double core_fwhm_rad,
                            orr_psf_kernels *memo, orr_error *err)
{
    orr_image_kernel k = {0};
    orr_status st = orr_view_psf_kernel(ps, memo, &k, err);
    if (!st && !(vp->sky = orr_calloc(1, sizeof *vp->sky, "sky PSF", err)))
        st = ORR_ERR_NOMEM;
    if (!st)
        st = orr_sky_psf_init(vp->sky, &k, core_fwhm_rad, ps->spike_stars, ps->spike_min_flux, colour ? 1 : 0,
                              err);
    if (!st)
        vp->sky->spike_flux = ps->spike_flux;
    orr_image_kernel_free(&k);
    return st;
}

orr_status orr_view_psf_setup(orr_view_psf *vp, const orr_psf_settings *ps, int colour, const orr_projection *proj,
                              const orr_kernel *k, orr_psf_kernels *memo, orr_error *err)
{
    memset(vp, 0, sizeof *vp);
    vp->kind = ps->kind;
    vp->on_sky = orr_projection_is_sky(proj);
    vp->fwhm = ps->fwhm;
    vp->arcsec_per_pixel = ps->arcsec_per_pixel;
    if (ps->kind == ORR_PSF_NONE)
        return ORR_OK;
    if (orr_projection_is_sky(proj)) {
        /* The sky deposit measures distances on the sphere as chords: a
         * half-maximum chord of q_half h / r is an angle of FWHM / 2. */
        double fwhm = ps->fwhm_arcmin > 0 ? ps->fwhm_arcmin * ARCMIN : ORR_SKY_CORE_PIXELS / proj->focal;
        vp->core_fwhm_arcmin = fwhm / ARCMIN;
        vp->h_per_r = 2.0 * sin(0.25 * fwhm) / orr_kernel_half_max_q(k);
        return ps->kind == ORR_PSF_GAUSSIAN ? ORR_OK : sky_setup(vp, ps, colour, fwhm, memo, err);
    }
    return flat_setup(vp, ps, colour, proj, memo, err);
}

orr_status orr_view_psf_apply(orr_view_psf *vp, orr_plane *plane, orr_error *err)
{
    return vp->conv ? orr_convolver_apply(vp->conv, plane, err) : ORR_OK;
}

void orr_view_psf_cards(const orr_view_psf *vp, orr_cards *h)
{
    orr_cards_add_string(h, "PSF", orr_named_name(orr_psf_kind_names, (int)vp->kind), "point spread function");
    if (vp->kind == ORR_PSF_GAUSSIAN && vp->on_sky)
        orr_cards_add_double(h, "PSFFWHM", vp->core_fwhm_arcmin, "[arcmin] PSF FWHM on the sky");
    else if (vp->kind == ORR_PSF_GAUSSIAN)
        orr_cards_add_double(h, "PSFFWHM", vp->fwhm, "[pixel] PSF FWHM");
    else if (vp->kind != ORR_PSF_NONE)
        orr_cards_add_double(h, "PSFSCALE", vp->arcsec_per_pixel, "[arcsec/pixel] image scale for the PSF");
    if (vp->core) {
        orr_cards_add_double(h, "PSFFWHM", vp->fwhm, "[pixel] the PSF core's FWHM");
        orr_cards_add_double(h, "PSFMAG", vp->sky->rad_per_pixel, "image pixels per PSF pixel");
        orr_cards_reserve(h, "PSFSTARS", "stars drawn with the whole PSF");
    } else if (vp->sky) {
        orr_cards_add_double(h, "PSFFWHM", vp->core_fwhm_arcmin, "[arcmin] the PSF core's FWHM on the sky");
        orr_cards_add_double(h, "PSFSKYSC", vp->sky->rad_per_pixel * (180.0 * 3600.0 / ORR_PI),
                             "[arcsec] one PSF pixel on the sky");
        orr_cards_reserve(h, "PSFSTARS", "stars drawn with the whole PSF");
    }
}

void orr_view_psf_free(orr_view_psf *vp)
{
    orr_convolver_free(vp->conv);
    orr_convolver_free(vp->core);
    vp->conv = vp->core = NULL;
    if (vp->sky)
        orr_sky_psf_free(vp->sky);
    free(vp->sky);
    vp->sky = NULL;
}
