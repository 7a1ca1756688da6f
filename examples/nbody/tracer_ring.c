/* A tracer's pull averaged around its galaxy: the local sums (tracer_ring.h). */
#include "tracer_ring.h"

#include <math.h>
#include <string.h>

#include "core/simd.h"

#define TWO_PI 6.283185307179586
#define TYPE_DISC 2
#define TYPE_BULGE 3

double ring_distance2(const double a[3], const double b[3])
{
    return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]);
}

void ring_cross(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

void ring_star_sums(const double *pos, const double *acc, const double *mass, const uint8_t *type, size_t n,
                    double light, const double centre[3], double radius, double s[RING_SUMS])
{
    for (size_t i = 0; i < n; i++) {
        if (mass[i] < light || (type[i] != TYPE_DISC && type[i] != TYPE_BULGE) ||
            ring_distance2(&pos[3 * i], centre) > radius * radius)
            continue;
        s[0] += mass[i];
        for (int k = 0; k < 3; k++) {
            s[1 + k] += mass[i] * pos[3 * i + k];
            s[4 + k] += mass[i] * acc[3 * i + k];
        }
    }
}

void ring_shape_sum(const double *pos, const double *mass, const uint8_t *type, size_t n, uint8_t which,
                    const double c[3], double radius, double m2[6])
{
    for (size_t i = 0; i < n; i++) {
        if (type[i] != which || ring_distance2(&pos[3 * i], c) > radius * radius)
            continue;
        double d[3] = {pos[3 * i] - c[0], pos[3 * i + 1] - c[1], pos[3 * i + 2] - c[2]};
        m2[0] += mass[i] * d[0] * d[0];
        m2[1] += mass[i] * d[1] * d[1];
        m2[2] += mass[i] * d[2] * d[2];
        m2[3] += mass[i] * d[0] * d[1];
        m2[4] += mass[i] * d[0] * d[2];
        m2[5] += mass[i] * d[1] * d[2];
    }
}

/* One Jacobi rotation of the symmetric a zeroing a[p][q], applied to the
 * eigenvectors' columns v too. */
static void jacobi_rotate(double a[3][3], double v[3][3], int p, int q)
{
    if (a[p][q] == 0.0)
        return;
    double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
    double t = (theta >= 0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
    double c = 1.0 / sqrt(t * t + 1.0), s = t * c;
    for (int k = 0; k < 3; k++) { /* columns p, q */
        double akp = a[k][p], akq = a[k][q];
        a[k][p] = c * akp - s * akq;
        a[k][q] = s * akp + c * akq;
    }
    for (int k = 0; k < 3; k++) { /* rows p, q */
        double apk = a[p][k], aqk = a[q][k];
        a[p][k] = c * apk - s * aqk;
        a[q][k] = s * apk + c * aqk;
    }
    for (int k = 0; k < 3; k++) {
        double vkp = v[k][p], vkq = v[k][q];
        v[k][p] = c * vkp - s * vkq;
        v[k][q] = s * vkp + c * vkq;
    }
}

int ring_axis(const double m2[6], double n[3])
{
    double a[3][3] = {{m2[0], m2[3], m2[4]}, {m2[3], m2[1], m2[5]}, {m2[4], m2[5], m2[2]}};
    double v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    double scale = fabs(a[0][0]) + fabs(a[1][1]) + fabs(a[2][2]);
    if (!(scale > 0))
        return 0;
    for (int sweep = 0; sweep < 50; sweep++) {
        double off = fabs(a[0][1]) + fabs(a[0][2]) + fabs(a[1][2]);
        if (off <= 1e-15 * scale)
            break;
        jacobi_rotate(a, v, 0, 1);
        jacobi_rotate(a, v, 0, 2);
        jacobi_rotate(a, v, 1, 2);
    }
    int least = 0;
    for (int k = 1; k < 3; k++)
        if (a[k][k] < a[least][least])
            least = k;
    double len = sqrt(v[0][least] * v[0][least] + v[1][least] * v[1][least] + v[2][least] * v[2][least]);
    for (int k = 0; k < 3; k++)
        n[k] = v[k][least] / len;
    return 1;
}

int ring_host(const double s[RING_SUMS], double c[3], double a[3])
{
    if (!(s[0] > 0))
        return 0;
    for (int k = 0; k < 3; k++) {
        c[k] = s[1 + k] / s[0];
        a[k] = s[4 + k] / s[0];
    }
    return 1;
}

/* v turned by the angle whose cosine and sine are co, si about the unit axis n (Rodrigues). */
static void turn(const double n[3], double co, double si, const double v[3], double out[3])
{
    double nxv[3], along = n[0] * v[0] + n[1] * v[1] + n[2] * v[2];
    ring_cross(n, v, nxv);
    for (int k = 0; k < 3; k++)
        out[k] = v[k] * co + nxv[k] * si + n[k] * along * (1.0 - co);
}

/* v reflected across the plane normal to the unit vector n. */
static void reflect(const double n[3], const double v[3], double out[3])
{
    double along = n[0] * v[0] + n[1] * v[1] + n[2] * v[2];
    for (int k = 0; k < 3; k++)
        out[k] = v[k] - 2.0 * along * n[k];
}

/* Point p of a mirrored ring is one of the reflected half: every odd one. */
static int reflected(int mirror, int p)
{
    return mirror && (p & 1);
}

void ring_points(const double c[3], const double n[3], const double x[3], int k, int mirror, double *pts)
{
    double d[3] = {x[0] - c[0], x[1] - c[1], x[2] - c[2]};
    for (int p = 0; p < k; p++) {
        double phi = TWO_PI * p / k, turned[3];
        turn(n, cos(phi), sin(phi), d, turned);
        if (reflected(mirror, p))
            reflect(n, turned, turned);
        for (int j = 0; j < 3; j++)
            pts[3 * p + j] = c[j] + turned[j];
    }
}

/* Points a pass over the particles serves: each particle read once for
 * eight points, whose sums the vector lanes hold side by side. */
#define RING_LANES 8

/* One pass: the pulls at the RING_LANES points x/y/z, each point's sum in
 * the particles' order, as one point alone would sum them. The lanes do
 * the same IEEE operations one by one (no contraction: CMakeLists.txt), so
 * every clone gives the same bits. The points and sums are copied into
 * arrays of the function's own: through the pointers the compiler must
 * assume a sum may overwrite a point, and then it does the lanes one by
 * one, with scalar square roots and divisions (4.5 times slower: 4.0 ns a
 * particle and point, 0.87 now, docs/nbody.md). */
ORR_WIDE_VECTOR_CLONES
static void ring_pass(const double *pos, const double *mass, const double *eps, size_t n, double light, double e2t,
                      const double *x, const double *y, const double *z, double *sx, double *sy, double *sz)
{
    double px[RING_LANES], py[RING_LANES], pz[RING_LANES], ax[RING_LANES], ay[RING_LANES], az[RING_LANES];
    for (int p = 0; p < RING_LANES; p++) {
        px[p] = x[p];
        py[p] = y[p];
        pz[p] = z[p];
        ax[p] = sx[p];
        ay[p] = sy[p];
        az[p] = sz[p];
    }
    for (size_t i = 0; i < n; i++) {
        if (mass[i] < light)
            continue;
        double soft = 0.5 * (eps[i] * eps[i] + e2t), m = mass[i];
        double xi = pos[3 * i], yi = pos[3 * i + 1], zi = pos[3 * i + 2];
        for (int p = 0; p < RING_LANES; p++) {
            double dx = xi - px[p], dy = yi - py[p], dz = zi - pz[p];
            double r2 = dx * dx + dy * dy + dz * dz + soft;
            double w = m / (r2 * sqrt(r2));
            ax[p] += w * dx;
            ay[p] += w * dy;
            az[p] += w * dz;
        }
    }
    for (int p = 0; p < RING_LANES; p++) {
        sx[p] = ax[p];
        sy[p] = ay[p];
        sz[p] = az[p];
    }
}

void ring_pulls(const double *pos, const double *mass, const double *eps, size_t n, double light, double eps_t,
                const double *pts, int npts, double G, double *acc)
{
    double e2t = eps_t * eps_t;
    int passes = (npts + RING_LANES - 1) / RING_LANES;
#pragma omp parallel for schedule(static)
    for (int pass = 0; pass < passes; pass++) {
        double x[RING_LANES], y[RING_LANES], z[RING_LANES];
        double sx[RING_LANES] = {0}, sy[RING_LANES] = {0}, sz[RING_LANES] = {0};
        int first = pass * RING_LANES;
        for (int p = 0; p < RING_LANES; p++) {
            /* the last pass's spare lanes repeat its last point, and are dropped */
            const double *at = &pts[3 * (first + p < npts ? first + p : npts - 1)];
            x[p] = at[0];
            y[p] = at[1];
            z[p] = at[2];
        }
        ring_pass(pos, mass, eps, n, light, e2t, x, y, z, sx, sy, sz);
        for (int p = 0; p < RING_LANES && first + p < npts; p++) {
            acc[3 * (first + p)] += G * sx[p];
            acc[3 * (first + p) + 1] += G * sy[p];
            acc[3 * (first + p) + 2] += G * sz[p];
        }
    }
}

void ring_average(const double n[3], const double a_host[3], const double *acc, int k, int mirror, double out[3])
{
    double mean[3] = {0, 0, 0};
    for (int p = 0; p < k; p++) {
        double phi = TWO_PI * p / k, rel[3], back[3];
        for (int j = 0; j < 3; j++)
            rel[j] = acc[3 * p + j] - a_host[j];
        if (reflected(mirror, p))
            reflect(n, rel, rel);
        turn(n, cos(phi), -sin(phi), rel, back);
        for (int j = 0; j < 3; j++)
            mean[j] += back[j];
    }
    for (int j = 0; j < 3; j++)
        out[j] = a_host[j] + mean[j] / k;
}

int ring_circular_velocity(const double c[3], const double n[3], const double a_host[3], const double v_host[3],
                           const double x[3], const double a[3], const double v[3], double out[3])
{
    double d[3] = {x[0] - c[0], x[1] - c[1], x[2] - c[2]};
    double height = n[0] * d[0] + n[1] * d[1] + n[2] * d[2], p[3], t[3];
    for (int k = 0; k < 3; k++)
        p[k] = d[k] - height * n[k]; /* from the axis to x, across it */
    double R = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    if (!(R > 0))
        return 0;
    ring_cross(n, p, t);
    double inward = 0, turning = 0;
    for (int k = 0; k < 3; k++) {
        t[k] /= R;
        inward -= (a[k] - a_host[k]) * p[k] / R;
        turning += (v[k] - v_host[k]) * t[k];
    }
    if (!(inward > 0) || turning == 0)
        return 0;
    double speed = copysign(sqrt(R * inward), turning);
    for (int k = 0; k < 3; k++)
        out[k] = v_host[k] + speed * t[k];
    return 1;
}
