#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "post/convolve.h"
#include "test_random.h"

static orr_plane make_plane(int w, int h)
{
    orr_plane p;
    orr_error err;
    if (orr_plane_alloc(&p, w, h, "test", "", &err) != ORR_OK) {
        fprintf(stderr, "cannot allocate a %d x %d plane: %s\n", w, h, err.msg);
        exit(1);
    }
    return p;
}

/* The Gaussian's integral over pixel offset i (no truncation). */
static double gauss_pixel(int i, double fwhm)
{
    double s = fwhm / (2 * sqrt(2 * log(2.0))) * sqrt(2.0);
    return 0.5 * (erf((i + 0.5) / s) - erf((i - 0.5) / s));
}

static float at(const orr_plane *p, int x, int y)
{
    return p->data[(size_t)y * p->width + x];
}

static void test_good_size(void)
{
    CHECK(orr_fft_good_size(1, 1) == 1);
    CHECK(orr_fft_good_size(1, 2) == 2);
    CHECK(orr_fft_good_size(11, 1) == 12);
    CHECK(orr_fft_good_size(101, 1) == 105);
    CHECK(orr_fft_good_size(101, 2) == 108);
    CHECK(orr_fft_good_size(3607, 1) == 3645); /* 3^6 5 */
    CHECK(orr_fft_good_size(2167, 1) == 2187); /* 3^7 */
    CHECK(orr_fft_good_size(2167, 4) == 2240); /* 2^6 5 7 */
    for (int n = 1; n < 5000; n += 37) {
        int g = orr_fft_good_size(n, 4);
        CHECK(g >= n && g % 4 == 0);
        int r = g;
        for (int q = 2; q <= 7; q++)
            while (r % q == 0)
                r /= q;
        CHECK(r == 1);
    }
}

static void test_gaussian_kernel(void)
{
    orr_image_kernel k;
    orr_error err;
    CHECK(orr_image_kernel_gaussian(&k, 3.0, &err) == ORR_OK);
    double sigma = 3.0 / 2.354820045;
    int r = (int)ceil(5 * sigma);
    CHECK(k.width == 2 * r + 1 && k.height == k.width);
    CHECK_NEAR(orr_image_kernel_sum(&k), 1.0, 1e-6);
    for (int y = 0; y < k.height; y++)
        for (int x = 0; x < k.width; x++) {
            double expect = gauss_pixel(x - r, 3.0) * gauss_pixel(y - r, 3.0);
            CHECK_NEAR(k.data[y * k.width + x], expect, 1e-7);
            CHECK(k.data[y * k.width + x] == k.data[(k.height - 1 - y) * k.width + (k.width - 1 - x)]);
        }
    orr_image_kernel_free(&k);
    CHECK(orr_image_kernel_gaussian(&k, 0, &err) == ORR_ERR_USAGE);
    CHECK(orr_image_kernel_gaussian(&k, NAN, &err) == ORR_ERR_USAGE);
    CHECK(orr_image_kernel_gaussian(&k, 1e6, &err) == ORR_ERR_USAGE);
    CHECK(k.data == NULL);
}

/* A single bright pixel becomes the pixel-integrated Gaussian around it:
 * compared with the analytic value at every pixel, to 1e-4 of the peak (the
 * truncation at 5 sigma and single precision leave ~1e-6). */
static void check_delta(double fwhm, int w, int h, int x0, int y0)
{
    orr_plane p = make_plane(w, h);
    p.data[(size_t)y0 * w + x0] = 1000.0f;
    orr_convolver *c;
    orr_error err;
    CHECK(orr_convolver_create_gaussian(&c, w, h, fwhm, NULL, &err) == ORR_OK);
    CHECK(orr_convolver_apply(c, &p, &err) == ORR_OK);
    double peak = 1000.0 * gauss_pixel(0, fwhm) * gauss_pixel(0, fwhm), worst = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            double expect = 1000.0 * gauss_pixel(x - x0, fwhm) * gauss_pixel(y - y0, fwhm);
            worst = fmax(worst, fabs(at(&p, x, y) - expect));
        }
    fprintf(stderr, "  delta, FWHM %g: worst error %.3g of the peak\n", fwhm, worst / peak);
    CHECK(worst < 1e-4 * peak);
    orr_convolver_free(c);
    orr_plane_free(&p);
}

static void test_delta_is_gaussian(void)
{
    check_delta(3.0, 64, 48, 30, 21);
    check_delta(0.7, 33, 31, 16, 15); /* sub-pixel FWHM: still centred and normalised */
    check_delta(12.0, 120, 130, 61, 70);
}

/* Flux well inside the image is conserved to 1e-6. */
static void test_flux_conserved(void)
{
    int w = 300, h = 217, margin = 40;
    orr_plane p = make_plane(w, h);
    uint64_t s = 7;
    double before = 0;
    for (int y = margin; y < h - margin; y++)
        for (int x = margin; x < w - margin; x++) {
            float v = (float)(test_uniform(&s) < 0.05 ? 1000 * test_uniform(&s) : test_uniform(&s));
            p.data[(size_t)y * w + x] = v;
            before += v;
        }
    orr_error err;
    orr_convolver *c;
    CHECK(orr_convolver_create_gaussian(&c, w, h, 5.0, NULL, &err) == ORR_OK);
    CHECK(orr_convolver_apply(c, &p, &err) == ORR_OK);
    double after = orr_plane_sum(&p);
    fprintf(stderr, "  flux: relative change %.3g\n", fabs(after - before) / before);
    CHECK(fabs(after - before) <= 1e-6 * before);
    orr_convolver_free(c);
    orr_plane_free(&p);
}

/* Light pushed over one edge must not come back on the opposite edge. */
static void test_no_wrap_around(void)
{
    int w = 100, h = 80;
    orr_plane p = make_plane(w, h);
    p.data[40 * w + 0] = 1.0f;       /* left edge */
    p.data[0 * w + 50] = 1.0f;       /* top edge */
    p.data[79 * w + 99] = 1.0f;      /* bottom-right corner */
    orr_error err;
    orr_convolver *c;
    CHECK(orr_convolver_create_gaussian(&c, w, h, 10.0, NULL, &err) == ORR_OK); /* reaches 22 pixels */
    CHECK(orr_convolver_apply(c, &p, &err) == ORR_OK);
    double peak = gauss_pixel(0, 10.0) * gauss_pixel(0, 10.0), worst = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            double expect = 0;
            expect += gauss_pixel(x - 0, 10.0) * gauss_pixel(y - 40, 10.0);
            expect += gauss_pixel(x - 50, 10.0) * gauss_pixel(y - 0, 10.0);
            expect += gauss_pixel(x - 99, 10.0) * gauss_pixel(y - 79, 10.0);
            worst = fmax(worst, fabs(at(&p, x, y) - expect));
        }
    CHECK(worst < 1e-5 * peak);
    /* The far edges, where a wrap would land first: nothing. */
    CHECK(fabs(at(&p, 99, 40)) < 1e-6 * peak);
    CHECK(fabs(at(&p, 50, 79)) < 1e-6 * peak);
    CHECK(fabs(at(&p, 0, 0)) < 1e-6 * peak);
    /* Half of the edge star's light fell off the image and is gone. */
    orr_convolver_free(c);
    orr_plane_free(&p);

    /* A kernel wider than the image. */
    p = make_plane(9, 7);
    p.data[3 * 9 + 8] = 1.0f;
    CHECK(orr_convolver_create_gaussian(&c, 9, 7, 20.0, NULL, &err) == ORR_OK);
    CHECK(orr_convolver_apply(c, &p, &err) == ORR_OK);
    worst = 0;
    for (int y = 0; y < 7; y++)
        for (int x = 0; x < 9; x++)
            worst = fmax(worst, fabs(at(&p, x, y) - gauss_pixel(x - 8, 20.0) * gauss_pixel(y - 3, 20.0)));
    CHECK(worst < 1e-5 * gauss_pixel(0, 20.0) * gauss_pixel(0, 20.0));
    orr_convolver_free(c);
    orr_plane_free(&p);
}

/* Against a direct sum, with an asymmetric, non-square kernel: checks the
 * orientation (a convolution, not a correlation) and the generic path. */
static void test_matches_direct_convolution(void)
{
    int w = 37, h = 29;
    orr_image_kernel k;
    orr_error err;
    CHECK(orr_image_kernel_alloc(&k, 7, 5, &err) == ORR_OK);
    uint64_t s = 99;
    for (int i = 0; i < 35; i++)
        k.data[i] = (float)test_uniform(&s);
    k.data[0] = 5.0f; /* top-left: offset (-3, -2) */
    CHECK(orr_image_kernel_normalise(&k, &err) == ORR_OK);
    orr_plane p = make_plane(w, h), q = make_plane(w, h);
    for (int i = 0; i < w * h; i++)
        p.data[i] = q.data[i] = (float)test_uniform(&s);
    CHECK(orr_convolve_plane(&q, &k, NULL, &err) == ORR_OK);
    double worst = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            double sum = 0;
            for (int ky = 0; ky < 5; ky++)
                for (int kx = 0; kx < 7; kx++) {
                    int sx = x - (kx - 3), sy = y - (ky - 2);
                    if (sx >= 0 && sy >= 0 && sx < w && sy < h)
                        sum += k.data[ky * 7 + kx] * (double)at(&p, sx, sy);
                }
            worst = fmax(worst, fabs(at(&q, x, y) - sum));
        }
    CHECK(worst < 1e-5);
    /* A delta shows the kernel the same way up. */
    orr_plane d = make_plane(20, 20);
    d.data[10 * 20 + 10] = 1.0f;
    CHECK(orr_convolve_plane(&d, &k, NULL, &err) == ORR_OK);
    CHECK_NEAR(at(&d, 7, 8), k.data[0], 1e-6);
    CHECK_NEAR(at(&d, 13, 12), k.data[34], 1e-6);
    orr_plane_free(&d);
    orr_plane_free(&p);
    orr_plane_free(&q);
    orr_image_kernel_free(&k);
}

/* A convolver owns its plans: made once when it is created (the renderer
 * creates its convolvers once per run), never again per plane convolved;
 * convolvers of one geometry stay independent of each other. */
static void test_plan_ownership(void)
{
    orr_error err;
    orr_convolve_options one = {.threads = 1};
    long n0 = orr_convolve_plans_created();
    orr_convolver *a, *b, *c;
    CHECK(orr_convolver_create_gaussian(&a, 300, 200, 3.0, &one, &err) == ORR_OK);
    CHECK(orr_convolve_plans_created() == n0 + 1);
    orr_plane p = make_plane(300, 200);
    p.data[100 * 300 + 150] = 1;
    CHECK(orr_convolver_apply(a, &p, &err) == ORR_OK);
    CHECK(orr_convolver_apply(a, &p, &err) == ORR_OK);
    CHECK(orr_convolve_plans_created() == n0 + 1);
    /* another kernel of the same reach: same padded size, plans of its own */
    CHECK(orr_convolver_create_gaussian(&b, 300, 200, 2.9, &one, &err) == ORR_OK);
    CHECK(orr_convolve_plans_created() == n0 + 2);
    orr_convolver_info ia, ib;
    orr_convolver_get_info(a, &ia);
    orr_convolver_get_info(b, &ib);
    CHECK(ia.applications == 2 && ib.applications == 0);
    CHECK(ia.fft_width == ib.fft_width && ia.fft_height == ib.fft_height);
    CHECK(ia.fft_width >= 300 + 7 && ia.fft_height >= 200 + 7 && ia.threads == 1);
    orr_convolve_options two = {.threads = 2};
    CHECK(orr_convolver_create_gaussian(&c, 300, 200, 3.0, &two, &err) == ORR_OK);
    CHECK(orr_convolve_plans_created() == n0 + 3);
    orr_convolver_free(c);
    orr_convolver_free(a);
    /* freeing a destroyed only its own plans: b still convolves, and gives
     * what a fresh convolver of its kernel gives */
    orr_plane q = make_plane(300, 200);
    q.data[100 * 300 + 150] = 1;
    CHECK(orr_convolver_apply(b, &q, &err) == ORR_OK);
    orr_plane r = make_plane(300, 200);
    r.data[100 * 300 + 150] = 1;
    CHECK(orr_convolver_create_gaussian(&a, 300, 200, 2.9, &one, &err) == ORR_OK);
    CHECK(orr_convolver_apply(a, &r, &err) == ORR_OK);
    CHECK(memcmp(q.data, r.data, 300 * 200 * sizeof(float)) == 0);
    CHECK(orr_convolve_plans_created() == n0 + 4);
    orr_convolver_free(a);
    orr_convolver_free(b);
    orr_plane_free(&p);
    orr_plane_free(&q);
    orr_plane_free(&r);
}

/* Same input, same thread count: the same bits every time. One thread and
 * two may differ in the last bits (FFTW splits the work differently). */
static void test_reproducible(void)
{
    int w = 257, h = 300;
    orr_plane p1 = make_plane(w, h), p2 = make_plane(w, h), p3 = make_plane(w, h);
    uint64_t s = 3;
    for (int i = 0; i < w * h; i++)
        p1.data[i] = p2.data[i] = p3.data[i] = (float)(test_uniform(&s) * test_uniform(&s) * 100);
    orr_error err;
    orr_convolve_options one = {.threads = 1}, two = {.threads = 2};
    orr_convolver *a, *b;
    CHECK(orr_convolver_create_gaussian(&a, w, h, 4.0, &one, &err) == ORR_OK);
    CHECK(orr_convolver_create_gaussian(&b, w, h, 4.0, &two, &err) == ORR_OK);
    CHECK(orr_convolver_apply(a, &p1, &err) == ORR_OK);
    CHECK(orr_convolver_apply(b, &p2, &err) == ORR_OK);
    double worst = 0, top = 0;
    for (int i = 0; i < w * h; i++) {
        worst = fmax(worst, fabs(p1.data[i] - p2.data[i]));
        top = fmax(top, fabs(p1.data[i]));
    }
    fprintf(stderr, "  1 vs 2 threads: largest difference %.3g of the maximum\n", worst / top);
    CHECK(worst <= 1e-6 * top);
    orr_convolver_free(b);
    CHECK(orr_convolver_create_gaussian(&b, w, h, 4.0, &one, &err) == ORR_OK);
    CHECK(orr_convolver_apply(b, &p3, &err) == ORR_OK);
    CHECK(memcmp(p1.data, p3.data, (size_t)w * h * sizeof(float)) == 0);
    orr_convolver_free(a);
    orr_convolver_free(b);
    orr_plane_free(&p1);
    orr_plane_free(&p2);
    orr_plane_free(&p3);
}

static void test_measure_agrees(void)
{
    int w = 64, h = 50;
    orr_plane p = make_plane(w, h), q = make_plane(w, h);
    uint64_t s = 11;
    for (int i = 0; i < w * h; i++)
        p.data[i] = q.data[i] = (float)test_uniform(&s);
    orr_error err;
    orr_convolve_options measure = {.threads = 1, .rigor = ORR_FFT_MEASURE};
    orr_image_kernel k;
    CHECK(orr_image_kernel_gaussian(&k, 2.5, &err) == ORR_OK);
    CHECK(orr_convolve_plane(&p, &k, &measure, &err) == ORR_OK);
    CHECK(orr_convolve_plane(&q, &k, NULL, &err) == ORR_OK);
    for (int i = 0; i < w * h; i++)
        CHECK_NEAR(p.data[i], q.data[i], 1e-5);
    orr_image_kernel_free(&k);
    orr_plane_free(&p);
    orr_plane_free(&q);
}

/* Convolvers made, used and freed from several threads at once: the
 * planner lock and the shared plans must hold up. */
typedef struct job {
    int index, failures;
} job;

static void *convolve_job(void *arg)
{
    job *j = arg;
    for (int round = 0; round < 6; round++) {
        int w = 96 + 32 * ((j->index + round) % 3), h = 80;
        orr_plane p;
        orr_error err;
        orr_convolver *c;
        if (orr_plane_alloc(&p, w, h, "t", "", &err) ||
            orr_convolver_create_gaussian(&c, w, h, 3.0, &(orr_convolve_options){.threads = 1}, &err)) {
            j->failures++;
            continue;
        }
        p.data[40 * w + 50] = 1;
        if (orr_convolver_apply(c, &p, &err) ||
            fabs(p.data[40 * w + 50] - gauss_pixel(0, 3.0) * gauss_pixel(0, 3.0)) > 1e-6)
            j->failures++;
        orr_convolver_free(c);
        orr_plane_free(&p);
    }
    return NULL;
}

static void test_concurrent_planning(void)
{
    pthread_t t[4];
    job jobs[4];
    for (int i = 0; i < 4; i++) {
        jobs[i] = (job){.index = i};
        CHECK(pthread_create(&t[i], NULL, convolve_job, &jobs[i]) == 0);
    }
    for (int i = 0; i < 4; i++) {
        pthread_join(t[i], NULL);
        CHECK(jobs[i].failures == 0);
    }
}

static void test_wisdom(void)
{
    orr_error err;
    char path[] = "/tmp/orrery_wisdom_XXXXXX";
    int fd = mkstemp(path);
    CHECK(fd >= 0);
    close(fd);
    /* a MEASURE plan, saved, loaded back */
    orr_convolver *c;
    orr_convolve_options measure = {.threads = 1, .rigor = ORR_FFT_MEASURE};
    CHECK(orr_convolver_create_gaussian(&c, 40, 36, 2.0, &measure, &err) == ORR_OK);
    orr_convolver_free(c);
    CHECK(orr_fft_wisdom_save(path, &err) == ORR_OK);
    CHECK(orr_fft_wisdom_load(path, &err) == ORR_OK);
    FILE *f = fopen(path, "w");
    CHECK(f != NULL);
    if (f) {
        fputs("not wisdom at all\n", f);
        fclose(f);
    }
    CHECK(orr_fft_wisdom_load(path, &err) == ORR_ERR_FORMAT);
    remove(path);
    CHECK(orr_fft_wisdom_load(path, &err) == ORR_ERR_IO);
    CHECK_CONTAINS(err.msg, path);
}

static void test_kernel_sample(void)
{
    orr_image_kernel k;
    orr_error err;
    CHECK(orr_image_kernel_alloc(&k, 3, 3, &err) == ORR_OK);
    for (int i = 0; i < 9; i++)
        k.data[i] = (float)i; /* row 0: 0 1 2; row 1: 3 4 5; row 2: 6 7 8 */
    CHECK_NEAR(orr_image_kernel_sample(&k, 0, 0), 4, 1e-6);
    CHECK_NEAR(orr_image_kernel_sample(&k, 1, 0), 5, 1e-6);
    CHECK_NEAR(orr_image_kernel_sample(&k, 0, -1), 1, 1e-6);  /* up: row 0 */
    CHECK_NEAR(orr_image_kernel_sample(&k, 0.5, 0), 4.5, 1e-6);
    CHECK_NEAR(orr_image_kernel_sample(&k, 0.25, 0.5), 0.5 * (4.25 + 7.25), 1e-6);
    CHECK_NEAR(orr_image_kernel_sample(&k, 1.5, 0), 2.5, 1e-6); /* half way to the zero outside */
    CHECK_NEAR(orr_image_kernel_sample(&k, 2.0, 0), 0, 0);
    CHECK_NEAR(orr_image_kernel_sample(&k, -5, 3), 0, 0);
    CHECK_NEAR(orr_image_kernel_sample(&k, NAN, 0), 0, 0);
    orr_image_kernel_free(&k);
}

static void test_errors(void)
{
    orr_error err;
    orr_image_kernel k;
    CHECK(orr_image_kernel_alloc(&k, 4, 3, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "odd");
    CHECK(orr_image_kernel_alloc(&k, 3, 3, &err) == ORR_OK);
    CHECK(orr_image_kernel_normalise(&k, &err) == ORR_ERR_DATA); /* all zero */
    k.data[4] = 1;
    orr_convolver *c;
    CHECK(orr_convolver_create(&c, 0, 10, &k, NULL, &err) == ORR_ERR_USAGE);
    CHECK(c == NULL);
    CHECK(orr_convolver_create(&c, 10, 10, &k, NULL, &err) == ORR_OK);
    orr_plane p = make_plane(10, 11);
    CHECK(orr_convolver_apply(c, &p, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "10 x 11");
    orr_plane_free(&p);
    p = make_plane(10, 10);
    p.data[3 * 10 + 7] = NAN;
    CHECK(orr_convolver_apply(c, &p, &err) == ORR_ERR_DATA);
    CHECK_CONTAINS(err.msg, "(7, 3)");
    p.data[3 * 10 + 7] = 2;
    CHECK(orr_convolver_apply(c, &p, &err) == ORR_OK); /* identity kernel */
    CHECK_NEAR(p.data[37], 2, 1e-6);
    CHECK_NEAR(orr_plane_sum(&p), 2, 1e-5);
    orr_convolver_free(c);
    orr_plane_free(&p);
    orr_image_kernel_free(&k);
}

int main(void)
{
    RUN(test_good_size);
    RUN(test_gaussian_kernel);
    RUN(test_delta_is_gaussian);
    RUN(test_flux_conserved);
    RUN(test_no_wrap_around);
    RUN(test_matches_direct_convolution);
    RUN(test_plan_ownership);
    RUN(test_reproducible);
    RUN(test_measure_agrees);
    RUN(test_concurrent_planning);
    RUN(test_wisdom);
    RUN(test_kernel_sample);
    RUN(test_errors);
    return check_summary();
}
