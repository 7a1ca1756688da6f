/* A tracer's ring (examples/nbody/tracer_ring.c) against independent truths:
 * for a galaxy symmetric under the ring's rotations, the ring's pull is the
 * direct sum at the tracer; for a bar, it is the bar's pull averaged over
 * the whole circle by a fine quadrature, with no torque; a host's axis is
 * recovered from a tilted thin disc; a uniform pull passes unchanged; a
 * tracer started on the ring's circular orbit about a point mass moves at
 * Kepler's speed; a mirrored ring gives the mean of the pulls above and below
 * the plane (quadratures), none across the plane on it. The pulls summed eight points a pass are, bit for bit,
 * each point's sum in the particles' order, on one thread and on two. */
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "tracer_ring.h"

#define TWO_PI 6.283185307179586
#define G 43007.1
#define K 32

/* An axis tilted off z, and two unit vectors e1, e2 spanning its plane. */
static const double axis[3] = {0.28, -0.15, 0.948156};
static double nrm[3], e1[3], e2[3];

static void make_frame(void)
{
    double len = sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    for (int k = 0; k < 3; k++)
        nrm[k] = axis[k] / len;
    double t[3] = {1, 0, 0}, d = nrm[0];
    for (int k = 0; k < 3; k++)
        e1[k] = t[k] - d * nrm[k];
    len = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
    for (int k = 0; k < 3; k++)
        e1[k] /= len;
    e2[0] = nrm[1] * e1[2] - nrm[2] * e1[1];
    e2[1] = nrm[2] * e1[0] - nrm[0] * e1[2];
    e2[2] = nrm[0] * e1[1] - nrm[1] * e1[0];
}

/* The point c + R (cos phi e1 + sin phi e2) + z n. */
static void at(const double c[3], double R, double phi, double z, double out[3])
{
    for (int k = 0; k < 3; k++)
        out[k] = c[k] + R * (cos(phi) * e1[k] + sin(phi) * e2[k]) + z * nrm[k];
}

/* v's radial, tangential and axial parts at azimuth phi about the axis. */
static void cylindrical(const double v[3], double phi, double out[3])
{
    out[0] = out[1] = out[2] = 0;
    for (int k = 0; k < 3; k++) {
        out[0] += v[k] * (cos(phi) * e1[k] + sin(phi) * e2[k]);
        out[1] += v[k] * (-sin(phi) * e1[k] + cos(phi) * e2[k]);
        out[2] += v[k] * nrm[k];
    }
}

/* G m d / (d^2 + e2)^1.5 from x towards p, added to a. */
static void pull(const double x[3], const double p[3], double m, double e2s, double a[3])
{
    double d[3] = {p[0] - x[0], p[1] - x[1], p[2] - x[2]};
    double r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + e2s;
    for (int k = 0; k < 3; k++)
        a[k] += G * m * d[k] / (r2 * sqrt(r2));
}

static void ring_of(const double *pos, const double *mass, const double *eps, size_t n, const double c[3],
                    const double x[3], double eps_t, double out[3])
{
    double pts[3 * K], acc[3 * K] = {0}, zero[3] = {0, 0, 0};
    ring_points(c, nrm, x, K, 0, pts);
    CHECK_NEAR(pts[0], x[0], 1e-12); /* point 0 is the tracer */
    ring_pulls(pos, mass, eps, n, 0.0, eps_t, pts, K, G, acc);
    ring_average(nrm, zero, acc, K, 0, out);
}

/* Masses in rings of K about the tilted axis (invariant under the ring's
 * turns): the ring's pull is the direct sum at the tracer. */
static void test_symmetric_galaxy(void)
{
    enum { RINGS = 6, N = RINGS * K };
    static double pos[3 * N], mass[N], eps[N];
    const double c[3] = {1.0, -2.0, 0.5};
    for (int r = 0; r < RINGS; r++)
        for (int j = 0; j < K; j++) {
            int i = r * K + j;
            at(c, 1.5 + 2.0 * r, TWO_PI * j / K + 0.1 * r, 0.3 * (r % 3 - 1), &pos[3 * i]);
            mass[i] = 1e-3 * (1 + r);
            eps[i] = 0.2;
        }
    double x[3], ring[3], direct[3] = {0, 0, 0};
    at(c, 8.0, 0.37, -0.05, x);
    ring_of(pos, mass, eps, N, c, x, 0.6, ring);
    for (int i = 0; i < N; i++)
        pull(x, &pos[3 * i], mass[i], 0.5 * (eps[i] * eps[i] + 0.36), direct);
    for (int k = 0; k < 3; k++)
        CHECK_NEAR(ring[k], direct[k], 1e-10 * fabs(direct[0]) + 1e-10);
}

/* A bar (two masses) and a lighter clump off the plane: the ring's pull is
 * the circle's mean of theirs (a 4096-point quadrature of the radial,
 * tangential and axial parts), and its tangential part, the torque, is 0. */
static void test_bar(void)
{
    const double c[3] = {0, 0, 0};
    double pos[9], mass[3] = {0.5, 0.5, 0.1}, eps[3] = {0.3, 0.3, 0.3};
    at(c, 3.0, 0.2, 0.0, &pos[0]);
    at(c, 3.0, 0.2 + TWO_PI / 2, 0.0, &pos[3]);
    at(c, 2.0, 1.3, 0.8, &pos[6]);
    const double R = 8.0, z = 0.1, phi0 = 0.9;
    double x[3], ring[3];
    at(c, R, phi0, z, x);
    ring_of(pos, mass, eps, 3, c, x, 0.5, ring);
    double mean[3] = {0, 0, 0}; /* radial, tangential, axial */
    const int Q = 4096;
    for (int q = 0; q < Q; q++) {
        double phi = TWO_PI * q / Q, p[3], a[3] = {0, 0, 0};
        at(c, R, phi, z, p);
        for (int j = 0; j < 3; j++)
            pull(p, &pos[3 * j], mass[j], 0.5 * (eps[j] * eps[j] + 0.25), a);
        double parts[3];
        cylindrical(a, phi, parts);
        for (int k = 0; k < 3; k++)
            mean[k] += parts[k] / Q;
    }
    double got[3];
    cylindrical(ring, phi0, got);
    double scale = fabs(mean[0]);
    CHECK(scale > 0);
    CHECK_NEAR(got[0], mean[0], 1e-9 * scale);
    CHECK_NEAR(got[1], 0.0, 1e-9 * scale);
    CHECK_NEAR(mean[1], 0.0, 1e-9 * scale);
    CHECK_NEAR(got[2], mean[2], 1e-9 * scale);
    /* The bar's own pull at the tracer has a torque the ring removes. */
    double here[3] = {0, 0, 0}, parts[3];
    for (int j = 0; j < 3; j++)
        pull(x, &pos[3 * j], mass[j], 0.5 * (eps[j] * eps[j] + 0.25), here);
    cylindrical(here, phi0, parts);
    CHECK(fabs(parts[1]) > 1e-3 * scale);
}

/* The circle's mean (a 4096-point quadrature) of the pull of pos/mass/eps
 * at radius R and height z about c, softened with eps_t, as radial,
 * tangential and axial parts: of the pull at height z, and of that at -z
 * reflected back across the plane. */
static void circle_mean(const double *pos, const double *mass, const double *eps, int n, const double c[3], double R,
                        double z, double eps_t, double at_z[3], double mirrored[3])
{
    const int Q = 4096;
    for (int k = 0; k < 3; k++)
        at_z[k] = mirrored[k] = 0;
    for (int q = 0; q < Q; q++) {
        double phi = TWO_PI * q / Q;
        for (int side = 0; side < 2; side++) {
            double p[3], a[3] = {0, 0, 0}, parts[3], *mean = side ? mirrored : at_z;
            at(c, R, phi, side ? -z : z, p);
            for (int j = 0; j < n; j++)
                pull(p, &pos[3 * j], mass[j], 0.5 * (eps[j] * eps[j] + eps_t * eps_t), a);
            cylindrical(a, phi, parts);
            parts[2] *= side ? -1 : 1; /* reflected back */
            for (int k = 0; k < 3; k++)
                mean[k] += parts[k] / Q;
        }
    }
}

/* A mirrored ring (every odd point reflected across the plane): its odd
 * points lie at -z; its pull is the mean of the circle's mean at z and the
 * reflected one at -z (quadratures), with no torque; on the plane it has
 * no part across it, where the plain ring has the off-plane clump's. */
static void test_mirror(void)
{
    const double c[3] = {0.5, -1.0, 0.2};
    double pos[9], mass[3] = {0.5, 0.5, 0.1}, eps[3] = {0.3, 0.3, 0.3};
    at(c, 3.0, 0.2, 0.05, &pos[0]);
    at(c, 3.0, 0.2 + TWO_PI / 2, -0.05, &pos[3]);
    at(c, 2.0, 1.3, 0.8, &pos[6]);
    const double R = 8.0, phi0 = 0.9, eps_t = 0.5;
    for (int on_plane = 0; on_plane < 2; on_plane++) {
        double z = on_plane ? 0.0 : 0.3, x[3], pts[3 * K], acc[3 * K] = {0}, zero[3] = {0, 0, 0}, ring[3];
        at(c, R, phi0, z, x);
        ring_points(c, nrm, x, K, 1, pts);
        for (int p = 0; p < K; p++) {
            double h = 0;
            for (int k = 0; k < 3; k++)
                h += (pts[3 * p + k] - c[k]) * nrm[k];
            CHECK_NEAR(h, p % 2 ? -z : z, 1e-12);
        }
        ring_pulls(pos, mass, eps, 3, 0.0, eps_t, pts, K, G, acc);
        ring_average(nrm, zero, acc, K, 1, ring);
        double at_z[3], mirrored[3], got[3];
        circle_mean(pos, mass, eps, 3, c, R, z, eps_t, at_z, mirrored);
        cylindrical(ring, phi0, got);
        double scale = fabs(at_z[0]);
        CHECK(scale > 0);
        CHECK_NEAR(got[0], 0.5 * (at_z[0] + mirrored[0]), 1e-6 * scale);
        CHECK_NEAR(got[1], 0.0, 1e-9 * scale);
        CHECK_NEAR(got[2], 0.5 * (at_z[2] + mirrored[2]), 1e-6 * scale);
        if (on_plane) {
            CHECK_NEAR(got[2], 0.0, 1e-9 * scale);
            CHECK(fabs(at_z[2]) > 1e-3 * scale); /* what the plain ring would give */
        } else {
            CHECK(fabs(got[2] - at_z[2]) > 1e-3 * scale); /* the mirror changed it */
        }
    }
}

/* A uniform pull (Andromeda's, far away) that the host feels too: the ring
 * gives it back whole, in every direction. */
static void test_uniform_pull(void)
{
    double acc[3 * K], g[3] = {12.0, -7.0, 3.0}, out[3];
    for (int p = 0; p < K; p++)
        for (int k = 0; k < 3; k++)
            acc[3 * p + k] = g[k];
    ring_average(nrm, g, acc, K, 0, out);
    for (int k = 0; k < 3; k++)
        CHECK_NEAR(out[k], g[k], 1e-12);
}

/* A host: a disc of particles in the plane of the tilted axis,
 * accelerating as a whole, with a round bulge and halo particles. The sums
 * give the centre and acceleration (halo and tracers left out); the disc's
 * second moments, the axis, against which the bulge's (rounder) would not
 * be the thinnest. */
static void test_host(void)
{
    enum { N = 401 }; /* the last a tracer in the disc */
    static double pos[3 * N], acc[3 * N], mass[N];
    static uint8_t type[N];
    const double c[3] = {3, 4, -1}, a0[3] = {5, 6, -7};
    srand(3);
    for (int i = 0; i < N; i++) {
        double R = 1 + 9.0 * rand() / RAND_MAX, phi = TWO_PI * i / 100.0;
        type[i] = i < 300 || i == 400 ? 2 : i < 360 ? 3 : 1;
        mass[i] = i == 400 ? 1e-12 : 1e-4;
        /* the disc 0.1 thick, the bulge round (radius 1.5) */
        double z = type[i] == 2 ? 0.1 * (2.0 * rand() / RAND_MAX - 1) : 0.0;
        if (type[i] == 3) {
            R = 1.5 * cos(0.05 * i);
            z = 1.5 * sin(0.05 * i);
        }
        at(c, R, phi, z, &pos[3 * i]);
        for (int k = 0; k < 3; k++)
            acc[3 * i + k] = a0[k];
    }
    at(c, 40.0, 0.0, 0.0, &pos[3 * 399]); /* a halo particle far out */
    double s[RING_SUMS] = {0}, got_c[3], got_a[3];
    ring_star_sums(pos, acc, mass, type, N, 1e-8, c, 12.0, s);
    CHECK_NEAR(s[0], 360 * 1e-4, 1e-12); /* 300 disc + 60 bulge: not the halo, nor the tracer */
    CHECK(ring_host(s, got_c, got_a));
    for (int k = 0; k < 3; k++)
        CHECK_NEAR(got_a[k], a0[k], 1e-9);
    double m2[6] = {0}, n[3];
    ring_shape_sum(pos, mass, type, N, 2, got_c, 12.0, m2);
    CHECK(ring_axis(m2, n));
    double along = fabs(n[0] * nrm[0] + n[1] * nrm[1] + n[2] * nrm[2]);
    CHECK_NEAR(along, 1.0, 1e-4);
    /* A shape thin along a known axis: the moments of a flat ellipse turned
     * about nothing, 1 4 0.01 on the diagonal, give z. */
    const double diag[6] = {1, 4, 0.01, 0, 0, 0};
    CHECK(ring_axis(diag, n));
    CHECK_NEAR(fabs(n[2]), 1.0, 1e-12);
    double none[RING_SUMS] = {0}, zero[6] = {0};
    CHECK(!ring_host(none, got_c, got_a));
    CHECK(!ring_axis(zero, n));
}

/* A tracer started on the circular orbit of the ring's pull: about one
 * mass M at the host's centre (unsoftened, the host moving and
 * accelerating as a whole), the speed is Kepler's sqrt(G M / R) whatever
 * the tracer's given velocity, along the circle in the sense it turned,
 * with the host's velocity added; no inward pull, or no turning given, and
 * it is left alone. */
static void test_circular_start(void)
{
    const double c[3] = {2, -1, 0.5}, M = 5.0, R = 8.0, mass[1] = {M}, eps[1] = {0};
    const double a_host[3] = {30, -20, 10}, v_host[3] = {-110, 80, 35};
    double x[3], pts[3 * K], acc[3 * K] = {0}, a[3];
    at(c, R, 0.9, 0.0, x);
    ring_points(c, nrm, x, K, 0, pts);
    ring_pulls(c, mass, eps, 1, 0.0, 0.0, pts, K, G, acc);
    for (int p = 0; p < K; p++)
        for (int k = 0; k < 3; k++)
            acc[3 * p + k] += a_host[k];
    ring_average(nrm, a_host, acc, K, 0, a);
    double t[3], inward[3], v[3], out[3];
    at(c, 1.0, 0.9 + TWO_PI / 4, 0.0, t); /* the circle's direction, increasing phi: c + t */
    at(c, 1.0, 0.9, 0.0, inward);
    for (int k = 0; k < 3; k++) {
        t[k] -= c[k];
        inward[k] = c[k] - inward[k];
    }
    for (int sense = -1; sense <= 1; sense += 2) {
        for (int k = 0; k < 3; k++) /* turning at 150 km/s, falling in at 40 and rising at 25 */
            v[k] = v_host[k] + sense * 150.0 * t[k] + 40.0 * inward[k] + 25.0 * nrm[k];
        CHECK(ring_circular_velocity(c, nrm, a_host, v_host, x, a, v, out));
        for (int k = 0; k < 3; k++)
            CHECK_NEAR(out[k], v_host[k] + sense * sqrt(G * M / R) * t[k], 1e-9);
    }
    double still[3] = {v_host[0], v_host[1], v_host[2]}, away[3];
    for (int k = 0; k < 3; k++)
        away[k] = 2 * a_host[k] - a[k]; /* pushed outward */
    out[0] = out[1] = out[2] = -1;
    CHECK(!ring_circular_velocity(c, nrm, a_host, v_host, x, a, still, out));
    CHECK(!ring_circular_velocity(c, nrm, a_host, v_host, x, away, v, out));
    CHECK(!ring_circular_velocity(c, nrm, a_host, v_host, c, a, v, out)); /* on the axis */
    CHECK(out[0] == -1 && out[1] == -1 && out[2] == -1);
}

/* ring_pulls against the plain loop its comment states (each point's sum
 * in the particles' order, the lighter ones left out): the same bits for
 * 11 points (a pass of eight and one of three), on one thread and two. */
static void test_pulls_bit_for_bit(void)
{
    enum { N = 997, P = 11 };
    static double pos[3 * N], mass[N], eps[N], pts[3 * P];
    unsigned s = 12345;
    for (int i = 0; i < 3 * N; i++) {
        s = s * 1103515245u + 12345u;
        pos[i] = 20.0 * ((s >> 8) / 16777216.0) - 10.0;
    }
    for (int i = 0; i < N; i++) {
        mass[i] = i % 7 == 0 ? 1e-9 : 1e-4 * (1 + i % 5); /* every 7th lighter than light */
        eps[i] = i % 2 ? 0.2 : 0.4;
    }
    for (int i = 0; i < 3 * P; i++)
        pts[i] = 3.0 * sin(1.7 * i + 0.3);
    const double light = 1e-6, eps_t = 0.3, e2t = eps_t * eps_t;
    double plain[3 * P];
    for (int p = 0; p < P; p++) {
        double sum[3] = {0, 0, 0};
        for (int i = 0; i < N; i++) {
            if (mass[i] < light)
                continue;
            double d[3] = {pos[3 * i] - pts[3 * p], pos[3 * i + 1] - pts[3 * p + 1], pos[3 * i + 2] - pts[3 * p + 2]};
            double r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + 0.5 * (eps[i] * eps[i] + e2t);
            double w = mass[i] / (r2 * sqrt(r2));
            for (int k = 0; k < 3; k++)
                sum[k] += w * d[k];
        }
        for (int k = 0; k < 3; k++)
            plain[3 * p + k] = 1.0 + G * sum[k]; /* added to acc's 1 */
    }
    for (int threads = 1; threads <= 2; threads++) {
        double acc[3 * P];
        for (int i = 0; i < 3 * P; i++)
            acc[i] = 1.0;
        omp_set_num_threads(threads);
        ring_pulls(pos, mass, eps, N, light, eps_t, pts, P, G, acc);
        CHECK(memcmp(acc, plain, sizeof acc) == 0);
    }
}

int main(void)
{
    make_frame();
    test_symmetric_galaxy();
    test_bar();
    test_mirror();
    test_uniform_pull();
    test_host();
    test_circular_start();
    test_pulls_bit_for_bit();
    printf("%d checks, %d failed\n", check_count, check_failures);
    return check_failures != 0;
}
