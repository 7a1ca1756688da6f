/* The disc's dynamics tabulated once per galaxy, and the disc sampler that
 * reads them (model_galaxy.h; docs/model.md, "Tables").
 *
 * Why: the exact recipe (model_galaxy.c) computes v_c^2, kappa^2 (three
 * v_c^2 by central difference), sigma_R (kappa^2 again) and the pressure
 * slope (two sigma_R) afresh for every disc star, each v_c^2 with a
 * logarithm and the spheroids' masses, and integrates the spheroids'
 * vertical pull on 24 nodes for its sigma_z^2: about 1.3 microseconds of
 * CPU a star, when a halo particle costs a tenth of that. All of it but
 * the spheroids' pull at the star's own height (spheroid_vc2_drop, two
 * enclosed masses) depends on R alone, or on (R, |z|) smoothly; it is read
 * from tables by interpolation instead.
 *
 * The radius grid: cells of equal width in R within each octave, 2^BITS of
 * them, so the cell of R is read from the bits of the double (the exponent
 * and the top mantissa bits) and the place in it from the rest of the
 * mantissa -- linear in R, no logarithm. */
#include "source/models/model_galaxy.h"

#include <math.h>
#include <string.h>

static uint64_t bits_of(double x)
{
    uint64_t b;
    memcpy(&b, &x, sizeof b);
    return b;
}

static double double_of(uint64_t b)
{
    double x;
    memcpy(&x, &b, sizeof x);
    return x;
}

/* Node k of a grid of 2^bits cells per octave from DISC_NODE_R0. */
static double grid_radius(int k, int bits)
{
    return double_of(bits_of(DISC_NODE_R0) + ((uint64_t)k << (52 - bits)));
}

/* The cell of R in that grid (R >= DISC_NODE_R0) and its place in the cell,
 * 0 to 1; beyond the last node, the last cell's end. */
static int grid_cell(double R, int bits, int cells, double *frac)
{
    const int shift = 52 - bits;
    uint64_t d = bits_of(R) - bits_of(DISC_NODE_R0);
    uint64_t k = d >> shift;
    if (k >= (uint64_t)cells) {
        *frac = 1.0;
        return cells - 1;
    }
    *frac = (double)(d & (((uint64_t)1 << shift) - 1)) * (1.0 / (double)((uint64_t)1 << shift));
    return (int)k;
}

/* What disc_velocity (model_galaxy.c) computes at R, from the exact
 * functions. */
static disc_node exact_node(const galaxy *g, double R)
{
    disc_node n;
    double kappa2 = orr_model_galaxy_disc_kappa2(g, R);
    n.vc2 = orr_model_galaxy_disc_vc2(g, R);
    n.gm_sph = MODEL_G * orr_model_spheroid_mass(g, R) / R;
    double ratio = kappa2 * R * R / (4.0 * n.vc2); /* kappa^2 / (4 Omega^2) */
    n.sigma_r = orr_model_galaxy_disc_sigma_r(g, R);
    n.drift = fmin(0.0, n.sigma_r * n.sigma_r * (1.0 - ratio + orr_model_galaxy_disc_pressure_slope(g, R)));
    n.sigma_phi = n.sigma_r * sqrt(ratio);
    n.radial = orr_model_galaxy_disc_radial(g, R);
    return n;
}

static double lerp(double a, double b, double f)
{
    return a + f * (b - a);
}

static disc_node lerp_node(const disc_node *a, const disc_node *b, double f)
{
    return (disc_node){lerp(a->vc2, b->vc2, f),         lerp(a->gm_sph, b->gm_sph, f),
                       lerp(a->drift, b->drift, f),     lerp(a->sigma_r, b->sigma_r, f),
                       lerp(a->sigma_phi, b->sigma_phi, f), lerp(a->radial, b->radial, f)};
}

/* The largest error of an interpolated node against the exact one, each
 * quantity relative to its scale (DISC_TABLE_TOL). */
static double node_error(const galaxy *g, const disc_node *t, const disc_node *e, double R)
{
    /* the radial term enters sigma_z^2 times h (|z| + h), beside the sheet's
     * 2 pi G Sigma h: its scale is the larger of itself and Sigma's term / h^2 */
    double h = g->s.disc_hz, sheet = orr_model_galaxy_disc_sheet(g, R);
    const double q[][3] = {{t->vc2, e->vc2, e->vc2},
                           {t->gm_sph, e->gm_sph, e->gm_sph},
                           {t->drift, e->drift, e->vc2},
                           {t->sigma_r, e->sigma_r, e->sigma_r},
                           {t->sigma_phi, e->sigma_phi, e->sigma_phi},
                           {t->radial, e->radial, fmax(fabs(e->radial), sheet / (h * h))}};
    double worst = 0.0;
    for (size_t i = 0; i < sizeof q / sizeof q[0]; i++)
        worst = fmax(worst, fabs(q[i][0] - q[i][1]) / fabs(q[i][2]));
    return worst;
}

/* Whether linear interpolation holds across cell k, checked at its
 * middle: nodes and middles are at most R/1024 apart, half the width of
 * the ramps the exact functions' central differences (step 1e-3 R) make
 * of a kink, so every ramp holds a middle, and the cells on either side
 * of it are flagged. */
static unsigned char cell_needs_exact(const galaxy *g, const disc_table *t, int k)
{
    double lo = grid_radius(k, DISC_NODE_BITS), hi = grid_radius(k + 1, DISC_NODE_BITS), R = 0.5 * (lo + hi);
    disc_node e = exact_node(g, R), i = lerp_node(&t->node[k], &t->node[k + 1], 0.5);
    return !(node_error(g, &i, &e, R) <= DISC_TABLE_TOL);
}

/* The pull's first row read (the cell of PULL_R_EXACT h): nearer the axis
 * it is computed exactly. */
static int first_pull_row(const galaxy *g)
{
    double f;
    return grid_cell(PULL_R_EXACT * g->s.disc_hz, PULL_R_BITS, PULL_R_CELLS, &f);
}

/* About 8,000 nodes of six exact quantities, as many checks, and 35,000
 * pull integrals: some tens of milliseconds a galaxy, shared by the
 * threads. */
void orr_model_galaxy_build_disc_table(galaxy *g)
{
    disc_table *t = &g->disc;
    double h = g->s.disc_hz;
#pragma omp parallel
    {
#pragma omp for schedule(dynamic, 64)
        for (int k = 0; k <= DISC_NODE_CELLS; k++)
            t->node[k] = exact_node(g, grid_radius(k, DISC_NODE_BITS));
#pragma omp for schedule(dynamic, 64) nowait
        for (int k = 0; k < DISC_NODE_CELLS; k++)
            t->exact[k] = cell_needs_exact(g, t, k);
#pragma omp for schedule(dynamic, 8)
        for (int i = first_pull_row(g); i <= PULL_R_CELLS; i++)
            for (int m = 0; m < PULL_Z_CELLS + 3; m++)
                t->pull[i][m] = orr_model_galaxy_spheroid_pull(g, grid_radius(i, PULL_R_BITS),
                                                               h * (m - 1) * (PULL_Z_MAX / PULL_Z_CELLS));
    }
}

int orr_model_disc_at(const galaxy *g, double R, disc_node *out)
{
    double f;
    int k = grid_cell(R, DISC_NODE_BITS, DISC_NODE_CELLS, &f);
    *out = lerp_node(&g->disc.node[k], &g->disc.node[k + 1], f);
    return !g->disc.exact[k];
}

/* Catmull-Rom interpolation in |z| along one row, in cell j at f (the
 * row's node j + 1 is at the cell's start). */
static double row_at(const double *row, int j, double f)
{
    return orr_model_catmull_rom(row[j], row[j + 1], row[j + 2], row[j + 3], f);
}

/* The pull integral: cubic in |z| (the pull changes over heights of order
 * R, which near the axis are not many h/4 steps: linear interpolation was
 * 0.3% off at R = 2h), linear in R between rows; exact above PULL_Z_MAX
 * scale heights, and within PULL_R_EXACT h of the axis, where the
 * spheroids' pull (its radius held at least h) has a kink in height for
 * every node of the integral (0.3-0.5% of the disc's stars). */
static double pull_at(const galaxy *g, double R, double az)
{
    double w = az / g->s.disc_hz * (PULL_Z_CELLS / PULL_Z_MAX);
    if (!(w < PULL_Z_CELLS) || R < PULL_R_EXACT * g->s.disc_hz)
        return orr_model_galaxy_spheroid_pull(g, R, az);
    int j = (int)w;
    double fz = w - j, fr;
    int i = grid_cell(R, PULL_R_BITS, PULL_R_CELLS, &fr);
    return lerp(row_at(g->disc.pull[i], j, fz), row_at(g->disc.pull[i + 1], j, fz), fr);
}

/* orr_model_galaxy_disc_sigma_z2's sum with its parts from the tables. */
double orr_model_disc_sigma_z2_at(const galaxy *g, const disc_node *n, double R, double az, double sheet,
                                  double layer)
{
    double h = g->s.disc_hz;
    return fmax(1.0, sheet * (1.0 - 0.5 * layer) + pull_at(g, R, az) - n->radial * h * (az + h));
}

/* orr_model_galaxy_disc_velocity from the node n at Rs: only the
 * spheroids' v_c^2 at the star's height is computed. */
static void table_velocity(const galaxy *g, const disc_node *n, double Rs, double z, double sheet, double layer,
                           double gr, double gt, double gz, double *vr, double *vphi, double *vz)
{
    double r2 = Rs * Rs + z * z, rs = sqrt(r2);
    double drop = MODEL_G * orr_model_spheroid_mass(g, rs) * Rs * Rs / (rs * r2) - n->gm_sph;
    *vr = n->sigma_r * gr;
    *vphi = sqrt(fmax(0.0, n->vc2 + drop + n->drift)) + n->sigma_phi * gt;
    *vz = sqrt(orr_model_disc_sigma_z2_at(g, n, Rs, fabs(z), sheet, layer)) * gz;
}

/* orr_model_galaxy_sample_disc's draws, in the same order, and its
 * velocities from the tables: only the spheroids' v_c^2 at the star's
 * height is computed here. Angles' sines and cosines by orr_sincos_turn. */
void orr_model_galaxy_sample_disc_fast(const galaxy *g, orr_rng *r, particle *p)
{
    const galaxy_spec *s = &g->s;
    double R, surface; /* exp(-R / Rd) */
    do {
        surface = orr_rng_uniform(r) * orr_rng_uniform(r);
        R = -s->disc_rd * log(surface);
    } while (R > s->disc_rmax);
    double sin_phi, cos_phi;
    orr_sincos_turn(orr_rng_uniform(r), &sin_phi, &cos_phi);
    double u = orr_rng_uniform(r);
    double layer = u < 0.5 ? 2.0 * u : 2.0 * (1.0 - u); /* exp(-|z| / h) */
    double z = u < 0.5 ? s->disc_hz * log(layer) : -s->disc_hz * log(layer);

    orr_vec3 rhat = orr_v3_add(orr_v3_scale(g->e1, cos_phi), orr_v3_scale(g->e2, sin_phi));
    orr_vec3 that = orr_v3_cross(g->spin, rhat);
    p->pos = orr_v3_add(g->centre, orr_v3_add(orr_v3_scale(rhat, R), orr_v3_scale(g->spin, z)));

    double gr, gt, gz, unused;
    orr_rng_gauss2_fast(r, &gr, &gt);
    orr_rng_gauss2_fast(r, &gz, &unused);
    double Rs = R > 1e-3 ? R : 1e-3, vr, vphi, vz;
    disc_node n;
    if (orr_model_disc_at(g, Rs, &n))
        table_velocity(g, &n, Rs, z, 2.0 * ORR_PI * g->g_sigma0 * (R > 1e-3 ? surface : exp(-Rs / s->disc_rd)) * s->disc_hz,
                       layer, gr, gt, gz, &vr, &vphi, &vz);
    else
        orr_model_galaxy_disc_velocity(g, R, z, gr, gt, gz, &vr, &vphi, &vz);
    orr_vec3 v = orr_v3_add(orr_v3_scale(rhat, vr), orr_v3_scale(that, vphi));
    p->vel = orr_v3_add(g->velocity, orr_v3_add(v, orr_v3_scale(g->spin, vz)));

    double rad = sqrt(R * R + z * z);
    p->r = (float)rad;
    p->e0 = (float)(orr_model_galaxy_potential(g, rad) + 0.5 * (vr * vr + vphi * vphi + vz * vz));
    p->ez = orr_model_disc_ez(gz, fabs(z), s->disc_hz);
}
