#include "core/ssp.h"

#include <math.h>

#include "core/ssp_data.h"

/* The cell [i, i+1] of an increasing table holding log10(v), and where v
 * lies in it (0..1), clamped to the table's ends. Tables are short (25 and
 * 11 entries), so a linear scan is as fast as a search. */
static int log_cell(const double *table, int n, double v, double *frac)
{
    double lv = v > 0 ? log10(v) : -INFINITY;
    double lo = log10(table[0]), hi = log10(table[n - 1]);
    if (lv <= lo) {
        *frac = 0;
        return 0;
    }
    if (lv >= hi) {
        *frac = 1;
        return n - 2;
    }
    int i = 0;
    while (i < n - 2 && lv >= log10(table[i + 1]))
        i++;
    double a = log10(table[i]), b = log10(table[i + 1]);
    *frac = (lv - a) / (b - a);
    return i;
}

static double bilinear(const double m[ORR_SSP_NZ][ORR_SSP_NAGE], int iz, double fz, int ia, double fa)
{
    double low = m[iz][ia] + fa * (m[iz][ia + 1] - m[iz][ia]);
    double high = m[iz + 1][ia] + fa * (m[iz + 1][ia + 1] - m[iz + 1][ia]);
    return low + fz * (high - low);
}

int orr_ssp_lookup(double age_yr, double z, orr_ssp_colour *out)
{
    if (isnan(age_yr) || isnan(z))
        return 0;
    double fa, fz;
    int ia = log_cell(orr_ssp_age_yr, ORR_SSP_NAGE, age_yr, &fa);
    int iz = log_cell(orr_ssp_metallicity, ORR_SSP_NZ, z, &fz);
    double b = bilinear(orr_ssp_bmag, iz, fz, ia, fa);
    double v = bilinear(orr_ssp_vmag, iz, fz, ia, fa);
    out->bv = b - v;
    out->mv = v;
    out->lv_per_msun = pow(10.0, -0.4 * (v - ORR_SSP_SUN_MV));
    return 1;
}

/* 1 / (100 km/s/Mpc) in Julian years: 1 Mpc = 3.0856775814913673e19 km
 * (IAU 2012 au, parsec by definition), 1 yr = 31557600 s. */
#define HUBBLE_TIME_YR_H1 (3.0856775814913673e19 / 100.0 / 31557600.0)

double orr_cosmic_time_yr(double a, double h, double omega_m)
{
    if (!(a > 0))
        return NAN;
    double hubble_time = HUBBLE_TIME_YR_H1 / h;
    double omega_l = 1.0 - omega_m;
    double a32 = a * sqrt(a);
    if (omega_l <= 0)
        return 2.0 / 3.0 * hubble_time * a32;
    return 2.0 / (3.0 * sqrt(omega_l)) * hubble_time * asinh(sqrt(omega_l / omega_m) * a32);
}
