/* Colour synthesis (docs/colour.md).
 *
 * Per particle: a colour as CIE XYZ normalised to Y = 1 (a chromaticity),
 * from a blackbody temperature, a B-V index, an sRGB triple or a chromaticity
 * (x, y); the renderer scales it by the particle's luminance and sums X, Y, Z
 * into three planes.
 *
 * Per pixel: chromaticity from the planes, the luminance Y stretched (log,
 * gamma, asinh or linear against a white level Y0), X and Z rebuilt at the
 * same chromaticity, converted to linear sRGB / Rec. 709 (D65) and brought
 * into gamut. The result is linear RGB; orr_srgb_encode gives PNG values.
 *
 * Conventions: XYZ with Y the luminance; "linear sRGB" is Rec. 709 primaries
 * with the D65 white, (1, 1, 1) = white of luminance Y = 1. */
#ifndef ORR_POST_COLOUR_H
#define ORR_POST_COLOUR_H

#include <stddef.h>

#include "core/error.h"
#include "splat/plane.h"

/* ---- colour-matching functions ---------------------------------------- */

typedef enum {
    ORR_CMF_CIE1931 = 0, /* CIE 1931 2-degree, 360-830 nm, 1 nm: the standard observer */
    ORR_CMF_JUDD_VOS,    /* Judd-Vos modified 2-degree, 380-825 nm, 5 nm */
} orr_cmf;

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

/* ---- per-pixel synthesis ------------------------------------------------- */

typedef enum {
    ORR_LUM_LINEAR = 0, /* Y' = Y / Y0 */
    ORR_LUM_LOG,        /* Y' = log(1 + n Y/Y0) / log(1 + n) */
    ORR_LUM_GAMMA,      /* Y' = (Y / Y0)^gamma */
    ORR_LUM_ASINH,      /* Y' = asinh(n Y/Y0) / asinh(n) */
} orr_lum_stretch;

/* "linear", "log", "gamma" or "asinh"; returns 0 on an unknown name. */
int orr_lum_stretch_from_name(const char *name, orr_lum_stretch *kind);
const char *orr_lum_stretch_name(orr_lum_stretch kind);

typedef enum {
    /* Out-of-gamut colours move toward the grey of the same luminance until
     * they fit: hue and luminance kept, saturation given up; luminance >= 1
     * is white. The default (docs/colour.md says why). */
    ORR_CLIP_DESATURATE = 0,
    /* Each channel clipped to [0, 1] on its own: hue shifts toward the
     * primaries and secondaries as a pixel saturates (a bright orange star
     * turns yellow). */
    ORR_CLIP_CHANNEL,
    /* No clipping: scene-referred linear values for EXR / FITS. */
    ORR_CLIP_NONE,
} orr_clip;

/* "desaturate", "channel" or "none"; returns 0 on an unknown name. */
int orr_clip_from_name(const char *name, orr_clip *clip);
const char *orr_clip_name(orr_clip clip);

typedef struct orr_colour_synth {
    orr_lum_stretch stretch;
    double n;             /* softening of log and asinh, > 0 */
    double gamma;         /* exponent of the gamma stretch, > 0 */
    double y0;            /* > 0: fixed white level; 0: from y0_percentile */
    double y0_percentile; /* in (0, 100], of the positive pixels of the Y plane */
    /* Applied to the stretched luminance s, keeping black black:
     * s'' = brightness * 0.5 * (2 s)^contrast, so contrast steepens (> 1) or
     * flattens (< 1) the curve about s = 0.5 and brightness is a gain. */
    double brightness; /* > 0, 1 = unchanged */
    double contrast;   /* > 0, 1 = unchanged */
    orr_clip clip;
} orr_colour_synth;

/* Log stretch, n = 10, Y0 at the 99.9th percentile, gamma 0.5 (when chosen),
 * brightness = contrast = 1, desaturating clip. */
void orr_colour_synth_defaults(orr_colour_synth *s);

/* Checks the parameters; messages name the offending one. */
orr_status orr_colour_synth_check(const orr_colour_synth *s, orr_error *err);

/* The stretched, brightness- and contrast-adjusted luminance of a pixel
 * with luminance y, for white level y0 > 0; 0 for y NaN or <= 0. Not clipped
 * (so 1 at y = y0 before brightness and contrast, more above). */
double orr_colour_stretch_value(const orr_colour_synth *s, double y, double y0);

/* The white level the synthesis would use for this Y plane: s->y0 when
 * fixed, else the percentile of its positive pixels (1 when there are none)
 * from orr_stretch_white. To keep Y0 fixed across frames, compute it once
 * (or take y0_used from the first frame) and set s->y0. */
orr_status orr_colour_synth_y0(const orr_colour_synth *s, const orr_plane *Y, double *y0, orr_error *err);

/* Brings a linear RGB triple into gamut as the clip mode says. */
void orr_colour_clip(orr_clip clip, double rgb[3]);

/* Three planes X, Y, Z (equal sizes) to width * height * 3 linear RGB
 * floats, row-major, row 0 at the top. Pixels with NaN, negative or zero Y,
 * or X + Y + Z <= 0, are black. y0_used (may be NULL) gets the white level. */
orr_status orr_colour_synthesise(const orr_colour_synth *s, const orr_plane *X, const orr_plane *Y,
                                 const orr_plane *Z, float *rgb, double *y0_used, orr_error *err);

/* A single-channel plane (its values taken as luminance) drawn in one colour
 * xyz (Y = 1, e.g. from orr_colour_path_xyz for the frame): the same as
 * orr_colour_synthesise with planes xyz * L. */
orr_status orr_colour_synthesise_mono(const orr_colour_synth *s, const orr_plane *L, const double xyz[3],
                                      float *rgb, double *y0_used, orr_error *err);

#endif
