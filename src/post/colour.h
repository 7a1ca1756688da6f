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
 * The colourimetry behind both (blackbodies, CMFs, B-V, sRGB) is in
 * core/colourimetry.h, which particles/ and the other stages share.
 *
 * Conventions: XYZ with Y the luminance; "linear sRGB" is Rec. 709 primaries
 * with the D65 white, (1, 1, 1) = white of luminance Y = 1. */
#ifndef ORR_POST_COLOUR_H
#define ORR_POST_COLOUR_H

#include <stddef.h>

#include "core/cards.h"
#include "core/colourimetry.h"
#include "core/error.h"
#include "core/keys.h"
#include "core/plane.h"
#include "particles/population.h"

/* ---- per-pixel synthesis ------------------------------------------------- */

typedef enum {
    ORR_LUM_LINEAR = 0, /* Y' = Y / Y0 */
    ORR_LUM_LOG,        /* Y' = log(1 + n Y/Y0) / log(1 + n) */
    ORR_LUM_GAMMA,      /* Y' = (Y / Y0)^gamma */
    ORR_LUM_ASINH,      /* Y' = asinh(n Y/Y0) / asinh(n) */
} orr_lum_stretch;

extern const orr_named orr_lum_stretch_names[];

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

extern const orr_named orr_clip_names[];

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

/* The post stage's colour.* settings: true colours (docs/colour.md). With
 * colour.populations the render splats CIE X, Y and Z planes (written to
 * FITS, linear) and the picture is their colour synthesis; without, one
 * weight plane drawn with a colour map (post/picture.h) or in one tint. */
typedef struct orr_colour_settings {
    int has_populations;            /* colour.populations was given */
    orr_population_set populations; /* colour.populations: list of {name, select, colour, luminance} */
    uint64_t seed;                  /* colour.seed: of the populations' random draws (default 1) */
    char only[ORR_POPULATION_NAME_MAX]; /* colour.only: draw just this population (default: all);
                                    * the others still take their particles first, so separate renders
                                    * of each population add up to the render of all */
    int only_index;                 /* its index, -1 for all */
    orr_colour_synth synth;         /* colour.synthesis.stretch: linear | log | gamma | asinh (default log),
                                     * .softening (10), .gamma (0.5), .white (auto), .white_percentile (99.9),
                                     * .brightness (1), .contrast (1), .clip: desaturate | channel | none */
    /* colour.tint.*: a single-channel map (no populations) drawn in one
     * colour, taken along a path of blackbody temperatures (e.g. a hue from
     * blue to deep red over a run) instead of a colour map. */
    int has_tint;                   /* colour.tint.path was given */
    orr_colour_path tint;           /* colour.tint.path: list of temperatures, K */
    double tint_t;                  /* colour.tint.t: position along it, 0..1 (default 0) */
    int tint_run;                   /* colour.tint.t: run: the position is the frame's u in the run
                                     * (0 at the first frame, 1 at the last) instead of tint_t */
} orr_colour_settings;

/* Fills d with the defaults above. */
void orr_colour_settings_defaults(orr_colour_settings *d);

/* The colour.* keys checked against each other: colour.only names a
 * population, the populations' keys only with populations, a tint only
 * without, the synthesis's parameters usable; keys says which were given,
 * and where. Sets what they come to: the populations' seed and
 * colour.only's index. */
orr_status orr_colour_prepare(orr_colour_settings *d, const orr_keys *keys, orr_error *err);

/* With colour populations: NPOPS, and the luminance Y deposited in and off
 * the image (YIMAGE, YOUTSIDE), which each frame gives: reserved. */
void orr_colour_cards(const orr_colour_settings *d, orr_cards *h);

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

/* The per-pixel halves of the two above, for n pixels of planes already
 * checked, at white level y0 (from orr_colour_synth_y0): so a picture can
 * be made a row at a time, with the same values. unit is a tint's colour
 * from orr_colour_tint_unit. */
void orr_colour_synthesise_span(const orr_colour_synth *s, double y0, const float *X, const float *Y,
                                const float *Z, size_t n, float *rgb);
void orr_colour_synthesise_mono_span(const orr_colour_synth *s, double y0, const double unit[3], const float *L,
                                     size_t n, float *rgb);

/* xyz scaled to Y = 1 into unit; ORR_ERR_USAGE when it is no colour (X, Z
 * >= 0, Y > 0). */
orr_status orr_colour_tint_unit(const double xyz[3], double unit[3], orr_error *err);

#endif
