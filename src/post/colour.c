#include "post/colour.h"

#include <math.h>
#include <pthread.h>
#include <string.h>

#include "post/cie_data.h"
#include "post/stretch.h"

/* ---- names ----------------------------------------------------------------- */

static int name_index(const char *name, const char *const *names, int count)
{
    if (!name)
        return -1;
    for (int i = 0; i < count; i++)
        if (strcmp(name, names[i]) == 0)
            return i;
    return -1;
}

#define COUNT(a) ((int)(sizeof(a) / sizeof((a)[0])))
#define NAME_OF(names, k) (((int)(k) >= 0 && (int)(k) < COUNT(names)) ? (names)[(int)(k)] : "unknown")

static const char *const cmf_names[] = {[ORR_CMF_CIE1931] = "cie1931", [ORR_CMF_JUDD_VOS] = "judd-vos"};
static const char *const bv_names[] = {[ORR_BV_MAMAJEK] = "mamajek", [ORR_BV_BALLESTEROS] = "ballesteros"};
static const char *const lum_names[] = {
    [ORR_LUM_LINEAR] = "linear", [ORR_LUM_LOG] = "log", [ORR_LUM_GAMMA] = "gamma", [ORR_LUM_ASINH] = "asinh"};
static const char *const clip_names[] = {
    [ORR_CLIP_DESATURATE] = "desaturate", [ORR_CLIP_CHANNEL] = "channel", [ORR_CLIP_NONE] = "none"};

int orr_cmf_from_name(const char *name, orr_cmf *cmf)
{
    int i = name_index(name, cmf_names, COUNT(cmf_names));
    if (i >= 0)
        *cmf = (orr_cmf)i;
    return i >= 0;
}

const char *orr_cmf_name(orr_cmf cmf) { return NAME_OF(cmf_names, cmf); }

int orr_bv_relation_from_name(const char *name, orr_bv_relation *rel)
{
    int i = name_index(name, bv_names, COUNT(bv_names));
    if (i >= 0)
        *rel = (orr_bv_relation)i;
    return i >= 0;
}

const char *orr_bv_relation_name(orr_bv_relation rel) { return NAME_OF(bv_names, rel); }

int orr_lum_stretch_from_name(const char *name, orr_lum_stretch *kind)
{
    int i = name_index(name, lum_names, COUNT(lum_names));
    if (i >= 0)
        *kind = (orr_lum_stretch)i;
    return i >= 0;
}

const char *orr_lum_stretch_name(orr_lum_stretch kind) { return NAME_OF(lum_names, kind); }

int orr_clip_from_name(const char *name, orr_clip *clip)
{
    int i = name_index(name, clip_names, COUNT(clip_names));
    if (i >= 0)
        *clip = (orr_clip)i;
    return i >= 0;
}

const char *orr_clip_name(orr_clip clip) { return NAME_OF(clip_names, clip); }

/* ---- blackbody integration ---------------------------------------------- */

/* Second radiation constant c2 = h c / k (CODATA 2018), in nm K. */
#define C2_NM_K 1.438776877e7

typedef struct cmf_set {
    const double (*rows)[3];
    int count;
    double first_nm, step_nm;
} cmf_set;

static int cmf_get(orr_cmf cmf, cmf_set *set)
{
    switch (cmf) {
    case ORR_CMF_CIE1931:
        *set = (cmf_set){orr_cie1931_2deg, orr_cie1931_2deg_count, ORR_CIE1931_FIRST_NM, ORR_CIE1931_STEP_NM};
        return 1;
    case ORR_CMF_JUDD_VOS:
        *set = (cmf_set){orr_judd_vos_2deg, orr_judd_vos_2deg_count, ORR_JUDD_VOS_FIRST_NM, ORR_JUDD_VOS_STEP_NM};
        return 1;
    }
    return 0;
}

/* Planck's spectral radiance up to a factor that depends on T only (which
 * drops out of the chromaticity): lambda^-5 / (e^a - 1), a = c2/(lambda T),
 * multiplied by e^(a_ref) with a_ref for the longest wavelength of the set,
 * so that cold bodies do not underflow to all zeros and hot ones do not
 * overflow. Written as e^(a_ref - a) / (1 - e^-a), both finite for any
 * T > 0. T = infinity is the Rayleigh-Jeans limit, lambda^-4. */
static double planck_scaled(double lambda_nm, double T, double lambda_ref_nm)
{
    double l_um = lambda_nm * 1e-3;
    if (isinf(T))
        return 1.0 / (l_um * l_um * l_um * l_um);
    double a = C2_NM_K / (lambda_nm * T);
    double a_ref = C2_NM_K / (lambda_ref_nm * T);
    double l5 = l_um * l_um * l_um * l_um * l_um;
    return exp(a_ref - a) / (-expm1(-a) * l5);
}

int orr_blackbody_xyz_exact(double T, orr_cmf cmf, double xyz[3])
{
    cmf_set set;
    xyz[0] = xyz[1] = xyz[2] = 0;
    if (!(T > 0) || !cmf_get(cmf, &set))
        return 0;
    double last_nm = set.first_nm + set.step_nm * (set.count - 1);
    double sum[3] = {0, 0, 0};
    for (int i = 0; i < set.count; i++) {
        /* Trapezoid rule: the end points count half. The step is common to
         * all three sums, so it drops out. */
        double w = planck_scaled(set.first_nm + set.step_nm * i, T, last_nm);
        if (i == 0 || i == set.count - 1)
            w *= 0.5;
        for (int k = 0; k < 3; k++)
            sum[k] += w * set.rows[i][k];
    }
    if (!(sum[1] > 0))
        return 0;
    xyz[0] = sum[0] / sum[1];
    xyz[1] = 1;
    xyz[2] = sum[2] / sum[1];
    return 1;
}

/* ---- blackbody table ------------------------------------------------------ */

/* X/Y and Z/Y at BB_N temperatures evenly spaced in ln T. Linear
 * interpolation error goes as step^2 times the curvature of the locus in
 * ln T; 1024 points (step 0.52% in T) keep it below 1e-6 in x and y. */
#define BB_N 1024

typedef struct bb_table {
    double ln_tmin, inv_step;
    double xz[BB_N][2];
} bb_table;

static bb_table bb_tables[2];
static pthread_once_t bb_once[2] = {PTHREAD_ONCE_INIT, PTHREAD_ONCE_INIT};

static void bb_build(orr_cmf cmf)
{
    bb_table *t = &bb_tables[cmf];
    double ln_min = log(ORR_BLACKBODY_T_MIN), ln_max = log(ORR_BLACKBODY_T_MAX);
    double step = (ln_max - ln_min) / (BB_N - 1);
    t->ln_tmin = ln_min;
    t->inv_step = 1.0 / step;
    for (int i = 0; i < BB_N; i++) {
        double xyz[3];
        orr_blackbody_xyz_exact(exp(ln_min + step * i), cmf, xyz);
        t->xz[i][0] = xyz[0];
        t->xz[i][1] = xyz[2];
    }
}

static void bb_build_cie1931(void) { bb_build(ORR_CMF_CIE1931); }
static void bb_build_judd_vos(void) { bb_build(ORR_CMF_JUDD_VOS); }

static const bb_table *bb_get(orr_cmf cmf)
{
    switch (cmf) {
    case ORR_CMF_CIE1931:
        pthread_once(&bb_once[0], bb_build_cie1931);
        return &bb_tables[0];
    case ORR_CMF_JUDD_VOS:
        pthread_once(&bb_once[1], bb_build_judd_vos);
        return &bb_tables[1];
    }
    return NULL;
}

/* Lookup by ln T, so B-V (interpolated in ln T) needs no exp/log round trip. */
static int bb_lookup_ln(double ln_t, orr_cmf cmf, double xyz[3])
{
    const bb_table *t = bb_get(cmf);
    if (!t || isnan(ln_t)) {
        xyz[0] = xyz[1] = xyz[2] = 0;
        return 0;
    }
    double u = (ln_t - t->ln_tmin) * t->inv_step;
    if (u < 0)
        u = 0;
    if (u > BB_N - 1)
        u = BB_N - 1;
    int i = (int)u;
    if (i > BB_N - 2)
        i = BB_N - 2;
    double f = u - i;
    xyz[0] = t->xz[i][0] + f * (t->xz[i + 1][0] - t->xz[i][0]);
    xyz[1] = 1;
    xyz[2] = t->xz[i][1] + f * (t->xz[i + 1][1] - t->xz[i][1]);
    return 1;
}

int orr_blackbody_xyz(double T, orr_cmf cmf, double xyz[3])
{
    if (!(T > 0)) {
        xyz[0] = xyz[1] = xyz[2] = 0;
        return 0;
    }
    return bb_lookup_ln(log(T), cmf, xyz);
}

/* ---- B-V ------------------------------------------------------------------ */

#define BALLESTEROS_BV_MIN (-0.1)
#define BALLESTEROS_BV_MAX 1.5

void orr_bv_range(orr_bv_relation rel, double *bv_min, double *bv_max)
{
    if (rel == ORR_BV_BALLESTEROS) {
        *bv_min = BALLESTEROS_BV_MIN;
        *bv_max = BALLESTEROS_BV_MAX;
    } else {
        *bv_min = orr_mamajek_dwarfs[0].bv;
        *bv_max = orr_mamajek_dwarfs[orr_mamajek_dwarfs_count - 1].bv;
    }
}

/* ln T_eff from Mamajek's sequence: linear in ln T between the bracketing
 * points (found by bisection), clamped at the ends. Interpolating ln T keeps
 * the steep hot end (B-V changes by 0.03 from O3V to B0V) monotone. */
static double mamajek_ln_teff(double bv)
{
    const orr_bv_teff *t = orr_mamajek_dwarfs;
    int n = orr_mamajek_dwarfs_count;
    if (bv <= t[0].bv)
        return log(t[0].teff);
    if (bv >= t[n - 1].bv)
        return log(t[n - 1].teff);
    int lo = 0, hi = n - 1; /* t[lo].bv <= bv < t[hi].bv */
    while (hi - lo > 1) {
        int mid = lo + (hi - lo) / 2;
        if (t[mid].bv <= bv)
            lo = mid;
        else
            hi = mid;
    }
    double f = (bv - t[lo].bv) / (t[hi].bv - t[lo].bv);
    double a = log(t[lo].teff), b = log(t[hi].teff);
    return a + f * (b - a);
}

static double ballesteros_teff(double bv)
{
    if (bv < BALLESTEROS_BV_MIN)
        bv = BALLESTEROS_BV_MIN;
    if (bv > BALLESTEROS_BV_MAX)
        bv = BALLESTEROS_BV_MAX;
    return 4600.0 * (1.0 / (0.92 * bv + 1.7) + 1.0 / (0.92 * bv + 0.62));
}

static double bv_ln_teff(double bv, orr_bv_relation rel)
{
    if (isnan(bv))
        return NAN;
    switch (rel) {
    case ORR_BV_MAMAJEK:
        return mamajek_ln_teff(bv);
    case ORR_BV_BALLESTEROS:
        return log(ballesteros_teff(bv));
    }
    return NAN;
}

double orr_bv_to_teff(double bv, orr_bv_relation rel) { return exp(bv_ln_teff(bv, rel)); }

/* ---- sRGB and chromaticities ---------------------------------------------- */

double orr_srgb_encode(double v)
{
    if (!(v > 0))
        return 0;
    return v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1.0 / 2.4) - 0.055;
}

double orr_srgb_decode(double v)
{
    if (!(v > 0))
        return 0;
    return v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4);
}

void orr_srgb_encode_buffer(float *values, size_t n)
{
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < n; i++)
        values[i] = (float)orr_srgb_encode(values[i]);
}

/* Derived from the Rec. 709 primaries and the D65 white in exact rational
 * arithmetic, M = P diag(P^-1 W) with P the primaries' XYZ as columns and W
 * the white's XYZ, then rounded to double. test_colour checks that they are
 * inverses, put the primaries at their chromaticities and D65 at (1, 1, 1). */
static const double RGB_TO_XYZ[3][3] = {
    {0.4123907992659595, 0.35758433938387796, 0.1804807884018343},
    {0.21263900587151036, 0.7151686787677559, 0.07219231536073371},
    {0.01933081871559185, 0.11919477979462599, 0.9505321522496606},
};
static const double XYZ_TO_RGB[3][3] = {
    {3.2409699419045213, -1.5373831775700935, -0.4986107602930033},
    {-0.9692436362808798, 1.8759675015077206, 0.04155505740717561},
    {0.05563007969699361, -0.20397695888897657, 1.0569715142428786},
};

static void mat3_apply(const double m[3][3], const double in[3], double out[3])
{
    double a = in[0], b = in[1], c = in[2]; /* in and out may alias */
    for (int k = 0; k < 3; k++)
        out[k] = m[k][0] * a + m[k][1] * b + m[k][2] * c;
}

void orr_xyz_to_linear_srgb(const double xyz[3], double rgb[3]) { mat3_apply(XYZ_TO_RGB, xyz, rgb); }
void orr_linear_srgb_to_xyz(const double rgb[3], double xyz[3]) { mat3_apply(RGB_TO_XYZ, rgb, xyz); }

double orr_linear_srgb_luminance(const double rgb[3])
{
    return RGB_TO_XYZ[1][0] * rgb[0] + RGB_TO_XYZ[1][1] * rgb[1] + RGB_TO_XYZ[1][2] * rgb[2];
}

int orr_xyz_normalise(double xyz[3])
{
    if (!(xyz[1] > 0) || !isfinite(xyz[0]) || !isfinite(xyz[1]) || !isfinite(xyz[2]))
        return 0;
    double inv = 1.0 / xyz[1];
    xyz[0] *= inv;
    xyz[2] *= inv;
    xyz[1] = 1;
    return 1;
}

int orr_xyz_to_xy(const double xyz[3], double *x, double *y)
{
    double s = xyz[0] + xyz[1] + xyz[2];
    if (!(s > 0))
        return 0;
    *x = xyz[0] / s;
    *y = xyz[1] / s;
    return 1;
}

int orr_xy_to_xyz(double x, double y, double xyz[3])
{
    if (!(x >= 0 && y > 0 && x + y <= 1))
        return 0;
    xyz[0] = x / y;
    xyz[1] = 1;
    xyz[2] = (1 - x - y) / y;
    return 1;
}

/* ---- user colours ---------------------------------------------------------- */

static orr_status rgb_colour_xyz(const orr_colour *c, double xyz[3], orr_error *err)
{
    int encoded = c->kind == ORR_COLOUR_SRGB;
    double rgb[3];
    for (int k = 0; k < 3; k++) {
        double v = c->v[k];
        if (!(v >= 0) || (encoded && v > 1) || isinf(v))
            return orr_fail(err, ORR_ERR_USAGE, "colour: %s component %g must be %s",
                            encoded ? "sRGB" : "linear sRGB", v, encoded ? "in [0, 1]" : "finite and >= 0");
        rgb[k] = encoded ? orr_srgb_decode(v) : v;
    }
    orr_linear_srgb_to_xyz(rgb, xyz);
    if (!orr_xyz_normalise(xyz))
        return orr_fail(err, ORR_ERR_USAGE, "colour: (%g, %g, %g) is black, which has no chromaticity", c->v[0],
                        c->v[1], c->v[2]);
    return ORR_OK;
}

orr_status orr_colour_xyz(const orr_colour *c, double xyz[3], orr_error *err)
{
    switch (c->kind) {
    case ORR_COLOUR_TEMPERATURE:
        if (!(c->v[0] > 0) || !orr_blackbody_xyz(c->v[0], c->cmf, xyz))
            return orr_fail(err, ORR_ERR_USAGE, "colour: temperature %g K must be > 0 (CMFs '%s')", c->v[0],
                            orr_cmf_name(c->cmf));
        return ORR_OK;
    case ORR_COLOUR_BV:
        if (!isfinite(c->v[0]) || !bb_lookup_ln(bv_ln_teff(c->v[0], c->bv_rel), c->cmf, xyz))
            return orr_fail(err, ORR_ERR_USAGE, "colour: B-V %g must be a finite number (relation '%s', CMFs '%s')",
                            c->v[0], orr_bv_relation_name(c->bv_rel), orr_cmf_name(c->cmf));
        return ORR_OK;
    case ORR_COLOUR_SRGB:
    case ORR_COLOUR_LINEAR_SRGB:
        return rgb_colour_xyz(c, xyz, err);
    case ORR_COLOUR_XY:
        if (!orr_xy_to_xyz(c->v[0], c->v[1], xyz))
            return orr_fail(err, ORR_ERR_USAGE,
                            "colour: chromaticity (x, y) = (%g, %g) needs x >= 0, y > 0, x + y <= 1", c->v[0],
                            c->v[1]);
        return ORR_OK;
    }
    return orr_fail(err, ORR_ERR_USAGE, "colour: unknown kind %d", (int)c->kind);
}

/* ---- colour paths ----------------------------------------------------------- */

/* CIE 1976 u'v' from XYZ and back at Y = 1: straight lines in u'v' are straight
 * in xy too (both are projective maps of XYZ), but equal steps are more even. */
static void xyz_to_upvp(const double xyz[3], double uv[2])
{
    double d = xyz[0] + 15 * xyz[1] + 3 * xyz[2];
    uv[0] = 4 * xyz[0] / d;
    uv[1] = 9 * xyz[1] / d;
}

static void upvp_to_xyz(const double uv[2], double xyz[3])
{
    /* Inverse of the above with Y = 1. */
    xyz[0] = 9 * uv[0] / (4 * uv[1]);
    xyz[1] = 1;
    xyz[2] = (12 - 3 * uv[0] - 20 * uv[1]) / (4 * uv[1]);
}

orr_status orr_colour_path_xyz(const orr_colour_path *p, double t, double xyz[3], orr_error *err)
{
    if (p->n < 1 || p->n > ORR_COLOUR_PATH_MAX)
        return orr_fail(err, ORR_ERR_USAGE, "colour path: %d stops, must be 1 to %d", p->n, ORR_COLOUR_PATH_MAX);
    int all_temperatures = 1;
    for (int i = 0; i < p->n; i++) {
        double check[3];
        orr_status st = orr_colour_xyz(&p->stop[i], check, err);
        if (st != ORR_OK)
            return orr_fail_prefix(err, "colour path stop %d: ", i + 1);
        all_temperatures &= p->stop[i].kind == ORR_COLOUR_TEMPERATURE;
    }
    if (!(t > 0))
        t = 0;
    if (t > 1)
        t = 1;
    double u = t * (p->n - 1);
    int i = (int)u;
    if (i > p->n - 2)
        i = p->n > 1 ? p->n - 2 : 0;
    double f = p->n > 1 ? u - i : 0;
    const orr_colour *a = &p->stop[i], *b = &p->stop[p->n > 1 ? i + 1 : i];
    if (all_temperatures) {
        /* Linear in mired; the CMFs of the first stop of the pair decide. */
        double mired = (1 - f) / a->v[0] + f / b->v[0];
        orr_blackbody_xyz(1.0 / mired, a->cmf, xyz);
        return ORR_OK;
    }
    double xa[3], xb[3], ua[2], ub[2], uv[2];
    orr_colour_xyz(a, xa, err);
    orr_colour_xyz(b, xb, err);
    xyz_to_upvp(xa, ua);
    xyz_to_upvp(xb, ub);
    uv[0] = ua[0] + f * (ub[0] - ua[0]);
    uv[1] = ua[1] + f * (ub[1] - ua[1]);
    upvp_to_xyz(uv, xyz);
    return ORR_OK;
}

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

static int positive_finite(double v) { return v > 0 && isfinite(v); }

orr_status orr_colour_synth_check(const orr_colour_synth *s, orr_error *err)
{
    if ((int)s->stretch < 0 || (int)s->stretch >= COUNT(lum_names))
        return orr_fail(err, ORR_ERR_USAGE, "colour: unknown luminance stretch %d", (int)s->stretch);
    if ((int)s->clip < 0 || (int)s->clip >= COUNT(clip_names))
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
    long npix = (long)Y->width * Y->height;
    prepared_stretch p = prepare_stretch(s, y0);
#pragma omp parallel for schedule(static)
    for (long i = 0; i < npix; i++)
        synth_pixel(&p, s->clip, X->data[i], Y->data[i], Z->data[i], rgb + 3 * i);
    return ORR_OK;
}

orr_status orr_colour_synthesise_mono(const orr_colour_synth *s, const orr_plane *L, const double xyz[3],
                                      float *rgb, double *y0_used, orr_error *err)
{
    double unit[3] = {xyz[0], xyz[1], xyz[2]};
    if (!orr_xyz_normalise(unit) || !(unit[0] >= 0) || !(unit[2] >= 0))
        return orr_fail(err, ORR_ERR_USAGE, "colour: (%g, %g, %g) is not a colour (needs X, Z >= 0, Y > 0)",
                        xyz[0], xyz[1], xyz[2]);
    double y0;
    orr_status st = orr_colour_synth_y0(s, L, &y0, err);
    if (st != ORR_OK)
        return st;
    if (y0_used)
        *y0_used = y0;
    long npix = (long)L->width * L->height;
    prepared_stretch p = prepare_stretch(s, y0);
#pragma omp parallel for schedule(static)
    for (long i = 0; i < npix; i++) {
        double v = L->data[i];
        synth_pixel(&p, s->clip, unit[0] * v, v, unit[2] * v, rgb + 3 * i);
    }
    return ORR_OK;
}
