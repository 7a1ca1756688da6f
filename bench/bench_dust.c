/* Dust's cost (docs/dust.md#cost): the Future Sky frame (configs/futuresky.yaml,
 * both views, one pass) rendered with and without its dusty gas discs in
 * the same run, and the optical-depth walk alone.
 *
 *   bench_dust [--particles N] [--dust D] [--size S] [--config FILE] [--walk-only] [--single]
 *
 * defaults: N = 2e6 model particles, D = 1e5 gas particles, the dome S x S
 * and the panorama 2S x S with S = 1024 (the config's own sizes are 3600 and
 * 4096 x 2048: pass --size 0 to keep them). Prints wall and CPU seconds of
 * each frame (on a shared machine CPU seconds say what the work cost) and
 * their ratio, then the walk's microseconds per star: the stars of each
 * chunk grouped by direction, as the renderer does (orr_dust_tau_many),
 * with the terms one at a time, eight stars at a time with AVX2 and the
 * best way this CPU runs (AVX-512 where it has it) side by side on the
 * same chunks (it fails if their bits differ), or with
 * --single each star on its own walk (orr_dust_tau). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "clocks.h"
#include "dust/column_lanes.h"
#include "dust/dust.h"
#include "render/render.h"
#include "scene/scene.h"
#include "source/models/model.h"

typedef struct options {
    long long particles, dust;
    int size, walk_only, single;
    const char *config;
} options;

static void parse(int argc, char **argv, options *o)
{
    *o = (options){2000000, 100000, 1024, 0, 0, "configs/futuresky.yaml"};
    for (int i = 1; i < argc; i += 2) {
        if (strcmp(argv[i], "--walk-only") == 0 || strcmp(argv[i], "--single") == 0) {
            *(argv[i][2] == 'w' ? &o->walk_only : &o->single) = 1;
            i--;
        } else if (i + 1 >= argc) {
            fprintf(stderr, "bench_dust: %s needs a value\n", argv[i]);
            exit(2);
        } else if (strcmp(argv[i], "--particles") == 0)
            o->particles = atoll(argv[i + 1]);
        else if (strcmp(argv[i], "--dust") == 0)
            o->dust = atoll(argv[i + 1]);
        else if (strcmp(argv[i], "--size") == 0)
            o->size = atoi(argv[i + 1]);
        else if (strcmp(argv[i], "--config") == 0)
            o->config = argv[i + 1];
        else {
            fprintf(stderr, "usage: bench_dust [--particles N] [--dust D] [--size S] [--config FILE] [--walk-only] "
                            "[--single]\n");
            exit(2);
        }
    }
}

static void die(const orr_error *err)
{
    fprintf(stderr, "bench_dust: %s\n", err->msg);
    exit(1);
}

/* One frame of every view; dust off by clearing dust.types. */
static void frame(const options *o, int with_dust, double *wall, double *cpu)
{
    static char ov[6][128];
    const char *overrides[6];
    int n = 0;
    snprintf(ov[n++], sizeof ov[0], "input.model.particles=%lld", o->particles);
    snprintf(ov[n++], sizeof ov[0], "input.model.dust_particles=%lld", o->dust);
    snprintf(ov[n++], sizeof ov[0], "output.dir=%s", with_dust ? "bench_dust_out/dust" : "bench_dust_out/clear");
    if (o->size > 0) {
        snprintf(ov[n++], sizeof ov[0], "views.dome.image.width=%d", o->size);
        snprintf(ov[n++], sizeof ov[0], "views.dome.image.height=%d", o->size);
    }
    for (int i = 0; i < n; i++)
        overrides[i] = ov[i];
    orr_scene_views *v = malloc(sizeof *v);
    orr_error err = {0};
    if (!v || orr_scene_load_views(v, o->config, overrides, n, &err))
        die(&err);
    const orr_scene *views[ORR_SCENE_MAX_VIEWS];
    for (int k = 0; k < v->n; k++) {
        if (!with_dust)
            v->view[k].dust.types = 0;
        if (o->size > 0 && v->view[k].projection.width != o->size) { /* the panorama: 2S x S */
            v->view[k].projection.width = 2 * o->size;
            v->view[k].projection.height = o->size;
        }
        views[k] = &v->view[k];
    }
    orr_render_report rep[ORR_SCENE_MAX_VIEWS];
    double w0 = wall_seconds(), c0 = cpu_seconds();
    if (orr_render_views(views, v->n, rep, NULL, NULL, &err))
        die(&err);
    *wall = wall_seconds() - w0;
    *cpu = cpu_seconds() - c0;
    orr_scene_views_free(v);
    free(v);
}

/* The walk alone: every star of the model's discs and bulges from the Sun. */
static void walk(const options *o)
{
    orr_model_params mp = {o->particles, 1, 780.0, ORR_MODEL_PAIR, 0, 0, 0, 0};
    orr_source *src;
    orr_error err = {0};
    if (orr_model_source_open_dust(&mp, o->dust, 1 << 20, &src, &err))
        die(&err);
    orr_dust_settings d;
    orr_dust_settings_defaults(&d);
    d.types = 1u;
    d.kappa_v = 3.7e4;
    orr_dust_context ctx = {"bench", ORR_KERNEL_CUBIC, 32, 1.0, 1, 1u << 2 | 1u << 3};
    orr_dust_frame f;
    double w0 = wall_seconds(), c0 = cpu_seconds();
    if (orr_dust_frame_prepare(&f, &d, &ctx, src, &err))
        die(&err);
    double prep_w = wall_seconds() - w0, prep_c = cpu_seconds() - c0;
    const double sun[3] = {-8.0, 0.0, 0.02};
    /* grouped: the terms one at a time, eight stars at a time with AVX2
     * and the best way side by side on the same chunks (the best last, as
     * the renderer runs it), their bits compared */
    const orr_dust_terms widths[3] = {ORR_DUST_TERMS_PLAIN, ORR_DUST_TERMS_EIGHT_AVX2, ORR_DUST_TERMS_BEST};
    const char *width_names[3] = {"one term at a time", "eight stars at a time (AVX2)",
                                  orr_dust_star_lanes_best() == ORR_DUST_LANES_AVX512
                                      ? "eight stars at a time (AVX-512)"
                                      : "the best way (no AVX-512: AVX2)"};
    const int nwidths = o->single ? 1 : 3;
    long n = 0, differ = 0;
    double walk_c[3] = {0}, walk_w[3] = {0}, sum = 0; /* the sum in the stars' order: the same on any thread count */
    const orr_chunk *c;
    unsigned char *want = NULL;
    double *tau = NULL, *first = NULL;
    while (!orr_source_next(src, &c, &err) && c->n > 0) {
        if (!(want = realloc(want, c->n)) || !(tau = realloc(tau, c->n * sizeof *tau)) ||
            !(first = realloc(first, c->n * sizeof *first)))
            exit(1);
        for (size_t i = 0; i < c->n; i++) {
            want[i] = c->type[i] == 2 || c->type[i] == 3;
            n += want[i];
        }
        for (int w = 0; w < nwidths; w++) {
            double a = wall_seconds(), b = cpu_seconds();
            if (o->single) {
#pragma omp parallel for schedule(dynamic, 1024)
                for (long i = 0; i < (long)c->n; i++) {
                    const double p[3] = {c->x[i], c->y[i], c->z[i]};
                    tau[i] = want[i] ? orr_dust_tau(&f.set, sun, p) : 0;
                }
            } else if (orr_dust_tau_many_with(widths[w], &f.set, sun, c->n, c->x, c->y, c->z, want, tau, &err)) {
                die(&err);
            }
            walk_w[w] += wall_seconds() - a;
            walk_c[w] += cpu_seconds() - b;
            if (w == 0)
                memcpy(first, tau, c->n * sizeof *tau);
            else
                differ += memcmp(first, tau, c->n * sizeof *tau) != 0;
        }
        for (size_t i = 0; i < c->n; i++)
            sum += tau[i];
    }
    free(want);
    free(tau);
    free(first);
    printf("walk: %zu dust kernels, read + lengths + tree + tables %.2f s wall %.2f s CPU; %ld stars, mean A_V %.2f "
           "mag\n",
           f.set.n, prep_w, prep_c, n, 1.0857 * sum / (double)n);
    for (int w = 0; w < nwidths; w++)
        printf("  %-36s %8.2f s wall %8.2f s CPU: %.3f us CPU per star\n",
               o->single ? "each star on its own walk" : width_names[w], walk_w[w], walk_c[w],
               1e6 * walk_c[w] / (double)n);
    if (differ) {
        fprintf(stderr, "bench_dust: the widths' optical depths differ in %ld chunks\n", differ);
        exit(1);
    }
    orr_dust_frame_free(&f);
    orr_source_close(src);
}

int main(int argc, char **argv)
{
    options o;
    parse(argc, argv, &o);
    printf("Future Sky (%s): %lld model particles, %lld dust particles, dome %s\n", o.config, o.particles, o.dust,
           o.size > 0 ? "S x S, panorama 2S x S" : "and panorama at the config's sizes");
    double w0, c0, w1, c1;
    if (o.walk_only) {
        walk(&o);
        return 0;
    }
    frame(&o, 0, &w0, &c0);
    frame(&o, 1, &w1, &c1);
    printf("frame without dust: %8.2f s wall %8.2f s CPU\n", w0, c0);
    printf("frame with dust:    %8.2f s wall %8.2f s CPU   ratio %.2f (CPU)\n", w1, c1, c1 / c0);
    walk(&o);
    return 0;
}
