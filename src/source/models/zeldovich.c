/* Zel'dovich initial conditions (zeldovich.h, docs/dark-universe.md).
 *
 * Conventions. A field on the grid is δ(x) = Σ_k δ_k exp(i k·x) with
 * δ_k = N⁻³ Σ_x δ(x) exp(−i k·x), and the power spectrum is
 * P(k) = V ⟨|δ_k|²⟩ (V = box³). The displacement obeys the linearised
 * continuity equation δ = −∇·ψ, so ψ_k = i k δ_k / k² (the gradient of the
 * potential φ_k = −δ_k / k², up to sign: ψ = −∇φ).
 *
 * The field: unit white noise w(x), one standard normal deviate per cell
 * from a generator keyed by (seed, cell), so the field depends on the seed
 * and the grid only; its unnormalised FFT W_k has ⟨|W_k|²⟩ = N³, hence
 * δ_k = W_k sqrt(P(k) / V) / N^(3/2). Modes on a Nyquist plane (any
 * component of the wave vector at ±N/2) are zeroed: their gradient has no
 * sign, as is usual for initial conditions. */
#include "source/models/zeldovich.h"

#include <fftw3.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "source/models/rng.h"

#define PI 3.14159265358979323846
/* ρ_crit today = 3 H0² / (8 π G) = 27.7536627 × 1e10 h² Msun / Mpc³
 * (e.g. Gadget-2's constants: G = 43007.1 in its units). */
#define RHO_CRIT_1E10 27.7536627

typedef struct field {
    int n;
    size_t ncomplex; /* n * n * (n/2 + 1) */
    fftwf_complex *delta; /* δ_k */
    fftwf_complex *work;  /* one component of ψ_k, consumed by the c2r transform */
    float *real;          /* one component of ψ(x) */
    fftwf_plan forward, backward;
} field;

static void field_free(field *f)
{
    if (f->forward)
        fftwf_destroy_plan(f->forward);
    if (f->backward)
        fftwf_destroy_plan(f->backward);
    fftwf_free(f->delta);
    fftwf_free(f->work);
    fftwf_free(f->real);
    memset(f, 0, sizeof *f);
}

static orr_status field_alloc(field *f, int n, orr_error *err)
{
    memset(f, 0, sizeof *f);
    f->n = n;
    f->ncomplex = (size_t)n * (size_t)n * (size_t)(n / 2 + 1);
    size_t nreal = (size_t)n * (size_t)n * (size_t)n;
    f->delta = fftwf_malloc(f->ncomplex * sizeof(fftwf_complex));
    f->work = fftwf_malloc(f->ncomplex * sizeof(fftwf_complex));
    f->real = fftwf_malloc(nreal * sizeof(float));
    if (!f->delta || !f->work || !f->real) {
        field_free(f);
        return orr_fail(err, ORR_ERR_NOMEM, "initial conditions: out of memory for three FFT grids of %d³", n);
    }
    /* FFTW_ESTIMATE leaves the arrays alone while planning. */
    f->forward = fftwf_plan_dft_r2c_3d(n, n, n, f->real, f->delta, FFTW_ESTIMATE);
    f->backward = fftwf_plan_dft_c2r_3d(n, n, n, f->work, f->real, FFTW_ESTIMATE);
    if (!f->forward || !f->backward) {
        field_free(f);
        return orr_fail(err, ORR_ERR_INTERNAL, "initial conditions: FFTW could not plan a %d³ transform", n);
    }
    return ORR_OK;
}

/* Unit white noise, cell by cell, a pure function of (seed, cell). */
static void white_noise(field *f, uint64_t seed)
{
    size_t nreal = (size_t)f->n * (size_t)f->n * (size_t)f->n;
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < nreal; i++) {
        orr_rng r = orr_rng_seed(seed, i, 0x5A1D);
        double g0, g1;
        orr_rng_gauss2(&r, &g0, &g1);
        f->real[i] = (float)g0;
    }
}

/* The signed wave number of FFT index i on a grid of n. */
static int wave_index(int i, int n)
{
    return i <= n / 2 ? i : i - n;
}

/* δ_k from the white noise: scaled by sqrt(P(k) D² / V) / N^(3/2), and by
 * exp(−k²/(2 k_t²)) when truncated (k_t > 0). */
static void shape_field(field *f, const orr_power *power, double box, double growth, double truncate)
{
    int n = f->n, nh = n / 2 + 1;
    double kf = 2 * PI / box, volume = box * box * box;
    double norm = growth / sqrt(volume) / pow((double)n, 1.5);
    for (int ix = 0; ix < n; ix++)
        for (int iy = 0; iy < n; iy++)
            for (int iz = 0; iz < nh; iz++) {
                size_t c = ((size_t)ix * n + iy) * nh + iz;
                int kx = wave_index(ix, n), ky = wave_index(iy, n), kz = iz;
                double scale = 0;
                int nyquist = kx == n / 2 || ky == n / 2 || kz == n / 2;
                if (!nyquist && (kx || ky || kz)) {
                    double k = kf * sqrt((double)kx * kx + (double)ky * ky + (double)kz * kz);
                    scale = norm * sqrt(orr_power_at(power, k));
                    if (truncate > 0)
                        scale *= exp(-0.5 * k * k / (truncate * truncate));
                }
                f->delta[c][0] = (float)(f->delta[c][0] * scale);
                f->delta[c][1] = (float)(f->delta[c][1] * scale);
            }
}

/* Component `axis` of ψ_k = i k δ_k / k² into f->work. */
static void displacement_modes(field *f, int axis, double box)
{
    int n = f->n, nh = n / 2 + 1;
    double kf = 2 * PI / box;
    for (int ix = 0; ix < n; ix++)
        for (int iy = 0; iy < n; iy++)
            for (int iz = 0; iz < nh; iz++) {
                size_t c = ((size_t)ix * n + iy) * nh + iz;
                int kv[3] = {wave_index(ix, n), wave_index(iy, n), iz};
                double k2 = (double)kv[0] * kv[0] + (double)kv[1] * kv[1] + (double)kv[2] * kv[2];
                double g = k2 > 0 ? kv[axis] / (kf * k2) : 0; /* k_axis / k² in Mpc/h */
                /* i g (re + i im) = −g im + i g re */
                float re = f->delta[c][0], im = f->delta[c][1];
                f->work[c][0] = (float)(-g * im);
                f->work[c][1] = (float)(g * re);
            }
}

void orr_zeldovich_lagrangian(const orr_zeldovich *z, int64_t i, double q[3])
{
    int64_t n = z->grid;
    int64_t idx[3] = {i / (n * n), (i / n) % n, i % n};
    for (int d = 0; d < 3; d++)
        q[d] = ((double)idx[d] + 0.5) * z->box / (double)n;
}

/* Moves the particles along one axis by the displacement in f->real. */
static double displace_axis(orr_zeldovich *z, const field *f, int axis)
{
    double sum2 = 0;
    const double box = z->box, cell = z->box / z->grid;
#pragma omp parallel for schedule(static) reduction(+ : sum2)
    for (int64_t i = 0; i < z->n; i++) {
        int64_t n = z->grid;
        int64_t idx = axis == 0 ? i / (n * n) : axis == 1 ? (i / n) % n : i % n;
        double psi = f->real[i];
        double x = ((double)idx + 0.5) * cell + psi;
        x -= box * floor(x / box);
        if (x >= box) /* rounding of a tiny negative x */
            x = 0;
        z->pos[3 * i + axis] = (float)x;
        z->vel[3 * i + axis] = (float)(z->vel_factor * psi);
        sum2 += psi * psi;
    }
    return sum2;
}

static orr_status check_params(const orr_zeldovich_params *p, orr_error *err)
{
    if (p->grid < 2 || p->grid > ORR_ZELDOVICH_GRID_MAX || p->grid % 2)
        return orr_fail(err, ORR_ERR_USAGE, "grid %d: expected an even number from 2 to %d", p->grid,
                        ORR_ZELDOVICH_GRID_MAX);
    if (!(p->box > 0 && p->box < 1e6))
        return orr_fail(err, ORR_ERR_USAGE, "box %g: expected a side in Mpc/h above 0 (and below 1e6)", p->box);
    if (!(p->redshift >= 0 && p->redshift < 1e4))
        return orr_fail(err, ORR_ERR_USAGE, "redshift %g: expected a value from 0 to 1e4", p->redshift);
    if (!(p->truncate >= 0 && p->truncate < 1e6))
        return orr_fail(err, ORR_ERR_USAGE, "truncate %g: expected a wavenumber in h/Mpc >= 0 (0: none)",
                        p->truncate);
    return orr_cosmology_check(&p->cosmo, err);
}

static void describe(orr_zeldovich *z, const orr_zeldovich_params *p)
{
    const orr_cosmology *c = &p->cosmo;
    z->grid = p->grid;
    z->n = (int64_t)p->grid * p->grid * p->grid;
    z->box = p->box;
    z->redshift = p->redshift;
    z->a = 1.0 / (1.0 + p->redshift);
    z->cosmo = *c;
    z->growth = orr_growth_factor(c, z->a);
    z->rate = orr_growth_rate(c, z->a);
    z->hubble = 100.0 * orr_hubble_e(c, z->a);
    /* Gadget stores u = v_pec / sqrt(a) with v_pec = a dx/dt and
     * dx/dt = dD/dt ψ = f H D ψ: u = sqrt(a) f H × (D ψ). */
    z->vel_factor = sqrt(z->a) * z->rate * z->hubble;
    double cell = p->box / p->grid;
    z->particle_mass = RHO_CRIT_1E10 * c->omega_m * cell * cell * cell;
}

orr_status orr_zeldovich_generate(const orr_zeldovich_params *p, orr_zeldovich *z, orr_error *err)
{
    memset(z, 0, sizeof *z);
    orr_status st = check_params(p, err);
    orr_power power;
    if (!st)
        st = orr_power_init(&power, &p->cosmo, err);
    if (st)
        return orr_fail_prefix(err, "initial conditions: ");
    describe(z, p);
    z->pos = orr_malloc((size_t)z->n * 3 * sizeof(float), "initial-condition positions", err);
    z->vel = z->pos ? orr_malloc((size_t)z->n * 3 * sizeof(float), "initial-condition velocities", err) : NULL;
    field f;
    if (!z->vel || (st = field_alloc(&f, p->grid, err))) {
        orr_zeldovich_free(z);
        return st ? st : ORR_ERR_NOMEM;
    }
    white_noise(&f, p->seed);
    fftwf_execute(f.forward);
    shape_field(&f, &power, p->box, z->growth, p->truncate);
    double sum2 = 0;
    for (int axis = 0; axis < 3; axis++) {
        displacement_modes(&f, axis, p->box);
        fftwf_execute(f.backward);
        sum2 += displace_axis(z, &f, axis);
    }
    z->rms_displacement = sqrt(sum2 / (double)z->n);
    field_free(&f);
    return ORR_OK;
}

void orr_zeldovich_free(orr_zeldovich *z)
{
    free(z->pos);
    free(z->vel);
    z->pos = z->vel = NULL;
}
