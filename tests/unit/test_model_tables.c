/* Tests of how the built-in mw-m31 model is generated fast (docs/model.md,
 * "Tables"): the same bytes on any thread count and chunk size; the disc's
 * tables against the exact functions they stand in for; and the particles
 * drawn from the tables against the exact recipe's for the same random
 * numbers. */
#include <math.h>
#include <omp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "source/models/model.h"
#include "source/models/model_galaxy.h"

/* ---- the same bytes on any thread count and chunk size ------------------ */

/* Every field of every particle, byte for byte, appended to one buffer. */
typedef struct bytes {
    unsigned char *data;
    size_t len, cap;
} bytes;

static void append(bytes *b, const void *p, size_t n)
{
    if (b->len + n > b->cap) {
        b->cap = 2 * (b->len + n);
        b->data = realloc(b->data, b->cap);
    }
    memcpy(b->data + b->len, p, n);
    b->len += n;
}

static void append_chunk(bytes *b, const orr_chunk *c)
{
    append(b, c->x, c->n * sizeof(float));
    append(b, c->y, c->n * sizeof(float));
    append(b, c->z, c->n * sizeof(float));
    append(b, c->mass, c->n * sizeof(float));
    append(b, c->id, c->n * sizeof(uint64_t));
    append(b, c->type, c->n);
    for (int f = 0; f < c->nextra; f++)
        append(b, c->extra[f].data, c->n * sizeof(float));
}

/* The whole stream of a model with dust particles, read in chunks of
 * `chunk` on `threads` threads, in the order of the particles: each chunk's
 * fields one after another, so the comparison is of the particles only when
 * the chunk sizes agree; read_particles reorders by particle. */
static int read_stream(long long n, long long dust, int galaxies, size_t chunk, int threads, bytes *out)
{
    orr_model_params params = {n, 7, 780.0, galaxies, 0.0, 0, 0, 0};
    orr_source *src;
    orr_error err = {0};
    memset(out, 0, sizeof *out);
    omp_set_num_threads(threads);
    if (orr_model_source_open_dust(&params, dust, chunk, &src, &err) != ORR_OK)
        return 0;
    for (;;) {
        const orr_chunk *c;
        if (orr_source_next(src, &c, &err) != ORR_OK) {
            orr_source_close(src);
            return 0;
        }
        if (c->n == 0)
            break;
        for (size_t k = 0; k < c->n; k++) { /* particle by particle, so chunk sizes compare */
            orr_chunk one = *c;
            one.n = 1;
            one.x = c->x + k;
            one.y = c->y + k;
            one.z = c->z + k;
            one.mass = c->mass + k;
            one.id = c->id + k;
            one.type = c->type + k;
            for (int f = 0; f < c->nextra; f++)
                one.extra[f].data = c->extra[f].data + k;
            append_chunk(out, &one);
        }
    }
    orr_source_close(src);
    return 1;
}

static void test_same_bytes_any_threads_and_chunks(void)
{
    const long long n = 60000, dust = 5000;
    static const size_t chunks[] = {1 << 20, 4096, 4095, 10007, 7};
    static const int threads[] = {1, 2, 2, 1, 2};
    for (int galaxies = ORR_MODEL_PAIR; galaxies <= ORR_MODEL_MW; galaxies++) {
        bytes ref;
        CHECK(read_stream(n, dust, galaxies, chunks[0], threads[0], &ref));
        for (int k = 1; k < 5; k++) {
            bytes b;
            CHECK(read_stream(n, dust, galaxies, chunks[k], threads[k], &b));
            CHECK(b.len == ref.len && memcmp(b.data, ref.data, ref.len) == 0);
            free(b.data);
        }
        free(ref.data);
    }
}

/* ---- the tables against the exact functions ----------------------------- */

static galaxy *make_galaxy(int which)
{
    galaxy *g = calloc(1, sizeof *g);
    orr_model_galaxy_init(g, &orr_model_galaxy_specs[which], ORR_MODEL_DISC_Q_DEFAULT);
    orr_model_galaxy_build_potential(g);
    CHECK(orr_model_galaxy_build_dfs(g));
    orr_model_galaxy_build_disc_table(g);
    return g;
}

static double rel(double a, double b)
{
    return fabs(a - b) / fmax(fabs(b), 1e-300);
}

typedef struct errors {
    double node, sigma_z2; /* the largest of the node quantities', sigma_z^2's */
    int exact;             /* radii in cells left to the exact functions */
} errors;

/* Each tabulated quantity's error at R relative to its scale: its own
 * size, v_c^2 for the drift (0 where clipped), and for the radial term the
 * larger of itself and 2 pi G Sigma / h (what it is compared with in
 * sigma_z^2). */
static void node_errors(const galaxy *g, double R, disc_node *t, errors *e)
{
    if (!orr_model_disc_at(g, R, t)) {
        e->exact++;
        return;
    }
    double vc2 = orr_model_galaxy_disc_vc2(g, R), kappa2 = orr_model_galaxy_disc_kappa2(g, R);
    double ratio = kappa2 * R * R / (4.0 * vc2), sr = orr_model_galaxy_disc_sigma_r(g, R);
    double drift = fmin(0.0, sr * sr * (1.0 - ratio + orr_model_galaxy_disc_pressure_slope(g, R)));
    double h = g->s.disc_hz, radial = orr_model_galaxy_disc_radial(g, R);
    double err[] = {rel(t->vc2, vc2), rel(t->gm_sph, MODEL_G * orr_model_spheroid_mass(g, R) / R),
                    fabs(t->drift - drift) / vc2, rel(t->sigma_r, sr), rel(t->sigma_phi, sr * sqrt(ratio)),
                    fabs(t->radial - radial) / fmax(fabs(radial), orr_model_galaxy_disc_sheet(g, R) / (h * h))};
    for (size_t i = 0; i < sizeof err / sizeof err[0]; i++)
        e->node = fmax(e->node, err[i]);
}

/* 200,000 radii uniform in ln R from 1 pc to the disc's edge and heights
 * from the disc's layer: every node quantity within 1e-4 (the build checks
 * each cell to 2e-5; cells where the exact functions have kinks, about 0.5%
 * of these radii, are computed exactly), sigma_z^2 within 1e-3 of its
 * positive terms (the layer's and the spheroids' pull: where they nearly
 * cancel the disc's radial term, high above the centre, sigma_z^2 itself
 * is clipped at 1 (km/s)^2 and its relative error means nothing). */
static void test_table_accuracy(void)
{
    for (int which = 0; which < 2; which++) {
        galaxy *g = make_galaxy(which);
        orr_rng r = orr_rng_seed(11, (uint64_t)which, 0);
        errors e = {0};
        const int n = 200000;
        for (int i = 0; i < n; i++) {
            double R = exp(log(1e-3) + orr_rng_uniform(&r) * (log(g->s.disc_rmax) - log(1e-3)));
            double az = -g->s.disc_hz * log(orr_rng_uniform(&r)), layer = exp(-az / g->s.disc_hz);
            disc_node t;
            int before = e.exact;
            node_errors(g, R, &t, &e);
            if (e.exact > before)
                continue;
            double sheet = orr_model_galaxy_disc_sheet(g, R) * (1.0 - 0.5 * layer);
            double tab = orr_model_disc_sigma_z2_at(g, &t, R, az, orr_model_galaxy_disc_sheet(g, R), layer);
            double exact = orr_model_galaxy_disc_sigma_z2(g, R, az);
            double er = fabs(tab - exact) / (sheet + orr_model_galaxy_spheroid_pull(g, R, az));
            e.sigma_z2 = fmax(e.sigma_z2, er);
        }
        fprintf(stderr, "  galaxy %d: node quantities within %.2g, sigma_z^2 within %.2g, %.2g%% of radii exact\n",
                which, e.node, e.sigma_z2, 100.0 * e.exact / n);
        CHECK(e.node < 1e-4);
        CHECK(e.sigma_z2 < 1e-3);
        CHECK(e.exact < n / 50);
        free(g);
    }
}

/* ---- the particles against the exact recipe ----------------------------- */

/* A disc star's ez from its definition, v_z^2 / (2 sigma_z^2(R, z)) + |z| / h,
 * with v_z and z along the spin axis from its position and velocity and the
 * exact sigma_z^2 (g centred at rest at the origin). */
static double ez_by_definition(const galaxy *g, const particle *p)
{
    double z = orr_v3_dot(p->pos, g->spin), vz = orr_v3_dot(p->vel, g->spin);
    double R = sqrt(fmax(0.0, orr_v3_dot(p->pos, p->pos) - z * z));
    double sz2 = orr_model_galaxy_disc_sigma_z2(g, R > 1e-3 ? R : 1e-3, z);
    return vz * vz / (2.0 * sz2) + fabs(z) / g->s.disc_hz;
}

static void test_particles_against_exact(void)
{
    for (int which = 0; which < 2; which++) {
        galaxy *g = make_galaxy(which);
        g->e1 = orr_v3(1, 0, 0);
        g->e2 = orr_v3(0, 1, 0);
        g->spin = orr_v3(0, 0, 1);
        for (int comp = 0; comp < COMP_COUNT; comp++) {
            double dpos = 0, dv = 0, de0 = 0, dez = 0, dez_def = 0;
            for (uint64_t i = 0; i < 100000; i++) {
                orr_rng r1 = orr_rng_seed(5, i, 0), r2 = r1;
                particle a, b;
                if (comp == COMP_DISC) {
                    orr_model_galaxy_sample_disc(g, &r1, &a);
                    orr_model_galaxy_sample_disc_fast(g, &r2, &b);
                } else {
                    orr_model_galaxy_sample_sphere(g, comp, &r1, &a);
                    orr_model_galaxy_sample_sphere_fast(g, comp, &r2, &b);
                }
                double rad = orr_v3_norm(a.pos);
                dpos = fmax(dpos, orr_v3_norm(orr_v3_sub(a.pos, b.pos)) / rad);
                dv = fmax(dv, orr_v3_norm(orr_v3_sub(a.vel, b.vel)));
                double e0 = orr_model_galaxy_potential(g, rad) + 0.5 * orr_v3_dot(a.vel, a.vel);
                de0 = fmax(de0, fabs(b.e0 - e0) / fabs(e0));
                dez = fmax(dez, fabs(b.ez - a.ez) / (1.0 + a.ez));
                if (comp == COMP_DISC)
                    dez_def = fmax(dez_def, fabs(a.ez - ez_by_definition(g, &a)) / (1.0 + a.ez));
                else
                    CHECK(a.ez == 0.0f && b.ez == 0.0f);
            }
            fprintf(stderr,
                    "  galaxy %d component %d: positions within %.2g, velocities %.2g km/s, E0 %.2g, ez %.2g "
                    "(%.2g from its definition)\n",
                    which, comp, dpos, dv, de0, dez, dez_def);
            CHECK(dpos < 1e-14);
            CHECK(dv < (comp == COMP_DISC ? 0.5 : 1e-9));
            CHECK(de0 < (comp == COMP_DISC ? 2e-4 : 1e-6));
            CHECK(dez < 2e-7);     /* the same Gaussian to 1e-15, then one float rounding */
            CHECK(dez_def < 1e-6); /* one float rounding and sigma_z's square root */
        }
        free(g);
    }
}

/* ---- the batches against the one-particle samplers --------------------- */

/* The batch samplers (model_batch.c) against the one-particle samplers
 * they vectorise, for the same keys: the same random numbers, so every
 * float within one rounding of the other's (the logarithms differ from
 * libm's in the last bit of a double, which the float seldom sees), and
 * nearly all of them bit for bit. */
static void test_batches_against_one_particle(void)
{
    for (int which = 0; which < 2; which++) {
        galaxy *g = make_galaxy(which);
        g->e1 = orr_v3(0.6, 0.8, 0);
        g->e2 = orr_v3(0, 0, 1);
        g->spin = orr_v3(0.8, -0.6, 0);
        g->centre = orr_v3(300, -500, 100);
        g->velocity = orr_v3(-50, 80, 20);
        const uint64_t key = orr_rng_seed_key(9);
        for (int comp = 0; comp < COMP_COUNT; comp++) {
            float col[9][ORR_MODEL_BATCH];
            particle_rows rows = {col[0], col[1], col[2], col[3], col[4], col[5], col[6], col[7], col[8]};
            double worst = 0.0;
            long differ = 0, total = 0;
            for (uint64_t first = 0; first < 60000; first += ORR_MODEL_BATCH - 1) { /* odd batch sizes too */
                orr_model_galaxy_sample_batch(g, comp, key, first, ORR_MODEL_BATCH - 1, &rows);
                for (int i = 0; i < ORR_MODEL_BATCH - 1; i++) {
                    orr_rng r = orr_rng_seed_keyed(key, first + (uint64_t)i, 0);
                    particle p;
                    if (comp == COMP_DISC)
                        orr_model_galaxy_sample_disc_fast(g, &r, &p);
                    else
                        orr_model_galaxy_sample_sphere_fast(g, comp, &r, &p);
                    const float want[9] = {(float)p.pos.x, (float)p.pos.y, (float)p.pos.z, (float)p.vel.x,
                                           (float)p.vel.y, (float)p.vel.z, p.r, p.e0, p.ez};
                    for (int f = 0; f < 9; f++) {
                        total++;
                        differ += col[f][i] != want[f];
                        worst = fmax(worst, fabs(col[f][i] - want[f]) / fmax(fabs(want[f]), 1e-30));
                    }
                }
            }
            fprintf(stderr, "  galaxy %d component %d: batches within %.2g (relative) of one by one, %ld of %ld floats differ\n",
                    which, comp, worst, differ, total);
            CHECK(worst <= 1.2e-7); /* one rounding of a float */
            CHECK(differ <= total / 1000);
        }
        free(g);
    }
}

int main(void)
{
    RUN(test_same_bytes_any_threads_and_chunks);
    RUN(test_table_accuracy);
    RUN(test_particles_against_exact);
    RUN(test_batches_against_one_particle);
    return check_summary();
}
