/* The Hubble PSF on a sky map, as the production frame draws it (issue 24):
 * the PSF's generation, then STARS spike stars on a 3600^2 dome master,
 * each stamped in its own tangent plane, fast (tiles interpolated,
 * sky_psf_stamp.c) and exact (every sample mapped to the sky), on the same
 * stars.
 *
 *   bench_sky_psf [STARS] [SIDE]     default: 200 stars, 3600
 *   BENCH_FAST_ONLY=1 bench_sky_psf  the fast path alone (for a profiler)
 *
 * Prints the generation's wall and CPU seconds, each path's (best of
 * three, interleaved; all threads: OMP_NUM_THREADS), and how the fast
 * planes differ from the exact ones: total flux, the largest difference
 * over the brightest pixel, and the largest relative difference among
 * pixels above 1e-4 of it. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "clocks.h"
#include "frame/projection.h"
#include "post/view_psf.h"
#include "splat/sph.h"
#include "test_random.h"

static void die(const orr_error *err)
{
    fprintf(stderr, "bench_sky_psf: %s\n", err->msg);
    exit(1);
}

/* Stars above the dome's horizon, one unit away, weights from 1 to 100. */
static void make_stars(orr_sky_psf *sp, int n, const orr_projection *p, double h)
{
    sp->stars = calloc((size_t)n, sizeof *sp->stars);
    uint64_t rng = 5;
    for (int i = 0; i < n; i++) {
        orr_sky_star *s = &sp->stars[i];
        for (;;) {
            double u = 2.0 * test_uniform(&rng) - 1.0, phi = 2.0 * ORR_PI * test_uniform(&rng), c = sqrt(1 - u * u);
            s->x = (float)(c * cos(phi)), s->y = (float)(c * sin(phi)), s->z = (float)u;
            uint8_t vis = 0;
            orr_project_batch(p, 1, &s->x, &s->y, &s->z, &s->px, &s->py, &s->scale, &vis);
            if (vis)
                break;
        }
        s->h = (float)h;
        s->key = s->w[0] = (float)(100.0 - i * 99.0 / n);
    }
    sp->nstars = n;
}

/* The plane as the splat leaves it: every star's core. */
static void draw_cores(const orr_sky_psf *sp, const orr_sph *sph, orr_plane *plane)
{
    memset(plane->data, 0, sizeof(float) * (size_t)plane->width * plane->height);
    const uint8_t visible = 1;
    for (int i = 0; i < sp->nstars; i++) {
        const orr_sky_star *s = &sp->stars[i];
        orr_sph_block b = {1, &s->x, &s->y, &s->z, &s->px, &s->py, &s->scale, &visible, &s->h, &s->w[0]};
        orr_deposit_stats stats = {0};
        orr_sph_deposit(sph, &b, plane, &stats);
    }
}

static double draw(orr_sky_psf *sp, const orr_sph *sph, orr_plane *plane, int exact, double *cpu)
{
    orr_error err = {0};
    draw_cores(sp, sph, plane);
    sp->exact = exact;
    double w0 = wall_seconds(), c0 = cpu_seconds();
    if (orr_sky_psf_draw(sp, sph, plane, 1, &err))
        die(&err);
    *cpu = cpu_seconds() - c0;
    return wall_seconds() - w0;
}

int main(int argc, char **argv)
{
    const int nstars = argc > 1 ? atoi(argv[1]) : 200, side = argc > 2 ? atoi(argv[2]) : 3600;
    orr_error err = {0};
    orr_psf_settings ps;
    orr_psf_settings_defaults(&ps);
    ps.kind = ORR_PSF_HST;
    orr_image_kernel psf = {0};
    double w0 = wall_seconds(), c0 = cpu_seconds();
    if (orr_view_psf_kernel(&ps, NULL, &psf, &err))
        die(&err);
    printf("Hubble PSF generated: %.3f s wall, %.3f s CPU\n", wall_seconds() - w0, cpu_seconds() - c0);

    const orr_projection_settings dome = {.kind = ORR_PROJ_DOME, .width = side, .height = side, .dome_fov_deg = 180};
    orr_projection p;
    orr_kernel k;
    orr_sph sph;
    orr_plane fast, exact;
    orr_sky_psf sp;
    const double fwhm = ORR_SKY_CORE_PIXELS / side * ORR_PI; /* the automatic core */
    if (orr_kernel_init(&k, ORR_KERNEL_CUBIC, &err) || orr_projection_plan(&p, &dome, &err) ||
        orr_sph_init(&sph, &k, &p, &err) || orr_plane_alloc(&fast, side, side, "w", "", &err) ||
        orr_plane_alloc(&exact, side, side, "w", "", &err) ||
        orr_sky_psf_init(&sp, &psf, ORR_SKY_CORE_PIXELS / p.focal, nstars, 0.0, 0, &err))
        die(&err);
    make_stars(&sp, nstars, &p, 2.0 * sin(0.25 * fwhm) / orr_kernel_half_max_q(&k));
    double best[2][2] = {{1e30, 1e30}, {1e30, 1e30}};
    orr_plane *planes[2] = {&fast, &exact};
    for (int rep = 0; rep < 3; rep++)
        for (int path = 0; path < (getenv("BENCH_FAST_ONLY") ? 1 : 2); path++) {
            double cpu, wall = draw(&sp, &sph, planes[path], path, &cpu);
            best[path][0] = fmin(best[path][0], wall);
            best[path][1] = fmin(best[path][1], cpu);
        }
    double flux[2] = {0, 0}, peak = 0, worst = 0, worst_rel = 0;
    for (size_t i = 0; i < (size_t)side * side; i++) {
        flux[0] += fast.data[i];
        flux[1] += exact.data[i];
        peak = fmax(peak, exact.data[i]);
    }
    for (size_t i = 0; i < (size_t)side * side; i++) {
        double d = fabs((double)fast.data[i] - exact.data[i]);
        worst = fmax(worst, d / peak);
        if (exact.data[i] > 1e-4 * peak)
            worst_rel = fmax(worst_rel, d / exact.data[i]);
    }
    printf("%d spike stars on a %d^2 dome master (%d drawn), best of 3:\n", nstars, side, sp.stars_drawn);
    printf("  fast   %.3f s wall, %.3f s CPU (%.2f ms CPU a star)\n", best[0][0], best[0][1],
           1e3 * best[0][1] / nstars);
    printf("  exact  %.3f s wall, %.3f s CPU (%.2f ms CPU a star)\n", best[1][0], best[1][1],
           1e3 * best[1][1] / nstars);
    double weight = 0;
    for (int i = 0; i < nstars; i++)
        weight += sp.stars[i].w[0];
    printf("  fast - exact: flux %.9g vs %.9g of %.9g; worst pixel %.2e of the brightest; worst relative %.2e "
           "(pixels above 1e-4 of it)\n",
           flux[0], flux[1], weight, worst, worst_rel);
    orr_sky_psf_free(&sp);
    orr_sph_free(&sph);
    orr_plane_free(&fast);
    orr_plane_free(&exact);
    orr_kernel_free(&k);
    return 0;
}
