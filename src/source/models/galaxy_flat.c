/* A spherical component's f(E) in a galaxy's flattened potential
 * (galaxy_flat.h). */
#define _XOPEN_SOURCE 700 /* j0 */
#include "source/models/galaxy_flat.h"

#include <math.h>

#include "core/vecmath.h"

#define FLAT_PI 3.14159265358979323846

/* The vertical profile exp(-|z'|/h) / (2h) averaged against exp(-k |z - z'|):
 * with a = 1/h, for z >= 0,
 *   I = (e^-kz + e^-az) / (2h (k + a)) + (e^-az - e^-kz) / (2h (k - a)),
 * the second term written with expm1 so it stays exact as k -> a
 * (where it tends to z e^-az / (2h)) and finite far above the layer. I = 1 / (1 + kh) at z = 0. */
static double vertical_average(double k, double z, double h)
{
    double a = 1.0 / h, eaz = exp(-a * z), ekz = exp(-k * z);
    double t1 = (ekz + eaz) / (2.0 * h * (k + a));
    double d = k - a;
    double t2; /* factor out the larger exponential so nothing overflows */
    if (d == 0.0)
        t2 = z * eaz / (2.0 * h);
    else if (d < 0.0)
        t2 = ekz * expm1(d * z) / (2.0 * h * d);
    else
        t2 = -eaz * expm1(-d * z) / (2.0 * h * d);
    return t1 + t2;
}

double gdf_thick_disc_potential(double R, double z, double rd, double h, double G_sigma0)
{
    /* As gdf_thick_disc_vc2: up to k = 20/h (the integrand falls as
     * k^-4 beyond 1/h and 1/rd), 20 points per period of J0(kR), and 10
     * per 1/rd and per 1/|z|, the scales of the integrand's envelope at
     * small k (midpoint error ~1e-4). */
    double az = fabs(z), sum = 0.0;
    double kmax = fmin(20.0 / h, 2000.0 / rd);
    double dk = fmin(fmin(0.1 / rd, 0.3 / fmax(R, 1e-6)), 0.1 / fmax(az, 1e-6));
    int n = (int)ceil(kmax / dk);
    dk = kmax / n;
    for (int i = 0; i < n; i++) {
        double k = (i + 0.5) * dk, s = 1.0 + k * k * rd * rd;
        sum += j0(k * R) * vertical_average(k, az, h) / (s * sqrt(s));
    }
    return -2.0 * FLAT_PI * G_sigma0 * rd * rd * sum * dk;
}

/* The radius at which the spherical potential equals psi (bisection in
 * ln r; psi decreases outward). Clipped to the potential table's range. */
static double equivalent_radius(const gdf_potential *p, double psi)
{
    double lo = p->ln_rmin, hi = p->ln_rmin + (GDF_POT_N - 1) * p->dln;
    if (psi >= gdf_psi(p, exp(lo)))
        return exp(lo);
    if (psi <= gdf_psi(p, exp(hi)))
        return exp(hi);
    for (int it = 0; it < 60; it++) {
        double mid = 0.5 * (lo + hi);
        if (gdf_psi(p, exp(mid)) > psi)
            lo = mid;
        else
            hi = mid;
    }
    return exp(0.5 * (lo + hi));
}

/* psi_true at (R, z): the spherical psi less the disc's departure from its
 * monopole, Phi_disc - Phi_mono = Phi_disc + psi_mono. */
static double true_psi(const gdf_flat_disc *d, double r, double R, double z)
{
    double phi_disc = gdf_thick_disc_potential(R, z, d->rd, d->h, d->G_sigma0);
    return gdf_psi(d->total, r) - (phi_disc + gdf_psi(d->disc_mono, r));
}

static double node_sin_b(int j)
{
    double s = (double)j / (GDF_FLAT_NB - 1);
    return s * s;
}

void gdf_flat_build(gdf_flat *t, const gdf_flat_disc *d, double rmin, double rmax,
                    double (*rho_fn)(double, const void *), const void *ctx)
{
    t->ln_rmin = log(rmin);
    t->dln = (log(rmax) - t->ln_rmin) / (GDF_FLAT_NR - 1);
    /* Each node on its own (the model is opened in one thread); the
     * largest weight is the same whatever the order. */
    double bound = 1.0;
#pragma omp parallel for schedule(dynamic, 1) reduction(max : bound)
    for (int i = 0; i < GDF_FLAT_NR; i++) {
        double r = exp(t->ln_rmin + i * t->dln);
        for (int j = 0; j < GDF_FLAT_NB; j++) {
            double sb = node_sin_b(j), z = r * sb, R = r * sqrt(fmax(0.0, 1.0 - sb * sb));
            double req = equivalent_radius(d->total, true_psi(d, r, R, z));
            t->ln_ratio[i][j] = (float)log(req / r);
            double w = rho_fn(req, ctx) / rho_fn(r, ctx);
            if (w > bound)
                bound = w;
        }
    }
    /* Between the nodes the ratio is interpolated; a margin keeps the
     * envelope above it. */
    t->bound = bound * 1.05;
}

double gdf_flat_req(const gdf_flat *t, double r, double sin_b)
{
    double fx, fy;
    const int i = orr_table_cell((log(r) - t->ln_rmin) / t->dln, GDF_FLAT_NR, &fx);
    const int j = orr_table_cell(sqrt(fmin(1.0, fabs(sin_b))) * (GDF_FLAT_NB - 1), GDF_FLAT_NB, &fy);
    double v = (1 - fx) * ((1 - fy) * t->ln_ratio[i][j] + fy * t->ln_ratio[i][j + 1]) +
               fx * ((1 - fy) * t->ln_ratio[i + 1][j] + fy * t->ln_ratio[i + 1][j + 1]);
    return r * exp(v);
}
