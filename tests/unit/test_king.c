/* Tests of the King (1966) model generator and the globular cluster
 * colour-magnitude diagram: the ODE's concentrations against published
 * values, the sampled mass profile against the ODE's, the tidal radius, the
 * virial ratio from a direct pair sum, escape speeds, determinism across
 * chunk sizes, the CMD's phase fractions and sequences, and bad input. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "scene/scene.h"
#include "source/models/gc_cmd.h"
#include "source/models/king.h"

typedef struct stars {
    size_t n;
    double *x, *y, *z, *vx, *vy, *vz, *m, *r, *V, *BV;
    uint64_t *id;
    uint8_t *type;
} stars;

static void stars_free(stars *s)
{
    double **cols[] = {&s->x, &s->y, &s->z, &s->vx, &s->vy, &s->vz, &s->m, &s->r, &s->V, &s->BV};
    for (size_t i = 0; i < sizeof cols / sizeof cols[0]; i++)
        free(*cols[i]);
    free(s->id);
    free(s->type);
    memset(s, 0, sizeof *s);
}

/* Reads a whole king model; returns 0 on any error. */
static int load_king(long long n, uint64_t seed, double w0, size_t chunk, stars *s)
{
    memset(s, 0, sizeof *s);
    orr_king_params p = {n, seed, w0, 1.0, 5e5};
    orr_source *src = NULL;
    orr_error err;
    if (orr_king_source_open(&p, chunk, &src, &err) != ORR_OK) {
        fprintf(stderr, "%s\n", err.msg);
        return 0;
    }
    double **cols[] = {&s->x, &s->y, &s->z, &s->vx, &s->vy, &s->vz, &s->m, &s->r, &s->V, &s->BV};
    for (size_t i = 0; i < sizeof cols / sizeof cols[0]; i++)
        *cols[i] = malloc((size_t)n * sizeof(double));
    s->id = malloc((size_t)n * sizeof(uint64_t));
    s->type = malloc((size_t)n);
    const orr_chunk *c;
    int ok = 1;
    while (ok && orr_source_next(src, &c, &err) == ORR_OK && c->n > 0) {
        const char *names[] = {"vx", "vy", "vz", "r", "V", "BV"};
        double *dst[] = {s->vx, s->vy, s->vz, s->r, s->V, s->BV};
        for (size_t k = 0; k < c->n; k++) {
            if (s->n + k >= (size_t)n) {
                ok = 0;
                break;
            }
            s->x[s->n + k] = c->x[k];
            s->y[s->n + k] = c->y[k];
            s->z[s->n + k] = c->z[k];
            s->m[s->n + k] = c->mass[k];
            s->id[s->n + k] = c->id[k];
            s->type[s->n + k] = c->type[k];
            for (int f = 0; f < 6; f++)
                dst[f][s->n + k] = orr_chunk_field(c, names[f])[k];
        }
        s->n += c->n;
    }
    orr_source_close(src);
    return ok && s->n == (size_t)n;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The density formula against its definition, integrated directly:
 * rho(W) ~ integral_0^sqrt(2W) (e^(W - x^2/2) - 1) x^2 dx, which equals
 * sqrt(pi/2) times the closed form (King 1966). Covers the series branch. */
static void test_density_formula(void)
{
    const double ws[] = {0.0002, 0.002, 0.5, 3.0, 9.0};
    for (size_t i = 0; i < sizeof ws / sizeof ws[0]; i++) {
        double w = ws[i], xe = sqrt(2.0 * w), sum = 0.0;
        int n = 20000;
        for (int k = 0; k < n; k++) { /* midpoint rule */
            double x = (k + 0.5) * xe / n;
            sum += (exp(w - 0.5 * x * x) - 1.0) * x * x;
        }
        double direct = sum * xe / n / sqrt(3.14159265358979323846 / 2.0);
        CHECK_NEAR(orr_king_rho_shape(w) / direct, 1.0, 1e-6);
    }
    CHECK(orr_king_rho_shape(0.0) == 0.0);
    CHECK(orr_king_rho_shape(-1.0) == 0.0);
}

/* Concentrations c = log10(rt / r0) of King models: 0.67, 1.26, 2.12 for
 * W0 = 3, 6, 9 (King 1966, Table; the same values in e.g. McLaughlin & van
 * der Marel 2005, ApJS 161, 304, their model grid). */
static void test_concentration(void)
{
    const double w0[] = {3.0, 6.0, 9.0}, c[] = {0.67, 1.26, 2.12};
    double last = 0.0;
    for (int i = 0; i < 3; i++) {
        orr_king_profile p;
        orr_error err;
        CHECK(orr_king_solve(w0[i], &p, &err) == ORR_OK);
        double ci = log10(p.rt);
        CHECK_NEAR(ci, c[i], 0.015);
        CHECK(ci > last); /* deeper potential, more concentrated */
        last = ci;
        /* Gauss's law: the tabulated mass rises monotonically to mu_total. */
        int mono = 1;
        for (int k = 1; k < p.n; k++)
            mono &= p.mu[k] >= p.mu[k - 1] && p.r[k] > p.r[k - 1];
        CHECK(mono);
        CHECK_NEAR(p.mu[p.n - 1], p.mu_total, 1e-12);
        CHECK_NEAR(orr_king_w_at(&p, 0.0), w0[i], 1e-12);
        CHECK_NEAR(orr_king_w_at(&p, p.rt), 0.0, 1e-12);
        /* Near the centre the density is rho0: W = W0 - 3/2 r^2. */
        CHECK_NEAR(orr_king_w_at(&p, 0.01), w0[i] - 1.5e-4, 1e-6);
        orr_king_free(&p);
    }
}

/* The sampled radii follow the ODE's cumulative mass: Kolmogorov-Smirnov
 * distance below the 99.9% critical value 1.95 / sqrt(N), and the sampled
 * half-mass radius within 3% of the ODE's. The tidal radius bounds all. */
static void test_mass_profile(void)
{
    const long long n = 20000;
    stars s;
    CHECK(load_king(n, 7, 7.0, 4096, &s));
    orr_king_profile p;
    orr_error err;
    CHECK(orr_king_solve(7.0, &p, &err) == ORR_OK);
    double *r = malloc((size_t)n * sizeof *r);
    double rmax = 0.0;
    for (long long i = 0; i < n; i++) {
        r[i] = sqrt(s.x[i] * s.x[i] + s.y[i] * s.y[i] + s.z[i] * s.z[i]);
        rmax = fmax(rmax, r[i]);
        CHECK_NEAR(r[i], s.r[i], 1e-4 * (1.0 + r[i]));
    }
    qsort(r, (size_t)n, sizeof *r, cmp_double);
    double d = 0.0;
    for (long long i = 0; i < n; i++) {
        double f = orr_king_mass_fraction(&p, r[i]);
        d = fmax(d, fmax(fabs(f - (double)i / n), fabs(f - (double)(i + 1) / n)));
    }
    CHECK(d < 1.95 / sqrt((double)n));
    double rh = 0.5 * (r[n / 2 - 1] + r[n / 2]);
    CHECK_NEAR(rh / orr_king_radius_of_mass(&p, 0.5), 1.0, 0.03);
    CHECK(rmax <= p.rt * 1.000001);
    CHECK(rmax > 0.5 * p.rt); /* the outskirts are populated */
    /* Equal masses adding up to the total. */
    double mt = 0.0;
    for (long long i = 0; i < n; i++)
        mt += s.m[i];
    CHECK_NEAR(mt / 5e5, 1.0, 1e-5);
    free(r);
    orr_king_free(&p);
    stars_free(&s);
}

/* Virial equilibrium: 2T / |U| = 1 with U from a direct pair sum (in
 * pc (km/s)^2 / Msun units, G = 4.30091e-3), independent of the ODE. With
 * N = 3000 the sampling noise is a few percent. Every speed is below the
 * local escape speed sigma sqrt(2 W(r)). */
static void test_virial_and_escape(void)
{
    const long long n = 3000;
    stars s;
    CHECK(load_king(n, 3, 6.0, 1000, &s));
    double kin = 0.0, pot = 0.0;
    for (long long i = 0; i < n; i++) {
        kin += 0.5 * s.m[i] * (s.vx[i] * s.vx[i] + s.vy[i] * s.vy[i] + s.vz[i] * s.vz[i]);
        for (long long j = i + 1; j < n; j++) {
            double dx = s.x[i] - s.x[j], dy = s.y[i] - s.y[j], dz = s.z[i] - s.z[j];
            pot -= ORR_KING_G * s.m[i] * s.m[j] / sqrt(dx * dx + dy * dy + dz * dz);
        }
    }
    CHECK_NEAR(2.0 * kin / fabs(pot), 1.0, 0.06);

    orr_king_profile p;
    orr_error err;
    CHECK(orr_king_solve(6.0, &p, &err) == ORR_OK);
    orr_king_params kp = {n, 3, 6.0, 1.0, 5e5};
    double sigma, rt;
    orr_king_scales(&kp, &p, &sigma, &rt);
    int below = 1;
    for (long long i = 0; i < n; i++) {
        double v2 = s.vx[i] * s.vx[i] + s.vy[i] * s.vy[i] + s.vz[i] * s.vz[i];
        below &= v2 <= 2.0 * sigma * sigma * orr_king_w_at(&p, s.r[i]) * 1.001 + 1e-6;
    }
    CHECK(below);
    /* sigma^2 = G M / (9 r0 mu_total): a few km/s for 5e5 Msun in 1 pc. */
    CHECK(sigma > 3.0 && sigma < 30.0);
    orr_king_free(&p);
    stars_free(&s);
}

/* Particle i depends on (seed, i) only: chunk sizes 7 and 5000 agree bit for
 * bit, another seed does not. */
static void test_determinism(void)
{
    stars a, b, c;
    CHECK(load_king(5000, 11, 5.0, 7, &a));
    CHECK(load_king(5000, 11, 5.0, 5000, &b));
    CHECK(load_king(5000, 12, 5.0, 5000, &c));
    int same = 1, differ = 0;
    for (size_t i = 0; i < a.n; i++) {
        same &= a.x[i] == b.x[i] && a.vz[i] == b.vz[i] && a.V[i] == b.V[i] && a.BV[i] == b.BV[i] &&
                a.id[i] == i + 1 && a.type[i] == b.type[i];
        differ += a.x[i] != c.x[i];
    }
    CHECK(same);
    CHECK(differ > 4990);
    stars_free(&a);
    stars_free(&b);
    stars_free(&c);
}

/* The CMD: phase fractions within 4 binomial sigma of the expected ones;
 * giants on their fiducial sequence; the HB at its level with M3's blue
 * fraction; main-sequence stars no brighter or bluer than the turnoff. */
static void test_cmd(void)
{
    const int n = 1000000;
    int count[ORR_GC_PHASES + 1] = {0}, hb_blue = 0, ms_bad = 0, hb_bad = 0;
    double rg_dev = 0.0;
    orr_rng r = orr_rng_seed(5, 0, 0);
    double total_frac = 0.0;
    for (int i = 0; i < n; i++) {
        orr_gc_star s = orr_gc_draw(&r);
        CHECK(s.phase >= 1 && s.phase <= ORR_GC_PHASES);
        count[s.phase]++;
        if (s.phase == ORR_GC_RED_GIANT)
            rg_dev += fabs(s.bv - orr_gc_fiducial_bv(s.phase, s.mv));
        if (s.phase == ORR_GC_HORIZONTAL_BRANCH) {
            hb_blue += s.bv < 0.18;
            hb_bad += s.mv < 0.4 || s.mv > 1.0 || s.bv < -0.15 || s.bv > 0.7;
        }
        if (s.phase == ORR_GC_MAIN_SEQUENCE)
            ms_bad += s.mv < 3.85 || s.bv < 0.35 || s.mv > 10.2;
    }
    for (int ph = 1; ph <= ORR_GC_PHASES; ph++) {
        double f = orr_gc_phase_fraction((orr_gc_phase)ph), sd = sqrt(f * (1 - f) / n);
        CHECK_NEAR((double)count[ph] / n, f, 4.0 * sd);
        total_frac += f;
    }
    CHECK_NEAR(total_frac, 1.0, 1e-12);
    CHECK_NEAR(rg_dev / count[ORR_GC_RED_GIANT], 0.015 * sqrt(2.0 / 3.14159265358979323846), 0.004);
    CHECK_NEAR((double)hb_blue / count[ORR_GC_HORIZONTAL_BRANCH], 0.33, 0.05);
    CHECK(hb_bad == 0);
    CHECK(ms_bad == 0);
    /* Giants: the red giant branch is redder than the turnoff and its tip
     * is the brightest part of the diagram. */
    CHECK(orr_gc_fiducial_bv(ORR_GC_RED_GIANT, -2.5) > 1.3);
    CHECK(orr_gc_fiducial_bv(ORR_GC_MAIN_SEQUENCE, 4.0) < orr_gc_fiducial_bv(ORR_GC_RED_GIANT, 2.0));
    CHECK(isnan(orr_gc_fiducial_bv(ORR_GC_HORIZONTAL_BRANCH, 0.6)));
}

/* The ends of the W0 range solve and sample (W0 = 15: rt ~ 10^3.6 r0; W0 =
 * 0.5: stars sit where W is small, and near the tidal radius the speed
 * rejection's envelope is computed per star), in virial equilibrium to
 * within the noise (measured 0.991 and 0.979). */
static void test_w0_limits(void)
{
    const double w0s[] = {ORR_KING_W0_MIN, ORR_KING_W0_MAX};
    for (int t = 0; t < 2; t++) {
        stars s;
        CHECK(load_king(1500, 9, w0s[t], 512, &s));
        double kin = 0.0, pot = 0.0;
        for (size_t i = 0; i < s.n; i++) {
            kin += 0.5 * s.m[i] * (s.vx[i] * s.vx[i] + s.vy[i] * s.vy[i] + s.vz[i] * s.vz[i]);
            for (size_t j = i + 1; j < s.n; j++) {
                double dx = s.x[i] - s.x[j], dy = s.y[i] - s.y[j], dz = s.z[i] - s.z[j];
                pot -= ORR_KING_G * s.m[i] * s.m[j] / sqrt(dx * dx + dy * dy + dz * dz);
            }
        }
        CHECK_NEAR(2.0 * kin / fabs(pot), 1.0, 0.06);
        stars_free(&s);
    }
}

static void test_bad_input(void)
{
    orr_error err;
    orr_source *src = NULL;
    orr_king_params p = {1000, 1, 20.0, 1.0, 5e5};
    CHECK(orr_king_source_open(&p, 100, &src, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "w0 = 20");
    p.w0 = 6;
    p.core_radius = -1;
    CHECK(orr_king_source_open(&p, 100, &src, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "core radius");
    p.core_radius = 1;
    p.mass = NAN;
    CHECK(orr_king_source_open(&p, 100, &src, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "mass");
    p.mass = 1e5;
    p.particles = 5;
    CHECK(orr_king_source_open(&p, 100, &src, &err) == ORR_ERR_USAGE);
    CHECK(src == NULL);
    orr_king_profile prof;
    CHECK(orr_king_solve(0.1, &prof, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "W0 = 0.1");
}

/* Scene keys: king's own keys go with input.model.name: king only. */
static void test_scene_keys(void)
{
    static orr_scene scene;
    orr_error err;
    const char *ok = "input: {model: {name: king, w0: 8, core_radius: 0.5, mass: 1e6, particles: 1000}}\n"
                     "camera: {projection: perspective, position: [0, 0, 30], look_at: [0, 0, 0], dim: true}\n";
    orr_scene_free(&scene);
    CHECK(orr_scene_load_string(&scene, ok, "ok.yaml", "/", NULL, 0, &err) == ORR_OK);
    CHECK(scene.input.model.w0 == 8 && scene.input.model.core_radius == 0.5 && scene.input.model.mass == 1e6);
    CHECK(scene.camera.dim == 1);
    const char *sep = "input: {model: {name: king, separation: 100}}\n";
    orr_scene_free(&scene);
    CHECK(orr_scene_load_string(&scene, sep, "sep.yaml", "/", NULL, 0, &err) != ORR_OK);
    CHECK_CONTAINS(err.msg, "input.model.separation");
    const char *w0 = "input: {model: {name: mw-m31, w0: 5}}\n";
    orr_scene_free(&scene);
    CHECK(orr_scene_load_string(&scene, w0, "w0.yaml", "/", NULL, 0, &err) != ORR_OK);
    CHECK_CONTAINS(err.msg, "input.model.w0");
    const char *big = "input: {model: {name: king, w0: 40}}\n";
    orr_scene_free(&scene);
    CHECK(orr_scene_load_string(&scene, big, "big.yaml", "/", NULL, 0, &err) != ORR_OK);
    CHECK_CONTAINS(err.msg, "input.model.w0");
    const char *near = "input: {model: {name: king}}\ncamera: {dim_near: 0.1}\n";
    orr_scene_free(&scene);
    CHECK(orr_scene_load_string(&scene, near, "near.yaml", "/", NULL, 0, &err) != ORR_OK);
    CHECK_CONTAINS(err.msg, "camera.dim_near");
}

int main(void)
{
    RUN(test_density_formula);
    RUN(test_concentration);
    RUN(test_mass_profile);
    RUN(test_virial_and_escape);
    RUN(test_determinism);
    RUN(test_w0_limits);
    RUN(test_cmd);
    RUN(test_bad_input);
    RUN(test_scene_keys);
    return check_summary();
}
