/* The built-in mw-m31 model's generation speed (docs/performance.md,
 * "Generating the model"): N particles drawn through the public source API
 * (orr_model_source_open, chunks of C) for the pair and for the Milky Way
 * alone, on 1 thread and on all of them, and beside each the exact
 * per-particle recipe the tables stand in for (orr_model_source_open_exact)
 * in the same run.
 *
 *   bench_model [--particles N] [--reference R] [--chunk C] [--seed S] [--components M]
 *
 * defaults: N = 1e7, R = N / 10 particles for the slow exact recipe (0 skips
 * it), C = 2^20 (the scenes' input.chunk), seed 42. Prints wall and CPU
 * seconds of each run and particles per second of each: per wall second and
 * per CPU second (on a shared machine the CPU seconds say what the work
 * cost). A checksum of the positions and velocities shows that the runs of one recipe on 1
 * and on all threads gave the same particles. --components M adds the CPU
 * nanoseconds a Milky Way disc, bulge and halo particle costs, M of each
 * drawn as the model draws them (orr_model_galaxy_sample_batch: batches of
 * the tabulated recipe) and M / 10 by the exact one-particle samplers. */
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "clocks.h"
#include "source/models/model.h"
#include "source/models/model_galaxy.h"

typedef struct options {
    long long particles, reference, components;
    size_t chunk;
    unsigned long long seed;
} options;

static void parse(int argc, char **argv, options *o)
{
    *o = (options){10000000, -1, 0, (size_t)1 << 20, 42};
    for (int i = 1; i < argc; i += 2) {
        if (i + 1 >= argc) {
            fprintf(stderr, "bench_model: %s needs a value\n", argv[i]);
            exit(2);
        } else if (strcmp(argv[i], "--particles") == 0)
            o->particles = atoll(argv[i + 1]);
        else if (strcmp(argv[i], "--reference") == 0)
            o->reference = atoll(argv[i + 1]);
        else if (strcmp(argv[i], "--components") == 0)
            o->components = atoll(argv[i + 1]);
        else if (strcmp(argv[i], "--chunk") == 0)
            o->chunk = (size_t)atoll(argv[i + 1]);
        else if (strcmp(argv[i], "--seed") == 0)
            o->seed = strtoull(argv[i + 1], NULL, 10);
        else {
            fprintf(stderr, "usage: bench_model [--particles N] [--reference R] [--chunk C] [--seed S] "
                            "[--components M]\n");
            exit(2);
        }
    }
    if (o->components < 0)
        o->components = 0;
    if (o->reference < 0)
        o->reference = o->particles / 10;
}

typedef orr_status (*open_fn)(const orr_model_params *, long long, size_t, orr_source **, orr_error *);

typedef struct timing {
    double wall, cpu;           /* the whole run */
    double open_wall, open_cpu; /* of which opening (the tables built) */
    unsigned long long checksum; /* of the positions' and velocities' bits, to see that thread counts agree */
} timing;

static unsigned long long checksum_chunk(const orr_chunk *c, unsigned long long sum)
{
    for (size_t k = 0; k < c->n; k++) {
        const float f[6] = {c->x[k], c->y[k], c->z[k], c->extra[0].data[k], c->extra[1].data[k], c->extra[2].data[k]};
        for (int i = 0; i < 6; i++) {
            unsigned int b;
            memcpy(&b, &f[i], sizeof b);
            sum = sum * 1099511628211ULL + b;
        }
    }
    return sum;
}

/* Opens the model, reads every chunk, closes it: what a frame's source
 * stage costs (the opening, with its tables, included). */
static timing run(open_fn open, const orr_model_params *params, size_t chunk, int threads)
{
    omp_set_num_threads(threads);
    orr_error err = {0};
    orr_source *src;
    timing t = {0};
    double w0 = wall_seconds(), c0 = cpu_seconds();
    if (open(params, 0, chunk, &src, &err) != ORR_OK) {
        fprintf(stderr, "bench_model: %s\n", err.msg);
        exit(1);
    }
    t.open_wall = wall_seconds() - w0;
    t.open_cpu = cpu_seconds() - c0;
    for (;;) {
        const orr_chunk *c;
        if (orr_source_next(src, &c, &err) != ORR_OK) {
            fprintf(stderr, "bench_model: %s\n", err.msg);
            exit(1);
        }
        if (c->n == 0)
            break;
        t.checksum = checksum_chunk(c, t.checksum);
    }
    orr_source_close(src);
    t.wall = wall_seconds() - w0;
    t.cpu = cpu_seconds() - c0;
    return t;
}

static void report(const char *model, const char *recipe, int threads, long long n, timing t)
{
    printf("%-4s %-9s %d thr N=%-9lld wall %6.3f s cpu %6.3f s (open %5.3f, %5.3f) %8.3g part/s %8.3g part/cpu-s sum %016llx\n",
           model, recipe, threads, n, t.wall, t.cpu, t.open_wall, t.open_cpu, n / t.wall, n / t.cpu, t.checksum);
    fflush(stdout);
}

static void bench_recipe(const char *model, const char *recipe, open_fn open, orr_model_params params, size_t chunk)
{
    int all = omp_get_num_procs();
    timing one = run(open, &params, chunk, 1);
    report(model, recipe, 1, params.particles, one);
    if (all > 1) {
        timing many = run(open, &params, chunk, all);
        report(model, recipe, all, params.particles, many);
        if (many.checksum != one.checksum)
            printf("  ** %s %s: %d threads gave other particles than 1 **\n", model, recipe, all);
    }
}

/* CPU nanoseconds a particle of each component of the Milky Way, drawn
 * by the samplers themselves (one thread, no chunk): where the time goes. */
static volatile double sink;

/* m particles of component comp drawn as the model draws them, in
 * batches (orr_model_galaxy_sample_batch), seed 42; the sum of their vx. */
static double batches(const galaxy *g, int comp, long long m)
{
    float col[9][ORR_MODEL_BATCH];
    particle_rows rows = {col[0], col[1], col[2], col[3], col[4], col[5], col[6], col[7], col[8]};
    uint64_t key = orr_rng_seed_key(42);
    double sum = 0.0;
    for (long long i = 0; i < m; i += ORR_MODEL_BATCH) {
        int n = m - i < ORR_MODEL_BATCH ? (int)(m - i) : ORR_MODEL_BATCH;
        orr_model_galaxy_sample_batch(g, comp, key, (uint64_t)i, n, &rows);
        for (int k = 0; k < n; k++)
            sum += col[3][k];
    }
    return sum;
}

static void bench_components(long long n)
{
    galaxy *g = calloc(1, sizeof *g);
    orr_model_galaxy_init(g, &orr_model_galaxy_specs[0], ORR_MODEL_DISC_Q_DEFAULT);
    orr_model_galaxy_build_potential(g);
    if (!orr_model_galaxy_build_dfs(g))
        exit(1);
    orr_model_galaxy_build_disc_table(g);
    g->e1 = (orr_vec3){1, 0, 0};
    g->e2 = (orr_vec3){0, 1, 0};
    g->spin = (orr_vec3){0, 0, 1};
    static const char *const NAMES[COMP_COUNT] = {"disc", "bulge", "halo"};
    for (int comp = 0; comp < COMP_COUNT; comp++) {
        double ns[2];
        for (int fast = 0; fast < 2; fast++) {
            long long m = fast ? n : n / 10;
            double sum = 0.0, c0 = cpu_seconds();
            if (fast)
                sum = batches(g, comp, m);
            for (long long i = 0; i < m && !fast; i++) {
                orr_rng r = orr_rng_seed(42, (uint64_t)i, 0);
                particle p;
                if (comp == COMP_DISC)
                    orr_model_galaxy_sample_disc(g, &r, &p);
                else
                    orr_model_galaxy_sample_sphere(g, comp, &r, &p);
                sum += p.vel.x;
            }
            ns[fast] = 1e9 * (cpu_seconds() - c0) / (double)m;
            sink = sum; /* the samples are used */
        }
        printf("mw %-5s exact %6.0f ns, tabulated %6.0f ns a particle (CPU)\n", NAMES[comp], ns[0], ns[1]);
    }
    free(g);
}

int main(int argc, char **argv)
{
    options o;
    parse(argc, argv, &o);
    static const struct {
        const char *name;
        int galaxies;
    } MODELS[] = {{"pair", ORR_MODEL_PAIR}, {"mw", ORR_MODEL_MW}};
    printf("bench_model: chunk %zu, seed %llu, %d processors; wall and cpu seconds of each run, of which "
           "opening (wall, cpu); particles per wall and per CPU second\n",
           o.chunk, o.seed, omp_get_num_procs());
    /* a small run first: the libraries' lazy symbol binding is not timed */
    orr_model_params warm = {1000, o.seed, 780.0, ORR_MODEL_PAIR, 0.0, 0, 0, 0};
    run(orr_model_source_open_dust, &warm, o.chunk, 1);
    for (int k = 0; k < 2; k++) {
        orr_model_params params = {o.particles, o.seed, 780.0, MODELS[k].galaxies, 0.0, 0, 0, 0};
        bench_recipe(MODELS[k].name, "tabulated", orr_model_source_open_dust, params, o.chunk);
        if (o.reference >= 100) {
            params.particles = o.reference;
            bench_recipe(MODELS[k].name, "exact", orr_model_source_open_exact, params, o.chunk);
        }
    }
    if (o.components > 0)
        bench_components(o.components);
    return 0;
}
