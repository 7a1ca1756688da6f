/* Extinction curves A_lambda / A_V on the wavelength grid of the CIE 1931
 * colour-matching functions (post/cie_data.h: 360-830 nm in 1 nm steps), so
 * a star's reddened colour is one sum over the same rows as its colour
 * (docs/dust.md).
 *
 * - ccm89: Cardelli, Clayton & Mathis (1989, ApJ 345, 245), eq. 3a-3b (the
 *   optical/near-IR polynomials, 1.1 <= x <= 3.3 per micron, which cover the
 *   whole CIE range: x = 1.20 .. 2.78), A_lambda/A_V = a(x) + b(x) / R_V.
 * - f99: Fitzpatrick (1999, PASP 111, 63): a cubic spline in 1/lambda
 *   through anchors that depend on R_V, normalised to 1 at 550 nm as ccm89 is.
 * - a user file: two columns, wavelength in nm and A_lambda/A_V, strictly
 *   increasing wavelengths covering 360-830 nm with no step over
 *   ORR_DUST_CURVE_MAX_GAP_NM, values >= 0; interpolated linearly. */
#ifndef ORR_DUST_CURVE_H
#define ORR_DUST_CURVE_H

#include "core/error.h"

#define ORR_DUST_CURVE_FIRST_NM 360
#define ORR_DUST_CURVE_LAST_NM 830
#define ORR_DUST_CURVE_N (ORR_DUST_CURVE_LAST_NM - ORR_DUST_CURVE_FIRST_NM + 1)
#define ORR_DUST_RV_DEFAULT 3.1
#define ORR_DUST_V_NM 550.0 /* where A_lambda / A_V = 1 */
/* A file's rows may be at most this far apart (nm): wider steps would
 * leave the curve's shape to the interpolation. */
#define ORR_DUST_CURVE_MAX_GAP_NM 50.0

typedef struct orr_dust_curve {
    double a[ORR_DUST_CURVE_N]; /* A_lambda / A_V at FIRST_NM + i nm */
} orr_dust_curve;

/* CCM89 A_lambda/A_V at wavelength lambda_nm (any wavelength of 303-909 nm,
 * the range of eq. 3; NaN outside) for R_V. */
double orr_ccm89(double lambda_nm, double r_v);

/* The CCM89 curve for R_V (> 0; ORR_ERR_USAGE naming dust.r_v otherwise). */
orr_status orr_dust_curve_ccm89(orr_dust_curve *c, double r_v, orr_error *err);

/* F99's A_lambda/E(B-V) (not normalised) at lambda_nm (any wavelength of
 * 260 nm and up, the spline's range; NaN outside) for R_V. */
double orr_f99_ebv(double lambda_nm, double r_v);

/* The F99 curve for R_V, A_lambda/A_V = A_lambda/E(B-V) over its value at
 * 550 nm (ORR_ERR_USAGE naming dust.r_v for R_V not > 0). */
orr_status orr_dust_curve_f99(orr_dust_curve *c, double r_v, orr_error *err);

/* A curve from a two-column text file ('#' comments and blank lines
 * skipped). Errors (ORR_ERR_IO, ORR_ERR_FORMAT) name the file and line:
 * unreadable, a row without two numbers, a NaN or negative value,
 * wavelengths not strictly increasing, a gap wider than
 * ORR_DUST_CURVE_MAX_GAP_NM, or rows not covering 360-830 nm. */
orr_status orr_dust_curve_load(orr_dust_curve *c, const char *path, orr_error *err);

/* The curve at a wavelength in nm (linear between rows; clamped at the ends). */
double orr_dust_curve_at(const orr_dust_curve *c, double lambda_nm);

#endif
