#include "post/colour.h"

#include <math.h>
#include <string.h>

#include "post/stretch.h"

/* ---- names ----------------------------------------------------------------- */

const orr_named orr_lum_stretch_names[] = {
    {"linear", ORR_LUM_LINEAR}, {"log", ORR_LUM_LOG}, {"gamma", ORR_LUM_GAMMA}, {"asinh", ORR_LUM_ASINH}, {NULL, 0}};
const orr_named orr_clip_names[] = {
    {"desaturate", ORR_CLIP_DESATURATE}, {"channel", ORR_CLIP_CHANNEL}, {"none", ORR_CLIP_NONE}, {NULL, 0}};

ORR_NAMED_PARSER(orr_lum_stretch_from_name, orr_lum_stretch, orr_lum_stretch_names)

const char *orr_lum_stretch_name(orr_lum_stretch kind) { return orr_named_name(orr_lum_stretch_names, (int)kind); }

ORR_NAMED_PARSER(orr_clip_from_name, orr_clip, orr_clip_names)

const char *orr_clip_name(orr_clip clip) { return orr_named_name(orr_clip_names, (int)clip); }

/* ---- synthesis ----------------------------------------------------------------- */

void orr_colour_synth_defaults(orr_colour_synth *s)
{
    *s = (orr_colour_synth){
        .stretch = ORR_LUM_LOG,
        .n = 10,
        .gamma = 0.5,
        .y0 = 0,
        .y0_percentile = 99.9,
        .brightness = 1,
        .contrast = 1,
        .clip = ORR_CLIP_DESATURATE,
    };
}

orr_status orr_colour_prepare(orr_colour_settings *d, const orr_keys *keys, orr_error *err)
{
    static const char *const needing[] = {"colour.seed", "colour.only", "colour.synthesis.stretch",
                                          "colour.synthesis.white"};
    /* What the populations' draws and colour.only come to. */
    d->populations.seed = d->seed;
    d->only_index = d->only[0] ? orr_population_find(&d->populations, d->only) : -1;
    if (d->has_populations && d->only[0] && d->only_index < 0)
        return orr_fail_key(keys, "colour.only", err, "colour.only: no population is called '%s'", d->only);
    for (size_t i = 0; !d->has_populations && i < sizeof needing / sizeof needing[0]; i++) {
        /* A tinted map is graded by colour.synthesis too (its stretch and
         * white), though it has no populations. */
        int synthesis_key = strncmp(needing[i], "colour.synthesis.", 17) == 0;
        if (orr_key_given(keys, needing[i]) && !(synthesis_key && d->has_tint))
            return orr_fail_key(keys, needing[i], err, "%s applies to colour.populations%s, which is not set",
                                needing[i], synthesis_key ? " or colour.tint" : "");
    }
    if (d->has_populations && d->has_tint)
        return orr_fail_key(keys, "colour.tint.path", err,
                            "colour.tint is for single-channel maps; with colour.populations each population "
                            "has its own colour");
    if (!d->has_tint && orr_key_given(keys, "colour.tint.t"))
        return orr_fail_key(keys, "colour.tint.t", err, "colour.tint.t needs colour.tint.path");
    if (orr_colour_synth_check(&d->synth, err))
        return orr_fail_key_prefix(keys, NULL, err, "colour.synthesis: ");
    return ORR_OK;
}

void orr_colour_cards(const orr_colour_settings *d, orr_cards *h)
{
    if (!d->has_populations)
        return;
    orr_cards_add_long(h, "NPOPS", d->populations.n, "colour populations");
    orr_cards_reserve(h, "YIMAGE", "luminance Y deposited in the image");
    orr_cards_reserve(h, "YOUTSIDE", "luminance Y that fell off the image");
}

void orr_colour_settings_defaults(orr_colour_settings *d)
{
    memset(d, 0, sizeof *d);
    d->has_populations = 0;
    d->seed = 1;
    d->only_index = -1;
    orr_population_set_init(&d->populations, 1);
    orr_colour_synth_defaults(&d->synth);
}

static int positive_finite(double v) { return v > 0 && isfinite(v); }

orr_status orr_colour_synth_check(const orr_colour_synth *s, orr_error *err)
{
    if (!orr_named_has(orr_lum_stretch_names, (int)s->stretch))
        return orr_fail(err, ORR_ERR_USAGE, "colour: unknown luminance stretch %d", (int)s->stretch);
    if (!orr_named_has(orr_clip_names, (int)s->clip))
        return orr_fail(err, ORR_ERR_USAGE, "colour: unknown clip mode %d", (int)s->clip);
    if ((s->stretch == ORR_LUM_LOG || s->stretch == ORR_LUM_ASINH) && !positive_finite(s->n))
        return orr_fail(err, ORR_ERR_USAGE, "colour: %s stretch softening n = %g must be > 0",
                        orr_lum_stretch_name(s->stretch), s->n);
    if (s->stretch == ORR_LUM_GAMMA && !positive_finite(s->gamma))
        return orr_fail(err, ORR_ERR_USAGE, "colour: gamma %g must be > 0", s->gamma);
    if (!(s->y0 >= 0) || isinf(s->y0))
        return orr_fail(err, ORR_ERR_USAGE, "colour: white level Y0 = %g must be > 0 (or 0 for a percentile)", s->y0);
    if (s->y0 == 0 && !(s->y0_percentile > 0 && s->y0_percentile <= 100))
        return orr_fail(err, ORR_ERR_USAGE, "colour: Y0 percentile %g must be in (0, 100]", s->y0_percentile);
    if (!positive_finite(s->brightness))
        return orr_fail(err, ORR_ERR_USAGE, "colour: brightness %g must be > 0", s->brightness);
    if (!positive_finite(s->contrast))
        return orr_fail(err, ORR_ERR_USAGE, "colour: contrast %g must be > 0", s->contrast);
    return ORR_OK;
}

/* The stretch with its per-image constants worked out once, so the pixel
 * loop costs one log1p, pow or asinh per pixel. */
typedef struct prepared_stretch {
    orr_lum_stretch kind;
    double inv_y0, n, gamma, norm, contrast, brightness;
} prepared_stretch;

static prepared_stretch prepare_stretch(const orr_colour_synth *s, double y0)
{
    prepared_stretch p = {s->stretch, 1.0 / y0, s->n, s->gamma, 1, s->contrast, s->brightness};
    if (s->stretch == ORR_LUM_LOG)
        p.norm = 1.0 / log1p(s->n);
    else if (s->stretch == ORR_LUM_ASINH)
        p.norm = 1.0 / asinh(s->n);
    return p;
}

static double apply_stretch(const prepared_stretch *p, double y)
{
    if (!(y > 0))
        return 0;
    double r = y * p->inv_y0, v;
    switch (p->kind) {
    case ORR_LUM_LOG:
        v = log1p(p->n * r) * p->norm;
        break;
    case ORR_LUM_GAMMA:
        v = pow(r, p->gamma);
        break;
    case ORR_LUM_ASINH:
        v = asinh(p->n * r) * p->norm;
        break;
    default:
        v = r;
        break;
    }
    if (p->contrast != 1)
        v = 0.5 * pow(2 * v, p->contrast);
    return p->brightness * v;
}

double orr_colour_stretch_value(const orr_colour_synth *s, double y, double y0)
{
    prepared_stretch p = prepare_stretch(s, y0);
    return apply_stretch(&p, y);
}

orr_status orr_colour_synth_y0(const orr_colour_synth *s, const orr_plane *Y, double *y0, orr_error *err)
{
    orr_status st = orr_colour_synth_check(s, err);
    if (st != ORR_OK)
        return st;
    if (s->y0 > 0) {
        *y0 = s->y0;
        return ORR_OK;
    }
    /* The percentile is the grey stretch's: one definition for the project. */
    orr_stretch pick = {.kind = ORR_STRETCH_LINEAR, .white = 0, .white_percentile = s->y0_percentile, .n = 1};
    return orr_stretch_white(&pick, Y, y0, err);
}

/* Moves rgb toward the grey of its own luminance, rgb' = y + k (rgb - y),
 * with the largest k <= 1 that brings every channel into [0, 1]. Luminance
 * is linear in rgb and the grey has luminance y, so y is kept exactly; the
 * direction from grey (the hue) is kept too. */
static void clip_desaturate(double c[3])
{
    double lo = fmin(c[0], fmin(c[1], c[2])), hi = fmax(c[0], fmax(c[1], c[2]));
    if (lo >= 0 && hi <= 1)
        return; /* in gamut, the common case */
    double y = orr_linear_srgb_luminance(c);
    if (!(y > 0)) {
        c[0] = c[1] = c[2] = 0;
        return;
    }
    if (y >= 1) {
        c[0] = c[1] = c[2] = 1;
        return;
    }
    double k = 1;
    if (lo < 0)
        k = y / (y - lo);
    if (hi > 1)
        k = fmin(k, (1 - y) / (hi - y));
    for (int i = 0; i < 3; i++)
        c[i] = y + k * (c[i] - y);
}

void orr_colour_clip(orr_clip clip, double rgb[3])
{
    switch (clip) {
    case ORR_CLIP_DESATURATE:
        clip_desaturate(rgb);
        break;
    case ORR_CLIP_CHANNEL:
        for (int i = 0; i < 3; i++)
            rgb[i] = rgb[i] > 1 ? 1 : (rgb[i] > 0 ? rgb[i] : 0);
        break;
    case ORR_CLIP_NONE:
        break;
    }
}

static orr_status check_planes(const orr_plane *a, const orr_plane *b, const orr_plane *c, orr_error *err)
{
    if (a->width != b->width || a->height != b->height || a->width != c->width || a->height != c->height)
        return orr_fail(err, ORR_ERR_USAGE, "colour: planes X %dx%d, Y %dx%d, Z %dx%d differ in size", a->width,
                        a->height, b->width, b->height, c->width, c->height);
    return ORR_OK;
}

/* One pixel: X, Y, Z scaled by Y'/Y (the same chromaticity at the stretched
 * luminance), to RGB, clipped. */
static void synth_pixel(const prepared_stretch *p, orr_clip clip, double X, double Y, double Z, float *out)
{
    double rgb[3] = {0, 0, 0};
    if (Y > 0 && X >= 0 && Z >= 0 && isfinite(X + Y + Z)) {
        double f = apply_stretch(p, Y) / Y;
        double xyz[3] = {X * f, Y * f, Z * f};
        orr_xyz_to_linear_srgb(xyz, rgb);
        orr_colour_clip(clip, rgb);
    }
    for (int k = 0; k < 3; k++)
        out[k] = (float)rgb[k];
}

void orr_colour_synthesise_span(const orr_colour_synth *s, double y0, const float *X, const float *Y,
                                const float *Z, size_t n, float *rgb)
{
    prepared_stretch p = prepare_stretch(s, y0);
    for (size_t i = 0; i < n; i++)
        synth_pixel(&p, s->clip, X[i], Y[i], Z[i], rgb + 3 * i);
}

void orr_colour_synthesise_mono_span(const orr_colour_synth *s, double y0, const double unit[3], const float *L,
                                     size_t n, float *rgb)
{
    prepared_stretch p = prepare_stretch(s, y0);
    for (size_t i = 0; i < n; i++) {
        double v = L[i];
        synth_pixel(&p, s->clip, unit[0] * v, v, unit[2] * v, rgb + 3 * i);
    }
}

orr_status orr_colour_synthesise(const orr_colour_synth *s, const orr_plane *X, const orr_plane *Y,
                                 const orr_plane *Z, float *rgb, double *y0_used, orr_error *err)
{
    orr_status st = check_planes(X, Y, Z, err);
    double y0;
    if (st == ORR_OK)
        st = orr_colour_synth_y0(s, Y, &y0, err);
    if (st != ORR_OK)
        return st;
    if (y0_used)
        *y0_used = y0;
    const size_t w = (size_t)Y->width;
#pragma omp parallel for schedule(static)
    for (int j = 0; j < Y->height; j++) {
        size_t at = (size_t)j * w;
        orr_colour_synthesise_span(s, y0, X->data + at, Y->data + at, Z->data + at, w, rgb + 3 * at);
    }
    return ORR_OK;
}

orr_status orr_colour_tint_unit(const double xyz[3], double unit[3], orr_error *err)
{
    unit[0] = xyz[0], unit[1] = xyz[1], unit[2] = xyz[2];
    if (!orr_xyz_normalise(unit) || !(unit[0] >= 0) || !(unit[2] >= 0))
        return orr_fail(err, ORR_ERR_USAGE, "colour: (%g, %g, %g) is not a colour (needs X, Z >= 0, Y > 0)",
                        xyz[0], xyz[1], xyz[2]);
    return ORR_OK;
}

orr_status orr_colour_synthesise_mono(const orr_colour_synth *s, const orr_plane *L, const double xyz[3],
                                      float *rgb, double *y0_used, orr_error *err)
{
    double unit[3], y0;
    orr_status st = orr_colour_tint_unit(xyz, unit, err);
    if (st == ORR_OK)
        st = orr_colour_synth_y0(s, L, &y0, err);
    if (st != ORR_OK)
        return st;
    if (y0_used)
        *y0_used = y0;
    const size_t w = (size_t)L->width;
#pragma omp parallel for schedule(static)
    for (int j = 0; j < L->height; j++) {
        size_t at = (size_t)j * w;
        orr_colour_synthesise_mono_span(s, y0, unit, L->data + at, w, rgb + 3 * at);
    }
    return ORR_OK;
}
