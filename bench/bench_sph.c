/* SPH kernel deposit throughput: N particles with a typical smoothing
 * length of 1, 3 and 10 pixels, into an orthographic 2048^2 image and a
 * 3600^2 dome master (and a 4096 x 2048 Hammer-Aitoff panorama), next to
 * cloud-in-cell on the same particles. Particles are spread uniformly over
 * the view; the renderer's block loop (project, deposit) is timed, with
 * the projection step reported separately.
 *
 *   bench_sph [N [kernel [view]]]     default: 1e6 cubic, all views
 *
 * view is orthographic, dome or hammer-aitoff. Prints one line per view
 * and h: wall-clock and CPU seconds for the deposit step, and particles
 * per CPU second (the machine may be shared). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "splat/sph.h"
#include "clocks.h"
#include "test_random.h"

#define BLOCK 4096

/* Camera-frame positions: a unit square in front of the camera for the
 * flat view, directions uniform over the visible sky (at distance 1) for
 * the sky maps, so every particle is drawn. */
static void make_particles(const orr_projection *p, size_t n, float *x, float *y, float *z)
{
    uint64_t s = 12345;
    for (size_t i = 0; i < n; i++) {
        if (!orr_projection_is_sky(p)) {
            x[i] = (float)(test_uniform(&s) - 0.5);
            y[i] = (float)(test_uniform(&s) - 0.5);
            z[i] = 1.0f;
            continue;
        }
        /* Uniform on the sphere, or on the hemisphere z > 0 for the dome. */
        double cz = 2.0 * test_uniform(&s) - 1.0, phi = 2.0 * ORR_PI * test_uniform(&s);
        if (p->settings.kind == ORR_PROJ_DOME)
            cz = fabs(cz);
        double sz = sqrt(1.0 - cz * cz);
        x[i] = (float)(sz * cos(phi));
        y[i] = (float)(sz * sin(phi));
        z[i] = (float)cz;
    }
}

typedef struct result {
    double deposit, deposit_cpu, project;
} result;

static result run(const orr_sph *sph, const orr_projection *p, size_t n, const float *x, const float *y,
                  const float *z, float hworld, int cic, orr_plane *plane)
{
    static float px[BLOCK], py[BLOCK], sc[BLOCK], h[BLOCK], w[BLOCK];
    static uint8_t vis[BLOCK];
    for (int i = 0; i < BLOCK; i++) {
        h[i] = hworld;
        w[i] = 1.0f;
    }
    orr_deposit_stats st = {0};
    result r = {0, 0, 0};
    for (size_t start = 0; start < n; start += BLOCK) {
        size_t m = n - start < BLOCK ? n - start : BLOCK;
        double t0 = wall_seconds();
        orr_project_batch(p, m, x + start, y + start, z + start, px, py, sc, vis);
        double t1 = wall_seconds(), c1 = cpu_seconds();
        if (cic) {
            orr_deposit(ORR_DEPOSIT_CIC, plane, m, px, py, w, vis, p, &st);
        } else {
            orr_sph_block b = {m, x + start, y + start, z + start, px, py, sc, vis, h, w};
            orr_sph_deposit(sph, &b, plane, &st);
        }
        r.deposit += wall_seconds() - t1;
        r.deposit_cpu += cpu_seconds() - c1;
        r.project += t1 - t0;
    }
    double total = st.deposited + st.outside + st.culled;
    if (fabs(total - (double)n) > 1e-3 * n)
        fprintf(stderr, "warning: weight %g of %zu not accounted for\n", total, n);
    return r;
}

static void bench_view(const char *name, const orr_projection_settings *settings, const orr_kernel *k, size_t n)
{
    orr_error err = {0};
    orr_projection planned, *p = &planned;
    if (orr_projection_plan(p, settings, &err)) {
        fprintf(stderr, "%s\n", err.msg);
        exit(1);
    }
    orr_sph sph;
    double t0 = wall_seconds();
    if (orr_sph_init(&sph, k, p, &err)) {
        fprintf(stderr, "%s\n", err.msg);
        exit(1);
    }
    double t_init = wall_seconds() - t0;
    float *x = malloc(n * sizeof *x), *y = malloc(n * sizeof *y), *z = malloc(n * sizeof *z);
    orr_plane plane;
    if (!x || !y || !z || orr_plane_alloc(&plane, p->width, p->height, "m", "", &err)) {
        fprintf(stderr, "out of memory\n");
        exit(1);
    }
    make_particles(p, n, x, y, z);
    printf("%s %dx%d (setup %.3f s)\n", name, p->width, p->height, t_init);
    result r = run(&sph, p, n, x, y, z, 0.0f, 1, &plane);
    printf("  %-10s deposit %7.3f s wall %7.3f s cpu  %10.3g particles/s (cpu)  (projection %.3f s)\n", "cic",
           r.deposit, r.deposit_cpu, n / r.deposit_cpu, r.project);
    const double hpix[] = {1, 3, 10};
    for (int i = 0; i < 3; i++) {
        /* Pixels per unit length at the view's centre, at distance 1. */
        float hw = (float)(hpix[i] / p->focal);
        r = run(&sph, p, n, x, y, z, hw, 0, &plane);
        char label[32];
        snprintf(label, sizeof label, "sph h=%g", hpix[i]);
        printf("  %-10s deposit %7.3f s wall %7.3f s cpu  %10.3g particles/s (cpu)\n", label, r.deposit,
               r.deposit_cpu, n / r.deposit_cpu);
    }
    fflush(stdout);
    orr_plane_free(&plane);
    orr_sph_free(&sph);
    free(x);
    free(y);
    free(z);
}

int main(int argc, char **argv)
{
    size_t n = argc > 1 ? (size_t)atof(argv[1]) : 1000000;
    orr_kernel_kind kind = ORR_KERNEL_CUBIC;
    orr_error err = {0};
    if (argc > 2 && orr_kernel_parse(argv[2], &kind, &err)) {
        fprintf(stderr, "%s\n", err.msg);
        return 2;
    }
    orr_kernel k;
    double t0 = wall_seconds();
    if (orr_kernel_init(&k, kind, &err)) {
        fprintf(stderr, "%s\n", err.msg);
        return 1;
    }
    printf("kernel %s tabulated in %.3f s; %zu particles\n", orr_kernel_name(kind), wall_seconds() - t0, n);
    const orr_projection_settings ortho = {.kind = ORR_PROJ_ORTHOGRAPHIC, .width = 2048, .height = 2048,
                                           .ortho_width = 1.0};
    const orr_projection_settings dome = {.kind = ORR_PROJ_DOME, .width = 3600, .height = 3600, .dome_fov_deg = 180};
    const orr_projection_settings ait = {.kind = ORR_PROJ_HAMMER_AITOFF, .width = 4096, .height = 2048};
    const char *only = argc > 3 ? argv[3] : NULL;
    if (!only || strcmp(only, "orthographic") == 0)
        bench_view("orthographic", &ortho, &k, n);
    if (!only || strcmp(only, "dome") == 0)
        bench_view("dome", &dome, &k, n);
    if (!only || strcmp(only, "hammer-aitoff") == 0)
        bench_view("hammer-aitoff", &ait, &k, n);
    orr_kernel_free(&k);
    return 0;
}
