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
#include "source/source.h"

typedef struct loaded {
    size_t n;
    float *x, *y, *z, *mass, *h;
} loaded;

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

/* Every particle of the file, h converted to orrery's convention (support
 * 2h) from the file's (its support radius in units of its h). */
static void load(const char *path, loaded *p)
{
    orr_error err = {0};
    const char *none[1] = {NULL};
    orr_source_options opt = {.format = "auto", .chunk_size = 1 << 20, .fields = none, .nfields = 0};
    orr_source *src = NULL;
    if (orr_source_open_file(path, &opt, &src, &err) != ORR_OK)
        fail(err.msg, NULL);
    if (src->info.count <= 0)
        fail(path, "the particle count is not in the header");
    if (!src->info.has_h)
        fail(path, "no smoothing lengths");
    size_t n = (size_t)src->info.count;
    double to_half_support = (src->info.h_support > 0 ? src->info.h_support : 2.0) / 2.0;
    *p = (loaded){n, malloc(n * sizeof *p->x), malloc(n * sizeof *p->y), malloc(n * sizeof *p->z),
                  malloc(n * sizeof *p->mass), malloc(n * sizeof *p->h)};
    if (!p->x || !p->y || !p->z || !p->mass || !p->h)
        fail(path, "out of memory");
    size_t filled = 0;
    for (;;) {
        const orr_chunk *c;
        if (orr_source_next(src, &c, &err) != ORR_OK)
            fail(err.msg, NULL);
        if (c->n == 0)
            break;
        if (c->n > n - filled)
            fail(path, "more particles than the header says");
        memcpy(p->x + filled, c->x, c->n * sizeof *c->x);
        memcpy(p->y + filled, c->y, c->n * sizeof *c->y);
        memcpy(p->z + filled, c->z, c->n * sizeof *c->z);
        memcpy(p->mass + filled, c->mass, c->n * sizeof *c->mass);
        for (size_t i = 0; i < c->n; i++)
            p->h[filled + i] = (float)(c->h[i] * to_half_support);
        filled += c->n;
    }
    orr_source_close(src);
    if (filled != n)
        fail(path, "fewer particles than the header says");
}

int main(int argc, char **argv)
{
    int repeats = argc > 3 ? atoi(argv[3]) : 3;
    if (argc < 3 || argc > 4 || repeats < 1) {
        fputs("usage: bench_inmemory SNAPSHOT SCENE.yaml [REPEATS]\n", stderr);
        return 2;
    }
    char *yaml = read_text(argv[2]);
    loaded p;
    load(argv[1], &p);
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
    free(p.x), free(p.y), free(p.z), free(p.mass), free(p.h);
    return 0;
}
