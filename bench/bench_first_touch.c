/* What zeroing a frame's image planes costs on this machine: the planes
 * allocated (their first touch: the kernel clears each page as it is
 * faulted in), cleared again while warm (a film's later frames), and freed
 * and allocated anew, side by side in one run (docs/performance.md, "What
 * the frame costs before its particles").
 *
 *   build/bench/bench_first_touch                # an 8192^2 view's X, Y, Z: 805 MB
 *   build/bench/bench_first_touch 3600 3600 3 5  # width, height, planes, rounds
 *
 * On a virtual machine whose host backs fresh memory on demand, the first
 * touch can run at a tenth of the warm clear's speed or less; that is a
 * cost every fresh frame's planes pay, whatever the particles. Planes go
 * through orr_plane_alloc, so on every thread and on huge pages as the
 * render's do. */
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/plane.h"
#include "core/timings.h"

#define PLANES_MAX 32

static int arg_int(int argc, char **argv, int k, int fallback, int lo, int hi, const char *what)
{
    if (argc <= k)
        return fallback;
    char *end;
    long v = strtol(argv[k], &end, 10);
    if (*end || v < lo || v > hi) {
        fprintf(stderr, "bench_first_touch: %s must be a whole number from %d to %d, not '%s'\n", what, lo, hi,
                argv[k]);
        exit(2);
    }
    return (int)v;
}

/* Seconds of wall and CPU since `from`. */
static orr_clock since(orr_clock from)
{
    orr_clock now = orr_clock_now();
    return (orr_clock){now.wall - from.wall, now.cpu - from.cpu};
}

static void print_row(const char *what, double gb, orr_clock t)
{
    printf("%-34s %8.3f %8.3f %10.2f %12.2f\n", what, t.wall, t.cpu, gb / t.wall, gb / t.cpu);
}

int main(int argc, char **argv)
{
    const int width = arg_int(argc, argv, 1, 8192, 1, 65536, "the width");
    const int height = arg_int(argc, argv, 2, 8192, 1, 65536, "the height");
    const int nplanes = arg_int(argc, argv, 3, 3, 1, PLANES_MAX, "the number of planes");
    const int rounds = arg_int(argc, argv, 4, 3, 1, 100, "the number of rounds");
    const double gb = (double)width * height * sizeof(float) * nplanes / 1e9;
    printf("%d planes of %d x %d floats (%.0f MB), %d threads, %d rounds\n", nplanes, width, height, gb * 1e3,
           omp_get_max_threads(), rounds);
    printf("%-34s %8s %8s %10s %12s\n", "", "wall s", "CPU s", "GB/s", "GB/CPU s");
    orr_plane planes[PLANES_MAX];
    orr_error err = {0};
    for (int r = 0; r < rounds; r++) {
        orr_clock t0 = orr_clock_now();
        for (int k = 0; k < nplanes; k++)
            if (orr_plane_alloc(&planes[k], width, height, "bench", "", &err)) {
                fprintf(stderr, "bench_first_touch: %s\n", err.msg);
                return 1;
            }
        print_row(r == 0 ? "allocated: the first touch" : "allocated again after the free", gb, since(t0));
        t0 = orr_clock_now();
        for (int k = 0; k < nplanes; k++)
            orr_plane_clear(&planes[k]);
        print_row("cleared again, warm", gb, since(t0));
        /* each plane's centre read back: a cleared plane is zero there */
        double sum = 0;
        for (int k = 0; k < nplanes; k++)
            sum += planes[k].data[(size_t)(height / 2) * width + width / 2];
        if (sum != 0) {
            fprintf(stderr, "bench_first_touch: a cleared plane is not zero\n");
            return 1;
        }
        for (int k = 0; k < nplanes; k++)
            orr_plane_free(&planes[k]);
    }
    return 0;
}
