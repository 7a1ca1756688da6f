/* The particle-mesh code (pm.h, docs/dark-universe.md "Particle mesh").
 *
 * Units: lengths in Mpc/h, time in 1/H0, so momenta p = a² dx/dt are in
 * units of 100 km/s; Gadget's u = v_pec / sqrt(a) with v_pec = p / a is
 * u = 100 p / a^1.5 km/s.
 *
 * One force evaluation: cloud-in-cell (CIC) deposit of the particles on an
 * M³ mesh; δ_k by a real-to-complex FFT; φ_k = −(3/2) Ω_m δ_k / (a k²); the
 * force −∇φ by the two-point central difference, −i sin(k_i Δ)/Δ φ_k in
 * Fourier space (Δ = box / M), one inverse FFT per axis; CIC interpolation
 * of each axis to the particles. Assigning and interpolating with the same
 * window with an odd difference kernel makes the pair forces
 * antisymmetric: the total momentum is conserved to rounding.
 *
 * Why not the spectral gradient i k, nor dividing by the CIC window W(k)²:
 * both were tried on a lattice of 32³ particles displaced by one plane wave
 * (where the exact force is the fluid one, sheets attracting as sheets).
 * On a 64³ mesh the force of the fundamental mode came out 7 % too strong
 * with i k, 2 % with the two-point difference divided by W², 0.2 % with
 * the two-point difference alone; that of the fourth harmonic 30 %, 26 %
 * and 3 %. The spectral gradient of the kinked potential of a sheet rings
 * (Gibbs), and deconvolution amplifies the lattice's own modes near the
 * mesh's Nyquist frequency. (Hockney & Eastwood 1988, "Computer Simulation
 * Using Particles", discuss these choices.)
 *
 * Determinism: the deposit is the only step where particles meet. They are
 * bucketed by the mesh plane (along x) of their lower CIC corner, in index
 * order within a bucket; a bucket writes to its plane and the next, so the
 * even buckets run in parallel, then the odd ones, each bucket in index
 * order on one thread: every cell sums its terms in the same order whatever
 * the thread count. The FFTs run on one thread (a threaded FFTW plan may
 * differ in its rounding with the thread count). */
#include "source/models/pm.h"

#include <fftw3.h>
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "core/fft_planner.h"

#define PI 3.14159265358979323846

/* g_p(a) = a³ E(a) dD/da = a² E f D: the momentum per unit displacement of
 * the linear growing mode (p = g_p ψ when x = q + D ψ). */
static double growth_momentum(const orr_cosmology *c, double a)
{
    return a * a * orr_hubble_e(c, a) * orr_growth_rate(c, a) * orr_growth_factor(c, a);
}

/* Drift: Δx = ∫ p / (a³ E) da with p ∝ g_p(a) over the step, so that the
 * growing mode moves exactly: p(ar) (D(a1) − D(a0)) / g_p(ar). */
double orr_pm_drift_factor(const orr_cosmology *c, double a0, double a1, double ar)
{
    return (orr_growth_factor(c, a1) - orr_growth_factor(c, a0)) / growth_momentum(c, ar);
}

/* Kick: Δp = ∫ −∇φ / (a E) da with −∇φ ∝ D / a over the step (linear
 * theory), and dg_p/da = (3/2) Ω_m D / (a² E) (the growth equation):
 * −∇φ(ar) (ar / D(ar)) (g_p(a1) − g_p(a0)) / ((3/2) Ω_m). */
double orr_pm_kick_factor(const orr_cosmology *c, double a0, double a1, double ar)
{
    double dg = growth_momentum(c, a1) - growth_momentum(c, a0);
    return ar / orr_growth_factor(c, ar) * dg / (1.5 * c->omega_m);
}

typedef struct pm_mesh {
    int m;
    size_t pad;          /* 2 (m/2 + 1): the in-place transform's padded last axis */
    float *grid;         /* m·m·pad floats: density, then its modes, then one force axis */
    fftwf_complex *pot;  /* m·m·(m/2+1) modes of the potential */
    fftwf_plan forward, backward;
    double *k;           /* m: signed wavenumber of each index, h/Mpc */
    double *grad;        /* m: sin(k Δ) / Δ, the two-point difference's wavenumber */
} pm_mesh;

static void mesh_free(pm_mesh *g)
{
    if ((g->forward || g->backward) && orr_fft_planner_lock(NULL) == ORR_OK) {
        if (g->forward)
            fftwf_destroy_plan(g->forward);
        if (g->backward)
            fftwf_destroy_plan(g->backward);
        orr_fft_planner_unlock();
    }
    fftwf_free(g->grid);
    fftwf_free(g->pot);
    free(g->k);
    free(g->grad);
    memset(g, 0, sizeof *g);
}

static orr_status mesh_alloc(pm_mesh *g, int m, double box, orr_error *err)
{
    memset(g, 0, sizeof *g);
    g->m = m;
    g->pad = 2 * (size_t)(m / 2 + 1);
    size_t nreal = (size_t)m * m * g->pad;
    g->grid = fftwf_malloc(nreal * sizeof(float));
    g->pot = fftwf_malloc(nreal / 2 * sizeof(fftwf_complex));
    g->k = malloc((size_t)m * sizeof *g->k);
    g->grad = malloc((size_t)m * sizeof *g->grad);
    if (!g->grid || !g->pot || !g->k || !g->grad) {
        mesh_free(g);
        return orr_fail(err, ORR_ERR_NOMEM, "particle mesh: out of memory for two meshes of %d³", m);
    }
    for (int i = 0; i < m; i++) {
        int n = i <= m / 2 ? i : i - m;
        double cell = box / m;
        g->k[i] = 2 * PI / box * n;
        g->grad[i] = sin(g->k[i] * cell) / cell; /* 0 on the Nyquist plane: the field stays real */
    }
    /* One thread: see the determinism note at the top. The planner's thread
     * count is global, hence the lock. FFTW_ESTIMATE leaves the array alone
     * while planning. */
    orr_status st = orr_fft_planner_lock(err);
    if (st) {
        mesh_free(g);
        return st;
    }
    fftwf_plan_with_nthreads(1);
    fftwf_complex *modes = (fftwf_complex *)g->grid;
    g->forward = fftwf_plan_dft_r2c_3d(m, m, m, g->grid, modes, FFTW_ESTIMATE);
    g->backward = fftwf_plan_dft_c2r_3d(m, m, m, modes, g->grid, FFTW_ESTIMATE);
    orr_fft_planner_unlock();
    if (!g->forward || !g->backward) {
        mesh_free(g);
        return orr_fail(err, ORR_ERR_INTERNAL, "particle mesh: FFTW could not plan a %d³ transform", m);
    }
    return ORR_OK;
}

/* The CIC corner below x along one axis (cells of size 1/inv), and the
 * weight of the upper neighbour. */
static inline int cic_corner(double x, double inv, int m, double *t)
{
    double u = x * inv;
    double f = floor(u);
    *t = u - f;
    int i = (int)f % m;
    return i < 0 ? i + m : i;
}

typedef struct pm_state {
    orr_zeldovich *z;
    pm_mesh mesh;
    uint32_t *order;  /* particle indices bucketed by the x plane of their CIC corner */
    int64_t *start;   /* m + 1: bucket b is order[start[b] .. start[b+1]) */
    float *acc;       /* 3n: −∇φ at the particles */
} pm_state;

/* Counting sort of the particles by the x plane of their CIC corner; stable,
 * so each bucket lists its particles in index order. */
static void bucket_particles(pm_state *s)
{
    const orr_zeldovich *z = s->z;
    int m = s->mesh.m;
    double inv = m / z->box, t;
    memset(s->start, 0, (size_t)(m + 1) * sizeof *s->start);
    for (int64_t i = 0; i < z->n; i++)
        s->start[cic_corner(z->pos[3 * i], inv, m, &t) + 1]++;
    for (int b = 0; b < m; b++)
        s->start[b + 1] += s->start[b];
    int64_t *fill = malloc((size_t)m * sizeof *fill);
    memcpy(fill, s->start, (size_t)m * sizeof *fill);
    for (int64_t i = 0; i < z->n; i++)
        s->order[fill[cic_corner(z->pos[3 * i], inv, m, &t)]++] = (uint32_t)i;
    free(fill);
}

static void deposit_particle(const pm_mesh *g, const float *x, double inv)
{
    double t[3];
    int lo[3];
    for (int d = 0; d < 3; d++)
        lo[d] = cic_corner(x[d], inv, g->m, &t[d]);
    for (int cx = 0; cx < 2; cx++) {
        int ix = cx ? (lo[0] + 1) % g->m : lo[0];
        double wx = cx ? t[0] : 1 - t[0];
        for (int cy = 0; cy < 2; cy++) {
            int iy = cy ? (lo[1] + 1) % g->m : lo[1];
            double wxy = wx * (cy ? t[1] : 1 - t[1]);
            float *row = g->grid + ((size_t)ix * g->m + iy) * g->pad;
            int iz = (lo[2] + 1) % g->m;
            row[lo[2]] += (float)(wxy * (1 - t[2]));
            row[iz] += (float)(wxy * t[2]);
        }
    }
}

/* Particle counts per cell, CIC, in an order fixed by the particles alone. */
static void deposit(pm_state *s)
{
    pm_mesh *g = &s->mesh;
    int m = g->m;
    double inv = m / s->z->box;
    size_t nreal = (size_t)m * m * g->pad;
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < nreal; i++)
        g->grid[i] = 0;
    bucket_particles(s);
    for (int parity = 0; parity < 2; parity++) {
#pragma omp parallel for schedule(dynamic, 1)
        for (int b = parity; b < m; b += 2)
            for (int64_t j = s->start[b]; j < s->start[b + 1]; j++)
                deposit_particle(g, s->z->pos + 3 * (size_t)s->order[j], inv);
    }
}

/* Σ of the mesh (padding excluded), in a fixed order. */
static double mesh_total(const pm_mesh *g)
{
    double sum = 0;
    for (size_t r = 0; r < (size_t)g->m * g->m; r++)
        for (int iz = 0; iz < g->m; iz++)
            sum += g->grid[r * g->pad + iz];
    return sum;
}

/* pot = φ_k from the density modes in g->grid: −(3/2) Ω_m / a × δ_k / k²,
 * with the 1/N that turns counts into δ and undoes the
 * unnormalised inverse FFT (δ = counts M³/N − 1; the mean only touches
 * k = 0, which is zeroed). */
static void potential_modes(pm_mesh *g, double omega_m, double a, int64_t n)
{
    int m = g->m, mh = m / 2 + 1;
    const fftwf_complex *rho = (const fftwf_complex *)g->grid;
    double scale = -1.5 * omega_m / a / (double)n;
#pragma omp parallel for schedule(static)
    for (int ix = 0; ix < m; ix++)
        for (int iy = 0; iy < m; iy++)
            for (int iz = 0; iz < mh; iz++) {
                size_t c = ((size_t)ix * m + iy) * mh + iz;
                double k2 = g->k[ix] * g->k[ix] + g->k[iy] * g->k[iy] + g->k[iz] * g->k[iz];
                double f = k2 > 0 ? scale / k2 : 0;
                g->pot[c][0] = (float)(f * rho[c][0]);
                g->pot[c][1] = (float)(f * rho[c][1]);
            }
}

/* g->grid = −∂φ/∂x_axis by the two-point difference: −i sin(k Δ)/Δ φ_k. */
static void force_modes(pm_mesh *g, int axis)
{
    int m = g->m, mh = m / 2 + 1;
    fftwf_complex *out = (fftwf_complex *)g->grid;
#pragma omp parallel for schedule(static)
    for (int ix = 0; ix < m; ix++)
        for (int iy = 0; iy < m; iy++)
            for (int iz = 0; iz < mh; iz++) {
                size_t c = ((size_t)ix * m + iy) * mh + iz;
                double k = g->grad[axis == 0 ? ix : axis == 1 ? iy : iz];
                /* −i k (re + i im) = k im − i k re */
                out[c][0] = (float)(k * g->pot[c][1]);
                out[c][1] = (float)(-k * g->pot[c][0]);
            }
}

/* acc[3i + axis] = the force mesh in g->grid at particle i, CIC. */
static void interpolate(pm_state *s, int axis)
{
    const pm_mesh *g = &s->mesh;
    const orr_zeldovich *z = s->z;
    int m = g->m;
    double inv = m / z->box;
#pragma omp parallel for schedule(static)
    for (int64_t i = 0; i < z->n; i++) {
        const float *x = z->pos + 3 * i;
        double t[3], sum = 0;
        int lo[3];
        for (int d = 0; d < 3; d++)
            lo[d] = cic_corner(x[d], inv, m, &t[d]);
        for (int cx = 0; cx < 2; cx++) {
            int ix = cx ? (lo[0] + 1) % m : lo[0];
            double wx = cx ? t[0] : 1 - t[0];
            for (int cy = 0; cy < 2; cy++) {
                int iy = cy ? (lo[1] + 1) % m : lo[1];
                double wxy = wx * (cy ? t[1] : 1 - t[1]);
                const float *row = g->grid + ((size_t)ix * m + iy) * g->pad;
                sum += wxy * ((1 - t[2]) * row[lo[2]] + t[2] * row[(lo[2] + 1) % m]);
            }
        }
        s->acc[3 * i + axis] = (float)sum;
    }
}

/* −∇φ at every particle at scale factor a; returns |Σ mesh − N| / N. */
static double compute_forces(pm_state *s, double a)
{
    deposit(s);
    double mass_error = fabs(mesh_total(&s->mesh) - (double)s->z->n) / (double)s->z->n;
    fftwf_execute(s->mesh.forward);
    potential_modes(&s->mesh, s->z->cosmo.omega_m, a, s->z->n);
    for (int axis = 0; axis < 3; axis++) {
        force_modes(&s->mesh, axis);
        fftwf_execute(s->mesh.backward);
        interpolate(s, axis);
    }
    return mass_error;
}

static void kick(pm_state *s, double factor)
{
    float *p = s->z->vel;
#pragma omp parallel for schedule(static)
    for (int64_t i = 0; i < 3 * s->z->n; i++)
        p[i] = (float)(p[i] + factor * s->acc[i]);
}

static void drift(pm_state *s, double factor)
{
    float *x = s->z->pos;
    const float *p = s->z->vel;
    const double box = s->z->box;
#pragma omp parallel for schedule(static)
    for (int64_t i = 0; i < 3 * s->z->n; i++) {
        double v = x[i] + factor * p[i];
        v -= box * floor(v / box);
        float f = (float)v;
        x[i] = f < (float)box ? f : 0; /* rounding up to the box side */
    }
}

/* |Σ p| / Σ |p|, summed in index order. */
static double momentum_imbalance(const orr_zeldovich *z)
{
    double sum[3] = {0}, norm = 0;
    for (int64_t i = 0; i < z->n; i++) {
        double q2 = 0;
        for (int d = 0; d < 3; d++) {
            sum[d] += z->vel[3 * i + d];
            q2 += (double)z->vel[3 * i + d] * z->vel[3 * i + d];
        }
        norm += sqrt(q2);
    }
    return norm > 0 ? sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]) / norm : 0;
}

/* Gadget's u (km/s) to p = a² dx/dt (100 km/s) and back. */
static void scale_velocities(orr_zeldovich *z, double factor)
{
#pragma omp parallel for schedule(static)
    for (int64_t i = 0; i < 3 * z->n; i++)
        z->vel[i] = (float)(z->vel[i] * factor);
}

/* The rms distance of the particles from their grid points, the nearest
 * periodic image. */
static double rms_displacement(const orr_zeldovich *z)
{
    double sum2 = 0;
    for (int64_t i = 0; i < z->n; i++) {
        double q[3];
        orr_zeldovich_lagrangian(z, i, q);
        for (int d = 0; d < 3; d++) {
            double dx = z->pos[3 * i + d] - q[d];
            dx -= z->box * floor(dx / z->box + 0.5);
            sum2 += dx * dx;
        }
    }
    return sqrt(sum2 / (double)z->n);
}

static orr_status check_params(const orr_zeldovich *z, const orr_pm_params *p, orr_error *err)
{
    if (p->mesh < 2 || p->mesh > ORR_PM_MESH_MAX || p->mesh % 2)
        return orr_fail(err, ORR_ERR_USAGE, "mesh %d: expected an even number from 2 to %d", p->mesh,
                        ORR_PM_MESH_MAX);
    if (p->steps < 1 || p->steps > ORR_PM_STEPS_MAX)
        return orr_fail(err, ORR_ERR_USAGE, "steps %d: expected 1 to %d", p->steps, ORR_PM_STEPS_MAX);
    if (!(p->a_end > z->a && p->a_end <= 1))
        return orr_fail(err, ORR_ERR_USAGE,
                        "the end (z = %g) must be later than the start (z = %g) and no later than z = 0",
                        1 / p->a_end - 1, z->redshift);
    if (z->n > UINT32_MAX)
        return orr_fail(err, ORR_ERR_USAGE, "%lld particles: at most 2^32 - 1", (long long)z->n);
    return ORR_OK;
}

static void set_epoch(orr_zeldovich *z, double a)
{
    z->a = a;
    z->redshift = 1 / a - 1;
    z->growth = orr_growth_factor(&z->cosmo, a);
    z->rate = orr_growth_rate(&z->cosmo, a);
    z->hubble = 100.0 * orr_hubble_e(&z->cosmo, a);
    z->vel_factor = sqrt(a) * z->rate * z->hubble;
}

static orr_status state_alloc(pm_state *s, orr_zeldovich *z, int mesh, orr_error *err)
{
    memset(s, 0, sizeof *s);
    s->z = z;
    orr_status st = mesh_alloc(&s->mesh, mesh, z->box, err);
    if (st)
        return st;
    s->order = orr_malloc((size_t)z->n * sizeof *s->order, "particle-mesh buckets", err);
    s->start = s->order ? orr_malloc((size_t)(mesh + 1) * sizeof *s->start, "particle-mesh buckets", err) : NULL;
    s->acc = s->start ? orr_malloc((size_t)z->n * 3 * sizeof *s->acc, "particle-mesh forces", err) : NULL;
    if (!s->acc) {
        mesh_free(&s->mesh);
        free(s->order);
        free(s->start);
        return ORR_ERR_NOMEM;
    }
    return ORR_OK;
}

static void state_free(pm_state *s)
{
    mesh_free(&s->mesh);
    free(s->order);
    free(s->start);
    free(s->acc);
}

orr_status orr_pm_evolve(orr_zeldovich *z, const orr_pm_params *p, orr_pm_report *report, orr_error *err)
{
    memset(report, 0, sizeof *report);
    orr_status st = check_params(z, p, err);
    pm_state s;
    if (st || (st = state_alloc(&s, z, p->mesh, err)))
        return orr_fail_prefix(err, "particle mesh: ");
    double t0 = omp_get_wtime();
    const orr_cosmology *c = &z->cosmo;
    double a = z->a, da = (p->a_end - z->a) / p->steps;
    scale_velocities(z, pow(a, 1.5) / 100);
    report->mesh_mass = compute_forces(&s, a);
    for (int step = 0; step < p->steps; step++) {
        double a1 = step + 1 == p->steps ? p->a_end : z->a + (step + 1) * da;
        double ah = 0.5 * (a + a1);
        kick(&s, orr_pm_kick_factor(c, a, ah, a));
        drift(&s, orr_pm_drift_factor(c, a, a1, ah));
        report->mesh_mass = fmax(report->mesh_mass, compute_forces(&s, a1));
        kick(&s, orr_pm_kick_factor(c, ah, a1, a1));
        double momentum = momentum_imbalance(z);
        report->momentum = fmax(report->momentum, momentum);
        a = a1;
        if (p->progress)
            p->progress(p->progress_user, step + 1, p->steps, a, momentum, omp_get_wtime() - t0);
    }
    scale_velocities(z, 100 / pow(a, 1.5));
    set_epoch(z, a);
    z->rms_displacement = rms_displacement(z);
    state_free(&s);
    report->wall_seconds = omp_get_wtime() - t0;
    return ORR_OK;
}
