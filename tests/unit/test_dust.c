/* Dust (docs/dust.md): the CCM89 curve at its defining points and from
 * files (bad ones refused with the line named), the tabulated partial
 * column against the kernel's own column integral, the tree's optical depth
 * against the brute-force line integral through every kernel (a random
 * configuration with the eye and stars inside kernels), and the reddening
 * table against direct integration of Planck's law times the curve, with
 * E(B-V)/A_V in Bessell's (1990) B and V passbands. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <omp.h>
#include <unistd.h>

#include "check.h"
#include "dust/column.h"
#include "dust/column_lanes.h"
#include "dust/column_walk.h"
#include "dust/dust.h"
#include "dust/curve.h"
#include "dust/redden.h"
#include "core/cie_data.h"
#include "post/colour.h"
#include "source/models/model.h"
#include "source/models/model_dust.h"

#define MAG_PER_TAU 1.0857362047581294 /* 2.5 log10(e) */

static void test_ccm89(void)
{
    /* V (0.55 micron, x = 1.82): A/A_V = 1 by construction; B (0.44 micron):
     * a = b = 1 (CCM89 section III), so A_B/A_V = 1 + 1/R_V. */
    CHECK_NEAR(orr_ccm89(1000.0 / 1.82, 3.1), 1.0, 1e-12);
    CHECK_NEAR(orr_ccm89(440.0, 3.1), 1.0 + 1.0 / 3.1, 2e-3);
    CHECK_NEAR(orr_ccm89(440.0, 5.0), 1.0 + 1.0 / 5.0, 2e-3);
    CHECK(isnan(orr_ccm89(200.0, 3.1)));
    orr_dust_curve c;
    orr_error err = {0};
    CHECK(orr_dust_curve_ccm89(&c, 3.1, &err) == ORR_OK);
    /* decreasing with wavelength over the visible: blue is dimmed more */
    for (int i = 1; i < ORR_DUST_CURVE_N; i++)
        CHECK(c.a[i] < c.a[i - 1]);
    CHECK(orr_dust_curve_ccm89(&c, -1, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "dust.r_v");
}

/* Fitzpatrick (1999) against its Table 3: A(lambda)/E(B-V) at the spline's
 * anchors for R_V = 3.1 (the optical ones from its R_V polynomials, the
 * ultraviolet ones from the FM90 form); then the curve normalised at 550 nm,
 * falling through the visible and near CCM89's there (0.047 apart at most,
 * at 700 nm). */
static void test_f99(void)
{
    const double x[] = {0.377, 0.820, 1.667, 1.828, 2.141, 2.433, 3.704, 3.846};
    const double table3[] = {0.265, 0.829, 2.688, 3.055, 3.806, 4.315, 6.265, 6.591};
    for (size_t i = 0; i < sizeof x / sizeof x[0]; i++)
        CHECK_NEAR(orr_f99_ebv(1000.0 / x[i], 3.1), table3[i], 6e-4);
    CHECK(isnan(orr_f99_ebv(200.0, 3.1)));
    orr_dust_curve f, ccm;
    orr_error err = {0};
    CHECK(orr_dust_curve_f99(&f, 3.1, &err) == ORR_OK);
    CHECK(orr_dust_curve_ccm89(&ccm, 3.1, &err) == ORR_OK);
    CHECK_NEAR(orr_dust_curve_at(&f, ORR_DUST_V_NM), 1.0, 1e-12);
    double worst = 0;
    for (int i = 1; i < ORR_DUST_CURVE_N; i++) {
        CHECK(f.a[i] < f.a[i - 1]);
        const double l = ORR_DUST_CURVE_FIRST_NM + i;
        if (l >= 400 && l <= 700)
            worst = fmax(worst, fabs(f.a[i] - ccm.a[i]));
    }
    fprintf(stderr, "  f99: A/A_V at 440 nm %.4f (ccm89 %.4f), at 700 nm %.4f (%.4f); 400-700 nm within %.3f of ccm89\n",
            orr_dust_curve_at(&f, 440), orr_dust_curve_at(&ccm, 440), orr_dust_curve_at(&f, 700),
            orr_dust_curve_at(&ccm, 700), worst);
    CHECK(worst < 0.1); /* two fits of the same dust: a wrong normalisation or anchor is far off */
    CHECK(orr_dust_curve_f99(&f, 0, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "dust.r_v");
}

static const char *write_file(const char *text)
{
    static char path[256];
    snprintf(path, sizeof path, "test_dust_curve_%d.txt", (int)getpid());
    FILE *fp = fopen(path, "w");
    fputs(text, fp);
    fclose(fp);
    return path;
}

/* A file of the CCM89 curve every step nm from a to b, with one row edited. */
static void curve_text(char *buf, size_t size, double a, double b, double step, double bad_at, const char *bad)
{
    size_t n = (size_t)snprintf(buf, size, "# lambda_nm A/A_V\n");
    for (double l = a; l <= b + 1e-9; l += step) {
        if (fabs(l - bad_at) < 1e-9)
            n += (size_t)snprintf(buf + n, size - n, "%s\n", bad);
        else
            n += (size_t)snprintf(buf + n, size - n, "%g %.6f\n", l, orr_ccm89(l, 3.1));
    }
}

static void test_curve_file(void)
{
    static char text[65536];
    orr_dust_curve c, ref;
    orr_error err = {0};
    orr_dust_curve_ccm89(&ref, 3.1, &err);
    curve_text(text, sizeof text, 350, 850, 10, -1, "");
    CHECK(orr_dust_curve_load(&c, write_file(text), &err) == ORR_OK);
    for (int i = 0; i < ORR_DUST_CURVE_N; i += 7)
        CHECK_NEAR(c.a[i], ref.a[i], 2e-3); /* linear between 10 nm rows */
    struct {
        const char *bad, *says;
    } cases[] = {
        {"400 -0.5", "A_lambda/A_V -0.5"},
        {"400 nan", "values must be finite"},
        {"385 1.2", "wavelengths must increase"},
        {"400 one", "expected two numbers"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        curve_text(text, sizeof text, 350, 850, 10, 400, cases[k].bad);
        CHECK(orr_dust_curve_load(&c, write_file(text), &err) == ORR_ERR_FORMAT);
        CHECK_CONTAINS(err.msg, cases[k].says);
        CHECK_CONTAINS(err.msg, ":7:"); /* the line: the comment, then 350 .. 390 */
    }
    curve_text(text, sizeof text, 350, 850, 60, -1, "");
    CHECK(orr_dust_curve_load(&c, write_file(text), &err) == ORR_ERR_FORMAT);
    CHECK_CONTAINS(err.msg, "gap");
    curve_text(text, sizeof text, 400, 850, 10, -1, "");
    CHECK(orr_dust_curve_load(&c, write_file(text), &err) == ORR_ERR_FORMAT);
    CHECK_CONTAINS(err.msg, "must cover 360-830 nm");
    CHECK(orr_dust_curve_load(&c, "no/such/curve.txt", &err) == ORR_ERR_IO);
    unlink(write_file(""));
}

/* The table's whole and partial columns against the kernel's own line-of-
 * sight integral (splat/kernel.h), and its normalisation over the plane. */
static void test_partial_column(void)
{
    orr_dust_set s;
    orr_error err = {0};
    CHECK(orr_dust_set_init(&s, ORR_KERNEL_CUBIC, &err) == ORR_OK);
    double worst = 0, plane = 0;
    for (int i = 0; i < 200; i++) {
        double beta = 2.0 * (i + 0.5) / 200;
        double whole = orr_dust_partial_column(&s, beta, 3) - orr_dust_partial_column(&s, beta, -3);
        worst = fmax(worst, fabs(whole - orr_kernel_column_exact(&s.kernel, beta)));
        CHECK_NEAR(orr_dust_partial_column(&s, beta, 0), 0.5 * whole, 1e-7);
        plane += 2 * 3.14159265358979323846 * beta * whole * (2.0 / 200);
    }
    CHECK(worst < 2e-5);
    CHECK_NEAR(plane, 1.0, 1e-4);
    CHECK(orr_dust_partial_column(&s, 2.0, 0.0) == 0);
    orr_dust_set_free(&s);
}

static double uniform(uint64_t *state)
{
    *state = *state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*state >> 11) * (1.0 / 9007199254740992.0);
}

/* The stars grouped by direction (orr_dust_tau_many) against each star's
 * own walk: the same bit for bit, for all of the stars at once, for every
 * other one (other groups), on one thread and on several, with the terms
 * one at a time as CPUs without AVX2 take them, and eight stars at a time
 * with AVX2 as CPUs without AVX-512 take them; unwanted stars get 0. */
static void check_tau_many(const orr_dust_set *s, const double eye[3], size_t n, const float *x, const float *y,
                           const float *z, const unsigned char *stars, const double *single)
{
    double *tau = malloc(n * sizeof *tau);
    unsigned char *want = malloc(n);
    orr_error err = {0};
    size_t differ = 0, zeros = 0, unwanted_nonzero = 0;
    const int threads = omp_get_max_threads();
    for (int pass = 0; pass < 5; pass++) {
        for (size_t i = 0; i < n; i++)
            want[i] = (!stars || stars[i]) && (pass % 3 == 0 || (i + (size_t)pass) % 2 == 0);
        omp_set_num_threads(pass == 1 ? 1 : 3);
        const orr_dust_terms terms = pass == 3   ? ORR_DUST_TERMS_PLAIN
                                     : pass == 4 ? ORR_DUST_TERMS_EIGHT_AVX2
                                                 : ORR_DUST_TERMS_BEST;
        CHECK(orr_dust_tau_many_with(terms, s, eye, n, x, y, z, pass == 0 && !stars ? NULL : want, tau, &err) ==
              ORR_OK);
        for (size_t i = 0; i < n; i++) {
            if (!want[i]) {
                unwanted_nonzero += tau[i] != 0;
                continue;
            }
            differ += memcmp(&tau[i], &single[i], sizeof tau[i]) != 0;
            zeros += single[i] == 0;
        }
    }
    omp_set_num_threads(threads);
    fprintf(stderr, "  grouped by direction: %zu of %zu stars differ from their own walk\n", differ, n);
    CHECK(differ == 0);
    CHECK(unwanted_nonzero == 0);
    CHECK(zeros < n); /* real columns, not all zero */
    free(tau);
    free(want);
}

/* Eight stars at a time (dust/column_lanes.h), with every kernel of the
 * set as the candidates in the set's order: each lane is its star's own
 * walk bit for bit, every way this CPU runs (AVX-512, two halves with
 * AVX2, and one lane and one term at a time as CPUs without AVX2 take
 * them). */
static void check_star_lanes(const orr_dust_set *s, const double eye[3], size_t n, const float *x, const float *y,
                             const float *z, const double *single)
{
    double *vx = malloc(s->n * sizeof *vx), *vy = malloc(s->n * sizeof *vy), *vz = malloc(s->n * sizeof *vz),
           *v2 = malloc(s->n * sizeof *v2);
    for (size_t j = 0; j < s->n; j++) {
        vx[j] = s->x[j] - eye[0];
        vy[j] = s->y[j] - eye[1];
        vz[j] = s->z[j] - eye[2];
        v2[j] = vx[j] * vx[j] + vy[j] * vy[j] + vz[j] * vz[j];
    }
    const orr_dust_candidate_view all = {s->n, vx, vy, vz, v2, s->ih, s->kih2};
    const orr_dust_lanes_way ways[3] = {ORR_DUST_LANES_PLAIN, ORR_DUST_LANES_AVX2, ORR_DUST_LANES_AVX512};
    const char *names[3] = {"one term at a time", "AVX2", "AVX-512"};
    size_t differ = 0, checked = 0, wanted = 0;
    for (int w = 0; w < 3; w++) {
        if (!orr_dust_star_lanes_runs(ways[w]))
            continue;
        fprintf(stderr, "  eight stars at a time: %s\n", names[w]);
        wanted += 512;
        for (size_t q = 0; q + ORR_DUST_STAR_LANES <= n && q < 512; q += ORR_DUST_STAR_LANES) {
            orr_dust_star_lanes lanes;
            for (int l = 0; l < ORR_DUST_STAR_LANES; l++) {
                const double p[3] = {x[q + l], y[q + l], z[q + l]};
                orr_dust_segment g = {.len = 0};
                CHECK(orr_dust_star_segment(&g, eye, p));
                for (int a = 0; a < 3; a++)
                    lanes.d[a][l] = g.d[a];
                lanes.len[l] = g.len;
            }
            double tau[ORR_DUST_STAR_LANES];
            orr_dust_star_lanes_tau(ways[w], s, &all, &lanes, tau);
            for (int l = 0; l < ORR_DUST_STAR_LANES; l++, checked++)
                differ += memcmp(&tau[l], &single[q + l], sizeof tau[l]) != 0;
        }
    }
    fprintf(stderr, "  eight stars at a time: %zu of %zu stars differ from their own walk\n", differ, checked);
    CHECK(checked == wanted && checked >= 512 && differ == 0);
    free(vx);
    free(vy);
    free(vz);
    free(v2);
}

/* Random kernels in a box, the eye inside one of them, stars anywhere
 * (many inside kernels): the tree against the brute force. */
static void test_tau_random(void)
{
    orr_dust_set s;
    orr_error err = {0};
    CHECK(orr_dust_set_init(&s, ORR_KERNEL_CUBIC, &err) == ORR_OK);
    uint64_t rng = 12345;
    const int nk = 400;
    for (int i = 0; i < nk; i++) {
        float h = (float)(0.02 + 0.1 * uniform(&rng));
        /* k chosen so a kernel's central column k F(0)/h^2 is about 0.5 */
        float k = (float)(0.5 * h * h / 0.48 * (0.2 + 1.6 * uniform(&rng)));
        CHECK(orr_dust_set_add(&s, (float)uniform(&rng), (float)uniform(&rng), (float)uniform(&rng), h, k, &err) ==
              ORR_OK);
    }
    /* The eye at a kernel's centre, offset a little. */
    const double eye[3] = {s.x[17] + 0.01, s.y[17] - 0.005, s.z[17]};
    CHECK(orr_dust_set_build(&s, &err) == ORR_OK);
    enum { nstars = 3000 };
    static float px[nstars], py[nstars], pz[nstars];
    static double single[nstars];
    int within_001 = 0, inside = 0;
    double worst = 0, tau_sum = 0;
    for (int j = 0; j < nstars; j++) {
        double p[3];
        if (j % 3 == 0) { /* at or near a kernel's centre */
            int i = (int)(uniform(&rng) * nk);
            for (int a = 0; a < 3; a++)
                p[a] = (a == 0 ? s.x[i] : a == 1 ? s.y[i] : s.z[i]) + s.h[i] * (uniform(&rng) - 0.5);
            inside++;
        } else {
            for (int a = 0; a < 3; a++)
                p[a] = -0.2 + 1.4 * uniform(&rng);
        }
        px[j] = (float)p[0];
        py[j] = (float)p[1];
        pz[j] = (float)p[2];
        p[0] = px[j]; /* the star as a chunk holds it */
        p[1] = py[j];
        p[2] = pz[j];
        double fast = single[j] = orr_dust_tau(&s, eye, p), exact = orr_dust_tau_exact(&s, eye, p);
        double dmag = MAG_PER_TAU * fabs(fast - exact);
        worst = fmax(worst, dmag);
        within_001 += dmag < 0.01;
        tau_sum += exact;
    }
    fprintf(stderr, "  random: %d stars (%d in kernels), mean tau %.3f, worst |dA_V| %.2e mag, within 0.01: %d\n",
            nstars, inside, tau_sum / nstars, worst, within_001);
    CHECK(tau_sum / nstars > 0.5); /* the test means something: real columns */
    CHECK(within_001 >= 0.99 * nstars);
    CHECK(worst < 0.05);
    check_tau_many(&s, eye, nstars, px, py, pz, NULL, single);
    check_star_lanes(&s, eye, nstars, px, py, pz, single);
    /* a ray to infinity: the limit of ever farther stars */
    const double dir[3] = {0.3, -0.5, 0.8}, far[3] = {eye[0] + 30, eye[1] - 50, eye[2] + 80};
    CHECK_NEAR(orr_dust_tau_ray(&s, eye, dir), orr_dust_tau_exact(&s, eye, far), 1e-3);
    orr_dust_set_free(&s);
}

/* Blackbodies through A_V = 1: the table's colour against direct integration. */
static void test_redden_chromaticity(void)
{
    orr_dust_curve c;
    orr_dust_redden r;
    orr_error err = {0};
    orr_dust_curve_ccm89(&c, 3.1, &err);
    CHECK(orr_dust_redden_build(&r, &c, &err) == ORR_OK);
    const double T[] = {1500, 3000, 4600, 5772, 10000, 12000, 30000, 80000};
    double worst = 0;
    for (size_t i = 0; i < sizeof T / sizeof T[0]; i++)
        for (double av = 0.25; av <= 3.0; av += 0.25) {
            const double tau = av / MAG_PER_TAU;
            double xyz0[3], direct[3], xd, yd, xt, yt;
            orr_blackbody_xyz(T[i], ORR_CMF_CIE1931, xyz0);
            float w[3] = {(float)(2 * xyz0[0]), (float)(2 * xyz0[1]), (float)(2 * xyz0[2])};
            orr_dust_redden_apply(&r, tau, w);
            orr_dust_blackbody_through(T[i], tau, &c, direct);
            double t[3] = {w[0], w[1], w[2]};
            orr_xyz_to_xy(direct, &xd, &yd);
            orr_xyz_to_xy(t, &xt, &yt);
            worst = fmax(worst, fmax(fabs(xt - xd), fabs(yt - yd)));
            /* and the luminance: Y dimmed as the direct integral says */
            double base[3];
            orr_dust_blackbody_through(T[i], 0, &c, base);
            CHECK_NEAR(w[1] / 2.0, direct[1] / base[1], 2e-4 * direct[1] / base[1] + 1e-7);
        }
    fprintf(stderr, "  reddening: worst chromaticity error %.2e\n", worst);
    CHECK(worst < 1e-4);
    /* reddened: a hot star's x and y grow */
    double xyz0[3], x0, y0;
    orr_blackbody_xyz(12000, ORR_CMF_CIE1931, xyz0);
    float w[3] = {(float)xyz0[0], (float)xyz0[1], (float)xyz0[2]};
    orr_dust_redden_apply(&r, 1.0, w);
    double t[3] = {w[0], w[1], w[2]}, x1, y1;
    orr_xyz_to_xy(xyz0, &x0, &y0);
    orr_xyz_to_xy(t, &x1, &y1);
    CHECK(x1 > x0 + 0.02 && y1 > y0);
    orr_dust_redden_free(&r);
}

/* Bessell (1990, PASP 102, 1181) B and V responses, 10 nm apart, as
 * tabulated in speclite (desihub/speclite, data/filters/bessell-{B,V}.ecsv). */
static const double BESSELL_B[] = {0.0,   0.03,  0.134, 0.567, 0.92,  0.978, 1.0,   0.978, 0.935, 0.853, 0.74,
                                   0.64,  0.536, 0.424, 0.325, 0.235, 0.15,  0.095, 0.043, 0.009, 0.0};
#define BESSELL_B_FIRST 360
static const double BESSELL_V[] = {0.0,   0.03,  0.163, 0.458, 0.78,  0.967, 1.0,   0.973, 0.898,
                                   0.792, 0.684, 0.574, 0.461, 0.359, 0.27,  0.197, 0.135, 0.081,
                                   0.045, 0.025, 0.017, 0.013, 0.009, 0.0};
#define BESSELL_V_FIRST 470

static double response(const double *r, int n, int first, double l)
{
    double u = (l - first) / 10.0;
    if (u < 0 || u >= n - 1)
        return 0;
    int i = (int)u;
    return r[i] + (u - i) * (r[i + 1] - r[i]);
}

/* Magnitude of a blackbody through tau in a band, Bessell's (1990) R as an
 * energy response: integral B_lambda R e^(-tau a) on 1 nm steps (counting
 * photons, B_lambda lambda R, moves E(B-V)/A_V by about 1 %: docs/dust.md). */
static double band_mag(const double *r, int n, int first, double T, double tau, const orr_dust_curve *c)
{
    double sum = 0;
    for (int l = ORR_DUST_CURVE_FIRST_NM; l <= ORR_DUST_CURVE_LAST_NM; l++) {
        double x = 1.438776877e7 / (l * T), lum = l * 1e-3;
        double planck = 1.0 / (lum * lum * lum * lum * lum * expm1(x));
        sum += planck * response(r, n, first, l) * exp(-tau * orr_dust_curve_at(c, l));
    }
    return -2.5 * log10(sum);
}

/* E(B-V)/A_V of a blackbody at T through A_V ~ 1 in Bessell's B and V. */
static double ebv_ratio(double T, const orr_dust_curve *c, double *av_out)
{
    const int nb = sizeof BESSELL_B / sizeof BESSELL_B[0], nv = sizeof BESSELL_V / sizeof BESSELL_V[0];
    const double tau = 1.0 / MAG_PER_TAU;
    double ab = band_mag(BESSELL_B, nb, BESSELL_B_FIRST, T, tau, c) - band_mag(BESSELL_B, nb, BESSELL_B_FIRST, T, 0, c);
    double av = band_mag(BESSELL_V, nv, BESSELL_V_FIRST, T, tau, c) - band_mag(BESSELL_V, nv, BESSELL_V_FIRST, T, 0, c);
    *av_out = av;
    return (ab - av) / av;
}

/* E(B-V)/A_V = 1/R_V: exactly at the curve's B and V wavelengths (440 and
 * 550 nm, where CCM89 is normalised); in Bessell's broad passbands for a
 * hot star (the early-type stars R_V was measured on) within 2 %, and for a
 * Sun-like star smaller (its B light sits at longer wavelengths, where the
 * curve is lower: docs/dust.md gives the figure), within 10 %. */
static void test_ebv(void)
{
    orr_dust_curve c;
    orr_error err = {0};
    for (double rv = 2.5; rv <= 5.01; rv += 0.6) {
        orr_dust_curve_ccm89(&c, rv, &err);
        double mono = orr_dust_curve_at(&c, 440) - orr_dust_curve_at(&c, 1000.0 / 1.82);
        CHECK(fabs(mono * rv - 1) < 0.01); /* a(2.27) and b(2.27) are 1 to 3 decimals */
        double av_hot, av_sun;
        double hot = ebv_ratio(20000, &c, &av_hot), sun = ebv_ratio(5772, &c, &av_sun);
        fprintf(stderr, "  R_V %.1f: E(B-V)/A_V x R_V: at 440/550 nm %.4f; Bessell B, V: 20000 K %.4f, 5772 K %.4f\n",
                rv, mono * rv, hot * rv, sun * rv);
        CHECK(fabs(hot * rv - 1) < 0.02);
        CHECK(sun < hot && fabs(sun * rv - 1) < 0.10);
        CHECK(fabs(av_sun - 1) < 0.01);
    }
}

/* The model's dusty gas discs: off, the stream is byte for byte the plain
 * model's; on, the same particles come first and the gas after them, type
 * 0, with the galaxies' gas masses. */
static void test_model_stream(void)
{
    orr_model_params mp = {3000, 7, 780.0, ORR_MODEL_PAIR, 0, 0, 0, 0};
    orr_source *plain = NULL, *off = NULL, *on = NULL;
    orr_error err = {0};
    CHECK(orr_model_source_open(&mp, 1000, &plain, &err) == ORR_OK);
    CHECK(orr_model_source_open_dust(&mp, 0, 1000, &off, &err) == ORR_OK);
    CHECK(orr_model_source_open_dust(&mp, 800, 1000, &on, &err) == ORR_OK);
    CHECK(on->info.count == 3800);
    double gas = 0;
    size_t n_same = 0, n_gas = 0;
    for (;;) {
        const orr_chunk *a, *b, *c;
        CHECK(orr_source_next(plain, &a, &err) == ORR_OK);
        CHECK(orr_source_next(off, &b, &err) == ORR_OK);
        CHECK(orr_source_next(on, &c, &err) == ORR_OK);
        if (c->n == 0)
            break;
        for (size_t i = 0; i < c->n; i++) {
            if (c->first_index + i < 3000) {
                int same = a->x[i] == c->x[i] && a->y[i] == c->y[i] && a->z[i] == c->z[i] &&
                           a->mass[i] == c->mass[i] && a->id[i] == c->id[i] && a->type[i] == c->type[i] &&
                           a->x[i] == b->x[i] && a->id[i] == b->id[i];
                n_same += same;
            } else {
                n_gas += c->type[i] == ORR_MODEL_TYPE_GAS;
                gas += c->mass[i];
            }
        }
    }
    CHECK(n_same == 3000);
    CHECK(n_gas == 800);
    CHECK_NEAR(gas, 0.7 + 0.6, 1e-4); /* the two discs' gas, 1e10 Msun */
    orr_error bad = {0};
    orr_source *none = NULL;
    CHECK(orr_model_source_open_dust(&mp, -1, 1000, &none, &bad) == ORR_ERR_USAGE);
    CHECK_CONTAINS(bad.msg, "dust_particles");
    orr_source_close(plain);
    orr_source_close(off);
    orr_source_close(on);
}

/* The gas discs' clumping (input.model.dust_clumping): the same particles
 * in the same places, each mass times a factor whose log spreads by the
 * clumping and whose mean is 1 (the field is smooth over 0.1-2 kpc, so the
 * 20000 particles are a few hundred independent samples: 10 %), and with
 * clumping 0 the same bits as without. */
static void test_model_clumping(void)
{
    orr_model_params smooth = {2000, 7, 780.0, ORR_MODEL_PAIR, 0, 0, 0, 0}, clumped = smooth;
    clumped.dust_clumping = 1.0;
    orr_source *a = NULL, *b = NULL;
    orr_error err = {0};
    CHECK(orr_model_source_open_dust(&smooth, 20000, 4096, &a, &err) == ORR_OK);
    CHECK(orr_model_source_open_dust(&clumped, 20000, 4096, &b, &err) == ORR_OK);
    double sum_ratio = 0, sum_log = 0, sum_log2 = 0;
    size_t n = 0, same_place = 0;
    for (;;) {
        const orr_chunk *ca, *cb;
        CHECK(orr_source_next(a, &ca, &err) == ORR_OK);
        CHECK(orr_source_next(b, &cb, &err) == ORR_OK);
        if (ca->n == 0 || cb->n != ca->n)
            break;
        for (size_t i = 0; i < ca->n; i++) {
            if (ca->type[i] != ORR_MODEL_TYPE_GAS)
                continue;
            same_place += ca->x[i] == cb->x[i] && ca->y[i] == cb->y[i] && ca->z[i] == cb->z[i];
            double ratio = (double)cb->mass[i] / ca->mass[i];
            sum_ratio += ratio;
            sum_log += log(ratio);
            sum_log2 += log(ratio) * log(ratio);
            n++;
        }
    }
    CHECK(n == 20000 && same_place == n);
    double mean_log = sum_log / n, spread = sqrt(sum_log2 / n - mean_log * mean_log);
    CHECK_NEAR(sum_ratio / n, 1.0, 0.1);
    CHECK_NEAR(spread, 1.0, 0.1);
    CHECK_NEAR(mean_log, -0.5, 0.15);
    orr_source_close(a);
    orr_source_close(b);
}

/* A small model seen from the Sun, inside the Milky Way's dust disc: the
 * frame's optical depth to each drawn star against the brute force. */
static void test_tau_model(void)
{
    orr_model_params mp = {20000, 1, 780.0, ORR_MODEL_PAIR, 0, 0, 0, 0};
    orr_source *src = NULL;
    orr_error err = {0};
    CHECK(orr_model_source_open_dust(&mp, 4000, 4096, &src, &err) == ORR_OK);
    orr_dust_settings d;
    orr_dust_settings_defaults(&d);
    d.types = 1u << ORR_MODEL_TYPE_GAS;
    d.kappa_v = 3.7e4; /* docs/dust.md#units: Milky Way dust, kpc^2 per 1e10 Msun of dust */
    orr_dust_context ctx = {"test", ORR_KERNEL_CUBIC, 32, 1.0, 0, 1u << 2 | 1u << 3};
    orr_dust_frame f;
    CHECK(orr_dust_frame_prepare(&f, &d, &ctx, src, &err) == ORR_OK);
    CHECK(f.set.n == 4000);
    const double sun[3] = {-8.0, 0.0, 0.02};
    int n = 0, within = 0;
    double worst = 0, mean = 0;
    const orr_chunk *c;
    while (orr_source_next(src, &c, &err) == ORR_OK && c->n > 0) {
        double *single = malloc(c->n * sizeof *single);
        unsigned char *stars = malloc(c->n);
        for (size_t i = 0; i < c->n; i++) {
            const double p[3] = {c->x[i], c->y[i], c->z[i]};
            stars[i] = c->type[i] == 2 || c->type[i] == 3;
            single[i] = stars[i] ? orr_dust_tau(&f.set, sun, p) : 0;
        }
        check_tau_many(&f.set, sun, c->n, c->x, c->y, c->z, stars, single);
        free(single);
        free(stars);
        for (size_t i = 0; i < c->n; i += 3) {
            if (c->type[i] != 2 && c->type[i] != 3)
                continue;
            const double p[3] = {c->x[i], c->y[i], c->z[i]};
            double exact = orr_dust_tau_exact(&f.set, sun, p), fast = orr_dust_tau(&f.set, sun, p);
            double dmag = MAG_PER_TAU * fabs(fast - exact);
            worst = fmax(worst, dmag);
            within += dmag < 0.01;
            mean += MAG_PER_TAU * exact;
            n++;
        }
    }
    mean /= n;
    fprintf(stderr, "  model from the Sun: %d stars, mean A_V %.2f mag, worst |dA_V| %.2e mag, within 0.01: %d\n",
            n, mean, worst, within);
    CHECK(n > 1000);
    CHECK(mean > 0.5);
    CHECK(within >= 0.99 * n);
    CHECK(worst < 0.05);
    orr_dust_frame_free(&f);
    orr_source_close(src);
}

int main(void)
{
    RUN(test_ccm89);
    RUN(test_f99);
    RUN(test_curve_file);
    RUN(test_partial_column);
    RUN(test_tau_random);
    RUN(test_model_stream);
    RUN(test_model_clumping);
    RUN(test_tau_model);
    RUN(test_redden_chromaticity);
    RUN(test_ebv);
    return check_failures ? 1 : 0;
}
