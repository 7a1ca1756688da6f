/* The built-in "mw-m31" model: a Milky Way-like and an Andromeda-like galaxy
 * (exponential disc + Hernquist bulge + truncated Hernquist halo + central
 * black hole each) on an approach orbit, plus a Sun marker. docs/model.md
 * gives the numbers, their sources and the approximations made.
 *
 * Every particle is a pure function of (seed, index): particle i is drawn
 * from a counter-based generator keyed by (seed, i), never from a stream
 * shared between particles. Chunk size, rewinds and the order of next()
 * calls therefore cannot change the output. */
#include "source/model.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/vecmath.h"
#include "source/rng.h"

/* Gravitational constant in kpc (km/s)^2 per 1e10 Msun
 * (4.30091e-6 kpc (km/s)^2 / Msun). */
#define MODEL_G 4.30091e4

#define MODEL_PARTICLES_MIN 100
#define MODEL_MARKERS 3
#define MODEL_SEPARATION_MIN 10.0    /* kpc; below this the Sun is inside M31 */
#define MODEL_SEPARATION_MAX 10000.0 /* kpc; keeps float positions precise */

/* The Sun: 8 kpc from the centre on the -x axis, 20 pc above the plane. */
#define SUN_X (-8.0)
#define SUN_Z 0.02
#define SUN_MASS 1e-10 /* one solar mass: a tracer, dynamically irrelevant */

/* Direction of M31 from the Sun (galactic l, b in degrees). */
#define M31_L_DEG 121.17
#define M31_B_DEG (-21.57)
/* Spin axis of M31's disc (galactic l, b in degrees); illustrative, see
 * docs/model.md. It inclines the disc ~78 deg to our line of sight. */
#define M31_SPIN_L_DEG 240.0
#define M31_SPIN_B_DEG (-30.0)
/* Velocity of M31 relative to the MW (km/s): radial (negative = approaching)
 * and tangential (van der Marel et al. 2012). */
#define M31_VRAD (-110.0)
#define M31_VTAN 17.0

/* Disc velocity dispersion, as a fraction of the local circular speed, in
 * each of the radial, azimuthal and vertical directions. */
#define DISC_SIGMA_FRAC 0.10

/* Share of the non-marker particles per component kind, in percent. Stars
 * get more particles than their mass share so discs and bulges are well
 * sampled; the halos (most of the mass) get heavier particles. */
#define SHARE_DISC 45
#define SHARE_BULGE 15 /* the halos take the rest, 40 */

/* Jeans table: sigma(r) on a grid uniform in ln r from JEANS_R_MIN to the
 * truncation radius. */
#define JEANS_N 512
#define JEANS_R_MIN 1e-3

/* Potential table: Phi(r) on a grid uniform in ln r from POT_R_MIN to the
 * halo's truncation radius (the outermost of the galaxy's components). */
#define POT_N 1024
#define POT_R_MIN 1e-3

enum { COMP_DISC, COMP_BULGE, COMP_HALO, COMP_COUNT };
enum { GAL_MW, GAL_M31, GAL_COUNT };

/* The fixed description of one galaxy (masses in 1e10 Msun, lengths in kpc).
 * Component masses are the masses within the truncation radii: they are what
 * the particles of that component add up to. */
typedef struct galaxy_spec {
    double disc_mass, disc_rd, disc_hz, disc_rmax;
    double bulge_mass, bulge_a, bulge_rmax;
    double halo_mass, halo_a, halo_rmax;
    double bh_mass;
} galaxy_spec;

static const galaxy_spec SPEC[GAL_COUNT] = {
    /* Milky Way */
    {5.0, 3.0, 0.3, 25.0, 1.0, 0.6, 10.0, 100.0, 33.0, 250.0, 4.3e-4},
    /* Andromeda */
    {7.0, 5.0, 0.4, 40.0, 2.5, 1.0, 15.0, 150.0, 35.0, 300.0, 1.4e-2},
};

typedef struct galaxy {
    galaxy_spec s;
    /* Fractions of the untruncated profiles' mass inside the truncation
     * radii: the inverse CDFs and enclosed masses are rescaled by them. */
    double disc_frac, bulge_frac, halo_frac;
    orr_vec3 centre, velocity;
    orr_vec3 e1, e2, spin; /* disc frame: e1 x e2 = spin (angular momentum) */
    double jeans_ln_rmin[COMP_COUNT], jeans_dln[COMP_COUNT];
    double sigma[COMP_COUNT][JEANS_N]; /* bulge and halo rows used */
    double pot_ln_rmin, pot_dln;
    double pot[POT_N]; /* spherically averaged potential, (km/s)^2 */
} galaxy;

/* A contiguous run of particle indices of one component of one galaxy. */
typedef struct block {
    uint64_t first, count;
    int gal, comp;
    float mass;
    uint8_t type;
} block;

typedef struct model_state {
    orr_model_params params;
    galaxy gal[GAL_COUNT];
    block blocks[GAL_COUNT * COMP_COUNT];
    uint64_t total, next_index;
} model_state;

/* Extra fields of every particle: velocity, the distance from its own
 * galaxy's centre and its specific binding energy there (for colours that
 * vary with radius or with how deeply bound a star is). */
#define MODEL_FIELDS 5
static const char *const FIELD_NAMES[MODEL_FIELDS] = {"vx", "vy", "vz", "r", "E0"};

typedef struct particle {
    orr_vec3 pos, vel;
    float mass;
    uint8_t type;
    float r;  /* distance from its galaxy's centre at generation (0 for markers) */
    float e0; /* specific binding energy in its galaxy at generation, (km/s)^2 (0 for markers) */
} particle;

/* ---- profiles ---------------------------------------------------------- */

/* Mass fraction of an exponential disc within cylindrical radius R. */
static double disc_cdf(double R, double rd)
{
    double x = R / rd;
    return 1.0 - (1.0 + x) * exp(-x);
}

/* Mass fraction of a Hernquist sphere within radius r. */
static double hernquist_cdf(double r, double a)
{
    double q = r / (r + a);
    return q * q;
}

/* Mass inside radius r, treating the disc as if spherical (its mass within
 * cylindrical radius r placed inside sphere r). This is the usual quick
 * estimate; the true thin-disc circular speed differs by ~10-15%. */
static double enclosed_mass(const galaxy *g, double r)
{
    const galaxy_spec *s = &g->s;
    double m = s->bh_mass;
    m += r >= s->disc_rmax ? s->disc_mass : s->disc_mass * disc_cdf(r, s->disc_rd) / g->disc_frac;
    m += r >= s->bulge_rmax ? s->bulge_mass
                            : s->bulge_mass * hernquist_cdf(r, s->bulge_a) / g->bulge_frac;
    m += r >= s->halo_rmax ? s->halo_mass : s->halo_mass * hernquist_cdf(r, s->halo_a) / g->halo_frac;
    return m;
}

static double circular_speed(const galaxy *g, double r)
{
    return r > 0 ? sqrt(MODEL_G * enclosed_mass(g, r) / r) : 0.0;
}

/* Hernquist density up to a constant (the constant cancels in sigma^2). */
static double hernquist_shape(double r, double a)
{
    double ra = r + a;
    return 1.0 / (r * ra * ra * ra);
}

/* ---- Jeans dispersion tables ------------------------------------------ */

/* Isotropic spherical Jeans equation for a component of density rho inside
 * the galaxy's total (spherically approximated) mass:
 *   sigma^2(r) = 1/rho(r) * integral_r^rmax rho(r') G M(<r') / r'^2 dr'.
 * Integrated inward with the trapezoid rule in ln r, which keeps the steep
 * inner profile accurate on a modest grid. sigma vanishes at the truncation
 * radius, as the Jeans equation for a truncated component implies. */
static void build_jeans_table(galaxy *g, int comp, double a, double rmax)
{
    double ln_lo = log(JEANS_R_MIN), dln = (log(rmax) - ln_lo) / (JEANS_N - 1);
    double integrand[JEANS_N], rho[JEANS_N];
    for (int j = 0; j < JEANS_N; j++) {
        double r = exp(ln_lo + j * dln);
        rho[j] = hernquist_shape(r, a);
        /* dr = r d(ln r) */
        integrand[j] = rho[j] * MODEL_G * enclosed_mass(g, r) / r;
    }
    double acc = 0.0;
    g->sigma[comp][JEANS_N - 1] = 0.0;
    for (int j = JEANS_N - 2; j >= 0; j--) {
        acc += 0.5 * (integrand[j] + integrand[j + 1]) * dln;
        g->sigma[comp][j] = sqrt(acc / rho[j]);
    }
    g->jeans_ln_rmin[comp] = ln_lo;
    g->jeans_dln[comp] = dln;
}

/* sigma(r) by linear interpolation in ln r; clamped at the table ends. */
static double jeans_sigma(const galaxy *g, int comp, double r)
{
    const double *tab = g->sigma[comp];
    if (r <= JEANS_R_MIN)
        return tab[0];
    double t = (log(r) - g->jeans_ln_rmin[comp]) / g->jeans_dln[comp];
    int j = (int)t;
    if (j >= JEANS_N - 1)
        return tab[JEANS_N - 1];
    double f = t - j;
    return tab[j] + f * (tab[j + 1] - tab[j]);
}

/* ---- potential table -------------------------------------------------- */

/* The galaxy's spherically averaged potential from its own enclosed mass:
 *   Phi(r) = -G M(rmax) / rmax - G integral_r^rmax M(r') / r'^2 dr',
 * with rmax the halo's truncation radius (all the mass is inside it).
 * Integrated inward with the trapezoid rule in ln r (dr = r d ln r), as the
 * Jeans tables are. */
static void build_potential_table(galaxy *g)
{
    double rmax = g->s.halo_rmax;
    double ln_lo = log(POT_R_MIN), dln = (log(rmax) - ln_lo) / (POT_N - 1);
    double integrand[POT_N];
    for (int j = 0; j < POT_N; j++) {
        double r = exp(ln_lo + j * dln);
        integrand[j] = MODEL_G * enclosed_mass(g, r) / r;
    }
    double phi = -MODEL_G * enclosed_mass(g, rmax) / rmax;
    g->pot[POT_N - 1] = phi;
    for (int j = POT_N - 2; j >= 0; j--) {
        phi -= 0.5 * (integrand[j] + integrand[j + 1]) * dln;
        g->pot[j] = phi;
    }
    g->pot_ln_rmin = ln_lo;
    g->pot_dln = dln;
}

/* Phi(r) by linear interpolation in ln r. Outside the truncation radius the
 * galaxy is a point mass; inside POT_R_MIN (1 pc) the value at 1 pc is kept
 * (the black hole's -G M / r would diverge). */
static double potential(const galaxy *g, double r)
{
    if (r >= g->s.halo_rmax)
        return -MODEL_G * enclosed_mass(g, r) / r;
    if (r <= POT_R_MIN)
        return g->pot[0];
    double t = (log(r) - g->pot_ln_rmin) / g->pot_dln;
    int j = (int)t;
    if (j >= POT_N - 1)
        return g->pot[POT_N - 1];
    double f = t - j;
    return g->pot[j] + f * (g->pot[j + 1] - g->pot[j]);
}

/* ---- geometry ---------------------------------------------------------- */

/* Unit vector towards galactic longitude l, latitude b (degrees) in the
 * model frame: +x to l = 0, +y to l = 90, +z to the north galactic pole. */
static orr_vec3 galactic_direction(double l_deg, double b_deg)
{
    double l = l_deg * ORR_PI / 180.0, b = b_deg * ORR_PI / 180.0;
    return orr_v3(cos(b) * cos(l), cos(b) * sin(l), sin(b));
}

/* A right-handed disc frame (e1, e2, spin) for a given spin axis. */
static void set_disc_frame(galaxy *g, orr_vec3 spin, orr_vec3 hint)
{
    g->spin = orr_v3_normalize(spin);
    g->e1 = orr_v3_normalize(orr_v3_cross(hint, g->spin));
    g->e2 = orr_v3_cross(g->spin, g->e1);
}

/* M31's centre: along the direction of M31 seen from the Sun, at the
 * distance D from the Sun for which |sun + D d| = separation (the positive
 * root of D^2 + 2 D (sun.d) + |sun|^2 - sep^2 = 0). */
static orr_vec3 m31_centre(double separation)
{
    orr_vec3 sun = orr_v3(SUN_X, 0.0, SUN_Z);
    orr_vec3 d = galactic_direction(M31_L_DEG, M31_B_DEG);
    double sd = orr_v3_dot(sun, d);
    double dist = -sd + sqrt(sd * sd - orr_v3_dot(sun, sun) + separation * separation);
    return orr_v3_add(sun, orr_v3_scale(d, dist));
}

static double galaxy_mass(const galaxy_spec *s)
{
    return s->disc_mass + s->bulge_mass + s->halo_mass + s->bh_mass;
}

/* Places M31 and gives both galaxies bulk velocities with zero total
 * momentum. The tangential direction is illustrative (the measured
 * tangential velocity has no well-constrained direction): it makes the
 * orbital angular momentum prograde with respect to the Milky Way's spin. */
static void set_orbit(model_state *m)
{
    galaxy *mw = &m->gal[GAL_MW], *m31 = &m->gal[GAL_M31];
    mw->centre = orr_v3(0, 0, 0);
    m31->centre = m31_centre(m->params.separation_kpc);
    orr_vec3 rhat = orr_v3_normalize(m31->centre);
    orr_vec3 that = orr_v3_normalize(orr_v3_cross(mw->spin, rhat));
    orr_vec3 vrel = orr_v3_add(orr_v3_scale(rhat, M31_VRAD), orr_v3_scale(that, M31_VTAN));
    double m_mw = galaxy_mass(&mw->s), m_m31 = galaxy_mass(&m31->s), mt = m_mw + m_m31;
    mw->velocity = orr_v3_scale(vrel, -m_m31 / mt);
    m31->velocity = orr_v3_scale(vrel, m_mw / mt);
}

static void init_galaxy(galaxy *g, const galaxy_spec *s)
{
    g->s = *s;
    g->disc_frac = disc_cdf(s->disc_rmax, s->disc_rd);
    g->bulge_frac = hernquist_cdf(s->bulge_rmax, s->bulge_a);
    g->halo_frac = hernquist_cdf(s->halo_rmax, s->halo_a);
}

static void init_galaxies(model_state *m)
{
    init_galaxy(&m->gal[GAL_MW], &SPEC[GAL_MW]);
    init_galaxy(&m->gal[GAL_M31], &SPEC[GAL_M31]);
    /* The Milky Way's angular momentum points to -z (clockwise seen from the
     * north galactic pole): the Sun at -x moves towards +y. */
    set_disc_frame(&m->gal[GAL_MW], orr_v3(0, 0, -1), orr_v3(0, 1, 0));
    set_disc_frame(&m->gal[GAL_M31], galactic_direction(M31_SPIN_L_DEG, M31_SPIN_B_DEG),
                   orr_v3(0, 0, 1));
    set_orbit(m);
    for (int i = 0; i < GAL_COUNT; i++) {
        galaxy *g = &m->gal[i];
        build_jeans_table(g, COMP_BULGE, g->s.bulge_a, g->s.bulge_rmax);
        build_jeans_table(g, COMP_HALO, g->s.halo_a, g->s.halo_rmax);
        build_potential_table(g);
    }
}

/* ---- particle split ---------------------------------------------------- */

static double comp_mass(const galaxy_spec *s, int comp)
{
    return comp == COMP_DISC ? s->disc_mass : comp == COMP_BULGE ? s->bulge_mass : s->halo_mass;
}

static uint8_t comp_type(int comp)
{
    return comp == COMP_DISC ? ORR_MODEL_TYPE_DISC
           : comp == COMP_BULGE ? ORR_MODEL_TYPE_BULGE
                                : ORR_MODEL_TYPE_HALO;
}

/* Particles of one component kind for the Milky Way, the rest going to M31:
 * in proportion to the two component masses, at least one each. */
static uint64_t mw_share(uint64_t n, double m_mw, double m_m31)
{
    double k = floor((double)n * m_mw / (m_mw + m_m31) + 0.5);
    if (k < 1)
        k = 1;
    if (k > (double)(n - 1))
        k = (double)(n - 1);
    return (uint64_t)k;
}

/* Blocks in id order: MW disc, bulge, halo, then M31 disc, bulge, halo. */
static void split_particles(model_state *m)
{
    uint64_t rest = m->total - MODEL_MARKERS;
    uint64_t kind[COMP_COUNT];
    kind[COMP_DISC] = rest * SHARE_DISC / 100;
    kind[COMP_BULGE] = rest * SHARE_BULGE / 100;
    kind[COMP_HALO] = rest - kind[COMP_DISC] - kind[COMP_BULGE];
    uint64_t first = MODEL_MARKERS;
    for (int gi = 0; gi < GAL_COUNT; gi++) {
        for (int c = 0; c < COMP_COUNT; c++) {
            uint64_t n_mw = mw_share(kind[c], comp_mass(&SPEC[GAL_MW], c), comp_mass(&SPEC[GAL_M31], c));
            block *b = &m->blocks[gi * COMP_COUNT + c];
            b->count = gi == GAL_MW ? n_mw : kind[c] - n_mw;
            b->first = first;
            b->gal = gi;
            b->comp = c;
            b->type = comp_type(c);
            b->mass = (float)(comp_mass(&SPEC[gi], c) / (double)b->count);
            first += b->count;
        }
    }
}

/* ---- sampling ---------------------------------------------------------- */

/* Exponential surface density: R = -Rd ln(u1 u2) samples the Gamma(2)
 * distribution R e^(-R/Rd) exactly; radii beyond the truncation are redrawn
 * from further values of the particle's own sequence (rare: 0.2% for the
 * MW). Vertical: exponential profile, z = -/+ hz ln(2u) on each side. */
static void sample_disc(const galaxy *g, orr_rng *r, particle *p)
{
    const galaxy_spec *s = &g->s;
    double R;
    do
        R = -s->disc_rd * log(orr_rng_uniform(r) * orr_rng_uniform(r));
    while (R > s->disc_rmax);
    double phi = 2.0 * ORR_PI * orr_rng_uniform(r);
    double u = orr_rng_uniform(r);
    double z = u < 0.5 ? s->disc_hz * log(2.0 * u) : -s->disc_hz * log(2.0 * (1.0 - u));

    orr_vec3 rhat = orr_v3_add(orr_v3_scale(g->e1, cos(phi)), orr_v3_scale(g->e2, sin(phi)));
    orr_vec3 that = orr_v3_cross(g->spin, rhat); /* direction of rotation */
    p->pos = orr_v3_add(g->centre, orr_v3_add(orr_v3_scale(rhat, R), orr_v3_scale(g->spin, z)));

    double vc = circular_speed(g, R), sigma = DISC_SIGMA_FRAC * vc;
    double gr, gt, gz, unused;
    orr_rng_gauss2(r, &gr, &gt);
    orr_rng_gauss2(r, &gz, &unused);
    orr_vec3 v = orr_v3_add(orr_v3_scale(rhat, sigma * gr), orr_v3_scale(that, vc + sigma * gt));
    p->vel = orr_v3_add(g->velocity, orr_v3_add(v, orr_v3_scale(g->spin, sigma * gz)));
}

/* Hernquist sphere truncated at rmax: the inverse CDF r = a s / (1 - s),
 * s = sqrt(u), with u scaled to (0, F(rmax)) so no redraw is needed.
 * Isotropic direction; isotropic Gaussian velocity with the Jeans sigma. */
static void sample_sphere(const galaxy *g, int comp, orr_rng *r, particle *p)
{
    double a = comp == COMP_BULGE ? g->s.bulge_a : g->s.halo_a;
    double frac = comp == COMP_BULGE ? g->bulge_frac : g->halo_frac;
    double sq = sqrt(orr_rng_uniform(r) * frac);
    double rad = a * sq / (1.0 - sq);
    double cost = 2.0 * orr_rng_uniform(r) - 1.0, sint = sqrt(fmax(0.0, 1.0 - cost * cost));
    double phi = 2.0 * ORR_PI * orr_rng_uniform(r);
    orr_vec3 dir = orr_v3(sint * cos(phi), sint * sin(phi), cost);
    p->pos = orr_v3_add(g->centre, orr_v3_scale(dir, rad));

    double sigma = jeans_sigma(g, comp, rad);
    double g0, g1, g2, unused;
    orr_rng_gauss2(r, &g0, &g1);
    orr_rng_gauss2(r, &g2, &unused);
    p->vel = orr_v3_add(g->velocity, orr_v3_scale(orr_v3(g0, g1, g2), sigma));
}

/* Index 0, 1, 2: the MW black hole, M31's black hole and the Sun. */
static void make_marker(const model_state *m, uint64_t index, particle *p)
{
    const galaxy *mw = &m->gal[GAL_MW];
    if (index < 2) {
        const galaxy *g = &m->gal[index];
        p->pos = g->centre;
        p->vel = g->velocity;
        p->mass = (float)g->s.bh_mass;
        p->type = ORR_MODEL_TYPE_BH;
        return;
    }
    /* The Sun: on a circular orbit in the MW disc, no random motion. */
    orr_vec3 rhat = orr_v3(-1, 0, 0);
    p->pos = orr_v3(SUN_X, 0.0, SUN_Z);
    p->vel = orr_v3_add(mw->velocity,
                        orr_v3_scale(orr_v3_cross(mw->spin, rhat), circular_speed(mw, -SUN_X)));
    p->mass = (float)SUN_MASS;
    p->type = ORR_MODEL_TYPE_SUN;
}

static const block *find_block(const model_state *m, uint64_t index)
{
    int nb = GAL_COUNT * COMP_COUNT;
    for (int b = 0; b < nb - 1; b++)
        if (index < m->blocks[b].first + m->blocks[b].count)
            return &m->blocks[b];
    return &m->blocks[nb - 1];
}

/* Particle `index` (0-based; its id is index + 1), from nothing but the
 * seed and the index. */
static void make_particle(const model_state *m, uint64_t index, particle *p)
{
    if (index < MODEL_MARKERS) {
        make_marker(m, index, p);
        p->r = 0.0f;
        p->e0 = 0.0f;
        return;
    }
    const block *b = find_block(m, index);
    const galaxy *g = &m->gal[b->gal];
    orr_rng r = orr_rng_seed(m->params.seed, index, 0);
    if (b->comp == COMP_DISC)
        sample_disc(g, &r, p);
    else
        sample_sphere(g, b->comp, &r, p);
    p->mass = b->mass;
    p->type = b->type;
    double rad = orr_v3_norm(orr_v3_sub(p->pos, g->centre));
    orr_vec3 v = orr_v3_sub(p->vel, g->velocity);
    p->r = (float)rad;
    p->e0 = (float)(potential(g, rad) + 0.5 * orr_v3_dot(v, v));
}

/* ---- the source -------------------------------------------------------- */

static orr_status model_next(orr_source *src, orr_error *err)
{
    (void)err;
    model_state *m = src->state;
    orr_chunk *c = &src->chunk;
    uint64_t left = m->total - m->next_index;
    size_t n = left < c->capacity ? (size_t)left : c->capacity;
    c->first_index = m->next_index;
    for (size_t k = 0; k < n; k++) {
        uint64_t index = m->next_index + k;
        particle p;
        make_particle(m, index, &p);
        c->x[k] = (float)p.pos.x;
        c->y[k] = (float)p.pos.y;
        c->z[k] = (float)p.pos.z;
        c->mass[k] = p.mass;
        c->id[k] = index + 1;
        c->type[k] = p.type;
        c->extra[0].data[k] = (float)p.vel.x;
        c->extra[1].data[k] = (float)p.vel.y;
        c->extra[2].data[k] = (float)p.vel.z;
        c->extra[3].data[k] = p.r;
        c->extra[4].data[k] = p.e0;
    }
    c->n = n;
    m->next_index += n;
    return ORR_OK;
}

static orr_status model_rewind(orr_source *src, orr_error *err)
{
    (void)err;
    ((model_state *)src->state)->next_index = 0;
    return ORR_OK;
}

static void model_close(orr_source *src)
{
    free(src->state);
    src->state = NULL;
}

/* Every particle is a pure function of its index: skipping costs nothing. */
static orr_status model_skip_chunk(orr_source *src, orr_error *err)
{
    (void)err;
    model_state *m = src->state;
    uint64_t left = m->total - m->next_index;
    m->next_index += left < src->chunk.capacity ? left : src->chunk.capacity;
    return ORR_OK;
}

static const orr_source_ops MODEL_OPS = {
    .next = model_next, .rewind = model_rewind, .close = model_close, .skip_chunk = model_skip_chunk};

static orr_status check_params(const orr_model_params *params, size_t chunk_size, orr_error *err)
{
    if (!params)
        return orr_fail(err, ORR_ERR_USAGE, "model: no parameters given");
    if (params->particles < MODEL_PARTICLES_MIN || params->particles > ORR_MODEL_PARTICLES_MAX)
        return orr_fail(err, ORR_ERR_USAGE,
                        "model: %lld particles requested; the mw-m31 model needs %d to %lld "
                        "(3 of them are the Sun and black-hole markers)",
                        params->particles, MODEL_PARTICLES_MIN, (long long)ORR_MODEL_PARTICLES_MAX);
    if (!(params->separation_kpc >= MODEL_SEPARATION_MIN && params->separation_kpc <= MODEL_SEPARATION_MAX))
        return orr_fail(err, ORR_ERR_USAGE,
                        "model: separation %g kpc is out of range (%g to %g kpc; 780 is today's "
                        "Milky Way-Andromeda distance)",
                        params->separation_kpc, MODEL_SEPARATION_MIN, MODEL_SEPARATION_MAX);
    if (chunk_size == 0)
        return orr_fail(err, ORR_ERR_USAGE, "model: chunk size must be at least 1 particle");
    return ORR_OK;
}

static void fill_info(orr_source_info *info, const orr_model_params *params)
{
    snprintf(info->format, sizeof info->format, "model:mw-m31");
    snprintf(info->path, sizeof info->path,
             "built-in model mw-m31 (N=%lld, seed=%llu, separation=%g kpc)", params->particles,
             (unsigned long long)params->seed, params->separation_kpc);
    info->count = params->particles;
    info->time = 0.0;
    info->has_h = 0;
    info->has_id = 1;
    info->has_type = 1;
    info->nextra = MODEL_FIELDS;
    for (int i = 0; i < MODEL_FIELDS; i++)
        snprintf(info->extra_names[i], sizeof info->extra_names[i], "%s", FIELD_NAMES[i]);
}

orr_status orr_model_source_open(const orr_model_params *params, size_t chunk_size, orr_source **out,
                                 orr_error *err)
{
    *out = NULL;
    orr_status st = check_params(params, chunk_size, err);
    if (st != ORR_OK)
        return st;
    orr_source *src = orr_source_new("model", "", &MODEL_OPS, sizeof(model_state), err);
    if (!src)
        return ORR_ERR_NOMEM;
    model_state *m = src->state;
    m->params = *params;
    m->total = (uint64_t)params->particles;
    init_galaxies(m);
    split_particles(m);
    fill_info(&src->info, params);

    size_t cap = (uint64_t)chunk_size < m->total ? chunk_size : (size_t)m->total;
    st = orr_chunk_alloc(&src->chunk, cap, 0, FIELD_NAMES, MODEL_FIELDS, err);
    if (st != ORR_OK) {
        orr_source_close(src);
        return st;
    }
    *out = src;
    return ORR_OK;
}
