/* The colour and brightness of a simple stellar population (docs/colour.md,
 * "Stellar ages"): B-V and the V luminance per unit mass of stars born in
 * one burst, from their age and metallicity, looked up in the CMD/PARSEC
 * table of ssp_data.c; and the cosmic time of a scale factor, to turn the
 * formation scale factors that cosmological snapshots store into ages. */
#ifndef ORR_CORE_SSP_H
#define ORR_CORE_SSP_H

/* The absolute V magnitude of the Sun (Willmer 2018, ApJS 236, 47: 4.81;
 * 4.83 is the classical value in Binney & Merrifield; the choice only
 * scales every SSP luminance alike). */
#define ORR_SSP_SUN_MV 4.83

typedef struct orr_ssp_colour {
    double bv; /* B - V, mag */
    double mv; /* absolute V magnitude of 1 solar mass of the population */
    /* The V luminance per solar mass in solar units, 10^(-0.4 (mv - M_V,sun)):
     * 79 at 4 Myr, 5.9 at 100 Myr and 0.14 at 10 Gyr for Z = 0.0152. */
    double lv_per_msun;
} orr_ssp_colour;

/* B-V and M_V of a population of age age_yr (years) and metal mass
 * fraction z, bilinear in log10(age) and log10(Z) between the table's
 * points. Outside the table the nearest edge is used (clamped): ages below
 * 3.98 Myr (including 0 and negative ages, a star formed "after" the
 * snapshot by rounding) take the youngest row, above 15.8 Gyr the oldest;
 * Z below 0.00016 (including Z = 0, the primordial stars of a simulation)
 * the most metal-poor column, above 0.01471 (about solar) the most
 * metal-rich. Returns 0 (out untouched) when age_yr or z is NaN. */
int orr_ssp_lookup(double age_yr, double z, orr_ssp_colour *out);

/* Cosmic time in years at scale factor a > 0 in a flat universe of matter
 * and a cosmological constant (radiation neglected: it changes a 1 Gyr
 * age by a few kyr), Hubble constant 100 h km/s/Mpc and matter density
 * omega_m in (0, 1]:
 *   t(a) = 2 / (3 H0 sqrt(1 - omega_m)) asinh(sqrt((1 - omega_m)/omega_m) a^1.5),
 * and 2 a^1.5 / (3 H0) for omega_m = 1. NaN for a <= 0 or NaN. */
double orr_cosmic_time_yr(double a, double h, double omega_m);

#endif
