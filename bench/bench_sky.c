/* Splatting throughput of the sky projections next to orthographic, on the
 * same particles: the renderer's block loop (rotate into the camera frame,
 * project, deposit) timed over N particles around an observer.
 *
 *   bench_sky [N ...]        default: 1e6 1e7
 *
 * Prints one line per projection and N: seconds, particles per second, and
 * the ratio to orthographic, for the whole loop and for the projection step
 * alone (where the transcendental functions are; the deposit's cost is
 * mostly cache misses, which depend on where the particles land). */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "frame/camera.h"
#include "frame/projection.h"
#include "splat/deposit.h"
#include "clocks.h"
#include "thick_disc.h"

#define BLOCK 4096

typedef struct timing {
    double total, project;
} timing;

static timing run(const orr_projection *p, size_t n, const float *x, const float *y, const float *z,
                  const float *w)
{
    static float cx[BLOCK], cy[BLOCK], cz[BLOCK], px[BLOCK], py[BLOCK], sc[BLOCK];
    static uint8_t vis[BLOCK];
    orr_plane plane;
    orr_error err = {0};
    if (orr_plane_alloc(&plane, p->width, p->height, "m", "", &err)) {
        fprintf(stderr, "%s\n", err.msg);
        exit(1);
    }
    orr_camera cam;
    orr_camera_look_along(&cam, orr_v3(0, 0, 0), orr_v3(1, 0.2, 0.1), orr_v3(0, 0, 1), 0, &err);
    orr_mat3 R = orr_camera_world_to_camera(&cam);
    float r[9];
    for (int i = 0; i < 9; i++)
        r[i] = (float)R.m[i / 3][i % 3];
    orr_deposit_stats st = {0};
    double t0 = wall_seconds(), t_project = 0;
    for (size_t start = 0; start < n; start += BLOCK) {
        size_t m = n - start < BLOCK ? n - start : BLOCK;
        const float *bx = x + start, *by = y + start, *bz = z + start;
        for (size_t i = 0; i < m; i++) {
            cx[i] = r[0] * bx[i] + r[1] * by[i] + r[2] * bz[i];
            cy[i] = r[3] * bx[i] + r[4] * by[i] + r[5] * bz[i];
            cz[i] = r[6] * bx[i] + r[7] * by[i] + r[8] * bz[i];
        }
        double t1 = wall_seconds();
        orr_project_batch(p, m, cx, cy, cz, px, py, sc, vis);
        t_project += wall_seconds() - t1;
        orr_deposit(ORR_DEPOSIT_NGP, &plane, m, px, py, w + start, vis, p, &st);
    }
    timing t = {wall_seconds() - t0, t_project};
    orr_plane_free(&plane);
    return t;
}

int main(int argc, char **argv)
{
    size_t sizes[8] = {1000000, 10000000};
    int nsizes = 2;
    if (argc > 1) {
        nsizes = 0;
        for (int i = 1; i < argc && nsizes < 8; i++)
            sizes[nsizes++] = (size_t)strtod(argv[i], NULL);
    }
    /* Each sky map is compared with an orthographic view of the same size:
     * scattered writes into a bigger plane miss the cache more, whatever
     * the projection. */
    struct { const char *name; orr_projection_settings settings; int reference; } projs[] = {
        {"orthographic 3600^2", {.kind = ORR_PROJ_ORTHOGRAPHIC, .width = 3600, .height = 3600, .ortho_width = 40}, 1},
        {"dome 3600^2", {.kind = ORR_PROJ_DOME, .width = 3600, .height = 3600, .dome_fov_deg = 180}, 0},
        {"orthographic 4096x2048", {.kind = ORR_PROJ_ORTHOGRAPHIC, .width = 4096, .height = 2048, .ortho_width = 40}, 1},
        {"hammer-aitoff 4096x2048", {.kind = ORR_PROJ_HAMMER_AITOFF, .width = 4096, .height = 2048}, 0},
        {"equirectangular 4096x2048", {.kind = ORR_PROJ_EQUIRECTANGULAR, .width = 4096, .height = 2048}, 0},
    };
    int nprojs = (int)(sizeof projs / sizeof projs[0]);
    printf("%-26s %10s %9s %12s %8s   %12s %8s\n", "projection (NGP)", "particles", "seconds", "particles/s",
           "vs ortho", "project-only", "vs ortho");
    for (int k = 0; k < nsizes; k++) {
        size_t n = sizes[k];
        float *x = malloc(n * sizeof *x), *y = malloc(n * sizeof *y), *z = malloc(n * sizeof *z),
              *w = malloc(n * sizeof *w);
        if (!x || !y || !z || !w)
            return 1;
        thick_disc(n, x, y, z); /* around the observer at the origin */
        for (size_t i = 0; i < n; i++)
            w[i] = 1.0f;
        timing ortho = {0, 0};
        for (int j = 0; j < nprojs; j++) {
            orr_error err = {0};
            orr_projection p;
            if (orr_projection_plan(&p, &projs[j].settings, &err))
                return 1;
            timing best = {1e30, 1e30};
            for (int rep = 0; rep < 3; rep++) { /* best of three: the machine may be shared */
                timing t = run(&p, n, x, y, z, w);
                best.total = t.total < best.total ? t.total : best.total;
                best.project = t.project < best.project ? t.project : best.project;
            }
            if (projs[j].reference)
                ortho = best;
            printf("%-26s %10zu %9.4f %12.3g %7.2fx   %12.3g %7.2fx\n", projs[j].name, n, best.total,
                   n / best.total, best.total / ortho.total, n / best.project, best.project / ortho.project);
        }
        free(x);
        free(y);
        free(z);
        free(w);
    }
    return 0;
}
