/* Stellar-population colours: the CMD/PARSEC table (core/ssp_data.c)
 * against values quoted from its source file, the bilinear interpolation
 * and its clamping, reddening and fading with age, the cosmic time of a
 * scale factor against known ages, and SSP populations (colour and
 * luminance from ages, formation times, formation scale factors and
 * metallicities) with their error messages. */
#include <math.h>
#include <stdlib.h>

#include "check.h"
#include "test_chunk.h"
#include "core/ssp.h"
#include "core/ssp_data.h"
#include "particles/population.h"

/* Rows of pynbody/analysis/default_ssp.txt (CMD 3.7 output, blob
 * 04af418f), quoted by hand: age, Z, then B and V (columns 5 and 6). */
static const struct {
    double age, z, b, v;
} quoted[] = {
    {3.981e+06, 0.00016, -0.061, -0.004}, /* line 14 */
    {1.259e+08, 0.00016, 3.158, 3.113},   /* line 34 */
    {1e+09, 0.00016, 4.510, 4.315},       /* line 46 */
    {1.585e+10, 0.00016, 7.046, 6.464},   /* line 62 */
    {3.981e+06, 0.00155, -0.851, -1.056}, /* line 264 */
    {1.259e+08, 0.00155, 3.094, 2.928},   /* line 284 */
    {1e+09, 0.00155, 4.734, 4.382},       /* line 296 */
    {1.585e+10, 0.00155, 7.505, 6.718},   /* line 312 */
    {3.981e+06, 0.01471, -0.060, 0.083},  /* line 514 */
    {1.259e+08, 0.01471, 3.254, 3.095},   /* line 534 */
    {1e+09, 0.01471, 5.164, 4.683},       /* line 546 */
    {1.585e+10, 0.01471, 8.388, 7.347},   /* line 562 */
};

static orr_ssp_colour lookup(double age, double z)
{
    orr_ssp_colour c = {NAN, NAN, NAN};
    CHECK(orr_ssp_lookup(age, z, &c));
    return c;
}

static void test_grid_points(void)
{
    for (size_t i = 0; i < sizeof quoted / sizeof quoted[0]; i++) {
        orr_ssp_colour c = lookup(quoted[i].age, quoted[i].z);
        CHECK_NEAR(c.bv, quoted[i].b - quoted[i].v, 1e-12);
        CHECK_NEAR(c.mv, quoted[i].v, 1e-12);
        CHECK_NEAR(c.lv_per_msun, pow(10, -0.4 * (quoted[i].v - 4.83)), 1e-9 * c.lv_per_msun);
    }
    /* The table is a full grid in increasing order. */
    for (int i = 1; i < ORR_SSP_NAGE; i++)
        CHECK(orr_ssp_age_yr[i] > orr_ssp_age_yr[i - 1]);
    for (int i = 1; i < ORR_SSP_NZ; i++)
        CHECK(orr_ssp_metallicity[i] > orr_ssp_metallicity[i - 1]);
}

static void test_interpolation(void)
{
    /* Halfway in log age between 1e9 (V 4.683) and 1.413e9 at Z = 0.01471,
     * and halfway in log Z between 0.00155 and 0.00244 at 1e9 yr: the mean
     * of the neighbours (bilinear in log age and log Z). */
    double a0 = 1e9, a1 = orr_ssp_age_yr[17];
    CHECK_NEAR(a1, 1.413e9, 1);
    orr_ssp_colour lo = lookup(a0, 0.01471), hi = lookup(a1, 0.01471), mid = lookup(sqrt(a0 * a1), 0.01471);
    CHECK_NEAR(mid.mv, 0.5 * (lo.mv + hi.mv), 1e-9);
    CHECK_NEAR(mid.bv, 0.5 * (lo.bv + hi.bv), 1e-9);
    orr_ssp_colour zl = lookup(1e9, 0.00155), zh = lookup(1e9, 0.00244), zm = lookup(1e9, sqrt(0.00155 * 0.00244));
    CHECK_NEAR(zm.mv, 0.5 * (zl.mv + zh.mv), 1e-9);
    /* The four corners of one cell, at its centre. */
    orr_ssp_colour c = lookup(sqrt(a0 * a1), sqrt(0.00155 * 0.00244));
    double corners = lookup(a0, 0.00155).bv + lookup(a1, 0.00155).bv + lookup(a0, 0.00244).bv + lookup(a1, 0.00244).bv;
    CHECK_NEAR(c.bv, corners / 4, 1e-9);
}

static void test_clamping(void)
{
    orr_ssp_colour young = lookup(3.981e6, 0.01471), old = lookup(1.585e10, 0.01471);
    double ages_young[] = {0, -5e8, 1e3, 3e6, -INFINITY};
    for (size_t i = 0; i < sizeof ages_young / sizeof ages_young[0]; i++)
        CHECK(lookup(ages_young[i], 0.01471).mv == young.mv && lookup(ages_young[i], 0.01471).bv == young.bv);
    CHECK(lookup(1e11, 0.01471).mv == old.mv && lookup(INFINITY, 0.01471).bv == old.bv);
    orr_ssp_colour poor = lookup(1e9, 0.00016), rich = lookup(1e9, 0.01471);
    CHECK(lookup(1e9, 0).mv == poor.mv && lookup(1e9, -1).bv == poor.bv && lookup(1e9, 1e-6).bv == poor.bv);
    CHECK(lookup(1e9, 0.04).mv == rich.mv && lookup(1e9, 0.5).bv == rich.bv);
    orr_ssp_colour c;
    CHECK(!orr_ssp_lookup(NAN, 0.01, &c));
    CHECK(!orr_ssp_lookup(1e9, NAN, &c));
}

/* At every metallicity of the table and between them, a population reddens
 * and fades as it ages from 1 to 10 Gyr; and 100 Myr < 1 Gyr < 10 Gyr in
 * B-V. (Younger than 100 Myr, red supergiants make B-V go up and down: the
 * table's own behaviour, not tested for monotony.) */
static void test_ageing(void)
{
    for (double lz = log10(0.00016); lz <= log10(0.01471) + 1e-9; lz += 0.1) {
        double z = pow(10, lz);
        CHECK(lookup(1e8, z).bv < lookup(1e9, z).bv);
        CHECK(lookup(1e9, z).bv < lookup(1e10, z).bv);
        CHECK(lookup(1e8, z).lv_per_msun > 5 * lookup(1e10, z).lv_per_msun);
        orr_ssp_colour prev = lookup(1e9, z);
        for (double la = 9.02; la <= 10.0 + 1e-9; la += 0.02) {
            orr_ssp_colour c = lookup(pow(10, la), z);
            CHECK(c.bv >= prev.bv);
            CHECK(c.lv_per_msun < prev.lv_per_msun);
            prev = c;
        }
    }
    /* Young populations are blue, old ones red, in T_eff through the
     * B-V relation the colours use. */
    CHECK(orr_bv_to_teff(lookup(5e7, 0.0152).bv, ORR_BV_MAMAJEK) > 8000);
    CHECK(orr_bv_to_teff(lookup(1e10, 0.0152).bv, ORR_BV_MAMAJEK) < 5500);
}

static void test_cosmic_time(void)
{
    /* Flat LCDM with h = 0.7, omega_m = 0.3: the universe's age is 13.47 Gyr
     * (e.g. Wright 2006's cosmology calculator, without radiation); Einstein-
     * de Sitter: 2/(3 H0) = 9.31 Gyr at h = 0.7. */
    CHECK_NEAR(orr_cosmic_time_yr(1, 0.7, 0.3) / 1e9, 13.47, 0.01);
    CHECK_NEAR(orr_cosmic_time_yr(1, 0.7, 1.0) / 1e9, 2.0 / 3.0 * 977.79 / 70, 0.01);
    /* Matter-dominated at early times: t grows as a^1.5. */
    CHECK_NEAR(orr_cosmic_time_yr(0.01, 0.7, 0.3) / orr_cosmic_time_yr(0.0025, 0.7, 0.3), 8.0, 0.01);
    CHECK(isnan(orr_cosmic_time_yr(0, 0.7, 0.3)));
    CHECK(isnan(orr_cosmic_time_yr(-0.1, 0.7, 0.3)));
}

/* ---- populations ---- */

enum { AGE, Z, NFIELDS };
static const char *const field_names[NFIELDS] = {"age", "Z"};

/* n stars (type 4) of mass 2, age 0 and Z = 0.0152. */
static orr_chunk make_chunk(size_t n)
{
    orr_chunk c = test_chunk(n, field_names, NFIELDS);
    for (size_t i = 0; i < n; i++) {
        c.mass[i] = 2;
        c.type[i] = 4;
        c.extra[Z].data[i] = 0.0152f;
    }
    return c;
}

/* Starts s afresh with p (ssp_population of the clock) added, after
 * setting unit_yr. */
static void ssp_set(orr_population_set *s, orr_population *p, orr_ssp_clock clock, double unit_yr);

static void ssp_population(orr_population *p, orr_ssp_clock clock)
{
    orr_population_defaults(p, "stars");
    p->colour.kind = ORR_POPCOLOUR_SSP;
    snprintf(p->colour.field, sizeof p->colour.field, "age");
    p->colour.ssp.clock = clock;
    snprintf(p->colour.ssp.metallicity_field, sizeof p->colour.ssp.metallicity_field, "Z");
    p->lum.kind = ORR_POPLUM_SSP;
}

static void ssp_set(orr_population_set *s, orr_population *p, orr_ssp_clock clock, double unit_yr)
{
    orr_error err;
    orr_population_set_init(s, 1);
    ssp_population(p, clock);
    p->colour.ssp.unit_yr = unit_yr;
    CHECK(orr_population_add(s, p, &err) == ORR_OK);
}

static double xof(float X, float Y, float Zc) { return X / (X + Y + Zc); }

static void test_population_ages(void)
{
    orr_population_set s;
    orr_population p;
    orr_error err;
    ssp_set(&s, &p, ORR_SSP_CLOCK_AGE, 1e9); /* ages in Gyr */
    orr_chunk c = make_chunk(3);
    c.extra[AGE].data[0] = 0.05f; /* 50 Myr */
    c.extra[AGE].data[1] = 10.0f; /* 10 Gyr */
    c.extra[AGE].data[2] = 10.0f;
    c.extra[Z].data[2] = 0.0f; /* metal-free: the poorest column */
    float X[3], Y[3], Zc[3];
    CHECK(orr_population_assign(&s, &c, 0, 3, -1, NULL, X, Y, Zc, &err) == ORR_OK);
    /* Young: blue (chromaticity x below the white point's 0.313), old: red. */
    CHECK(xof(X[0], Y[0], Zc[0]) < 0.30);
    CHECK(xof(X[1], Y[1], Zc[1]) > 0.33);
    /* Each weight is mass * L_V / M of its population, Y = luminance. */
    CHECK_NEAR(Y[0], 2 * lookup(5e7, 0.0152).lv_per_msun, 1e-5 * Y[0]);
    CHECK_NEAR(Y[1], 2 * lookup(1e10, 0.0152).lv_per_msun, 1e-5 * Y[1]);
    CHECK(Y[0] > 20 * Y[1]);
    /* The metal-poor old population is bluer and brighter than the rich one. */
    CHECK(xof(X[2], Y[2], Zc[2]) < xof(X[1], Y[1], Zc[1]));
    CHECK(Y[2] > Y[1]);
    orr_chunk_free(&c);
}

static void test_population_clocks(void)
{
    orr_error err;
    orr_chunk c = make_chunk(2);
    float X[2], Y[2], Zc[2];
    double want_young = 2 * lookup(5e7, 0.0152).lv_per_msun, want_old = 2 * lookup(1e10, 0.0152).lv_per_msun;

    /* Formation times in Myr, now from the snapshot (10 050 Myr). */
    orr_population_set s;
    orr_population p;
    ssp_set(&s, &p, ORR_SSP_CLOCK_TIME, 1e6);
    c.extra[AGE].data[0] = 10000.0f;
    c.extra[AGE].data[1] = 50.0f;
    CHECK(orr_population_assign_at(&s, 10050.0, &c, 0, 2, -1, NULL, X, Y, Zc, &err) == ORR_OK);
    CHECK_NEAR(Y[0], want_young, 1e-4 * want_young);
    CHECK_NEAR(Y[1], want_old, 1e-4 * want_old);
    /* Without the snapshot's time and without ssp.now: an error saying so. */
    CHECK(orr_population_assign(&s, &c, 0, 2, -1, NULL, X, Y, Zc, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "ssp.now");
    /* An own "now" wins over the snapshot's. */
    s.pop[0].colour.ssp.has_now = 1;
    s.pop[0].colour.ssp.now = 10050.0;
    CHECK(orr_population_assign_at(&s, 1.0, &c, 0, 2, -1, NULL, X, Y, Zc, &err) == ORR_OK);
    CHECK_NEAR(Y[0], want_young, 1e-4 * want_young);

    /* Formation scale factors, now a = 1, h = 0.7, omega_m = 0.3: a star
     * born at the a where t = 13.47 - 0.05 Gyr is 50 Myr old. */
    orr_population_set_init(&s, 1);
    ssp_population(&p, ORR_SSP_CLOCK_SCALE_FACTOR);
    p.colour.ssp.h = 0.7;
    p.colour.ssp.omega_m = 0.3;
    CHECK(orr_population_add(&s, &p, &err) == ORR_OK);
    double t0 = orr_cosmic_time_yr(1, 0.7, 0.3), a_lo = 0.5, a_hi = 1;
    for (int i = 0; i < 60; i++) { /* bisection for t(a) = t0 - 5e7 */
        double a = 0.5 * (a_lo + a_hi);
        if (orr_cosmic_time_yr(a, 0.7, 0.3) < t0 - 5e7)
            a_lo = a;
        else
            a_hi = a;
    }
    c.extra[AGE].data[0] = (float)a_lo;
    c.extra[AGE].data[1] = 1.0f; /* born now: clamped to the youngest row */
    CHECK(orr_population_assign_at(&s, 1.0, &c, 0, 2, -1, NULL, X, Y, Zc, &err) == ORR_OK);
    CHECK_NEAR(Y[0], want_young, 2e-3 * want_young); /* float a: ~0.1 Myr */
    CHECK_NEAR(Y[1], 2 * lookup(3.981e6, 0.0152).lv_per_msun, 1e-4 * Y[1]);
    /* A snapshot time that is no scale factor, and a formation a <= 0 (AREPO's wind particles). */
    CHECK(orr_population_assign_at(&s, 0.0, &c, 0, 2, -1, NULL, X, Y, Zc, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "not a scale factor");
    c.extra[AGE].data[1] = -0.3f;
    CHECK(orr_population_assign_at(&s, 1.0, &c, 0, 2, -1, NULL, X, Y, Zc, &err) == ORR_ERR_DATA);
    CHECK_CONTAINS(err.msg, "id 2");
    CHECK_CONTAINS(err.msg, "scale_factor 'age' = -0.3");
    c.extra[AGE].data[1] = 0.5f;
    c.extra[Z].data[1] = NAN;
    CHECK(orr_population_assign_at(&s, 1.0, &c, 0, 2, -1, NULL, X, Y, Zc, &err) == ORR_ERR_DATA);
    CHECK_CONTAINS(err.msg, "metallicity 'Z'");
    orr_chunk_free(&c);
}

static void test_population_errors(void)
{
    orr_population_set s;
    orr_population p;
    orr_error err;
    orr_population_set_init(&s, 1);
    ssp_population(&p, ORR_SSP_CLOCK_AGE);
    p.colour.ssp.unit_yr = 0;
    CHECK(orr_population_add(&s, &p, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "unit_yr");
    ssp_population(&p, ORR_SSP_CLOCK_SCALE_FACTOR);
    p.colour.ssp.omega_m = 0;
    CHECK(orr_population_add(&s, &p, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "omega_m");
    ssp_population(&p, ORR_SSP_CLOCK_AGE);
    p.colour.ssp.metallicity_field[0] = 0;
    p.colour.ssp.metallicity = 1.5;
    CHECK(orr_population_add(&s, &p, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "metallicity");
    ssp_population(&p, ORR_SSP_CLOCK_AGE);
    p.colour.kind = ORR_POPCOLOUR_FIXED;
    CHECK(orr_population_add(&s, &p, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "needs the colour from one (ssp)");
    /* A chunk without the metallicity field. */
    ssp_population(&p, ORR_SSP_CLOCK_AGE);
    snprintf(p.colour.ssp.metallicity_field, sizeof p.colour.ssp.metallicity_field, "Metallicities");
    CHECK(orr_population_add(&s, &p, &err) == ORR_OK);
    orr_chunk c = make_chunk(1);
    float X, Y, Zc;
    CHECK(orr_population_assign(&s, &c, 0, 1, -1, NULL, &X, &Y, &Zc, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "no field 'Metallicities' (metallicity)");
    orr_chunk_free(&c);
}

int main(void)
{
    RUN(test_grid_points);
    RUN(test_interpolation);
    RUN(test_clamping);
    RUN(test_ageing);
    RUN(test_cosmic_time);
    RUN(test_population_ages);
    RUN(test_population_clocks);
    RUN(test_population_errors);
    return check_summary();
}
