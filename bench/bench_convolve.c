/* FFT convolution timings for full frames: a 3600 x 3600 dome master and a
 * 4096 x 2160 flat frame, with a Gaussian of FWHM 3 pixels and with a
 * 129 x 129 generated HST PSF, on 1 and 2 threads.
 *
 *   bench_convolve [--measure] [repeats]      default: FFTW_ESTIMATE, 3
 *
 * For each case: the first call (convolver creation: padding, planning, the
 * kernel's transform; then one convolution) and the mean of the following
 * calls, which is what every further frame costs. Each case starts with no
 * plans cached. Also prints the time to generate the PSF. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "post/convolve.h"
#include "post/psf.h"
#include "clocks.h"
#include "test_random.h"

static void die(const orr_error *err)
{
    fprintf(stderr, "bench_convolve: %s\n", err->msg);
    exit(1);
}

/* A star field: a few thousand bright pixels on a faint background. */
static void fill(orr_plane *p)
{
    uint64_t s = 42;
    size_t n = (size_t)p->width * p->height;
    for (size_t i = 0; i < n; i++)
        p->data[i] = 0.01f;
    for (int k = 0; k < 5000; k++) {
        const size_t at = (size_t)test_below(&s, n);
        p->data[at] += (float)test_below(&s, 1000);
    }
}

static void run_case(int w, int h, const char *kname, const orr_image_kernel *k, int threads,
                     orr_fft_rigor rigor, int repeats)
{
    orr_error err;
    orr_plane p;
    if (orr_plane_alloc(&p, w, h, "bench", "", &err))
        die(&err);
    fill(&p);
    orr_convolve_options opt = {.threads = threads, .rigor = rigor};
    orr_convolver *c;
    double t0 = wall_seconds();
    if (orr_convolver_create(&c, w, h, k, &opt, &err))
        die(&err);
    double t1 = wall_seconds();
    if (orr_convolver_apply(c, &p, &err))
        die(&err);
    double t2 = wall_seconds();
    for (int r = 0; r < repeats; r++)
        if (orr_convolver_apply(c, &p, &err))
            die(&err);
    double t3 = wall_seconds();
    orr_convolver_info info;
    orr_convolver_get_info(c, &info);
    printf("%4d x %-4d  %-14s %d thr  fft %4d x %-4d  create %7.3f s  first %7.3f s  next %7.3f s\n", w, h,
           kname, threads, info.fft_width, info.fft_height, t1 - t0, t2 - t0, (t3 - t2) / repeats);
    fflush(stdout);
    orr_convolver_free(c);
    orr_plane_free(&p);
}

int main(int argc, char **argv)
{
    orr_fft_rigor rigor = ORR_FFT_ESTIMATE;
    int repeats = 3;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--measure") == 0)
            rigor = ORR_FFT_MEASURE;
        else
            repeats = atoi(argv[i]) > 0 ? atoi(argv[i]) : repeats;
    }
    orr_error err;
    orr_image_kernel gauss, psf[3];
    if (orr_image_kernel_gaussian(&gauss, 3.0, &err))
        die(&err);
    orr_psf_params pp;
    orr_psf_hst_defaults(&pp);
    orr_psf_report rep;
    double t0 = wall_seconds();
    if (orr_psf_generate(&pp, psf, &rep, &err))
        die(&err);
    printf("HST PSF, 3 bands x 5 wavelengths, %d x %d at %g arcsec/px: %.3f s (transform %d, oversample %d)\n",
           pp.size, pp.size, pp.arcsec_per_pixel, wall_seconds() - t0, rep.fft_size, rep.oversample);
    printf("FFTW_%s, %d repeats\n", rigor == ORR_FFT_MEASURE ? "MEASURE" : "ESTIMATE", repeats);
    const int sizes[2][2] = {{3600, 3600}, {4096, 2160}};
    char gname[32];
    snprintf(gname, sizeof gname, "gauss %dx%d", gauss.width, gauss.height);
    for (int s = 0; s < 2; s++)
        for (int t = 1; t <= 2; t++) {
            run_case(sizes[s][0], sizes[s][1], gname, &gauss, t, rigor, repeats);
            run_case(sizes[s][0], sizes[s][1], "PSF 129x129", &psf[1], t, rigor, repeats);
        }
    orr_image_kernel_free(&gauss);
    for (int b = 0; b < 3; b++)
        orr_image_kernel_free(&psf[b]);
    return 0;
}
