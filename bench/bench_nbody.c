/* Gravity for the example N-body code: today's monopole Barnes-Hut tree
 * (examples/nbody/tree.c, one walk per particle) side by side with the
 * quadrupole group tree that replaced it (examples/nbody/qtree.c), on the
 * built-in model, in one run.
 *
 *   bench_nbody [N [CHECK [mw|pair [THETA]]]]
 *       default: 100000 particles, 2000 checked, the Milky Way alone
 *       ("pair": both galaxies), the new tree's default opening angle 0.7
 *
 * For each tree: seconds to build and to compute every particle's
 * acceleration once (wall clock; CPU seconds too, the machine may be
 * shared), particle-steps per second (N over build + forces), interactions
 * per particle, and the median and 99th-percentile relative error of the
 * acceleration against direct summation over all N for CHECK particles
 * spread evenly through the ids (every component), each tree against its
 * own softening rule. Threads: OMP_NUM_THREADS. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "clocks.h"
#include "qtree.h"
#include "source/models/model.h"
#include "tree.h"

#define G_KPC_KMS 43007.1
#define OLD_THETA 0.6 /* orrery-nbody's default before the quadrupole tree */
#define OLD_EPS 0.2
#define NEW_THETA 0.7 /* orrery-nbody's default (docs/nbody.md) */
#define NEW_EPS_STAR 0.05
#define NEW_EPS_HALO 0.1 /* orrery-nbody's defaults */

typedef struct result {
    double build, force, cpu, interactions, median, p99;
} result;

static void die(const char *msg)
{
    fprintf(stderr, "bench_nbody: %s\n", msg);
    exit(1);
}

static void load(long long n, int pair, double *pos, double *mass, unsigned char *type)
{
    orr_model_params p = {n, 1, 780.0, pair ? ORR_MODEL_PAIR : ORR_MODEL_MW, 0, 0, 0};
    orr_source *src = NULL;
    orr_error err = {0};
    if (orr_model_source_open(&p, 1 << 16, &src, &err) != ORR_OK)
        die(err.msg);
    size_t k = 0;
    const orr_chunk *c;
    while (orr_source_next(src, &c, &err) == ORR_OK && c->n > 0)
        for (size_t i = 0; i < c->n; i++, k++) {
            pos[3 * k] = c->x[i];
            pos[3 * k + 1] = c->y[i];
            pos[3 * k + 2] = c->z[i];
            mass[k] = c->mass[i];
            type[k] = c->type[i];
        }
    orr_source_close(src);
}

static int compare(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Errors of acc (all N) against direct summation for every stride-th particle. */
static void errors(const double *pos, const double *mass, const double *eps, size_t n, size_t check,
                   const double *acc, result *r)
{
    double *err = malloc(check * sizeof *err);
    size_t stride = n / check;
#pragma omp parallel for schedule(dynamic, 8)
    for (size_t c = 0; c < check; c++) {
        size_t i = c * stride;
        double ref[3];
        qt_direct(pos, mass, eps, n, G_KPC_KMS, i, 1, ref, NULL);
        double d2 = 0, a2 = 0;
        for (int k = 0; k < 3; k++) {
            d2 += (acc[3 * i + k] - ref[k]) * (acc[3 * i + k] - ref[k]);
            a2 += ref[k] * ref[k];
        }
        err[c] = sqrt(d2 / a2);
    }
    qsort(err, check, sizeof *err, compare);
    r->median = err[check / 2];
    r->p99 = err[(size_t)(0.99 * (double)(check - 1))];
    free(err);
}

static void run_old(const double *pos, const double *mass, size_t n, double *acc, result *r)
{
    bh_tree t = {0};
    double c0 = cpu_seconds(), t0 = wall_seconds();
    if (bh_build(&t, pos, mass, n) != 0)
        die("out of memory (old tree)");
    double t1 = wall_seconds();
    r->interactions = bh_accelerations(&t, pos, mass, G_KPC_KMS, OLD_EPS, OLD_THETA, acc) / (double)n;
    r->force = wall_seconds() - t1;
    r->build = t1 - t0;
    r->cpu = cpu_seconds() - c0;
    bh_free(&t);
}

static void run_new(const double *pos, const double *mass, const double *eps, size_t n, double theta, double *acc,
                    result *r)
{
    qt_tree t = {0};
    double c0 = cpu_seconds(), t0 = wall_seconds();
    if (qt_build(&t, pos, mass, eps, n) != 0)
        die("out of memory (new tree)");
    double t1 = wall_seconds();
    r->interactions = qt_accelerations_of(&t, G_KPC_KMS, theta, 0, n, acc, NULL) / (double)n;
    r->force = wall_seconds() - t1;
    r->build = t1 - t0;
    r->cpu = cpu_seconds() - c0;
    qt_free(&t);
}

int main(int argc, char **argv)
{
    long long n = argc > 1 ? atoll(argv[1]) : 100000;
    long long check = argc > 2 ? atoll(argv[2]) : 2000;
    int pair = argc > 3 && strcmp(argv[3], "pair") == 0;
    double theta = argc > 4 ? atof(argv[4]) : NEW_THETA;
    if (n < 1000 || check < 10 || check > n || !(theta > 0 && theta <= 1))
        die("usage: bench_nbody [N >= 1000 [CHECK, 10 to N [mw|pair [THETA, 0 to 1]]]]");
    double *pos = malloc(3 * (size_t)n * sizeof *pos), *mass = malloc((size_t)n * sizeof *mass);
    double *eps_old = malloc((size_t)n * sizeof *eps_old), *eps_new = malloc((size_t)n * sizeof *eps_new);
    double *acc = malloc(3 * (size_t)n * sizeof *acc);
    unsigned char *type = malloc((size_t)n);
    if (!pos || !mass || !eps_old || !eps_new || !acc || !type)
        die("out of memory");
    load(n, pair, pos, mass, type);
    for (long long i = 0; i < n; i++) {
        eps_old[i] = OLD_EPS;
        eps_new[i] = type[i] == ORR_MODEL_TYPE_HALO ? NEW_EPS_HALO : NEW_EPS_STAR;
    }
    result old, neu;
    run_old(pos, mass, (size_t)n, acc, &old);
    errors(pos, mass, eps_old, (size_t)n, (size_t)check, acc, &old);
    run_new(pos, mass, eps_new, (size_t)n, theta, acc, &neu);
    errors(pos, mass, eps_new, (size_t)n, (size_t)check, acc, &neu);

    printf("bench_nbody: N = %lld (%s), %d threads; errors against direct summation over all N for %lld "
           "particles\n",
           n, pair ? "Milky Way and M31" : "Milky Way alone", omp_get_max_threads(), check);
    printf("%-28s %22s %22s\n", "", "old: monopole", "new: quadrupole groups");
    char new_set[64];
    snprintf(new_set, sizeof new_set, "%.2g, %.2g / %.2g kpc", theta, NEW_EPS_STAR, NEW_EPS_HALO);
    printf("%-28s %22s %22s\n", "opening angle, softening", "0.6, 0.2 kpc", new_set);
    printf("%-28s %22.3f %22.3f\n", "build (s)", old.build, neu.build);
    printf("%-28s %22.3f %22.3f\n", "forces (s)", old.force, neu.force);
    printf("%-28s %22.3f %22.3f\n", "CPU (s)", old.cpu, neu.cpu);
    printf("%-28s %22.3g %22.3g\n", "particle-steps per second", n / (old.build + old.force),
           n / (neu.build + neu.force));
    printf("%-28s %22.0f %22.0f\n", "interactions per particle", old.interactions, neu.interactions);
    printf("%-28s %22.2e %22.2e\n", "median relative error", old.median, neu.median);
    printf("%-28s %22.2e %22.2e\n", "99th percentile rel. error", old.p99, neu.p99);
    printf("speed-up %.1fx\n", (old.build + old.force) / (neu.build + neu.force));
    free(pos);
    free(mass);
    free(eps_old);
    free(eps_new);
    free(acc);
    free(type);
    return 0;
}
