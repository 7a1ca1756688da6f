/* Discs phase-mixed before a run: the rings, the field, the orbits
 * (phase_mix.h). */
#include "phase_mix.h"

#include <math.h>
#include <string.h>

#define PI 3.14159265358979323846

/* The complete elliptic integrals K(k) and E(k) from k'^2 = 1 - k^2 by the
 * arithmetic-geometric mean (Abramowitz & Stegun 17.6): K = pi / (2 a_N),
 * E = K (1 - sum_n 2^(n-1) c_n^2), c_0 = k. */
static void elliptic_ke(double k2, double kp2, double *K, double *E)
{
    double a = 1.0, b = sqrt(kp2), sum = 0.5 * k2, power = 0.5;
    for (int n = 0; n < 40 && fabs(a - b) > 1e-15 * a; n++) {
        const double c = 0.5 * (a - b);
        power *= 2.0;
        sum += power * c * c;
        const double next = 0.5 * (a + b);
        b = sqrt(a * b);
        a = next;
    }
    *K = PI / (2.0 * a);
    *E = *K * (1.0 - sum);
}

/* With s^2 = (z - z0)^2 + eps2, p = (R + a)^2 + s^2, q = (R - a)^2 + s^2 and
 * k^2 = 4 R a / p, the ring's potential is -(2 m / pi) K / sqrt(p) and
 *   F_R = -(m / (pi R sqrt(p))) [K + (R^2 - a^2 - s^2) E / q],
 *   F_z = -(2 m / pi) (z - z0) E / (q sqrt(p))
 * (the integrals over the ring of 1 / D^(1/2) and 1 / D^(3/2), D the
 * squared softened distance). On the axis F_R is 0. */
void pm_ring_pull(double m, double a, double z0, double eps2, double R, double z, double *fr, double *fz)
{
    const double dz = z - z0, s2 = dz * dz + eps2;
    const double p = (R + a) * (R + a) + s2, q = (R - a) * (R - a) + s2;
    double K, E;
    elliptic_ke(4.0 * R * a / p, q / p, &K, &E);
    const double sp = sqrt(p);
    *fr = R > 0 ? -(m / (PI * R * sp)) * (K + (R * R - a * a - s2) * E / q) : 0.0;
    *fz = -(2.0 * m / PI) * dz * E / (q * sp);
}

static double u_of(double R)
{
    return R / (R + PM_SCALE_R);
}

static double v_of(double z)
{
    return z / (fabs(z) + PM_SCALE_Z);
}

static int bin_of(double t, double lo, double hi, int n)
{
    const int i = (int)floor((t - lo) / (hi - lo) * n);
    return i < 0 ? 0 : i >= n ? n - 1 : i;
}

void pm_rings_add(pm_rings *r, double R, double z, double m, double eps)
{
    const int i = bin_of(u_of(R), 0.0, 1.0, PM_BINS_U), j = bin_of(v_of(z), -1.0, 1.0, PM_BINS_V);
    double *s = &r->sum[PM_BIN_SUMS * ((size_t)i * PM_BINS_V + (size_t)j)];
    s[0] += m;
    s[1] += m * R;
    s[2] += m * z;
    s[3] += m * eps * eps;
}

/* The probe (i, j): R and z >= 0 on the lattice in u and v. */
static double probe_r(int i)
{
    const double u = PM_PROBE_U_MAX * i / (PM_PROBES_U - 1);
    return PM_SCALE_R * u / (1.0 - u);
}

static double probe_z(int j)
{
    const double v = PM_PROBE_V_MAX * j / (PM_PROBES_V - 1);
    return PM_SCALE_Z * v / (1.0 - v);
}

void pm_field_build(pm_field *f, const pm_rings *r, double G, double eps)
{
    const long nprobes = (long)PM_PROBES_U * PM_PROBES_V;
#pragma omp parallel for schedule(dynamic, 16)
    for (long p = 0; p < nprobes; p++) {
        const double R = probe_r((int)(p / PM_PROBES_V)), z = probe_z((int)(p % PM_PROBES_V));
        double fr = 0, fz = 0;
        for (size_t b = 0; b < (size_t)PM_BINS_U * PM_BINS_V; b++) {
            const double *s = &r->sum[PM_BIN_SUMS * b];
            if (!(s[0] > 0))
                continue;
            double dr, dz;
            pm_ring_pull(s[0], s[1] / s[0], s[2] / s[0], 0.5 * (eps * eps + s[3] / s[0]), R, z, &dr, &dz);
            fr += dr;
            fz += dz;
        }
        f->fr[p] = G * fr;
        f->fz[p] = z > 0 ? G * fz : 0.0; /* in the plane, by symmetry */
    }
}

/* The lattice's cell and fractions at t in [0, max], n points. */
static void lattice(double t, double max, int n, int *i, double *frac)
{
    double x = t / max * (n - 1);
    if (x > n - 1)
        x = n - 1;
    *i = (int)x < n - 1 ? (int)x : n - 2;
    *frac = x - *i;
}

void pm_field_pull(const pm_field *f, const double x[3], double a[3])
{
    const double R = sqrt(x[0] * x[0] + x[1] * x[1]);
    int i, j;
    double fu, fv;
    lattice(u_of(R), PM_PROBE_U_MAX, PM_PROBES_U, &i, &fu);
    lattice(fabs(v_of(x[2])), PM_PROBE_V_MAX, PM_PROBES_V, &j, &fv);
    const size_t p = (size_t)i * PM_PROBES_V + (size_t)j;
    const double w00 = (1 - fu) * (1 - fv), w10 = fu * (1 - fv), w01 = (1 - fu) * fv, w11 = fu * fv;
    const double fr = w00 * f->fr[p] + w10 * f->fr[p + PM_PROBES_V] + w01 * f->fr[p + 1] +
                      w11 * f->fr[p + PM_PROBES_V + 1];
    const double fz = w00 * f->fz[p] + w10 * f->fz[p + PM_PROBES_V] + w01 * f->fz[p + 1] +
                      w11 * f->fz[p + PM_PROBES_V + 1];
    a[0] = R > 0 ? fr * x[0] / R : 0.0;
    a[1] = R > 0 ? fr * x[1] / R : 0.0;
    a[2] = x[2] < 0 ? -fz : fz;
}

/* SplitMix64's finaliser (Steele, Lea & Flood 2014): a well-mixed 64-bit
 * number from a counter. */
static uint64_t mix64(uint64_t x)
{
    x += 0x9e3779b97f4a7c15ULL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
}

double pm_mix_time(uint64_t id, double T)
{
    return T * (double)(mix64(id ^ 0x70686173652d6d78ULL) >> 11) * (1.0 / 9007199254740992.0);
}

void pm_follow(const pm_field *f, double x[3], double v[3], double t)
{
    if (!(t > 0))
        return;
    const long steps = (long)ceil(t / PM_DT);
    const double h = t / (double)steps;
    double a[3];
    pm_field_pull(f, x, a);
    for (long s = 0; s < steps; s++) {
        for (int k = 0; k < 3; k++) {
            v[k] += 0.5 * h * a[k];
            x[k] += h * v[k];
        }
        pm_field_pull(f, x, a);
        for (int k = 0; k < 3; k++)
            v[k] += 0.5 * h * a[k];
    }
}
