/* The fast multipole method over the quadrupole tree (examples/nbody/fmm.c)
 * against direct summation with the same softening rule:
 * - two leaves far apart act on each other through one pair of
 *   expansions, whose error in the pull of one on the other falls as
 *   (size / distance)^3 (a third-order expansion of a quadrupole), with one
 *   softening and with a mix of two (the expansions' dependence on each
 *   target's own softening);
 * - at a small opening angle a galaxy-like mix of 4000 particles (galaxy_mix.h) gets the
 *   direct accelerations and potentials. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "fmm.h"
#include "galaxy_mix.h"
#include "qtree.h"

#define BLOB 16 /* one leaf each (QT_LEAF) */
#define N 4000

static double pos[3 * N], mass[N], eps[N], acc[3 * N], pot[N], acc_direct[3 * N], pot_direct[N];

/* Two blobs of BLOB particles, the second D along x: uneven masses, an
 * elongated shape (a quadrupole), softening eps_a, or eps_a and 2 eps_a
 * in turns when mixed. */
static void two_blobs(double D, double eps_a, int mixed)
{
    srand(2);
    for (int i = 0; i < 2 * BLOB; i++) {
        for (int k = 0; k < 3; k++)
            pos[3 * i + k] = ((double)rand() / RAND_MAX - 0.5) * (k == 0 ? 1.5 : 1.0);
        if (i >= BLOB)
            pos[3 * i] += D;
        mass[i] = 1.0 + i % 7;
        eps[i] = mixed && i % 3 == 0 ? 2 * eps_a : eps_a;
    }
}

/* The largest relative error, over the particles of both blobs, in the
 * pull of the other blob (the total less the own blob's direct pull,
 * which both sums share). */
static double cross_error(double D, double eps_a, int mixed, double *cell_cell)
{
    const size_t n = 2 * BLOB;
    two_blobs(D, eps_a, mixed);
    qt_tree t = {0};
    CHECK(qt_build(&t, pos, mass, eps, n) == 0);
    fmm_counts c;
    CHECK(fmm_accelerations(&t, 1.0, 0.95, acc, NULL, &c) == 0);
    *cell_cell = c.cell_cell;
    qt_free(&t);
    qt_direct(pos, mass, eps, n, 1.0, 0, n, acc_direct, NULL);
    double worst = 0;
    for (size_t i = 0; i < n; i++) {
        const size_t own = i < BLOB ? 0 : BLOB;
        double self[3];
        qt_direct(pos + 3 * own, mass + own, eps + own, BLOB, 1.0, i - own, 1, self, NULL);
        /* qt_direct of the own blob at particle i: the same pair rule */
        double d2 = 0, a2 = 0;
        for (int k = 0; k < 3; k++) {
            const double cross = acc_direct[3 * i + k] - self[k], d = acc[3 * i + k] - acc_direct[3 * i + k];
            d2 += d * d;
            a2 += cross * cross;
        }
        worst = fmax(worst, sqrt(d2 / a2));
    }
    return worst;
}

static void test_expansion_order(int mixed)
{
    double e[3], cc = 0;
    for (int s = 0; s < 3; s++) {
        e[s] = cross_error(8.0 * (1 << s), 0.3, mixed, &cc);
        CHECK(cc >= 1); /* the blobs met through expansions, not particle by particle */
    }
    /* third order: eight times smaller for twice the distance (the
     * softening's share falls faster still, so between 6 and 40) */
    CHECK(e[0] / e[1] > 6 && e[0] / e[1] < 40);
    CHECK(e[1] / e[2] > 6 && e[1] / e[2] < 40);
    CHECK(e[0] < 3e-3);
}

static void test_galaxy(void)
{
    make_galaxy_mix(pos, mass, eps, N);
    qt_tree t = {0};
    CHECK(qt_build(&t, pos, mass, eps, N) == 0);
    fmm_counts c;
    CHECK(fmm_accelerations(&t, 1.0, 0.15, acc, pot, &c) == 0);
    qt_free(&t);
    CHECK(c.cell_cell > 0 && c.pair > 0 && c.pair < 0.5 * N * (N - 1.0)); /* not all direct */
    qt_direct(pos, mass, eps, N, 1.0, 0, N, acc_direct, pot_direct);
    int within = 0;
    double w_fmm = 0, w_direct = 0;
    for (int i = 0; i < N; i++) {
        double d2 = 0, a2 = 0;
        for (int k = 0; k < 3; k++) {
            const double d = acc[3 * i + k] - acc_direct[3 * i + k];
            d2 += d * d;
            a2 += acc_direct[3 * i + k] * acc_direct[3 * i + k];
        }
        within += sqrt(d2 / a2) < 1e-3;
        w_fmm += mass[i] * pot[i];
        w_direct += mass[i] * pot_direct[i];
    }
    CHECK(within >= 0.99 * N);
    CHECK(fabs(w_fmm - w_direct) < 1e-5 * fabs(w_direct));
}

int main(void)
{
    test_expansion_order(0);
    test_expansion_order(1);
    test_galaxy();
    return check_summary();
}
