#include "core/colourimetry.h"

#include <math.h>
#include <pthread.h>
#include <string.h>

#include "core/cie_data.h"
#include "core/vecmath.h"

/* ---- names ------------------------------------------------------------------ */

const orr_named orr_cmf_names[] = {{"cie1931", ORR_CMF_CIE1931}, {"judd-vos", ORR_CMF_JUDD_VOS}, {NULL, 0}};
const orr_named orr_bv_relation_names[] = {
    {"mamajek", ORR_BV_MAMAJEK}, {"ballesteros", ORR_BV_BALLESTEROS}, {NULL, 0}};

ORR_NAMED_PARSER(orr_cmf_from_name, orr_cmf, orr_cmf_names)

const char *orr_cmf_name(orr_cmf cmf) { return orr_named_name(orr_cmf_names, (int)cmf); }

ORR_NAMED_PARSER(orr_bv_relation_from_name, orr_bv_relation, orr_bv_relation_names)

const char *orr_bv_relation_name(orr_bv_relation rel) { return orr_named_name(orr_bv_relation_names, (int)rel); }

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
    double f;
    const int i = orr_table_cell((ln_t - t->ln_tmin) * t->inv_step, BB_N, &f);
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
