#include "dust/curve.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Cardelli, Clayton & Mathis (1989), ApJ 345, 245, eq. 3a and 3b: with
 * x = 1/lambda in inverse microns and y = x - 1.82 (V at 0.55 micron),
 * a(x) and b(x) are polynomials of degree 7 in y, valid for 1.1 <= x <= 3.3
 * (303-909 nm). At y = 0 they give a = 1, b = 0 (A_V / A_V = 1), and at
 * B's 0.44 micron a = b = 1 to 1e-4, so A_B - A_V = A_V / R_V. */
static const double CCM_A[8] = {1.0, 0.17699, -0.50447, -0.02427, 0.72085, 0.01979, -0.77530, 0.32999};
static const double CCM_B[8] = {0.0, 1.41338, 2.28305, 1.07233, -5.38434, -0.62251, 5.30260, -2.09002};

static double poly7(const double c[8], double y)
{
    double s = c[7];
    for (int k = 6; k >= 0; k--)
        s = s * y + c[k];
    return s;
}

double orr_ccm89(double lambda_nm, double r_v)
{
    const double x = 1000.0 / lambda_nm;
    if (!(x >= 1.1 && x <= 3.3) || !(r_v > 0))
        return NAN;
    const double y = x - 1.82;
    return poly7(CCM_A, y) + poly7(CCM_B, y) / r_v;
}

orr_status orr_dust_curve_ccm89(orr_dust_curve *c, double r_v, orr_error *err)
{
    if (!(r_v > 0) || !isfinite(r_v))
        return orr_fail(err, ORR_ERR_USAGE, "dust.r_v = %g: R_V must be a number > 0 (3.1 is the diffuse ISM)",
                        r_v);
    for (int i = 0; i < ORR_DUST_CURVE_N; i++)
        c->a[i] = orr_ccm89(ORR_DUST_CURVE_FIRST_NM + i, r_v);
    return ORR_OK;
}

/* Fitzpatrick (1999, PASP 111, 63), section 4 and Table 3: A(lambda)/E(B-V)
 * = k(lambda - V) + R_V is a natural cubic spline in x = 1/lambda (per
 * micron) through nine anchors: 0 at x = 0; the infrared ones at 0.377 and
 * 0.820, 0.26469 and 0.82925 times R_V/3.1; the optical ones at 1.667,
 * 1.828, 2.141 and 2.433, polynomials in R_V (the paper tabulates these
 * anchors by R_V; the polynomial fits to them are those of the IDL
 * Astronomy Library's fm_unred.pro, which give the paper's 2.688, 3.055,
 * 3.806 and 4.315 at R_V = 3.1: test_dust); and the ultraviolet ones at
 * 3.704 and 3.846 from the Fitzpatrick & Massa (1990) form
 * c1 + c2 x + c3 x^2 / ((x^2 - x0^2)^2 + x^2 gamma^2) + R_V with x0 = 4.596,
 * gamma = 0.99, c3 = 3.23, c2 = -0.824 + 4.717 / R_V, c1 = 2.030 - 3.007 c2. */
#define F99_N 9
static const double F99_X[F99_N] = {0.0, 0.377, 0.820, 1.667, 1.828, 2.141, 2.433, 3.704, 3.846};

static double f99_uv(double x, double r_v)
{
    const double x0 = 4.596, gamma = 0.99, c3 = 3.23, c2 = -0.824 + 4.717 / r_v, c1 = 2.030 - 3.007 * c2;
    const double x2 = x * x, d = x2 - x0 * x0;
    return c1 + c2 * x + c3 * x2 / (d * d + x2 * gamma * gamma) + r_v;
}

static void f99_anchors(double r_v, double y[F99_N])
{
    const double r2 = r_v * r_v;
    y[0] = 0.0;
    y[1] = 0.26469 * r_v / 3.1;
    y[2] = 0.82925 * r_v / 3.1;
    y[3] = -0.422809 + 1.00270 * r_v + 2.13572e-4 * r2;
    y[4] = -5.13540e-2 + 1.00216 * r_v - 7.35778e-5 * r2;
    y[5] = 0.700127 + 1.00184 * r_v - 3.32598e-5 * r2;
    y[6] = 1.19456 + 1.01707 * r_v - 5.46959e-3 * r2 + 7.97809e-4 * r2 * r_v - 4.45636e-5 * r2 * r2;
    y[7] = f99_uv(F99_X[7], r_v);
    y[8] = f99_uv(F99_X[8], r_v);
}

/* The natural cubic spline's second derivatives m at the anchors (zero at
 * both ends), by the tridiagonal system's forward sweep and back substitution. */
static void natural_spline(const double *x, const double *y, int n, double *m)
{
    double c[F99_N], r[F99_N];
    m[0] = m[n - 1] = 0;
    c[0] = r[0] = 0;
    for (int i = 1; i < n - 1; i++) {
        const double h0 = x[i] - x[i - 1], h1 = x[i + 1] - x[i];
        const double rhs = 6 * ((y[i + 1] - y[i]) / h1 - (y[i] - y[i - 1]) / h0);
        const double diag = 2 * (h0 + h1) - h0 * c[i - 1];
        c[i] = h1 / diag;
        r[i] = (rhs - h0 * r[i - 1]) / diag;
    }
    for (int i = n - 2; i >= 1; i--)
        m[i] = r[i] - c[i] * m[i + 1];
}

double orr_f99_ebv(double lambda_nm, double r_v)
{
    const double x = 1000.0 / lambda_nm;
    if (!(x >= F99_X[0] && x <= F99_X[F99_N - 1]) || !(r_v > 0))
        return NAN;
    double y[F99_N], m[F99_N];
    f99_anchors(r_v, y);
    natural_spline(F99_X, y, F99_N, m);
    int i = 0;
    while (i < F99_N - 2 && x > F99_X[i + 1])
        i++;
    const double h = F99_X[i + 1] - F99_X[i], a = (F99_X[i + 1] - x) / h, b = 1 - a;
    return a * y[i] + b * y[i + 1] + ((a * a * a - a) * m[i] + (b * b * b - b) * m[i + 1]) * h * h / 6;
}

orr_status orr_dust_curve_f99(orr_dust_curve *c, double r_v, orr_error *err)
{
    if (!(r_v > 0) || !isfinite(r_v))
        return orr_fail(err, ORR_ERR_USAGE, "dust.r_v = %g: R_V must be a number > 0 (3.1 is the diffuse ISM)",
                        r_v);
    const double at_v = orr_f99_ebv(ORR_DUST_V_NM, r_v);
    for (int i = 0; i < ORR_DUST_CURVE_N; i++)
        c->a[i] = orr_f99_ebv(ORR_DUST_CURVE_FIRST_NM + i, r_v) / at_v;
    return ORR_OK;
}

double orr_dust_curve_at(const orr_dust_curve *c, double lambda_nm)
{
    double u = lambda_nm - ORR_DUST_CURVE_FIRST_NM;
    if (!(u > 0))
        return c->a[0];
    if (u >= ORR_DUST_CURVE_N - 1)
        return c->a[ORR_DUST_CURVE_N - 1];
    int i = (int)u;
    double f = u - i;
    return c->a[i] * (1 - f) + c->a[i + 1] * f;
}

/* ---- a curve from a file ---- */

typedef struct curve_rows {
    double *lambda, *value;
    size_t n, cap;
} curve_rows;

static orr_status rows_push(curve_rows *r, double l, double v, orr_error *err)
{
    if (r->n == r->cap) {
        size_t cap = r->cap ? 2 * r->cap : 256;
        double *nl = realloc(r->lambda, cap * sizeof *nl);
        if (nl)
            r->lambda = nl;
        double *nv = nl ? realloc(r->value, cap * sizeof *nv) : NULL;
        if (nv)
            r->value = nv;
        if (!nl || !nv)
            return orr_fail(err, ORR_ERR_NOMEM, "out of memory reading an extinction curve");
        r->cap = cap;
    }
    r->lambda[r->n] = l;
    r->value[r->n] = v;
    r->n++;
    return ORR_OK;
}

/* Whether the line holds only a comment or blanks. */
static int blank_line(const char *s)
{
    while (*s == ' ' || *s == '\t' || *s == '\r' || *s == '\n')
        s++;
    return *s == '\0' || *s == '#';
}

/* One row "lambda value" (commas allowed), checked against the previous. */
static orr_status parse_row(const char *path, int line, const char *text, const curve_rows *r, double *l,
                            double *v, orr_error *err)
{
    char *end;
    *l = strtod(text, &end);
    const char *p = end;
    while (*p == ' ' || *p == '\t' || *p == ',')
        p++;
    char *end2;
    *v = strtod(p, &end2);
    if (end == text || end2 == p)
        return orr_fail(err, ORR_ERR_FORMAT, "%s:%d: dust.curve: expected two numbers, wavelength (nm) and "
                        "A_lambda/A_V", path, line);
    if (!isfinite(*l) || !isfinite(*v) || *v < 0 || *l <= 0)
        return orr_fail(err, ORR_ERR_FORMAT, "%s:%d: dust.curve: wavelength %g nm, A_lambda/A_V %g: values must "
                        "be finite, wavelengths > 0 and A_lambda/A_V >= 0", path, line, *l, *v);
    if (r->n > 0 && !(*l > r->lambda[r->n - 1]))
        return orr_fail(err, ORR_ERR_FORMAT, "%s:%d: dust.curve: wavelength %g nm after %g nm: wavelengths must "
                        "increase strictly", path, line, *l, r->lambda[r->n - 1]);
    if (r->n > 0 && *l - r->lambda[r->n - 1] > ORR_DUST_CURVE_MAX_GAP_NM)
        return orr_fail(err, ORR_ERR_FORMAT, "%s:%d: dust.curve: a gap from %g to %g nm (rows may be at most %g nm "
                        "apart)", path, line, r->lambda[r->n - 1], *l, ORR_DUST_CURVE_MAX_GAP_NM);
    return ORR_OK;
}

static orr_status read_rows(FILE *fp, const char *path, curve_rows *r, orr_error *err)
{
    char buf[512];
    int line = 0;
    while (fgets(buf, sizeof buf, fp)) {
        line++;
        if (blank_line(buf))
            continue;
        double l, v;
        orr_status st = parse_row(path, line, buf, r, &l, &v, err);
        if (!st)
            st = rows_push(r, l, v, err);
        if (st)
            return st;
    }
    if (ferror(fp))
        return orr_fail(err, ORR_ERR_IO, "%s: dust.curve: read error", path);
    return ORR_OK;
}

static double rows_at(const curve_rows *r, double l)
{
    size_t i = 1;
    while (i < r->n - 1 && r->lambda[i] < l)
        i++;
    double f = (l - r->lambda[i - 1]) / (r->lambda[i] - r->lambda[i - 1]);
    return r->value[i - 1] + f * (r->value[i] - r->value[i - 1]);
}

orr_status orr_dust_curve_load(orr_dust_curve *c, const char *path, orr_error *err)
{
    FILE *fp = fopen(path, "r");
    if (!fp)
        return orr_fail(err, ORR_ERR_IO, "%s: dust.curve: cannot open: %s", path, strerror(errno));
    curve_rows r = {0};
    orr_status st = read_rows(fp, path, &r, err);
    fclose(fp);
    if (!st && (r.n < 2 || r.lambda[0] > ORR_DUST_CURVE_FIRST_NM || r.lambda[r.n - 1] < ORR_DUST_CURVE_LAST_NM))
        st = orr_fail(err, ORR_ERR_FORMAT, "%s: dust.curve: the rows cover %g-%g nm; they must cover %d-%d nm (the "
                      "colour-matching functions' range)", path, r.n ? r.lambda[0] : 0.0,
                      r.n ? r.lambda[r.n - 1] : 0.0, ORR_DUST_CURVE_FIRST_NM, ORR_DUST_CURVE_LAST_NM);
    for (int i = 0; i < ORR_DUST_CURVE_N && !st; i++)
        c->a[i] = rows_at(&r, ORR_DUST_CURVE_FIRST_NM + i);
    free(r.lambda);
    free(r.value);
    return st;
}
