/* Flat-image SPH deposit (orr_sph_deposit on an orthographic 1024^2
 * image), the case of the scale goal "exact column density 10x faster than
 * SPLASH": uniform particles with h = 0.3, 1, 1.7, 3 and 10 pixels, and a
 * Plummer sphere (cut at r = 10, h = 1.2 (m / rho)^(1/3) from its density,
 * an 8 x 8 unit view: as bench/bench_splash.sh's, so for N = 1e7 the
 * centre's h is 1.2 pixels, the median 2.6, the 90th percentile 9.7).
 *
 *   OMP_NUM_THREADS=2 bench_sph_flat [N [case ...]]    default: 1e6, all cases
 *
 * case: a number (uniform, h in pixels) or "plummer". Particles are
 * projected once (not timed) and deposited in blocks of 4096 as the
 * renderer does. Prints per case the CPU seconds and particles per CPU
 * second of the deposit on one thread, and the wall and CPU seconds on
 * OMP_NUM_THREADS threads, each depositing every other block into its own
 * plane (the renderer's lanes), planes not summed. CPU time because the
 * machine may be shared: on a loaded machine the wall clock of the
 * threaded run says little. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "clocks.h"
#include "splat/sph.h"
#include "test_random.h"

#define BLOCK 4096
#define NPIX 1024
#define VIEW 8.0 /* units across the image */

/* Camera-frame positions and smoothing lengths (units of the view). */
static void make_uniform(size_t n, double hpix, float *x, float *y, float *z, float *h)
{
    uint64_t s = 12345;
    for (size_t i = 0; i < n; i++) {
        x[i] = (float)(VIEW * (test_uniform(&s) - 0.5));
        y[i] = (float)(VIEW * (test_uniform(&s) - 0.5));
        z[i] = 20.0f;
        h[i] = (float)(hpix * VIEW / NPIX);
    }
}

/* A Plummer sphere of unit mass and scale length, cut at r = 10: radius
 * from the inverse of the enclosed mass, direction uniform, h from the
 * density at that radius. */
static void make_plummer(size_t n, float *x, float *y, float *z, float *h)
{
    uint64_t s = 6789;
    const double rmax = 10.0, mmax = pow(rmax * rmax / (rmax * rmax + 1.0), 1.5), m = 1.0 / n;
    for (size_t i = 0; i < n; i++) {
        double u = mmax * test_uniform(&s);
        while (!(u > 0))
            u = mmax * test_uniform(&s);
        double r = 1.0 / sqrt(pow(u, -2.0 / 3.0) - 1.0);
        double cz = 2.0 * test_uniform(&s) - 1.0, phi = 2.0 * ORR_PI * test_uniform(&s), sz = sqrt(1.0 - cz * cz);
        double rho = 3.0 / (4.0 * ORR_PI) * pow(1.0 + r * r, -2.5);
        x[i] = (float)(r * sz * cos(phi));
        y[i] = (float)(r * sz * sin(phi));
        z[i] = (float)(20.0 + r * cz);
        h[i] = (float)(1.2 * cbrt(m / rho));
    }
}

typedef struct projected {
    size_t n;
    float *x, *y, *z, *h, *w, *px, *py, *scale;
    uint8_t *visible;
} projected;

static void deposit_blocks(const orr_sph *sph, const projected *p, size_t first, size_t stride, orr_plane *plane,
                           orr_deposit_stats *st)
{
    for (size_t start = first * BLOCK; start < p->n; start += stride * BLOCK) {
        size_t m = p->n - start < BLOCK ? p->n - start : BLOCK;
        orr_sph_block b = {m,         p->x + start,     p->y + start, p->z + start, p->px + start, p->py + start,
                           p->scale + start, p->visible + start, p->h + start, p->w + start};
        orr_sph_deposit(sph, &b, plane, st);
    }
}

static void bench_case(const char *name, const orr_sph *sph, const orr_projection *proj, projected *p,
                       orr_plane *planes, int threads)
{
    orr_project_batch(proj, p->n, p->x, p->y, p->z, p->px, p->py, p->scale, p->visible);
    orr_deposit_stats st = {0};
    memset(planes[0].data, 0, sizeof(float) * NPIX * NPIX);
    double c0 = cpu_seconds();
    deposit_blocks(sph, p, 0, 1, &planes[0], &st);
    double cpu1 = cpu_seconds() - c0;
    double total = st.deposited + st.outside + st.culled;
    if (fabs(total - (double)p->n) > 1e-3 * p->n)
        fprintf(stderr, "warning: weight %g of %zu not accounted for\n", total, p->n);
    double w0 = wall_seconds();
    c0 = cpu_seconds();
#pragma omp parallel num_threads(threads)
    {
        orr_deposit_stats mine = {0};
        int t = omp_get_thread_num(), nt = omp_get_num_threads();
        memset(planes[t].data, 0, sizeof(float) * NPIX * NPIX);
        deposit_blocks(sph, p, (size_t)t, (size_t)nt, &planes[t], &mine);
    }
    double wall = wall_seconds() - w0, cpun = cpu_seconds() - c0;
    printf("  %-12s 1 thread %7.3f s cpu %10.3g particles/s | %d threads %7.3f s wall %7.3f s cpu\n", name, cpu1,
           p->n / cpu1, threads, wall, cpun);
    fflush(stdout);
}

int main(int argc, char **argv)
{
    size_t n = argc > 1 ? (size_t)atof(argv[1]) : 1000000;
    int threads = omp_get_max_threads();
    orr_error err = {0};
    orr_kernel k;
    const orr_projection_settings view = {.kind = ORR_PROJ_ORTHOGRAPHIC, .width = NPIX, .height = NPIX,
                                          .ortho_width = VIEW};
    orr_projection proj;
    orr_sph sph;
    if (orr_kernel_init(&k, ORR_KERNEL_CUBIC, &err) || orr_projection_plan(&proj, &view, &err) ||
        orr_sph_init(&sph, &k, &proj, &err)) {
        fprintf(stderr, "%s\n", err.msg);
        return 1;
    }
    projected p = {.n = n};
    float **arrays[] = {&p.x, &p.y, &p.z, &p.h, &p.w, &p.px, &p.py, &p.scale};
    for (size_t a = 0; a < sizeof arrays / sizeof arrays[0]; a++)
        if (!(*arrays[a] = malloc(n * sizeof(float)))) {
            fprintf(stderr, "out of memory\n");
            return 1;
        }
    p.visible = malloc(n);
    orr_plane *planes = calloc((size_t)threads, sizeof *planes);
    if (!p.visible || !planes)
        return 1;
    for (int t = 0; t < threads; t++)
        if (orr_plane_alloc(&planes[t], NPIX, NPIX, "m", "", &err)) {
            fprintf(stderr, "%s\n", err.msg);
            return 1;
        }
    for (size_t i = 0; i < n; i++)
        p.w[i] = 1.0f;
    printf("flat SPH deposit, cubic kernel, %dx%d, %zu particles, %d threads\n", NPIX, NPIX, n, threads);
    static const char *defaults[] = {"0.3", "1", "1.7", "3", "10", "plummer"};
    int ncases = argc > 2 ? argc - 2 : (int)(sizeof defaults / sizeof defaults[0]);
    for (int c = 0; c < ncases; c++) {
        const char *name = argc > 2 ? argv[c + 2] : defaults[c];
        char label[32];
        if (strcmp(name, "plummer") == 0) {
            make_plummer(n, p.x, p.y, p.z, p.h);
            snprintf(label, sizeof label, "plummer");
        } else {
            make_uniform(n, atof(name), p.x, p.y, p.z, p.h);
            snprintf(label, sizeof label, "h=%s px", name);
        }
        bench_case(label, &sph, &proj, &p, planes, threads);
    }
    for (int t = 0; t < threads; t++)
        orr_plane_free(&planes[t]);
    for (size_t a = 0; a < sizeof arrays / sizeof arrays[0]; a++)
        free(*arrays[a]);
    free(p.visible);
    free(planes);
    orr_sph_free(&sph);
    orr_kernel_free(&k);
    return 0;
}
