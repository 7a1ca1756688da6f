/* Equilibrium building blocks: galaxy_df.h says what and why. */
#define _XOPEN_SOURCE 700 /* j1, the Bessel function of the first kind (XSI) */
#include "source/models/galaxy_df.h"

#include <math.h>
#include <stdlib.h>

#define GDF_PI 3.14159265358979323846

/* ---- modified Bessel functions (Abramowitz & Stegun 9.8.1-9.8.8) ------- */

/* c[0] + c[1] t + ... + c[n-1] t^(n-1) */
static double poly(const double *c, int n, double t)
{
    double s = 0.0;
    for (int k = n - 1; k >= 0; k--)
        s = s * t + c[k];
    return s;
}

double gdf_bessel_i0(double x)
{
    static const double small[] = {1.0, 3.5156229, 3.0899424, 1.2067492, 0.2659732, 0.0360768, 0.0045813};
    static const double large[] = {0.39894228, 0.01328592, 0.00225319, -0.00157565, 0.00916281,
                                   -0.02057706, 0.02635537, -0.01647633, 0.00392377};
    double ax = fabs(x);
    if (ax < 3.75) {
        double t = ax / 3.75;
        return poly(small, 7, t * t);
    }
    return exp(ax) / sqrt(ax) * poly(large, 9, 3.75 / ax);
}

double gdf_bessel_i1(double x)
{
    static const double small[] = {0.5, 0.87890594, 0.51498869, 0.15084934, 0.02658733, 0.00301532, 0.00032411};
    static const double large[] = {0.39894228, -0.03988024, -0.00362018, 0.00163801, -0.01031555,
                                   0.02282967, -0.02895312, 0.01787654, -0.00420059};
    double ax = fabs(x), v;
    if (ax < 3.75) {
        double t = ax / 3.75;
        v = ax * poly(small, 7, t * t);
    } else {
        v = exp(ax) / sqrt(ax) * poly(large, 9, 3.75 / ax);
    }
    return x < 0 ? -v : v;
}

double gdf_bessel_k0(double x)
{
    static const double small[] = {-0.57721566, 0.42278420, 0.23069756, 0.03488590,
                                   0.00262698,  0.00010750, 0.00000740};
    static const double large[] = {1.25331414, -0.07832358, 0.02189568, -0.01062446,
                                   0.00587872, -0.00251540, 0.00053208};
    if (x <= 2.0) {
        double t = 0.5 * x;
        return -log(t) * gdf_bessel_i0(x) + poly(small, 7, t * t);
    }
    return exp(-x) / sqrt(x) * poly(large, 7, 2.0 / x);
}

double gdf_bessel_k1(double x)
{
    static const double small[] = {1.0,         0.15443144,  -0.67278579, -0.18156897,
                                   -0.01919402, -0.00110404, -0.00004686};
    static const double large[] = {1.25331414, 0.23498619,  -0.03655620, 0.01504268,
                                   -0.00780353, 0.00325614, -0.00068245};
    if (x <= 2.0) {
        double t = 0.5 * x;
        return log(t) * gdf_bessel_i1(x) + poly(small, 7, t * t) / x;
    }
    return exp(-x) / sqrt(x) * poly(large, 7, 2.0 / x);
}

double gdf_freeman_vc2(double R, double rd, double G_sigma0)
{
    if (R <= 0.0)
        return 0.0;
    double y = 0.5 * R / rd;
    /* Products I*K are formed directly: e^y and e^-y cancel and nothing
     * overflows for the radii a model uses (y < 100). */
    double b = gdf_bessel_i0(y) * gdf_bessel_k0(y) - gdf_bessel_i1(y) * gdf_bessel_k1(y);
    return 4.0 * GDF_PI * G_sigma0 * rd * y * y * b;
}

double gdf_thick_disc_vc2(double R, double rd, double h, double G_sigma0)
{
    /* Up to k = 20/h the thickness factor has cut the integrand to ~1/20 of
     * its thin-disc value (which itself falls as k^-2); a thin disc stops
     * at k = 2000/rd. At least 4000 points, and 20 per period of J1(kR). */
    double kmax = fmin(20.0 / h, 2000.0 / rd);
    int n = (int)ceil(kmax / fmin(kmax / 4000.0, 0.3 / R));
    double dk = kmax / n, sum = 0.0;
    for (int i = 0; i < n; i++) {
        double k = (i + 0.5) * dk, s = 1.0 + k * k * rd * rd;
        sum += k * j1(k * R) / (s * sqrt(s) * (1.0 + k * h));
    }
    return 2.0 * GDF_PI * G_sigma0 * rd * rd * R * sum * dk;
}

/* ---- spherical potential ----------------------------------------------- */

void gdf_potential_build(gdf_potential *p, double rmin, double rmax, double (*gm_fn)(double, const void *),
                         const void *ctx)
{
    p->ln_rmin = log(rmin);
    p->dln = (log(rmax) - p->ln_rmin) / (GDF_POT_N - 1);
    for (int i = 0; i < GDF_POT_N; i++)
        p->gm[i] = gm_fn(exp(p->ln_rmin + i * p->dln), ctx);
    /* psi(rmax) = G M / rmax; inward, d psi = G M(r) / r^2 dr = G M / r d ln r
     * (trapezoid rule in ln r). */
    p->psi[GDF_POT_N - 1] = p->gm[GDF_POT_N - 1] / rmax;
    for (int i = GDF_POT_N - 2; i >= 0; i--) {
        double ri = exp(p->ln_rmin + i * p->dln), rj = exp(p->ln_rmin + (i + 1) * p->dln);
        p->psi[i] = p->psi[i + 1] + 0.5 * (p->gm[i] / ri + p->gm[i + 1] / rj) * p->dln;
    }
}

double gdf_psi(const gdf_potential *p, double r)
{
    return gdf_psi_ln(p, r, r > 0 ? log(r) : 0.0);
}

double gdf_psi_ln(const gdf_potential *p, double r, double ln_r)
{
    double t = r > 0 ? (ln_r - p->ln_rmin) / p->dln : -1.0;
    if (t <= 0.0)
        return p->psi[0];
    if (t >= GDF_POT_N - 1)
        return p->gm[GDF_POT_N - 1] / r;
    int i = (int)t;
    double f = t - i;
    return p->psi[i] + f * (p->psi[i + 1] - p->psi[i]);
}

/* ---- Eddington inversion ------------------------------------------------ */

/* f(E) on the potential grid's energies E_j = psi_j, from h = d rho / d psi
 * and g = d h / d psi at the grid points. Over each grid interval g is taken
 * as its mean and 1/sqrt(E - psi) is integrated exactly, so the
 * integrable singularity at psi = E costs no accuracy. The part of the
 * integral beyond the grid's last radius, where psi < psi_last, is
 * h(psi_last) / sqrt(E - psi_last) to first order (it also stands for the
 * boundary term h(0) / sqrt(E), which vanishes for our profiles). */
static void eddington(const gdf_potential *p, const double *h, const double *g, double *f, int *negative)
{
    const int n = GDF_POT_N;
    const double norm = 1.0 / (sqrt(8.0) * GDF_PI * GDF_PI);
    *negative = 0;
    for (int j = 0; j < n; j++) {
        double e = p->psi[j], sum = 0.0;
        for (int i = j; i < n - 1; i++) {
            double w = 2.0 * (sqrt(e - p->psi[i + 1]) - sqrt(fmax(0.0, e - p->psi[i])));
            sum += 0.5 * (g[i] + g[i + 1]) * w;
        }
        if (j < n - 1)
            sum += h[n - 1] / sqrt(e - p->psi[n - 1]);
        f[j] = norm * sum;
        if (f[j] < 0.0) {
            f[j] = 0.0;
            (*negative)++;
        }
    }
}

/* f at any energy: the grid's psi decreases with index, so a bisection
 * finds the bracketing pair; linear in between, 0 below the last energy. */
static double f_at(const gdf_potential *p, const double *f, double e)
{
    if (e >= p->psi[0])
        return f[0];
    if (e <= p->psi[GDF_POT_N - 1])
        return 0.0;
    int lo = 0, hi = GDF_POT_N - 1; /* psi[lo] > e >= psi[hi] */
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (p->psi[mid] > e)
            lo = mid;
        else
            hi = mid;
    }
    double t = (p->psi[lo] - e) / (p->psi[lo] - p->psi[hi]);
    return f[lo] + t * (f[hi] - f[lo]);
}

#define FINE_Q 512

/* The table's columns hold q at cumulative probabilities u_j =
 * 1 - (1 - j / (GDF_COLS - 1))^2, crowded toward u = 1: the fast tail, where
 * q climbs steeply to its largest value, needs them. With columns uniform
 * in u the last one spanned u = 0.992 to 1, and q interpolated linearly
 * across it overstated <v^2> by 3-4% for a bulge in a deep halo potential
 * (its speeds reach only a quarter of the escape speed, but its last column
 * goes up to it): the Milky Way's bulge was made that much too hot. */
static double column_probability(int j)
{
    double t = 1.0 - (double)j / (GDF_COLS - 1);
    return 1.0 - t * t;
}

/* One row: the inverse cumulative distribution of q = v / v_esc at psi,
 * p(q) ~ q^2 f(psi (1 - q^2)), from a trapezoid CDF on FINE_Q points. */
static void speed_row(const gdf_potential *p, const double *f, double psi, float *row)
{
    double cdf[FINE_Q], prev = 0.0;
    cdf[0] = 0.0;
    for (int m = 1; m < FINE_Q; m++) {
        double q = (double)m / (FINE_Q - 1);
        double pm = q * q * f_at(p, f, psi * (1.0 - q * q));
        cdf[m] = cdf[m - 1] + 0.5 * (prev + pm) / (FINE_Q - 1);
        prev = pm;
    }
    double total = cdf[FINE_Q - 1];
    int m = 0;
    for (int j = 0; j < GDF_COLS; j++) {
        if (!(total > 0.0)) {
            row[j] = 0.0f;
            continue;
        }
        double c = total * column_probability(j);
        while (m < FINE_Q - 2 && cdf[m + 1] < c)
            m++;
        double span = cdf[m + 1] - cdf[m];
        double t = span > 0 ? (c - cdf[m]) / span : 0.0;
        if (t > 1.0)
            t = 1.0;
        row[j] = (float)((m + t) / (FINE_Q - 1));
    }
}

int gdf_speeds_build(gdf_speeds *s, const gdf_potential *p, double rmin, double rmax,
                     double (*rho_fn)(double, const void *), double (*dlnrho_fn)(double, const void *),
                     const void *ctx)
{
    const int n = GDF_POT_N;
    double *h = malloc(3 * n * sizeof *h);
    if (!h)
        return 0;
    double *g = h + n, *f = h + 2 * n;
    /* h = d rho / d psi = (d rho / dr) / (d psi / dr), d psi / dr = -G M / r^2. */
    for (int i = 0; i < n; i++) {
        double r = exp(p->ln_rmin + i * p->dln);
        h[i] = -rho_fn(r, ctx) * dlnrho_fn(r, ctx) * r / p->gm[i];
    }
    for (int i = 0; i < n; i++) {
        int a = i > 0 ? i - 1 : i, b = i < n - 1 ? i + 1 : i;
        g[i] = (h[b] - h[a]) / (p->psi[b] - p->psi[a]);
    }
    eddington(p, h, g, f, &s->negative_f);
    s->ln_rmin = log(rmin);
    s->dln = (log(rmax) - s->ln_rmin) / (GDF_ROWS - 1);
#pragma omp parallel for schedule(dynamic, 8) /* rows are independent */
    for (int k = 0; k < GDF_ROWS; k++)
        speed_row(p, f, gdf_psi(p, exp(s->ln_rmin + k * s->dln)), s->q[k]);
    free(h);
    return 1;
}

double gdf_speed(const gdf_speeds *s, const gdf_potential *p, double r, double u)
{
    return gdf_speed_ln(s, p, r, r > 0 ? log(r) : 0.0, u);
}

double gdf_speed_ln(const gdf_speeds *s, const gdf_potential *p, double r, double ln_r, double u)
{
    double t = r > 0 ? (ln_r - s->ln_rmin) / s->dln : 0.0;
    t = t < 0 ? 0 : t > GDF_ROWS - 1 ? GDF_ROWS - 1 : t;
    int k = (int)t;
    if (k >= GDF_ROWS - 1)
        k = GDF_ROWS - 2;
    double fr = t - k;
    double c = (1.0 - sqrt(fmax(0.0, 1.0 - u))) * (GDF_COLS - 1); /* inverse of column_probability */
    int j = (int)c;
    if (j >= GDF_COLS - 1)
        j = GDF_COLS - 2;
    double fc = c - j;
    double q0 = s->q[k][j] + fc * (s->q[k][j + 1] - s->q[k][j]);
    double q1 = s->q[k + 1][j] + fc * (s->q[k + 1][j + 1] - s->q[k + 1][j]);
    double q = q0 + fr * (q1 - q0);
    return q * sqrt(2.0 * gdf_psi_ln(p, r, ln_r));
}
