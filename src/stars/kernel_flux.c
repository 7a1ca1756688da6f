/* The flux from light spread over a Gaussian kernel (stars/kernel_flux.h). */
#include "stars/kernel_flux.h"

#include <math.h>
#include <stddef.h>

/* The kernel is taken this many sigmas either side of its centre: beyond,
 * exp(-32) of it. */
#define REACH_SIGMAS 8.0
/* Beyond this many sigmas the asymptotic series is exact to double
 * rounding (its smallest term, at the 32nd, is about 1e-14) and cheaper. */
#define FAR_SIGMAS 8.0
/* Each piece of the quadrature at most this many sigmas wide: eight
 * Gauss-Legendre points integrate a Gaussian over two sigmas to about
 * 1e-9 (tests/unit/test_kernel_flux.c). */
#define PIECE_SIGMAS 2.0

/* Gauss-Legendre's eight points on [-1, 1], the positive half (the
 * Legendre polynomial P8's roots and their weights). */
static const double gl_x[4] = {0.18343464249564980, 0.52553240991632899, 0.79666647741362674, 0.96028985649753623};
static const double gl_w[4] = {0.36268378337836198, 0.31370664587788729, 0.22238103445337447, 0.10122853629037626};

double orr_kernel_q(double s, double mu, double sigma)
{
    const double inv2s2 = 0.5 / (sigma * sigma), t = s * mu / (sigma * sigma);
    const double norm = sqrt(2.0 / 3.14159265358979323846) / (sigma * sigma * sigma);
    if (t < 1e-4) /* sinh(t) / t = 1 + t^2 / 6 + ... */
        return norm * exp(-(s * s + mu * mu) * inv2s2) * (1.0 + t * t / 6.0);
    /* exp(-(s^2 + mu^2) / 2 sigma^2) sinh(t) = (exp(-(s - mu)^2 / 2 sigma^2) - exp(-(s + mu)^2 / 2 sigma^2)) / 2,
     * which cannot overflow however far the kernel is. */
    const double near = exp(-(s - mu) * (s - mu) * inv2s2), far = exp(-(s + mu) * (s + mu) * inv2s2);
    return norm * 0.5 * (near - far) / t;
}

/* Adds the integrals over one piece [a, b], eight points, to *part. */
static void integrate_piece(double mu, double sigma, double a, double b, orr_kernel_weight w, const void *user,
                            orr_kernel_part *part)
{
    const double mid = 0.5 * (a + b), half = 0.5 * (b - a);
    for (int k = 0; k < 8; k++) {
        const double s = mid + (k < 4 ? -gl_x[k] : gl_x[k - 4]) * half;
        const double weight = gl_w[k & 3] * half * orr_kernel_q(s, mu, sigma) * (w ? w(s, user) : 1.0);
        part->flux += weight;
        part->light += weight * s * s;
    }
}

/* Adds the integrals over [a, b] to *part, in pieces at most PIECE_SIGMAS
 * wide; w NULL: weight 1. A weight changes with the apparent magnitude, as
 * log s: its pieces also end at most at twice their start, so that near
 * the observer, where log s runs fast, each piece spans at most 1.5
 * magnitudes of it. */
static void integrate(double mu, double sigma, double a, double b, orr_kernel_weight w, const void *user,
                      orr_kernel_part *part)
{
    if (!w) {
        if (!(b > a))
            return;
        const int pieces = (int)ceil((b - a) / (PIECE_SIGMAS * sigma));
        const double width = (b - a) / pieces;
        for (int p = 0; p < pieces; p++)
            integrate_piece(mu, sigma, a + p * width, p + 1 < pieces ? a + (p + 1) * width : b, NULL, NULL, part);
        return;
    }
    while (b > a) {
        double end = a + PIECE_SIGMAS * sigma;
        if (a > 0 && end > 2 * a)
            end = 2 * a;
        if (end > b)
            end = b;
        integrate_piece(mu, sigma, a, end, w, user, part);
        a = end;
    }
}

double orr_kernel_inv_r2(double mu, double sigma)
{
    if (mu >= FAR_SIGMAS * sigma) {
        /* E[1/s^2] = (1/mu^2) sum_k (2k - 1)!! (sigma/mu)^(2k): Dawson's
         * integral's asymptotic series; its terms fall while (2k + 1) x < 1. */
        const double x = (sigma * sigma) / (mu * mu);
        double sum = 1.0, term = 1.0;
        for (int k = 1; k < 40; k++) {
            const double next = term * (2 * k - 1) * x;
            if (next >= term || next < 1e-17 * sum)
                break;
            term = next;
            sum += term;
        }
        return sum / (mu * mu);
    }
    orr_kernel_part part = {0, 0};
    integrate(mu, sigma, 0.0, mu + REACH_SIGMAS * sigma, NULL, NULL, &part);
    return part.flux;
}

orr_kernel_part orr_kernel_weighted(double mu, double sigma, double a, double b, double split, orr_kernel_weight w,
                                    const void *user)
{
    orr_kernel_part part = {0, 0};
    /* Only where the kernel is. */
    const double lo = mu - REACH_SIGMAS * sigma, hi = mu + REACH_SIGMAS * sigma;
    a = a > lo ? a : lo;
    a = a > 0 ? a : 0;
    b = b < hi ? b : hi;
    if (split > a && split < b) {
        integrate(mu, sigma, a, split, w, user, &part);
        integrate(mu, sigma, split, b, w, user, &part);
    } else {
        integrate(mu, sigma, a, b, w, user, &part);
    }
    return part;
}
