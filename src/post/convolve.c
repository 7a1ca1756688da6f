#include "post/convolve.h"

#include <fftw3.h>
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/vecmath.h"

#define KERNEL_MAX_SIZE 8191
#define PLANE_MAX_SIZE 65536
/* Padded sides are multiples of 4: r2c wants an even last dimension, and
 * sides with few factors of two (4116 x 2187 = 2^2 3 7^3 x 3^7 for a 4K
 * frame) planned by estimate ran up to 4 times slower on two threads than
 * the slightly larger 4116 x 2240 (bench_convolve, docs/psf.md). */
#define PADDED_MULTIPLE 4
/* Below this many values a loop is not worth waking a thread team for. */
#define PARALLEL_MIN 65536

/* ---- kernels ------------------------------------------------------------- */

static int odd_size_ok(int n)
{
    return n >= 1 && n <= KERNEL_MAX_SIZE && n % 2 == 1;
}

orr_status orr_image_kernel_alloc(orr_image_kernel *k, int width, int height, orr_error *err)
{
    memset(k, 0, sizeof *k);
    if (!odd_size_ok(width) || !odd_size_ok(height))
        return orr_fail(err, ORR_ERR_USAGE, "kernel size %d x %d: both sides must be odd, 1 to %d pixels",
                        width, height, KERNEL_MAX_SIZE);
    k->data = orr_calloc((size_t)width * (size_t)height, sizeof(float), "convolution kernel", err);
    if (!k->data)
        return ORR_ERR_NOMEM;
    k->width = width;
    k->height = height;
    return ORR_OK;
}

void orr_image_kernel_free(orr_image_kernel *k)
{
    free(k->data);
    k->data = NULL;
    k->width = k->height = 0;
}

double orr_image_kernel_sum(const orr_image_kernel *k)
{
    double s = 0;
    size_t n = (size_t)k->width * (size_t)k->height;
    for (size_t i = 0; i < n; i++)
        s += k->data[i];
    return s;
}

orr_status orr_image_kernel_normalise(orr_image_kernel *k, orr_error *err)
{
    size_t n = (size_t)k->width * (size_t)k->height;
    for (size_t i = 0; i < n; i++)
        if (!isfinite(k->data[i]))
            return orr_fail(err, ORR_ERR_DATA, "the kernel's element at row %zu, column %zu is %g, not a finite "
                            "number (values beyond single precision?)", i / (size_t)k->width, i % (size_t)k->width,
                            (double)k->data[i]);
    double s = orr_image_kernel_sum(k);
    if (!(s > 0) || !isfinite(s))
        return orr_fail(err, ORR_ERR_DATA, "kernel cannot be normalised: its sum is %g", s);
    for (size_t i = 0; i < n; i++)
        k->data[i] = (float)(k->data[i] / s);
    return ORR_OK;
}

orr_status orr_image_kernel_taper(orr_image_kernel *k, double fraction, orr_error *err)
{
    if (!(fraction >= 0 && fraction <= 1))
        return orr_fail(err, ORR_ERR_USAGE, "kernel taper %g must be a fraction of the radius, 0 to 1", fraction);
    int cx = k->width / 2, cy = k->height / 2;
    double radius = cx < cy ? cx : cy, inner = 1.0 - fraction;
    if (fraction == 0 || radius == 0)
        return ORR_OK;
    for (int y = 0; y < k->height; y++)
        for (int x = 0; x < k->width; x++) {
            double r = hypot(x - cx, y - cy) / radius, w = 1;
            if (r >= 1)
                w = 0;
            else if (r > inner)
                w = 0.5 * (1 + cos(ORR_PI * (r - inner) / fraction));
            k->data[(size_t)y * (size_t)k->width + (size_t)x] *= (float)w;
        }
    return ORR_OK;
}

/* Integral of a unit Gaussian of standard deviation sigma over the pixel
 * [i - 1/2, i + 1/2]. erfc of the far edge minus erfc of the near edge keeps
 * full relative precision in the wings, where erf differences would cancel. */
static double gaussian_pixel(int i, double sigma)
{
    double s = sigma * sqrt(2.0);
    int a = abs(i);
    if (a == 0)
        return erf(0.5 / s);
    return 0.5 * (erfc((a - 0.5) / s) - erfc((a + 0.5) / s));
}

orr_status orr_image_kernel_gaussian(orr_image_kernel *k, double fwhm_pixels, orr_error *err)
{
    memset(k, 0, sizeof *k);
    if (!(fwhm_pixels > 0) || !isfinite(fwhm_pixels))
        return orr_fail(err, ORR_ERR_USAGE, "Gaussian FWHM %g pixels: must be positive", fwhm_pixels);
    double sigma = fwhm_pixels / (2.0 * sqrt(2.0 * log(2.0)));
    double radius = ceil(ORR_GAUSSIAN_TRUNCATE_SIGMA * sigma);
    if (2 * radius + 1 > KERNEL_MAX_SIZE)
        return orr_fail(err, ORR_ERR_USAGE, "Gaussian FWHM %g pixels is too wide for a %d-pixel kernel",
                        fwhm_pixels, KERNEL_MAX_SIZE);
    int r = (int)radius, n = 2 * r + 1;
    orr_status st = orr_image_kernel_alloc(k, n, n, err);
    if (st)
        return st;
    /* Separable: the 2-D pixel integral is the product of two 1-D ones. */
    double *g = orr_malloc((size_t)n * sizeof *g, "Gaussian profile", err);
    if (!g) {
        orr_image_kernel_free(k);
        return ORR_ERR_NOMEM;
    }
    for (int i = 0; i < n; i++)
        g[i] = gaussian_pixel(i - r, sigma);
    for (int y = 0; y < n; y++)
        for (int x = 0; x < n; x++)
            k->data[(size_t)y * n + x] = (float)(g[y] * g[x]);
    free(g);
    return orr_image_kernel_normalise(k, err);
}

static float kernel_at(const orr_image_kernel *k, int x, int y)
{
    if (x < 0 || y < 0 || x >= k->width || y >= k->height)
        return 0.0f;
    return k->data[(size_t)y * (size_t)k->width + (size_t)x];
}

float orr_image_kernel_sample(const orr_image_kernel *k, double dx, double dy)
{
    double px = k->width / 2 + dx, py = k->height / 2 + dy;
    if (!(px > -1.0 && py > -1.0 && px < k->width && py < k->height))
        return 0.0f; /* also rejects NaN */
    int x0 = (int)floor(px), y0 = (int)floor(py);
    double fx = px - x0, fy = py - y0;
    double top = (1 - fx) * kernel_at(k, x0, y0) + fx * kernel_at(k, x0 + 1, y0);
    double bottom = (1 - fx) * kernel_at(k, x0, y0 + 1) + fx * kernel_at(k, x0 + 1, y0 + 1);
    return (float)((1 - fy) * top + fy * bottom);
}

/* ---- FFT sizes and the planner lock ---------------------------------------- */

static int is_smooth(int n)
{
    static const int primes[] = {2, 3, 5, 7};
    for (int i = 0; i < 4; i++)
        while (n % primes[i] == 0)
            n /= primes[i];
    return n == 1;
}

int orr_fft_good_size(int min_size, int multiple)
{
    if (min_size < 1)
        min_size = 1;
    if (multiple < 1)
        multiple = 1;
    for (long n = min_size; n <= (1L << 30); n++)
        if (n % multiple == 0 && is_smooth((int)n))
            return (int)n;
    return -1;
}

/* ---- the plans ----------------------------------------------------------------
 * Each convolver owns its pair of plans: the renderer's plan (render/plan.h)
 * makes its convolvers once per run, so the plans live as long as the run
 * does and no process-wide list is needed. A plan is made for the
 * convolver's work buffer (MEASURE overwrites it, so this happens before the
 * kernel is placed there) and run with FFTW's new-array execute functions.
 * Planning and destroying plans take the planner lock (core/fft_planner.h):
 * FFTW's planner is not thread-safe. */

typedef struct fft_plans {
    fftwf_plan forward, inverse;
} fft_plans;

static long plans_created;

long orr_convolve_plans_created(void)
{
    if (orr_fft_planner_lock(NULL) != ORR_OK)
        return 0; /* no threads, so no plan was ever made */
    long n = plans_created;
    orr_fft_planner_unlock();
    return n;
}

static void destroy_plans_locked(fft_plans *p)
{
    if (p->forward)
        fftwf_destroy_plan(p->forward);
    if (p->inverse)
        fftwf_destroy_plan(p->inverse);
    p->forward = p->inverse = NULL;
}

/* Plans an in-place r2c / c2r pair of nx x ny on buf, which MEASURE
 * overwrites. */
static orr_status make_plans(fft_plans *p, int nx, int ny, int threads, orr_fft_rigor rigor, fftwf_complex *buf,
                             orr_error *err)
{
    orr_status st = orr_fft_planner_lock(err);
    if (st)
        return st;
    unsigned flags = rigor == ORR_FFT_MEASURE ? FFTW_MEASURE : FFTW_ESTIMATE;
    fftwf_plan_with_nthreads(threads);
    p->forward = fftwf_plan_dft_r2c_2d(ny, nx, (float *)buf, buf, flags);
    p->inverse = fftwf_plan_dft_c2r_2d(ny, nx, buf, (float *)buf, flags);
    if (p->forward && p->inverse)
        plans_created++;
    else
        destroy_plans_locked(p);
    orr_fft_planner_unlock();
    return p->forward ? ORR_OK : orr_fail(err, ORR_ERR_INTERNAL, "FFTW could not plan a %d x %d transform", nx, ny);
}

static void release_plans(fft_plans *p)
{
    if ((!p->forward && !p->inverse) || orr_fft_planner_lock(NULL))
        return;
    destroy_plans_locked(p);
    orr_fft_planner_unlock();
}

/* ---- the convolver ----------------------------------------------------------- */

struct orr_convolver {
    int width, height;           /* planes */
    int kernel_width, kernel_height;
    int nx, ny;                  /* padded transform size */
    int threads;
    size_t ncomplex;             /* ny * (nx/2 + 1) */
    fftwf_complex *work;         /* in place: the real image in rows of 2 (nx/2 + 1) floats */
    fftwf_complex *spectrum;     /* the kernel's transform, divided by nx ny */
    fft_plans plans;
    long applications;
};

static size_t real_stride(const orr_convolver *c)
{
    return 2 * ((size_t)c->nx / 2 + 1);
}

static orr_status check_geometry(int width, int height, const orr_image_kernel *k, orr_error *err)
{
    if (width < 1 || height < 1 || width > PLANE_MAX_SIZE || height > PLANE_MAX_SIZE)
        return orr_fail(err, ORR_ERR_USAGE, "convolution: image size %d x %d is out of range", width,
                        height);
    if (!k || !k->data || !odd_size_ok(k->width) || !odd_size_ok(k->height))
        return orr_fail(err, ORR_ERR_USAGE, "convolution: the kernel must have odd sides of 1 to %d pixels",
                        KERNEL_MAX_SIZE);
    return ORR_OK;
}

/* Padding: with the kernel reaching r pixels either side, output pixel
 * i < W only gathers input pixels j with |i - j| <= r. In a periodic
 * transform of length n, the wrapped copies sit at i - j +- n; with
 * n >= W + r those are all further than r away, so the wrap-around lands
 * only in the margin we discard. n >= 2r + 1 also holds the whole kernel. */
static int padded_size(int size, int kernel_size)
{
    int r = kernel_size / 2;
    int need = size + r > kernel_size ? size + r : kernel_size;
    return orr_fft_good_size(need, PADDED_MULTIPLE);
}

/* Places the kernel with its centre at index (0, 0), negative offsets
 * wrapped to the far end, and transforms it into c->spectrum. */
static void transform_kernel(orr_convolver *c, const orr_image_kernel *k)
{
    float *real = (float *)c->work;
    size_t stride = real_stride(c);
    memset(c->work, 0, c->ncomplex * sizeof *c->work);
    int rx = k->width / 2, ry = k->height / 2;
    for (int y = 0; y < k->height; y++) {
        int wy = (y - ry + c->ny) % c->ny;
        for (int x = 0; x < k->width; x++) {
            int wx = (x - rx + c->nx) % c->nx;
            real[(size_t)wy * stride + (size_t)wx] = k->data[(size_t)y * (size_t)k->width + (size_t)x];
        }
    }
    fftwf_execute_dft_r2c(c->plans.forward, real, c->work);
    /* FFTW's transforms are unnormalised: fold the 1 / (nx ny) in here. */
    float scale = (float)(1.0 / ((double)c->nx * (double)c->ny));
    for (size_t i = 0; i < c->ncomplex; i++) {
        c->spectrum[i][0] = c->work[i][0] * scale;
        c->spectrum[i][1] = c->work[i][1] * scale;
    }
}

static int resolve_threads(const orr_convolve_options *opt)
{
    int t = opt && opt->threads > 0 ? opt->threads : omp_get_max_threads();
    return t < 1 ? 1 : t;
}

orr_status orr_convolver_create(orr_convolver **out, int width, int height, const orr_image_kernel *k,
                                const orr_convolve_options *opt, orr_error *err)
{
    *out = NULL;
    orr_status st = check_geometry(width, height, k, err);
    if (st)
        return st;
    orr_convolver *c = orr_calloc(1, sizeof *c, "convolver", err);
    if (!c)
        return ORR_ERR_NOMEM;
    c->width = width;
    c->height = height;
    c->kernel_width = k->width;
    c->kernel_height = k->height;
    c->nx = padded_size(width, k->width);
    c->ny = padded_size(height, k->height);
    c->threads = resolve_threads(opt);
    c->ncomplex = (size_t)c->ny * ((size_t)c->nx / 2 + 1);
    c->work = fftwf_alloc_complex(c->ncomplex);
    c->spectrum = fftwf_alloc_complex(c->ncomplex);
    if (!c->work || !c->spectrum) {
        orr_fail(err, ORR_ERR_NOMEM, "out of memory for a %d x %d FFT convolution", c->nx, c->ny);
        orr_convolver_free(c);
        return ORR_ERR_NOMEM;
    }
    st = make_plans(&c->plans, c->nx, c->ny, c->threads, opt ? opt->rigor : ORR_FFT_ESTIMATE, c->work, err);
    if (st) {
        orr_convolver_free(c);
        return st;
    }
    transform_kernel(c, k);
    *out = c;
    return ORR_OK;
}

orr_status orr_convolver_create_gaussian(orr_convolver **out, int width, int height, double fwhm_pixels,
                                         const orr_convolve_options *opt, orr_error *err)
{
    *out = NULL;
    orr_image_kernel k;
    orr_status st = orr_image_kernel_gaussian(&k, fwhm_pixels, err);
    if (st)
        return st;
    st = orr_convolver_create(out, width, height, &k, opt, err);
    orr_image_kernel_free(&k);
    return st;
}

/* Copies the plane into the padded buffer and zeroes the margin; returns the
 * index of a non-finite value, or -1. */
static long load_plane(orr_convolver *c, const orr_plane *plane)
{
    float *real = (float *)c->work;
    size_t stride = real_stride(c);
    long bad = -1;
    int w = c->width;
#pragma omp parallel for num_threads(c->threads) schedule(static) if ((size_t)c->ny * stride > PARALLEL_MIN)
    for (int y = 0; y < c->ny; y++) {
        float *row = real + (size_t)y * stride;
        if (y >= c->height) {
            memset(row, 0, stride * sizeof *row);
            continue;
        }
        const float *src = plane->data + (size_t)y * (size_t)w;
        for (int x = 0; x < w; x++) {
            row[x] = src[x];
            if (!isfinite(src[x])) {
#pragma omp critical(orr_convolve_bad)
                if (bad < 0 || (long)y * w + x < bad)
                    bad = (long)y * w + x;
            }
        }
        memset(row + w, 0, (stride - (size_t)w) * sizeof *row);
    }
    return bad;
}

static void multiply_spectrum(orr_convolver *c)
{
    fftwf_complex *a = c->work;
    const fftwf_complex *b = c->spectrum;
    long n = (long)c->ncomplex;
#pragma omp parallel for num_threads(c->threads) schedule(static) if (n > PARALLEL_MIN)
    for (long i = 0; i < n; i++) {
        float re = a[i][0] * b[i][0] - a[i][1] * b[i][1];
        float im = a[i][0] * b[i][1] + a[i][1] * b[i][0];
        a[i][0] = re;
        a[i][1] = im;
    }
}

static void store_plane(const orr_convolver *c, orr_plane *plane)
{
    const float *real = (const float *)c->work;
    size_t stride = real_stride(c);
    size_t row_bytes = (size_t)c->width * sizeof(float);
#pragma omp parallel for num_threads(c->threads) schedule(static) if ((size_t)c->height * stride > PARALLEL_MIN)
    for (int y = 0; y < c->height; y++)
        memcpy(plane->data + (size_t)y * (size_t)c->width, real + (size_t)y * stride, row_bytes);
}

orr_status orr_convolver_apply(orr_convolver *c, orr_plane *plane, orr_error *err)
{
    if (!plane || !plane->data)
        return orr_fail(err, ORR_ERR_USAGE, "convolution: no plane given");
    if (plane->width != c->width || plane->height != c->height)
        return orr_fail(err, ORR_ERR_USAGE, "convolution: plane %s is %d x %d but the convolver was made for %d x %d",
                        plane->name, plane->width, plane->height, c->width, c->height);
    long bad = load_plane(c, plane);
    if (bad >= 0)
        return orr_fail(err, ORR_ERR_DATA, "convolution: plane %s has a non-finite value at pixel (%ld, %ld)",
                        plane->name, bad % c->width, bad / c->width);
    float *real = (float *)c->work;
    fftwf_execute_dft_r2c(c->plans.forward, real, c->work);
    multiply_spectrum(c);
    fftwf_execute_dft_c2r(c->plans.inverse, c->work, real);
    store_plane(c, plane);
    c->applications++;
    return ORR_OK;
}

void orr_convolver_get_info(const orr_convolver *c, orr_convolver_info *info)
{
    info->width = c->width;
    info->height = c->height;
    info->kernel_width = c->kernel_width;
    info->kernel_height = c->kernel_height;
    info->fft_width = c->nx;
    info->fft_height = c->ny;
    info->threads = c->threads;
    info->applications = c->applications;
}

void orr_convolver_free(orr_convolver *c)
{
    if (!c)
        return;
    release_plans(&c->plans);
    fftwf_free(c->work);
    fftwf_free(c->spectrum);
    free(c);
}

orr_status orr_convolve_plane(orr_plane *plane, const orr_image_kernel *k, const orr_convolve_options *opt,
                              orr_error *err)
{
    if (!plane)
        return orr_fail(err, ORR_ERR_USAGE, "convolution: no plane given");
    orr_convolver *c;
    orr_status st = orr_convolver_create(&c, plane->width, plane->height, k, opt, err);
    if (st)
        return st;
    st = orr_convolver_apply(c, plane, err);
    orr_convolver_free(c);
    return st;
}
