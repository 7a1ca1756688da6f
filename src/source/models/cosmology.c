/* Background cosmology and the linear power spectrum for the initial
 * conditions generator (zeldovich.h). */
#include "source/models/zeldovich.h"

#include <math.h>

#define PI 3.14159265358979323846
#define T_CMB 2.7255 /* K, Fixsen (2009) */

orr_cosmology orr_cosmology_default(void)
{
    /* Planck 2018, TT,TE,EE+lowE+lensing (A&A 641, A6, table 2), rounded. */
    return (orr_cosmology){.omega_m = 0.315, .omega_lambda = 0.685, .omega_b = 0.049, .h = 0.674,
                           .sigma8 = 0.811, .n_s = 0.965};
}

static orr_status check_range(const char *name, double v, double lo, double hi, int lo_open, orr_error *err)
{
    int ok = isfinite(v) && (lo_open ? v > lo : v >= lo) && v <= hi;
    if (!ok)
        return orr_fail(err, ORR_ERR_USAGE, "%s %g: expected a value in %c%g, %g]", name, v, lo_open ? '(' : '[',
                        lo, hi);
    return ORR_OK;
}

orr_status orr_cosmology_check(const orr_cosmology *c, orr_error *err)
{
    orr_status st = check_range("omega_m", c->omega_m, 0, 2, 1, err);
    if (!st)
        st = check_range("omega_lambda", c->omega_lambda, -1, 2, 0, err);
    if (!st)
        st = check_range("omega_b", c->omega_b, 0, c->omega_m, 0, err);
    if (!st)
        st = check_range("h", c->h, 0.2, 2, 0, err);
    if (!st)
        st = check_range("sigma8", c->sigma8, 0, 10, 1, err);
    if (!st)
        st = check_range("n_s", c->n_s, 0, 3, 1, err);
    if (st)
        return st;
    /* E(a)² must stay positive from a = 0 to 1, or the model recollapses
     * or bounces in the past and D(a) below is meaningless. */
    for (int i = 1; i <= 100; i++) {
        double a = i / 100.0;
        double ok_k = 1 - c->omega_m - c->omega_lambda;
        double e2 = c->omega_m / (a * a * a) + ok_k / (a * a) + c->omega_lambda;
        if (!(e2 > 0))
            return orr_fail(err, ORR_ERR_USAGE,
                            "omega_m %g, omega_lambda %g: H(a)² is not positive at a = %g (no big bang model)",
                            c->omega_m, c->omega_lambda, a);
    }
    return ORR_OK;
}

double orr_hubble_e(const orr_cosmology *c, double a)
{
    double ok_k = 1 - c->omega_m - c->omega_lambda;
    return sqrt(c->omega_m / (a * a * a) + ok_k / (a * a) + c->omega_lambda);
}

/* I(a) = ∫0^a da' / (a' E(a'))³, by Simpson's rule. The integrand goes as
 * a'^(3/2) near 0, smooth enough for a few thousand intervals to give
 * ~1e-8. */
static double growth_integral(const orr_cosmology *c, double a)
{
    const int n = 4000; /* even */
    double h = a / n, sum = 0;
    for (int i = 1; i <= n; i++) {
        double x = i * h;
        double xe = x * orr_hubble_e(c, x);
        double g = 1.0 / (xe * xe * xe);
        sum += (i == n ? 1 : (i % 2 ? 4 : 2)) * g;
    }
    return sum * h / 3; /* the integrand is 0 at a' = 0 */
}

/* Heath (1977, MNRAS 179, 351): for matter, curvature and Λ the growing
 * mode is D(a) ∝ E(a) ∫0^a da' / (a' E(a'))³ (also Peebles 1980, §10). */
static double growth_unnormalised(const orr_cosmology *c, double a)
{
    return orr_hubble_e(c, a) * growth_integral(c, a);
}

double orr_growth_factor(const orr_cosmology *c, double a)
{
    return growth_unnormalised(c, a) / growth_unnormalised(c, 1.0);
}

double orr_growth_rate(const orr_cosmology *c, double a)
{
    /* Differentiating Heath's integral: f = d ln E / d ln a + 1 / (a² E³ I). */
    double ok_k = 1 - c->omega_m - c->omega_lambda;
    double e = orr_hubble_e(c, a);
    double dlne = (-3 * c->omega_m / (a * a * a) - 2 * ok_k / (a * a)) / (2 * e * e);
    return dlne + 1.0 / (a * a * e * e * e * growth_integral(c, a));
}

/* Eisenstein & Hu (1998, ApJ 496, 605), the transfer function without
 * baryon oscillations: equations (26) sound horizon, (31) alpha_Gamma, (30)
 * the scale-dependent shape Gamma_eff, (28) q and (29) T0. */
double orr_transfer_eh98(const orr_cosmology *c, double k)
{
    double theta = T_CMB / 2.7;
    double om_h2 = c->omega_m * c->h * c->h;
    double ob_h2 = c->omega_b * c->h * c->h;
    double fb = c->omega_b / c->omega_m;
    double s = 44.5 * log(9.83 / om_h2) / sqrt(1 + 10 * pow(ob_h2, 0.75)); /* Mpc */
    double alpha = 1 - 0.328 * log(431 * om_h2) * fb + 0.38 * log(22.3 * om_h2) * fb * fb;
    double ks = 0.43 * k * c->h * s; /* k in 1/Mpc times s */
    double gamma = c->omega_m * c->h * (alpha + (1 - alpha) / (1 + ks * ks * ks * ks));
    double q = k * theta * theta / gamma;
    double l0 = log(2 * exp(1.0) + 1.8 * q);
    double c0 = 14.2 + 731 / (1 + 62.5 * q);
    return l0 / (l0 + c0 * q * q);
}

static double unnormalised_power(const orr_cosmology *c, double k)
{
    double t = orr_transfer_eh98(c, k);
    return pow(k, c->n_s) * t * t;
}

/* The Fourier transform of a top-hat sphere, 3 (sin x − x cos x) / x³,
 * by its series below x = 1e-3 where the difference cancels. */
static double tophat_window(double x)
{
    if (x < 1e-3)
        return 1 - x * x / 10;
    return 3 * (sin(x) - x * cos(x)) / (x * x * x);
}

/* σ²(r) = ∫ k³ P(k) W²(kr) / (2π²) d ln k, Simpson's rule in ln k from
 * 1e-5 to 1e3 h/Mpc (the integrand is negligible outside for r ~ 1-100). */
static double sigma2_r(const orr_cosmology *c, double amplitude, double r)
{
    const int n = 6000; /* even */
    const double lo = log(1e-5), hi = log(1e3);
    double h = (hi - lo) / n, sum = 0;
    for (int i = 0; i <= n; i++) {
        double k = exp(lo + i * h);
        double w = tophat_window(k * r);
        double g = k * k * k * amplitude * unnormalised_power(c, k) * w * w / (2 * PI * PI);
        sum += (i == 0 || i == n ? 1 : (i % 2 ? 4 : 2)) * g;
    }
    return sum * h / 3;
}

orr_status orr_power_init(orr_power *p, const orr_cosmology *c, orr_error *err)
{
    orr_status st = orr_cosmology_check(c, err);
    if (st)
        return st;
    p->cosmo = *c;
    p->amplitude = c->sigma8 * c->sigma8 / sigma2_r(c, 1.0, 8.0);
    return ORR_OK;
}

double orr_power_at(const orr_power *p, double k)
{
    return k > 0 ? p->amplitude * unnormalised_power(&p->cosmo, k) : 0.0;
}

double orr_power_sigma_r(const orr_power *p, double r)
{
    return sqrt(sigma2_r(&p->cosmo, p->amplitude, r));
}
