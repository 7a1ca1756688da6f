/* Colour reference tables, generated from the published data by
 * scripts/gen_colour_tables.py (sources named in cie_data.c):
 *   - the CIE 1931 2-degree colour-matching functions, 1 nm, 360-830 nm;
 *   - the Judd-Vos modified 2-degree functions, 5 nm, 380-825 nm;
 *   - Mamajek's mean dwarf sequence, B-V and T_eff, O3V to M9V. */
#ifndef ORR_CORE_CIE_DATA_H
#define ORR_CORE_CIE_DATA_H

/* First wavelength and step of each set, in nm: row i is at FIRST + i STEP. */
#define ORR_CIE1931_FIRST_NM 360
#define ORR_CIE1931_STEP_NM 1
#define ORR_JUDD_VOS_FIRST_NM 380
#define ORR_JUDD_VOS_STEP_NM 5

/* Rows of (xbar, ybar, zbar). */
extern const double orr_cie1931_2deg[][3];
extern const int orr_cie1931_2deg_count;
extern const double orr_judd_vos_2deg[][3];
extern const int orr_judd_vos_2deg_count;

typedef struct orr_bv_teff {
    double bv;   /* Johnson B-V, mag */
    double teff; /* K */
} orr_bv_teff;

/* Ordered by increasing B-V (and so decreasing T_eff), strictly. */
extern const orr_bv_teff orr_mamajek_dwarfs[];
extern const int orr_mamajek_dwarfs_count;

#endif
