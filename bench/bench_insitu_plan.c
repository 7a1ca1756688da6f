/* What planning costs an in-situ run: the built-in model (mw-m31) handed
 * over as arrays, a scene opened once (orrery_open) and FRAMES frames
 * rendered from it (orrery_render), as a simulation calling orrery every
 * step does. For each scene, side by side in one run: the seconds
 * orrery_open took (loading the scene; with the renderer's plan, also
 * planning it: projections, kernels, the Hubble PSF, the FFT plans, the sky
 * maps' index), the first frame, and the later frames' median and mean.
 * Before the plan (commit ab22b06) every frame planned its views again,
 * with process-wide caches for the Hubble PSF and the FFT plans; build this
 * file against that commit to compare (docs/architecture.md).
 *
 *   bench_insitu_plan [FRAMES [PARTICLES]]     default: 100 frames, 100000 particles
 *
 * The scenes write no files (output.fits and output.png false): the time
 * is the frame's gather, splat, reduction and post-processing. The
 * particles do not move between frames (the plan does not look at them;
 * the observer frame is still found among them every frame). Threads:
 * OMP_NUM_THREADS. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "orrery.h"
#include "source/models/model.h"

typedef struct model_arrays {
    size_t n;
    float *x, *y, *z, *mass;
    uint64_t *id;
    uint8_t *type;
} model_arrays;

/* The scenes timed: the Future Sky observer's dome and panorama (the
 * observer frame rebuilt every frame; every star drawn as the PSF's core,
 * from the sky maps' index and core stamps), and a flat view convolved
 * with the Hubble PSF (its kernel and FFT plans). */
static const char *const scene_names[] = {"future sky: dome 512 + panorama 512x256, psf cores",
                                          "flat 1024x768, hst convolution"};
static const char *const scene_yaml[] = {
    "input: {types: [2, 3]}\n"
    "observer: {id: 3, reference_id: 1, normal: [0, 0, 1], dim: true, dim_near: 0.1}\n"
    "deposit: cic\n"
    "psf: {kind: gaussian}\n"
    "output: {dir: /tmp/bench_insitu_plan, name: sky, fits: false, png: false}\n"
    "views:\n"
    "  dome:\n"
    "    camera: {projection: dome, zenith: [90, 0], front: [0, 0]}\n"
    "    image: {width: 512, height: 512}\n"
    "  panorama:\n"
    "    camera: {projection: hammer-aitoff}\n"
    "    image: {width: 512, height: 256}\n",
    "input: {types: [2, 3]}\n"
    "camera: {projection: orthographic, width: 200}\n"
    "image: {width: 1024, height: 768}\n"
    "deposit: cic\n"
    "psf: {kind: hst}\n"
    "output: {dir: /tmp/bench_insitu_plan, name: flat, fits: false, png: false}\n",
};

static void die(const char *what, const char *detail)
{
    fprintf(stderr, "bench_insitu_plan: %s: %s\n", what, detail);
    exit(1);
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void *take(size_t n, size_t size)
{
    void *p = malloc(n * size);
    if (!p)
        die("arrays", "out of memory");
    return p;
}

static void load_model(long long n, model_arrays *m)
{
    orr_model_params p = {n, 1, 780.0, ORR_MODEL_PAIR, 0, 0, 0, 0};
    orr_source *src = NULL;
    orr_error err = {0};
    if (orr_model_source_open(&p, 1 << 16, &src, &err) != ORR_OK)
        die("model", err.msg);
    size_t cap = (size_t)n + 16, k = 0;
    m->x = take(cap, sizeof *m->x), m->y = take(cap, sizeof *m->y), m->z = take(cap, sizeof *m->z);
    m->mass = take(cap, sizeof *m->mass), m->id = take(cap, sizeof *m->id), m->type = take(cap, 1);
    const orr_chunk *c;
    while (orr_source_next(src, &c, &err) == ORR_OK && c->n > 0)
        for (size_t i = 0; i < c->n && k < cap; i++, k++) {
            m->x[k] = c->x[i], m->y[k] = c->y[i], m->z[k] = c->z[i], m->mass[k] = c->mass[i];
            m->id[k] = c->id[i], m->type[k] = c->type[i];
        }
    orr_source_close(src);
    m->n = k;
}

static int by_value(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Opens the scene, renders the frames; prints one line. */
static void run_scene(const char *name, const char *yaml, const orr_particle_arrays *a, long frames)
{
    orrery_renderer *r;
    char msg[1024];
    double t0 = now();
    if (orrery_open_yaml(&r, yaml, ".", NULL, 0, msg, sizeof msg) != ORRERY_OK)
        die(name, msg);
    double open = now() - t0;
    double *t = take((size_t)frames, sizeof *t);
    for (long f = 0; f < frames; f++) {
        double s = now();
        if (orrery_render(r, a, f) != ORRERY_OK)
            die(name, orrery_error(r));
        t[f] = now() - s;
    }
    orrery_close(r);
    double first = t[0], sum = 0;
    for (long f = 1; f < frames; f++)
        sum += t[f];
    long later = frames - 1;
    qsort(t + 1, (size_t)later, sizeof *t, by_value);
    printf("%-52s open %.3f s | frame 0 %.3f s | frames 1-%ld: median %.4f s, mean %.4f s | total %.2f s\n", name,
           open, first, frames - 1, later ? t[1 + later / 2] : 0.0, later ? sum / (double)later : 0.0,
           open + first + sum);
    free(t);
}

int main(int argc, char **argv)
{
    long frames = argc > 1 ? atol(argv[1]) : 100;
    long long particles = argc > 2 ? atoll(argv[2]) : 100000;
    if (argc > 3 || frames < 2 || particles < 10) {
        fputs("usage: bench_insitu_plan [FRAMES >= 2 [PARTICLES]]\n", stderr);
        return 2;
    }
    model_arrays m;
    load_model(particles, &m);
    orr_particle_arrays a = {.n = m.n,
                             .x = {m.x, ORR_F32, 0},
                             .y = {m.y, ORR_F32, 0},
                             .z = {m.z, ORR_F32, 0},
                             .mass = {m.mass, ORR_F32, 0},
                             .id = m.id,
                             .type = m.type};
    printf("%zu particles of the mw-m31 model, %ld frames in-situ (orrery_open once, orrery_render each frame)\n",
           m.n, frames);
    for (size_t k = 0; k < sizeof scene_yaml / sizeof scene_yaml[0]; k++)
        run_scene(scene_names[k], scene_yaml[k], &a, frames);
    free(m.x), free(m.y), free(m.z), free(m.mass), free(m.id), free(m.type);
    return 0;
}
