/* The example N-body code's Barnes-Hut tree against direct summation: with
 * theta -> 0 it is direct summation; at the usual opening angles its
 * accelerations are within the errors a monopole tree is known for. */
#include <stdlib.h>

#include "check.h"
#include "tree.h"

#define N 3000

static double pos[3 * N], mass[N], acc_tree[3 * N], acc_direct[3 * N];

/* A Plummer-like clump plus a distant, lighter one: cells at all depths. */
static void make_particles(void)
{
    srand(11);
    for (int i = 0; i < N; i++) {
        double r = pow((double)rand() / RAND_MAX + 1e-9, 1.0 / 3.0) * (i < 2 * N / 3 ? 1.0 : 0.3);
        double u = 2.0 * rand() / RAND_MAX - 1, phi = 6.283185307179586 * rand() / RAND_MAX, s = sqrt(1 - u * u);
        double off = i < 2 * N / 3 ? 0 : 5;
        pos[3 * i] = r * s * cos(phi) + off;
        pos[3 * i + 1] = r * s * sin(phi);
        pos[3 * i + 2] = r * u;
        mass[i] = i < 2 * N / 3 ? 1.0 / N : 0.5 / N;
    }
}

/* Relative error of each particle's acceleration; returns the given percentile. */
static double error_percentile(double pct)
{
    static double err[N];
    for (int i = 0; i < N; i++) {
        double d2 = 0, a2 = 0;
        for (int k = 0; k < 3; k++) {
            double d = acc_tree[3 * i + k] - acc_direct[3 * i + k];
            d2 += d * d;
            a2 += acc_direct[3 * i + k] * acc_direct[3 * i + k];
        }
        err[i] = sqrt(d2 / a2);
    }
    for (int i = 1; i < N; i++) /* insertion sort: small N */
        for (int j = i; j > 0 && err[j] < err[j - 1]; j--) {
            double t = err[j];
            err[j] = err[j - 1];
            err[j - 1] = t;
        }
    return err[(int)(pct / 100 * (N - 1))];
}

int main(void)
{
    make_particles();
    const double G = 43007.1, eps = 0.01;
    direct_accelerations(pos, mass, N, G, eps, acc_direct);
    bh_tree t = {0};
    CHECK(bh_build(&t, pos, mass, N) == 0);
    /* The root holds all the mass at the centre of mass. */
    double m = 0, cx = 0;
    for (int i = 0; i < N; i++) {
        m += mass[i];
        cx += mass[i] * pos[3 * i];
    }
    CHECK_NEAR(t.nodes[0].mass, m, 1e-12);
    CHECK_NEAR(t.nodes[0].com[0], cx / m, 1e-12);

    /* theta = 0 opens every cell: direct summation, up to the order of sums. */
    double n0 = bh_accelerations(&t, pos, mass, G, eps, 1e-9, acc_tree);
    CHECK_NEAR(n0, (double)N * (N - 1), 0);
    CHECK(error_percentile(100) < 1e-10);

    /* Monopole errors shrink as the opening angle does (about theta^2 at
     * first order); at theta = 0.5, the median is a few 1e-3 and 99% of the
     * particles are within 2%. */
    double median[3], thetas[3] = {0.8, 0.5, 0.3};
    for (int k = 0; k < 3; k++) {
        double n = bh_accelerations(&t, pos, mass, G, eps, thetas[k], acc_tree);
        CHECK(n < 0.5 * N * (N - 1));
        median[k] = error_percentile(50);
        if (k == 1)
            CHECK(error_percentile(99) < 2e-2);
        fprintf(stderr, "theta %.1f: %.0f interactions (direct %d), median error %.2g, 99th %.2g\n", thetas[k], n,
                N * (N - 1), median[k], error_percentile(99));
    }
    CHECK(median[0] > median[1] && median[1] > median[2]);
    CHECK(median[1] < 5e-3);

    /* A process's slice (orrery-nbody-mpi): the same accelerations, bit for
     * bit, as those of the whole. */
    bh_accelerations(&t, pos, mass, G, eps, 0.5, acc_tree);
    const size_t first = N / 3, count = N / 4;
    bh_accelerations_of(&t, pos, mass, G, eps, 0.5, first, count, acc_direct);
    CHECK(memcmp(acc_direct, &acc_tree[3 * first], 3 * count * sizeof *acc_direct) == 0);

    /* Coincident particles end in one deep leaf, and still come out finite. */
    for (int i = 0; i < 20; i++)
        for (int k = 0; k < 3; k++)
            pos[3 * i + k] = 0.25;
    CHECK(bh_build(&t, pos, mass, N) == 0);
    bh_accelerations(&t, pos, mass, G, eps, 0.5, acc_tree);
    int finite = 1;
    for (int i = 0; i < 3 * N; i++)
        finite &= isfinite(acc_tree[i]);
    CHECK(finite);
    bh_free(&t);
    return check_summary();
}
