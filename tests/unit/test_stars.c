/* Stars spawned from particles (stars/stars.h): the luminosity function
 * against its source table's own totals, light kept exactly per particle,
 * the expected number of stars against a Poisson count, stars that are the
 * same whatever the chunking, and the settings' errors. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "test_chunk.h"
#include "stars/stars.h"

/* Allen (1973) section 117's own column totals: the V emission, 669e-6
 * stars of M_V = 0 per pc^3, and the mass density, 437e-4 solar masses per
 * pc^3: the light per solar mass the integration must give. */
static void test_luminosity_function(void)
{
    static orr_lf lf;
    orr_lf_solar_neighbourhood(&lf);
    CHECK_NEAR(lf.mass_density, 0.0437, 0.0001);
    const double table_light = 669e-6 * orr_lf_luminosity(0.0) / 0.0437;
    CHECK_NEAR(orr_lf_light_per_mass(&lf) / table_light, 1.0, 0.03);
    /* Counts grow with magnitude; the inverse undoes them. */
    double last = -1;
    for (double m = -6.0; m <= 22.0; m += 0.37) {
        double n = orr_lf_count_brighter(&lf, m);
        CHECK(n > last);
        last = n;
        CHECK_NEAR(orr_lf_magnitude_at(&lf, n), m, 1e-6);
    }
    /* A star of M_V = 4.83 is the Sun. */
    CHECK_NEAR(orr_lf_luminosity(ORR_LF_SUN_MV), 1.0, 1e-12);
    /* Giants only among the bright: red; the faint main sequence red too,
     * its bright end blue. */
    CHECK(orr_lf_giant_fraction(6.0) == 0.0);
    CHECK(orr_lf_star_bv(0.8, 0.01) > 0.8);
    CHECK(orr_lf_star_bv(0.8, 0.99) < 0.1);
    CHECK(orr_lf_star_bv(10.0, 0.5) > 1.4);
}

/* The galloping inverse (a particle's stars, counts growing) gives the
 * bisection's magnitude bit for bit: runs of growing counts as a particle
 * draws them (exponential gaps, small and large), every table node and
 * its neighbouring doubles, the ends, and counts that fall (a new
 * particle) with a stale step. */
static void test_magnitude_from_matches(void)
{
    static orr_lf lf;
    orr_lf_solar_neighbourhood(&lf);
    const double total = lf.count[ORR_LF_STEPS];
    long differ = 0, tried = 0;
    srand(7);
    for (int run = 0; run < 200; run++) {
        int step = run % 3 ? 0 : ORR_LF_STEPS / 2; /* stale or fresh */
        double u = 0, m = pow(10.0, 2.0 + 4.0 * rand() / RAND_MAX), mean_gap = total * m * pow(10.0, -1.0 - 5.0 * rand() / RAND_MAX);
        while (u / m < total * 1.01) {
            u -= mean_gap * log((rand() + 1.0) / (RAND_MAX + 2.0));
            double count = u / m;
            differ += orr_lf_magnitude_from(&lf, count, &step) != orr_lf_magnitude_at(&lf, count), tried++;
        }
    }
    int step = 0;
    for (int k = 0; k <= ORR_LF_STEPS; k++)
        for (int side = -1; side <= 1; side++) {
            double count = side ? nextafter(lf.count[k], side * INFINITY) : lf.count[k];
            differ += orr_lf_magnitude_from(&lf, count, &step) != orr_lf_magnitude_at(&lf, count), tried++;
        }
    const double odd[] = {0.0, -1.0, NAN, total, 2 * total, 1e-300, total * 0.5, total * 1e-9};
    for (size_t k = 0; k < sizeof odd / sizeof *odd; k++) {
        step = ORR_LF_STEPS; /* past the table: the search starts again */
        double a = orr_lf_magnitude_from(&lf, odd[k], &step), b = orr_lf_magnitude_at(&lf, odd[k]);
        differ += a != b, tried++;
    }
    printf("magnitude_from: %ld of %ld counts differ from the bisection\n", differ, tried);
    CHECK(differ == 0 && tried > 10000);
}

static orr_stars prepared(double limit, double spread)
{
    orr_stars_settings set;
    orr_stars_defaults(&set);
    set.enabled = 1;
    set.limit = limit;
    set.types = 1u << 2;
    set.spread = spread;
    orr_stars st;
    orr_error err = {0};
    CHECK(orr_stars_prepare(&st, &set, "test.yaml", &err) == ORR_OK);
    return st;
}

/* n disc particles of light light (solar units) at distance r kpc around
 * the eye at the origin, on a ring in the plane. */
static orr_chunk ring(size_t n, double r, float light, float *xyz[3])
{
    orr_chunk c = test_chunk(n, NULL, 0);
    for (size_t i = 0; i < n; i++) {
        double phi = 2 * 3.14159265358979 * (double)i / (double)n;
        c.x[i] = (float)(r * cos(phi)), c.y[i] = (float)(r * sin(phi)), c.z[i] = 0.0f;
        c.mass[i] = 2e-5f;
        c.type[i] = 2;
        c.id[i] = 1000 + i;
        xyz[0][i] = 0.9f * light, xyz[1][i] = light, xyz[2][i] = 1.1f * light;
    }
    return c;
}

static float *floats(size_t n) { return calloc(n, sizeof(float)); }

/* Every particle's light is its stars' and its glow's, to float rounding;
 * its glow keeps its colour. */
static void test_light_kept(void)
{
    orr_stars st = prepared(8.0, 0.0);
    const size_t n = 400;
    float *xyz[3] = {floats(n), floats(n), floats(n)};
    orr_chunk c = ring(n, 0.3, 1e5f, xyz);
    orr_star_batch batch = {0};
    orr_error err = {0};
    orr_stars_begin_frame(&st);
    CHECK(orr_stars_spawn(&st, (orr_vec3){0, 0, 0}, 0, &c, xyz, &batch, &err) == ORR_OK);
    CHECK(batch.stars.n > 1000);
    double before = 1e5 * (double)n, after = 0;
    for (size_t i = 0; i < n; i++) {
        after += xyz[1][i];
        CHECK_NEAR(xyz[0][i] / xyz[1][i], 0.9, 1e-5);
    }
    for (size_t k = 0; k < batch.stars.n; k++) {
        after += batch.xyz[1][k];
        CHECK(batch.info[k].v <= 8.0);
        CHECK(batch.stars.type[k] == 2);
    }
    CHECK_NEAR(after / before, 1.0, 1e-5);
    orr_star_batch_free(&batch);
    orr_chunk_free(&c);
    for (int k = 0; k < 3; k++)
        free(xyz[k]);
}

/* With no spread, every star of a particle at distance r is at r: the
 * number drawn brighter than the limit is Poisson with mean N m, N the
 * function's count brighter than M = limit - 5 log10(r / 10 pc), m the
 * particle's solar masses of the local disc (its light over L/M); and the
 * light they carry has the function's mean. */
static void test_expected_counts(void)
{
    orr_stars st = prepared(6.0, 1e-9);
    const size_t n = 2000;
    const double r_kpc = 0.5, light = 2e4;
    float *xyz[3] = {floats(n), floats(n), floats(n)};
    orr_chunk c = ring(n, r_kpc, (float)light, xyz);
    orr_star_batch batch = {0};
    orr_error err = {0};
    orr_stars_begin_frame(&st);
    CHECK(orr_stars_spawn(&st, (orr_vec3){0, 0, 0}, 0, &c, xyz, &batch, &err) == ORR_OK);
    const double m = light / orr_lf_light_per_mass(&st.lf);
    const double m_lim = 6.0 - 5.0 * log10(r_kpc * 1000 / 10.0);
    const double expected = n * m * orr_lf_count_brighter(&st.lf, m_lim);
    CHECK(expected > 500);
    CHECK(fabs((double)batch.stars.n - expected) < 5 * sqrt(expected));
    double star_light = 0;
    for (size_t k = 0; k < batch.stars.n; k++)
        star_light += batch.xyz[1][k];
    const double expected_light = n * m * orr_lf_light_brighter(&st.lf, m_lim);
    CHECK_NEAR(star_light / expected_light, 1.0, 0.1);
    orr_star_batch_free(&batch);
    orr_chunk_free(&c);
    for (int k = 0; k < 3; k++)
        free(xyz[k]);
}

/* A particle's stars depend on its id and the seed alone: the same
 * particles spawned as one chunk or as two, in another order, give the same
 * stars; another seed gives others. */
static void test_same_stars_any_chunking(void)
{
    orr_stars st = prepared(8.0, 0.0);
    const size_t n = 60;
    float *xyz[3] = {floats(n), floats(n), floats(n)};
    orr_chunk whole = ring(n, 0.2, 1e5f, xyz);
    orr_star_batch all = {0}, part = {0};
    orr_error err = {0};
    orr_stars_begin_frame(&st);
    CHECK(orr_stars_spawn(&st, (orr_vec3){0, 0, 0}, 0, &whole, xyz, &all, &err) == ORR_OK);
    /* The last particle alone, from a chunk of its own. */
    float *one[3] = {floats(1), floats(1), floats(1)};
    orr_chunk single = ring(1, 0.2, 1e5f, one);
    single.x[0] = whole.x[n - 1], single.y[0] = whole.y[n - 1], single.id[0] = whole.id[n - 1];
    CHECK(orr_stars_spawn(&st, (orr_vec3){0, 0, 0}, 0, &single, one, &part, &err) == ORR_OK);
    size_t first = 0;
    while (first < all.stars.n && all.info[first].parent != whole.id[n - 1])
        first++;
    CHECK(part.stars.n > 0 && first + part.stars.n == all.stars.n);
    for (size_t k = 0; k < part.stars.n && first + k < all.stars.n; k++) {
        CHECK(part.stars.x[k] == all.stars.x[first + k]);
        CHECK(part.info[k].abs_v == all.info[first + k].abs_v);
        CHECK(part.xyz[1][k] == all.xyz[1][first + k]);
    }
    CHECK(one[1][0] == xyz[1][n - 1]);
    /* Another seed: other stars. */
    orr_stars other = st;
    other.set.seed = 2;
    orr_star_batch again = {0};
    float *xyz2[3] = {floats(1), floats(1), floats(1)};
    orr_chunk single2 = ring(1, 0.2, 1e5f, xyz2);
    single2.x[0] = single.x[0], single2.y[0] = single.y[0], single2.id[0] = single.id[0];
    CHECK(orr_stars_spawn(&other, (orr_vec3){0, 0, 0}, 0, &single2, xyz2, &again, &err) == ORR_OK);
    CHECK(again.stars.n == 0 || again.stars.x[0] != part.stars.x[0]);
    orr_star_batch_free(&all), orr_star_batch_free(&part), orr_star_batch_free(&again);
    orr_chunk_free(&whole), orr_chunk_free(&single), orr_chunk_free(&single2);
    for (int k = 0; k < 3; k++)
        free(xyz[k]), free(one[k]), free(xyz2[k]);
}

/* stars.max stops the drawing, and says so; the observer spawns none. */
static void test_cap_and_observer(void)
{
    orr_stars st = prepared(8.0, 0.0);
    st.set.max_stars = 10;
    const size_t n = 50;
    float *xyz[3] = {floats(n), floats(n), floats(n)};
    orr_chunk c = ring(n, 0.2, 1e5f, xyz);
    orr_star_batch batch = {0};
    orr_error err = {0};
    orr_stars_begin_frame(&st);
    CHECK(orr_stars_spawn(&st, (orr_vec3){0, 0, 0}, c.id[0], &c, xyz, &batch, &err) == ORR_OK);
    CHECK(batch.stars.n == 10 && st.capped);
    for (size_t k = 0; k < batch.stars.n; k++)
        CHECK(batch.info[k].parent != c.id[0]);
    CHECK(xyz[1][0] == 1e5f);
    orr_star_batch_free(&batch);
    orr_chunk_free(&c);
    for (int k = 0; k < 3; k++)
        free(xyz[k]);
}

/* One chunk's spawn on threads (shares joined in order) against one
 * thread: the same stars in the same order, the same glows, the same count
 * and cap flag; with no cap, with stars.max falling inside the chunk (the
 * threads' draw is done again in order), and exactly at the chunk's count. */
static long long spawn_with(int threads, long long max_stars, size_t n, orr_star_batch *b, float *xyz[3], int *capped)
{
    orr_stars st = prepared(8.0, 0.0);
    st.set.max_stars = max_stars;
    orr_chunk c = ring(n, 0.25, 300.0f, xyz);
    orr_error err = {0};
    omp_set_num_threads(threads);
    orr_stars_begin_frame(&st);
    CHECK(orr_stars_spawn(&st, (orr_vec3){0, 0, 0}, c.id[7], &c, xyz, b, &err) == ORR_OK);
    orr_chunk_free(&c);
    *capped = st.capped;
    return st.drawn;
}

/* Field by field: the struct has padding, which memcmp would read. */
static int same_infos(const orr_star_info *a, const orr_star_info *b, size_t n)
{
    for (size_t k = 0; k < n; k++)
        if (memcmp(&a[k].abs_v, &b[k].abs_v, sizeof a[k].abs_v) || memcmp(&a[k].v, &b[k].v, sizeof a[k].v) ||
            memcmp(&a[k].bv, &b[k].bv, sizeof a[k].bv) || a[k].parent != b[k].parent || a[k].index != b[k].index)
            return 0;
    return 1;
}

static int same_batches(const orr_star_batch *a, const orr_star_batch *b)
{
    if (a->stars.n != b->stars.n)
        return 0;
    size_t n = a->stars.n;
    return !memcmp(a->stars.x, b->stars.x, n * sizeof(float)) && !memcmp(a->stars.z, b->stars.z, n * sizeof(float)) &&
           !memcmp(a->stars.id, b->stars.id, n * sizeof(uint64_t)) &&
           !memcmp(a->xyz[0], b->xyz[0], n * sizeof(float)) && !memcmp(a->xyz[1], b->xyz[1], n * sizeof(float)) &&
           same_infos(a->info, b->info, n);
}

static void test_threads_same_stars(void)
{
    const size_t n = 20000; /* past SPAWN_PARALLEL_MIN: drawn on the threads */
    long long uncapped = 0;
    for (int round = 0; round < 3; round++) {
        long long cap = round == 0 ? 2000000 : round == 1 ? uncapped / 2 : uncapped;
        orr_star_batch one = {0}, two = {0};
        float *g1[3] = {floats(n), floats(n), floats(n)}, *g2[3] = {floats(n), floats(n), floats(n)};
        int capped1, capped2;
        long long d1 = spawn_with(1, cap, n, &one, g1, &capped1), d2 = spawn_with(2, cap, n, &two, g2, &capped2);
        if (round == 0)
            uncapped = d1;
        printf("threads: max %lld: %lld stars on one thread, %lld on two, capped %d %d\n", cap, d1, d2, capped1, capped2);
        CHECK(d1 == d2 && capped1 == capped2 && (long long)one.stars.n == d1);
        CHECK(same_batches(&one, &two));
        for (int k = 0; k < 3; k++)
            CHECK(!memcmp(g1[k], g2[k], n * sizeof(float)));
        CHECK(round != 1 || (capped1 && d1 == cap));
        CHECK(round != 2 || d1 == cap);
        orr_star_batch_free(&one), orr_star_batch_free(&two);
        for (int k = 0; k < 3; k++)
            free(g1[k]), free(g2[k]);
    }
    CHECK(uncapped > 1000);
    omp_set_num_threads(omp_get_num_procs());
}

static void test_settings_errors(void)
{
    orr_stars_settings set;
    orr_stars st;
    orr_error err = {0};
    orr_stars_defaults(&set);
    set.limit = NAN;
    CHECK(orr_stars_prepare(&st, &set, "sky.yaml", &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "sky.yaml: stars.limit");
    orr_stars_defaults(&set);
    set.light_unit = 0;
    CHECK(orr_stars_prepare(&st, &set, "sky.yaml", &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "stars.light_unit");
    orr_stars_defaults(&set);
    set.max_stars = 0;
    CHECK(orr_stars_prepare(&st, &set, "sky.yaml", &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "stars.max");
}

int main(void)
{
    RUN(test_luminosity_function);
    RUN(test_magnitude_from_matches);
    RUN(test_light_kept);
    RUN(test_expected_counts);
    RUN(test_same_stars_any_chunking);
    RUN(test_cap_and_observer);
    RUN(test_threads_same_stars);
    RUN(test_settings_errors);
    return check_summary();
}
