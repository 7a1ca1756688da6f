/* The cosmology (growth factor, transfer function, σ8 normalisation) and the
 * Zel'dovich initial conditions: the power spectrum measured from the
 * particles' displacements against the input P(k), zero mean displacement,
 * velocities proportional to displacements, determinism, and the HDF5
 * snapshot read back by orrery's own reader. */
#include <fftw3.h>
#include <math.h>
#include <stdlib.h>
#include <signal.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "check.h"
#include "source/models/zeldovich.h"
#include "source/source.h"
#include "source/writers/zeldovich_hdf5.h"
#include "tmpdir.h"

#define PI 3.14159265358979323846

static void test_growth_einstein_de_sitter(void)
{
    /* Ω_m = 1: D(a) = a and f = 1 exactly. */
    orr_cosmology eds = {.omega_m = 1, .omega_lambda = 0, .omega_b = 0.05, .h = 0.7, .sigma8 = 0.8, .n_s = 1};
    for (double a = 0.05; a <= 1.0001; a += 0.19) {
        CHECK_NEAR(orr_growth_factor(&eds, a), a, 1e-6);
        CHECK_NEAR(orr_growth_rate(&eds, a), 1.0, 1e-5);
    }
}

static void test_growth_lcdm(void)
{
    orr_cosmology c = orr_cosmology_default();
    /* The growth rate is close to Ω_m(a)^0.55 (Linder 2005, to ~0.5% for
     * ΛCDM); deep in matter domination D ∝ a. */
    for (double a = 0.1; a <= 1.0001; a += 0.3) {
        double e = orr_hubble_e(&c, a);
        double om_a = c.omega_m / (a * a * a * e * e);
        CHECK_NEAR(orr_growth_rate(&c, a), pow(om_a, 0.55), 0.005);
    }
    CHECK_NEAR(orr_growth_factor(&c, 1.0), 1.0, 1e-12);
    CHECK_NEAR(orr_growth_factor(&c, 0.002) / orr_growth_factor(&c, 0.001), 2.0, 1e-3);
    /* Λ slows growth today: D(a=0.5) lies above 0.5 (the EdS value). Carroll,
     * Press & Turner (1992) fit: g(a) = D/a = 2.5 Ω_m(a) / (Ω_m^(4/7) − Ω_Λ +
     * (1 + Ω_m/2)(1 + Ω_Λ/70)), normalised by its value today, good to ~1%. */
    double a = 0.5, e = orr_hubble_e(&c, a);
    double om_a = c.omega_m / (a * a * a * e * e), ol_a = c.omega_lambda / (e * e);
    double g_a = 2.5 * om_a / (pow(om_a, 4.0 / 7) - ol_a + (1 + om_a / 2) * (1 + ol_a / 70));
    double g_1 = 2.5 * c.omega_m /
                 (pow(c.omega_m, 4.0 / 7) - c.omega_lambda + (1 + c.omega_m / 2) * (1 + c.omega_lambda / 70));
    CHECK_NEAR(orr_growth_factor(&c, a), a * g_a / g_1, 0.01 * a);
}

static void test_transfer_function(void)
{
    orr_cosmology c = orr_cosmology_default();
    CHECK_NEAR(orr_transfer_eh98(&c, 1e-5), 1.0, 1e-3);
    double prev = 1.0;
    for (double k = 1e-3; k < 100; k *= 1.5) {
        double t = orr_transfer_eh98(&c, k);
        CHECK(t > 0 && t < prev);
        prev = t;
    }
    /* Without baryons the shape depends on k / (Ω_m h) alone (EH98 eq. 28
     * with Γ_eff = Ω_m h). */
    orr_cosmology a = {.omega_m = 0.3, .omega_lambda = 0.7, .omega_b = 0, .h = 0.5, .sigma8 = 0.8, .n_s = 1};
    orr_cosmology b = a;
    b.h = 1.0;
    for (double k = 0.01; k < 10; k *= 3)
        CHECK_NEAR(orr_transfer_eh98(&a, k), orr_transfer_eh98(&b, 2 * k), 1e-12);
}

static void test_sigma8_normalisation(void)
{
    orr_cosmology c = orr_cosmology_default();
    orr_power p;
    orr_error err = {0};
    CHECK(orr_power_init(&p, &c, &err) == ORR_OK);
    CHECK_NEAR(orr_power_sigma_r(&p, 8.0), c.sigma8, 1e-9);
    /* An independent integral: σ²(8) by the trapezoid rule in k with a
     * different grid must agree. */
    double sum = 0, dk = 1e-4;
    for (double k = dk; k < 20; k += dk) {
        double x = 8 * k;
        double w = 3 * (sin(x) - x * cos(x)) / (x * x * x);
        sum += k * k * orr_power_at(&p, k) * w * w * dk / (2 * PI * PI);
    }
    CHECK_NEAR(sqrt(sum), c.sigma8, 0.002);
    /* Bigger spheres, smaller fluctuations. */
    CHECK(orr_power_sigma_r(&p, 16.0) < c.sigma8);
    /* The spectrum turns over: rises as k^n_s at small k, falls at large k. */
    CHECK_NEAR(orr_power_at(&p, 2e-5) / orr_power_at(&p, 1e-5), pow(2.0, c.n_s), 0.01);
    CHECK(orr_power_at(&p, 1.0) < orr_power_at(&p, 0.1));
}

static orr_zeldovich_params small_box(int grid, uint64_t seed)
{
    return (orr_zeldovich_params){.cosmo = orr_cosmology_default(), .grid = grid, .box = 200.0,
                                  .redshift = 10, .seed = seed};
}

/* Particle i's displacement x − q, wrapped to the nearest image. */
static void displacement(const orr_zeldovich *z, int64_t i, double d[3])
{
    double q[3];
    orr_zeldovich_lagrangian(z, i, q);
    for (int k = 0; k < 3; k++) {
        double v = z->pos[3 * i + k] - q[k];
        d[k] = v - z->box * floor(v / z->box + 0.5);
    }
}

static void test_counts_mean_and_velocities(void)
{
    orr_zeldovich_params p = small_box(16, 7);
    orr_zeldovich z;
    orr_error err = {0};
    CHECK(orr_zeldovich_generate(&p, &z, &err) == ORR_OK);
    CHECK(z.n == 16 * 16 * 16);
    double a = 1.0 / 11;
    CHECK_NEAR(z.a, a, 1e-15);
    /* Gadget velocities: sqrt(a) f H(a) per unit displacement. */
    double h_a = 100 * orr_hubble_e(&p.cosmo, a);
    CHECK_NEAR(z.vel_factor, sqrt(a) * orr_growth_rate(&p.cosmo, a) * h_a, 1e-9);
    /* Particle mass: Ω_m ρ_crit (L/N)³ with ρ_crit = 2.775e11 h² Msun/Mpc³. */
    CHECK_NEAR(z.particle_mass, 0.315 * 27.7536627 * pow(200.0 / 16, 3), 1e-6);
    double sum[3] = {0}, worst = 0, rms = 0, vd = 0;
    int inside = 1;
    for (int64_t i = 0; i < z.n; i++) {
        double d[3];
        displacement(&z, i, d);
        for (int k = 0; k < 3; k++) {
            sum[k] += d[k];
            rms += d[k] * d[k];
            /* positions are floats of up to 200 Mpc/h: d is known to ~2e-5 */
            double miss = fabs(z.vel[3 * i + k] / z.vel_factor - d[k]);
            worst = miss > worst ? miss : worst;
            vd += z.vel[3 * i + k] * d[k];
            inside &= z.pos[3 * i + k] >= 0 && z.pos[3 * i + k] < z.box;
        }
    }
    rms = sqrt(rms / (double)z.n);
    CHECK(inside);
    CHECK(rms > 0.01 && rms < z.box / 16); /* a linear field: well under a cell at z = 10 */
    CHECK_NEAR(rms, z.rms_displacement, 1e-3 * rms);
    for (int k = 0; k < 3; k++) /* the k = 0 mode is zero: no net displacement */
        CHECK_NEAR(sum[k] / (double)z.n, 0.0, 1e-5 * rms);
    CHECK(worst < 3e-5);
    CHECK_NEAR(vd / (rms * rms * (double)z.n), z.vel_factor, 1e-5 * z.vel_factor); /* least-squares slope */
    orr_zeldovich_free(&z);
}

static void test_deterministic(void)
{
    orr_zeldovich a, b, c;
    orr_error err = {0};
    orr_zeldovich_params p = small_box(8, 42);
    CHECK(orr_zeldovich_generate(&p, &a, &err) == ORR_OK);
    CHECK(orr_zeldovich_generate(&p, &b, &err) == ORR_OK);
    p.seed = 43;
    CHECK(orr_zeldovich_generate(&p, &c, &err) == ORR_OK);
    size_t bytes = (size_t)a.n * 3 * sizeof(float);
    CHECK(memcmp(a.pos, b.pos, bytes) == 0 && memcmp(a.vel, b.vel, bytes) == 0);
    CHECK(memcmp(a.pos, c.pos, bytes) != 0);
    orr_zeldovich_free(&a);
    orr_zeldovich_free(&b);
    orr_zeldovich_free(&c);
}

/* The power spectrum of δ = −∇·ψ measured from the particles (the test's
 * own FFT of their displacements), in shells of |k|, against the input
 * P(k) D(a)². Each independent mode's |δ_k|² / (P(k)/V) is exponentially
 * distributed with mean 1, so a shell of M independent modes has a mean
 * ratio of 1 ± 1/sqrt(M) (cosmic variance). */
static void check_power_spectrum(double truncate)
{
    enum { N = 32 };
    orr_zeldovich_params p = small_box(N, 3);
    p.truncate = truncate;
    orr_zeldovich z;
    orr_error err = {0};
    orr_power power;
    CHECK(orr_zeldovich_generate(&p, &z, &err) == ORR_OK);
    CHECK(orr_power_init(&power, &p.cosmo, &err) == ORR_OK);
    const int nh = N / 2 + 1;
    size_t ncell = (size_t)N * N * N, nmode = (size_t)N * N * nh;
    float *grid = fftwf_malloc(ncell * sizeof(float));
    fftwf_complex *modes[3];
    for (int k = 0; k < 3; k++) {
        modes[k] = fftwf_malloc(nmode * sizeof(fftwf_complex));
        fftwf_plan plan = fftwf_plan_dft_r2c_3d(N, N, N, grid, modes[k], FFTW_ESTIMATE);
        for (int64_t i = 0; i < z.n; i++) {
            double d[3];
            displacement(&z, i, d);
            grid[i] = (float)d[k];
        }
        fftwf_execute(plan);
        fftwf_destroy_plan(plan);
    }
    double kf = 2 * PI / p.box, volume = p.box * p.box * p.box;
    double d2 = z.growth * z.growth;
    enum { NBIN = N / 2 };
    double ratio_sum[NBIN] = {0};
    int count[NBIN] = {0};
    for (int ix = 0; ix < N; ix++)
        for (int iy = 0; iy < N; iy++)
            for (int iz = 1; iz < N / 2; iz++) { /* kz > 0: each mode independent of the others */
                int kx = ix <= N / 2 ? ix : ix - N, ky = iy <= N / 2 ? iy : iy - N;
                if (kx == N / 2 || ky == N / 2)
                    continue; /* Nyquist planes are zeroed by the generator */
                size_t c = ((size_t)ix * N + iy) * nh + iz;
                /* δ_k = −i k·ψ_k, with ψ_k = FFT / N³ */
                double re = 0, im = 0;
                int kv[3] = {kx, ky, iz};
                for (int a = 0; a < 3; a++) {
                    re += kf * kv[a] * modes[a][c][1];
                    im -= kf * kv[a] * modes[a][c][0];
                }
                re /= (double)ncell;
                im /= (double)ncell;
                double kmag = sqrt((double)kx * kx + (double)ky * ky + (double)iz * iz);
                int bin = (int)kmag;
                if (bin >= NBIN)
                    continue;
                double k = kf * kmag;
                double expected = orr_power_at(&power, k) * d2 / volume;
                if (truncate > 0)
                    expected *= exp(-k * k / (truncate * truncate));
                ratio_sum[bin] += (re * re + im * im) / expected;
                count[bin]++;
            }
    int bins_checked = 0;
    double chi2 = 0;
    for (int b = 1; b < NBIN; b++) {
        if (count[b] < 20)
            continue;
        double mean = ratio_sum[b] / count[b], sigma = 1 / sqrt((double)count[b]);
        CHECK_NEAR(mean, 1.0, 4.5 * sigma);
        chi2 += (mean - 1) * (mean - 1) / (sigma * sigma);
        bins_checked++;
    }
    CHECK(bins_checked >= 12);
    /* Over all bins together: chi² of bins_checked degrees of freedom stays
     * below its 99.9% point (about 2.6 × dof for ~14). */
    CHECK(chi2 < 2.6 * bins_checked + 10);
    fftwf_free(grid);
    for (int k = 0; k < 3; k++)
        fftwf_free(modes[k]);
    orr_zeldovich_free(&z);
}

static void test_power_spectrum(void)
{
    check_power_spectrum(0);
}

/* Truncated: P(k) exp(−k²/k_t²), here with k_t = 0.3 h/Mpc, about a third
 * of the grid's Nyquist wavenumber (0.5 h/Mpc). */
static void test_power_spectrum_truncated(void)
{
    check_power_spectrum(0.3);
}

static void test_snapshot_round_trip(void)
{
    orr_zeldovich_params p = small_box(8, 5);
    p.redshift = 0;
    orr_zeldovich z;
    orr_error err = {0};
    CHECK(orr_zeldovich_generate(&p, &z, &err) == ORR_OK);
    char path[512];
    snprintf(path, sizeof path, "%s/box.hdf5", tmpdir);
    CHECK(orr_zeldovich_write_hdf5(&z, path, &err) == ORR_OK);
    orr_source_options opt = {.format = "auto", .chunk_size = 100};
    orr_source *src = NULL;
    CHECK(orr_source_open_file(path, &opt, &src, &err) == ORR_OK);
    if (!src) {
        orr_zeldovich_free(&z);
        return;
    }
    CHECK(src->info.count == 512);
    CHECK_NEAR(src->info.time, 1.0, 1e-12);
    int has_box = 0;
    for (int i = 0; i < src->info.nheader; i++)
        has_box |= strcmp(src->info.header[i].key, "BoxSize") == 0 && atof(src->info.header[i].value) == 200.0;
    CHECK(has_box);
    const orr_chunk *c;
    int64_t seen = 0, same = 1;
    while (orr_source_next(src, &c, &err) == ORR_OK && c->n > 0)
        for (size_t j = 0; j < c->n; j++) {
            int64_t i = (int64_t)c->id[j] - 1;
            same &= i >= 0 && i < z.n && c->x[j] == z.pos[3 * i] && c->y[j] == z.pos[3 * i + 1] &&
                    c->z[j] == z.pos[3 * i + 2] && c->type[j] == 1 && fabsf(c->mass[j] - (float)z.particle_mass) <
                    1e-6f * (float)z.particle_mass;
            seen++;
        }
    CHECK(seen == 512 && same);
    orr_source_close(src);
    orr_zeldovich_free(&z);
}

/* A write that fails says why, as the system does: here a file-size limit
 * (EFBIG) stands in for a full disk. It runs in a child process that ends
 * with _exit: libhdf5 1.10 crashes in its atexit clean-up after a file
 * whose close failed (H5F__close_cb), which is libhdf5's to fix. */
static void test_write_failure_says_why(void)
{
    orr_zeldovich_params p = small_box(8, 5);
    orr_zeldovich z;
    orr_error err = {0};
    CHECK(orr_zeldovich_generate(&p, &z, &err) == ORR_OK);
    char path[512];
    snprintf(path, sizeof path, "%s/too_big.hdf5", tmpdir);
    int fds[2];
    CHECK(pipe(fds) == 0);
    fflush(NULL);
    pid_t pid = fork();
    if (pid == 0) {
        close(fds[0]);
        signal(SIGXFSZ, SIG_IGN);
        struct rlimit small = {4096, 4096};
        setrlimit(RLIMIT_FSIZE, &small);
        orr_status st = orr_zeldovich_write_hdf5(&z, path, &err);
        const char *said = st == ORR_ERR_IO ? err.msg : "(no I/O error)";
        ssize_t w = write(fds[1], said, strlen(said));
        _exit(w > 0 ? 0 : 1);
    }
    close(fds[1]);
    char msg[sizeof err.msg] = "";
    ssize_t got = pid > 0 ? read(fds[0], msg, sizeof msg - 1) : -1;
    close(fds[0]);
    int status = 0;
    if (pid > 0)
        waitpid(pid, &status, 0);
    CHECK(got > 0);
    CHECK_CONTAINS(msg, "too_big.hdf5: could not write the HDF5 snapshot: File too large");
    CHECK(access(path, F_OK) != 0);
    orr_zeldovich_free(&z);
}

static void test_bad_parameters(void)
{
    orr_zeldovich z;
    orr_error err = {0};
    orr_zeldovich_params p = small_box(7, 1);
    CHECK(orr_zeldovich_generate(&p, &z, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "grid 7");
    p = small_box(8, 1);
    p.box = -1;
    CHECK(orr_zeldovich_generate(&p, &z, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "box -1");
    p = small_box(8, 1);
    p.truncate = -0.5;
    CHECK(orr_zeldovich_generate(&p, &z, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "truncate -0.5");
    p = small_box(8, 1);
    p.cosmo.omega_m = 0;
    CHECK(orr_zeldovich_generate(&p, &z, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "omega_m 0");
    p = small_box(8, 1);
    p.cosmo.omega_m = 0.1;
    p.cosmo.omega_lambda = 1.5; /* no big bang: H² < 0 in the past */
    CHECK(orr_zeldovich_generate(&p, &z, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "omega_lambda 1.5");
    orr_zeldovich_params ok = small_box(8, 1);
    CHECK(orr_zeldovich_generate(&ok, &z, &err) == ORR_OK);
    CHECK(orr_zeldovich_write_hdf5(&z, "/nonexistent-dir/x/box.hdf5", &err) != ORR_OK);
    CHECK_CONTAINS(err.msg, "/nonexistent-dir/x");
    orr_zeldovich_free(&z);
}

int main(void)
{
    make_tmpdir();
    RUN(test_growth_einstein_de_sitter);
    RUN(test_growth_lcdm);
    RUN(test_transfer_function);
    RUN(test_sigma8_normalisation);
    RUN(test_counts_mean_and_velocities);
    RUN(test_deterministic);
    RUN(test_power_spectrum);
    RUN(test_power_spectrum_truncated);
    RUN(test_snapshot_round_trip);
    RUN(test_write_failure_says_why);
    RUN(test_bad_parameters);
    remove_tmpdir();
    return check_summary();
}
