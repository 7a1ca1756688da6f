/* Gravity for the example N-body code: today's monopole Barnes-Hut tree
 * (examples/nbody/tree.c, one walk per particle) side by side with the
 * quadrupole group tree that replaced it (examples/nbody/qtree.c), on the
 * built-in model, in one run; or (`steps`) the quadrupole tree's walks
 * from the root per group (as of commit f4e2010) side by side with its
 * super-group walks, over a few leapfrog steps.
 *
 *   bench_nbody [N [CHECK [mw|pair [THETA [EPS]]]]]
 *       default: 100000 particles, 2000 checked, the Milky Way alone
 *       ("pair": both galaxies), the new tree's default opening angle 0.7,
 *       its default softening 0.05 kpc for stars (the halo's twice it; the
 *       films use 0.2)
 *
 * For each tree: seconds to build and to compute every particle's
 * acceleration once (wall clock; CPU seconds too, the machine may be
 * shared), particle-steps per second (N over build + forces), interactions
 * per particle, and the median and 99th-percentile relative error of the
 * acceleration against direct summation over all N for CHECK particles
 * spread evenly through the ids (every component), each tree against its
 * own softening rule. Threads: OMP_NUM_THREADS.
 *
 *   bench_nbody steps [N [STEPS [CHECK [THETA [EPS]]]]]
 *       default: 200000 particles of the Milky Way alone, 5 steps, 300
 *       checked, the films' settings (theta 0.7, softening 0.2 / 0.4 kpc,
 *       dt 0.002)
 *
 * For each walk, from the same start: STEPS kick-drift-kick steps, each with
 * a tree built anew and every particle's acceleration and potential (as
 * orrery-nbody does); CPU seconds of the gravity per step, particle-steps
 * per CPU second (the figure per core: run it with OMP_NUM_THREADS=1),
 * interactions per particle, the errors of the first forces against
 * direct summation and the energy error after the steps.
 *
 *   bench_nbody substeps [N [REPEAT [CHECK [ETA [EPS]]]]]
 *       default: 200000 particles of the Milky Way alone, best of 3, 2000
 *       checked, the
 *       films' block steps (eta 0.2, softening 0.2 / 0.4 kpc, dt 0.008,
 *       dt-min 0.002)
 *
 * What a block step's sub-step costs a force against a full step (every
 * particle): from the start, the particles whose wanted step
 * sqrt(2 eta eps / |a|) is under 0.004 (those on steps of 0.002, active at
 * every sub-step) and under 0.008 (active at the step's middle), their
 * forces alone (qt_accelerations_masked, no potentials), by root walks
 * (before issue 42 item 1) and by super-groups (the full step's forces
 * bit for bit); the best CPU seconds of REPEAT runs, a tree build's too,
 * the interactions a force and the 99th percentile of the active
 * particles' errors against direct summation (of CHECK spread through
 * all).
 *
 *   bench_nbody fmm [N [CHECK [REPEAT [FMM_THETA ...]]]]
 *       default: 200000 particles of the pair, 1000 checked, best of 3;
 *       the films' softening (0.2 / 0.4 kpc)
 *
 * Every particle's acceleration by the tree walk (theta 0.7, as the films
 * run it) and by the fast multipole method of fmm.h at each FMM_THETA
 * given, from the same particles, one after the other: CPU seconds (the
 * tree's build included), interactions a particle (FMM: cell-cell pairs
 * and particle pairs, each pair counted once though it acts both ways) and
 * the median and 99th percentile of the errors against direct summation.
 * The FMM is plain scalar code: its seconds are not what a tuned one would
 * take; its counts at the tree's accuracy are what docs/nbody.md weighs
 * ("A fast multipole method, measured"). */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "clocks.h"
#include "fmm.h"
#include "qtree.h"
#include "source/models/model.h"
#include "tree.h"

#define G_KPC_KMS 43007.1
#define OLD_THETA 0.6 /* orrery-nbody's default before the quadrupole tree */
#define OLD_EPS 0.2
#define NEW_THETA 0.7 /* orrery-nbody's default (docs/nbody.md) */
#define NEW_EPS_STAR 0.05 /* orrery-nbody's default; the halo's is twice it */

typedef struct result {
    double build, force, cpu, interactions, median, p99;
} result;

static void die(const char *msg)
{
    fprintf(stderr, "bench_nbody: %s\n", msg);
    exit(1);
}

/* The model's particles; their velocities too when vel is not NULL. */
static void load(long long n, int pair, double *pos, double *vel, double *mass, unsigned char *type)
{
    orr_model_params p = {n, 1, 780.0, pair ? ORR_MODEL_PAIR : ORR_MODEL_MW, 0, 0, 0, 0};
    orr_source *src = NULL;
    orr_error err = {0};
    if (orr_model_source_open(&p, 1 << 16, &src, &err) != ORR_OK)
        die(err.msg);
    size_t k = 0;
    const orr_chunk *c;
    while (orr_source_next(src, &c, &err) == ORR_OK && c->n > 0) {
        const float *v[3] = {orr_chunk_field(c, "vx"), orr_chunk_field(c, "vy"), orr_chunk_field(c, "vz")};
        if (vel && (!v[0] || !v[1] || !v[2]))
            die("the model gave no velocities");
        for (size_t i = 0; i < c->n; i++, k++) {
            pos[3 * k] = c->x[i];
            pos[3 * k + 1] = c->y[i];
            pos[3 * k + 2] = c->z[i];
            for (int a = 0; vel && a < 3; a++)
                vel[3 * k + a] = v[a][i];
            mass[k] = c->mass[i];
            type[k] = c->type[i];
        }
    }
    orr_source_close(src);
}

static int compare(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Direct summation's accelerations of every stride-th particle, into ref
 * (3 a particle checked). */
static void reference(const double *pos, const double *mass, const double *eps, size_t n, size_t check,
                      double *ref)
{
    size_t stride = n / check;
#pragma omp parallel for schedule(dynamic, 8)
    for (size_t c = 0; c < check; c++)
        qt_direct(pos, mass, eps, n, G_KPC_KMS, c * stride, 1, &ref[3 * c], NULL);
}

/* Errors of acc (all N) against ref (reference) for every stride-th
 * particle; ref NULL: computed here. */
static void errors(const double *pos, const double *mass, const double *eps, size_t n, size_t check,
                   const double *ref_given, const double *acc, result *r)
{
    double *err = malloc(check * sizeof *err), *ref = ref_given ? NULL : malloc(3 * check * sizeof *ref);
    if (!err || (!ref_given && !ref))
        die("out of memory");
    if (!ref_given)
        reference(pos, mass, eps, n, check, ref);
    const double *refs = ref_given ? ref_given : ref;
    size_t stride = n / check;
    for (size_t c = 0; c < check; c++) {
        size_t i = c * stride;
        double d2 = 0, a2 = 0;
        const double *rf = &refs[3 * c];
        for (int k = 0; k < 3; k++) {
            d2 += (acc[3 * i + k] - rf[k]) * (acc[3 * i + k] - rf[k]);
            a2 += rf[k] * rf[k];
        }
        err[c] = sqrt(d2 / a2);
    }
    qsort(err, check, sizeof *err, compare);
    r->median = err[check / 2];
    r->p99 = err[(size_t)(0.99 * (double)(check - 1))];
    free(err);
    free(ref);
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

/* ---- steps: the walks of f4e2010 and of now, over leapfrog steps -------- */

#define FILM_DT 0.002

typedef struct stepped {
    double gravity_cpu, interactions, median, p99, de;
} stepped;

/* Builds the tree anew and computes every particle's acceleration and
 * potential; the interactions. */
static double forces(qt_tree *t, const double *pos, const double *mass, const double *eps, size_t n, double theta,
                     double *acc, double *pot)
{
    if (qt_build(t, pos, mass, eps, n) != 0)
        die("out of memory (tree)");
    double inter = qt_accelerations_of(t, G_KPC_KMS, theta, 0, n, acc, pot);
    if (inter < 0)
        die("out of memory (walk)");
    return inter;
}

static double energy(const double *vel, const double *mass, const double *pot, size_t n)
{
    double e = 0;
    for (size_t i = 0; i < n; i++)
        e += mass[i] * (0.5 * (vel[3 * i] * vel[3 * i] + vel[3 * i + 1] * vel[3 * i + 1] +
                               vel[3 * i + 2] * vel[3 * i + 2]) +
                        0.5 * pot[i]);
    return e;
}

/* `steps` kick-drift-kick steps of one walk from pos0, vel0. */
static void run_steps(int root_walks, const double *pos0, const double *vel0, const double *mass, const double *eps,
                      size_t n, long steps, double theta, size_t check, const double *ref, stepped *r)
{
    double *pos = malloc(3 * n * sizeof *pos), *vel = malloc(3 * n * sizeof *vel);
    double *acc = malloc(3 * n * sizeof *acc), *pot = malloc(n * sizeof *pot);
    if (!pos || !vel || !acc || !pot)
        die("out of memory");
    memcpy(pos, pos0, 3 * n * sizeof *pos);
    memcpy(vel, vel0, 3 * n * sizeof *vel);
    qt_tree t = {0};
    t.root_walks = root_walks;
    double c0 = cpu_seconds();
    r->interactions = forces(&t, pos, mass, eps, n, theta, acc, pot);
    r->gravity_cpu = cpu_seconds() - c0;
    result e;
    errors(pos, mass, eps, n, check, ref, acc, &e);
    r->median = e.median;
    r->p99 = e.p99;
    double e0 = energy(vel, mass, pot, n);
    for (long s = 0; s < steps; s++) {
        for (size_t i = 0; i < 3 * n; i++)
            vel[i] += 0.5 * FILM_DT * acc[i];
        for (size_t i = 0; i < 3 * n; i++)
            pos[i] += FILM_DT * vel[i];
        c0 = cpu_seconds();
        r->interactions += forces(&t, pos, mass, eps, n, theta, acc, pot);
        r->gravity_cpu += cpu_seconds() - c0;
        for (size_t i = 0; i < 3 * n; i++)
            vel[i] += 0.5 * FILM_DT * acc[i];
    }
    r->gravity_cpu /= (double)(steps + 1);
    r->interactions /= (double)(steps + 1) * (double)n;
    r->de = (energy(vel, mass, pot, n) - e0) / fabs(e0);
    qt_free(&t);
    free(pos);
    free(vel);
    free(acc);
    free(pot);
}

static int bench_steps(int argc, char **argv)
{
    long long n = argc > 0 ? atoll(argv[0]) : 200000;
    long steps = argc > 1 ? atol(argv[1]) : 5;
    long long check = argc > 2 ? atoll(argv[2]) : 300;
    double theta = argc > 3 ? atof(argv[3]) : NEW_THETA;
    double eps_star = argc > 4 ? atof(argv[4]) : 0.2;
    if (n < 1000 || steps < 0 || check < 10 || check > n || !(theta > 0 && theta <= 1) || !(eps_star > 0))
        die("usage: bench_nbody steps [N >= 1000 [STEPS >= 0 [CHECK, 10 to N [THETA, 0 to 1 [EPS > 0]]]]]");
    size_t nn = (size_t)n;
    double *pos = malloc(3 * nn * sizeof *pos), *vel = malloc(3 * nn * sizeof *vel);
    double *mass = malloc(nn * sizeof *mass), *eps = malloc(nn * sizeof *eps);
    double *ref = malloc(3 * (size_t)check * sizeof *ref);
    unsigned char *type = malloc(nn);
    if (!pos || !vel || !mass || !eps || !ref || !type)
        die("out of memory");
    load(n, 0, pos, vel, mass, type);
    for (size_t i = 0; i < nn; i++)
        eps[i] = type[i] == ORR_MODEL_TYPE_HALO ? 2 * eps_star : eps_star;
    reference(pos, mass, eps, nn, (size_t)check, ref);
    stepped before, now;
    run_steps(1, pos, vel, mass, eps, nn, steps, theta, (size_t)check, ref, &before);
    run_steps(0, pos, vel, mass, eps, nn, steps, theta, (size_t)check, ref, &now);

    printf("bench_nbody steps: N = %lld (Milky Way alone), %ld steps of %g, theta %g, softening %g / %g kpc, %d "
           "threads; errors of the first forces against direct summation over all N for %lld particles\n",
           n, steps, FILM_DT, theta, eps_star, 2 * eps_star, omp_get_max_threads(), check);
    printf("%-34s %20s %20s\n", "", "f4e2010: root walks", "super-group walks");
    printf("%-34s %20.3f %20.3f\n", "gravity CPU s per step", before.gravity_cpu, now.gravity_cpu);
    printf("%-34s %20.3g %20.3g\n", "particle-steps per CPU second", n / before.gravity_cpu, n / now.gravity_cpu);
    printf("%-34s %20.0f %20.0f\n", "interactions per particle", before.interactions, now.interactions);
    printf("%-34s %20.2e %20.2e\n", "median relative error", before.median, now.median);
    printf("%-34s %20.2e %20.2e\n", "99th percentile rel. error", before.p99, now.p99);
    printf("%-34s %20.2e %20.2e\n", "dE/|E0| after the steps", before.de, now.de);
    printf("speed-up %.2fx (CPU)\n", before.gravity_cpu / now.gravity_cpu);
    free(pos);
    free(vel);
    free(mass);
    free(eps);
    free(ref);
    free(type);
    return 0;
}

/* ---- substeps: a block step's forces for its active particles -------- */

/* The best CPU seconds of `repeat` force computations of the particles
 * with active[i] set (NULL: all, with potentials), on tree t, walked by
 * super-groups or (root_walks) by groups from the root. */
static double masked_cpu(qt_tree *t, int root_walks, size_t n, double theta, const unsigned char *active,
                         int repeat, double *acc, double *pot, double *interactions)
{
    double best = INFINITY;
    t->root_walks = root_walks;
    for (int r = 0; r < repeat; r++) {
        double c0 = cpu_seconds();
        double done = qt_accelerations_masked(t, G_KPC_KMS, theta, 0, n, active, acc, active ? NULL : pot);
        if (done < 0)
            die("out of memory (walk)");
        *interactions = done;
        best = fmin(best, cpu_seconds() - c0);
    }
    return best;
}

/* The 99th percentile of the relative errors of acc against ref
 * (reference: every stride-th particle) over the checked particles that
 * are active. */
static double active_p99(const double *acc, const double *ref, size_t n, size_t check, const unsigned char *active)
{
    double *err = malloc(check * sizeof *err);
    if (!err)
        die("out of memory");
    size_t stride = n / check, k = 0;
    for (size_t c = 0; c < check; c++) {
        size_t i = c * stride;
        if (!active[i])
            continue;
        double d2 = 0, a2 = 0;
        for (int a = 0; a < 3; a++) {
            d2 += (acc[3 * i + a] - ref[3 * c + a]) * (acc[3 * i + a] - ref[3 * c + a]);
            a2 += ref[3 * c + a] * ref[3 * c + a];
        }
        err[k++] = sqrt(d2 / a2);
    }
    qsort(err, k, sizeof *err, compare);
    double p = k ? err[(size_t)(0.99 * (double)(k - 1))] : NAN;
    free(err);
    return p;
}

static int bench_substeps(int argc, char **argv)
{
    long long n = argc > 0 ? atoll(argv[0]) : 200000;
    int repeat = argc > 1 ? atoi(argv[1]) : 3;
    long long check = argc > 2 ? atoll(argv[2]) : 2000;
    double eta = argc > 3 ? atof(argv[3]) : 0.2;
    double eps_star = argc > 4 ? atof(argv[4]) : 0.2;
    if (n < 1000 || repeat < 1 || check < 10 || check > n || !(eta > 0) || !(eps_star > 0))
        die("usage: bench_nbody substeps [N >= 1000 [REPEAT >= 1 [CHECK, 10 to N [ETA > 0 [EPS > 0]]]]]");
    size_t nn = (size_t)n;
    double *pos = malloc(3 * nn * sizeof *pos), *mass = malloc(nn * sizeof *mass), *eps = malloc(nn * sizeof *eps);
    double *acc = malloc(3 * nn * sizeof *acc), *pot = malloc(nn * sizeof *pot);
    unsigned char *type = malloc(nn), *active = malloc(nn);
    double *ref = malloc(3 * (size_t)check * sizeof *ref);
    if (!pos || !mass || !eps || !acc || !pot || !type || !active || !ref)
        die("out of memory");
    double *vel = malloc(3 * nn * sizeof *vel);
    if (!vel)
        die("out of memory");
    load(n, 0, pos, vel, mass, type);
    for (size_t i = 0; i < nn; i++)
        eps[i] = type[i] == ORR_MODEL_TYPE_HALO ? 2 * eps_star : eps_star;
    qt_tree t = {0};
    /* A build from the particles' own order, then builds after drifts of
     * 0.002 (a sub-step), which start from the last build's order; the
     * forces are then measured at the last positions. */
    double build = INFINITY, first_build = cpu_seconds();
    if (qt_build(&t, pos, mass, eps, nn) != 0)
        die("out of memory (tree)");
    first_build = cpu_seconds() - first_build;
    for (int r = 0; r < repeat; r++) {
        for (size_t i = 0; i < 3 * nn; i++)
            pos[i] += FILM_DT * vel[i];
        double c0 = cpu_seconds();
        if (qt_build(&t, pos, mass, eps, nn) != 0)
            die("out of memory (tree)");
        build = fmin(build, cpu_seconds() - c0);
    }
    free(vel);
    reference(pos, mass, eps, nn, (size_t)check, ref);
    double inter_full, inter[2];
    double full = masked_cpu(&t, 0, nn, NEW_THETA, NULL, repeat, acc, pot, &inter_full);
    printf("bench_nbody substeps: N = %lld (Milky Way alone), eta %g, softening %g / %g kpc, %d threads, best of %d\n",
           n, eta, eps_star, 2 * eps_star, omp_get_max_threads(), repeat);
    printf("tree build %.3f CPU s (the first, from the particles' order: %.3f); every particle's force and potential "
           "(super-groups) %.3f CPU s, %.0f interactions a particle\n", build, first_build, full, inter_full / (double)nn);
    printf("%-26s %6s %22s %22s\n", "active: wanted step under", "share", "root walks: CPU s (/)",
           "super-groups: CPU s (/)");
    const double under[2] = {0.004, 0.008};
    for (int u = 0; u < 2; u++) {
        size_t on = 0;
        for (size_t i = 0; i < nn; i++) {
            const double *a = &acc[3 * i];
            double amag = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
            active[i] = amag > 0 && sqrt(2 * eta * eps[i] / amag) < under[u];
            on += active[i];
        }
        double share = (double)on / (double)nn, per = full * share; /* a full step's CPU for as many forces */
        double *a2 = malloc(3 * nn * sizeof *a2), p99[2];
        if (!a2)
            die("out of memory");
        double root = masked_cpu(&t, 1, nn, NEW_THETA, active, repeat, a2, NULL, &inter[0]);
        p99[0] = active_p99(a2, ref, nn, (size_t)check, active);
        double super = masked_cpu(&t, 0, nn, NEW_THETA, active, repeat, a2, NULL, &inter[1]);
        p99[1] = active_p99(a2, ref, nn, (size_t)check, active);
        printf("%-26g %6.3f %15.3f (%4.2f) %15.3f (%4.2f)\n", under[u], share, root, root / per, super, super / per);
        printf("%-26s %6s %22.0f %22.0f\n", "  interactions a force", "", inter[0] / (double)on, inter[1] / (double)on);
        printf("%-26s %6s %22.2e %22.2e\n", "  99th percentile error", "", p99[0], p99[1]);
        free(a2);
    }
    printf("(/): CPU a force over the full step's\n");
    qt_free(&t);
    free(pos);
    free(mass);
    free(eps);
    free(acc);
    free(pot);
    free(type);
    free(active);
    free(ref);
    return 0;
}

/* ---- fmm: the tree walk against a fast multipole method -------------- */

/* The CPU seconds of the best of `repeat` runs of one way of computing
 * every particle's acceleration (the tree built anew each time, its
 * build included): fmm_theta 0 the tree walk at theta, else the FMM at
 * fmm_theta. The interactions a particle of the last run into *inter
 * (tree: particle-cell and particle-particle; FMM: cell-cell and
 * particle pairs, each counted once), its counts into *fc. */
static double one_way(const double *pos, const double *mass, const double *eps, size_t n, double theta,
                      double fmm_theta, int repeat, double *acc, double *inter, fmm_counts *fc)
{
    double best = INFINITY;
    for (int r = 0; r < repeat; r++) {
        qt_tree t = {0};
        double c0 = cpu_seconds();
        if (qt_build(&t, pos, mass, eps, n) != 0)
            die("out of memory (tree)");
        if (fmm_theta > 0) {
            if (fmm_accelerations(&t, G_KPC_KMS, fmm_theta, acc, NULL, fc) != 0)
                die("out of memory (fmm)");
            *inter = (fc->cell_cell + fc->pair) / (double)n;
        } else {
            *inter = qt_accelerations_of(&t, G_KPC_KMS, theta, 0, n, acc, NULL) / (double)n;
        }
        double c = cpu_seconds() - c0;
        best = c < best ? c : best;
        qt_free(&t);
    }
    return best;
}

static int bench_fmm(int argc, char **argv)
{
    long long n = argc > 0 ? atoll(argv[0]) : 200000;
    long long check = argc > 1 ? atoll(argv[1]) : 1000;
    int repeat = argc > 2 ? atoi(argv[2]) : 3;
    if (n < 1000 || check < 10 || check > n || repeat < 1)
        die("usage: bench_nbody fmm [N >= 1000 [CHECK, 10 to N [REPEAT >= 1 [FMM_THETA ...]]]]");
    size_t nn = (size_t)n;
    double *pos = malloc(3 * nn * sizeof *pos), *mass = malloc(nn * sizeof *mass), *eps = malloc(nn * sizeof *eps);
    double *acc = malloc(3 * nn * sizeof *acc), *ref = malloc(3 * (size_t)check * sizeof *ref);
    unsigned char *type = malloc(nn);
    if (!pos || !mass || !eps || !acc || !ref || !type)
        die("out of memory");
    load(n, 1, pos, NULL, mass, type);
    for (size_t i = 0; i < nn; i++)
        eps[i] = type[i] == ORR_MODEL_TYPE_HALO ? 0.4 : 0.2;
    reference(pos, mass, eps, nn, (size_t)check, ref);
    printf("bench_nbody fmm: N = %lld (Milky Way and M31), the films' softening 0.2 / 0.4 kpc, %d threads, "
           "best of %d; errors against direct summation for %lld particles\n",
           n, omp_get_max_threads(), repeat, check);
    printf("%-26s %10s %12s %12s %12s %10s %10s\n", "", "CPU s", "interactions", "cell-cell", "pairs",
           "median", "99th pct");
    double inter;
    fmm_counts fc = {0};
    result e;
    double cpu = one_way(pos, mass, eps, nn, NEW_THETA, 0, repeat, acc, &inter, &fc);
    errors(pos, mass, eps, nn, (size_t)check, ref, acc, &e);
    printf("%-26s %10.3f %12.0f %12s %12s %10.2e %10.2e\n", "tree walk, theta 0.7", cpu, inter, "", "", e.median,
           e.p99);
    for (int a = 3; a < argc; a++) {
        double ft = atof(argv[a]);
        if (!(ft > 0 && ft < 1))
            die("an FMM theta must lie between 0 and 1");
        double c = one_way(pos, mass, eps, nn, NEW_THETA, ft, repeat, acc, &inter, &fc);
        errors(pos, mass, eps, nn, (size_t)check, ref, acc, &e);
        char name[32];
        snprintf(name, sizeof name, "FMM, theta %.2f", ft);
        printf("%-26s %10.3f %12.0f %12.0f %12.0f %10.2e %10.2e\n", name, c, inter, fc.cell_cell / (double)n,
               fc.pair / (double)n, e.median, e.p99);
    }
    free(pos);
    free(mass);
    free(eps);
    free(acc);
    free(ref);
    free(type);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc > 1 && strcmp(argv[1], "fmm") == 0)
        return bench_fmm(argc - 2, argv + 2);
    if (argc > 1 && strcmp(argv[1], "steps") == 0)
        return bench_steps(argc - 2, argv + 2);
    if (argc > 1 && strcmp(argv[1], "substeps") == 0)
        return bench_substeps(argc - 2, argv + 2);
    long long n = argc > 1 ? atoll(argv[1]) : 100000;
    long long check = argc > 2 ? atoll(argv[2]) : 2000;
    int pair = argc > 3 && strcmp(argv[3], "pair") == 0;
    double theta = argc > 4 ? atof(argv[4]) : NEW_THETA;
    double eps_star = argc > 5 ? atof(argv[5]) : NEW_EPS_STAR;
    if (n < 1000 || check < 10 || check > n || !(theta > 0 && theta <= 1) || !(eps_star > 0))
        die("usage: bench_nbody [N >= 1000 [CHECK, 10 to N [mw|pair [THETA, 0 to 1 [EPS > 0]]]]]");
    double *pos = malloc(3 * (size_t)n * sizeof *pos), *mass = malloc((size_t)n * sizeof *mass);
    double *eps_old = malloc((size_t)n * sizeof *eps_old), *eps_new = malloc((size_t)n * sizeof *eps_new);
    double *acc = malloc(3 * (size_t)n * sizeof *acc);
    unsigned char *type = malloc((size_t)n);
    if (!pos || !mass || !eps_old || !eps_new || !acc || !type)
        die("out of memory");
    load(n, pair, pos, NULL, mass, type);
    for (long long i = 0; i < n; i++) {
        eps_old[i] = OLD_EPS;
        eps_new[i] = type[i] == ORR_MODEL_TYPE_HALO ? 2 * eps_star : eps_star;
    }
    result old, neu;
    run_old(pos, mass, (size_t)n, acc, &old);
    errors(pos, mass, eps_old, (size_t)n, (size_t)check, NULL, acc, &old);
    run_new(pos, mass, eps_new, (size_t)n, theta, acc, &neu);
    errors(pos, mass, eps_new, (size_t)n, (size_t)check, NULL, acc, &neu);

    printf("bench_nbody: N = %lld (%s), %d threads; errors against direct summation over all N for %lld "
           "particles\n",
           n, pair ? "Milky Way and M31" : "Milky Way alone", omp_get_max_threads(), check);
    printf("%-28s %22s %22s\n", "", "old: monopole", "new: quadrupole groups");
    char new_set[64];
    snprintf(new_set, sizeof new_set, "%.2g, %.2g / %.2g kpc", theta, eps_star, 2 * eps_star);
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
