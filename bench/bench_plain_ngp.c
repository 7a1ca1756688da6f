/* The yardstick for orrery's nearest-pixel figures: the plainest C loop
 * that bins a snapshot's particles into an image, on the same particles,
 * view and machine, in the same run (bench/bench_scale.sh prints it beside
 * orrery's in-memory rate). One pass over x, y and mass: scale, test the
 * bounds, add. Each thread bins its slice into an image of its own, and
 * the images are then summed, so the figure includes what orrery's frame
 * includes (the images zeroed and merged), and none of what a renderer
 * needs beyond that (no camera rotation, no checks for NaNs, no report).
 *
 *   bench_plain_ngp SNAPSHOT CX CY WIDTH PIXELS [REPEATS]
 *
 * The view: x in [CX - WIDTH/2, CX + WIDTH/2], y likewise around CY,
 * PIXELS x PIXELS. Threads: OMP_NUM_THREADS. Prints one line:
 * "plain C loop N particles: best W s wall, R particles/s". */
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>

#include "clocks.h"
#include "snapshot_load.h"

static double bin_once(const loaded_snapshot *p, double cx, double cy, double width, int npix, double *total)
{
    const int nthreads = omp_get_max_threads();
    const size_t npixels = (size_t)npix * (size_t)npix;
    double t0 = wall_seconds();
    float *images = calloc((size_t)nthreads * npixels, sizeof *images);
    if (!images) {
        fputs("bench_plain_ngp: out of memory\n", stderr);
        exit(1);
    }
    const float scale = (float)(npix / width), x0 = (float)(cx - 0.5 * width), y0 = (float)(cy - 0.5 * width);
    const float side = (float)npix;
#pragma omp parallel
    {
        float *restrict img = images + (size_t)omp_get_thread_num() * npixels;
        const float *restrict x = p->x, *restrict y = p->y, *restrict m = p->mass;
#pragma omp for schedule(static)
        for (size_t i = 0; i < p->n; i++) {
            float px = (x[i] - x0) * scale, py = (y[i] - y0) * scale;
            if (px >= 0.0f && px < side && py >= 0.0f && py < side)
                img[(size_t)(int)py * (size_t)npix + (size_t)(int)px] += m[i];
        }
#pragma omp for schedule(static)
        for (size_t k = 0; k < npixels; k++)
            for (int t = 1; t < nthreads; t++)
                images[k] += images[(size_t)t * npixels + k];
    }
    double wall = wall_seconds() - t0;
    double sum = 0;
    for (size_t k = 0; k < npixels; k++)
        sum += images[k];
    *total = sum;
    free(images);
    return wall;
}

int main(int argc, char **argv)
{
    int repeats = argc > 6 ? atoi(argv[6]) : 3;
    if (argc < 6 || argc > 7 || repeats < 1) {
        fputs("usage: bench_plain_ngp SNAPSHOT CX CY WIDTH PIXELS [REPEATS]\n", stderr);
        return 2;
    }
    double cx = atof(argv[2]), cy = atof(argv[3]), width = atof(argv[4]);
    int npix = atoi(argv[5]);
    if (!(width > 0) || npix < 1 || npix > 65536) {
        fputs("bench_plain_ngp: WIDTH must be positive and PIXELS from 1 to 65536\n", stderr);
        return 2;
    }
    loaded_snapshot p;
    load_snapshot(argv[1], 0, &p);
    double best = 0, total = 0;
    for (int r = 0; r < repeats; r++) {
        double t = bin_once(&p, cx, cy, width, npix, &total);
        best = r == 0 || t < best ? t : best;
    }
    printf("plain C loop %zu particles: best %.4f s wall, %.4g particles/s (binned mass %.6g)\n", p.n, best,
           (double)p.n / best, total);
    free_snapshot(&p);
    return 0;
}
