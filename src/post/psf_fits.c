/* PSFs read from FITS images: Tiny Tim models, empirical star stamps.
 *
 * The steps, each for a reason:
 *   1. read the first image HDU and turn it so row 0 is the top (FITS keeps
 *      the bottom row first), non-finite pixels set to 0;
 *   2. optionally subtract a sky level (median of the outermost pixels), then
 *      clip negative values: a PSF is light, and negative wings would dig
 *      dark rings around every bright star;
 *   3. find the star: the brightest pixel refined to a fraction of a pixel
 *      (parabola or centroid);
 *   4. integrate the image over output pixels of the target scale centred on
 *      the star (flux-conserving; plain binning for aligned integer ratios);
 *   5. normalise to sum 1. */
#include "post/psf.h"

#include <fitsio.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/fits_scan.h"

#define FITS_MAX_SIDE 16384
/* The largest odd kernel side (psf.size and the automatic size alike). */
#define PSF_MAX_SIZE 8191

/* ---- resampling -------------------------------------------------------- */

/* Length of [a0, a1) inside the unit pixel [c, c + 1). */
static double overlap(double a0, double a1, int c)
{
    double lo = a0 > c ? a0 : c, hi = a1 < c + 1 ? a1 : c + 1;
    return hi > lo ? hi - lo : 0;
}

/* Integral over [a0, a1) of one image row of n pixels. */
static double row_integral(const float *line, int n, double a0, double a1)
{
    int c0 = (int)floor(a0), c1 = (int)ceil(a1) - 1;
    c0 = c0 < 0 ? 0 : c0;
    c1 = c1 > n - 1 ? n - 1 : c1;
    double s = 0;
    for (int c = c0; c <= c1; c++)
        s += overlap(a0, a1, c) * line[c];
    return s;
}

orr_status orr_image_rebin(const float *img, int w, int h, double xc, double yc, double ratio, int size,
                           float *out, orr_error *err)
{
    if (!img || w < 1 || h < 1 || size < 1 || !(ratio > 0) || !isfinite(ratio) || !isfinite(xc) ||
        !isfinite(yc))
        return orr_fail(err, ORR_ERR_USAGE, "rebin: bad arguments (image %d x %d, ratio %g, size %d)", w, h,
                        ratio, size);
    /* Every edge of an output pixel, in file pixels, is converted to int
     * (row_integral): they must lie well inside int's range. */
    double reach = fabs(xc) + fabs(yc) + ((double)size / 2 + 1) * ratio;
    if (!(reach < INT_MAX / 4))
        return orr_fail(err, ORR_ERR_USAGE,
                        "rebin: %d output pixels of %g image pixels around (%g, %g) reach beyond an int", size,
                        ratio, xc, yc);
    /* Separable: integrate along rows into a h x size table, then columns. */
    double *cols = orr_malloc((size_t)h * (size_t)size * sizeof *cols, "rebin table", err);
    if (!cols)
        return ORR_ERR_NOMEM;
    double x_first = xc - (size / 2 + 0.5) * ratio, y_first = yc - (size / 2 + 0.5) * ratio;
    for (int y = 0; y < h; y++)
        for (int j = 0; j < size; j++) {
            double a0 = x_first + j * ratio;
            cols[(size_t)y * size + j] = row_integral(img + (size_t)y * w, w, a0, a0 + ratio);
        }
    for (int i = 0; i < size; i++)
        for (int j = 0; j < size; j++) {
            double a0 = y_first + i * ratio;
            int r0 = (int)floor(a0), r1 = (int)ceil(a0 + ratio) - 1;
            r0 = r0 < 0 ? 0 : r0;
            r1 = r1 > h - 1 ? h - 1 : r1;
            double s = 0;
            for (int r = r0; r <= r1; r++)
                s += overlap(a0, a0 + ratio, r) * cols[(size_t)r * size + j];
            out[(size_t)i * size + j] = (float)s;
        }
    free(cols);
    return ORR_OK;
}

/* ---- reading ------------------------------------------------------------ */

static orr_status fits_error(const char *path, int status, orr_error *err)
{
    char text[FLEN_STATUS] = "";
    fits_get_errstatus(status, text);
    fits_clear_errmsg();
    return orr_fail(err, status == FILE_NOT_OPENED ? ORR_ERR_IO : ORR_ERR_FORMAT, "%s: cannot read PSF: %s",
                    path, text);
}

/* Opens path as it is named (fits_open_image would parse cfitsio's extended
 * file-name syntax, so a name with '[' would not open) and moves, as
 * fits_open_image does, to the first HDU holding an image: the primary
 * when it has axes, else the first image extension that has. */
static int open_first_image(const char *path, fitsfile **f, int *status)
{
    int nhdu = 0, naxis = 0, type = 0;
    if (fits_open_diskfile(f, path, READONLY, status) || fits_get_img_dim(*f, &naxis, status) || naxis > 0 ||
        fits_get_num_hdus(*f, &nhdu, status))
        return *status;
    for (int hdu = 2; hdu <= nhdu; hdu++) {
        if (fits_movabs_hdu(*f, hdu, &type, status))
            return *status;
        if (type == IMAGE_HDU && !fits_get_img_dim(*f, &naxis, status) && naxis > 0)
            return 0;
    }
    /* No image anywhere: back to the primary, whose size is then refused. */
    return fits_movabs_hdu(*f, 1, NULL, status);
}

/* Reads the pixels (row 0 at the top) and the PIXSCALE keyword (NaN if absent). */
static orr_status read_image(const char *path, float **pixels, int *w, int *h, double *pixscale,
                             orr_error *err)
{
    fitsfile *f = NULL;
    int status = 0, naxis = 0;
    long naxes[3] = {0, 0, 0};
    *pixels = NULL;
    orr_status refused = orr_fits_refuse_compressed(path, "a PSF", err);
    if (refused)
        return refused;
    if (open_first_image(path, &f, &status)) {
        int close_status = 0; /* cfitsio leaves the file open when it fails looking for the image */
        if (f)
            fits_close_file(f, &close_status);
        return fits_error(path, status, err);
    }
    fits_get_img_dim(f, &naxis, &status);
    fits_get_img_size(f, 3, naxes, &status);
    LONGLONG head = 0, start = 0, end = 0; /* the data must be in the file before it is allocated */
    if (!status && !fits_get_hduaddrll(f, &head, &start, &end, &status) && end > f->Fptr->logfilesize)
        status = END_OF_FILE;
    if (!status && fits_is_compressed_image(f, &status)) { /* cfitsio 4.2 crashes on damaged tiles */
        fits_close_file(f, &status);
        return orr_fail(err, ORR_ERR_FORMAT, "%s: a PSF must be an uncompressed image (funpack it first)", path);
    }
    if (!status && (naxis != 2 || naxes[0] < 1 || naxes[1] < 1 || naxes[0] > FITS_MAX_SIDE ||
                    naxes[1] > FITS_MAX_SIDE)) {
        fits_close_file(f, &status);
        return orr_fail(err, ORR_ERR_FORMAT, "%s: a PSF must be a 2-D image of at most %d pixels a side", path,
                        FITS_MAX_SIDE);
    }
    *pixscale = NAN;
    if (!status && fits_read_key(f, TDOUBLE, "PIXSCALE", pixscale, NULL, &status) == KEY_NO_EXIST) {
        status = 0;
        *pixscale = NAN;
        fits_clear_errmsg();
    }
    float *buf = NULL;
    if (!status) {
        buf = orr_malloc((size_t)naxes[0] * (size_t)naxes[1] * sizeof *buf, "PSF image", err);
        if (!buf) {
            fits_close_file(f, &status);
            return ORR_ERR_NOMEM;
        }
        float nulval = 0;
        int anynul = 0;
        fits_read_img(f, TFLOAT, 1, (LONGLONG)naxes[0] * naxes[1], &nulval, buf, &anynul, &status);
    }
    int close_status = 0;
    fits_close_file(f, &close_status);
    if (status) {
        free(buf);
        return fits_error(path, status, err);
    }
    *w = (int)naxes[0];
    *h = (int)naxes[1];
    /* FITS row 1 is the bottom of the picture. */
    for (int y = 0; y < *h / 2; y++) {
        float *a = buf + (size_t)y * *w, *b = buf + (size_t)(*h - 1 - y) * *w;
        for (int x = 0; x < *w; x++) {
            float t = a[x];
            a[x] = b[x];
            b[x] = t;
        }
    }
    *pixels = buf;
    return ORR_OK;
}

/* ---- cleaning and centring -------------------------------------------------- */

static int compare_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* Median of the outermost ring of pixels: the sky level of a stamp. */
static double border_median(const float *img, int w, int h)
{
    size_t n = 0, cap = 2 * (size_t)w + 2 * (size_t)h;
    float *ring = malloc(cap * sizeof *ring);
    if (!ring)
        return 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            if (y == 0 || y == h - 1 || x == 0 || x == w - 1)
                ring[n++] = img[(size_t)y * w + x];
    qsort(ring, n, sizeof *ring, compare_float);
    double m = n % 2 ? ring[n / 2] : 0.5 * ((double)ring[n / 2 - 1] + ring[n / 2]);
    free(ring);
    return m;
}

/* Subtracts bg, zeroes non-finite and negative values; returns the sum of
 * the negative values removed (as a positive number). */
static double clean_image(float *img, size_t n, double bg)
{
    double clipped = 0;
    for (size_t i = 0; i < n; i++) {
        double v = isfinite(img[i]) ? img[i] - bg : 0;
        if (v < 0) {
            clipped -= v;
            v = 0;
        }
        img[i] = (float)v;
    }
    return clipped;
}

static size_t brightest(const float *img, size_t n)
{
    size_t best = 0;
    for (size_t i = 1; i < n; i++)
        if (img[i] > img[best])
            best = i;
    return best;
}

/* Vertex of the parabola through (-1, a), (0, b), (1, c), within +-1/2. */
static double parabola_offset(double a, double b, double c)
{
    double den = a - 2 * b + c;
    if (!(den < 0))
        return 0;
    double d = 0.5 * (a - c) / den;
    return d > 0.5 ? 0.5 : (d < -0.5 ? -0.5 : d);
}

static void peak_centre(const float *img, int w, int h, int px, int py, double *xc, double *yc)
{
    const float *row = img + (size_t)py * w;
    double dx = px > 0 && px < w - 1 ? parabola_offset(row[px - 1], row[px], row[px + 1]) : 0;
    double dy = py > 0 && py < h - 1
                    ? parabola_offset(img[(size_t)(py - 1) * w + px], row[px], img[(size_t)(py + 1) * w + px])
                    : 0;
    *xc = px + 0.5 + dx;
    *yc = py + 0.5 + dy;
}

static void centroid_centre(const float *img, int w, int h, int px, int py, int half, double *xc, double *yc)
{
    double s = 0, sx = 0, sy = 0;
    for (int y = py - half; y <= py + half; y++)
        for (int x = px - half; x <= px + half; x++) {
            if (x < 0 || y < 0 || x >= w || y >= h)
                continue;
            double v = img[(size_t)y * w + x];
            s += v;
            sx += v * (x + 0.5);
            sy += v * (y + 0.5);
        }
    *xc = s > 0 ? sx / s : px + 0.5;
    *yc = s > 0 ? sy / s : py + 0.5;
}

/* ---- the loader ---------------------------------------------------------- */

/* The output scale (psf.arcsec_per_pixel) must make an output pixel no
 * larger than the PSF image, beyond which the whole PSF falls into one
 * pixel (and the rebinning's pixel edges outgrow an int); with the size
 * automatic, it must also keep that size at most PSF_MAX_SIZE pixels. */
static orr_status check_ratio(const char *path, const orr_psf_fits_options *o, int w, int h,
                              const orr_psf_fits_info *info, orr_error *err)
{
    int side = w < h ? w : h;
    double lo = info->file_arcsec_per_pixel * side / PSF_MAX_SIZE;
    double hi = info->file_arcsec_per_pixel * side;
    int above_lo = o->size ? info->ratio > 0 : info->ratio >= (double)side / PSF_MAX_SIZE;
    if (above_lo && info->ratio <= side)
        return ORR_OK;
    if (o->size)
        return orr_fail(err, ORR_ERR_USAGE,
                        "%s: psf.arcsec_per_pixel = %g is out of range for this PSF: it must be above 0 and at most "
                        "%g arcsec (an output pixel no larger than the %d x %d image of %g arcsec pixels)",
                        path, o->arcsec_per_pixel, hi, w, h, info->file_arcsec_per_pixel);
    return orr_fail(err, ORR_ERR_USAGE,
                    "%s: psf.arcsec_per_pixel = %g is out of range for this PSF: it must be at least %g and at most "
                    "%g arcsec (an output pixel no larger than the %d x %d image of %g arcsec pixels, and an "
                    "automatic size of at most %d pixels)",
                    path, o->arcsec_per_pixel, lo, hi, w, h, info->file_arcsec_per_pixel, PSF_MAX_SIZE);
}

static orr_status resolve_scale(const char *path, const orr_psf_fits_options *o, double pixscale, int w, int h,
                                orr_psf_fits_info *info, orr_error *err)
{
    int sub = o->subsample > 1 ? o->subsample : 1;
    double file_scale = o->file_arcsec_per_pixel > 0 ? o->file_arcsec_per_pixel : pixscale;
    int usable = file_scale > 0 && !isinf(file_scale);
    info->file_arcsec_per_pixel = usable ? file_scale : 0; /* 0: unknown */
    if (!(o->arcsec_per_pixel > 0)) {
        info->ratio = sub;
        return ORR_OK;
    }
    if (isnan(file_scale))
        return orr_fail(err, ORR_ERR_USAGE,
                        "%s: no PIXSCALE keyword, so it cannot be resampled to %g arcsec per pixel: set psf.arcsec_per_pixel: 0 to use the file's own pixels", path,
                        o->arcsec_per_pixel);
    if (!usable)
        return orr_fail(err, ORR_ERR_FORMAT,
                        "%s: PIXSCALE = %g is not a pixel scale (arcsec per pixel, above 0), so it cannot be resampled "
                        "to %g arcsec per pixel: mend the file's PIXSCALE or set psf.arcsec_per_pixel: 0 to use the "
                        "file's own pixels", path, file_scale, o->arcsec_per_pixel);
    info->ratio = o->arcsec_per_pixel / info->file_arcsec_per_pixel;
    return check_ratio(path, o, w, h, info, err);
}

static orr_status check_options(const char *path, const orr_psf_fits_options *o, orr_error *err)
{
    if (o->subsample < 0 || o->subsample > 64)
        return orr_fail(err, ORR_ERR_USAGE, "%s: subsampling %d (1 to 64)", path, o->subsample);
    if (!(o->taper >= 0 && o->taper <= 1))
        return orr_fail(err, ORR_ERR_USAGE, "%s: taper %g must be a fraction, 0 to 1", path, o->taper);
    if (o->size < 0 || (o->size > 0 && o->size % 2 == 0) || o->size > PSF_MAX_SIZE)
        return orr_fail(err, ORR_ERR_USAGE, "%s: PSF size %d must be odd (0 = automatic)", path, o->size);
    if (!(o->arcsec_per_pixel >= 0) || !(o->file_arcsec_per_pixel >= 0))
        return orr_fail(err, ORR_ERR_USAGE, "%s: pixel scales must be positive", path);
    return ORR_OK;
}

/* Finds the star, resamples around it and normalises into out. */
static orr_status build_kernel(const float *img, int w, int h, const orr_psf_fits_options *o,
                               orr_psf_fits_info *info, orr_image_kernel *out, orr_error *err)
{
    size_t best = brightest(img, (size_t)w * h);
    int px = (int)(best % (size_t)w), py = (int)(best / (size_t)w);
    if (o->centre == ORR_PSF_CENTRE_CENTROID) {
        int half = o->subsample > 1 ? 2 * o->subsample : 2;
        centroid_centre(img, w, h, px, py, half, &info->centre_x, &info->centre_y);
    } else {
        peak_centre(img, w, h, px, py, &info->centre_x, &info->centre_y);
    }
    int size = o->size;
    if (!size) {
        size = (int)floor((w < h ? w : h) / info->ratio);
        size -= size % 2 == 0;
    }
    if (size < 1)
        return orr_fail(err, ORR_ERR_USAGE, "PSF image %d x %d is smaller than one output pixel", w, h);
    orr_status st = orr_image_kernel_alloc(out, size, size, err);
    if (!st)
        st = orr_image_rebin(img, w, h, info->centre_x, info->centre_y, info->ratio, size, out->data, err);
    if (!st) {
        double total = 0;
        for (size_t i = 0; i < (size_t)w * h; i++)
            total += img[i];
        info->captured = total > 0 ? orr_image_kernel_sum(out) / total : 0;
        st = orr_image_kernel_taper(out, o->taper, err);
    }
    if (!st)
        st = orr_image_kernel_normalise(out, err);
    if (st)
        orr_image_kernel_free(out);
    else
        out->arcsec_per_pixel = info->file_arcsec_per_pixel * info->ratio; /* 0 when unknown */
    return st;
}

orr_status orr_psf_load_fits(const char *path, const orr_psf_fits_options *opt, orr_image_kernel *out,
                             orr_psf_fits_info *info, orr_error *err)
{
    orr_psf_fits_options defaults = {0};
    const orr_psf_fits_options *o = opt ? opt : &defaults;
    orr_psf_fits_info local;
    info = info ? info : &local;
    memset(info, 0, sizeof *info);
    memset(out, 0, sizeof *out);
    if (!path || !path[0])
        return orr_fail(err, ORR_ERR_USAGE, "PSF: no FITS file named");
    orr_status st = check_options(path, o, err);
    if (st)
        return st;
    float *img = NULL;
    int w = 0, h = 0;
    double pixscale = NAN;
    if ((st = read_image(path, &img, &w, &h, &pixscale, err)))
        return st;
    info->file_width = w;
    info->file_height = h;
    if (!(st = resolve_scale(path, o, pixscale, w, h, info, err))) {
        info->background = o->subtract_background ? border_median(img, w, h) : 0;
        info->clipped = clean_image(img, (size_t)w * h, info->background);
        st = build_kernel(img, w, h, o, info, out, err);
        if (st)
            orr_fail_prefix(err, "%s: ", path);
    }
    free(img);
    return st;
}
