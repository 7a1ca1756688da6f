/* Populations: the id hash (SplitMix64 reference values, determinism,
 * uniformity), selection by type / id / field / probability, per-particle
 * X, Y, Z weights, independence from how particles are split into blocks,
 * additivity of per-population weights, and the error messages. */
#include <math.h>
#include <stdlib.h>

#include "check.h"
#include "test_chunk.h"
#include "particles/population.h"

#define GAMMA64 0x9E3779B97F4A7C15u

static orr_chunk make_chunk(size_t n, const char *const *extra, int nextra)
{
    return test_chunk(n, extra, nextra);
}

static void add_ok(orr_population_set *s, const orr_population *p)
{
    orr_error err;
    orr_status st = orr_population_add(s, p, &err);
    CHECK(st == ORR_OK);
    if (st != ORR_OK)
        fprintf(stderr, "  %s\n", err.msg);
}

static void test_hash(void)
{
    /* orr_hash64(k * gamma) is SplitMix64's k+1-th output from state 0:
     * the published reference sequence. */
    CHECK(orr_hash64(0) == 0xE220A8397B1DCDAFu);
    CHECK(orr_hash64(GAMMA64) == 0x6E789E6AA1B965F4u);
    CHECK(orr_hash64(2 * GAMMA64) == 0x06C45D188009454Fu);

    CHECK(orr_id_uniform(42, 7, 9) == orr_id_uniform(42, 7, 9));
    CHECK(orr_id_uniform(42, 7, 9) != orr_id_uniform(42, 8, 9));
    CHECK(orr_id_uniform(42, 7, 9) != orr_id_uniform(42, 7, 10));
    CHECK(orr_id_uniform(42, 7, 9) != orr_id_uniform(43, 7, 9));
    CHECK(orr_name_salt("red") != orr_name_salt("blue"));
    CHECK(orr_name_salt("") == 0xcbf29ce484222325u);

    /* Consecutive ids: the draws fill [0, 1) evenly (chi-square over 20 bins
     * for 100000 ids; 20 bins have 19 degrees of freedom, and 50 is beyond
     * the 0.9999 quantile) and are uncorrelated from one id to the next. */
    enum { N = 100000, BINS = 20 };
    int hist[BINS] = {0};
    double prev = orr_id_uniform(0, 1, 2), corr = 0, mean = 0;
    for (uint64_t id = 1; id <= N; id++) {
        double u = orr_id_uniform(id, 1, 2);
        CHECK(u >= 0 && u < 1);
        hist[(int)(u * BINS)]++;
        corr += (u - 0.5) * (prev - 0.5);
        mean += u;
        prev = u;
    }
    double chi2 = 0, expect = (double)N / BINS;
    for (int b = 0; b < BINS; b++)
        chi2 += (hist[b] - expect) * (hist[b] - expect) / expect;
    CHECK(chi2 < 50);
    CHECK_NEAR(mean / N, 0.5, 5 * sqrt(1.0 / 12 / N));
    CHECK_NEAR(corr / N / (1.0 / 12), 0, 5 / sqrt((double)N));
}

static void test_probability(void)
{
    orr_pop_select sel = {.random = 1, .prob = ORR_PROB_EXP, .v0 = -2, .dv = 0.5};
    CHECK_NEAR(orr_pop_probability(&sel, -2), 1, 0);
    CHECK_NEAR(orr_pop_probability(&sel, -1.5), exp(-1), 1e-15);
    CHECK_NEAR(orr_pop_probability(&sel, -3), 1, 0); /* clipped */
    CHECK(orr_pop_probability(&sel, NAN) == 0);
    sel.prob = ORR_PROB_LOGISTIC;
    CHECK_NEAR(orr_pop_probability(&sel, -2), 0.5, 1e-15);
    CHECK(orr_pop_probability(&sel, 100) < 1e-10);
    CHECK(orr_pop_probability(&sel, -100) > 1 - 1e-10);
    sel.prob = ORR_PROB_CONSTANT;
    sel.p = 0.3;
    CHECK_NEAR(orr_pop_probability(&sel, 123), 0.3, 0);
    orr_prob_kind k;
    CHECK(orr_prob_kind_from_name("logistic", &k) && k == ORR_PROB_LOGISTIC);
    CHECK(!orr_prob_kind_from_name("gauss", &k));
    CHECK(!strcmp(orr_prob_kind_name(ORR_PROB_EXP), "exp"));
}

/* The fraction drawn red matches the probability within statistical
 * tolerance: a constant p over consecutive ids, and p(E) = exp(-(E-E0)/dE)
 * over a spread of binding energies. */
static void test_fraction(void)
{
    enum { N = 200000 };
    const char *extra[] = {"E"};
    orr_chunk c = make_chunk(N, extra, 1);
    for (size_t i = 0; i < N; i++)
        c.extra[0].data[i] = (float)(-3.0 + 3.0 * (double)i / N); /* E in [-3, 0) */

    orr_population_set s;
    orr_population red, blue;
    orr_population_set_init(&s, 2024);
    orr_population_defaults(&red, "red");
    red.select.random = 1;
    red.select.prob = ORR_PROB_CONSTANT;
    red.select.p = 0.3;
    add_ok(&s, &red);
    orr_population_defaults(&blue, "blue");
    add_ok(&s, &blue);

    int32_t *pop = malloc(N * sizeof *pop);
    float *X = malloc(N * sizeof *X), *Y = malloc(N * sizeof *Y), *Z = malloc(N * sizeof *Z);
    orr_error err;
    CHECK(orr_population_assign(&s, &c, 0, N, -1, pop, X, Y, Z, &err) == ORR_OK);
    long nred = 0;
    for (size_t i = 0; i < N; i++) {
        CHECK(pop[i] == 0 || pop[i] == 1); /* blue takes the rest */
        nred += pop[i] == 0;
    }
    double sigma = sqrt(N * 0.3 * 0.7);
    CHECK(fabs(nred - 0.3 * N) < 5 * sigma);
    fprintf(stderr, "  p = 0.3: %ld red of %d (expected %.0f +- %.0f)\n", nred, N, 0.3 * N, sigma);

    /* Old, tightly bound stars red: p = exp(-(E - E0)/dE), E0 = -3, dE = 1. */
    orr_population_set_init(&s, 99);
    red.select.prob = ORR_PROB_EXP;
    snprintf(red.select.prob_field, sizeof red.select.prob_field, "E");
    red.select.v0 = -3;
    red.select.dv = 1;
    add_ok(&s, &red);
    add_ok(&s, &blue);
    CHECK(orr_population_assign(&s, &c, 0, N, -1, pop, X, Y, Z, &err) == ORR_OK);
    double expect = 0, var = 0;
    long inner_red = 0, outer_red = 0;
    nred = 0;
    for (size_t i = 0; i < N; i++) {
        double p = orr_pop_probability(&s.pop[0].select, c.extra[0].data[i]);
        expect += p;
        var += p * (1 - p);
        nred += pop[i] == 0;
        if (i < N / 10)
            inner_red += pop[i] == 0;
        if (i >= N - N / 10)
            outer_red += pop[i] == 0;
    }
    CHECK(fabs(nred - expect) < 5 * sqrt(var));
    CHECK(inner_red > 4 * outer_red); /* p ~ 0.87 against ~ 0.07 */
    fprintf(stderr, "  p = exp(-(E+3)): %ld red of %d (expected %.0f +- %.0f)\n", nred, N, expect, sqrt(var));
    free(pop);
    free(X);
    free(Y);
    free(Z);
    orr_chunk_free(&c);
}

/* The same ids get the same populations however the particles are cut into
 * blocks and in whatever order they come. */
static void test_block_independence(void)
{
    enum { N = 5000 };
    const char *extra[] = {"r"};
    orr_chunk a = make_chunk(N, extra, 1), b = make_chunk(N, extra, 1);
    for (size_t i = 0; i < N; i++) {
        a.id[i] = 1000003u * i + 17; /* sparse ids */
        a.extra[0].data[i] = (float)(i % 97) / 10;
        /* b holds the same particles in reverse order */
        b.id[N - 1 - i] = a.id[i];
        b.extra[0].data[N - 1 - i] = a.extra[0].data[i];
    }
    orr_population_set s;
    orr_population_set_init(&s, 5);
    orr_population p;
    orr_population_defaults(&p, "halo");
    p.select.random = 1;
    p.select.prob = ORR_PROB_LOGISTIC;
    snprintf(p.select.prob_field, sizeof p.select.prob_field, "r");
    p.select.v0 = 5;
    p.select.dv = 2;
    add_ok(&s, &p);
    orr_population_defaults(&p, "disc");
    p.select.random = 1;
    p.select.p = 0.5;
    add_ok(&s, &p);

    int32_t whole[N], parts[N], reversed[N];
    float X[N], Y[N], Z[N];
    orr_error err;
    CHECK(orr_population_assign(&s, &a, 0, N, -1, whole, X, Y, Z, &err) == ORR_OK);
    /* Uneven blocks: 1, 2, 3, ... particles at a time. */
    for (size_t start = 0, len = 1; start < N; start += len, len++) {
        size_t n = start + len > N ? N - start : len;
        CHECK(orr_population_assign(&s, &a, start, n, -1, parts + start, X, Y, Z, &err) == ORR_OK);
    }
    CHECK(orr_population_assign(&s, &b, 0, N, -1, reversed, X, Y, Z, &err) == ORR_OK);
    int same_parts = 1, same_reversed = 1, counts[3] = {0, 0, 0};
    for (size_t i = 0; i < N; i++) {
        same_parts &= whole[i] == parts[i];
        same_reversed &= whole[i] == reversed[N - 1 - i];
        counts[whole[i] + 1]++;
    }
    CHECK(same_parts);
    CHECK(same_reversed);
    CHECK(counts[0] > 0 && counts[1] > 0 && counts[2] > 0); /* none, halo, disc all occur */

    /* Another seed: a different draw. */
    s.seed = 6;
    CHECK(orr_population_assign(&s, &a, 0, N, -1, parts, X, Y, Z, &err) == ORR_OK);
    int differ = 0;
    for (size_t i = 0; i < N; i++)
        differ += whole[i] != parts[i];
    CHECK(differ > N / 10);
    orr_chunk_free(&a);
    orr_chunk_free(&b);
}

static void test_selection(void)
{
    const char *extra[] = {"age"};
    orr_chunk c = make_chunk(8, extra, 1);
    for (size_t i = 0; i < 8; i++) {
        c.type[i] = (uint8_t)(i % 4);
        c.extra[0].data[i] = (float)i;
    }
    c.type[7] = 200; /* a type beyond the mask's 32 bits */
    orr_population_set s;
    orr_population_set_init(&s, 0);
    orr_population p;
    orr_population_defaults(&p, "stars");
    p.select.types = 1u << 2 | 1u << 3; /* types 2 and 3 */
    add_ok(&s, &p);
    orr_population_defaults(&p, "tagged");
    p.select.has_id_range = 1;
    p.select.id_min = 2;
    p.select.id_max = 3; /* ids 2..3: particles 1 and 2 */
    add_ok(&s, &p);
    orr_population_defaults(&p, "young");
    snprintf(p.select.range_field, sizeof p.select.range_field, "age");
    p.select.field_min = 4;
    p.select.field_max = 5;
    add_ok(&s, &p);
    CHECK(orr_population_find(&s, "tagged") == 1 && orr_population_find(&s, "old") == -1);

    int32_t pop[8];
    float X[8], Y[8], Z[8];
    orr_error err;
    CHECK(orr_population_assign(&s, &c, 0, 8, -1, pop, X, Y, Z, &err) == ORR_OK);
    /* types 0 1 2 3 0 1 2 200, ids 1..8, age 0..7; first match wins */
    const int32_t want[8] = {-1, 1, 0, 0, 2, 2, 0, -1};
    for (int i = 0; i < 8; i++) {
        CHECK(pop[i] == want[i]);
        if (want[i] < 0)
            CHECK(X[i] == 0 && Y[i] == 0 && Z[i] == 0);
        else
            CHECK(Y[i] == 1);
    }
    /* pop may be NULL */
    CHECK(orr_population_assign(&s, &c, 2, 3, -1, NULL, X, Y, Z, &err) == ORR_OK);
    CHECK(Y[0] == 1 && Y[2] == 1);
    orr_chunk_free(&c);
}

static void test_weights(void)
{
    const char *extra[] = {"T", "BV", "V", "L"};
    orr_chunk c = make_chunk(4, extra, 4);
    const float T[4] = {3000, 5772, 10000, 40000}, BV[4] = {1.83f, 0.65f, 0.0f, -0.301f};
    const float V[4] = {0, 5, 10, -2.5f}, L[4] = {1, 2, 3, 4};
    for (int i = 0; i < 4; i++) {
        c.extra[0].data[i] = T[i];
        c.extra[1].data[i] = BV[i];
        c.extra[2].data[i] = V[i];
        c.extra[3].data[i] = L[i];
        c.mass[i] = 0.5f * (float)(i + 1);
    }
    orr_error err;
    float X[4], Y[4], Z[4];
    double xyz[3];
    orr_population p;

    /* Temperature field, luminance from mass. */
    orr_population_set s;
    orr_population_set_init(&s, 0);
    orr_population_defaults(&p, "stars");
    p.colour.kind = ORR_POPCOLOUR_TEMPERATURE;
    snprintf(p.colour.field, sizeof p.colour.field, "T");
    p.lum.kind = ORR_POPLUM_MASS;
    p.lum.scale = 2;
    add_ok(&s, &p);
    CHECK(orr_population_assign(&s, &c, 0, 4, -1, NULL, X, Y, Z, &err) == ORR_OK);
    for (int i = 0; i < 4; i++) {
        orr_blackbody_xyz(T[i], ORR_CMF_CIE1931, xyz);
        double lum = 2 * c.mass[i];
        CHECK_NEAR(Y[i], lum, 1e-6);
        CHECK_NEAR(X[i], lum * xyz[0], 1e-6 * lum);
        CHECK_NEAR(Z[i], lum * xyz[2], 1e-6 * lum);
    }

    /* B-V field with Judd-Vos CMFs, luminance from V magnitude. */
    orr_population_set_init(&s, 0);
    p.colour.kind = ORR_POPCOLOUR_BV;
    p.colour.cmf = ORR_CMF_JUDD_VOS;
    snprintf(p.colour.field, sizeof p.colour.field, "BV");
    p.lum.kind = ORR_POPLUM_MAGNITUDE;
    p.lum.scale = 1;
    snprintf(p.lum.field, sizeof p.lum.field, "V");
    add_ok(&s, &p);
    CHECK(orr_population_assign(&s, &c, 0, 4, -1, NULL, X, Y, Z, &err) == ORR_OK);
    const double lum_v[4] = {1, 0.01, 1e-4, 10};
    for (int i = 0; i < 4; i++) {
        orr_blackbody_xyz(orr_bv_to_teff(BV[i], ORR_BV_MAMAJEK), ORR_CMF_JUDD_VOS, xyz);
        CHECK_NEAR(Y[i], lum_v[i], 1e-6 * lum_v[i]);
        CHECK_NEAR(X[i] / Y[i], xyz[0], 1e-6);
        CHECK_NEAR(Z[i] / Y[i], xyz[2], 1e-6);
    }

    /* Fixed colour, luminance from a field, and a constant. */
    orr_population_set_init(&s, 0);
    orr_population_defaults(&p, "gas");
    p.colour.fixed = (orr_colour){.kind = ORR_COLOUR_XY, .v = {0.2, 0.3}};
    p.lum.kind = ORR_POPLUM_FIELD;
    snprintf(p.lum.field, sizeof p.lum.field, "L");
    p.lum.scale = 0.5;
    add_ok(&s, &p);
    CHECK(orr_population_assign(&s, &c, 0, 4, -1, NULL, X, Y, Z, &err) == ORR_OK);
    for (int i = 0; i < 4; i++) {
        CHECK_NEAR(Y[i], 0.5 * L[i], 1e-7);
        CHECK_NEAR(X[i], 0.5 * L[i] * 0.2 / 0.3, 1e-6);
        CHECK_NEAR(Z[i], 0.5 * L[i] * 0.5 / 0.3, 1e-6);
    }
    s.pop[0].lum.kind = ORR_POPLUM_CONSTANT;
    CHECK(orr_population_assign(&s, &c, 0, 4, -1, NULL, X, Y, Z, &err) == ORR_OK);
    CHECK(Y[0] == 0.5f && Y[3] == 0.5f);
    orr_chunk_free(&c);
}

/* Rendering each population alone (only = k) and adding the weights gives
 * the weights of rendering them together, particle by particle. */
static void test_additivity(void)
{
    enum { N = 3000 };
    const char *extra[] = {"T"};
    orr_chunk c = make_chunk(N, extra, 1);
    for (size_t i = 0; i < N; i++) {
        c.extra[0].data[i] = (float)(2000 + 10 * (i % 2000));
        c.mass[i] = (float)(1 + i % 7);
        c.type[i] = (uint8_t)(i % 3);
    }
    orr_population_set s;
    orr_population_set_init(&s, 11);
    orr_population p;
    orr_population_defaults(&p, "old");
    p.select.random = 1;
    p.select.p = 0.4;
    p.colour.fixed = (orr_colour){.kind = ORR_COLOUR_TEMPERATURE, .v = {3500}};
    p.lum.kind = ORR_POPLUM_MASS;
    add_ok(&s, &p);
    orr_population_defaults(&p, "young");
    p.select.types = 1u << 1 | 1u << 2;
    p.colour.kind = ORR_POPCOLOUR_TEMPERATURE;
    snprintf(p.colour.field, sizeof p.colour.field, "T");
    add_ok(&s, &p);

    static float X[N], Y[N], Z[N], Xa[N], Ya[N], Za[N], Xb[N], Yb[N], Zb[N];
    static int32_t pop[N], popa[N];
    orr_error err;
    CHECK(orr_population_assign(&s, &c, 0, N, -1, pop, X, Y, Z, &err) == ORR_OK);
    CHECK(orr_population_assign(&s, &c, 0, N, 0, popa, Xa, Ya, Za, &err) == ORR_OK);
    CHECK(orr_population_assign(&s, &c, 0, N, 1, NULL, Xb, Yb, Zb, &err) == ORR_OK);
    int exact = 1, same_pop = 1;
    double sum_all[3] = {0, 0, 0}, sum_parts[3] = {0, 0, 0};
    for (size_t i = 0; i < N; i++) {
        exact &= X[i] == Xa[i] + Xb[i] && Y[i] == Ya[i] + Yb[i] && Z[i] == Za[i] + Zb[i];
        exact &= (Ya[i] == 0 || Yb[i] == 0); /* each particle in at most one */
        same_pop &= pop[i] == popa[i];
        sum_all[0] += X[i];
        sum_all[1] += Y[i];
        sum_all[2] += Z[i];
        sum_parts[0] += Xa[i] + Xb[i];
        sum_parts[1] += Ya[i] + Yb[i];
        sum_parts[2] += Za[i] + Zb[i];
    }
    CHECK(exact);
    CHECK(same_pop);
    for (int k = 0; k < 3; k++)
        CHECK_NEAR(sum_all[k], sum_parts[k], 1e-9 * sum_all[k]);
    orr_chunk_free(&c);
}

static void test_add_errors(void)
{
    orr_population_set s;
    orr_population_set_init(&s, 0);
    orr_population p;
    orr_error err;

    orr_population_defaults(&p, "");
    CHECK(orr_population_add(&s, &p, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "name");

    orr_population_defaults(&p, "red");
    add_ok(&s, &p);
    CHECK(orr_population_add(&s, &p, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "twice");

    orr_population_defaults(&p, "bad-p");
    p.select.random = 1;
    p.select.p = 1.5;
    CHECK(orr_population_add(&s, &p, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "bad-p");
    CHECK_CONTAINS(err.msg, "1.5");

    orr_population_defaults(&p, "bad-dv");
    p.select.random = 1;
    p.select.prob = ORR_PROB_EXP;
    snprintf(p.select.prob_field, sizeof p.select.prob_field, "E");
    CHECK(orr_population_add(&s, &p, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "dv");
    p.select.prob_field[0] = 0;
    p.select.dv = 1;
    CHECK(orr_population_add(&s, &p, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "field");

    orr_population_defaults(&p, "bad-range");
    p.select.has_id_range = 1;
    p.select.id_min = 5;
    p.select.id_max = 4;
    CHECK(orr_population_add(&s, &p, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "empty");
    orr_population_defaults(&p, "bad-field-range");
    snprintf(p.select.range_field, sizeof p.select.range_field, "age");
    p.select.field_min = NAN;
    CHECK(orr_population_add(&s, &p, &err) == ORR_ERR_USAGE);

    orr_population_defaults(&p, "black");
    p.colour.fixed = (orr_colour){.kind = ORR_COLOUR_SRGB, .v = {0, 0, 0}};
    CHECK(orr_population_add(&s, &p, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "black");
    orr_population_defaults(&p, "nofield");
    p.colour.kind = ORR_POPCOLOUR_BV;
    CHECK(orr_population_add(&s, &p, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "B-V");
    orr_population_defaults(&p, "dark");
    p.lum.scale = 0;
    CHECK(orr_population_add(&s, &p, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "scale");
    orr_population_defaults(&p, "nolum");
    p.lum.kind = ORR_POPLUM_MAGNITUDE;
    CHECK(orr_population_add(&s, &p, &err) == ORR_ERR_USAGE);
    CHECK(s.n == 1);

    for (int i = 1; i < ORR_POPULATION_MAX; i++) {
        char name[16];
        snprintf(name, sizeof name, "p%d", i);
        orr_population_defaults(&p, name);
        add_ok(&s, &p);
    }
    orr_population_defaults(&p, "one-too-many");
    CHECK(orr_population_add(&s, &p, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "at most");
}

static void test_assign_errors(void)
{
    const char *extra[] = {"T"};
    orr_chunk c = make_chunk(4, extra, 1);
    c.first_index = 1000;
    for (int i = 0; i < 4; i++)
        c.extra[0].data[i] = 5000;
    c.extra[0].data[2] = 0;
    orr_population_set s;
    orr_population_set_init(&s, 0);
    orr_population p;
    orr_population_defaults(&p, "hot");
    p.colour.kind = ORR_POPCOLOUR_TEMPERATURE;
    snprintf(p.colour.field, sizeof p.colour.field, "T");
    add_ok(&s, &p);
    float X[4], Y[4], Z[4];
    orr_error err;
    CHECK(orr_population_assign(&s, &c, 0, 4, -1, NULL, X, Y, Z, &err) == ORR_ERR_DATA);
    CHECK_CONTAINS(err.msg, "particle 1002");
    CHECK_CONTAINS(err.msg, "id 3");
    CHECK_CONTAINS(err.msg, "'T'");
    /* A block without the bad particle is fine. */
    CHECK(orr_population_assign(&s, &c, 0, 2, -1, NULL, X, Y, Z, &err) == ORR_OK);

    c.extra[0].data[2] = 5000;
    c.mass[1] = -1;
    s.pop[0].lum.kind = ORR_POPLUM_MASS;
    CHECK(orr_population_assign(&s, &c, 0, 4, -1, NULL, X, Y, Z, &err) == ORR_ERR_DATA);
    CHECK_CONTAINS(err.msg, "mass");

    orr_population_set_init(&s, 0);
    orr_population_defaults(&p, "lum");
    p.lum.kind = ORR_POPLUM_FIELD;
    snprintf(p.lum.field, sizeof p.lum.field, "Lv");
    add_ok(&s, &p);
    CHECK(orr_population_assign(&s, &c, 0, 4, -1, NULL, X, Y, Z, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "no field 'Lv'");
    CHECK_CONTAINS(err.msg, "'lum'");
    CHECK(orr_population_assign(&s, &c, 3, 2, -1, NULL, X, Y, Z, &err) == ORR_ERR_INTERNAL);
    orr_chunk_free(&c);
}

int main(void)
{
    RUN(test_hash);
    RUN(test_probability);
    RUN(test_fraction);
    RUN(test_block_independence);
    RUN(test_selection);
    RUN(test_weights);
    RUN(test_additivity);
    RUN(test_add_errors);
    RUN(test_assign_errors);
    return check_summary();
}
