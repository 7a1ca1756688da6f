#include "splat/kernel.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/vecmath.h"
#include "splat/kernel_separable.h"

/* ---- the kernels ----
 *
 * All three with support radius 2h, written in q = r / h:
 *
 * M4 cubic spline (Monaghan & Lattanzio 1985, A&A 149, 135):
 *   w = 1 - 3/2 q^2 + 3/4 q^3 (q < 1), 1/4 (2 - q)^3 (1 <= q < 2);
 *   sigma = 1 / pi in 3-D.
 * Wendland (1995, Adv. Comput. Math. 4, 389) C2 and C4, in the 3-D forms
 * and normalisations of Dehnen & Aly (2012, MNRAS 425, 1068, table 1),
 * which use the support radius H = 2h; with t = 1 - q/2:
 *   C2: w = t^4 (1 + 2q),                 sigma = 21 / (16 pi);
 *   C4: w = t^6 (1 + 3q + 35/12 q^2),     sigma = 495 / (256 pi).
 *
 * lap w = w'' + 2 w' / q is the 3-D Laplacian of w (derived by hand from
 * the formulas above; the tests check it against finite differences).
 * Projected along the line of sight it gives the 2-D Laplacian of the
 * column kernel, because the z-derivative term integrates to zero. */

static double shape(orr_kernel_kind kind, double q)
{
    if (!(q < 2.0))
        return 0.0;
    double t = 1.0 - 0.5 * q;
    switch (kind) {
    case ORR_KERNEL_CUBIC:
        return q < 1.0 ? 1.0 - 1.5 * q * q + 0.75 * q * q * q : 0.25 * (2.0 - q) * (2.0 - q) * (2.0 - q);
    case ORR_KERNEL_WENDLAND_C2:
        return t * t * t * t * (1.0 + 2.0 * q);
    case ORR_KERNEL_WENDLAND_C4:
        return t * t * t * t * t * t * (1.0 + 3.0 * q + 35.0 / 12.0 * q * q);
    }
    return 0.0;
}

static double shape_laplacian(orr_kernel_kind kind, double q)
{
    if (!(q < 2.0))
        return 0.0;
    double t = 1.0 - 0.5 * q;
    switch (kind) {
    case ORR_KERNEL_CUBIC:
        /* w' = -3q + 9/4 q^2, w'' = -3 + 9/2 q inside; w' = -3/4 (2-q)^2,
         * w'' = 3/2 (2-q) outside. */
        return q < 1.0 ? -9.0 + 9.0 * q : 1.5 * (2.0 - q) - 1.5 * (2.0 - q) * (2.0 - q) / q;
    case ORR_KERNEL_WENDLAND_C2:
        /* w' = -5 q t^3, w'' = 5 t^2 (2q - 1). */
        return 15.0 * t * t * (q - 1.0);
    case ORR_KERNEL_WENDLAND_C4:
        /* w' = -7/3 q (2 + 5q) t^5, w'' = -7/3 t^4 (2 + 4q - 35/2 q^2). */
        return -7.0 / 3.0 * t * t * t * t * (6.0 + 12.0 * q - 22.5 * q * q);
    }
    return 0.0;
}

static double sigma_of(orr_kernel_kind kind)
{
    switch (kind) {
    case ORR_KERNEL_CUBIC: return 1.0 / ORR_PI;
    case ORR_KERNEL_WENDLAND_C2: return 21.0 / (16.0 * ORR_PI);
    case ORR_KERNEL_WENDLAND_C4: return 495.0 / (256.0 * ORR_PI);
    }
    return 0.0;
}

const orr_named orr_kernel_names[] = {{"cubic", ORR_KERNEL_CUBIC},
                                      {"wendland-c2", ORR_KERNEL_WENDLAND_C2},
                                      {"wendland-c4", ORR_KERNEL_WENDLAND_C4},
                                      {NULL, 0}};

const char *orr_kernel_name(orr_kernel_kind kind) { return orr_named_name(orr_kernel_names, (int)kind); }

orr_status orr_kernel_parse(const char *name, orr_kernel_kind *kind, orr_error *err)
{
    static const orr_named aliases[] = {
        {"m4", ORR_KERNEL_CUBIC},        {"cubic-spline", ORR_KERNEL_CUBIC}, {"wendland2", ORR_KERNEL_WENDLAND_C2},
        {"c2", ORR_KERNEL_WENDLAND_C2}, {"wendland4", ORR_KERNEL_WENDLAND_C4}, {"c4", ORR_KERNEL_WENDLAND_C4},
        {NULL, 0}};
    int v;
    if (orr_named_value(orr_kernel_names, name, &v) || orr_named_value(aliases, name, &v)) {
        *kind = (orr_kernel_kind)v;
        return ORR_OK;
    }
    return orr_fail(err, ORR_ERR_USAGE, "unknown smoothing kernel \"%s\" (use cubic, wendland-c2 or wendland-c4)",
                    name ? name : "");
}

double orr_kernel_shape(const orr_kernel *k, double q)
{
    return shape(k->kind, fabs(q));
}

double orr_kernel_w3(const orr_kernel *k, double r, double h)
{
    return k->sigma * shape(k->kind, fabs(r) / h) / (h * h * h);
}

/* ---- quadrature ---- */

/* Gauss-Legendre nodes and weights on [-1, 1], from Newton's method on the
 * Legendre polynomial (three-term recurrence); n is small, so this is
 * exact to round-off and cheaper than carrying a table. */
#define GL_N 12
typedef struct gauss_rule {
    double x[GL_N], w[GL_N];
} gauss_rule;

static gauss_rule gauss_legendre(void)
{
    gauss_rule g;
    for (int i = 0; i < GL_N; i++) {
        double x = cos(ORR_PI * (i + 0.75) / (GL_N + 0.5)), dp = 1.0;
        for (int it = 0; it < 100; it++) {
            double p0 = 1.0, p1 = x;
            for (int n = 2; n <= GL_N; n++) {
                double p2 = ((2 * n - 1) * x * p1 - (n - 1) * p0) / n;
                p0 = p1;
                p1 = p2;
            }
            dp = GL_N * (x * p1 - p0) / (x * x - 1.0);
            double dx = p1 / dp;
            x -= dx;
            if (fabs(dx) < 1e-16)
                break;
        }
        g.x[i] = x;
        g.w[i] = 2.0 / ((1.0 - x * x) * dp * dp);
    }
    return g;
}

/* Integral over [a, b] of f(sqrt(q^2 + z^2)) dz with the rule g. */
static double panel(const gauss_rule *g, double (*f)(orr_kernel_kind, double), orr_kernel_kind kind, double q,
                    double a, double b)
{
    double mid = 0.5 * (a + b), half = 0.5 * (b - a), s = 0.0;
    for (int i = 0; i < GL_N; i++) {
        double z = mid + half * g->x[i];
        s += g->w[i] * f(kind, sqrt(q * q + z * z));
    }
    return s * half;
}

/* 2 sigma * integral over z in [0, sqrt(4 - q^2)] of f(sqrt(q^2 + z^2)).
 * The integrand varies on the scale q near z = 0 (odd powers of r), so the
 * panels grow geometrically from q; the cubic spline's joint at r = 1 is a
 * panel edge. Panels are at most 1/8 long. */
static double line_of_sight(const gauss_rule *g, double (*f)(orr_kernel_kind, double), orr_kernel_kind kind,
                            double sigma, double q)
{
    if (!(q < 2.0))
        return 0.0;
    double zmax = sqrt(4.0 - q * q);
    double z1 = kind == ORR_KERNEL_CUBIC && q < 1.0 ? sqrt(1.0 - q * q) : -1.0;
    double a = 0.0, s = 0.0, step = q > 1e-6 ? q : 1e-6;
    while (a < zmax) {
        double b = a + step;
        if (b > a + 0.125)
            b = a + 0.125;
        if (a < z1 && b > z1)
            b = z1;
        if (b > zmax)
            b = zmax;
        s += panel(g, f, kind, q, a, b);
        step = 2.0 * (b - a);
        a = b;
    }
    return 2.0 * sigma * s;
}

double orr_kernel_column_exact(const orr_kernel *k, double q)
{
    gauss_rule g = gauss_legendre();
    return line_of_sight(&g, shape, k->kind, k->sigma, fabs(q));
}

double orr_kernel_column(const orr_kernel *k, double q)
{
    float lap;
    return orr_kernel_column_u(k, (float)(q * q), &lap);
}

/* ---- tables ---- */

/* F and lap F at the table's nodes. F is then scaled (by a few parts in
 * 10^7) so that the table itself, read with linear interpolation in u,
 * integrates to exactly 1: with dA = pi du that integral is pi times the
 * trapezoid sum in u. Large kernels, whose pixels sample the table, then
 * add up to 1 without a correction (splat/sph.c). */
static void fill_column(orr_kernel *k, const gauss_rule *g)
{
    double f[ORR_KERNEL_NU + 1], sum = 0.0;
    for (int i = 0; i <= ORR_KERNEL_NU; i++) {
        double q = sqrt(4.0 * i / ORR_KERNEL_NU);
        f[i] = line_of_sight(g, shape, k->kind, k->sigma, q);
        k->column[2 * i + 1] = (float)line_of_sight(g, shape_laplacian, k->kind, k->sigma, q);
        sum += i == 0 || i == ORR_KERNEL_NU ? 0.5 * f[i] : f[i];
    }
    double scale = 1.0 / (ORR_PI * sum * 4.0 / ORR_KERNEL_NU);
    for (int i = 0; i <= ORR_KERNEL_NU; i++)
        k->column[2 * i] = (float)(f[i] * scale);
    for (int i = 2 * (ORR_KERNEL_NU + 1); i < 2 * (ORR_KERNEL_NU + 1 + ORR_KERNEL_PAD); i++)
        k->column[i] = 0.0f;
}

/* ---- piecewise polynomials ---- */

/* The range of t = ORR_KERNEL_POLY_T u that piece p covers, and the value
 * subtracted from t to give its local variable x. */
static void poly_piece_range(int p, double *t0, double *t1, double *base)
{
    *t0 = p == 0 ? 0.0 : p == 1 ? 0.25 : p - 1.0;
    *t1 = p == 0 ? 0.25 : p == 1 ? 1.0 : p == ORR_KERNEL_POLY_PIECES - 1 ? 4.0 * ORR_KERNEL_POLY_T : p;
    *base = p <= 1 ? 0.0 : p - 1.0;
}

/* Solves the n x n system a c = b in place (Gaussian elimination with
 * partial pivoting; n is small and the system well conditioned). */
static void solve_small(int n, double a[][ORR_KERNEL_POLY_DEGREE + 1], double *b)
{
    for (int col = 0; col < n; col++) {
        int piv = col;
        for (int r = col + 1; r < n; r++)
            if (fabs(a[r][col]) > fabs(a[piv][col]))
                piv = r;
        for (int c = 0; c < n; c++) {
            double tmp = a[col][c];
            a[col][c] = a[piv][c];
            a[piv][c] = tmp;
        }
        double tmp = b[col];
        b[col] = b[piv];
        b[piv] = tmp;
        for (int r = col + 1; r < n; r++) {
            double f = a[r][col] / a[col][col];
            for (int c = col; c < n; c++)
                a[r][c] -= f * a[col][c];
            b[r] -= f * b[col];
        }
    }
    for (int r = n - 1; r >= 0; r--) {
        for (int c = r + 1; c < n; c++)
            b[r] -= a[r][c] * b[c];
        b[r] /= a[r][r];
    }
}

/* The monomial coefficients (in x) of f over one piece: the Legendre
 * series of f to degree ORR_KERNEL_POLY_DEGREE from the Gauss rule's nodes
 * (the least-squares polynomial, whose integral over the piece is the
 * rule's integral of f), then re-expressed in powers of x by solving for
 * the polynomial through that series' values at DEGREE + 1 points. */
static void fit_piece(const gauss_rule *g, double (*f)(orr_kernel_kind, double), orr_kernel_kind kind,
                      double sigma, int p, double *coef)
{
    enum { D = ORR_KERNEL_POLY_DEGREE };
    double t0, t1, base, fx[GL_N], leg[D + 1] = {0};
    poly_piece_range(p, &t0, &t1, &base);
    const double mid = 0.5 * (t0 + t1), half = 0.5 * (t1 - t0);
    for (int i = 0; i < GL_N; i++)
        fx[i] = line_of_sight(g, f, kind, sigma, sqrt((mid + half * g->x[i]) / ORR_KERNEL_POLY_T));
    for (int i = 0; i < GL_N; i++) {
        double p0 = 1.0, p1 = g->x[i];
        for (int n = 0; n <= D; n++) {
            leg[n] += (2 * n + 1) * 0.5 * g->w[i] * fx[i] * p0;
            double p2 = ((2 * n + 3) * g->x[i] * p1 - (n + 1) * p0) / (n + 2);
            p0 = p1;
            p1 = p2;
        }
    }
    double a[D + 1][D + 1];
    for (int r = 0; r <= D; r++) {
        double s = -1.0 + 2.0 * r / D, x = mid + half * s - base, v = 0.0, p0 = 1.0, p1 = s, xp = 1.0;
        for (int n = 0; n <= D; n++) {
            v += leg[n] * p0;
            double p2 = ((2 * n + 3) * s * p1 - (n + 1) * p0) / (n + 2);
            p0 = p1;
            p1 = p2;
        }
        for (int c = 0; c <= D; c++, xp *= x)
            a[r][c] = xp;
        coef[r] = v;
    }
    solve_small(D + 1, a, coef);
}

/* Fits both polynomials, F's scaled so it integrates over the plane
 * (dA = pi du) to exactly 1, as the column table does. */
static void fill_poly(orr_kernel *k, const gauss_rule *g)
{
    enum { D = ORR_KERNEL_POLY_DEGREE, P = ORR_KERNEL_POLY_PIECES };
    double cf[P][D + 1], cl[P][D + 1], integral = 0.0;
    for (int p = 0; p < P; p++) {
        fit_piece(g, shape, k->kind, k->sigma, p, cf[p]);
        fit_piece(g, shape_laplacian, k->kind, k->sigma, p, cl[p]);
        double t0, t1, base;
        poly_piece_range(p, &t0, &t1, &base);
        for (int d = 0; d <= D; d++)
            integral += cf[p][d] * (pow(t1 - base, d + 1) - pow(t0 - base, d + 1)) / (d + 1);
    }
    const double scale = 1.0 / (ORR_PI * integral / ORR_KERNEL_POLY_T);
    for (int p = 0; p < P; p++)
        for (int d = 0; d <= D; d++) {
            k->poly_f[d * P + p] = (float)(cf[p][d] * scale);
            k->poly_lap[d * P + p] = (float)cl[p][d];
        }
}

/* The integral of F over one cell of the cumulative table, by a 4 x 4
 * Gauss-Legendre rule on the column table (accurate to ~1e-7 of F). */
static double cell_integral(const orr_kernel *k, double a0, double b0, double d)
{
    static const double x[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                                0.8611363115940526};
    static const double w[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                                0.3478548451374538};
    double s = 0.0;
    for (int i = 0; i < 4; i++) {
        double a = a0 + 0.5 * d * (1.0 + x[i]);
        for (int j = 0; j < 4; j++) {
            double b = b0 + 0.5 * d * (1.0 + x[j]);
            float lap;
            s += w[i] * w[j] * orr_kernel_column_u(k, (float)(a * a + b * b), &lap);
        }
    }
    return s * 0.25 * d * d;
}

/* The integrals of F over the n x n cells of width 2 / n tiling [0, 2]^2
 * (F is symmetric, so only cells with a <= b are integrated). */
static double *cell_table(const orr_kernel *k, int n, orr_error *err)
{
    const double d = 2.0 / n;
    double *cell = orr_malloc(sizeof(double) * (size_t)n * n, "kernel table scratch", err);
    if (!cell)
        return NULL;
    for (int j = 0; j < n; j++)
        for (int i = 0; i <= j; i++)
            cell[(size_t)j * n + i] = cell[(size_t)i * n + j] = cell_integral(k, i * d, j * d, d);
    return cell;
}

/* G(a, b) = integral of F over [0, a] x [0, b] as prefix sums of the cell
 * integrals, scaled so G(2, 2) is exactly 1/4 and a whole kernel deposits
 * exactly 1. */
static orr_status fill_cumulative(orr_kernel *k, const double *cell, orr_error *err)
{
    const int n = ORR_KERNEL_NG, m = n + 1;
    double *g = orr_calloc((size_t)m * m, sizeof(double), "kernel table scratch", err);
    if (!g)
        return ORR_ERR_NOMEM;
    for (int j = 1; j < m; j++)
        for (int i = 1; i < m; i++)
            g[(size_t)j * m + i] = cell[(size_t)(j - 1) * n + (i - 1)] + g[(size_t)(j - 1) * m + i] +
                                   g[(size_t)j * m + (i - 1)] - g[(size_t)(j - 1) * m + (i - 1)];
    double scale = 0.25 / g[(size_t)m * m - 1];
    for (size_t i = 0; i < (size_t)m * m; i++)
        k->cumulative[i] = (float)(g[i] * scale);
    k->cumulative[(size_t)m * m - 1] = 0.25f;
    free(g);
    return ORR_OK;
}

orr_status orr_kernel_init(orr_kernel *k, orr_kernel_kind kind, orr_error *err)
{
    memset(k, 0, sizeof *k);
    if (kind != ORR_KERNEL_CUBIC && kind != ORR_KERNEL_WENDLAND_C2 && kind != ORR_KERNEL_WENDLAND_C4)
        return orr_fail(err, ORR_ERR_USAGE, "unknown smoothing kernel kind %d", (int)kind);
    k->kind = kind;
    k->sigma = sigma_of(kind);
    const size_t m = (size_t)(ORR_KERNEL_NG + 1) * (ORR_KERNEL_NG + 1);
    k->column = orr_malloc(sizeof(float) * 2 * (ORR_KERNEL_NU + 1 + ORR_KERNEL_PAD), "kernel column table", err);
    k->cumulative = orr_malloc(sizeof(float) * m, "kernel cumulative table", err);
    if (!k->column || !k->cumulative) {
        orr_kernel_free(k);
        return ORR_ERR_NOMEM;
    }
    gauss_rule g = gauss_legendre();
    fill_column(k, &g);
    fill_poly(k, &g);
    double *cell = cell_table(k, ORR_KERNEL_NG, err);
    orr_status st = cell ? fill_cumulative(k, cell, err) : ORR_ERR_NOMEM;
    if (!st)
        st = orr_kernel_fill_separable(k, cell, ORR_KERNEL_NG, err);
    free(cell);
    if (st)
        orr_kernel_free(k);
    return st;
}

void orr_kernel_free(orr_kernel *k)
{
    free(k->column);
    free(k->cumulative);
    free(k->separable);
    k->column = NULL;
    k->cumulative = NULL;
    k->separable = NULL;
}

/* ---- rectangles ---- */

/* G(|x|, |y|) with the signs of x and y: the integral of F over the
 * rectangle between the centre and (x, y), counted negative in the
 * quadrants where one coordinate is. Bilinear in the table. */
static double corner(const orr_kernel *k, double x, double y)
{
    double s = (x < 0) == (y < 0) ? 1.0 : -1.0;
    double a = fmin(fabs(x), 2.0) * (ORR_KERNEL_NG / 2.0), b = fmin(fabs(y), 2.0) * (ORR_KERNEL_NG / 2.0);
    int i = (int)a, j = (int)b;
    if (i >= ORR_KERNEL_NG)
        i = ORR_KERNEL_NG - 1;
    if (j >= ORR_KERNEL_NG)
        j = ORR_KERNEL_NG - 1;
    double fa = a - i, fb = b - j;
    const float *g = k->cumulative + (size_t)j * (ORR_KERNEL_NG + 1) + i;
    const float *g1 = g + ORR_KERNEL_NG + 1;
    return s * ((1 - fb) * ((1 - fa) * g[0] + fa * g[1]) + fb * ((1 - fa) * g1[0] + fa * g1[1]));
}

double orr_kernel_rect(const orr_kernel *k, double x0, double x1, double y0, double y1)
{
    return corner(k, x1, y1) - corner(k, x0, y1) - corner(k, x1, y0) + corner(k, x0, y0);
}
