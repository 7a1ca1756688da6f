/* Reddening in colour (docs/dust.md): the CIE X, Y, Z of a star seen
 * through optical depth tau_V are its spectrum times exp(-tau_V A_lambda/A_V)
 * against the colour-matching functions. For a blackbody each channel is
 * dimmed by its own factor t_c(T, tau) = integral B_T e^(-tau a) cbar /
 * integral B_T cbar, which this table holds (as ln t_c) over the star's
 * colour and tau_V, so the renderer dims a star's three weights by three
 * table lookups.
 *
 * The table is indexed not by T but by rho = ln(Z/Y), which grows
 * monotonically with a blackbody's temperature: a star's weights give its
 * row directly, whatever set its colour (a temperature, B-V, or a fixed
 * colour, which is treated as the blackbody of the same Z/Y: exact for
 * blackbodies, an approximation for other colours). Rows are uniform in rho
 * between the blackbodies at ORR_BLACKBODY_T_MIN and _MAX (colours beyond
 * are clamped); columns uniform in tau_V up to ORR_DUST_TAU_MAX, beyond
 * which ln t_c continues on the last column's slope. Built with the CIE 1931
 * functions. */
#ifndef ORR_DUST_REDDEN_H
#define ORR_DUST_REDDEN_H

#include "core/error.h"
#include "dust/curve.h"

#define ORR_DUST_REDDEN_ROWS 256
#define ORR_DUST_TAU_STEP 0.05
#define ORR_DUST_TAU_COLS 401 /* tau_V = 0 .. 20 */
#define ORR_DUST_TAU_MAX (ORR_DUST_TAU_STEP * (ORR_DUST_TAU_COLS - 1))

typedef struct orr_dust_redden {
    double rho0, inv_drho; /* row i at rho0 + i / inv_drho */
    double row_teff[ORR_DUST_REDDEN_ROWS]; /* the blackbody temperature of each row, K */
    float *lnt; /* [row][col][3]: ln t_X, ln t_Y, ln t_Z */
} orr_dust_redden;

/* Builds the table for the curve (about 0.1 s). */
orr_status orr_dust_redden_build(orr_dust_redden *r, const orr_dust_curve *c, orr_error *err);
void orr_dust_redden_free(orr_dust_redden *r);

/* Multiplies xyz (a star's weights, any scale) by the transmissions at
 * optical depth tau (>= 0). Weights with Y <= 0 only get the grey factor
 * e^-tau. */
void orr_dust_redden_apply(const orr_dust_redden *r, double tau, float xyz[3]);

/* Planck's law times e^(-tau a) integrated against the CIE 1931 functions
 * directly (trapezoid rule, 1 nm), X, Y, Z up to a common factor: for the
 * table and for checks. */
void orr_dust_blackbody_through(double T, double tau, const orr_dust_curve *c, double xyz[3]);

#endif
