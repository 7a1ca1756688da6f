/* Smoothing lengths from the k-th nearest neighbour: k-d tree build and
 * queries on a Plummer sphere, with 1 and 2 threads.
 *
 *   bench_knn [N ...]        default: 1e5 1e6 (1e7 takes minutes)
 *
 * Prints, per N and thread count: build and query seconds (wall clock),
 * particles per second overall, the process's CPU seconds over the wall
 * seconds (about the thread count on an idle machine; less when other work
 * shares the cores), the tree's bytes per particle, and whether the lengths
 * match the 1-thread run bit for bit. */
#include <math.h>
#include <omp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "particles/kdtree.h"
#include "particles/smoothing.h"
#include "plummer.h"
#include "clocks.h"

static void die(const orr_error *err)
{
    fprintf(stderr, "bench_knn: %s\n", err->msg);
    exit(1);
}

static void run(size_t n, const float *x, const float *y, const float *z, int threads, float *h,
                const float *h_ref)
{
    orr_error err = {0};
    orr_kdtree t;
    omp_set_num_threads(threads);
    double c0 = cpu_seconds(), t0 = omp_get_wtime();
    if (orr_kdtree_build(&t, n, x, y, z, &err) != ORR_OK)
        die(&err);
    double t1 = omp_get_wtime();
    if (orr_smoothing_lengths_tree(&t, ORR_SMOOTHING_K_DEFAULT, ORR_SMOOTHING_FACTOR_DEFAULT, h, &err) != ORR_OK)
        die(&err);
    double t2 = omp_get_wtime(), c2 = cpu_seconds();
    double bytes = (double)(n * sizeof *t.pts + t.nnodes * sizeof *t.box) / (double)n;
    const char *same = h_ref ? (memcmp(h, h_ref, n * sizeof *h) == 0 ? "identical" : "DIFFERENT") : "-";
    printf("%10zu %7d %9.3f %9.3f %12.3g %8.2f %7.1f  %s\n", n, threads, t1 - t0, t2 - t1,
           (double)n / (t2 - t0), (c2 - c0) / (t2 - t0), bytes, same);
    fflush(stdout);
    orr_kdtree_free(&t);
}

int main(int argc, char **argv)
{
    size_t sizes[16] = {100000, 1000000};
    int nsizes = 2;
    if (argc > 1) {
        nsizes = 0;
        for (int i = 1; i < argc && nsizes < 16; i++)
            sizes[nsizes++] = (size_t)strtod(argv[i], NULL);
    }
    printf("k = %d, factor %.2f, Plummer sphere\n", ORR_SMOOTHING_K_DEFAULT, (double)ORR_SMOOTHING_FACTOR_DEFAULT);
    printf("%10s %7s %9s %9s %12s %8s %7s  %s\n", "N", "threads", "build s", "query s", "particles/s",
           "cpu/wall", "B/part", "vs 1 thread");
    for (int s = 0; s < nsizes; s++) {
        size_t n = sizes[s];
        float *x = malloc(n * sizeof *x), *y = malloc(n * sizeof *y), *z = malloc(n * sizeof *z);
        float *h1 = malloc(n * sizeof *h1), *h2 = malloc(n * sizeof *h2);
        if (!x || !y || !z || !h1 || !h2) {
            fprintf(stderr, "bench_knn: out of memory for %zu particles\n", n);
            return 1;
        }
        plummer_positions(n, 12345, 30.0, x, y, z);
        run(n, x, y, z, 1, h1, NULL);
        run(n, x, y, z, 2, h2, h1);
        free(x);
        free(y);
        free(z);
        free(h1);
        free(h2);
    }
    return 0;
}
