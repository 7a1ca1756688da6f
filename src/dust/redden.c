#include "dust/redden.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/cie_data.h"
#include "core/colourimetry.h"
#include "core/vecmath.h"

/* The second radiation constant hc/k in nm K (CODATA 2018). */
#define C2_NM_K 1.438776877e7

_Static_assert(ORR_CIE1931_FIRST_NM == ORR_DUST_CURVE_FIRST_NM && ORR_CIE1931_STEP_NM == 1,
               "the extinction curve shares the CIE 1931 functions' grid");

/* Planck's B_lambda up to a factor of T alone, scaled so neither cold nor
 * hot bodies under- or overflow (as post/colour.c does). */
static double planck(double lambda_nm, double T)
{
    const double a = C2_NM_K / (lambda_nm * T), a_ref = C2_NM_K / (ORR_DUST_CURVE_LAST_NM * T);
    const double l = lambda_nm * 1e-3;
    return exp(a_ref - a) / (-expm1(-a) * l * l * l * l * l);
}

/* The spectrum's weights on the grid: Planck times the trapezoid rule's
 * weights (the end points count half). */
static void spectrum(double T, double *w)
{
    for (int i = 0; i < ORR_DUST_CURVE_N; i++) {
        w[i] = planck(ORR_DUST_CURVE_FIRST_NM + i, T);
        if (i == 0 || i == ORR_DUST_CURVE_N - 1)
            w[i] *= 0.5;
    }
}

void orr_dust_blackbody_through(double T, double tau, const orr_dust_curve *c, double xyz[3])
{
    double w[ORR_DUST_CURVE_N];
    spectrum(T, w);
    xyz[0] = xyz[1] = xyz[2] = 0;
    for (int i = 0; i < ORR_DUST_CURVE_N; i++) {
        double e = w[i] * exp(-tau * c->a[i]);
        for (int k = 0; k < 3; k++)
            xyz[k] += e * orr_cie1931_2deg[i][k];
    }
}

static double rho_of_teff(double T)
{
    double xyz[3];
    orr_blackbody_xyz(T, ORR_CMF_CIE1931, xyz);
    return log(xyz[2] / xyz[1]);
}

/* The temperature whose blackbody has ln(Z/Y) = rho, by bisection in ln T. */
static double teff_of_rho(double rho)
{
    double lo = log(ORR_BLACKBODY_T_MIN), hi = log(ORR_BLACKBODY_T_MAX);
    for (int it = 0; it < 60; it++) {
        double mid = 0.5 * (lo + hi);
        if (rho_of_teff(exp(mid)) < rho)
            lo = mid;
        else
            hi = mid;
    }
    return exp(0.5 * (lo + hi));
}

/* One row: ln t_c at every column, the attenuation stepped by a constant
 * factor per column so the whole row takes one exponential per wavelength. */
static void fill_row(const orr_dust_curve *c, double T, float *row)
{
    double w[ORR_DUST_CURVE_N], step[ORR_DUST_CURVE_N], base[3] = {0, 0, 0};
    spectrum(T, w);
    for (int i = 0; i < ORR_DUST_CURVE_N; i++) {
        step[i] = exp(-ORR_DUST_TAU_STEP * c->a[i]);
        for (int k = 0; k < 3; k++)
            base[k] += w[i] * orr_cie1931_2deg[i][k];
    }
    for (int j = 0; j < ORR_DUST_TAU_COLS; j++) {
        double sum[3] = {0, 0, 0};
        for (int i = 0; i < ORR_DUST_CURVE_N; i++) {
            for (int k = 0; k < 3; k++)
                sum[k] += w[i] * orr_cie1931_2deg[i][k];
            w[i] *= step[i];
        }
        for (int k = 0; k < 3; k++)
            row[3 * j + k] = (float)log(sum[k] / base[k]);
    }
}

orr_status orr_dust_redden_build(orr_dust_redden *r, const orr_dust_curve *c, orr_error *err)
{
    memset(r, 0, sizeof *r);
    const size_t per_row = 3 * (size_t)ORR_DUST_TAU_COLS;
    r->lnt = orr_malloc(ORR_DUST_REDDEN_ROWS * per_row * sizeof *r->lnt, "reddening table", err);
    if (!r->lnt)
        return ORR_ERR_NOMEM;
    const double rho_min = rho_of_teff(ORR_BLACKBODY_T_MIN), rho_max = rho_of_teff(ORR_BLACKBODY_T_MAX);
    r->rho0 = rho_min;
    r->inv_drho = (ORR_DUST_REDDEN_ROWS - 1) / (rho_max - rho_min);
    for (int i = 0; i < ORR_DUST_REDDEN_ROWS; i++)
        r->row_teff[i] = teff_of_rho(rho_min + i / r->inv_drho);
    /* Rows are independent: the same values on any number of threads. */
#pragma omp parallel for schedule(dynamic, 4)
    for (int i = 0; i < ORR_DUST_REDDEN_ROWS; i++)
        fill_row(c, r->row_teff[i], r->lnt + (size_t)i * per_row);
    return ORR_OK;
}

void orr_dust_redden_free(orr_dust_redden *r)
{
    free(r->lnt);
    memset(r, 0, sizeof *r);
}

/* ln t of one row at tau: linear between columns, on the last slope beyond. */
static inline void row_at(const float *row, double tau, double out[3])
{
    double u = tau * (1.0 / ORR_DUST_TAU_STEP);
    int j = (int)u;
    if (j > ORR_DUST_TAU_COLS - 2)
        j = ORR_DUST_TAU_COLS - 2;
    double f = u - j;
    const float *a = row + 3 * j;
    for (int k = 0; k < 3; k++)
        out[k] = a[k] + f * (a[k + 3] - a[k]);
}

void orr_dust_redden_apply(const orr_dust_redden *r, double tau, float xyz[3])
{
    if (!(tau > 0))
        return;
    if (!(xyz[1] > 0) || !(xyz[2] > 0)) {
        const float grey = (float)exp(-tau);
        for (int k = 0; k < 3; k++)
            xyz[k] *= grey;
        return;
    }
    double f;
    const int i = orr_table_cell((log((double)xyz[2] / xyz[1]) - r->rho0) * r->inv_drho, ORR_DUST_REDDEN_ROWS, &f);
    const size_t per_row = 3 * (size_t)ORR_DUST_TAU_COLS;
    double a[3], b[3];
    row_at(r->lnt + (size_t)i * per_row, tau, a);
    row_at(r->lnt + (size_t)(i + 1) * per_row, tau, b);
    for (int k = 0; k < 3; k++)
        xyz[k] = (float)(xyz[k] * exp(a[k] + f * (b[k] - a[k])));
}
