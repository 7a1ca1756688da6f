/* The model's particles drawn a batch at a time (model_galaxy.h;
 * docs/model.md, "Batches"): the same draws as the one-particle samplers
 * (orr_model_galaxy_sample_sphere_fast and _disc_fast), in loops over the
 * particles of a batch that the compiler turns into vector instructions
 * (`omp simd`, in AVX-512, AVX2 and SSE2 copies) -- the random numbers,
 * the logarithms and exponentials (model_math.h), the sines and cosines
 * (orr_sincos_turn) and the tables' interpolations, gathered lane by lane.
 *
 * A particle that does not take the common path -- a radius beyond a
 * table's end, a disc star redrawn beyond the truncation or in a cell left
 * to the exact functions, a bulge star rejected three times -- is marked
 * in the vector loop and drawn again, whole, by the one-particle sampler
 * from the start of its own sequence: still a pure function of (seed,
 * index). */
#include "source/models/model_galaxy.h"
#include "source/models/model_math.h"

#include <math.h>

#include "core/simd.h"

/* The j-th uniform (from 0) of the sequence keyed `key`: what the j+1-th
 * orr_rng_uniform of orr_rng_seed_keyed's generator returns. */
static ORR_ALWAYS_INLINE double uniform_at(uint64_t key, uint64_t j)
{
    return orr_uniform_of_bits(orr_rng_mix(key + (j + 1) * ORR_RNG_GAMMA));
}

/* orr_rng_seed_keyed's state: the key of particle `index`'s sequence. */
static ORR_ALWAYS_INLINE uint64_t key_of(uint64_t seed_key, uint64_t index)
{
    return orr_rng_seed_keyed(seed_key, index, 0).state;
}

/* A linear interpolation in a table of doubles. */
static ORR_ALWAYS_INLINE double lerp_at(const double *v, int i, double f)
{
    return v[i] + f * (v[i + 1] - v[i]);
}

/* A table uniform in ln r, its fields read once, out of the loops (a
 * store to the output could otherwise alias them, for the compiler). */
typedef struct ln_table {
    double ln_rmin, dln;
} ln_table;

/* gdf_speed_ln's operations, with selects for its clamps, for q the
 * speeds' rows (sp their grid) and psi the potential's value at r. */
static ORR_ALWAYS_INLINE double speed_at(const float *q, ln_table sp, double ln_r, double u, double psi)
{
    double t = (ln_r - sp.ln_rmin) / sp.dln;
    t = t < 0 ? 0 : t > GDF_ROWS - 1 ? GDF_ROWS - 1 : t;
    int k = (int)t;
    k = k >= GDF_ROWS - 1 ? GDF_ROWS - 2 : k;
    double fr = t - k;
    double c = (1.0 - sqrt(1.0 - u)) * (GDF_COLS - 1); /* u < 1: fmax(0, 1 - u) there */
    int j = (int)c;
    j = j >= GDF_COLS - 1 ? GDF_COLS - 2 : j;
    double fc = c - j;
    int a = k * GDF_COLS + j, b = a + GDF_COLS;
    double q0 = q[a] + fc * (q[a + 1] - q[a]);
    double q1 = q[b] + fc * (q[b + 1] - q[b]);
    double qq = q0 + fr * (q1 - q0);
    return qq * sqrt(2.0 * psi);
}

/* The place of ln r in a table uniform in ln r of n nodes: cell *i (kept
 * inside the table, for the gather) and the fraction; 0 where the table's
 * own formula has another branch there (the caller redraws the particle). */
static ORR_ALWAYS_INLINE int table_place(double ln_r, ln_table tab, int n, int *i, double *f)
{
    double t = (ln_r - tab.ln_rmin) / tab.dln;
    int inside = t > 0.0 && t < n - 1;
    int k = inside ? (int)t : 0;
    *i = k;
    *f = t - k;
    return inside;
}

/* Halo particles first .. first + n - 1: orr_model_galaxy_sample_sphere_fast
 * for COMP_HALO lane by lane (no rejection: the radius's draw is scaled to
 * the truncation). odd[i] = 1 where particle i must be drawn by it. */
ORR_WIDE_VECTOR_CLONES
static void halo_batch(const galaxy *g, uint64_t seed_key, uint64_t first, int n, const particle_rows *out,
                       int64_t *restrict odd)
{
    const double a = g->s.halo_a, frac = g->halo_frac, rmax = g->s.halo_rmax;
    const float *q = &g->speeds[COMP_HALO].q[0][0];
    const ln_table sp = {g->speeds[COMP_HALO].ln_rmin, g->speeds[COMP_HALO].dln};
    const ln_table psi_grid = {g->sph.ln_rmin, g->sph.dln}, pot_grid = {g->pot_ln_rmin, g->pot_dln};
    const double *psi = g->sph.psi, *pot = g->pot;
    const orr_vec3 c0 = g->centre, v0 = g->velocity;
    float *restrict x = out->x, *restrict y = out->y, *restrict z = out->z, *restrict vx = out->vx,
                    *restrict vy = out->vy, *restrict vz = out->vz, *restrict r = out->r, *restrict e0 = out->e0,
                    *restrict ez = out->ez;
#pragma omp simd
    for (int i = 0; i < n; i++) {
        uint64_t key = key_of(seed_key, first + (uint64_t)i);
        double sq = sqrt(uniform_at(key, 0) * frac);
        double rad = a * sq / (1.0 - sq);
        double cost = 2.0 * uniform_at(key, 1) - 1.0, sint = sqrt(1.0 - cost * cost), sn, cs;
        orr_sincos_turn(uniform_at(key, 2), &sn, &cs);
        x[i] = (float)(c0.x + sint * cs * rad);
        y[i] = (float)(c0.y + sint * sn * rad);
        z[i] = (float)(c0.z + cost * rad);
        double ln_rad = orr_log_poly(rad), f_psi, f_pot;
        int i_psi, i_pot;
        int in_psi = table_place(ln_rad, psi_grid, GDF_POT_N, &i_psi, &f_psi);
        int in_pot = table_place(ln_rad, pot_grid, POT_N, &i_pot, &f_pot);
        odd[i] = !(in_psi & in_pot & (rad > POT_R_MIN) & (rad < rmax));
        double speed = speed_at(q, sp, ln_rad, uniform_at(key, 3), lerp_at(psi, i_psi, f_psi));
        double vcost = 2.0 * uniform_at(key, 4) - 1.0, vsint = sqrt(1.0 - vcost * vcost);
        orr_sincos_turn(uniform_at(key, 5), &sn, &cs);
        vx[i] = (float)(v0.x + vsint * cs * speed);
        vy[i] = (float)(v0.y + vsint * sn * speed);
        vz[i] = (float)(v0.z + vcost * speed);
        r[i] = (float)rad;
        e0[i] = (float)(lerp_at(pot, i_pot, f_pot) + 0.5 * speed * speed);
        ez[i] = 0.0f;
    }
}

/* The Hernquist density's shape (model_galaxy.c's hernquist_rho). */
static ORR_ALWAYS_INLINE double hernquist_shape(double r, double a)
{
    double ra = r + a;
    return 1.0 / (r * ra * ra * ra);
}

/* gdf_flat_req's operations (orr_table_cell's clamps as selects), ln r
 * given: r_eq at r and |sin b|. */
static ORR_ALWAYS_INLINE double flat_req(const float *ln_ratio, ln_table grid, double r, double ln_r, double sin_b)
{
    double u = (ln_r - grid.ln_rmin) / grid.dln;
    u = u < 0 ? 0 : u > GDF_FLAT_NR - 1 ? GDF_FLAT_NR - 1 : u;
    int i = (int)u;
    i = i > GDF_FLAT_NR - 2 ? GDF_FLAT_NR - 2 : i;
    double fx = u - i, sb = fabs(sin_b);
    double w = sqrt(sb < 1.0 ? sb : 1.0) * (GDF_FLAT_NB - 1);
    w = w < 0 ? 0 : w > GDF_FLAT_NB - 1 ? GDF_FLAT_NB - 1 : w;
    int j = (int)w;
    j = j > GDF_FLAT_NB - 2 ? GDF_FLAT_NB - 2 : j;
    double fy = w - j;
    int a = i * GDF_FLAT_NB + j, b = a + GDF_FLAT_NB;
    double v = (1 - fx) * ((1 - fy) * ln_ratio[a] + fy * ln_ratio[a + 1]) +
               fx * ((1 - fy) * ln_ratio[b] + fy * ln_ratio[b + 1]);
    return r * orr_exp_poly(v);
}

/* A bulge star's point: kept once a try is taken, the uniform that
 * follows it, the radius, its logarithm, r_eq and the direction. */
typedef struct bulge_point {
    int kept;
    uint64_t next;
    double rad, ln_rad, req, dx, dy, dz;
} bulge_point;

/* One try of sphere_point, from the uniforms j .. j + 3: taken into p if
 * none was before it and the rejection keeps it. */
static ORR_ALWAYS_INLINE void bulge_try(bulge_point *p, uint64_t key, uint64_t j, double a, double frac,
                                        double bound, const float *ln_ratio, ln_table flat, orr_vec3 spin)
{
    double sq = sqrt(uniform_at(key, j) * frac);
    double rt = a * sq / (1.0 - sq), lt = orr_log_poly(rt);
    double cost = 2.0 * uniform_at(key, j + 1) - 1.0, sint = sqrt(1.0 - cost * cost), sn, cs;
    orr_sincos_turn(uniform_at(key, j + 2), &sn, &cs);
    double ex = sint * cs, ey = sint * sn;
    double qt = flat_req(ln_ratio, flat, rt, lt, ex * spin.x + ey * spin.y + cost * spin.z);
    double keep = hernquist_shape(qt, a) / (bound * hernquist_shape(rt, a));
    int take = !p->kept & (uniform_at(key, j + 3) < keep);
    p->rad = take ? rt : p->rad;
    p->ln_rad = take ? lt : p->ln_rad;
    p->req = take ? qt : p->req;
    p->dx = take ? ex : p->dx;
    p->dy = take ? ey : p->dy;
    p->dz = take ? cost : p->dz;
    p->next = take ? j + 4 : p->next;
    p->kept |= take;
}

/* Bulge particles first .. first + n - 1: orr_model_galaxy_sample_sphere_fast
 * for COMP_BULGE lane by lane, for the stars kept within three tries of
 * sphere_point's four uniforms (radius, two angles, the rejection's): the
 * others, about (1 - 1/1.86)^3 = 10% of the Milky Way's (its envelope is
 * 1.86), and those off the tables' common path have odd[i] = 1. */
ORR_WIDE_VECTOR_CLONES
static void bulge_batch(const galaxy *g, uint64_t seed_key, uint64_t first, int n, const particle_rows *out,
                        int64_t *restrict odd)
{
    const double a = g->s.bulge_a, frac = g->bulge_frac, rmax = g->s.halo_rmax, bound = g->bulge_flat.bound;
    const float *q = &g->speeds[COMP_BULGE].q[0][0], *ln_ratio = &g->bulge_flat.ln_ratio[0][0];
    const ln_table sp = {g->speeds[COMP_BULGE].ln_rmin, g->speeds[COMP_BULGE].dln};
    const ln_table flat = {g->bulge_flat.ln_rmin, g->bulge_flat.dln};
    const ln_table psi_grid = {g->sph.ln_rmin, g->sph.dln}, pot_grid = {g->pot_ln_rmin, g->pot_dln};
    const double *psi = g->sph.psi, *pot = g->pot;
    const orr_vec3 c0 = g->centre, v0 = g->velocity, spin = g->spin;
    float *restrict x = out->x, *restrict y = out->y, *restrict z = out->z, *restrict vx = out->vx,
                    *restrict vy = out->vy, *restrict vz = out->vz, *restrict r = out->r, *restrict e0 = out->e0,
                    *restrict ez = out->ez;
#pragma omp simd
    for (int i = 0; i < n; i++) {
        uint64_t key = key_of(seed_key, first + (uint64_t)i);
        bulge_point p = {0, 0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0};
        /* the tries written out: a loop here would be an inner loop, which
         * keeps the outer one from being vectorised */
        bulge_try(&p, key, 0, a, frac, bound, ln_ratio, flat, spin);
        bulge_try(&p, key, 4, a, frac, bound, ln_ratio, flat, spin);
        bulge_try(&p, key, 8, a, frac, bound, ln_ratio, flat, spin);
        int kept = p.kept;
        uint64_t next = p.next;
        double rad = p.rad, ln_rad = p.ln_rad, req = p.req, dx = p.dx, dy = p.dy, dz = p.dz;
        x[i] = (float)(c0.x + dx * rad);
        y[i] = (float)(c0.y + dy * rad);
        z[i] = (float)(c0.z + dz * rad);
        double ln_req = orr_log_poly(req), f_psi, f_pot;
        int i_psi, i_pot;
        int in_psi = table_place(ln_req, psi_grid, GDF_POT_N, &i_psi, &f_psi);
        int in_pot = table_place(ln_rad, pot_grid, POT_N, &i_pot, &f_pot);
        odd[i] = !(kept & in_psi & in_pot & (rad > POT_R_MIN) & (rad < rmax));
        double speed = speed_at(q, sp, ln_req, uniform_at(key, next), lerp_at(psi, i_psi, f_psi));
        double vcost = 2.0 * uniform_at(key, next + 1) - 1.0, vsint = sqrt(1.0 - vcost * vcost), sn, cs;
        orr_sincos_turn(uniform_at(key, next + 2), &sn, &cs);
        vx[i] = (float)(v0.x + vsint * cs * speed);
        vy[i] = (float)(v0.y + vsint * sn * speed);
        vz[i] = (float)(v0.z + vcost * speed);
        r[i] = (float)rad;
        e0[i] = (float)(lerp_at(pot, i_pot, f_pot) + 0.5 * speed * speed);
        ez[i] = 0.0f;
    }
}

/* The cell of R >= DISC_NODE_R0 in a grid of 2^bits cells per octave
 * (model_disc_table.c's grid_cell) and the place in it, by bit work:
 * the mantissa's low bits made a double by the 2^52 trick. Beyond the
 * grid's end (DISC_NODE_OCTAVES octaves up), the last cell's end, as
 * there; the test is on R itself, as 64-bit integer minima are not
 * vector instructions before AVX-512. */
static ORR_ALWAYS_INLINE int cell_of(double R, int bits, double *frac)
{
    const int shift = 52 - bits;
    const double end = DISC_NODE_R0 * (double)(1 << DISC_NODE_OCTAVES);
    int beyond = R >= end;
    double Rc = beyond ? DISC_NODE_R0 : R;
    uint64_t d = orr_bits_of(Rc) - orr_bits_of(DISC_NODE_R0);
    double low = orr_double_of(0x4330000000000000ULL | (d & (((uint64_t)1 << shift) - 1))) - 4503599627370496.0;
    *frac = beyond ? 1.0 : low * (1.0 / (double)((uint64_t)1 << shift));
    return beyond ? (DISC_NODE_OCTAVES << bits) - 1 : (int)(d >> shift);
}

/* The disc's tables at Rs (orr_model_disc_at's interpolation), from the
 * nodes as a flat array of doubles (what the vectoriser gathers from). */
#define NODE_FIELDS ((int)(sizeof(disc_node) / sizeof(double)))
#define PULL_ROW (PULL_Z_CELLS + 3)

static ORR_ALWAYS_INLINE disc_node node_at(const double *nodes, int k, double f)
{
    /* indices, not pointers, so the compiler sees gathers of base + index */
    const int a = k * NODE_FIELDS, b = a + NODE_FIELDS;
    return (disc_node){nodes[a] + f * (nodes[b] - nodes[a]),
                       nodes[a + 1] + f * (nodes[b + 1] - nodes[a + 1]),
                       nodes[a + 2] + f * (nodes[b + 2] - nodes[a + 2]),
                       nodes[a + 3] + f * (nodes[b + 3] - nodes[a + 3]),
                       nodes[a + 4] + f * (nodes[b + 4] - nodes[a + 4]),
                       nodes[a + 5] + f * (nodes[b + 5] - nodes[a + 5])};
}

/* model_disc_table.c's pull_at inside the table (pull its rows as one
 * array; the caller redraws the star where it is not: *inside 0). */
static ORR_ALWAYS_INLINE double pull_in_table(const double *pull, double h, double R, double az, int *inside)
{
    double w = az / h * (PULL_Z_CELLS / PULL_Z_MAX), fr;
    *inside = (w < PULL_Z_CELLS) & (R >= PULL_R_EXACT * h);
    int j = *inside ? (int)w : 0;
    double fz = w - j;
    int i = cell_of(R, PULL_R_BITS, &fr);
    const int a = i * PULL_ROW + j, b = a + PULL_ROW;
    double p0 = orr_model_catmull_rom(pull[a], pull[a + 1], pull[a + 2], pull[a + 3], fz);
    double p1 = orr_model_catmull_rom(pull[b], pull[b + 1], pull[b + 2], pull[b + 3], fz);
    return p0 + fr * (p1 - p0);
}

/* orr_model_spheroid_mass's operations, the galaxy's numbers read once
 * (loads under a condition would be masked loads, which the vectoriser
 * does not make of a structure's fields). */
typedef struct spheroids {
    double bh, bulge_mass, bulge_a, bulge_rmax, bulge_frac, halo_mass, halo_a, halo_rmax, halo_frac;
} spheroids;

static spheroids spheroids_of(const galaxy *g)
{
    const galaxy_spec *s = &g->s;
    return (spheroids){s->bh_mass,   s->bulge_mass, s->bulge_a, s->bulge_rmax, g->bulge_frac,
                       s->halo_mass, s->halo_a,     s->halo_rmax, g->halo_frac};
}

static ORR_ALWAYS_INLINE double spheroid_mass(const spheroids *p, double r)
{
    double bulge = p->bulge_mass * orr_model_hernquist_cdf(r, p->bulge_a) / p->bulge_frac;
    double halo = p->halo_mass * orr_model_hernquist_cdf(r, p->halo_a) / p->halo_frac;
    double m = p->bh;
    m += r >= p->bulge_rmax ? p->bulge_mass : bulge;
    m += r >= p->halo_rmax ? p->halo_mass : halo;
    return m;
}

/* A unit Gaussian pair from the uniforms j and j + 1 (orr_rng_gauss2_fast). */
static ORR_ALWAYS_INLINE void gauss_pair(uint64_t key, uint64_t j, double *g0, double *g1)
{
    double rad = sqrt(-2.0 * orr_log_poly(uniform_at(key, j))), sn, cs;
    orr_sincos_turn(uniform_at(key, j + 1), &sn, &cs);
    *g0 = rad * cs;
    *g1 = rad * sn;
}

/* Disc particles first .. first + n - 1: orr_model_galaxy_sample_disc_fast
 * lane by lane, for the stars whose first radius lies inside the
 * truncation, above 1 pc, in a cell the tables resolve, with the pull
 * tabulated at their height (odd[i] = 1 for the others); cell[i], the
 * radius's cell, for the caller to see whether the tables resolve it (a
 * gather of bytes is not a vector instruction). */
ORR_WIDE_VECTOR_CLONES
static void disc_batch(const galaxy *g, uint64_t seed_key, uint64_t first, int n, const particle_rows *out,
                       int64_t *restrict odd, int *restrict cell)
{
    const galaxy_spec *s = &g->s;
    const ln_table pot_grid = {g->pot_ln_rmin, g->pot_dln};
    const orr_vec3 e1 = g->e1, e2 = g->e2, spin = g->spin, c0 = g->centre, v0 = g->velocity;
    const double h = s->disc_hz, *nodes = &g->disc.node[0].vc2, *pull = &g->disc.pull[0][0], *pot = g->pot;
    const spheroids sph = spheroids_of(g);
    float *restrict x = out->x, *restrict y = out->y, *restrict z = out->z, *restrict vx = out->vx,
                    *restrict vy = out->vy, *restrict vz = out->vz, *restrict r = out->r, *restrict e0 = out->e0,
                    *restrict ez = out->ez;
#pragma omp simd
    for (int i = 0; i < n; i++) {
        uint64_t key = key_of(seed_key, first + (uint64_t)i);
        double surface = uniform_at(key, 0) * uniform_at(key, 1); /* exp(-R / Rd) */
        double R = -s->disc_rd * orr_log_poly(surface), sin_phi, cos_phi;
        orr_sincos_turn(uniform_at(key, 2), &sin_phi, &cos_phi);
        double u = uniform_at(key, 3);
        double layer = u < 0.5 ? 2.0 * u : 2.0 * (1.0 - u); /* exp(-|z| / h) */
        double ln_layer = h * orr_log_poly(layer), zz = u < 0.5 ? ln_layer : -ln_layer;
        orr_vec3 rhat = orr_v3_add(orr_v3_scale(e1, cos_phi), orr_v3_scale(e2, sin_phi));
        orr_vec3 that = orr_v3_cross(spin, rhat);
        orr_vec3 pos = orr_v3_add(c0, orr_v3_add(orr_v3_scale(rhat, R), orr_v3_scale(spin, zz)));
        double gr, gt, gz, unused;
        gauss_pair(key, 4, &gr, &gt);
        gauss_pair(key, 6, &gz, &unused);

        double Rs = R > 1e-3 ? R : 1e-3, fk, az = fabs(zz);
        int k = cell_of(Rs, DISC_NODE_BITS, &fk), pull_inside;
        disc_node nd = node_at(nodes, k, fk);
        double r2 = Rs * Rs + zz * zz, rs = sqrt(r2);
        double drop = MODEL_G * spheroid_mass(&sph, rs) * Rs * Rs / (rs * r2) - nd.gm_sph;
        double vr = nd.sigma_r * gr, mean2 = nd.vc2 + drop + nd.drift;
        double vphi = sqrt(mean2 > 0.0 ? mean2 : 0.0) + nd.sigma_phi * gt;
        double sheet = 2.0 * ORR_PI * g->g_sigma0 * surface * h;
        double sz2 = sheet * (1.0 - 0.5 * layer) + pull_in_table(pull, h, Rs, az, &pull_inside) - nd.radial * h * (az + h);
        double vzz = sqrt(sz2 > 1.0 ? sz2 : 1.0) * gz;
        orr_vec3 v = orr_v3_add(orr_v3_scale(rhat, vr), orr_v3_scale(that, vphi));
        orr_vec3 vel = orr_v3_add(v0, orr_v3_add(v, orr_v3_scale(spin, vzz)));

        double rad = sqrt(R * R + zz * zz), f_pot;
        int i_pot, in_pot = table_place(orr_log_poly(rad), pot_grid, POT_N, &i_pot, &f_pot);
        cell[i] = k;
        odd[i] = !((R <= s->disc_rmax) & (R > 1e-3) & pull_inside & in_pot &
                   (rad > POT_R_MIN) & (rad < s->halo_rmax));
        x[i] = (float)pos.x;
        y[i] = (float)pos.y;
        z[i] = (float)pos.z;
        vx[i] = (float)vel.x;
        vy[i] = (float)vel.y;
        vz[i] = (float)vel.z;
        r[i] = (float)rad;
        e0[i] = (float)(lerp_at(pot, i_pot, f_pot) + 0.5 * (vr * vr + vphi * vphi + vzz * vzz));
        ez[i] = orr_model_disc_ez(gz, az, h);
    }
}

/* Particle `index` by the one-particle sampler into slot i of the rows. */
static void draw_one(const galaxy *g, int comp, uint64_t seed_key, uint64_t index, const particle_rows *out, int i)
{
    orr_rng r = orr_rng_seed_keyed(seed_key, index, 0);
    particle p;
    if (comp == COMP_DISC)
        orr_model_galaxy_sample_disc_fast(g, &r, &p);
    else
        orr_model_galaxy_sample_sphere_fast(g, comp, &r, &p);
    out->x[i] = (float)p.pos.x;
    out->y[i] = (float)p.pos.y;
    out->z[i] = (float)p.pos.z;
    out->vx[i] = (float)p.vel.x;
    out->vy[i] = (float)p.vel.y;
    out->vz[i] = (float)p.vel.z;
    out->r[i] = p.r;
    out->e0[i] = p.e0;
    out->ez[i] = p.ez;
}

void orr_model_galaxy_sample_batch(const galaxy *g, int comp, uint64_t seed_key, uint64_t first, int n,
                                   const particle_rows *out)
{
    int64_t odd[ORR_MODEL_BATCH];
    if (comp == COMP_HALO) {
        halo_batch(g, seed_key, first, n, out, odd);
    } else if (comp == COMP_DISC) {
        int cell[ORR_MODEL_BATCH];
        disc_batch(g, seed_key, first, n, out, odd, cell);
        for (int i = 0; i < n; i++)
            odd[i] |= g->disc.exact[cell[i]];
    } else {
        bulge_batch(g, seed_key, first, n, out, odd);
    }
    for (int i = 0; i < n; i++)
        if (odd[i])
            draw_one(g, comp, seed_key, first + (uint64_t)i, out, i);
}
