/* The solar neighbourhood's luminosity function per solar mass, and the
 * colours of its stars (stars/luminosity.h). */
#include "stars/luminosity.h"

#include <math.h>

/* Allen's Astrophysical Quantities (3rd ed., 1973), section 117: log10 of
 * phi(M_V), stars per pc^3 per magnitude, for M_V = -6, -5, ..., +22, and the
 * mass density of those stars, 1e-4 solar masses per pc^3 per magnitude. */
#define LF_BINS 29
#define LF_FIRST_M (-6.0)
static const double lf_log_phi_v[LF_BINS] = {
    -7.9, -7.2, -6.54, -5.90, -5.28, -4.60, -3.95, -3.46, -3.20, -2.94, -2.72, -2.47, -2.37, -2.45, -2.38,
    -2.27, -2.11, -2.01, -1.97, -1.93, -1.89, -1.90, -1.92, -1.97, -2.08, -2.3, -2.5, -2.9, -3.3};
static const double lf_mass_density_e4[LF_BINS] = {
    0.005, 0.02, 0.06, 0.17, 0.5, 1.6, 4, 10, 12, 18, 23, 37, 38, 26, 26,
    29, 34, 35, 34, 28, 23, 20, 15, 9, 6, 4, 2, 1, 1};

/* The main sequence: absolute V magnitude and B-V of dwarfs from O3 V to
 * M8.5 V, every third row of Pecaut & Mamajek (2013, ApJS 208, 9; E.
 * Mamajek's table, version 2024.05.15). */
#define MS_ROWS 27
static const double ms_mv[MS_ROWS] = {-5.8, -4.8, -3.9, -2.6, -1.2, -0.55, 0.5, 1.16, 1.94, 2.23, 2.57, 3.08, 3.69, 4.25,
                                      4.62, 4.93, 5.2, 5.78, 6.53, 7.64, 8.56, 9.64, 10.61, 12.61, 15.3, 17.7, 19.2};
static const double ms_bv[MS_ROWS] = {-0.33, -0.318, -0.301, -0.252, -0.178, -0.14, -0.07, 0.035, 0.14,
                                      0.21,  0.295,  0.39,   0.486,  0.56,   0.622, 0.67, 0.71,  0.816,
                                      0.99,  1.24,   1.4,    1.485,  1.522,  1.65,  1.94, 2.12,  2.16};

/* Linear interpolation in a table of n increasing abscissae, clamped at the
 * ends. */
static double interpolate(const double *xs, const double *ys, int n, double x)
{
    if (x <= xs[0])
        return ys[0];
    if (x >= xs[n - 1])
        return ys[n - 1];
    int k = 0;
    while (x > xs[k + 1])
        k++;
    double t = (x - xs[k]) / (xs[k + 1] - xs[k]);
    return ys[k] + t * (ys[k + 1] - ys[k]);
}

/* phi(m), stars per pc^3 per magnitude: log phi linear between the bin
 * centres, the end bins' values over their outer halves. */
static double phi_at(double m)
{
    double pos = m - LF_FIRST_M;
    if (pos <= 0)
        return pow(10.0, lf_log_phi_v[0]);
    if (pos >= LF_BINS - 1)
        return pow(10.0, lf_log_phi_v[LF_BINS - 1]);
    int k = (int)pos;
    double t = pos - k;
    return pow(10.0, lf_log_phi_v[k] + t * (lf_log_phi_v[k + 1] - lf_log_phi_v[k]));
}

double orr_lf_luminosity(double m) { return pow(10.0, -0.4 * (m - ORR_LF_SUN_MV)); }

void orr_lf_solar_neighbourhood(orr_lf *lf)
{
    double rho = 0;
    for (int k = 0; k < LF_BINS; k++)
        rho += lf_mass_density_e4[k] * 1e-4;
    lf->mass_density = rho;
    /* The trapezoid rule on the steps: phi varies by at most 0.05 dex in one. */
    lf->count[0] = lf->light[0] = 0;
    for (int k = 1; k <= ORR_LF_STEPS; k++) {
        double m0 = ORR_LF_M_BRIGHT + (k - 1) * ORR_LF_STEP, m1 = m0 + ORR_LF_STEP;
        double n0 = phi_at(m0) / rho, n1 = phi_at(m1) / rho;
        lf->count[k] = lf->count[k - 1] + 0.5 * ORR_LF_STEP * (n0 + n1);
        lf->light[k] = lf->light[k - 1] + 0.5 * ORR_LF_STEP * (n0 * orr_lf_luminosity(m0) + n1 * orr_lf_luminosity(m1));
    }
}

/* Linear between the steps of a cumulative table, 0 before it, its total
 * after it. */
static double cumulative_at(const double *table, double m)
{
    double pos = (m - ORR_LF_M_BRIGHT) / ORR_LF_STEP;
    if (!(pos > 0))
        return 0;
    if (pos >= ORR_LF_STEPS)
        return table[ORR_LF_STEPS];
    int k = (int)pos;
    return table[k] + (pos - k) * (table[k + 1] - table[k]);
}

double orr_lf_count_brighter(const orr_lf *lf, double m) { return cumulative_at(lf->count, m); }
double orr_lf_light_brighter(const orr_lf *lf, double m) { return cumulative_at(lf->light, m); }
double orr_lf_light_per_mass(const orr_lf *lf) { return lf->light[ORR_LF_STEPS]; }

/* The magnitude within step lo, where count[lo] < count <= count[lo + 1]. */
static double magnitude_in_step(const orr_lf *lf, int lo, double count)
{
    double t = (count - lf->count[lo]) / (lf->count[lo + 1] - lf->count[lo]);
    return ORR_LF_M_BRIGHT + (lo + t) * ORR_LF_STEP;
}

/* Bisection of count[lo .. hi] for the last step below count, given
 * count[lo] < count <= count[hi]. That step is the one index k with
 * count[k] < count <= count[k + 1] (the table never falls), so any search
 * that finds it gives the same magnitude, bit for bit. */
static int step_below(const orr_lf *lf, int lo, int hi, double count)
{
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (lf->count[mid] < count)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

double orr_lf_magnitude_at(const orr_lf *lf, double count)
{
    if (!(count > 0))
        return ORR_LF_M_BRIGHT;
    if (count >= lf->count[ORR_LF_STEPS])
        return ORR_LF_M_FAINT;
    return magnitude_in_step(lf, step_below(lf, 0, ORR_LF_STEPS, count), count);
}

double orr_lf_magnitude_from(const orr_lf *lf, double count, int *step)
{
    if (!(count > 0))
        return ORR_LF_M_BRIGHT;
    if (count >= lf->count[ORR_LF_STEPS])
        return ORR_LF_M_FAINT;
    int lo = *step >= 0 && *step < ORR_LF_STEPS && lf->count[*step] < count ? *step : 0;
    /* Gallop forward from the last step to bracket count, then bisect. */
    int reach = 1;
    while (lo + reach < ORR_LF_STEPS && lf->count[lo + reach] < count) {
        lo += reach;
        reach *= 2;
    }
    int hi = lo + reach < ORR_LF_STEPS ? lo + reach : ORR_LF_STEPS;
    *step = step_below(lf, lo, hi, count);
    return magnitude_in_step(lf, *step, count);
}

/* Giants by absolute magnitude: our approximation of the solar
 * neighbourhood's mix (docs/sky.md): the red clump at M_V = +0.8 and the
 * giant branch above it outnumber the B and A dwarfs of the same
 * magnitudes; the supergiants among the brightest; subgiants fading out
 * by M_V = +3.5, below which every star is a dwarf. */
#define GIANT_ROWS 7
static const double giant_m[GIANT_ROWS] = {-3.0, -1.0, 0.0, 1.0, 2.0, 3.0, 3.5};
static const double giant_share[GIANT_ROWS] = {0.25, 0.55, 0.65, 0.65, 0.3, 0.1, 0.0};
/* Their B-V: K giants of the clump near 1.0, redder up the branch to the M
 * giants near 1.6, subgiants near 0.9. */
#define GIANT_BV_ROWS 5
static const double giant_bv_m[GIANT_BV_ROWS] = {-3.0, -1.0, 0.8, 2.0, 3.5};
static const double giant_bv[GIANT_BV_ROWS] = {1.6, 1.3, 1.0, 0.95, 0.9};

double orr_lf_giant_fraction(double m) { return interpolate(giant_m, giant_share, GIANT_ROWS, m); }

double orr_lf_star_bv(double m, double u)
{
    double g = orr_lf_giant_fraction(m);
    if (u < g) {
        /* Spread along the branch by the draw itself: +-0.1 mag. */
        double spread = 0.2 * (u / g - 0.5);
        return interpolate(giant_bv_m, giant_bv, GIANT_BV_ROWS, m) + spread;
    }
    return interpolate(ms_mv, ms_bv, MS_ROWS, m);
}
