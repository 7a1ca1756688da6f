/* Colourimetry (docs/colour.md): colour-matching functions, blackbodies,
 * B-V to temperature, sRGB and chromaticities, the colours a user gives and
 * colours that change along a run. Every stage that handles colour uses it:
 * particles (a population's colour), post (synthesis), the dust stage.
 *
 * Conventions: XYZ with Y the luminance; "linear sRGB" is Rec. 709 primaries
 * with the D65 white, (1, 1, 1) = white of luminance Y = 1. */
#ifndef ORR_CORE_COLOURIMETRY_H
#define ORR_CORE_COLOURIMETRY_H

#include <stddef.h>

#include "core/error.h"
#include "core/names.h"

/* ---- colour-matching functions ---------------------------------------- */

typedef enum {
    ORR_CMF_CIE1931 = 0, /* CIE 1931 2-degree, 360-830 nm, 1 nm: the standard observer */
    ORR_CMF_JUDD_VOS,    /* Judd-Vos modified 2-degree, 380-825 nm, 5 nm */
} orr_cmf;

extern const orr_named orr_cmf_names[];

/* "cie1931" or "judd-vos"; returns 0 on an unknown name. */
int orr_cmf_from_name(const char *name, orr_cmf *cmf);
const char *orr_cmf_name(orr_cmf cmf);

/* ---- blackbodies ------------------------------------------------------ */

/* Range of the tabulated blackbody; temperatures outside are clamped to it.
 * Below 500 K a blackbody is invisible; above 1e5 K its chromaticity
 * (0.2426, 0.2380) has less than 0.005 left to go to the infinite-temperature
 * limit (0.2399, 0.2340), and no star is hotter than a few 1e5 K. */
#define ORR_BLACKBODY_T_MIN 500.0
#define ORR_BLACKBODY_T_MAX 100000.0

/* XYZ (Y = 1) of a blackbody at T kelvin: Planck's law integrated against
 * the CMFs (trapezoid rule on their own grid). Any T > 0, and T = INFINITY
 * (the Rayleigh-Jeans limit). Returns 0, xyz = 0, for T NaN or <= 0 or an
 * unknown cmf. About 500 exponentials: for tables and tests. */
int orr_blackbody_xyz_exact(double T, orr_cmf cmf, double xyz[3]);

/* The same from a table in log T built on first use (thread-safe), with T
 * clamped to [ORR_BLACKBODY_T_MIN, ORR_BLACKBODY_T_MAX]: a logarithm and a
 * linear interpolation per call, within 1e-6 of the exact chromaticity. */
int orr_blackbody_xyz(double T, orr_cmf cmf, double xyz[3]);

/* ---- B-V to effective temperature ------------------------------------- */

typedef enum {
    /* Mamajek's mean dwarf sequence (Pecaut & Mamajek 2013, version
     * 2024.05.15), interpolated linearly in log T between its 86 points,
     * B-V -0.33 (O3V, 45900 K) to 2.17 (M9V, 2380 K). */
    ORR_BV_MAMAJEK = 0,
    /* Ballesteros (2012, EPL 97, 34008), a blackbody fit:
     * T = 4600 K (1/(0.92 (B-V) + 1.7) + 1/(0.92 (B-V) + 0.62)),
     * used over B-V -0.1 to 1.5, where it is within 6% of Mamajek's table. */
    ORR_BV_BALLESTEROS,
} orr_bv_relation;

extern const orr_named orr_bv_relation_names[];

/* "mamajek" or "ballesteros"; returns 0 on an unknown name. */
int orr_bv_relation_from_name(const char *name, orr_bv_relation *rel);
const char *orr_bv_relation_name(orr_bv_relation rel);

/* The B-V range over which rel is used; colours outside are clamped to it. */
void orr_bv_range(orr_bv_relation rel, double *bv_min, double *bv_max);

/* T_eff in K for a B-V index, clamped to the relation's range (so the
 * bluest and reddest ends give the temperature at the range's edge).
 * NaN for NaN or an unknown relation. */
double orr_bv_to_teff(double bv, orr_bv_relation rel);

/* ---- sRGB, chromaticities ---------------------------------------------- */

/* The sRGB transfer curve (IEC 61966-2-1) on one value: encode for PNG,
 * decode to read an sRGB triple. Values <= 0 give 0; values above 1 follow
 * the curve (callers clip). */
double orr_srgb_encode(double linear);
double orr_srgb_decode(double encoded);
/* Encodes n floats in place (e.g. width * height * 3 RGB values). */
void orr_srgb_encode_buffer(float *values, size_t n);

/* The Rec. 709 / sRGB matrices for D65, derived from the primaries
 * (0.64, 0.33), (0.30, 0.60), (0.15, 0.06) and white (0.3127, 0.3290);
 * each is the other's inverse to double precision. */
void orr_xyz_to_linear_srgb(const double xyz[3], double rgb[3]);
void orr_linear_srgb_to_xyz(const double rgb[3], double xyz[3]);

/* Luminance Y of a linear sRGB triple (the middle row of the matrix). */
double orr_linear_srgb_luminance(const double rgb[3]);

/* xyz scaled to Y = 1; returns 0 (xyz unchanged) when Y is not > 0 or a
 * component is not finite. */
int orr_xyz_normalise(double xyz[3]);

/* Chromaticity x = X/(X+Y+Z), y = Y/(X+Y+Z); returns 0 when X+Y+Z <= 0. */
int orr_xyz_to_xy(const double xyz[3], double *x, double *y);

/* XYZ with Y = 1 at chromaticity (x, y); returns 0 unless 0 <= x, 0 < y and
 * x + y <= 1. */
int orr_xy_to_xyz(double x, double y, double xyz[3]);

/* ---- a colour given by the user ----------------------------------------- */

typedef enum {
    ORR_COLOUR_TEMPERATURE = 0, /* v[0] = T in K (a blackbody) */
    ORR_COLOUR_BV,              /* v[0] = B-V */
    ORR_COLOUR_SRGB,            /* v[0..2] sRGB, gamma-encoded, in [0, 1] */
    ORR_COLOUR_LINEAR_SRGB,     /* v[0..2] linear sRGB, >= 0 */
    ORR_COLOUR_XY,              /* v[0..1] chromaticity (x, y) */
} orr_colour_kind;

/* A fixed colour. Zero-initialised fields give the defaults: CIE 1931 CMFs
 * and Mamajek's B-V relation. Only the chromaticity counts: sRGB (1, 1, 1)
 * and (0.5, 0.5, 0.5) are the same colour; luminance comes from elsewhere. */
typedef struct orr_colour {
    orr_colour_kind kind;
    double v[3];
    orr_cmf cmf;            /* for TEMPERATURE and BV */
    orr_bv_relation bv_rel; /* for BV */
} orr_colour;

/* The colour's XYZ with Y = 1. Fails (ORR_ERR_USAGE, with a message naming
 * the value) on a temperature not > 0, sRGB components outside their range
 * or all zero (black has no chromaticity), or (x, y) outside the diagram. */
orr_status orr_colour_xyz(const orr_colour *c, double xyz[3], orr_error *err);

/* ---- a colour that changes along a run ---------------------------------- */

#define ORR_COLOUR_PATH_MAX 16

/* Stops evenly spaced in t in [0, 1]. When every stop is a temperature the
 * path follows the Planckian locus, linear in mired (1e6 / T), so equal steps
 * in t look like equal steps in colour; otherwise it runs straight between the
 * stops in the CIE 1976 u'v' diagram (roughly perceptually uniform). */
typedef struct orr_colour_path {
    int n; /* 1 .. ORR_COLOUR_PATH_MAX */
    orr_colour stop[ORR_COLOUR_PATH_MAX];
} orr_colour_path;

/* XYZ (Y = 1) at t, clamped to [0, 1] (NaN counts as 0). Typically
 * t = frame / (frames - 1) or (time - t_start) / (t_end - t_start). */
orr_status orr_colour_path_xyz(const orr_colour_path *p, double t, double xyz[3], orr_error *err);

#endif
