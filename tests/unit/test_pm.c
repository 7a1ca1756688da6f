/* The particle-mesh code (source/models/pm.h) against theory: large-scale modes of
 * the density grow as linear theory's D(a)², with D from the test's own
 * integration of the growth equation; the density field ends far from
 * Gaussian; momentum and mass are conserved; the result is the same bit for
 * bit on 1 and 3 threads; bad parameters are named. */
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "source/models/pm.h"
#include "source/models/zeldovich.h"

#define PI 3.14159265358979323846

/* The linear growing mode, independently of the library's Heath integral:
 * the growth equation as two first-order ones in a, y = a³ E dD/da:
 *     dD/da = y / (a³ E),   dy/da = (3/2) Ω_m D / (a² E),
 * by fourth-order Runge-Kutta from a = 1e-3 in matter domination (D = a,
 * dD/da = 1). Unnormalised. */
static double growth_ode(const orr_cosmology *c, double a_end)
{
    const int steps = 20000;
    double a = 1e-3, h = (a_end - a) / steps;
    double d = a, y = a * a * a * orr_hubble_e(c, a);
#define DD(A, Y) ((Y) / ((A) * (A) * (A) * orr_hubble_e(c, (A))))
#define DY(A, D) (1.5 * c->omega_m * (D) / ((A) * (A) * orr_hubble_e(c, (A))))
    for (int i = 0; i < steps; i++) {
        double k1d = DD(a, y), k1y = DY(a, d);
        double k2d = DD(a + h / 2, y + h / 2 * k1y), k2y = DY(a + h / 2, d + h / 2 * k1d);
        double k3d = DD(a + h / 2, y + h / 2 * k2y), k3y = DY(a + h / 2, d + h / 2 * k2d);
        double k4d = DD(a + h, y + h * k3y), k4y = DY(a + h, d + h * k3d);
        d += h / 6 * (k1d + 2 * k2d + 2 * k3d + k4d);
        y += h / 6 * (k1y + 2 * k2y + 2 * k3y + k4y);
        a += h;
    }
#undef DD
#undef DY
    return d;
}

static orr_zeldovich start_box(int grid, double box, double z_start, uint64_t seed)
{
    orr_zeldovich_params p = {
        .cosmo = orr_cosmology_default(), .grid = grid, .box = box, .redshift = z_start, .seed = seed};
    orr_zeldovich z;
    orr_error err = {0};
    if (orr_zeldovich_generate(&p, &z, &err) != ORR_OK) {
        fprintf(stderr, "generate: %s\n", err.msg);
        exit(1);
    }
    return z;
}

/* |δ_k|² summed over the modes of each shell |n| in [s, s+1) (n the integer
 * wave vector, k = 2π n / box), by direct summation over the particles:
 * δ_k = N⁻¹ Σ_j exp(−i k·x_j), no mesh involved. Half of k-space (n and −n
 * give the same |δ_k|). */
static void shell_power(const orr_zeldovich *z, int shells, double *power)
{
    memset(power, 0, (size_t)shells * sizeof *power);
    double kf = 2 * PI / z->box;
    for (int nx = 0; nx < shells; nx++)
        for (int ny = -shells; ny < shells; ny++)
            for (int nz = -shells; nz < shells; nz++) {
                int n2 = nx * nx + ny * ny + nz * nz;
                int upper = nx > 0 || (nx == 0 && (ny > 0 || (ny == 0 && nz > 0)));
                int s = (int)sqrt((double)n2);
                if (!upper || s >= shells)
                    continue;
                double re = 0, im = 0;
                for (int64_t j = 0; j < z->n; j++) {
                    const float *x = z->pos + 3 * j;
                    double phase = kf * (nx * (double)x[0] + ny * (double)x[1] + nz * (double)x[2]);
                    re += cos(phase);
                    im -= sin(phase);
                }
                power[s] += (re * re + im * im) / ((double)z->n * (double)z->n);
            }
}

/* A 500 Mpc/h box of 32³ from z = 24 to 0: every shell below k = 0.05 h/Mpc
 * grows by [D(1) / D(a_start)]² within 5 % (the same modes at both ends, so
 * cosmic variance cancels). Measured 0.977, 0.967, 0.990 for the three
 * shells, the same with 40 steps; evolved only to z = 2, 0.993, 0.991,
 * 1.003: the few per cent at z = 0 are the non-linear damping of large
 * modes by the bulk flows, not the stepping. A force off by a factor a
 * misses by orders of magnitude; one 10 % too strong makes D grow as
 * a^1.06 rather than a in matter domination, 40 % more in D² over these
 * 20-fold growth. */
static void test_linear_growth(void)
{
    orr_zeldovich z = start_box(32, 500, 24, 7);
    const int shells = 4; /* |n| < 4: k < 0.050 h/Mpc */
    double before[4], after[4];
    shell_power(&z, shells, before);
    double a0 = z.a, mass = z.particle_mass;
    double expect = pow(growth_ode(&z.cosmo, 1) / growth_ode(&z.cosmo, a0), 2);
    /* (The library's D from Heath's integral agrees.) */
    CHECK_NEAR(expect, pow(1 / orr_growth_factor(&z.cosmo, a0), 2), 1e-4 * expect);
    orr_pm_params p = {.a_end = 1, .steps = 10, .mesh = 64};
    orr_pm_report rep;
    orr_error err = {0};
    CHECK(orr_pm_evolve(&z, &p, &rep, &err) == ORR_OK);
    shell_power(&z, shells, after);
    for (int s = 1; s < shells; s++) {
        double ratio = after[s] / before[s] / expect;
        printf("shell |n| in [%d, %d), k < %.3f h/Mpc: P(z=0) / P(z=24) / [D(1)/D(a0)]^2 = %.4f\n", s, s + 1,
               2 * PI / z.box * (s + 1), ratio);
        CHECK_NEAR(ratio, 1.0, 0.05);
    }
    /* Mass: the same particles, each of the same mass, all inside the box;
     * the mesh holds N to float rounding. Momentum: Σ u stays ~0. */
    CHECK(z.n == 32 * 32 * 32);
    CHECK(z.particle_mass == mass);
    CHECK(rep.mesh_mass < 1e-5);
    CHECK(rep.momentum < 1e-5);
    double sum[3] = {0}, norm = 0;
    int inside = 1;
    for (int64_t i = 0; i < z.n; i++) {
        double u2 = 0;
        for (int d = 0; d < 3; d++) {
            sum[d] += z.vel[3 * i + d];
            u2 += (double)z.vel[3 * i + d] * z.vel[3 * i + d];
            inside &= z.pos[3 * i + d] >= 0 && z.pos[3 * i + d] < z.box;
        }
        norm += sqrt(u2);
    }
    CHECK(inside);
    CHECK(sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]) < 1e-5 * norm);
    CHECK_NEAR(z.a, 1.0, 1e-12);
    CHECK_NEAR(z.redshift, 0.0, 1e-12);
    orr_zeldovich_free(&z);
}

/* The skewness of the CIC density contrast of the particles on an m³ grid
 * (the test's own deposit, in double). */
static double density_skewness(const orr_zeldovich *z, int m)
{
    size_t cells = (size_t)m * m * m;
    double *rho = calloc(cells, sizeof *rho);
    double inv = m / z->box;
    for (int64_t j = 0; j < z->n; j++) {
        int lo[3];
        double t[3];
        for (int d = 0; d < 3; d++) {
            double u = z->pos[3 * j + d] * inv;
            lo[d] = (int)floor(u);
            t[d] = u - lo[d];
        }
        for (int c = 0; c < 8; c++) {
            double w = 1;
            size_t idx = 0;
            for (int d = 0; d < 3; d++) {
                int up = (c >> d) & 1;
                w *= up ? t[d] : 1 - t[d];
                idx = idx * m + (size_t)((lo[d] + up) % m);
            }
            rho[idx] += w;
        }
    }
    double mean = (double)z->n / (double)cells, m2 = 0, m3 = 0;
    for (size_t i = 0; i < cells; i++) {
        double d = rho[i] / mean - 1;
        m2 += d * d;
        m3 += d * d * d;
    }
    free(rho);
    m2 /= (double)cells;
    m3 /= (double)cells;
    return m3 / pow(m2, 1.5);
}

/* A 100 Mpc/h box of 32³: the nearly Gaussian start becomes a skewed field
 * of voids and halos. A Gaussian field has skewness 0; second-order
 * perturbation theory gives S3 σ with S3 = 34/7 (Peebles 1980, §18; Bernardeau
 * et al. 2002): about 0.25 at the start for σ ≈ 0.05. */
static void test_non_gaussian(void)
{
    orr_zeldovich z = start_box(32, 100, 24, 5);
    double start = density_skewness(&z, 32);
    orr_pm_params p = {.a_end = 1, .steps = 20, .mesh = 64};
    orr_pm_report rep;
    orr_error err = {0};
    CHECK(orr_pm_evolve(&z, &p, &rep, &err) == ORR_OK);
    double end = density_skewness(&z, 32);
    printf("skewness of the CIC density contrast on 32³ cells: %.3f at z = 24, %.3f at z = 0\n", start, end);
    CHECK(fabs(start) < 0.5);
    CHECK(end > 3);
    orr_zeldovich_free(&z);
}

/* The same particles, bit for bit, on 1 and 3 threads. */
static void test_thread_count(void)
{
    orr_zeldovich one = start_box(16, 100, 24, 2), three = start_box(16, 100, 24, 2);
    orr_pm_params p = {.a_end = 1, .steps = 6, .mesh = 32};
    orr_pm_report rep;
    orr_error err = {0};
    int threads = omp_get_max_threads();
    omp_set_num_threads(1);
    CHECK(orr_pm_evolve(&one, &p, &rep, &err) == ORR_OK);
    omp_set_num_threads(3);
    CHECK(orr_pm_evolve(&three, &p, &rep, &err) == ORR_OK);
    omp_set_num_threads(threads);
    size_t bytes = (size_t)one.n * 3 * sizeof(float);
    CHECK(memcmp(one.pos, three.pos, bytes) == 0);
    CHECK(memcmp(one.vel, three.vel, bytes) == 0);
    orr_zeldovich_free(&one);
    orr_zeldovich_free(&three);
}

static void test_bad_parameters(void)
{
    orr_zeldovich z = start_box(4, 100, 9, 1);
    orr_pm_report rep;
    orr_error err = {0};
    orr_pm_params p = {.a_end = 1, .steps = 2, .mesh = 7};
    CHECK(orr_pm_evolve(&z, &p, &rep, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "mesh 7");
    p = (orr_pm_params){.a_end = 1, .steps = 0, .mesh = 8};
    CHECK(orr_pm_evolve(&z, &p, &rep, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "steps 0");
    p = (orr_pm_params){.a_end = 0.05, .steps = 2, .mesh = 8};
    CHECK(orr_pm_evolve(&z, &p, &rep, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "later than the start");
    CHECK_NEAR(z.a, 0.1, 1e-12); /* untouched */
    orr_zeldovich_free(&z);
}

int main(void)
{
    RUN(test_linear_growth);
    RUN(test_non_gaussian);
    RUN(test_thread_count);
    RUN(test_bad_parameters);
    return check_summary();
}
