/* orrery's splat alone on a snapshot's particles: the file is read once
 * into memory, then the scene is rendered from the arrays (the in-situ
 * source) and only the frame's splat is timed, so that reading the file is
 * not in the figure. bench/bench_scale.sh uses it for the rendering rates
 * (nearest-pixel binning at 1e7 particles splats in tens of milliseconds,
 * less than the noise of timing whole runs on a shared machine).
 *
 *   bench_inmemory SNAPSHOT SCENE.yaml [REPEATS]      default: 3 repeats
 *
 * SCENE.yaml: a scene with input: {insitu: true} (its outputs go to /tmp;
 * set output.fits: false to write nothing). Threads: OMP_NUM_THREADS.
 * Prints one line: "splat N particles: best W s wall, C s CPU, R particles/s"
 * (the best repeat's wall seconds, the CPU seconds of that repeat). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "frame_timer.h"
#include "snapshot_load.h"
#include "source/source.h"

static void fail(const char *what, const char *detail)
{
    fprintf(stderr, "bench_inmemory: %s%s%s\n", what, detail ? ": " : "", detail ? detail : "");
    exit(1);
}

static char *read_text(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        fail(path, "cannot open");
    char *text = NULL;
    size_t len = 0, cap = 0, got;
    do {
        if (len + 4096 + 1 > cap) {
            cap = 2 * cap + 8192;
            char *grown = realloc(text, cap);
            if (!grown)
                fail(path, "out of memory");
            text = grown;
        }
        got = fread(text + len, 1, 4096, f);
        len += got;
    } while (got > 0);
    int bad = ferror(f);
    fclose(f);
    if (bad)
        fail(path, "read error");
    text[len] = '\0';
    return text;
}

int main(int argc, char **argv)
{
    int repeats = argc > 3 ? atoi(argv[3]) : 3;
    if (argc < 3 || argc > 4 || repeats < 1) {
        fputs("usage: bench_inmemory SNAPSHOT SCENE.yaml [REPEATS]\n", stderr);
        return 2;
    }
    char *yaml = read_text(argv[2]);
    loaded_snapshot p;
    load_snapshot(argv[1], 1, &p);
    orr_particle_arrays a = {.n = p.n,
                             .x = {p.x, ORR_F32, 0},
                             .y = {p.y, ORR_F32, 0},
                             .z = {p.z, ORR_F32, 0},
                             .mass = {p.mass, ORR_F32, 0},
                             .h = {p.h, ORR_F32, 0}};
    double cpu = 0, wall = frame_timer_best(yaml, &a, repeats, &cpu);
    printf("splat %zu particles: best %.4f s wall, %.4f s CPU, %.4g particles/s\n", p.n, wall, cpu,
           (double)p.n / wall);
    free(yaml);
    free_snapshot(&p);
    return 0;
}
