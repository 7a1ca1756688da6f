/* A simple-stellar-population magnitude table (CMD 3.7, PARSEC + COLIBRI,
 * Kroupa IMF; source and extraction in ssp_data.c and
 * scripts/gen_ssp_table.py): absolute B and V magnitudes of a population
 * of 1 solar mass formed in one burst, by age and metallicity. */
#ifndef ORR_CORE_SSP_DATA_H
#define ORR_CORE_SSP_DATA_H

#define ORR_SSP_NAGE 25
#define ORR_SSP_NZ 11

/* Increasing; ages evenly spaced in log10 (0.15 dex), metallicities (metal
 * mass fraction Z) nearly so (0.2 dex in [M/H], rounded by CMD). */
extern const double orr_ssp_age_yr[ORR_SSP_NAGE];
extern const double orr_ssp_metallicity[ORR_SSP_NZ];

/* [metallicity][age], mag per solar mass. */
extern const double orr_ssp_bmag[ORR_SSP_NZ][ORR_SSP_NAGE];
extern const double orr_ssp_vmag[ORR_SSP_NZ][ORR_SSP_NAGE];

#endif
