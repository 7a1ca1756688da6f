/* Tests of the built-in mw-m31 model: markers, geometry, masses, sampling,
 * rotation, determinism across chunk sizes and parameter checking. The
 * component masses and scale lengths below are the ones docs/model.md lists. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "source/models/model.h"
#include "source/models/model_dust.h"
#include "source/source.h"

/* All particles of a model, read into flat arrays. */
typedef struct table {
    size_t n;
    float *x, *y, *z, *m, *vx, *vy, *vz;
    uint64_t *id;
    uint8_t *type;
} table;

static void table_free(table *t)
{
    free(t->x);
    free(t->y);
    free(t->z);
    free(t->m);
    free(t->vx);
    free(t->vy);
    free(t->vz);
    free(t->id);
    free(t->type);
    memset(t, 0, sizeof *t);
}

static void copy_chunk(table *t, const orr_chunk *c)
{
    size_t f = c->n * sizeof(float), o = t->n;
    memcpy(t->x + o, c->x, f);
    memcpy(t->y + o, c->y, f);
    memcpy(t->z + o, c->z, f);
    memcpy(t->m + o, c->mass, f);
    memcpy(t->vx + o, orr_chunk_field(c, "vx"), f);
    memcpy(t->vy + o, orr_chunk_field(c, "vy"), f);
    memcpy(t->vz + o, orr_chunk_field(c, "vz"), f);
    memcpy(t->id + o, c->id, c->n * sizeof(uint64_t));
    memcpy(t->type + o, c->type, c->n);
    t->n += c->n;
}

/* Reads every particle of src; returns 0 on any error or overflow. */
static int read_source(orr_source *src, size_t expect, table *t)
{
    memset(t, 0, sizeof *t);
    t->x = malloc(expect * sizeof(float));
    t->y = malloc(expect * sizeof(float));
    t->z = malloc(expect * sizeof(float));
    t->m = malloc(expect * sizeof(float));
    t->vx = malloc(expect * sizeof(float));
    t->vy = malloc(expect * sizeof(float));
    t->vz = malloc(expect * sizeof(float));
    t->id = malloc(expect * sizeof(uint64_t));
    t->type = malloc(expect);
    orr_error err = {0};
    for (;;) {
        const orr_chunk *c;
        if (orr_source_next(src, &c, &err) != ORR_OK || c->n > c->capacity) {
            fprintf(stderr, "read error: %s\n", err.msg);
            return 0;
        }
        if (c->n == 0)
            return t->n == expect;
        if (t->n + c->n > expect)
            return 0;
        copy_chunk(t, c);
    }
}

static int load_model_params(const orr_model_params *params, size_t chunk, table *t);

static int load_model(long long n, uint64_t seed, double sep, size_t chunk, table *t)
{
    orr_model_params p = {n, seed, sep, ORR_MODEL_PAIR, 0, 0, 0, 0};
    return load_model_params(&p, chunk, t);
}

static int load_model_params(const orr_model_params *params, size_t chunk, table *t)
{
    orr_model_params p = *params;
    long long n = p.particles;
    orr_source *src = NULL;
    orr_error err = {0};
    if (orr_model_source_open(&p, chunk, &src, &err) != ORR_OK) {
        fprintf(stderr, "open failed: %s\n", err.msg);
        return 0;
    }
    int ok = read_source(src, (size_t)n, t);
    orr_source_close(src);
    return ok;
}

static double dist3(double ax, double ay, double az, double bx, double by, double bz)
{
    return sqrt((ax - bx) * (ax - bx) + (ay - by) * (ay - by) + (az - bz) * (az - bz));
}

/* Galaxy (0 MW, 1 M31) of each particle from the documented id order:
 * markers, then MW disc, bulge, halo, then M31 disc, bulge, halo. The
 * galaxy changes where a halo run is followed by a disc particle. */
static void galaxy_of(const table *t, int *gal)
{
    int g = 0;
    for (size_t i = 0; i < t->n; i++) {
        if (i >= 4 && t->type[i] == ORR_MODEL_TYPE_DISC && t->type[i - 1] == ORR_MODEL_TYPE_HALO)
            g++;
        gal[i] = i < 3 ? (int)i % 2 : g;
    }
}

static void test_markers(void)
{
    table t;
    CHECK(load_model(1000, 42, 780.0, 100, &t));
    if (t.n != 1000)
        return;
    CHECK(t.id[0] == ORR_MODEL_ID_MW_BH && t.type[0] == ORR_MODEL_TYPE_BH);
    CHECK(t.id[1] == ORR_MODEL_ID_M31_BH && t.type[1] == ORR_MODEL_TYPE_BH);
    CHECK(t.id[2] == ORR_MODEL_ID_SUN && t.type[2] == ORR_MODEL_TYPE_SUN);
    CHECK(t.x[0] == 0.0f && t.y[0] == 0.0f && t.z[0] == 0.0f);
    CHECK_NEAR(t.m[0], 4.3e-4, 1e-9);
    CHECK_NEAR(t.m[1], 1.4e-2, 1e-8);
    CHECK_NEAR(t.x[2], -8.0, 1e-6);
    CHECK_NEAR(t.y[2], 0.0, 1e-6);
    CHECK_NEAR(t.z[2], 0.02, 1e-6);
    CHECK_NEAR(dist3(t.x[2], t.y[2], t.z[2], t.x[0], t.y[0], t.z[0]), 8.0, 1e-3);
    CHECK(fabs(t.z[2] - t.z[0]) < 0.1);
    CHECK_NEAR(dist3(t.x[1], t.y[1], t.z[1], t.x[0], t.y[0], t.z[0]), 780.0, 1e-3);

    /* M31 seen from the Sun at galactic (l, b) = (121.17, -21.57) deg. */
    double dx = t.x[1] - t.x[2], dy = t.y[1] - t.y[2], dz = t.z[1] - t.z[2];
    double l = atan2(dy, dx) * 180.0 / 3.14159265358979, b = atan2(dz, hypot(dx, dy)) * 180.0 / 3.14159265358979;
    CHECK_NEAR(l, 121.17, 1e-3);
    CHECK_NEAR(b, -21.57, 1e-3);

    /* The Sun moves towards +y at 220-235 km/s relative to the MW centre. */
    double vy = t.vy[2] - t.vy[0];
    /* The true circular speed of the model's potential at 8 kpc (thin disc
     * + spheroids), 241.7 km/s; test_disc_equilibrium measures it. */
    CHECK(vy > 235.0 && vy < 248.0);
    CHECK(fabs(t.vx[2] - t.vx[0]) < 1e-3 && fabs(t.vz[2] - t.vz[0]) < 1e-3);

    /* M31 approaches at ~110 km/s radially, ~17 km/s tangentially. */
    double rx = t.x[1] - t.x[0], ry = t.y[1] - t.y[0], rz = t.z[1] - t.z[0], r = sqrt(rx * rx + ry * ry + rz * rz);
    double wx = t.vx[1] - t.vx[0], wy = t.vy[1] - t.vy[0], wz = t.vz[1] - t.vz[0];
    double vrad = (rx * wx + ry * wy + rz * wz) / r;
    double vtan = sqrt(fmax(0.0, wx * wx + wy * wy + wz * wz - vrad * vrad));
    CHECK_NEAR(vrad, -110.0, 0.01);
    CHECK_NEAR(vtan, 17.0, 0.01);
    table_free(&t);
}

static void test_separation_parameter(void)
{
    table t;
    CHECK(load_model(200, 1, 120.0, 64, &t));
    if (t.n == 200)
        CHECK_NEAR(dist3(t.x[1], t.y[1], t.z[1], t.x[0], t.y[0], t.z[0]), 120.0, 1e-4);
    table_free(&t);
    CHECK(load_model(200, 1, 10.0, 64, &t));
    if (t.n == 200)
        CHECK_NEAR(dist3(t.x[1], t.y[1], t.z[1], t.x[0], t.y[0], t.z[0]), 10.0, 1e-5);
    table_free(&t);
}

static void test_info(void)
{
    orr_model_params p = {12345, 7, 780.0, ORR_MODEL_PAIR, 0, 0, 0, 0};
    orr_source *src = NULL;
    orr_error err = {0};
    CHECK(orr_model_source_open(&p, 1 << 20, &src, &err) == ORR_OK);
    if (!src)
        return;
    CHECK(strcmp(src->info.format, "model:mw-m31") == 0);
    CHECK_CONTAINS(src->info.path, "N=12345");
    CHECK_CONTAINS(src->info.path, "seed=7");
    CHECK_CONTAINS(src->info.path, "separation=780 kpc");
    CHECK(src->info.count == 12345);
    CHECK(src->info.has_id == 1 && src->info.has_type == 1 && src->info.has_h == 0);
    CHECK(src->info.nextra == 6);
    CHECK(strcmp(src->info.extra_names[0], "vx") == 0 && strcmp(src->info.extra_names[2], "vz") == 0);
    CHECK(strcmp(src->info.extra_names[3], "r") == 0);
    CHECK(strcmp(src->info.extra_names[4], "E0") == 0);
    CHECK(strcmp(src->info.extra_names[5], "ez") == 0);
    CHECK(src->chunk.capacity == 12345); /* min(chunk_size, N) */
    orr_source_close(src);
}

/* Component masses as documented: [galaxy][disc, bulge, halo]. */
static const double COMP_MASS[2][3] = {{5.0, 1.0, 100.0}, {7.0, 2.5, 150.0}};

static int comp_index(uint8_t type)
{
    return type == ORR_MODEL_TYPE_DISC ? 0 : type == ORR_MODEL_TYPE_BULGE ? 1 : 2;
}

static void test_masses_and_split(void)
{
    const long long n = 20000;
    table t;
    CHECK(load_model(n, 3, 780.0, 4096, &t));
    if (t.n != (size_t)n)
        return;
    int *gal = malloc(t.n * sizeof(int));
    galaxy_of(&t, gal);
    double mass[2][3] = {{0}}, count[3] = {0};
    int ids_ok = 1, finite = 1, kinds_ok = 1;
    for (size_t i = 0; i < t.n; i++) {
        ids_ok = ids_ok && t.id[i] == i + 1;
        finite = finite && isfinite(t.x[i]) && isfinite(t.y[i]) && isfinite(t.z[i]) &&
                 isfinite(t.vx[i]) && isfinite(t.vy[i]) && isfinite(t.vz[i]) && t.m[i] > 0;
        if (i < 3)
            continue;
        kinds_ok = kinds_ok && t.type[i] >= 1 && t.type[i] <= 3 && gal[i] <= 1;
        mass[gal[i]][comp_index(t.type[i])] += t.m[i];
        count[comp_index(t.type[i])] += 1;
    }
    CHECK(ids_ok);
    CHECK(finite);
    CHECK(kinds_ok);
    CHECK(gal[t.n - 1] == 1);
    for (int g = 0; g < 2; g++)
        for (int c = 0; c < 3; c++)
            CHECK_NEAR(mass[g][c] / COMP_MASS[g][c], 1.0, 1e-6);
    /* Star particles (discs and bulges of both galaxies) weigh the same, a
     * halo particle 8 of them (docs/model.md), up to one particle's
     * rounding per component; every particle counted once. */
    double star = t.m[3]; /* the first MW disc particle */
    for (size_t i = 3; i < t.n; i++) {
        double want = t.type[i] == ORR_MODEL_TYPE_HALO ? 8.0 * star : star;
        if (fabs(t.m[i] / want - 1.0) > 2e-3) {
            CHECK_NEAR(t.m[i] / want, 1.0, 2e-3);
            break;
        }
    }
    CHECK_NEAR(count[0] + count[1] + count[2], n - 3, 0.5);
    double star_mass = 5.0 + 1.0 + 7.0 + 2.5, halo_share = (250.0 / 8.0) / (star_mass + 250.0 / 8.0);
    CHECK_NEAR(count[2] / (n - 3), halo_share, 1e-3);
    free(gal);
    table_free(&t);
}

static int tables_equal(const table *a, const table *b)
{
    size_t f = a->n * sizeof(float);
    return a->n == b->n && memcmp(a->x, b->x, f) == 0 && memcmp(a->y, b->y, f) == 0 &&
           memcmp(a->z, b->z, f) == 0 && memcmp(a->m, b->m, f) == 0 && memcmp(a->vx, b->vx, f) == 0 &&
           memcmp(a->vy, b->vy, f) == 0 && memcmp(a->vz, b->vz, f) == 0 &&
           memcmp(a->id, b->id, a->n * sizeof(uint64_t)) == 0 && memcmp(a->type, b->type, a->n) == 0;
}

static void test_chunk_size_independence(void)
{
    const long long n = 5003;
    table a, b, c, d;
    CHECK(load_model(n, 99, 780.0, 1000, &a));
    CHECK(load_model(n, 99, 780.0, 7, &b));
    CHECK(load_model(n, 99, 780.0, (size_t)n, &c));
    CHECK(tables_equal(&a, &b));
    CHECK(tables_equal(&a, &c));
    CHECK(load_model(n, 100, 780.0, 1000, &d));
    CHECK(a.n == d.n && memcmp(a.x + 3, d.x + 3, 100 * sizeof(float)) != 0); /* the seed matters */
    table_free(&a);
    table_free(&b);
    table_free(&c);
    table_free(&d);
}

static void test_rewind(void)
{
    orr_model_params p = {3000, 5, 780.0, ORR_MODEL_PAIR, 0, 0, 0, 0};
    orr_source *src = NULL;
    orr_error err = {0};
    CHECK(orr_model_source_open(&p, 512, &src, &err) == ORR_OK);
    if (!src)
        return;
    table a, b;
    CHECK(read_source(src, 3000, &a));
    CHECK(orr_source_rewind(src, &err) == ORR_OK);
    CHECK(read_source(src, 3000, &b));
    CHECK(tables_equal(&a, &b));
    const orr_chunk *c;
    CHECK(orr_source_next(src, &c, &err) == ORR_OK && c->n == 0); /* stays at the end */
    table_free(&a);
    table_free(&b);
    orr_source_close(src);
}

/* Mean radius of an exponential disc truncated at x = Rmax/Rd, in units of
 * Rd: the ratio of the lower incomplete gamma functions g(3, x) / g(2, x). */
static double truncated_disc_mean(double x)
{
    double e = exp(-x);
    return (2.0 - e * (x * x + 2.0 * x + 2.0)) / (1.0 - e * (1.0 + x));
}

static void test_disc_profile_and_rotation(void)
{
    const long long n = 200000;
    table t;
    CHECK(load_model(n, 11, 780.0, 65536, &t));
    if (t.n != (size_t)n)
        return;
    int *gal = malloc(t.n * sizeof(int));
    galaxy_of(&t, gal);
    double sum_r = 0, sum_absz = 0, cnt = 0, lx = 0, ly = 0, lz = 0;
    double ml[3] = {0}; /* M31 disc angular momentum */
    for (size_t i = 3; i < t.n; i++) {
        if (t.type[i] != ORR_MODEL_TYPE_DISC)
            continue;
        int g = gal[i];
        double x = t.x[i] - t.x[g], y = t.y[i] - t.y[g], z = t.z[i] - t.z[g];
        double vx = t.vx[i] - t.vx[g], vy = t.vy[i] - t.vy[g], vz = t.vz[i] - t.vz[g];
        double jx = y * vz - z * vy, jy = z * vx - x * vz, jz = x * vy - y * vx;
        if (g == 0) {
            sum_r += sqrt(x * x + y * y);
            sum_absz += fabs(z);
            cnt += 1;
            lx += jx;
            ly += jy;
            lz += jz;
        } else {
            ml[0] += jx;
            ml[1] += jy;
            ml[2] += jz;
        }
    }
    /* MW: Rd = 3 kpc truncated at 25 kpc; exponential vertical, hz = 0.3 kpc. */
    CHECK_NEAR(sum_r / cnt / (3.0 * truncated_disc_mean(25.0 / 3.0)), 1.0, 0.02);
    CHECK_NEAR(sum_absz / cnt / 0.3, 1.0, 0.03);
    /* Angular momentum along -z. */
    CHECK(lz < 0);
    CHECK(sqrt(lx * lx + ly * ly) < 0.02 * fabs(lz));
    /* M31: along the documented spin axis (l, b) = (240, -30) deg. */
    double d2r = 3.14159265358979 / 180.0;
    double sx = cos(-30 * d2r) * cos(240 * d2r), sy = cos(-30 * d2r) * sin(240 * d2r), sz = sin(-30 * d2r);
    double mn = sqrt(ml[0] * ml[0] + ml[1] * ml[1] + ml[2] * ml[2]);
    CHECK((ml[0] * sx + ml[1] * sy + ml[2] * sz) / mn > cos(2 * d2r));
    free(gal);
    table_free(&t);
}

/* The galaxies' bulk velocities (carried by the black-hole markers) cancel
 * exactly; the particles' random motions leave a residual of order
 * M sigma / sqrt(N), 1-5% of M31's momentum at N = 10^5. Were the bulk
 * velocities unbalanced, it would be ~100%. */
static void test_momentum(void)
{
    const double m_mw = 106.00043, m_m31 = 159.514; /* galaxy totals */
    table t;
    CHECK(load_model(100000, 2, 780.0, 10000, &t));
    if (t.n != 100000)
        return;
    double bulk[3] = {m_mw * t.vx[0] + m_m31 * t.vx[1], m_mw * t.vy[0] + m_m31 * t.vy[1],
                      m_mw * t.vz[0] + m_m31 * t.vz[1]};
    double p31 = m_m31 * sqrt((double)t.vx[1] * t.vx[1] + (double)t.vy[1] * t.vy[1] + (double)t.vz[1] * t.vz[1]);
    CHECK(p31 > 0 && sqrt(bulk[0] * bulk[0] + bulk[1] * bulk[1] + bulk[2] * bulk[2]) < 1e-6 * p31);
    double p[3] = {0};
    for (size_t i = 0; i < t.n; i++) {
        p[0] += (double)t.m[i] * t.vx[i];
        p[1] += (double)t.m[i] * t.vy[i];
        p[2] += (double)t.m[i] * t.vz[i];
    }
    CHECK(sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) < 0.15 * p31);
    table_free(&t);
}

static void expect_usage(long long n, double sep, size_t chunk, const char *word)
{
    orr_model_params p = {n, 1, sep, ORR_MODEL_PAIR, 0, 0, 0, 0};
    orr_source *src = (orr_source *)&p; /* must be reset to NULL */
    orr_error err = {0};
    CHECK(orr_model_source_open(&p, chunk, &src, &err) == ORR_ERR_USAGE);
    CHECK(src == NULL);
    CHECK_CONTAINS(err.msg, word);
}

static void test_bad_parameters(void)
{
    expect_usage(99, 780.0, 1000, "99 particles");
    expect_usage(0, 780.0, 1000, "particles");
    expect_usage(-5, 780.0, 1000, "particles");
    expect_usage(ORR_MODEL_PARTICLES_MAX + 1, 780.0, 1000, "particles");
    expect_usage(1000, NAN, 1000, "separation");
    expect_usage(1000, INFINITY, 1000, "separation");
    expect_usage(1000, 5.0, 1000, "separation");
    expect_usage(1000, -780.0, 1000, "separation");
    expect_usage(1000, 1e6, 1000, "separation");
    expect_usage(1000, 780.0, 0, "chunk size");
    orr_error err = {0};
    orr_source *src = NULL;
    CHECK(orr_model_source_open(NULL, 1000, &src, &err) == ORR_ERR_USAGE);
    table t; /* the minimum is accepted */
    CHECK(load_model(100, 1, 780.0, 1000, &t));
    table_free(&t);
}

/* ---- binding energy E0 -------------------------------------------------- */

#define G_MODEL 4.30091e4 /* kpc (km/s)^2 per 1e10 Msun, as docs/model.md */

/* The Milky Way's potential beyond its disc and bulge truncation radii
 * (25 and 10 kpc), where everything but the halo is enclosed: a point mass
 * Mc = black hole + disc + bulge plus a Hernquist halo of scale a whose
 * untruncated mass is Mh / F(rmax), truncated at rmax = 250 kpc. Integrating
 * -G M(r)/r^2 in from the point-mass potential at rmax analytically:
 *   Phi(r) = -G Mtot/rmax - G [Mc (1/r - 1/rmax) + Mh' (1/(r+a) - 1/(rmax+a))]. */
static double mw_outer_potential(double r)
{
    const double mc = 4.3e-4 + 5.0 + 1.0, mh = 100.0, a = 33.0, rmax = 250.0;
    double q = rmax / (rmax + a), mh_full = mh / (q * q);
    return -G_MODEL * (mc + mh) / rmax -
           G_MODEL * (mc * (1.0 / r - 1.0 / rmax) + mh_full * (1.0 / (r + a) - 1.0 / (rmax + a)));
}

typedef struct energy_stats {
    size_t halo_checked, disc_bound, disc_total;
    double worst_rel;                /* |Phi_particle - Phi_analytic| / |Phi_analytic| */
    double bin_sum[3], bin_count[3]; /* mean E0 of MW disc stars: r < 3, 3-6, 6-12 kpc */
} energy_stats;

static void energy_from_chunk(const orr_chunk *c, const float vbulk[3], int *galaxy, energy_stats *s)
{
    const float *vx = orr_chunk_field(c, "vx"), *vy = orr_chunk_field(c, "vy"), *vz = orr_chunk_field(c, "vz");
    const float *r = orr_chunk_field(c, "r"), *e0 = orr_chunk_field(c, "E0");
    for (size_t k = 0; k < c->n; k++) {
        uint64_t i = c->first_index + k;
        /* Documented id order: markers, MW disc, bulge, halo, then M31's
         * runs; the one chunk holds every particle, so k - 1 is i - 1. */
        if (i >= 4 && c->type[k] == ORR_MODEL_TYPE_DISC && c->type[k - 1] == ORR_MODEL_TYPE_HALO)
            *galaxy = 1;
        if (i < 3) {
            CHECK(e0[k] == 0.0f); /* markers */
            continue;
        }
        if (*galaxy != 0)
            continue;
        double dv[3] = {vx[k] - vbulk[0], vy[k] - vbulk[1], vz[k] - vbulk[2]};
        double kin = 0.5 * (dv[0] * dv[0] + dv[1] * dv[1] + dv[2] * dv[2]);
        if (c->type[k] == ORR_MODEL_TYPE_HALO && r[k] > 30.0 && r[k] < 240.0) {
            double want = mw_outer_potential(r[k]), got = e0[k] - kin;
            double rel = fabs(got - want) / fabs(want);
            if (rel > s->worst_rel)
                s->worst_rel = rel;
            s->halo_checked++;
        }
        if (c->type[k] == ORR_MODEL_TYPE_DISC) {
            s->disc_total++;
            s->disc_bound += e0[k] < 0;
            int b = r[k] < 3 ? 0 : r[k] < 6 ? 1 : r[k] < 12 ? 2 : -1;
            if (b >= 0) {
                s->bin_sum[b] += e0[k];
                s->bin_count[b]++;
            }
        }
    }
}

/* E0 = Phi(r) + |v - v_galaxy|^2 / 2: the potential part matches the
 * analytic Hernquist-plus-point-mass potential where that is exact, disc
 * stars are bound, and binding weakens outward. */
static void test_binding_energy(void)
{
    const long long n = 40000;
    orr_model_params p = {n, 3, 780.0, ORR_MODEL_PAIR, 0, 0, 0, 0};
    orr_source *src = NULL;
    orr_error err = {0};
    CHECK(orr_model_source_open(&p, (size_t)n, &src, &err) == ORR_OK);
    if (!src)
        return;
    const orr_chunk *c;
    CHECK(orr_source_next(src, &c, &err) == ORR_OK && c->n == (size_t)n);
    CHECK(orr_chunk_field(c, "E0") != NULL);
    if (c->n != (size_t)n || !orr_chunk_field(c, "E0")) {
        orr_source_close(src);
        return;
    }
    /* The Milky Way's bulk velocity is its black hole's (index 0). */
    const float vbulk[3] = {orr_chunk_field(c, "vx")[0], orr_chunk_field(c, "vy")[0], orr_chunk_field(c, "vz")[0]};
    energy_stats s = {0};
    int galaxy = 0;
    energy_from_chunk(c, vbulk, &galaxy, &s);
    orr_source_close(src);

    CHECK(galaxy == 1);
    CHECK(s.halo_checked > 1000);
    CHECK(s.worst_rel < 1e-3);
    CHECK(s.disc_total > 3000);
    CHECK(s.disc_bound == s.disc_total); /* disc random motions (sigma < v_c / 2) cannot unbind a disc star */
    for (int b = 0; b < 3; b++)
        CHECK(s.bin_count[b] > 100);
    double m0 = s.bin_sum[0] / s.bin_count[0], m1 = s.bin_sum[1] / s.bin_count[1];
    double m2 = s.bin_sum[2] / s.bin_count[2];
    CHECK(m0 < m1 && m1 < m2 && m2 < 0);
}

/* ---- vertical energy ez ------------------------------------------------- */

static int compare_floats(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* The CDF of the Gamma(3/2) distribution: that of g^2 / 2 + e for a unit
 * Gaussian g and an independent unit exponential e. */
static double gamma_three_halves_cdf(double x)
{
    const double pi = 3.14159265358979323846;
    return erf(sqrt(x)) - 2.0 * sqrt(x / pi) * exp(-x);
}

/* ez = gz^2 / 2 + |z| / h (docs/model.md, "Vertical energy ez"): the disc
 * stars' values follow Gamma(3/2) (mean 1.5), none below the Milky Way
 * star's own |z| / 0.3 kpc; 0 for the markers, bulges, halos and gas. */
static void test_vertical_energy(void)
{
    const long long n = 40000, dust = 2000;
    orr_model_params p = {n, 3, 780.0, ORR_MODEL_PAIR, 0, 0, 0, 0};
    orr_source *src = NULL;
    orr_error err = {0};
    CHECK(orr_model_source_open_dust(&p, dust, (size_t)(n + dust), &src, &err) == ORR_OK);
    if (!src)
        return;
    const orr_chunk *c;
    CHECK(orr_source_next(src, &c, &err) == ORR_OK && c->n == (size_t)(n + dust));
    const float *ez = orr_chunk_field(c, "ez");
    CHECK(ez != NULL && src->info.nextra == 6 && strcmp(src->info.extra_names[5], "ez") == 0);
    if (c->n != (size_t)(n + dust) || !ez) {
        orr_source_close(src);
        return;
    }
    float *disc = malloc(c->n * sizeof *disc);
    CHECK(disc != NULL);
    if (!disc) {
        orr_source_close(src);
        return;
    }
    size_t ndisc = 0, others = 0, others_zero = 0, below_height = 0;
    int galaxy = 0;
    double sum = 0.0;
    for (size_t k = 0; k < c->n; k++) {
        if (k >= 4 && c->type[k] == ORR_MODEL_TYPE_DISC && c->type[k - 1] == ORR_MODEL_TYPE_HALO)
            galaxy = 1; /* M31's disc: its plane is not z = 0 */
        if (k < 3 || c->type[k] != ORR_MODEL_TYPE_DISC) {
            others++;
            others_zero += ez[k] == 0.0f;
            continue;
        }
        disc[ndisc++] = ez[k];
        sum += ez[k];
        if (galaxy == 0) /* the Milky Way's disc lies in z = 0, h = 0.3 kpc */
            below_height += ez[k] < fabs(c->z[k]) / 0.3 * (1.0 - 1e-6);
    }
    orr_source_close(src);
    qsort(disc, ndisc, sizeof *disc, compare_floats);
    double ks = 0.0;
    for (size_t i = 0; i < ndisc; i++) {
        double f = gamma_three_halves_cdf(disc[i]);
        ks = fmax(ks, fmax(fabs(f - (double)i / ndisc), fabs(f - (double)(i + 1) / ndisc)));
    }
    fprintf(stderr, "  %zu disc stars: mean ez %.4f, median %.4f, KS distance to Gamma(3/2) %.4f\n", ndisc,
            sum / ndisc, disc[ndisc / 2], ks);
    CHECK(ndisc > 5000);
    CHECK(others == others_zero);
    CHECK(below_height == 0);
    CHECK(fabs(sum / ndisc - 1.5) < 0.05); /* 4 standard errors: sqrt(1.5 / 10^4) = 0.012 */
    CHECK(ks < 1.63 / sqrt((double)ndisc)); /* Kolmogorov's 1% point */
    free(disc);
}

/* ---- one galaxy alone, and its equilibrium ----------------------------- */

static void test_single_galaxy(void)
{
    const long long n = 5000;
    orr_model_params mw = {n, 4, 780.0, ORR_MODEL_MW, 0, 0, 0, 0}, m31 = {n, 4, 0.0, ORR_MODEL_M31, 2.0, 0, 0, 0};
    table t;
    CHECK(load_model_params(&mw, 999, &t));
    if (t.n == (size_t)n) {
        /* Markers: the MW black hole at rest at the origin, the Sun; ids then run from 4. */
        CHECK(t.id[0] == ORR_MODEL_ID_MW_BH && t.type[0] == ORR_MODEL_TYPE_BH);
        CHECK(t.x[0] == 0.0f && t.vx[0] == 0.0f && t.vy[0] == 0.0f);
        CHECK(t.id[1] == ORR_MODEL_ID_SUN && t.type[1] == ORR_MODEL_TYPE_SUN);
        CHECK_NEAR(t.x[1], -8.0, 1e-6);
        int ids = 1;
        double m = 0, r_max = 0;
        for (size_t i = 2; i < t.n; i++) {
            ids = ids && t.id[i] == i + 2 && t.type[i] != ORR_MODEL_TYPE_BH;
            m += t.m[i];
            double r = dist3(t.x[i], t.y[i], t.z[i], 0, 0, 0);
            r_max = r > r_max ? r : r_max;
        }
        CHECK(ids);
        CHECK_NEAR(m, 106.0, 1e-4 * 106.0); /* the MW's disc, bulge and halo, nothing of M31 */
        CHECK(r_max <= 250.0 + 1e-3);
        table_free(&t);
    }
    CHECK(load_model_params(&m31, 999, &t));
    if (t.n == (size_t)n) {
        CHECK(t.id[0] == ORR_MODEL_ID_M31_BH && t.x[0] == 0.0f);
        CHECK_NEAR(t.m[0], 1.4e-2, 1e-8);
        CHECK(t.id[1] == 4 && t.type[1] == ORR_MODEL_TYPE_DISC);
        double m = 0;
        for (size_t i = 1; i < t.n; i++)
            m += t.m[i];
        CHECK_NEAR(m, 159.5, 1e-4 * 159.5);
        table_free(&t);
    }
    orr_model_params bad = {n, 4, 780.0, 7, 0, 0, 0, 0};
    orr_source *src = NULL;
    orr_error err = {0};
    CHECK(orr_model_source_open(&bad, 100, &src, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "galaxies");
}

/* The radial force on points of a ring of radius R in the plane z = 0 by
 * direct summation over the model's particles, averaged over RING_POINTS
 * azimuths: v_c^2 = R <-F_R>. The points sit inside a grainy disc, so the
 * nearest few particles dominate each point's noise; many points and a
 * 0.1 kpc softening (a bias of order (0.1/R)^2, under 0.1%) beat it down. */
#define RING_POINTS 256
static double ring_vc2(const table *t, double R)
{
    double sum = 0;
    for (int k = 0; k < RING_POINTS; k++) {
        double ph = 2 * 3.14159265358979 * (k + 0.5) / RING_POINTS, px = R * cos(ph), py = R * sin(ph);
        double fr = 0;
        for (size_t i = 0; i < t->n; i++) {
            double dx = t->x[i] - px, dy = t->y[i] - py, dz = t->z[i];
            double d2 = dx * dx + dy * dy + dz * dz + 0.1 * 0.1;
            fr += t->m[i] * (dx * cos(ph) + dy * sin(ph)) / (d2 * sqrt(d2));
        }
        sum += -G_MODEL * fr; /* fr < 0: the pull is inward */
    }
    return R * sum / RING_POINTS;
}

typedef struct ring {
    double n, vphi, vphi2, vr2, vz2;
} ring;

/* Disc-star moments in 1-kpc rings about R (mean and second moments). */
static void disc_rings(const table *t, const double *radii, int nr, ring *out)
{
    memset(out, 0, (size_t)nr * sizeof *out);
    for (size_t i = 0; i < t->n; i++) {
        if (t->type[i] != ORR_MODEL_TYPE_DISC)
            continue;
        double R = hypot(t->x[i], t->y[i]);
        for (int k = 0; k < nr; k++) {
            if (fabs(R - radii[k]) > 0.5)
                continue;
            /* The MW rotates clockwise seen from +z: vphi = -(x vy - y vx) / R. */
            double vphi = -(t->x[i] * t->vy[i] - t->y[i] * t->vx[i]) / R;
            double vr = (t->x[i] * t->vx[i] + t->y[i] * t->vy[i]) / R;
            out[k].n++;
            out[k].vphi += vphi;
            out[k].vphi2 += vphi * vphi;
            out[k].vr2 += vr * vr;
            out[k].vz2 += (double)t->vz[i] * t->vz[i];
        }
    }
    for (int k = 0; k < nr; k++) {
        ring *r = &out[k];
        r->vphi /= r->n;
        r->vphi2 = r->vphi2 / r->n - r->vphi * r->vphi; /* sigma_phi^2 */
        r->vr2 /= r->n;
        r->vz2 /= r->n;
    }
}

/* The disc's radial "pressure" Sigma sigma_R^2 at R, in arbitrary units:
 * the disc particles of the ring R +- 0.5 kpc over its area, times their
 * mean squared radial speed. */
static double ring_pressure(const table *t, double R)
{
    double r1[1] = {R};
    ring rg;
    disc_rings(t, r1, 1, &rg);
    return rg.n / (2.0 * 3.14159265358979 * R) * rg.vr2;
}

/* An isolated Milky Way is in rotational equilibrium with its own
 * particles' gravity: the disc's mean rotation is the circular speed
 * measured by direct summation less the asymmetric drift of the radial
 * Jeans equation (Binney & Tremaine 2008 eq. 4.228) evaluated with the
 * measured dispersions and the measured slope of Sigma sigma_R^2 (from the
 * rings 1 kpc inside and outside),
 *   v_c^2 - vphi^2 = sigma_phi^2 - sigma_R^2 (1 + d ln(Sigma sigma_R^2) / d ln R);
 * and the Sun moves at v_c(8 kpc). A model rotating at the
 * spherical-approximation speed, or with no drift, fails by more than the
 * tolerance (the drift alone is 4-12% of v_c^2 at 4-6 kpc). */
static void test_disc_equilibrium(void)
{
    const long long n = 100000;
    orr_model_params p = {n, 9, 780.0, ORR_MODEL_MW, 0, 0, 0, 0};
    table t;
    CHECK(load_model_params(&p, 8192, &t));
    if (t.n != (size_t)n)
        return;
    const double radii[] = {4.0, 6.0, 8.0, 10.0};
    ring rg[4];
    disc_rings(&t, radii, 4, rg);
    for (int k = 0; k < 4; k++) {
        double R = radii[k], vc2 = ring_vc2(&t, R);
        double slope = log(ring_pressure(&t, R + 1.0) / ring_pressure(&t, R - 1.0)) / log((R + 1.0) / (R - 1.0));
        double drift = rg[k].vphi2 - rg[k].vr2 * (1.0 + slope);
        double want = sqrt(vc2 - drift);
        CHECK(rg[k].n > 500);
        CHECK_NEAR(rg[k].vphi / want, 1.0, 0.02);
        /* the lag is real: the mean rotation is below v_c where the drift is large */
        if (R <= 6.0)
            CHECK(rg[k].vphi < sqrt(vc2) - 3.0);
        if (R == 8.0)
            CHECK_NEAR(t.vy[1] / sqrt(vc2), 1.0, 0.02); /* the Sun: circular */
    }
    table_free(&t);
}

/* A steady component obeys the tensor virial theorem direction by
 * direction (Binney & Tremaine 2008 eq. 4.250): for the Milky Way's
 * bulge inside 3 kpc (its surface term is isotropic and cancels in the
 * ratio), sum v_z^2 / sum -z a_z equals the same for x and y, with a the
 * direct-summation acceleration of all the model's particles. An isotropic
 * bulge placed spherically in the disc's flattened potential gives 0.73
 * and z^2 / (R^2 / 2) = 0.95 at 0.5-3 kpc (it then flattened by 20% within
 * 25 Myr of an N-body run); its f(E) in the flattened potential
 * (galaxy_flat.h) gives 0.87 (the bulge's own flattening is not fed back
 * into the potential) and a bulge flattened to 0.66. */
static void test_bulge_tensor_virial(void)
{
    const long long n = 100000;
    orr_model_params p = {n, 5, 780.0, ORR_MODEL_MW, 0, 0, 0, 0};
    table t;
    CHECK(load_model_params(&p, 8192, &t));
    if (t.n != (size_t)n)
        return;
    double kz = 0, wz = 0, kxy = 0, wxy = 0, z2 = 0, r2 = 0;
    for (size_t i = 0; i < t.n; i++) {
        double x = t.x[i], y = t.y[i], z = t.z[i];
        if (t.type[i] != ORR_MODEL_TYPE_BULGE || x * x + y * y + z * z > 9.0)
            continue;
        double ax = 0, ay = 0, az = 0;
        for (size_t j = 0; j < t.n; j++) {
            double dx = t.x[j] - x, dy = t.y[j] - y, dz = t.z[j] - z;
            double d2 = dx * dx + dy * dy + dz * dz + 0.01 * 0.01, f = t.m[j] / (d2 * sqrt(d2));
            ax += f * dx;
            ay += f * dy;
            az += f * dz;
        }
        kz += (double)t.vz[i] * t.vz[i];
        wz -= G_MODEL * z * az;
        kxy += ((double)t.vx[i] * t.vx[i] + (double)t.vy[i] * t.vy[i]) / 2;
        wxy -= G_MODEL * (x * ax + y * ay) / 2;
        if (x * x + y * y + z * z > 0.25) {
            z2 += z * z;
            r2 += (x * x + y * y) / 2;
        }
    }
    double ratio = (kz / wz) / (kxy / wxy);
    CHECK(ratio > 0.80 && ratio < 1.1);
    CHECK(z2 / r2 > 0.55 && z2 / r2 < 0.8);
    table_free(&t);
}

static void test_bad_disc_q(void)
{
    const double bad[] = {-1.0, NAN, INFINITY, 1e9};
    for (int i = 0; i < 4; i++) {
        orr_model_params p = {1000, 1, 780.0, ORR_MODEL_PAIR, bad[i], 0, 0, 0};
        orr_source *src = NULL;
        orr_error err = {0};
        CHECK(orr_model_source_open(&p, 100, &src, &err) == ORR_ERR_USAGE);
        CHECK(src == NULL);
        CHECK_CONTAINS(err.msg, "disc_q");
    }
}

/* input.model.m31_weight: in the pair each of M31's particles weighs w
 * times the Milky Way's of the same kind, every component keeps its mass,
 * and the particles split by the weights (mass over particle mass); w = 1
 * is the default's particles exactly, and a galaxy alone ignores it. */
static void check_m31_weight(double w)
{
    const long long n = 20000;
    orr_model_params p = {n, 3, 780.0, ORR_MODEL_PAIR, 0, 0, 0, w};
    table t;
    CHECK(load_model_params(&p, 4096, &t));
    if (t.n != (size_t)n)
        return;
    int *gal = malloc(t.n * sizeof(int));
    galaxy_of(&t, gal);
    double mass[2][3] = {{0}}, count[2] = {0};
    double star = t.m[3]; /* the first MW disc particle */
    int weights_ok = 1;
    for (size_t i = 3; i < t.n; i++) {
        mass[gal[i]][comp_index(t.type[i])] += t.m[i];
        count[gal[i]] += 1;
        double want = star * (t.type[i] == ORR_MODEL_TYPE_HALO ? 8.0 : 1.0) * (gal[i] == 1 ? w : 1.0);
        weights_ok = weights_ok && fabs(t.m[i] / want - 1.0) < 2e-3;
    }
    CHECK(weights_ok);
    for (int g = 0; g < 2; g++)
        for (int c = 0; c < 3; c++)
            CHECK_NEAR(mass[g][c] / COMP_MASS[g][c], 1.0, 1e-6);
    double claim[2] = {0, 0};
    for (int g = 0; g < 2; g++)
        for (int c = 0; c < 3; c++)
            claim[g] += COMP_MASS[g][c] / (c == 2 ? 8.0 : 1.0) / (g == 1 ? w : 1.0);
    CHECK_NEAR(count[0] / (n - 3), claim[0] / (claim[0] + claim[1]), 1e-3);
    free(gal);
    table_free(&t);
}

static void test_m31_weight(void)
{
    check_m31_weight(4.0);
    check_m31_weight(0.5);
    table a, b;
    orr_model_params p0 = {3000, 5, 780.0, ORR_MODEL_PAIR, 0, 0, 0, 0}, p1 = p0;
    p1.m31_weight = 1.0;
    CHECK(load_model_params(&p0, 1000, &a) && load_model_params(&p1, 1000, &b) && tables_equal(&a, &b));
    table_free(&a);
    table_free(&b);
    orr_model_params mw0 = {3000, 5, 780.0, ORR_MODEL_MW, 0, 0, 0, 0}, mw4 = mw0;
    mw4.m31_weight = 4.0;
    CHECK(load_model_params(&mw0, 1000, &a) && load_model_params(&mw4, 1000, &b) && tables_equal(&a, &b));
    table_free(&a);
    table_free(&b);
    const double bad[] = {-1.0, 0.01, 65.0, NAN, INFINITY};
    for (int i = 0; i < 5; i++) {
        orr_model_params q = {1000, 1, 780.0, ORR_MODEL_PAIR, 0, 0, 0, bad[i]};
        orr_source *src = NULL;
        orr_error err = {0};
        CHECK(orr_model_source_open(&q, 100, &src, &err) == ORR_ERR_USAGE);
        CHECK(src == NULL);
        CHECK_CONTAINS(err.msg, "m31_weight");
    }
}

/* With a type mask the model emits the markers and the particles of those
 * types only: the same particles, in the same order, as the full stream
 * filtered, on any chunk size; info.count says how many; each chunk's
 * first_index still names its particles (id = index + 1 in the pair). */
static void test_type_mask(void)
{
    const long long n = 5000;
    table all;
    CHECK(load_model(n, 11, 780.0, 333, &all));
    size_t expect = 0;
    for (size_t i = 0; i < all.n; i++)
        expect += i < 3 || all.type[i] == ORR_MODEL_TYPE_DISC || all.type[i] == ORR_MODEL_TYPE_BULGE;
    CHECK(expect > 3 && expect < all.n / 2);
    const size_t chunks[3] = {7, 1000, 4096};
    for (int k = 0; k < 3; k++) {
        orr_model_params p = {n, 11, 780.0, ORR_MODEL_PAIR, 0,
                              1u << ORR_MODEL_TYPE_DISC | 1u << ORR_MODEL_TYPE_BULGE, 0, 0};
        orr_source *src = NULL;
        orr_error err = {0};
        CHECK(orr_model_source_open(&p, chunks[k], &src, &err) == ORR_OK);
        if (!src)
            continue;
        CHECK(src->info.count == (int64_t)expect);
        size_t j = 0, bad = 0;
        const orr_chunk *c;
        while (orr_source_next(src, &c, &err) == ORR_OK && c->n > 0) {
            for (size_t q = 0; q < c->n; q++, j++) {
                while (j < all.n && !(j < 3 || all.type[j] == ORR_MODEL_TYPE_DISC || all.type[j] == ORR_MODEL_TYPE_BULGE))
                    j++;
                bad += j >= all.n || c->id[q] != all.id[j] || c->x[q] != all.x[j] ||
                       orr_chunk_field(c, "vz")[q] != all.vz[j] || (j >= 3 && c->id[q] != c->first_index + q + 1);
            }
        }
        while (j < all.n && !(all.type[j] == ORR_MODEL_TYPE_DISC || all.type[j] == ORR_MODEL_TYPE_BULGE))
            j++;
        CHECK(bad == 0);
        CHECK(j == all.n);
        orr_source_close(src);
    }
    table_free(&all);
}

/* A pass that asks for the disc and bulge alone (orr_source_only_types)
 * gets exactly the particles of a full pass of those types, the same
 * values, without the gas it would have made, which it counts as left out
 * (the halos, between the other blocks, still come); the rewind after it
 * brings every type back. */
static void test_only_types(void)
{
    const long long n = 6000, dust = 1500;
    orr_model_params p = {n, 5, 780.0, ORR_MODEL_PAIR, 0, 0, 0.6, 0};
    orr_source *src = NULL;
    orr_error err = {0};
    CHECK(orr_model_source_open_dust(&p, dust, 1000, &src, &err) == ORR_OK);
    if (!src)
        return;
    const unsigned mask = 1u << ORR_MODEL_TYPE_DISC | 1u << ORR_MODEL_TYPE_BULGE;
    size_t cap = (size_t)(n + dust + 16), full_n = 0, kept_n = 0, gas = 0, bad = 0;
    uint64_t *full_id = malloc(cap * sizeof *full_id);
    float *full_x = malloc(cap * sizeof *full_x);
    const orr_chunk *c;
    while (full_id && full_x && orr_source_next(src, &c, &err) == ORR_OK && c->n > 0)
        for (size_t q = 0; q < c->n; q++) {
            gas += c->type[q] == ORR_MODEL_TYPE_GAS;
            if (full_n < cap && (mask >> c->type[q] & 1u)) {
                full_id[full_n] = c->id[q];
                full_x[full_n++] = c->x[q];
            }
        }
    CHECK(gas == (size_t)dust);
    CHECK(orr_source_rewind(src, &err) == ORR_OK);
    orr_source_only_types(src, mask);
    size_t other = 0;
    while (full_id && full_x && orr_source_next(src, &c, &err) == ORR_OK && c->n > 0)
        for (size_t q = 0; q < c->n; q++) {
            if (!(mask >> c->type[q] & 1u)) {
                other += c->type[q] == ORR_MODEL_TYPE_GAS; /* (the halos and markers stay) */
                continue;
            }
            bad += kept_n >= full_n || c->id[q] != full_id[kept_n] || c->x[q] != full_x[kept_n];
            kept_n++;
        }
    CHECK(bad == 0 && kept_n == full_n && other == 0);
    CHECK(src->left_out == (uint64_t)dust); /* (the gas alone: the halos lie between the other blocks) */
    CHECK(orr_source_rewind(src, &err) == ORR_OK);
    CHECK(src->left_out == 0);
    gas = 0;
    while (orr_source_next(src, &c, &err) == ORR_OK && c->n > 0)
        for (size_t q = 0; q < c->n; q++)
            gas += c->type[q] == ORR_MODEL_TYPE_GAS;
    CHECK(gas == (size_t)dust);
    free(full_id);
    free(full_x);
    orr_source_close(src);
}

int main(void)
{
    RUN(test_markers);
    RUN(test_separation_parameter);
    RUN(test_info);
    RUN(test_masses_and_split);
    RUN(test_chunk_size_independence);
    RUN(test_rewind);
    RUN(test_disc_profile_and_rotation);
    RUN(test_momentum);
    RUN(test_bad_parameters);
    RUN(test_binding_energy);
    RUN(test_vertical_energy);
    RUN(test_single_galaxy);
    RUN(test_disc_equilibrium);
    RUN(test_bulge_tensor_virial);
    RUN(test_bad_disc_q);
    RUN(test_m31_weight);
    RUN(test_type_mask);
    RUN(test_only_types);
    return check_summary();
}
