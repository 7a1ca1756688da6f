#include <fitsio.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "encode/fits.h"
#include "encode/png.h"
#include "post/colormap.h"
#include "post/convolve.h"
#include "post/psf.h"
#include "post/stretch.h"
#include "test_random.h"
#include "tmpdir.h"

#define PI 3.14159265358979323846

/* Set when a shared reference file is absent: the other checks still run,
 * then the program exits with SKIP_CODE if they passed. */
static int shared_skipped;

static float kat(const orr_image_kernel *k, int x, int y)
{
    return k->data[(size_t)y * k->width + x];
}

static float kernel_peak(const orr_image_kernel *k, int *px, int *py)
{
    float best = -1;
    for (int y = 0; y < k->height; y++)
        for (int x = 0; x < k->width; x++)
            if (kat(k, x, y) > best) {
                best = kat(k, x, y);
                *px = x;
                *py = y;
            }
    return best;
}

/* Mean of the kernel over radii [r0, r1] pixels at angle phi (degrees,
 * counterclockwise from +x with +y up). */
static double ray_mean(const orr_image_kernel *k, double phi, double r0, double r1)
{
    double s = 0;
    int n = 0;
    for (double r = r0; r <= r1; r += 0.25, n++)
        s += orr_image_kernel_sample(k, r * cos(phi * PI / 180), -r * sin(phi * PI / 180));
    return s / n;
}

/* ---- the pupil ---------------------------------------------------------- */

static void test_pupil_geometry(void)
{
    orr_pupil p;
    orr_pupil_hst(&p);
    CHECK_NEAR(p.diameter_m, 2.4, 0);
    CHECK(!orr_pupil_open(&p, 0, 0));          /* secondary */
    CHECK(!orr_pupil_open(&p, 0.3, 0.1));       /* still inside 0.330 */
    CHECK(!orr_pupil_open(&p, 0.5, 0.5));       /* on the 45-degree vane */
    CHECK(!orr_pupil_open(&p, -0.5, 0.5));      /* and on the one across it */
    CHECK(orr_pupil_open(&p, 0.65, 0));
    CHECK(!orr_pupil_open(&p, 1.01, 0));
    /* pad 2 at (-0.4615, 0.7555) in the vanes' frame, turned by 45 degrees */
    double a = PI / 4, px = -0.4615 * cos(a) - 0.7555 * sin(a), py = -0.4615 * sin(a) + 0.7555 * cos(a);
    CHECK(!orr_pupil_open(&p, px, py));
    CHECK(orr_pupil_open(&p, px * 0.88, py * 0.88));
    /* Open area: annulus minus four vanes minus three pads (pad 1 sits on a
     * vane, so their overlap, about 2 * 0.065 * 0.022, is counted back). */
    int n = 2000, open = 0;
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++)
            open += orr_pupil_open(&p, -1 + (i + 0.5) * 2.0 / n, -1 + (j + 0.5) * 2.0 / n);
    double area = open * 4.0 / ((double)n * n);
    double expect = PI * (1 - 0.33 * 0.33) - 4 * 0.022 * (1 - 0.33) - 3 * PI * 0.065 * 0.065 + 2 * 0.065 * 0.022;
    fprintf(stderr, "  open area %.4f pi R^2 (expected %.4f)\n", area / PI, expect / PI);
    CHECK_NEAR(area, expect, 0.003);
}

/* ---- generated PSFs ----------------------------------------------------- */

static void check_normalised_symmetric(const orr_image_kernel *k)
{
    CHECK_NEAR(orr_image_kernel_sum(k), 1.0, 1e-5);
    int px = -1, py = -1;
    float peak = kernel_peak(k, &px, &py);
    CHECK(px == k->width / 2 && py == k->height / 2);
    double worst = 0;
    for (int y = 0; y < k->height; y++)
        for (int x = 0; x < k->width; x++)
            worst = fmax(worst, fabs(kat(k, x, y) - kat(k, k->width - 1 - x, k->height - 1 - y)));
    CHECK(worst <= 1e-5 * peak);
}

/* The four spikes: the azimuthal profile over an annulus of 8 to 16 lambda/D
 * has its maxima at angle + k 90 degrees, well above the level between them. */
static void check_spikes(const orr_image_kernel *k, double angle)
{
    double prof[360], sorted_med = 0;
    for (int phi = 0; phi < 360; phi++)
        prof[phi] = ray_mean(k, phi, 15, 30);
    double tmp[360];
    memcpy(tmp, prof, sizeof tmp);
    for (int i = 0; i < 360; i++) /* a small sort for the median */
        for (int j = i + 1; j < 360; j++)
            if (tmp[j] < tmp[i]) {
                double t = tmp[i];
                tmp[i] = tmp[j];
                tmp[j] = t;
            }
    sorted_med = 0.5 * (tmp[179] + tmp[180]);
    for (int q = 0; q < 4; q++) {
        double expect = fmod(angle + 90.0 * q, 360.0);
        int best = -1;
        for (int d = -30; d <= 30; d++) {
            int phi = ((int)lround(expect) + d + 360) % 360;
            if (best < 0 || prof[phi] > prof[best])
                best = phi;
        }
        double off = fmod(best - expect + 540.0, 360.0) - 180.0;
        fprintf(stderr, "  spike %d: expected %.0f, found %d (%.1f x the median)\n", q, expect, best,
                prof[best] / sorted_med);
        CHECK(fabs(off) <= 3);
        CHECK(prof[best] > 1.5 * sorted_med);
    }
}

static void test_hst_psf(void)
{
    orr_psf_params p;
    orr_psf_hst_defaults(&p);
    orr_image_kernel k[3];
    orr_psf_report rep;
    orr_error err;
    CHECK(orr_psf_generate(&p, k, &rep, &err) == ORR_OK);
    fprintf(stderr, "  FFT %d, oversample %d, pupil %.0f..%.0f samples; captured B %.4f G %.4f R %.4f\n",
            rep.fft_size, rep.oversample, rep.pupil_samples_min, rep.pupil_samples_max, rep.captured[0],
            rep.captured[1], rep.captured[2]);
    for (int b = 0; b < 3; b++) {
        CHECK(k[b].width == 129 && k[b].height == 129);
        CHECK_NEAR(k[b].arcsec_per_pixel, 0.04, 1e-12);
        check_normalised_symmetric(&k[b]);
        CHECK(rep.captured[b] > 0.9 && rep.captured[b] < 1.0);
    }
    check_spikes(&k[1], 45);
    /* Chromatic: the core holds more of the light in blue than in red. */
    double core[3];
    for (int b = 0; b < 3; b++) {
        core[b] = 0;
        for (int y = 62; y <= 66; y++)
            for (int x = 62; x <= 66; x++)
                core[b] += kat(&k[b], x, y);
    }
    fprintf(stderr, "  light in the central 5x5 pixels: B %.3f G %.3f R %.3f\n", core[0], core[1], core[2]);
    CHECK(core[0] > core[1] && core[1] > core[2]);
    for (int b = 0; b < 3; b++)
        orr_image_kernel_free(&k[b]);

    /* Turning the vanes by 30 degrees turns the spikes with them. */
    p.pupil.angle_deg = 75;
    p.nbands = 1;
    CHECK(orr_psf_generate(&p, k, NULL, &err) == ORR_OK);
    check_spikes(&k[0], 75);
    check_normalised_symmetric(&k[0]);
    orr_image_kernel_free(&k[0]);
}

/* J1 by its integral representation, J1(x) = (1/pi) int_0^pi cos(t - x sin t) dt
 * (Simpson's rule; plenty for x < 10). */
static double bessel_j1(double x)
{
    int n = 400;
    double h = PI / n, s = 0;
    for (int i = 0; i <= n; i++) {
        double t = i * h, w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
        s += w * cos(t - x * sin(t));
    }
    return s * h / 3 / PI;
}

/* First zero of the amplitude of an annular aperture of obscuration e:
 * 2 J1(x)/x - e^2 2 J1(e x)/(e x), x = pi D theta / lambda. */
static double annular_first_zero(double e)
{
    double lo = 2.5, hi = 4.0;
    for (int i = 0; i < 60; i++) {
        double mid = 0.5 * (lo + hi);
        double f = 2 * bessel_j1(mid) / mid - e * e * 2 * bessel_j1(e * mid) / (e * mid);
        if (f > 0)
            lo = mid;
        else
            hi = mid;
    }
    return 0.5 * (lo + hi);
}

/* Radius (pixels) of the first minimum of the azimuthally averaged profile. */
static double first_dark_ring(const orr_image_kernel *k)
{
    double prev2 = 1e30, prev = 1e30, step = 0.02;
    for (double r = 0.5; r < k->width / 2 - 1; r += step) {
        double s = 0;
        int n = 0;
        for (int a = 0; a < 360; a++, n++)
            s += orr_image_kernel_sample(k, r * cos(a * PI / 180), -r * sin(a * PI / 180));
        s /= n;
        if (prev < prev2 && prev < s) {
            double den = prev2 - 2 * prev + s;
            return r - step + (den > 0 ? 0.5 * step * (prev2 - s) / den : 0);
        }
        prev2 = prev;
        prev = s;
    }
    return -1;
}

static void test_dark_ring_scales_with_wavelength(void)
{
    orr_psf_params p;
    orr_psf_hst_defaults(&p);
    p.arcsec_per_pixel = 0.004; /* 10 to 14 pixels per lambda/D: fine enough to place a minimum */
    p.size = 65;
    p.nbands = 2;
    snprintf(p.bands[0].name, sizeof p.bands[0].name, "450");
    p.bands[0].lambda_min_nm = p.bands[0].lambda_max_nm = 450;
    p.bands[0].samples = 1;
    snprintf(p.bands[1].name, sizeof p.bands[1].name, "650");
    p.bands[1].lambda_min_nm = p.bands[1].lambda_max_nm = 650;
    p.bands[1].samples = 1;
    orr_image_kernel k[2];
    orr_error err;
    CHECK(orr_psf_generate(&p, k, NULL, &err) == ORR_OK);
    double x1 = annular_first_zero(0.33);
    double r450 = first_dark_ring(&k[0]), r650 = first_dark_ring(&k[1]);
    double e450 = x1 / PI * orr_lambda_over_d_arcsec(450, 2.4) / p.arcsec_per_pixel;
    double e650 = x1 / PI * orr_lambda_over_d_arcsec(650, 2.4) / p.arcsec_per_pixel;
    fprintf(stderr, "  first dark ring: 450 nm %.3f px (annulus %.3f), 650 nm %.3f px (annulus %.3f); ratio %.4f\n",
            r450, e450, r650, e650, r650 / r450);
    CHECK_NEAR(r650 / r450, 650.0 / 450.0, 0.01 * 650.0 / 450.0);
    CHECK_NEAR(r450, e450, 0.02 * e450);
    CHECK_NEAR(r650, e650, 0.02 * e650);
    orr_image_kernel_free(&k[0]);
    orr_image_kernel_free(&k[1]);
}

static void test_generate_errors(void)
{
    orr_psf_params p;
    orr_psf_hst_defaults(&p);
    orr_image_kernel k[ORR_PSF_MAX_BANDS];
    orr_error err;
    p.size = 128;
    CHECK(orr_psf_generate(&p, k, NULL, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "odd");
    orr_psf_hst_defaults(&p);
    p.arcsec_per_pixel = 0.0005; /* far finer than the pupil sampling allows */
    CHECK(orr_psf_generate(&p, k, NULL, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "transform");
    orr_psf_hst_defaults(&p);
    p.bands[1].lambda_max_nm = 100; /* below lambda_min */
    CHECK(orr_psf_generate(&p, k, NULL, &err) == ORR_ERR_USAGE);
    orr_psf_hst_defaults(&p);
    p.oversample = 1;
    p.arcsec_per_pixel = 0.1; /* coarser than Nyquist without sub-pixels */
    CHECK(orr_psf_generate(&p, k, NULL, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "Nyquist");
    orr_psf_hst_defaults(&p);
    p.pupil.obscuration = 1.0;
    CHECK(orr_psf_generate(&p, k, NULL, &err) == ORR_ERR_USAGE);
}

/* ---- resampling and FITS ------------------------------------------------ */

static void test_rebin_is_binning(void)
{
    float img[12 * 12], out[25];
    uint64_t s = 5;
    for (int i = 0; i < 144; i++)
        img[i] = (float)test_uniform(&s);
    orr_error err;
    /* odd ratio, centre on a pixel centre: 3x3 blocks starting at pixel 2 */
    CHECK(orr_image_rebin(img, 12, 12, 6.5, 6.5, 3, 3, out, &err) == ORR_OK);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double sum = 0;
            for (int y = 2 + 3 * i; y < 5 + 3 * i; y++)
                for (int x = 2 + 3 * j; x < 5 + 3 * j; x++)
                    sum += img[y * 12 + x];
            CHECK_NEAR(out[i * 3 + j], sum, 1e-5);
        }
    /* even ratio, centre on a pixel corner: 2x2 blocks starting at pixel 1 */
    CHECK(orr_image_rebin(img, 12, 12, 6.0, 6.0, 2, 5, out, &err) == ORR_OK);
    CHECK_NEAR(out[0], img[13] + img[14] + img[25] + img[26], 1e-5);
    /* any ratio and offset conserves the flux that lies inside */
    double total = 0, got = 0;
    for (int i = 0; i < 144; i++)
        total += img[i];
    CHECK(orr_image_rebin(img, 12, 12, 6.3, 5.8, 2.7, 5, out, &err) == ORR_OK); /* covers 13.5 px */
    for (int i = 0; i < 25; i++)
        got += out[i];
    CHECK_NEAR(got, total, 1e-4);
    CHECK(orr_image_rebin(img, 12, 12, 6, 6, 0, 5, out, &err) == ORR_ERR_USAGE);
}

static void test_nicmos_fits(void)
{
    char path[1024];
    if (!shared_data_path(path, sizeof path, "psf/nic2_f160w_4xsub00.fits")) {
        shared_skipped = 1;
        return;
    }
    orr_psf_fits_options o = {.subsample = 4};
    orr_psf_fits_info info;
    orr_image_kernel k;
    orr_error err;
    CHECK(orr_psf_load_fits(path, &o, &k, &info, &err) == ORR_OK);
    fprintf(stderr, "  NICMOS: %dx%d -> %dx%d, centre (%.3f, %.3f), scale %.4f, captured %.5f\n",
            info.file_width, info.file_height, k.width, k.height, info.centre_x, info.centre_y,
            info.file_arcsec_per_pixel, info.captured);
    CHECK(info.file_width == 528 && info.file_height == 528);
    CHECK_NEAR(info.file_arcsec_per_pixel, 0.0189, 1e-9);
    CHECK_NEAR(info.ratio, 4, 0);
    CHECK(k.width == 131 && k.height == 131); /* 528 / 4 = 132, odd */
    CHECK_NEAR(k.arcsec_per_pixel, 4 * 0.0189, 1e-9);
    CHECK_NEAR(orr_image_kernel_sum(&k), 1.0, 1e-5);
    CHECK(info.captured > 0.99);
    int px = 0, py = 0;
    kernel_peak(&k, &px, &py);
    CHECK(px == 65 && py == 65);
    /* FITS row 264 (0-based, from the bottom) is our row 528 - 1 - 264 = 263 */
    CHECK_NEAR(info.centre_x, 264.5, 0.5);
    CHECK_NEAR(info.centre_y, 263.5, 0.5);
    orr_image_kernel_free(&k);

    /* resampled to the camera's 0.075 arcsec pixels, centroid centring */
    o.arcsec_per_pixel = 0.075;
    o.centre = ORR_PSF_CENTRE_CENTROID;
    o.size = 63;
    CHECK(orr_psf_load_fits(path, &o, &k, &info, &err) == ORR_OK);
    CHECK(k.width == 63);
    CHECK_NEAR(info.ratio, 0.075 / 0.0189, 1e-9);
    CHECK_NEAR(k.arcsec_per_pixel, 0.075, 1e-9);
    CHECK_NEAR(orr_image_kernel_sum(&k), 1.0, 1e-5);
    kernel_peak(&k, &px, &py);
    CHECK(px == 31 && py == 31);
    orr_image_kernel_free(&k);
}

static void test_acs_fits(void)
{
    char path[1024];
    if (!shared_data_path(path, sizeof path, "psf/acs_wfc_f814w_ngc5128_psf.fits")) {
        shared_skipped = 1;
        return;
    }
    orr_psf_fits_options o = {.subtract_background = 1};
    orr_psf_fits_info info;
    orr_image_kernel k;
    orr_error err;
    CHECK(orr_psf_load_fits(path, &o, &k, &info, &err) == ORR_OK);
    CHECK(k.width == 19 && k.height == 19);
    CHECK_NEAR(orr_image_kernel_sum(&k), 1.0, 1e-5);
    int px = 0, py = 0;
    kernel_peak(&k, &px, &py);
    CHECK(px == 9 && py == 9);
    CHECK(info.background >= 0);
    CHECK(k.arcsec_per_pixel == 0); /* no PIXSCALE, none given */
    orr_image_kernel_free(&k);
    /* no PIXSCALE in this file: a target scale needs the file's */
    o.arcsec_per_pixel = 0.1;
    CHECK(orr_psf_load_fits(path, &o, &k, &info, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "PIXSCALE");
    CHECK_CONTAINS(err.msg, "psf.arcsec_per_pixel: 0"); /* the scene's way out */
    o.file_arcsec_per_pixel = 0.05;
    CHECK(orr_psf_load_fits(path, &o, &k, &info, &err) == ORR_OK);
    CHECK(k.width == 9); /* 19 / 2 */
    orr_image_kernel_free(&k);
}

/* A 33 x 33 Gaussian PSF of peak `peak` and pixscale arcsec pixels
 * (PIXSCALE), written with orrery's own FITS writer into the scratch folder. */
static const char *write_psf(const char *name, double pixscale, double peak)
{
    static char path[512];
    snprintf(path, sizeof path, "%s/%s", tmpdir, name);
    orr_plane p;
    orr_error err;
    CHECK(orr_plane_alloc(&p, 33, 33, "PSF", "", &err) == ORR_OK);
    for (int y = 0; y < 33; y++)
        for (int x = 0; x < 33; x++)
            p.data[y * 33 + x] = (float)(peak * exp(-((x - 16) * (x - 16) + (y - 16) * (y - 16)) / 8.0));
    orr_cards h = {0};
    orr_cards_add_double(&h, "PIXSCALE", pixscale, "arcsec per pixel");
    CHECK(orr_write_fits(path, &p, 1, &h, &err) == ORR_OK);
    orr_plane_free(&p);
    return path;
}

/* A 33 x 33 Gaussian PSF of 0.02 arcsec pixels. */
static const char *write_gaussian_psf(const char *name) { return write_psf(name, 0.02, 1.0); }

/* A PIXSCALE of 0 or below is told as what it is, not as a missing
 * keyword; a kernel that overflows single precision names the element and
 * its value (the message used to read as if the index were the value). */
static void test_bad_pixscale_and_values(void)
{
    orr_image_kernel k;
    orr_error err;
    orr_psf_fits_options o = {.arcsec_per_pixel = 0.04};
    const double scales[2] = {0, -1};
    for (int i = 0; i < 2; i++) {
        const char *path = write_psf("badscale.fits", scales[i], 1.0);
        CHECK(orr_psf_load_fits(path, &o, &k, NULL, &err) == ORR_ERR_FORMAT);
        CHECK_CONTAINS(err.msg, i == 0 ? "PIXSCALE = 0 is not a pixel scale" : "PIXSCALE = -1 is not a pixel scale");
        CHECK(!strstr(err.msg, "no PIXSCALE"));
    }
    /* The file's own pixels need no scale. */
    o.arcsec_per_pixel = 0;
    CHECK(orr_psf_load_fits(write_psf("badscale.fits", 0, 1.0), &o, &k, NULL, &err) == ORR_OK);
    orr_image_kernel_free(&k);
    /* Peaks of 3e38: their sum is beyond a float. */
    o.arcsec_per_pixel = 0.04;
    CHECK(orr_psf_load_fits(write_psf("huge.fits", 0.02, 3e38), &o, &k, NULL, &err) != ORR_OK);
    CHECK_CONTAINS(err.msg, "is inf, not a finite number");
}

/* psf.arcsec_per_pixel far beyond the PSF image (1e6 arcsec) used to reach
 * unchecked float-to-int conversions in the rebinning (undefined; the
 * release build drew no PSF at all): refused, naming the key and range. */
static void test_scale_out_of_range(void)
{
    const char *path = write_gaussian_psf("gauss.fits");
    orr_image_kernel k;
    orr_error err;
    orr_psf_fits_options o = {.arcsec_per_pixel = 1e6, .size = 129};
    CHECK(orr_psf_load_fits(path, &o, &k, NULL, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, path);
    CHECK_CONTAINS(err.msg, "psf.arcsec_per_pixel = 1e+06 is out of range for this PSF: it must be above 0 and at "
                            "most 0.66 arcsec (an output pixel no larger than the 33 x 33 image");
    /* The largest scale is allowed: the whole image in one output pixel. */
    o.arcsec_per_pixel = 0.66;
    o.size = 3;
    CHECK(orr_psf_load_fits(path, &o, &k, NULL, &err) == ORR_OK);
    orr_image_kernel_free(&k);
    /* An automatic size must stay below 8192 pixels. */
    o.arcsec_per_pixel = 1e-9;
    o.size = 0;
    CHECK(orr_psf_load_fits(path, &o, &k, NULL, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "psf.arcsec_per_pixel = 1e-09 is out of range for this PSF: it must be at least 8.05762e-05");
    CHECK_CONTAINS(err.msg, "and an automatic size of at most 8191 pixels");
    o.size = 129; /* with a size given, a tiny scale only magnifies the core */
    CHECK(orr_psf_load_fits(path, &o, &k, NULL, &err) == ORR_OK);
    orr_image_kernel_free(&k);
    /* The case: the shipped NICMOS PSF (0.0189 arcsec, 528 pixels). */
    char nicmos[1024];
    if (shared_data_path(nicmos, sizeof nicmos, "psf/nic2_f160w_4xsub00.fits")) {
        o = (orr_psf_fits_options){.arcsec_per_pixel = 1e6, .size = 129, .subsample = 4};
        CHECK(orr_psf_load_fits(nicmos, &o, &k, NULL, &err) == ORR_ERR_USAGE);
        CHECK_CONTAINS(err.msg, "psf.arcsec_per_pixel = 1e+06 is out of range for this PSF: it must be above 0 "
                                "and at most 9.9792 arcsec");
    } else {
        shared_skipped = 1;
    }
    /* The rebinning itself refuses pixel edges beyond an int. */
    float img[144] = {0}, out[25];
    CHECK(orr_image_rebin(img, 12, 12, 6, 6, 1e9, 5, out, &err) == ORR_ERR_USAGE);
    CHECK(orr_image_rebin(img, 12, 12, 3e9, 6, 2, 5, out, &err) == ORR_ERR_USAGE);
}

/* psf.file is opened as named: brackets are not cfitsio's extended syntax
 * (which would read "psf[1].fits" as extension 1 of "psf"). */
static void test_file_name_with_brackets(void)
{
    const char *path = write_gaussian_psf("psf[1].fits");
    orr_image_kernel k;
    orr_error err;
    orr_psf_fits_options o = {.size = 9};
    orr_status st = orr_psf_load_fits(path, &o, &k, NULL, &err);
    CHECK(st == ORR_OK);
    if (st != ORR_OK) {
        fprintf(stderr, "  %s\n", err.msg);
        return;
    }
    CHECK(k.width == 9 && k.arcsec_per_pixel == 0.02);
    CHECK_NEAR(orr_image_kernel_sum(&k), 1.0, 1e-5);
    orr_image_kernel_free(&k);
    /* As fits_open_image did: an empty primary HDU, the PSF in extension 1. */
    char ext[512];
    snprintf(ext, sizeof ext, "%s/ext[2].fits", tmpdir);
    fitsfile *f = NULL;
    int status = 0;
    long naxes[2] = {5, 5};
    float pix[25] = {0};
    pix[12] = 1;
    fits_create_diskfile(&f, ext, &status);
    fits_create_img(f, FLOAT_IMG, 0, NULL, &status);
    fits_create_img(f, FLOAT_IMG, 2, naxes, &status);
    fits_write_img(f, TFLOAT, 1, 25, pix, &status);
    fits_close_file(f, &status);
    CHECK(status == 0);
    o.size = 5;
    CHECK(orr_psf_load_fits(ext, &o, &k, NULL, &err) == ORR_OK);
    CHECK(k.width == 5 && k.data[12] == 1.0f);
    orr_image_kernel_free(&k);
}

static void test_fits_errors(void)
{
    orr_image_kernel k;
    orr_error err;
    CHECK(orr_psf_load_fits("/nonexistent/psf.fits", NULL, &k, NULL, &err) == ORR_ERR_IO);
    CHECK_CONTAINS(err.msg, "/nonexistent/psf.fits");
    orr_psf_fits_options o = {.size = 10};
    CHECK(orr_psf_load_fits("x.fits", &o, &k, NULL, &err) == ORR_ERR_USAGE);

    /* A header claiming 16384 x 16384 pixels with one block of data: an
     * error before the 1 GiB image is allocated (found by fuzz_fits: it
     * took 4.5 s under ASan, reading nothing). main() made tmpdir. */
    char path[512], block[2880];
    snprintf(path, sizeof path, "%s/claims.fits", tmpdir);
    memset(block, ' ', sizeof block);
    const char *cards[] = {"SIMPLE  =                    T", "BITPIX  =                  -32",
                           "NAXIS   =                    2", "NAXIS1  =                16384",
                           "NAXIS2  =                16384", "END"};
    for (int i = 0; i < 6; i++)
        memcpy(block + 80 * i, cards[i], strlen(cards[i]));
    FILE *fp = fopen(path, "wb");
    CHECK(fp != NULL);
    if (fp) {
        fwrite(block, 1, sizeof block, fp);
        memset(block, 0, sizeof block);
        fwrite(block, 1, sizeof block, fp);
        fclose(fp);
    }
    CHECK(orr_psf_load_fits(path, NULL, &k, NULL, &err) == ORR_ERR_FORMAT);
    CHECK_CONTAINS(err.msg, "claims.fits");
    CHECK(k.data == NULL);

    /* A tile-compressed PSF is refused before cfitsio decompresses it (4.2
     * crashes on a damaged tile: tests/data/fits/regress_psf_rice_tile_damaged.fits). */
    snprintf(path, sizeof path, "%s/packed.fits", tmpdir);
    fitsfile *f = NULL;
    int status = 0, ipx[25] = {0};
    long naxes[2] = {5, 5};
    ipx[12] = 100;
    fits_create_file(&f, path, &status);
    fits_create_img(f, FLOAT_IMG, 0, NULL, &status);
    fits_set_compression_type(f, RICE_1, &status);
    fits_create_img(f, LONG_IMG, 2, naxes, &status);
    fits_write_img(f, TINT, 1, 25, ipx, &status);
    fits_close_file(f, &status);
    CHECK(status == 0);
    CHECK(orr_psf_load_fits(path, NULL, &k, NULL, &err) == ORR_ERR_FORMAT);
    CHECK_CONTAINS(err.msg, "uncompressed");
    CHECK(orr_psf_load_fits(ORRERY_TEST_DATA "/fits/regress_psf_rice_tile_damaged.fits", NULL, &k, NULL, &err) ==
          ORR_ERR_FORMAT);
    CHECK_CONTAINS(err.msg, "uncompressed");

    /* An empty primary HDU and a cut-short image extension: cfitsio's
     * fits_open_image fails but leaves the file open, which the loader must
     * close (found by fuzz_fits under LeakSanitizer). The next free file
     * descriptor is the same after the failed load as before. */
    const char *cut = ORRERY_SOURCE_DIR "/tests/fuzz/corpus/fits/regress_psf_open_fails_left_open.fits";
    int before = dup(0);
    close(before);
    for (int i = 0; i < 3; i++) {
        CHECK(orr_psf_load_fits(cut, NULL, &k, NULL, &err) != ORR_OK);
        CHECK_CONTAINS(err.msg, "regress_psf_open_fails_left_open.fits");
    }
    int after = dup(0);
    close(after);
    CHECK(after == before);
}

/* ---- star mode: a synthetic cluster ----------------------------------------
 * A few hundred point stars with power-law fluxes, convolved by the HST PSF
 * and log-stretched. Checks flux and the spikes around the brightest star;
 * with ORRERY_PSF_DEMO_DIR set, writes grey (luminance) and colour PNGs. */

typedef struct cluster {
    int n;
    int x[400], y[400];
    float f[400], colour[400][3];
} cluster;

static void make_cluster(cluster *c, int size)
{
    uint64_t s = 2024;
    c->n = 300;
    for (int i = 0; i < c->n; i++) {
        /* a concentrated cluster: radius ~ Plummer-like */
        double r = 0.3 * size * sqrt(pow(test_uniform(&s), -2.0 / 3.0) - 1) / 3, a = 2 * PI * test_uniform(&s);
        r = fmin(r, 0.5 * size - 70);
        c->x[i] = size / 2 + (int)(r * cos(a));
        c->y[i] = size / 2 + (int)(r * sin(a));
        c->f[i] = (float)pow(test_uniform(&s) + 1e-4, -1.5); /* dN/dF ~ F^(-5/3) */
        double t = test_uniform(&s); /* 0 = red giant, 1 = blue */
        c->colour[i][0] = (float)(1.0 - 0.5 * t);
        c->colour[i][1] = 0.85f;
        c->colour[i][2] = (float)(0.5 + 0.5 * t);
    }
    c->f[0] = 3e4f; /* one bright star in the middle, for the checks */
    c->x[0] = c->y[0] = size / 2;
}

static int compare_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Median of the plane along a ray from (x0, y0) at angle phi (degrees, +y
 * up), 15 to 45 pixels out: robust against other stars on the ray. */
static double ray_median(const orr_plane *p, int x0, int y0, double phi)
{
    double v[31];
    for (int r = 15; r <= 45; r++) {
        int x = x0 + (int)lround(r * cos(phi * PI / 180)), y = y0 - (int)lround(r * sin(phi * PI / 180));
        v[r - 15] = p->data[(size_t)y * p->width + x];
    }
    qsort(v, 31, sizeof v[0], compare_double);
    return v[15];
}

static void write_demo(const char *dir, const char *name, const float *rgb, int size)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    orr_error err;
    if (orr_write_png_rgb(path, size, size, rgb, 8, NULL, 0, &err))
        fprintf(stderr, "  %s\n", err.msg);
    else
        fprintf(stderr, "  wrote %s\n", path);
}

static void test_star_cluster(void)
{
    int size = 512;
    static cluster c;
    make_cluster(&c, size);
    orr_psf_params p;
    orr_psf_hst_defaults(&p);
    orr_image_kernel k[3];
    orr_error err;
    CHECK(orr_psf_generate(&p, k, NULL, &err) == ORR_OK);
    orr_plane lum, rgb[3];
    CHECK(orr_plane_alloc(&lum, size, size, "Y", "", &err) == ORR_OK);
    for (int b = 0; b < 3; b++)
        CHECK(orr_plane_alloc(&rgb[b], size, size, "c", "", &err) == ORR_OK);
    double total = 0;
    for (int i = 0; i < c.n; i++) {
        size_t at = (size_t)c.y[i] * size + c.x[i];
        lum.data[at] += c.f[i];
        total += c.f[i];
        for (int b = 0; b < 3; b++)
            rgb[b].data[at] += c.f[i] * c.colour[i][2 - b]; /* bands are B, G, R */
    }
    /* luminance: the G-band PSF stands in for the eye's response */
    CHECK(orr_convolve_plane(&lum, &k[1], NULL, &err) == ORR_OK);
    CHECK_NEAR(orr_plane_sum(&lum) / total, 1.0, 1e-6);
    for (int b = 0; b < 3; b++)
        CHECK(orr_convolve_plane(&rgb[b], &k[b], NULL, &err) == ORR_OK);
    /* the bright star's spikes: along the diagonals, not along the axes */
    double spike = INFINITY, off = 0;
    for (int q = 0; q < 4; q++) {
        spike = fmin(spike, ray_median(&lum, size / 2, size / 2, 45 + 90 * q));
        off = fmax(off, ray_median(&lum, size / 2, size / 2, 90 * q));
    }
    fprintf(stderr, "  bright star, 15 to 45 px out: %.3g on the spikes, %.3g between them\n", spike, off);
    CHECK(spike > 3 * off);

    orr_stretch st = {.kind = ORR_STRETCH_LOG, .white = 0, .white_percentile = 99.95, .n = 300};
    float *t = malloc((size_t)size * size * sizeof *t), *out = malloc((size_t)size * size * 3 * sizeof *out);
    double white = 0;
    CHECK(orr_stretch_apply(&st, &lum, t, &white, &err) == ORR_OK);
    for (size_t i = 0; i < (size_t)size * size; i++)
        orr_colormap_lookup(ORR_CMAP_GREY, t[i], out + 3 * i);
    const char *dir = getenv("ORRERY_PSF_DEMO_DIR");
    if (dir)
        write_demo(dir, "orrery_psf_cluster_grey.png", out, size);
    st.white = white;
    for (int b = 0; b < 3; b++) {
        CHECK(orr_stretch_apply(&st, &rgb[b], t, NULL, &err) == ORR_OK);
        for (size_t i = 0; i < (size_t)size * size; i++)
            out[3 * i + (2 - b)] = t[i];
    }
    if (dir)
        write_demo(dir, "orrery_psf_cluster_colour.png", out, size);
    free(t);
    free(out);
    orr_plane_free(&lum);
    for (int b = 0; b < 3; b++) {
        orr_plane_free(&rgb[b]);
        orr_image_kernel_free(&k[b]);
    }
}

/* The PSF's own checks (orr_psf_prepare), through a stand-in for the
 * scene's keys: the keys it names as given, each "set" on line 7 of
 * "s.yaml". */
static int fake_locate(const void *ctx, const char *key, char *prefix, size_t size)
{
    for (const char *const *k = ctx; key && *k; k++)
        if (strcmp(*k, key) == 0) {
            snprintf(prefix, size, "s.yaml:7: ");
            return 1;
        }
    snprintf(prefix, size, "s.yaml: ");
    return 0;
}

static void test_prepare_checks_keys(void)
{
    orr_psf_settings ps;
    orr_psf_settings_defaults(&ps);
    orr_error err = {0};
    CHECK(orr_psf_prepare(&ps, 0, NULL, &err) == ORR_OK);
    ps.size = 32;
    CHECK(orr_psf_prepare(&ps, 0, NULL, &err) == ORR_ERR_USAGE);
    CHECK(strcmp(err.msg, "psf.size must be odd (the PSF's centre is a pixel), got 32") == 0);
    const char *given[] = {"psf.size", NULL};
    orr_keys keys = {given, fake_locate};
    CHECK(orr_psf_prepare(&ps, 0, &keys, &err) == ORR_ERR_USAGE);
    CHECK(strcmp(err.msg, "s.yaml:7: psf.size must be odd (the PSF's centre is a pixel), got 32") == 0);
    ps.size = 31;
    ps.kind = ORR_PSF_FILE;
    CHECK(orr_psf_prepare(&ps, 0, &keys, &err) == ORR_ERR_USAGE);
    CHECK(strcmp(err.msg, "s.yaml: psf.kind: file needs psf.file, a FITS PSF image") == 0);
    /* A spike key is for stars drawn one by one: a sky map's, or a flat
     * view's given psf.fwhm. */
    ps.kind = ORR_PSF_HST;
    const char *spikes[] = {"psf.spike_stars", NULL};
    keys.ctx = spikes;
    CHECK(orr_psf_prepare(&ps, 1, &keys, &err) == ORR_OK);
    CHECK(orr_psf_prepare(&ps, 0, &keys, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "s.yaml:7: psf.spike_stars is for psf.kind: hst or file on sky maps");
    CHECK(!orr_psf_flat_stars(&ps, 0));
    ps.has_fwhm = 1;
    CHECK(orr_psf_flat_stars(&ps, 0) && !orr_psf_flat_stars(&ps, 1));
    CHECK(orr_psf_prepare(&ps, 0, &keys, &err) == ORR_OK);
    ps.kind = ORR_PSF_GAUSSIAN;
    CHECK(!orr_psf_flat_stars(&ps, 0));
}

int main(void)
{
    make_tmpdir();
    RUN(test_pupil_geometry);
    RUN(test_prepare_checks_keys);
    RUN(test_hst_psf);
    RUN(test_dark_ring_scales_with_wavelength);
    RUN(test_generate_errors);
    RUN(test_rebin_is_binning);
    RUN(test_nicmos_fits);
    RUN(test_acs_fits);
    RUN(test_fits_errors);
    RUN(test_scale_out_of_range);
    RUN(test_bad_pixscale_and_values);
    RUN(test_file_name_with_brackets);
    RUN(test_star_cluster);
    int status = check_summary();
    remove_tmpdir();
    return status == 0 && shared_skipped ? SKIP_CODE : status;
}
