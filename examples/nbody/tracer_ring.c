/* A tracer's pull averaged around its galaxy: the local sums (tracer_ring.h). */
#include "tracer_ring.h"

#include <math.h>
#include <string.h>

#define TWO_PI 6.283185307179586
#define TYPE_DISC 2
#define TYPE_BULGE 3

static double distance2(const double a[3], const double b[3])
{
    return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]);
}

static void cross(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

void ring_star_sums(const double *pos, const double *vel, const double *acc, const double *mass, const uint8_t *type,
                    size_t n, double light, const double centre[3], double radius, double s[RING_SUMS])
{
    for (size_t i = 0; i < n; i++) {
        if (mass[i] < light || (type[i] != TYPE_DISC && type[i] != TYPE_BULGE) ||
            distance2(&pos[3 * i], centre) > radius * radius)
            continue;
        s[0] += mass[i];
        for (int k = 0; k < 3; k++) {
            s[1 + k] += mass[i] * pos[3 * i + k];
            s[4 + k] += mass[i] * vel[3 * i + k];
            s[7 + k] += mass[i] * acc[3 * i + k];
        }
    }
}

void ring_spin_sum(const double *pos, const double *vel, const double *mass, const uint8_t *type, size_t n,
                   uint8_t which, const double c[3], const double v_c[3], double radius, double spin[3])
{
    for (size_t i = 0; i < n; i++) {
        if (type[i] != which || distance2(&pos[3 * i], c) > radius * radius)
            continue;
        double d[3], u[3], l[3];
        for (int k = 0; k < 3; k++) {
            d[k] = pos[3 * i + k] - c[k];
            u[k] = vel[3 * i + k] - v_c[k];
        }
        cross(d, u, l);
        for (int k = 0; k < 3; k++)
            spin[k] += mass[i] * l[k];
    }
}

int ring_host(const double s[RING_SUMS], double c[3], double v[3], double a[3])
{
    if (!(s[0] > 0))
        return 0;
    for (int k = 0; k < 3; k++) {
        c[k] = s[1 + k] / s[0];
        v[k] = s[4 + k] / s[0];
        a[k] = s[7 + k] / s[0];
    }
    return 1;
}

/* v turned by the angle whose cosine and sine are co, si about the unit axis n (Rodrigues). */
static void turn(const double n[3], double co, double si, const double v[3], double out[3])
{
    double nxv[3], along = n[0] * v[0] + n[1] * v[1] + n[2] * v[2];
    cross(n, v, nxv);
    for (int k = 0; k < 3; k++)
        out[k] = v[k] * co + nxv[k] * si + n[k] * along * (1.0 - co);
}

void ring_points(const double c[3], const double n[3], const double x[3], int k, double *pts)
{
    double d[3] = {x[0] - c[0], x[1] - c[1], x[2] - c[2]};
    for (int p = 0; p < k; p++) {
        double phi = TWO_PI * p / k, turned[3];
        turn(n, cos(phi), sin(phi), d, turned);
        for (int j = 0; j < 3; j++)
            pts[3 * p + j] = c[j] + turned[j];
    }
}

void ring_pulls(const double *pos, const double *mass, const double *eps, size_t n, double light, double eps_t,
                const double *pts, int npts, double G, double *acc)
{
    double e2t = eps_t * eps_t;
#pragma omp parallel for schedule(static)
    for (int p = 0; p < npts; p++) {
        const double *x = &pts[3 * p];
        double sum[3] = {0, 0, 0};
        for (size_t i = 0; i < n; i++) {
            if (mass[i] < light)
                continue;
            double d[3] = {pos[3 * i] - x[0], pos[3 * i + 1] - x[1], pos[3 * i + 2] - x[2]};
            double r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + 0.5 * (eps[i] * eps[i] + e2t);
            double w = mass[i] / (r2 * sqrt(r2));
            for (int k = 0; k < 3; k++)
                sum[k] += w * d[k];
        }
        for (int k = 0; k < 3; k++)
            acc[3 * p + k] += G * sum[k];
    }
}

void ring_average(const double n[3], const double a_host[3], const double *acc, int k, double out[3])
{
    double mean[3] = {0, 0, 0};
    for (int p = 0; p < k; p++) {
        double phi = TWO_PI * p / k, rel[3], back[3];
        for (int j = 0; j < 3; j++)
            rel[j] = acc[3 * p + j] - a_host[j];
        turn(n, cos(phi), -sin(phi), rel, back);
        for (int j = 0; j < 3; j++)
            mean[j] += back[j];
    }
    for (int j = 0; j < 3; j++)
        out[j] = a_host[j] + mean[j] / k;
}
