/* The flux an observer receives from light spread over a particle's
 * kernel (docs/sky.md, "The glow's flux"): a 3-D Gaussian of width sigma
 * whose centre is mu away. A point of light L at distance s gives L / s^2;
 * spread over the kernel it gives L E[1/s^2], which is 1/mu^2 far away and
 * 1/sigma^2 at the centre, instead of growing without bound as the particle
 * passes the observer.
 *
 * Written with the distance s from the observer, the kernel's density of s
 * over s^2 is
 *     q(s) = f(s) / s^2 = sqrt(2/pi) / sigma^3 exp(-(s^2 + mu^2) / 2 sigma^2) sinh(t) / t,
 *     t = s mu / sigma^2,
 * smooth and finite everywhere (the s^2 of the volume cancels the 1/s^2 of
 * the flux), so E[1/s^2] = int_0^inf q(s) ds, and the light in a shell is
 * q(s) s^2 ds. In closed form E[1/s^2] = sqrt(2) / (sigma mu) D(mu / (sqrt(2)
 * sigma)), D Dawson's integral; tests/unit/test_kernel_flux.c checks the
 * functions here against it and against a brute-force sum over the sky. */
#ifndef ORR_STARS_KERNEL_FLUX_H
#define ORR_STARS_KERNEL_FLUX_H

/* E[1/s^2] over the kernel (units of 1/length^2, as mu and sigma):
 * quadrature over s near the kernel, its asymptotic series far away.
 * sigma > 0, mu >= 0. */
double orr_kernel_inv_r2(double mu, double sigma);

/* A weight on the distance s from the observer, between 0 and 1: which
 * share of the kernel's light at s is taken elsewhere (drawn as stars). */
typedef double (*orr_kernel_weight)(double s, const void *user);

/* The part of the kernel that w takes, over a <= s <= b (a kink of w at
 * split is integrated on both sides; give split outside [a, b] for none):
 * light = int q(s) s^2 w(s) ds, the share of the light, and
 * flux = int q(s) w(s) ds, its share of E[1/s^2]. */
typedef struct orr_kernel_part {
    double light, flux;
} orr_kernel_part;

orr_kernel_part orr_kernel_weighted(double mu, double sigma, double a, double b, double split, orr_kernel_weight w,
                                    const void *user);

/* The kernel's distance density over s^2, q(s) above. */
double orr_kernel_q(double s, double mu, double sigma);

#endif
