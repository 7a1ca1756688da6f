/* Generated PSFs: the Fraunhofer diffraction pattern of a pupil.
 *
 * For each wavelength the pupil is drawn on an N x N grid and Fourier
 * transformed; |FT|^2 is the monochromatic PSF sampled every lambda/(N dx)
 * radians, where dx is the pupil sample spacing. Rather than resampling the
 * result, dx is chosen per wavelength (dx = lambda m / (N s), s the output
 * pixel scale) so that the transform's samples fall exactly on an m x m
 * grid of sub-pixels of the output pixels: summing them gives each output
 * pixel's integral, with no interpolation, and the chromatic scaling comes
 * from the pupil being drawn at a different sampling for each wavelength.
 * See docs/psf.md for the choice of N, m and the sources of the geometry. */
#include "post/psf.h"

#include <fftw3.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/owned.h"
#include "core/vecmath.h"

const orr_named orr_psf_kind_names[] = {
    {"none", ORR_PSF_NONE}, {"gaussian", ORR_PSF_GAUSSIAN}, {"hst", ORR_PSF_HST}, {"file", ORR_PSF_FILE}, {NULL, 0}};

void orr_psf_settings_defaults(orr_psf_settings *d)
{
    memset(d, 0, sizeof *d);
    d->kind = ORR_PSF_NONE;
    d->fwhm = 3.6;        /* pixels: stars twinkle by at most 1.2x (docs/psf.md#stars-that-do-not-twinkle) */
    d->fwhm_arcmin = 0;   /* auto: ORR_SKY_CORE_PIXELS at the map's centre */
    d->file_subsample = 1;
    d->arcsec_per_pixel = 0.04;
    d->angle = 45.0;
    d->vane_width = 0.022; /* Hubble's (Tiny Tim's pupil tables) */
    d->spike_gain = 1.0;
    d->size = 129;
    d->spike_stars = 200;
    d->spike_min_flux = 0.001;
    d->glow_max_arcmin = 60;
}

int orr_psf_settings_strings(orr_psf_settings *d, char **fields[])
{
    fields[0] = &d->file;
    return ORR_PSF_STRINGS;
}

int orr_psf_flat_stars(const orr_psf_settings *d, int sky)
{
    return !sky && (d->kind == ORR_PSF_HST || d->kind == ORR_PSF_FILE) && d->has_fwhm;
}

/* The keys of a PSF kind, or of a way of drawing stars, given without it. */
static orr_status check_foreign_keys(const orr_psf_settings *d, int sky, const orr_keys *keys, orr_error *err)
{
    if (d->kind != ORR_PSF_FILE && orr_key_given(keys, "psf.file"))
        return orr_fail_key(keys, "psf.file", err, "psf.file is used only with psf.kind: file");
    /* A sky map draws the brightest stars with the whole PSF, the rest as
     * its core (docs/psf.md); so does a flat view given the core's width
     * (psf.fwhm), else it convolves every star with the whole PSF. */
    const char *hst_keys[2] = {"psf.vane_width", "psf.spike_gain"};
    for (int k = 0; k < 2; k++)
        if (d->kind != ORR_PSF_HST && orr_key_given(keys, hst_keys[k]))
            return orr_fail_key(keys, hst_keys[k], err, "%s is used only with psf.kind: hst", hst_keys[k]);
    int whole = d->kind == ORR_PSF_HST || d->kind == ORR_PSF_FILE;
    const char *spike_keys[2] = {"psf.spike_stars", "psf.spike_min_flux"};
    for (int k = 0; k < 2; k++)
        if (orr_key_given(keys, spike_keys[k]) && !((sky && whole) || orr_psf_flat_stars(d, sky)))
            return orr_fail_key(keys, spike_keys[k], err,
                                "%s is for psf.kind: hst or file on sky maps, or on flat views with psf.fwhm "
                                "(the core's width in pixels); a Gaussian has no spikes, and a flat view "
                                "without psf.fwhm convolves every star with the whole PSF",
                                spike_keys[k]);
    if (sky && orr_key_given(keys, "psf.fwhm"))
        return orr_fail_key(keys, "psf.fwhm", err,
                            "psf.fwhm is in pixels, for flat views; a sky map's PSF size is psf.fwhm_arcmin");
    if (!sky && orr_key_given(keys, "psf.fwhm_arcmin"))
        return orr_fail_key(keys, "psf.fwhm_arcmin", err,
                            "psf.fwhm_arcmin is for sky maps; a flat view's Gaussian PSF is psf.fwhm, in pixels");
    return ORR_OK;
}

orr_status orr_psf_prepare(const orr_psf_settings *d, int sky, const orr_keys *keys, orr_error *err)
{
    if (d->kind == ORR_PSF_FILE && !d->file)
        return orr_fail_key(keys, "psf.kind", err, "psf.kind: file needs psf.file, a FITS PSF image");
    orr_status st = check_foreign_keys(d, sky, keys, err);
    if (st)
        return st;
    if (d->size % 2 == 0)
        return orr_fail_key(keys, "psf.size", err, "psf.size must be odd (the PSF's centre is a pixel), got %d",
                            d->size);
    if (d->has_glow && (!sky || d->kind == ORR_PSF_NONE))
        return orr_fail_key(keys, "glow.threshold", err,
                            "glow.threshold draws faint stars as a glow of angular kernels and bright ones as "
                            "the PSF's core: it needs a sky map with a psf.kind");
    return ORR_OK;
}

#define ARCSEC_RAD (ORR_PI / (180.0 * 3600.0))
#define PSF_MAX_FFT 4096
#define PSF_MAX_SAMPLES 64
#define DEFAULT_MIN_PUPIL_SAMPLES 128
#define DEFAULT_PUPIL_SUPERSAMPLE 8

/* ---- the pupil ------------------------------------------------------------ */

void orr_pupil_hst(orr_pupil *p)
{
    /* Tiny Tim's pupil tables (spacetelescope/tinytim, e.g. wfpc2pc1.pup,
     * newnicmos2.pup: "OTA Secondary Mirror Radius", "OTA Spider Width",
     * "OTA Pad 1-3 (V3, V2, Pad Radius)"), all in units of the primary's
     * radius, with the vanes along the V2 and V3 axes. */
    static const double pad_x[] = {0.8921, -0.4615, -0.4564};
    static const double pad_y[] = {0.0000, 0.7555, -0.7606};
    memset(p, 0, sizeof *p);
    p->diameter_m = 2.4;
    p->obscuration = 0.330;
    p->spider_width = 0.022;
    p->angle_deg = 45.0;
    p->npads = 3;
    for (int i = 0; i < 3; i++) {
        p->pad_x[i] = pad_x[i];
        p->pad_y[i] = pad_y[i];
        p->pad_radius[i] = 0.065;
    }
}

/* The pupil with its vanes' direction worked out once: the supersampled
 * pixels along its edges test tens of points each. */
typedef struct vane_pupil {
    const orr_pupil *p;
    double cos_a, sin_a; /* of angle_deg */
} vane_pupil;

static vane_pupil vane_pupil_of(const orr_pupil *p)
{
    const double a = p->angle_deg * ORR_PI / 180.0;
    return (vane_pupil){p, cos(a), sin(a)};
}

/* (x, y) turned into the vanes' frame: u along the vane at angle_deg. */
static void to_vane_frame(const vane_pupil *vp, double x, double y, double *u, double *v)
{
    *u = vp->cos_a * x + vp->sin_a * y;
    *v = -vp->sin_a * x + vp->cos_a * y;
}

static int pupil_open(const vane_pupil *vp, double x, double y)
{
    const orr_pupil *p = vp->p;
    double r2 = x * x + y * y;
    if (r2 > 1.0 || r2 < p->obscuration * p->obscuration)
        return 0;
    double u, v, hw = 0.5 * p->spider_width;
    to_vane_frame(vp, x, y, &u, &v);
    if (fabs(u) < hw || fabs(v) < hw)
        return 0;
    for (int i = 0; i < p->npads; i++) {
        double du = u - p->pad_x[i], dv = v - p->pad_y[i];
        if (du * du + dv * dv < p->pad_radius[i] * p->pad_radius[i])
            return 0;
    }
    return 1;
}

int orr_pupil_open(const orr_pupil *p, double x, double y)
{
    const vane_pupil vp = vane_pupil_of(p);
    return pupil_open(&vp, x, y);
}

/* Distance from (x, y) to the nearest edge of any part of the pupil (or a
 * lower bound of it: vane edges are taken as infinite lines). A pupil pixel
 * whose centre is further than its half-diagonal from every edge is wholly
 * open or wholly dark. */
static double edge_distance(const vane_pupil *vp, double x, double y)
{
    const orr_pupil *p = vp->p;
    double r = sqrt(x * x + y * y), u, v, hw = 0.5 * p->spider_width;
    double d = fmin(fabs(r - 1.0), fabs(r - p->obscuration));
    to_vane_frame(vp, x, y, &u, &v);
    d = fmin(d, fmin(fabs(fabs(u) - hw), fabs(fabs(v) - hw)));
    for (int i = 0; i < p->npads; i++) {
        const double du = u - p->pad_x[i], dv = v - p->pad_y[i];
        d = fmin(d, fabs(sqrt(du * du + dv * dv) - p->pad_radius[i]));
    }
    return d;
}

/* Open fraction of the pupil pixel centred on (x, y) with side dx: exact
 * for pixels no edge crosses, else an s x s point average (anti-aliasing,
 * so a vane narrower than a pixel still blocks the right amount of light). */
static float pupil_pixel(const vane_pupil *vp, double x, double y, double dx, int s)
{
    if (edge_distance(vp, x, y) > 0.7072 * dx)
        return (float)pupil_open(vp, x, y);
    int open = 0;
    for (int b = 0; b < s; b++)
        for (int a = 0; a < s; a++)
            open += pupil_open(vp, x + ((a + 0.5) / s - 0.5) * dx, y + ((b + 0.5) / s - 0.5) * dx);
    return (float)open / (float)(s * s);
}

/* ---- parameters ---------------------------------------------------------- */

static void set_band(orr_psf_band *b, const char *name, double lo, double hi, int samples)
{
    snprintf(b->name, sizeof b->name, "%s", name);
    b->lambda_min_nm = lo;
    b->lambda_max_nm = hi;
    b->samples = samples;
}

void orr_psf_hst_defaults(orr_psf_params *p)
{
    memset(p, 0, sizeof *p);
    orr_pupil_hst(&p->pupil);
    p->arcsec_per_pixel = 0.04;
    p->size = 129;
    p->nbands = 3;
    set_band(&p->bands[0], "B", 400, 500, 5);
    set_band(&p->bands[1], "G", 500, 600, 5);
    set_band(&p->bands[2], "R", 600, 700, 5);
    p->taper = 0.3;
}

double orr_lambda_over_d_arcsec(double lambda_nm, double diameter_m)
{
    return lambda_nm * 1e-9 / diameter_m / ARCSEC_RAD;
}

static orr_status check_pupil(const orr_pupil *u, orr_error *err)
{
    if (!(u->diameter_m > 0) || !isfinite(u->diameter_m))
        return orr_fail(err, ORR_ERR_USAGE, "PSF: pupil diameter %g m must be positive", u->diameter_m);
    if (!(u->obscuration >= 0 && u->obscuration < 1))
        return orr_fail(err, ORR_ERR_USAGE, "PSF: obscuration %g must be in [0, 1)", u->obscuration);
    if (!(u->spider_width >= 0 && u->spider_width < 1))
        return orr_fail(err, ORR_ERR_USAGE, "PSF: spider width %g must be in [0, 1)", u->spider_width);
    if (!isfinite(u->angle_deg))
        return orr_fail(err, ORR_ERR_USAGE, "PSF: spider angle is not a number");
    if (u->npads < 0 || u->npads > ORR_PUPIL_MAX_PADS)
        return orr_fail(err, ORR_ERR_USAGE, "PSF: %d mirror pads (0 to %d)", u->npads, ORR_PUPIL_MAX_PADS);
    for (int i = 0; i < u->npads; i++)
        if (!(u->pad_radius[i] >= 0) || !isfinite(u->pad_x[i]) || !isfinite(u->pad_y[i]))
            return orr_fail(err, ORR_ERR_USAGE, "PSF: mirror pad %d is malformed", i + 1);
    return ORR_OK;
}

static orr_status check_params(const orr_psf_params *p, orr_error *err)
{
    orr_status st = check_pupil(&p->pupil, err);
    if (st)
        return st;
    if (!(p->arcsec_per_pixel > 0) || !isfinite(p->arcsec_per_pixel))
        return orr_fail(err, ORR_ERR_USAGE, "PSF: pixel scale %g arcsec must be positive", p->arcsec_per_pixel);
    if (p->size < 1 || p->size % 2 == 0 || p->size > 8191)
        return orr_fail(err, ORR_ERR_USAGE, "PSF: size %d must be odd, 1 to 8191", p->size);
    if (p->nbands < 1 || p->nbands > ORR_PSF_MAX_BANDS)
        return orr_fail(err, ORR_ERR_USAGE, "PSF: %d bands (1 to %d)", p->nbands, ORR_PSF_MAX_BANDS);
    for (int b = 0; b < p->nbands; b++) {
        const orr_psf_band *band = &p->bands[b];
        if (!(band->lambda_min_nm > 0) || !(band->lambda_max_nm >= band->lambda_min_nm) ||
            !isfinite(band->lambda_max_nm) || band->samples < 1 || band->samples > PSF_MAX_SAMPLES)
            return orr_fail(err, ORR_ERR_USAGE,
                            "PSF: band %d (%s): need 0 < lambda_min <= lambda_max and 1 to %d samples", b + 1,
                            band->name, PSF_MAX_SAMPLES);
    }
    if (p->oversample < 0 || (p->oversample > 0 && p->oversample % 2 == 0) || p->oversample > 31)
        return orr_fail(err, ORR_ERR_USAGE, "PSF: oversample %d must be odd (0 = automatic)", p->oversample);
    if (p->min_pupil_samples < 0 || (p->min_pupil_samples > 0 && p->min_pupil_samples < 16))
        return orr_fail(err, ORR_ERR_USAGE, "PSF: at least 16 pupil samples (0 = automatic)");
    if (!(p->taper >= 0 && p->taper <= 1))
        return orr_fail(err, ORR_ERR_USAGE, "PSF: taper %g must be a fraction, 0 to 1", p->taper);
    if (p->pupil_supersample < 0 || p->pupil_supersample > 32)
        return orr_fail(err, ORR_ERR_USAGE, "PSF: pupil supersampling %d (0 to 32)", p->pupil_supersample);
    return ORR_OK;
}

/* ---- sampling plan ------------------------------------------------------ */

typedef struct psf_grid {
    int n;              /* FFT side */
    int m;              /* sub-samples per output pixel side (odd) */
    int size;           /* kernel side */
    double scale;       /* output pixel, radians */
    double diameter;    /* metres */
    int supersample;
} psf_grid;

/* Sub-sample spacing at most lambda_min / (3 D) (1.5 times Nyquist for
 * the intensity), so pixel integrals are accurate at every wavelength. The
 * transform spans twice the kernel (light from beyond the transform's field
 * wraps around into its far edge, not into the kernel), and the pupil gets at
 * least min_pupil_samples across at the longest wavelength, where it is
 * coarsest. */
static orr_status plan_grid(const orr_psf_params *p, double lam_min, double lam_max, psf_grid *g,
                            orr_error *err)
{
    g->size = p->size;
    g->scale = p->arcsec_per_pixel * ARCSEC_RAD;
    g->diameter = p->pupil.diameter_m;
    g->supersample = p->pupil_supersample ? p->pupil_supersample : DEFAULT_PUPIL_SUPERSAMPLE;
    double nyquist = lam_min / (2 * g->diameter);
    if (p->oversample) {
        g->m = p->oversample;
        if (g->scale / g->m > nyquist)
            return orr_fail(err, ORR_ERR_USAGE,
                            "PSF: oversample %d leaves sub-pixels of %.4g arcsec, coarser than the %.4g arcsec "
                            "Nyquist step at %g nm",
                            g->m, p->arcsec_per_pixel / g->m, nyquist / ARCSEC_RAD, lam_min * 1e9);
    } else {
        int m = (int)ceil(3 * g->scale * g->diameter / lam_min);
        g->m = m < 1 ? 1 : m + (m % 2 == 0);
    }
    int min_pupil = p->min_pupil_samples ? p->min_pupil_samples : DEFAULT_MIN_PUPIL_SAMPLES;
    double need_pupil = g->m * min_pupil * lam_max / (g->diameter * g->scale);
    double need = fmax(2.0 * g->m * g->size, need_pupil);
    if (need > PSF_MAX_FFT)
        return orr_fail(err, ORR_ERR_USAGE,
                        "PSF: a %d-pixel kernel at %g arcsec per pixel needs a %.0f-point transform (at most %d): "
                        "use a smaller kernel or a coarser scale",
                        p->size, p->arcsec_per_pixel, need, PSF_MAX_FFT);
    g->n = orr_fft_good_size((int)ceil(need) < 32 ? 32 : (int)ceil(need), 4);
    return ORR_OK;
}

/* Pupil samples across the diameter at this wavelength. */
static double pupil_samples(const psf_grid *g, double lambda)
{
    return g->n * g->scale * g->diameter / (g->m * lambda);
}

/* ---- one wavelength ---------------------------------------------------- */

/* The pupil's transform, pruned to what the kernel reads. The pupil fills
 * only rows and columns [lo, lo + rows) of the n x n grid (294 of 1296 for
 * the default PSF), and the kernel reads frequencies |kx|, |ky| <= m
 * (size / 2) + (m - 1) / 2 (645 of 1296): so the rows are transformed only
 * where the pupil is (real to complex: a real pupil's transform has
 * F(-k) = conj F(k), so kx >= 0 suffices), then the columns only for the
 * frequencies read, out of place (the rows of zeros stay zero). Five to six
 * times fewer operations than the whole complex n x n transform; the same
 * transform, to single-precision round-off.
 *
 * All on one thread: the whole PSF then takes about 0.1 s, and on two
 * shared cores the threads' hand-offs (15 wavelengths, three parallel
 * steps each) cost more than they saved: 0.9 s of wall time against
 * 0.16 s on one thread, with other jobs running. */
typedef struct pupil_fft {
    int n, lo, rows, cols; /* side; the pupil's rows; columns kx = 0 .. cols - 1 kept */
    float *in;             /* rows x n: the pupil's rows */
    fftwf_complex *spec;   /* n x (n/2 + 1): the rows' transforms (zero outside the pupil's rows) */
    fftwf_complex *far;    /* n x cols: the whole transform, kx < cols */
    double *row_power;     /* per pupil row: sum |pupil|^2 */
    fftwf_plan rows_plan, cols_plan;
} pupil_fft;

/* The pupil's rows and columns at its widest (the shortest wavelength). */
static void pupil_extent(int n, double samples, int *lo, int *hi)
{
    *lo = (int)floor(n / 2 - samples / 2) - 1;
    *hi = (int)ceil(n / 2 + samples / 2) + 1;
    *lo = *lo < 0 ? 0 : *lo;
    *hi = *hi > n - 1 ? n - 1 : *hi;
}

/* Draws the pupil centred on the grid, P samples across its diameter, and
 * returns the sum of |pupil|^2 (for Parseval's normalisation). */
static double draw_pupil(const orr_pupil *pupil, const psf_grid *g, double samples, pupil_fft *f)
{
    const int n = g->n;
    const vane_pupil vp = vane_pupil_of(pupil);
    memset(f->in, 0, (size_t)f->rows * (size_t)n * sizeof *f->in);
    double dx = 2.0 / samples; /* in primary radii */
    int lo, hi;
    pupil_extent(n, samples, &lo, &hi);
    for (int r = lo; r <= hi; r++) {
        double y = (r + 0.5 - n / 2) * dx, power = 0;
        float *row = f->in + (size_t)(r - f->lo) * n;
        for (int c = lo; c <= hi; c++) {
            float t = pupil_pixel(&vp, (c + 0.5 - n / 2) * dx, y, dx, g->supersample);
            row[c] = t;
            power += (double)t * t;
        }
        f->row_power[r - f->lo] = power;
    }
    double power = 0;
    for (int r = lo; r <= hi; r++)
        power += f->row_power[r - f->lo];
    return power;
}

/* |F|^2 at frequency (kx, ky), kx signed, ky wrapped into [0, n). */
static double power_at(const pupil_fft *f, int kx, int ky)
{
    const float *z = kx >= 0 ? f->far[(size_t)ky * f->cols + kx]
                             : f->far[(size_t)((f->n - ky) % f->n) * f->cols + (size_t)-kx];
    return (double)z[0] * z[0] + (double)z[1] * z[1];
}

/* Adds weight x the transform's power in each output pixel's m x m
 * sub-samples. Frequency index k (wrapped modulo n) is angle k * scale / m;
 * output row i is at angle (size/2 - i) * scale, +y up. */
static void bin_power(const psf_grid *g, const pupil_fft *f, double weight, double *acc)
{
    int n = g->n, m = g->m, c = g->size / 2, h = (m - 1) / 2;
    for (int i = 0; i < g->size; i++) {
        for (int j = 0; j < g->size; j++) {
            double sum = 0;
            for (int b = 0; b < m; b++) {
                int ky = ((m * (c - i) + b - h) % n + n) % n;
                for (int a = 0; a < m; a++)
                    sum += power_at(f, m * (j - c) + a - h, ky);
            }
            acc[(size_t)i * g->size + j] += weight * sum;
        }
    }
}

static void pupil_fft_free(pupil_fft *f)
{
    if ((f->rows_plan || f->cols_plan) && orr_fft_planner_lock(NULL) == ORR_OK) {
        if (f->rows_plan)
            fftwf_destroy_plan(f->rows_plan);
        if (f->cols_plan)
            fftwf_destroy_plan(f->cols_plan);
        orr_fft_planner_unlock();
    }
    fftwf_free(f->in);
    fftwf_free(f->spec);
    fftwf_free(f->far);
    free(f->row_power);
    memset(f, 0, sizeof *f);
}

static orr_status pupil_fft_plan(pupil_fft *f, orr_error *err)
{
    const int n = f->n, nh = n / 2 + 1;
    orr_status st = orr_fft_planner_lock(err);
    if (st)
        return st;
    fftwf_plan_with_nthreads(1);
    f->rows_plan = fftwf_plan_many_dft_r2c(1, &n, f->rows, f->in, NULL, 1, n, f->spec + (size_t)f->lo * nh, NULL, 1,
                                           nh, FFTW_ESTIMATE);
    f->cols_plan = fftwf_plan_many_dft(1, &n, f->cols, f->spec, NULL, nh, 1, f->far, NULL, f->cols, 1, FFTW_FORWARD,
                                       FFTW_ESTIMATE);
    orr_fft_planner_unlock();
    if (!f->rows_plan || !f->cols_plan)
        return orr_fail(err, ORR_ERR_INTERNAL, "PSF: FFTW could not plan a %d x %d transform", n, n);
    return ORR_OK;
}

/* The buffers and plans for the grid, the pupil at its widest being
 * samples across. */
static orr_status pupil_fft_init(pupil_fft *f, const psf_grid *g, double samples, orr_error *err)
{
    const int n = g->n, nh = n / 2 + 1;
    int hi;
    memset(f, 0, sizeof *f);
    f->n = n;
    pupil_extent(n, samples, &f->lo, &hi);
    f->rows = hi - f->lo + 1;
    f->cols = g->m * (g->size / 2) + (g->m - 1) / 2 + 1;
    f->cols = f->cols > nh ? nh : f->cols;
    f->in = fftwf_alloc_real((size_t)f->rows * n);
    f->spec = fftwf_alloc_complex((size_t)n * nh);
    f->far = fftwf_alloc_complex((size_t)n * f->cols);
    f->row_power = calloc((size_t)f->rows, sizeof *f->row_power);
    if (!f->in || !f->spec || !f->far || !f->row_power) {
        pupil_fft_free(f);
        return orr_fail(err, ORR_ERR_NOMEM, "PSF: out of memory for a %d x %d transform", n, n);
    }
    memset(f->spec, 0, (size_t)n * nh * sizeof *f->spec);
    orr_status st = pupil_fft_plan(f, err);
    if (st)
        pupil_fft_free(f);
    return st;
}

static void pupil_fft_execute(pupil_fft *f)
{
    fftwf_execute(f->rows_plan);
    fftwf_execute(f->cols_plan);
}

/* ---- bands ------------------------------------------------------------------ */

static double band_lambda(const orr_psf_band *b, int i)
{
    return 1e-9 * (b->lambda_min_nm + (i + 0.5) * (b->lambda_max_nm - b->lambda_min_nm) / b->samples);
}

/* The band's PSF into acc: every wavelength's power normalised to 1 over
 * the whole transform (Parseval: n^2 sum |pupil|^2), then averaged, so acc
 * sums to the fraction of the band's light inside the kernel. */
static void band_psf(const orr_psf_params *p, const psf_grid *g, const orr_psf_band *band, pupil_fft *f,
                     double *acc)
{
    memset(acc, 0, (size_t)g->size * (size_t)g->size * sizeof *acc);
    for (int i = 0; i < band->samples; i++) {
        double power = draw_pupil(&p->pupil, g, pupil_samples(g, band_lambda(band, i)), f);
        if (power <= 0)
            continue; /* a fully dark pupil: no light at this wavelength */
        pupil_fft_execute(f);
        double total = (double)g->n * g->n * power;
        bin_power(g, f, 1.0 / (total * band->samples), acc);
    }
}

static orr_status store_kernel(const psf_grid *g, const double *acc, double taper, orr_image_kernel *k,
                               double *captured, orr_error *err)
{
    orr_status st = orr_image_kernel_alloc(k, g->size, g->size, err);
    if (st)
        return st;
    size_t n = (size_t)g->size * (size_t)g->size;
    double sum = 0;
    for (size_t i = 0; i < n; i++)
        sum += acc[i];
    *captured = sum;
    if (!(sum > 0)) {
        orr_image_kernel_free(k);
        return orr_fail(err, ORR_ERR_USAGE, "PSF: the pupil lets no light through");
    }
    for (size_t i = 0; i < n; i++)
        k->data[i] = (float)(acc[i] / sum);
    k->arcsec_per_pixel = g->scale / ARCSEC_RAD;
    if (!(st = orr_image_kernel_taper(k, taper, err)))
        st = orr_image_kernel_normalise(k, err);
    if (st)
        orr_image_kernel_free(k);
    return st;
}

static void wavelength_range(const orr_psf_params *p, double *lo, double *hi)
{
    *lo = INFINITY;
    *hi = 0;
    for (int b = 0; b < p->nbands; b++) {
        *lo = fmin(*lo, band_lambda(&p->bands[b], 0));
        *hi = fmax(*hi, band_lambda(&p->bands[b], p->bands[b].samples - 1));
    }
}

orr_status orr_psf_generate(const orr_psf_params *p, orr_image_kernel *kernels, orr_psf_report *report,
                            orr_error *err)
{
    orr_status st = check_params(p, err);
    if (st)
        return st;
    for (int b = 0; b < p->nbands; b++)
        memset(&kernels[b], 0, sizeof kernels[b]);
    double lam_min, lam_max;
    wavelength_range(p, &lam_min, &lam_max);
    psf_grid g = {0};
    if ((st = plan_grid(p, lam_min, lam_max, &g, err)))
        return st;
    pupil_fft f;
    double *acc = orr_malloc((size_t)g.size * (size_t)g.size * sizeof *acc, "PSF accumulator", err);
    if (!acc)
        return ORR_ERR_NOMEM;
    if ((st = pupil_fft_init(&f, &g, pupil_samples(&g, lam_min), err))) {
        free(acc);
        return st;
    }
    double captured[ORR_PSF_MAX_BANDS] = {0};
    for (int b = 0; b < p->nbands && !st; b++) {
        band_psf(p, &g, &p->bands[b], &f, acc);
        st = store_kernel(&g, acc, p->taper, &kernels[b], &captured[b], err);
    }
    pupil_fft_free(&f);
    free(acc);
    if (st) {
        for (int b = 0; b < p->nbands; b++)
            orr_image_kernel_free(&kernels[b]);
        return st;
    }
    if (report) {
        memset(report, 0, sizeof *report);
        report->fft_size = g.n;
        report->oversample = g.m;
        report->pupil_samples_min = pupil_samples(&g, lam_max);
        report->pupil_samples_max = pupil_samples(&g, lam_min);
        memcpy(report->captured, captured, sizeof captured);
    }
    return ORR_OK;
}
