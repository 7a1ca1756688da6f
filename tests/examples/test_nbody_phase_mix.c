/* The example N-body code's phase mixing (examples/nbody/phase_mix.h):
 * the softened ring's pull against direct summation over points around
 * the ring, the field of a point mass, orbits that keep their angular
 * momentum and energy, mixing times drawn from the id alone, and a
 * breathing ring of stars made still. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "check.h"
#include "phase_mix.h"

#define G 43007.1 /* kpc (km/s)^2 per 1e10 solar masses */
#define PI 3.14159265358979323846

/* The pull at (R, 0, z) of n equal points on the ring, each softened
 * with eps2: what the ring's closed form must give. */
static void points_pull(double m, double a, double z0, double eps2, double R, double z, int n, double *fr,
                        double *fz)
{
    *fr = *fz = 0;
    for (int k = 0; k < n; k++) {
        const double phi = 2 * PI * (k + 0.5) / n;
        const double dx = a * cos(phi) - R, dy = a * sin(phi), dz = z0 - z;
        const double d2 = dx * dx + dy * dy + dz * dz + eps2;
        const double w = (m / n) / (d2 * sqrt(d2));
        *fr += w * dx;
        *fz += w * dz;
    }
}

static void test_ring_pull(void)
{
    const double probes[][2] = {{0, 0.5}, {3, 0.1}, {8, 0}, {8.05, 0.01}, {7.9, -0.3}, {20, 3}, {0.01, 0}};
    double worst = 0;
    for (size_t p = 0; p < sizeof probes / sizeof *probes; p++) {
        double fr, fz, dr, dz;
        pm_ring_pull(2.5, 8.0, 0.05, 0.04, probes[p][0], probes[p][1], &fr, &fz);
        points_pull(2.5, 8.0, 0.05, 0.04, probes[p][0], probes[p][1], 200000, &dr, &dz);
        const double err = hypot(fr - dr, fz - dz) / hypot(dr, dz);
        worst = fmax(worst, err);
    }
    fprintf(stderr, "  ring pull against 200000 points: worst relative error %.2e\n", worst);
    CHECK(worst < 1e-6);
    /* a ring of radius 0 is a softened point mass */
    double fr, fz;
    pm_ring_pull(1.0, 0.0, 0.0, 0.04, 3.0, 4.0, &fr, &fz);
    const double d3 = pow(25.04, 1.5);
    CHECK_NEAR(fr, -3.0 / d3, 1e-12);
    CHECK_NEAR(fz, -4.0 / d3, 1e-12);
}

/* A field of mass m at the centre, softened as stars (eps 0.2). */
static pm_field *point_field(double m)
{
    pm_rings *r = calloc(1, sizeof *r);
    pm_field *f = malloc(sizeof *f);
    pm_rings_add(r, 0.0, 0.0, m, 0.2);
    pm_field_build(f, r, G, 0.2);
    free(r);
    return f;
}

/* The softened point mass's potential, as the field's (eps^2 = 0.04). */
static double point_potential(double m, const double x[3])
{
    return -G * m / sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2] + 0.04);
}

static void test_orbits(void)
{
    const double m = 10.0; /* 1e11 solar masses: 232 km/s at 8 kpc */
    pm_field *f = point_field(m);
    double a[3];
    const double at[3] = {8.0, 0.0, 0.0};
    pm_field_pull(f, at, a);
    const double exact = -G * m * 8.0 / pow(64.04, 1.5);
    fprintf(stderr, "  the field at 8 kpc: %.6g against %.6g\n", a[0], exact);
    CHECK(fabs(a[0] / exact - 1) < 2e-3);
    CHECK(a[1] == 0 && a[2] == 0);
    /* a circular orbit stays circular; an eccentric, inclined one keeps
     * its angular momentum about the axis exactly and its energy */
    double x[3] = {8.0, 0.0, 0.0}, v[3] = {0.0, sqrt(-exact * 8.0), 0.0};
    pm_follow(f, x, v, 2.0);
    const double R = hypot(x[0], x[1]);
    fprintf(stderr, "  circular orbit at 8 kpc after 2 time units (9 turns): R = %.5f\n", R);
    CHECK(fabs(R - 8.0) < 0.02 && fabs(x[2]) < 1e-12);
    double y[3] = {6.0, 1.0, 0.4}, w[3] = {-40.0, 250.0, 30.0};
    const double lz0 = y[0] * w[1] - y[1] * w[0];
    const double e0 = 0.5 * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]) + point_potential(m, y);
    pm_follow(f, y, w, 1.3);
    const double lz1 = y[0] * w[1] - y[1] * w[0];
    const double e1 = 0.5 * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]) + point_potential(m, y);
    fprintf(stderr, "  eccentric orbit: L_z %.3e relative change, E %.3e\n", fabs(lz1 / lz0 - 1), fabs(e1 / e0 - 1));
    CHECK(fabs(lz1 / lz0 - 1) < 1e-12);
    CHECK(fabs(e1 / e0 - 1) < 3e-3);
    /* no time, no move */
    double p[3] = {1, 2, 3}, q[3] = {4, 5, 6};
    pm_follow(f, p, q, 0.0);
    CHECK(p[0] == 1 && p[2] == 3 && q[1] == 5);
    free(f);
}

static void test_mix_times(void)
{
    double sum = 0, least = 1, most = 0;
    const int n = 100000;
    for (int i = 0; i < n; i++) {
        const double t = pm_mix_time((uint64_t)i, 1.0);
        sum += t;
        least = fmin(least, t);
        most = fmax(most, t);
    }
    fprintf(stderr, "  mixing times of ids 0..%d: mean %.4f, from %.2e to %.6f\n", n - 1, sum / n, least, most);
    CHECK(fabs(sum / n - 0.5) < 0.005);
    CHECK(least >= 0 && most < 1 && least < 1e-3 && most > 0.999);
    CHECK(pm_mix_time(42, 0.5) == pm_mix_time(42, 0.5));
    CHECK(pm_mix_time(42, 0.5) != pm_mix_time(43, 0.5));
    CHECK(pm_mix_time(42, 0.0) == 0);
}

/* What the mixing is for: a ring of stars moving out together (a disc
 * that breathes) has no mean radial motion once each star has followed
 * its orbit for its own time. */
static void test_breathing_stilled(void)
{
    pm_field *f = point_field(10.0);
    const int n = 4000;
    double before = 0, after = 0;
    for (int i = 0; i < n; i++) {
        const double phi = 2 * PI * i / n, c = cos(phi), s = sin(phi);
        double x[3] = {8.0 * c, 8.0 * s, 0.0}, v[3] = {20.0 * c - 232.0 * s, 20.0 * s + 232.0 * c, 0.0};
        before += (x[0] * v[0] + x[1] * v[1]) / 8.0;
        pm_follow(f, x, v, pm_mix_time((uint64_t)i, 2.0));
        after += (x[0] * v[0] + x[1] * v[1]) / hypot(x[0], x[1]);
    }
    fprintf(stderr, "  a breathing ring's mean radial speed: %.2f km/s before mixing, %.2f after\n", before / n,
            after / n);
    CHECK(fabs(before / n - 20.0) < 1e-9);
    CHECK(fabs(after / n) < 2.0);
    free(f);
}

int main(void)
{
    test_ring_pull();
    test_orbits();
    test_mix_times();
    test_breathing_stilled();
    return check_summary();
}
