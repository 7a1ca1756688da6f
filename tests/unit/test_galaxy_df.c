/* Tests of the equilibrium building blocks (src/source/models/galaxy_df.c) against
 * independent results: Bessel functions against their integral
 * representations, the thick-disc rotation curve against Freeman's thin-disc
 * formula in the thin limit, and Eddington's inversion against the isotropic
 * Jeans dispersion of a Hernquist sphere known in closed form. */
#include <math.h>
#include <stdlib.h>

#include "check.h"
#include "source/models/galaxy_df.h"

#define PI 3.14159265358979323846

/* I_n(x) = (1/pi) int_0^pi e^(x cos t) cos(n t) dt;
 * K_n(x) = int_0^inf e^(-x cosh t) cosh(n t) dt (Abramowitz & Stegun 9.6.19, 9.6.24). */
static double i_integral(int n, double x)
{
    const int m = 20000;
    double s = 0;
    for (int j = 0; j < m; j++) {
        double t = PI * (j + 0.5) / m;
        s += exp(x * cos(t)) * cos(n * t);
    }
    return s / m;
}

static double k_integral(int n, double x)
{
    const int m = 20000;
    const double tmax = 20.0;
    double s = 0;
    for (int j = 0; j < m; j++) {
        double t = tmax * (j + 0.5) / m;
        s += exp(-x * cosh(t)) * cosh(n * t);
    }
    return s * tmax / m;
}

static void test_bessel(void)
{
    const double xs[] = {0.05, 0.7, 1.99, 2.01, 3.7, 3.8, 6.0, 12.0};
    for (int k = 0; k < 8; k++) {
        double x = xs[k];
        CHECK_NEAR(gdf_bessel_i0(x) / i_integral(0, x), 1.0, 1e-6);
        CHECK_NEAR(gdf_bessel_i1(x) / i_integral(1, x), 1.0, 1e-6);
        CHECK_NEAR(gdf_bessel_k0(x) / k_integral(0, x), 1.0, 1e-6);
        CHECK_NEAR(gdf_bessel_k1(x) / k_integral(1, x), 1.0, 1e-6);
    }
}

/* A disc 10^4 times thinner than its scale length rotates as Freeman's
 * thin disc; at h = rd / 10 it is slower, most near the centre. */
static void test_thick_disc(void)
{
    const double rd = 3.0;
    for (double R = 1.0; R < 30.0; R *= 1.7)
        CHECK_NEAR(gdf_thick_disc_vc2(R, rd, 3e-4, 1.0) / gdf_freeman_vc2(R, rd, 1.0), 1.0, 2e-3);
    double r2 = gdf_thick_disc_vc2(2.0, rd, 0.3, 1.0) / gdf_freeman_vc2(2.0, rd, 1.0);
    double r8 = gdf_thick_disc_vc2(8.0, rd, 0.3, 1.0) / gdf_freeman_vc2(8.0, rd, 1.0);
    CHECK(r2 > 0.80 && r2 < 0.90);
    CHECK(r8 > r2 && r8 < 0.98);
}

/* Hernquist sphere, G = M = a = 1. */
static double hernquist_gm(double r, const void *ctx)
{
    (void)ctx;
    return r * r / ((1 + r) * (1 + r));
}
static double hernquist_rho(double r, const void *ctx)
{
    (void)ctx;
    return 1.0 / (2 * PI * r * (1 + r) * (1 + r) * (1 + r));
}
static double hernquist_dln(double r, const void *ctx)
{
    (void)ctx;
    return -1.0 - 3.0 * r / (1 + r);
}

/* The isotropic dispersion of a Hernquist sphere in its own potential
 * (Hernquist 1990, ApJ 356, 359, eq. 10). */
static double hernquist_sigma2(double r)
{
    double p = 1 + r;
    return r * p * p * p * log(p / r) - r / (12 * p) * (25 + 52 * r + 42 * r * r + 12 * r * r * r);
}

/* The potential of gm_fn (1e-4 to pot_rmax) and a Hernquist sphere's
 * (a = 1) speed tables in it, in one allocation; NULL if out of memory. */
typedef struct tables {
    gdf_potential pot;
    gdf_speeds sp;
} tables;

static tables *hernquist_tables(double (*gm_fn)(double, const void *), double pot_rmax)
{
    tables *t = malloc(sizeof *t);
    CHECK(t != NULL);
    if (!t)
        return NULL;
    gdf_potential_build(&t->pot, 1e-4, pot_rmax, gm_fn, NULL);
    CHECK(gdf_speeds_build(&t->sp, &t->pot, 1e-3, 100.0, hernquist_rho, hernquist_dln, NULL));
    CHECK(t->sp.negative_f == 0);
    return t;
}

/* <v^2> at r: a quadrature over the speed's inverse cumulative
 * distribution (m midpoints); *vmax the largest speed met. */
static double mean_v2(const tables *t, double r, int m, double *vmax)
{
    double s = 0;
    *vmax = 0;
    for (int j = 0; j < m; j++) {
        double v = gdf_speed(&t->sp, &t->pot, r, (j + 0.5) / m);
        s += v * v;
        *vmax = v > *vmax ? v : *vmax;
    }
    return s / m;
}

static void test_eddington_hernquist(void)
{
    tables *t = hernquist_tables(hernquist_gm, 1e4);
    if (!t)
        return;
    CHECK_NEAR(gdf_psi(&t->pot, 1.0), 0.5, 1e-3); /* psi = 1 / (1 + r) */
    const double radii[] = {0.05, 0.3, 1.0, 4.0, 20.0};
    for (int k = 0; k < 5; k++) {
        /* <v^2> = 3 sigma^2 for an isotropic distribution */
        double vmax, v2 = mean_v2(t, radii[k], 4000, &vmax);
        CHECK_NEAR(v2 / (3 * hernquist_sigma2(radii[k])), 1.0, 0.02);
        CHECK(vmax <= sqrt(2 * gdf_psi(&t->pot, radii[k]))); /* bound */
    }
    free(t);
}

/* A small Hernquist bulge (G = M = a = 1) inside a massive, extended halo
 * (100 times its mass, scale 30): the bulge's speeds reach only a small
 * part of the escape speed, so its inverse speed distribution rises
 * steeply at the top. */
static double bulge_in_halo_gm(double r, const void *ctx)
{
    (void)ctx;
    return r * r / ((1 + r) * (1 + r)) + 100.0 * r * r / ((30 + r) * (30 + r));
}

/* The isotropic Jeans dispersion, sigma^2(r) = (1/rho) integral_r^inf rho G M / r'^2 dr',
 * by the midpoint rule in ln r'. */
static double bulge_in_halo_sigma2(double r)
{
    const int n = 200000;
    double l0 = log(r), dl = (log(1e6) - l0) / n, sum = 0;
    for (int i = 0; i < n; i++) {
        double x = exp(l0 + (i + 0.5) * dl);
        sum += hernquist_rho(x, NULL) * bulge_in_halo_gm(x, NULL) / x * dl;
    }
    return sum / hernquist_rho(r, NULL);
}

/* Its <v^2> from the tables matches 3 sigma^2 of the Jeans equation to
 * 0.5%. Columns uniform in probability overstated it by 3% (their last one
 * interpolated linearly up to the escape speed), which made the model's
 * bulge too hot. */
static void test_eddington_deep_potential(void)
{
    tables *t = hernquist_tables(bulge_in_halo_gm, 1e5);
    if (!t)
        return;
    const double radii[] = {0.1, 0.5, 1.5, 5.0};
    for (int k = 0; k < 4; k++) {
        double vmax, v2 = mean_v2(t, radii[k], 20000, &vmax);
        CHECK_NEAR(v2 / (3 * bulge_in_halo_sigma2(radii[k])), 1.0, 0.005);
    }
    free(t);
}

int main(void)
{
    RUN(test_bessel);
    RUN(test_thick_disc);
    RUN(test_eddington_hernquist);
    RUN(test_eddington_deep_potential);
    return check_summary();
}
