/* A sky map's PSF cores drawn one by one (each star's kernel evaluated, as
 * before) and from the stamp table (splat/sky_cores.h), side by side on the
 * same stars: the time, and how much the pixels differ.
 *
 *   bench_sky_cores [N] [CORE_PIXELS]    default: 1e6 stars, 3.2 (the automatic core)
 *
 * Stars are scattered uniformly over the sky at 1 to 10 units, each drawn
 * with the kernel the renderer gives a star under a PSF (h = k r, its
 * half-maximum width CORE_PIXELS at the map's centre: post/view_psf.c).
 * Times are one thread's, best of three, the two paths interleaved; the
 * table's includes making its stamps (the first star in each cell).
 * Accuracy, on 3000 of the stars drawn alone: the largest difference of a
 * pixel over the star's brightest pixel, flux and centroid of each path,
 * and the brightest pixel's share of the flux (what twinkles). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "clocks.h"
#include "frame/projection.h"
#include "post/view_psf.h"
#include "splat/sky_cores.h"
#include "splat/sph.h"
#include "test_random.h"

typedef struct stars {
    size_t n;
    float *x, *y, *z, *h, *w, *px, *py, *scale;
    uint8_t *visible;
} stars;

static void make_stars(stars *s, size_t n, double h_per_r, const orr_projection *p)
{
    s->n = n;
    float **arrays[] = {&s->x, &s->y, &s->z, &s->h, &s->w, &s->px, &s->py, &s->scale};
    for (size_t k = 0; k < sizeof arrays / sizeof arrays[0]; k++)
        *arrays[k] = malloc(n * sizeof(float));
    s->visible = malloc(n);
    uint64_t rng = 11;
    for (size_t i = 0; i < n; i++) {
        double u = 2.0 * test_uniform(&rng) - 1.0, phi = 2.0 * ORR_PI * test_uniform(&rng);
        double r = 1.0 + 9.0 * test_uniform(&rng), c = sqrt(1.0 - u * u);
        s->x[i] = (float)(r * c * cos(phi));
        s->y[i] = (float)(r * c * sin(phi));
        s->z[i] = (float)(r * u);
        float r2 = s->x[i] * s->x[i] + s->y[i] * s->y[i] + s->z[i] * s->z[i], k = (float)h_per_r;
        s->h[i] = sqrtf(k * k * r2); /* as render.c's widen_for_psf, with no length of its own */
        s->w[i] = 1.0f;
    }
    orr_project_batch(p, n, s->x, s->y, s->z, s->px, s->py, s->scale, s->visible);
}

static void free_stars(stars *s)
{
    float *arrays[] = {s->x, s->y, s->z, s->h, s->w, s->px, s->py, s->scale};
    for (size_t k = 0; k < sizeof arrays / sizeof arrays[0]; k++)
        free(arrays[k]);
    free(s->visible);
}

/* Stars [first, first + n) deposited in blocks of 4096, as the renderer does. */
static void deposit(const orr_sph *sph, const stars *s, size_t first, size_t n, orr_plane *plane)
{
    orr_deposit_stats st = {0};
    for (size_t i = first; i < first + n; i += 4096) {
        size_t m = first + n - i < 4096 ? first + n - i : 4096;
        orr_sph_block b = {m, s->x + i, s->y + i, s->z + i, s->px + i, s->py + i, s->scale + i, s->visible + i,
                           s->h + i, s->w + i};
        orr_sph_deposit(sph, &b, plane, &st);
    }
}

/* One path's time for all stars: a fresh table each time (its stamps are
 * part of the cost). */
static double time_path(orr_sph *sph, double theta, int table, const stars *s, orr_plane *plane)
{
    orr_error err = {0};
    if (table && orr_sph_use_cores(sph, theta, &err)) {
        fprintf(stderr, "%s\n", err.msg);
        exit(1);
    }
    double t0 = cpu_seconds();
    deposit(sph, s, 0, s->n, plane);
    double t = cpu_seconds() - t0;
    orr_sky_cores_free(sph->cores);
    sph->cores = NULL;
    return t;
}

/* Colour's three planes (X, Y, Z) from the table: plane after plane
 * (orr_sph_deposit three times, as before) against all three at once
 * (orr_sph_deposit_planes: one look-up a star); best of three each,
 * interleaved, the table made beforehand. */
static void time_planes(orr_sph *sph, double theta, const stars *s, orr_plane *planes, double best[2])
{
    orr_error err = {0};
    if (orr_sph_use_cores(sph, theta, &err)) {
        fprintf(stderr, "%s\n", err.msg);
        exit(1);
    }
    const float *w[3] = {s->w, s->w, s->w};
    best[0] = best[1] = 1e30;
    for (int rep = 0; rep < 4; rep++)
        for (int way = 0; way < 2; way++) {
            double t0 = cpu_seconds();
            for (size_t i = 0; i < s->n; i += 4096) {
                size_t m = s->n - i < 4096 ? s->n - i : 4096;
                orr_sph_block b = {m, s->x + i, s->y + i, s->z + i, s->px + i, s->py + i, s->scale + i,
                                   s->visible + i, s->h + i, s->w + i};
                orr_deposit_stats st[3] = {{0}};
                const float *wi[3] = {w[0] + i, w[1] + i, w[2] + i};
                if (way)
                    orr_sph_deposit_planes(sph, &b, wi, planes, 3, st);
                else
                    for (int k = 0; k < 3; k++)
                        orr_sph_deposit(sph, &b, &planes[k], &st[k]);
            }
            if (rep) /* the first pass makes the stamps */
                best[way] = fmin(best[way], cpu_seconds() - t0);
        }
    orr_sky_cores_free(sph->cores);
    sph->cores = NULL;
}

/* A star's light in the box of +-R pixels around it: flux, centroid, peak. */
#define R 14
typedef struct light {
    double flux, cx, cy, peak;
} light;

static light measure(const orr_plane *p, int ix, int iy)
{
    light l = {0, 0, 0, 0};
    for (int j = iy - R; j <= iy + R; j++)
        for (int i = ix - R; i <= ix + R; i++) {
            double v = p->data[(size_t)j * p->width + i];
            l.flux += v;
            l.cx += v * (i + 0.5);
            l.cy += v * (j + 0.5);
            l.peak = v > l.peak ? v : l.peak;
        }
    l.cx /= l.flux;
    l.cy /= l.flux;
    return l;
}

static void clear_box(orr_plane *p, int ix, int iy)
{
    for (int j = iy - R; j <= iy + R; j++)
        memset(p->data + (size_t)j * p->width + ix - R, 0, (2 * R + 1) * sizeof(float));
}

/* Largest |a - b| in the box over a's peak. */
static double worst_pixel(const orr_plane *a, const orr_plane *b, int ix, int iy, double peak)
{
    double worst = 0.0;
    for (int j = iy - R; j <= iy + R; j++)
        for (int i = ix - R; i <= ix + R; i++) {
            size_t k = (size_t)j * a->width + i;
            worst = fmax(worst, fabs((double)a->data[k] - b->data[k]) / peak);
        }
    return worst;
}

typedef struct accuracy {
    int stars;
    double worst_pixel, mean_worst, flux_err, centroid_err[2], share_lo[2], share_hi[2];
} accuracy;

/* The stars the table draws (the others are drawn one by one either way),
 * each alone, by both paths. */
static void accuracy_of(orr_sph *exact, orr_sph *table, const stars *s, orr_plane *a, orr_plane *b,
                        accuracy *acc)
{
    memset(acc, 0, sizeof *acc);
    acc->share_lo[0] = acc->share_lo[1] = 1.0;
    for (size_t i = 0; i < s->n && acc->stars < 3000; i++) {
        const int ix = (int)floorf(s->px[i]), iy = (int)floorf(s->py[i]);
        if (!s->visible[i] || ix < R || iy < R || ix >= a->width - R || iy >= a->height - R)
            continue;
        const double theta = s->h[i] / sqrt((double)s->x[i] * s->x[i] + (double)s->y[i] * s->y[i] +
                                            (double)s->z[i] * s->z[i]);
        if (orr_sky_cores_draw(table->cores, table, s->px[i], s->py[i], theta, s->w[i], b)) {
            deposit(exact, s, i, 1, a);
            light la = measure(a, ix, iy), lb = measure(b, ix, iy);
            double truth[2] = {s->px[i], s->py[i]};
            double wp = worst_pixel(a, b, ix, iy, la.peak);
            acc->stars++;
            acc->worst_pixel = fmax(acc->worst_pixel, wp);
            acc->mean_worst += wp;
            acc->flux_err = fmax(acc->flux_err, fabs(lb.flux - 1.0));
            const light *l[2] = {&la, &lb};
            for (int k = 0; k < 2; k++) {
                acc->centroid_err[k] = fmax(acc->centroid_err[k], hypot(l[k]->cx - truth[0], l[k]->cy - truth[1]));
                acc->share_lo[k] = fmin(acc->share_lo[k], l[k]->peak / l[k]->flux);
                acc->share_hi[k] = fmax(acc->share_hi[k], l[k]->peak / l[k]->flux);
            }
        }
        clear_box(a, ix, iy);
        clear_box(b, ix, iy);
    }
    acc->mean_worst /= acc->stars ? acc->stars : 1;
}

static void run_projection(const char *name, const orr_projection_settings *settings, const orr_kernel *k, size_t n,
                           double core_pixels)
{
    orr_error err = {0};
    orr_projection planned, *p = &planned;
    orr_sph exact, table;
    orr_plane a, b;
    if (orr_projection_plan(p, settings, &err) || orr_sph_init(&exact, k, p, &err) ||
        orr_sph_init(&table, k, p, &err) ||
        orr_plane_alloc(&a, p->width, p->height, "w", "", &err) ||
        orr_plane_alloc(&b, p->width, p->height, "w", "", &err)) {
        fprintf(stderr, "%s\n", err.msg);
        exit(1);
    }
    /* The core's angle as post/view_psf.c makes it. */
    const double fwhm = core_pixels / p->focal, theta = (float)(2.0 * sin(0.25 * fwhm) / orr_kernel_half_max_q(k));
    stars s;
    make_stars(&s, n, theta, p);
    double best[2] = {1e30, 1e30};
    for (int rep = 0; rep < 3; rep++)
        for (int path = 0; path < 2; path++) /* interleaved: the machine is shared */
            best[path] = fmin(best[path], time_path(&exact, theta, path, &s, &a));
    memset(a.data, 0, sizeof(float) * (size_t)p->width * p->height);
    accuracy acc;
    if (orr_sph_use_cores(&table, theta, &err)) {
        fprintf(stderr, "%s\n", err.msg);
        exit(1);
    }
    accuracy_of(&exact, &table, &s, &a, &b, &acc);
    long cells;
    size_t bytes;
    orr_sky_cores_usage(table.cores, &cells, &bytes);
    printf("%-24s %9zu  one by one %7.3f s (%8.3g stars/s)  table %7.3f s (%8.3g stars/s)  %5.1fx\n", name, n,
           best[0], n / best[0], best[1], n / best[1], best[0] / best[1]);
    orr_plane xyz[3];
    for (int c = 0; c < 3; c++)
        if (orr_plane_alloc(&xyz[c], p->width, p->height, "w", "", &err)) {
            fprintf(stderr, "%s\n", err.msg);
            exit(1);
        }
    double three[2];
    time_planes(&exact, theta, &s, xyz, three);
    printf("%-24s   X, Y, Z from the table: plane after plane %7.3f s, all at once %7.3f s  %5.2fx\n", "", three[0],
           three[1], three[0] / three[1]);
    for (int c = 0; c < 3; c++)
        orr_plane_free(&xyz[c]);
    printf("%-24s   %d stars alone, from the table: worst pixel %.2e of the star's peak (mean of the worst "
           "%.2e); table flux within %.1e; centroid within %.4f px (one by one %.4f); peak share %.4f-%.4f "
           "(%.3fx; one by one %.4f-%.4f, %.3fx); %ld cells of stamps, %.1f MB after these stars\n",
           "", acc.stars, acc.worst_pixel, acc.mean_worst, acc.flux_err, acc.centroid_err[1],
           acc.centroid_err[0], acc.share_lo[1], acc.share_hi[1], acc.share_hi[1] / acc.share_lo[1],
           acc.share_lo[0], acc.share_hi[0], acc.share_hi[0] / acc.share_lo[0], cells, bytes / 1e6);
    free_stars(&s);
    orr_sph_free(&exact);
    orr_sph_free(&table);
    orr_plane_free(&a);
    orr_plane_free(&b);
}

int main(int argc, char **argv)
{
    size_t n = argc > 1 ? (size_t)strtod(argv[1], NULL) : 1000000;
    double core = argc > 2 ? strtod(argv[2], NULL) : ORR_SKY_CORE_PIXELS;
    orr_kernel k;
    orr_error err = {0};
    if (n < 1 || !(core > 0) || orr_kernel_init(&k, ORR_KERNEL_CUBIC, &err)) {
        fprintf(stderr, "usage: bench_sky_cores [N] [CORE_PIXELS] %s\n", err.msg);
        return 2;
    }
    printf("PSF cores of %.2f pixels (FWHM at the map's centre), CPU seconds on one thread, best of 3\n", core);
    struct {
        const char *name;
        orr_projection_settings settings;
    } projs[] = {
        {"dome 3600^2", {.kind = ORR_PROJ_DOME, .width = 3600, .height = 3600, .dome_fov_deg = 180}},
        {"hammer-aitoff 4096x2048", {.kind = ORR_PROJ_HAMMER_AITOFF, .width = 4096, .height = 2048}},
        {"equirectangular 4096x2048", {.kind = ORR_PROJ_EQUIRECTANGULAR, .width = 4096, .height = 2048}},
    };
    for (size_t j = 0; j < sizeof projs / sizeof projs[0]; j++)
        run_projection(projs[j].name, &projs[j].settings, &k, n, core);
    orr_kernel_free(&k);
    return 0;
}
