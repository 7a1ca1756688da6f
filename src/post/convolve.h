/* Convolution of image planes with a kernel image by FFT (FFTW3, single
 * precision, real-to-complex), with zero padding so nothing wraps around.
 *
 * A convolver is made once for an image size and a kernel, then applied to
 * any number of planes of that size (every frame of an animation, every
 * colour channel that uses the same kernel). It owns its FFTW plans, made
 * when it is created and destroyed with it (the renderer makes its
 * convolvers once per run, in its plan: render/plan.h); planning happens
 * under a lock, because FFTW's planner is not thread-safe.
 *
 * Kernels are odd-sized images whose centre pixel is offset (0, 0); the
 * result of convolving a single bright pixel is the kernel itself, placed
 * on that pixel the same way up (a true convolution, not a correlation).
 * See docs/psf.md. */
#ifndef ORR_POST_CONVOLVE_H
#define ORR_POST_CONVOLVE_H

#include "core/error.h"
#include "core/fft_planner.h"
#include "core/plane.h"

/* ---- kernels ------------------------------------------------------------- */

/* width x height values (both odd), row-major, row 0 at the top; the centre
 * pixel (width/2, height/2) is offset zero. PSFs are normalised to sum 1.
 * (Named apart from splat/kernel.h's orr_kernel, the SPH smoothing kernel.) */
typedef struct orr_image_kernel {
    int width, height;
    float *data;
    /* Angular size of one kernel pixel, for PSFs (generated, or from a file
     * whose scale is known); 0 for kernels defined in image pixels only. */
    double arcsec_per_pixel;
} orr_image_kernel;

/* A zeroed kernel; sizes must be odd, 1 to 8191. */
orr_status orr_image_kernel_alloc(orr_image_kernel *k, int width, int height, orr_error *err);
void orr_image_kernel_free(orr_image_kernel *k);
/* Sum of all values, accumulated in double. */
double orr_image_kernel_sum(const orr_image_kernel *k);
/* Divides by the sum; fails (ORR_ERR_DATA) when the sum is not positive and
 * finite or a value is not finite. */
orr_status orr_image_kernel_normalise(orr_image_kernel *k, orr_error *err);

/* Rolls the kernel off to zero towards its edge, so a kernel cut from a
 * PSF with wide wings does not print a square outline around bright stars:
 * values are multiplied by 1 within (1 - fraction) R of the centre, by
 * (1 + cos(pi (r/R - 1 + fraction) / fraction)) / 2 out to R, and by 0
 * beyond (the corners), where R is half the smaller side (the distance from
 * the centre pixel to the middle of the nearest edge pixel). fraction 0
 * leaves the kernel as it is. Does not renormalise. */
orr_status orr_image_kernel_taper(orr_image_kernel *k, double fraction, orr_error *err);

/* Truncation radius of the Gaussian kernel, in standard deviations: the
 * pixel-integrated mass beyond it is below 1e-6, under single precision. */
#define ORR_GAUSSIAN_TRUNCATE_SIGMA 5.0

/* A circular Gaussian of the given FWHM (pixels), pixel-integrated: each
 * value is the Gaussian's integral over that pixel (a product of erf
 * differences), so even a sub-pixel FWHM conserves flux and stays centred.
 * Size 2 ceil(5 sigma) + 1, normalised to sum 1. */
orr_status orr_image_kernel_gaussian(orr_image_kernel *k, double fwhm_pixels, orr_error *err);

/* Bilinear interpolation of the kernel at an offset (dx, dy) from the centre
 * of its centre pixel, in kernel pixels: dx to the right, dy down the image
 * (rows), as in plane coordinates. Values outside the kernel count as 0, so
 * the result falls to 0 one pixel beyond the outer pixel centres. Meant for
 * depositing a kernel at sub-pixel positions (e.g. per particle). */
float orr_image_kernel_sample(const orr_image_kernel *k, double dx, double dy);

/* ---- the convolver ------------------------------------------------------- */

typedef enum {
    /* FFTW_ESTIMATE: the plan is chosen by rule, not by timing, so it is
     * the same on every run and planning costs nothing; the default. */
    ORR_FFT_ESTIMATE,
    /* FFTW_MEASURE: FFTW times candidate plans. Worth it only for very long
     * runs of one size; the chosen plan (and so the last bits of the
     * result) can change from run to run. */
    ORR_FFT_MEASURE,
} orr_fft_rigor;

typedef struct orr_convolve_options {
    int threads;         /* FFTW threads; 0 = omp_get_max_threads() */
    orr_fft_rigor rigor; /* default ORR_FFT_ESTIMATE */
} orr_convolve_options;

typedef struct orr_convolver orr_convolver;

/* What a convolver chose, for reports and benchmarks. */
typedef struct orr_convolver_info {
    int width, height;          /* the planes it convolves */
    int kernel_width, kernel_height;
    int fft_width, fft_height;  /* padded transform size, 4 x 2^a 3^b 5^c 7^d */
    int threads;
    long applications;          /* planes convolved so far */
} orr_convolver_info;

/* Makes a convolver for width x height planes and the kernel k (odd sizes;
 * it is copied, transformed and need not outlive the call). opt may be NULL
 * for the defaults. The kernel is used as given: normalise it first for a
 * flux-conserving convolution. */
orr_status orr_convolver_create(orr_convolver **out, int width, int height, const orr_image_kernel *k,
                                const orr_convolve_options *opt, orr_error *err);

/* The same with orr_image_kernel_gaussian(fwhm_pixels). */
orr_status orr_convolver_create_gaussian(orr_convolver **out, int width, int height, double fwhm_pixels,
                                         const orr_convolve_options *opt, orr_error *err);

/* Convolves the plane in place. Its size must be the convolver's; every
 * value must be finite (one NaN would spread over the whole transform).
 * Flux carried beyond the plane's edges by the kernel is lost, not wrapped.
 * Not reentrant for one convolver (it owns one work buffer); distinct
 * convolvers may run in parallel. */
orr_status orr_convolver_apply(orr_convolver *c, orr_plane *plane, orr_error *err);

void orr_convolver_get_info(const orr_convolver *c, orr_convolver_info *info);
void orr_convolver_free(orr_convolver *c);

/* One-off convolution: create, apply, free. */
orr_status orr_convolve_plane(orr_plane *plane, const orr_image_kernel *k, const orr_convolve_options *opt,
                              orr_error *err);

/* Number of FFTW plan pairs (forward + inverse) the convolvers have created
 * since the program started: one per convolver created, none per plane
 * convolved. */
long orr_convolve_plans_created(void);

/* The smallest n >= min_size of the form 2^a 3^b 5^c 7^d that is a
 * multiple of `multiple` (1, 2, 4, ...), or -1 beyond 2^30. */
int orr_fft_good_size(int min_size, int multiple);

#endif
