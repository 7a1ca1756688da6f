/* The built-in "mw-m31" model: a Milky Way-like and an Andromeda-like galaxy
 * (exponential disc + Hernquist bulge + truncated Hernquist halo + central
 * black hole each) on an approach orbit, plus a Sun marker; or one of the
 * two alone. Each galaxy is set up near equilibrium: bulge and halo
 * velocities from their Eddington distribution functions in the galaxy's
 * spherically averaged potential, disc velocities from the true circular
 * speed and epicyclic frequency with a Toomre Q profile, asymmetric drift
 * and a vertical dispersion matched to the scale height (the recipe of
 * Hernquist 1993, ApJS 86, 389). docs/model.md gives the numbers, their
 * sources and the approximations made.
 *
 * Every particle is a pure function of (seed, index): particle i is drawn
 * from a counter-based generator keyed by (seed, i), never from a stream
 * shared between particles. Chunk size, rewinds and the order of next()
 * calls therefore cannot change the output. */
#include "source/models/model.h"
#include "source/models/model_dust.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/vecmath.h"
#include "source/models/model_galaxy.h"

#define MODEL_PARTICLES_MIN 100
#define MODEL_MARKERS_MAX 3
#define MODEL_FIRST_ID 4 /* the first non-marker particle's id, whatever the markers */
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

#define DISC_Q_MAX ORR_MODEL_DISC_Q_MAX /* the largest disc_q accepted */

/* A halo particle weighs this many star (disc or bulge) particles. Equal
 * masses would leave only ~6% of the particles to the stars; 8 keeps a
 * third of them stars (5e4 disc particles in an isolated Milky Way of 2e5)
 * while cutting the halo particles' heating of the discs (which grows with
 * their mass; Lacey & Ostriker 1985) threefold from the previous 25. */
#define HALO_MASS_RATIO 8.0

enum { GAL_MW, GAL_M31, GAL_COUNT };

const galaxy_spec orr_model_galaxy_specs[GAL_COUNT] = {
    /* Milky Way */
    {5.0, 3.0, 0.3, 25.0, 1.0, 0.6, 10.0, 100.0, 33.0, 250.0, 4.3e-4},
    /* Andromeda */
    {7.0, 5.0, 0.4, 40.0, 2.5, 1.0, 15.0, 150.0, 35.0, 300.0, 1.4e-2},
};

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
    int ngal, gal_index[GAL_COUNT]; /* the galaxies present, in id order */
    int nmarkers;                   /* black holes of the galaxies present, the Sun with the MW */
    uint64_t marker_id[MODEL_MARKERS_MAX];
    block blocks[GAL_COUNT * COMP_COUNT];
    int nblocks;
    uint64_t total, next_index;
    unsigned pass_types;            /* this pass's types (orr_source_only_types; 0: all), until a rewind */
    uint64_t dust_first;            /* the first gas particle's index (= total without gas) */
    orr_model_dust dust;            /* the dusty gas discs (model_dust.h) */
    int exact;                      /* the per-particle recipe without tables (orr_model_source_open_exact) */
    uint64_t seed_key;              /* orr_rng_seed_key(params.seed) */
} model_state;

/* Extra fields of every particle: velocity, the distance from its own
 * galaxy's centre, its specific binding energy there (for colours that
 * vary with radius or with how deeply bound a star is) and a disc star's
 * vertical energy ez (for a thinner young disc; 0 off the discs). */
#define MODEL_FIELDS 6
static const char *const FIELD_NAMES[MODEL_FIELDS] = {"vx", "vy", "vz", "r", "E0", "ez"};

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

/* Which galaxies are present, and the marker particles: each present
 * galaxy's black hole, then the Sun when the Milky Way is there. Marker ids
 * are the well-known ones (1, 2, 3) whichever are present. */
static void choose_galaxies(model_state *m)
{
    int mode = m->params.galaxies;
    m->ngal = 0;
    m->nmarkers = 0;
    if (mode != ORR_MODEL_M31)
        m->gal_index[m->ngal++] = GAL_MW;
    if (mode != ORR_MODEL_MW)
        m->gal_index[m->ngal++] = GAL_M31;
    for (int k = 0; k < m->ngal; k++)
        m->marker_id[m->nmarkers++] = m->gal_index[k] == GAL_MW ? ORR_MODEL_ID_MW_BH : ORR_MODEL_ID_M31_BH;
    if (mode != ORR_MODEL_M31)
        m->marker_id[m->nmarkers++] = ORR_MODEL_ID_SUN;
}

/* Returns 0 on allocation failure. */
static int init_galaxies(model_state *m)
{
    double q = m->params.disc_q > 0 ? m->params.disc_q : ORR_MODEL_DISC_Q_DEFAULT;
    orr_model_galaxy_init(&m->gal[GAL_MW], &orr_model_galaxy_specs[GAL_MW], q);
    orr_model_galaxy_init(&m->gal[GAL_M31], &orr_model_galaxy_specs[GAL_M31], q);
    /* The Milky Way's angular momentum points to -z (clockwise seen from the
     * north galactic pole): the Sun at -x moves towards +y. */
    set_disc_frame(&m->gal[GAL_MW], orr_v3(0, 0, -1), orr_v3(0, 1, 0));
    set_disc_frame(&m->gal[GAL_M31], galactic_direction(M31_SPIN_L_DEG, M31_SPIN_B_DEG),
                   orr_v3(0, 0, 1));
    choose_galaxies(m);
    if (m->ngal == 2) {
        set_orbit(m);
    } else { /* alone: at rest at the origin, for isolation tests */
        galaxy *g = &m->gal[m->gal_index[0]];
        g->centre = orr_v3(0, 0, 0);
        g->velocity = orr_v3(0, 0, 0);
    }
    for (int k = 0; k < m->ngal; k++) {
        galaxy *g = &m->gal[m->gal_index[k]];
        orr_model_galaxy_build_potential(g);
        if (!orr_model_galaxy_build_dfs(g))
            return 0;
        if (!m->exact)
            orr_model_galaxy_build_disc_table(g);
    }
    return 1;
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

/* The pair's M31 particles weigh m31_weight times the Milky Way's of the
 * same kind (1 alone or when not set). */
static double galaxy_weight(const model_state *m, int gal)
{
    double w = m->params.m31_weight;
    return gal == GAL_M31 && m->ngal == 2 && w > 0 ? w : 1.0;
}

/* A component's claim on particles: its mass in units of its particle
 * mass (the Milky Way's star particles 1, its halo particles
 * HALO_MASS_RATIO, M31's those times galaxy_weight). */
static double comp_weight(const model_state *m, int gal, int comp)
{
    const galaxy_spec *s = &orr_model_galaxy_specs[gal];
    return comp_mass(s, comp) / (comp == COMP_HALO ? HALO_MASS_RATIO : 1.0) / galaxy_weight(m, gal);
}

/* Every block gets at least one particle: an empty one takes one from the
 * largest (N >= 100 leaves the largest far above one). */
static void ensure_nonempty(model_state *m)
{
    for (int b = 0; b < m->nblocks; b++) {
        if (m->blocks[b].count)
            continue;
        int big = 0;
        for (int k = 1; k < m->nblocks; k++)
            if (m->blocks[k].count > m->blocks[big].count)
                big = k;
        m->blocks[big].count--;
        m->blocks[b].count = 1;
    }
}

/* Blocks in id order: MW disc, bulge, halo, then M31 disc, bulge, halo (the
 * galaxies present). Counts are the cumulative rounding of the weights, so
 * they add up to exactly N minus the markers and particle masses are
 * equal within each kind up to one particle's rounding. */
static void split_particles(model_state *m)
{
    uint64_t rest = m->total - (uint64_t)m->nmarkers;
    double wsum = 0.0;
    for (int k = 0; k < m->ngal; k++)
        for (int c = 0; c < COMP_COUNT; c++)
            wsum += comp_weight(m, m->gal_index[k], c);
    double cum = 0.0;
    uint64_t prev = 0;
    m->nblocks = 0;
    for (int k = 0; k < m->ngal; k++) {
        for (int c = 0; c < COMP_COUNT; c++) {
            int gi = m->gal_index[k];
            cum += comp_weight(m, gi, c);
            uint64_t upto = (uint64_t)floor((double)rest * cum / wsum + 0.5);
            if (upto > rest)
                upto = rest;
            block *b = &m->blocks[m->nblocks++];
            b->count = upto - prev;
            b->gal = gi;
            b->comp = c;
            b->type = comp_type(c);
            prev = upto;
        }
    }
    m->blocks[m->nblocks - 1].count += rest - prev;
    ensure_nonempty(m);
    uint64_t first = (uint64_t)m->nmarkers;
    for (int b = 0; b < m->nblocks; b++) {
        block *bl = &m->blocks[b];
        bl->first = first;
        bl->mass = (float)(comp_mass(&orr_model_galaxy_specs[bl->gal], bl->comp) / (double)bl->count);
        first += bl->count;
    }
}

/* ---- particles -------------------------------------------------------- */

/* The markers: the black holes of the galaxies present, then the Sun. */
static void make_marker(const model_state *m, uint64_t index, particle *p)
{
    const galaxy *mw = &m->gal[GAL_MW];
    if (m->marker_id[index] != ORR_MODEL_ID_SUN) {
        const galaxy *g = &m->gal[m->marker_id[index] == ORR_MODEL_ID_MW_BH ? GAL_MW : GAL_M31];
        p->pos = g->centre;
        p->vel = g->velocity;
        p->mass = (float)g->s.bh_mass;
        p->type = ORR_MODEL_TYPE_BH;
        return;
    }
    /* The Sun: on the circular orbit of the MW's true potential in the disc
     * plane (disc_vc2), no random motion. */
    orr_vec3 rhat = orr_v3(-1, 0, 0);
    p->pos = orr_v3(SUN_X, 0.0, SUN_Z);
    p->vel = orr_v3_add(mw->velocity,
                        orr_v3_scale(orr_v3_cross(mw->spin, rhat), sqrt(orr_model_galaxy_disc_vc2(mw, -SUN_X))));
    p->mass = (float)SUN_MASS;
    p->type = ORR_MODEL_TYPE_SUN;
}

static const block *find_block(const model_state *m, uint64_t index)
{
    for (int b = 0; b < m->nblocks - 1; b++)
        if (index < m->blocks[b].first + m->blocks[b].count)
            return &m->blocks[b];
    return &m->blocks[m->nblocks - 1];
}

/* A particle's id: the markers' well-known ids, then MODEL_FIRST_ID on (so
 * with both galaxies, id = index + 1). */
static uint64_t particle_id(const model_state *m, uint64_t index)
{
    if (index < (uint64_t)m->nmarkers)
        return m->marker_id[index];
    return index - (uint64_t)m->nmarkers + MODEL_FIRST_ID;
}

/* Particle `index` (0-based), from nothing but the seed and the index. */
static void make_particle(const model_state *m, uint64_t index, particle *p)
{
    if (index < (uint64_t)m->nmarkers) {
        make_marker(m, index, p);
        p->r = 0.0f;
        p->e0 = 0.0f;
        p->ez = 0.0f;
        return;
    }
    const block *b = find_block(m, index);
    const galaxy *g = &m->gal[b->gal];
    orr_rng r = orr_rng_seed_keyed(m->seed_key, index, 0);
    p->mass = b->mass;
    p->type = b->type;
    if (!m->exact) {
        if (b->comp == COMP_DISC)
            orr_model_galaxy_sample_disc_fast(g, &r, p);
        else
            orr_model_galaxy_sample_sphere_fast(g, b->comp, &r, p);
        return;
    }
    if (b->comp == COMP_DISC)
        orr_model_galaxy_sample_disc(g, &r, p);
    else
        orr_model_galaxy_sample_sphere(g, b->comp, &r, p);
    double rad = orr_v3_norm(orr_v3_sub(p->pos, g->centre));
    orr_vec3 v = orr_v3_sub(p->vel, g->velocity);
    p->r = (float)rad;
    p->e0 = (float)(orr_model_galaxy_potential(g, rad) + 0.5 * orr_v3_dot(v, v));
}

/* The dusty gas discs (model_dust.c), appended after every other particle:
 * each galaxy's disc frame and circular speeds handed over. */
static void plan_dust(model_state *m, long long dust_particles)
{
    m->dust_first = m->total;
    orr_model_dust_init(&m->dust, (uint64_t)dust_particles, m->params.seed, m->params.dust_clumping);
    for (int k = 0; k < m->ngal && dust_particles > 0; k++) {
        const galaxy *g = &m->gal[m->gal_index[k]];
        orr_model_dust_disc *d =
            orr_model_dust_add(&m->dust, m->gal_index[k] == GAL_MW ? ORR_MODEL_DUST_MW : ORR_MODEL_DUST_M31);
        d->centre = g->centre;
        d->velocity = g->velocity;
        d->e1 = g->e1;
        d->e2 = g->e2;
        d->spin = g->spin;
        for (int i = 0; i < ORR_MODEL_DUST_VC_N; i++)
            d->vc[i] = sqrt(orr_model_galaxy_disc_vc2(g, d->rmax * i / (ORR_MODEL_DUST_VC_N - 1)));
    }
    orr_model_dust_split(&m->dust);
    m->total += m->dust.total;
}

static void make_gas(const model_state *m, uint64_t index, particle *p)
{
    orr_model_dust_make(&m->dust, index - m->dust_first, &p->pos, &p->vel, &p->mass, &p->r);
    p->type = ORR_MODEL_TYPE_GAS;
    p->e0 = 0.0f;
    p->ez = 0.0f;
}

/* ---- the source -------------------------------------------------------- */

/* Particle `index` into slot k of chunk c. */
static void fill_slot(const model_state *m, uint64_t index, orr_chunk *c, size_t k)
{
    particle p;
    if (index >= m->dust_first)
        make_gas(m, index, &p);
    else
        make_particle(m, index, &p);
    c->x[k] = (float)p.pos.x;
    c->y[k] = (float)p.pos.y;
    c->z[k] = (float)p.pos.z;
    c->mass[k] = p.mass;
    c->id[k] = particle_id(m, index);
    c->type[k] = p.type;
    c->extra[0].data[k] = (float)p.vel.x;
    c->extra[1].data[k] = (float)p.vel.y;
    c->extra[2].data[k] = (float)p.vel.z;
    c->extra[3].data[k] = p.r;
    c->extra[4].data[k] = p.e0;
    c->extra[5].data[k] = p.ez;
}

/* Slots k .. k + n - 1 of chunk c, particles index .. index + n - 1 of
 * one block (one component of one galaxy): drawn a batch at a time. */
static void fill_block_slots(const model_state *m, const block *b, uint64_t index, orr_chunk *c, size_t k, size_t n)
{
    const galaxy *g = &m->gal[b->gal];
    for (size_t done = 0; done < n;) {
        size_t at = k + done, count = n - done < ORR_MODEL_BATCH ? n - done : ORR_MODEL_BATCH;
        particle_rows rows = {c->x + at,
                              c->y + at,
                              c->z + at,
                              c->extra[0].data + at,
                              c->extra[1].data + at,
                              c->extra[2].data + at,
                              c->extra[3].data + at,
                              c->extra[4].data + at,
                              c->extra[5].data + at};
        orr_model_galaxy_sample_batch(g, b->comp, m->seed_key, index + done, (int)count, &rows);
        for (size_t i = at; i < at + count; i++) {
            c->mass[i] = b->mass;
            c->id[i] = particle_id(m, index + (i - k));
            c->type[i] = b->type;
        }
        done += count;
    }
}

/* Slots k .. k + n - 1 of chunk c, particles index .. index + n - 1: the
 * markers and the gas one by one, each block's run of the model's own
 * particles in batches (the exact recipe one by one). */
static void fill_slots(const model_state *m, uint64_t index, orr_chunk *c, size_t k, size_t n)
{
    while (n > 0) {
        size_t run = 1;
        if (!m->exact && index >= (uint64_t)m->nmarkers && index < m->dust_first) {
            const block *b = find_block(m, index);
            uint64_t left = b->first + b->count - index;
            run = left < n ? (size_t)left : n;
            fill_block_slots(m, b, index, c, k, run);
        } else {
            fill_slot(m, index, c, k);
        }
        index += run;
        k += run;
        n -= run;
    }
}

/* What becomes of the particles of a type: emitted, never made
 * (orr_model_params.types), or left out of this pass alone (pass_types,
 * orr_source_only_types; only the gas, `gas`), which the source counts.
 * The gas comes after every other particle, so leaving it out leaves the
 * chunks of the others as they were (a splat's blocks, so its sums); the
 * components' blocks lie between one another and are cheap to make. */
enum { RUN_EMITTED, RUN_NOT_MADE, RUN_LEFT_OUT };

static int type_fate(const model_state *m, uint8_t type, int gas)
{
    if (m->params.types != 0 && !(m->params.types >> type & 1u))
        return RUN_NOT_MADE;
    return !gas || m->pass_types == 0 || (type < 32 && (m->pass_types >> type & 1u)) ? RUN_EMITTED : RUN_LEFT_OUT;
}

/* The end of the run of indices from `index` that share their fate: the
 * markers (always emitted), one component's block, or the gas; *fate says
 * what becomes of it. */
static uint64_t run_end(const model_state *m, uint64_t index, int *fate)
{
    if (index < (uint64_t)m->nmarkers) {
        *fate = RUN_EMITTED;
        return (uint64_t)m->nmarkers;
    }
    if (index >= m->dust_first) {
        *fate = type_fate(m, ORR_MODEL_TYPE_GAS, 1);
        return m->total;
    }
    const block *b = find_block(m, index);
    *fate = type_fate(m, b->type, 0);
    return b->first + b->count;
}

/* The next chunk's indices, from next_index: past the runs not emitted
 * (those this pass leaves out counted into *left_out), then at most
 * `capacity` of the emitted runs that follow one another. A chunk's
 * indices stay contiguous (first_index names them), and with every type
 * emitted the chunks are those of a model without a type mask. Returns the
 * count and sets *first. */
static size_t next_range(const model_state *m, size_t capacity, uint64_t *first, uint64_t *left_out)
{
    uint64_t i = m->next_index, end = i;
    int fate = RUN_NOT_MADE;
    while (i < m->total && fate != RUN_EMITTED) {
        end = run_end(m, i, &fate);
        if (fate == RUN_LEFT_OUT)
            *left_out += end - i;
        if (fate != RUN_EMITTED)
            i = end;
    }
    *first = i;
    if (i >= m->total)
        return 0;
    while (end < m->total) {
        uint64_t more = run_end(m, end, &fate);
        if (fate != RUN_EMITTED)
            break;
        end = more;
    }
    return end - i < capacity ? (size_t)(end - i) : capacity;
}

/* How many particles the source emits in all. */
static uint64_t count_kept(const model_state *m)
{
    uint64_t n = 0;
    int fate;
    for (uint64_t i = 0, end; i < m->total; i = end) {
        end = run_end(m, i, &fate);
        if (fate == RUN_EMITTED)
            n += end - i;
    }
    return n;
}

/* Below this many particles a chunk is filled on one thread (a team costs
 * more than it saves). */
#define MODEL_PARALLEL_MIN 4096
/* A thread's share of a chunk: particles dealt out this many at a time. */
#define MODEL_SHARE 1024

/* Each particle is a pure function of its index, so the threads' shares,
 * and how many threads there are, cannot change a bit of the output. The
 * shares are dynamic: the components lie in long runs of indices and a disc
 * particle costs more than a halo one. */
static orr_status model_next(orr_source *src, orr_error *err)
{
    (void)err;
    model_state *m = src->state;
    orr_chunk *c = &src->chunk;
    uint64_t first;
    size_t n = next_range(m, c->capacity, &first, &src->left_out);
    c->first_index = first;
    size_t shares = (n + MODEL_SHARE - 1) / MODEL_SHARE;
#pragma omp parallel for schedule(dynamic, 1) if (n >= MODEL_PARALLEL_MIN)
    for (size_t s = 0; s < shares; s++) {
        size_t k = s * MODEL_SHARE;
        fill_slots(m, first + k, c, k, n - k < MODEL_SHARE ? n - k : MODEL_SHARE);
    }
    c->n = n;
    m->next_index = first + n;
    return ORR_OK;
}

static orr_status model_rewind(orr_source *src, orr_error *err)
{
    (void)err;
    model_state *m = src->state;
    m->next_index = 0;
    m->pass_types = 0;
    return ORR_OK;
}

/* Every particle is a pure function of its index, so leaving the gas out
 * (next_range skips it as it skips what params.types leaves out) changes
 * none of the others: a pass that drops the gas does not make it, 96 waves
 * of the clumping field a particle (model_dust.c). */
static void model_only_types(orr_source *src, unsigned mask)
{
    ((model_state *)src->state)->pass_types = mask;
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
    uint64_t first;
    size_t n = next_range(m, src->chunk.capacity, &first, &src->left_out);
    m->next_index = first + n;
    return ORR_OK;
}

static const orr_source_ops MODEL_OPS = {
    .next = model_next, .rewind = model_rewind, .close = model_close, .skip_chunk = model_skip_chunk,
    .only_types = model_only_types};

static orr_status check_params(const orr_model_params *params, size_t chunk_size, orr_error *err)
{
    if (!params)
        return orr_fail(err, ORR_ERR_USAGE, "model: no parameters given");
    if (params->particles < MODEL_PARTICLES_MIN || params->particles > ORR_MODEL_PARTICLES_MAX)
        return orr_fail(err, ORR_ERR_USAGE,
                        "model: %lld particles requested; the mw-m31 model needs %d to %lld "
                        "(3 of them are the Sun and black-hole markers)",
                        params->particles, MODEL_PARTICLES_MIN, (long long)ORR_MODEL_PARTICLES_MAX);
    if (params->galaxies == ORR_MODEL_PAIR && !(params->separation_kpc >= MODEL_SEPARATION_MIN && params->separation_kpc <= MODEL_SEPARATION_MAX))
        return orr_fail(err, ORR_ERR_USAGE,
                        "model: separation %g kpc is out of range (%g to %g kpc; 780 is today's "
                        "Milky Way-Andromeda distance)",
                        params->separation_kpc, MODEL_SEPARATION_MIN, MODEL_SEPARATION_MAX);
    if (params->galaxies != ORR_MODEL_PAIR && params->galaxies != ORR_MODEL_MW && params->galaxies != ORR_MODEL_M31)
        return orr_fail(err, ORR_ERR_USAGE, "model: galaxies = %d is not one of pair (0), mw (1), m31 (2)",
                        params->galaxies);
    /* 0 selects the default; anything else must be a positive finite Q. */
    if (params->disc_q != 0.0 && !(params->disc_q > 0.0 && params->disc_q <= DISC_Q_MAX))
        return orr_fail(err, ORR_ERR_USAGE,
                        "model: disc_q (the discs' Toomre Q) is %g; it must be above 0 (stable discs "
                        "need Q > 1; at most %g)",
                        params->disc_q, DISC_Q_MAX);
    /* 0 selects 1; a weight far from 1 would leave one galaxy a handful of particles. */
    if (params->m31_weight != 0.0 &&
        !(params->m31_weight >= 1.0 / ORR_MODEL_M31_WEIGHT_MAX && params->m31_weight <= ORR_MODEL_M31_WEIGHT_MAX))
        return orr_fail(err, ORR_ERR_USAGE,
                        "model: m31_weight (how many times the Milky Way's particles each of M31's weighs) is %g; "
                        "it must be from %g to %g",
                        params->m31_weight, 1.0 / ORR_MODEL_M31_WEIGHT_MAX, ORR_MODEL_M31_WEIGHT_MAX);
    if (chunk_size == 0)
        return orr_fail(err, ORR_ERR_USAGE, "model: chunk size must be at least 1 particle");
    return ORR_OK;
}

static void fill_info(orr_source_info *info, const orr_model_params *params)
{
    snprintf(info->format, sizeof info->format, "model:mw-m31");
    double q = params->disc_q > 0 ? params->disc_q : ORR_MODEL_DISC_Q_DEFAULT;
    char weight[64] = "";
    if (params->m31_weight > 0 && params->m31_weight != 1.0)
        snprintf(weight, sizeof weight, ", M31's particles %g x the Milky Way's", params->m31_weight);
    if (params->galaxies == ORR_MODEL_PAIR)
        snprintf(info->path, sizeof info->path,
                 "built-in model mw-m31 (N=%lld, seed=%llu, separation=%g kpc, disc Q=%g%s)", params->particles,
                 (unsigned long long)params->seed, params->separation_kpc, q, weight);
    else
        snprintf(info->path, sizeof info->path, "built-in model mw-m31 (N=%lld, seed=%llu, %s alone, disc Q=%g)",
                 params->particles, (unsigned long long)params->seed,
                 params->galaxies == ORR_MODEL_MW ? "Milky Way" : "M31", q);
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
    return orr_model_source_open_dust(params, 0, chunk_size, out, err);
}

/* The model's source, from its tables or (exact) by the per-particle recipe. */
static orr_status open_model(const orr_model_params *params, long long dust_particles, size_t chunk_size, int exact,
                             orr_source **out, orr_error *err)
{
    *out = NULL;
    orr_status st = check_params(params, chunk_size, err);
    if (!st && (dust_particles < 0 || dust_particles > ORR_MODEL_PARTICLES_MAX - params->particles))
        st = orr_fail(err, ORR_ERR_USAGE, "model: dust_particles = %lld: 0 (no dusty gas discs) to %lld",
                      dust_particles, (long long)ORR_MODEL_PARTICLES_MAX - params->particles);
    if (st != ORR_OK)
        return st;
    orr_source *src = orr_source_new("model", "", &MODEL_OPS, sizeof(model_state), err);
    if (!src)
        return ORR_ERR_NOMEM;
    model_state *m = src->state;
    m->params = *params;
    m->exact = exact;
    m->seed_key = orr_rng_seed_key(params->seed);
    m->total = (uint64_t)params->particles;
    if (!init_galaxies(m)) {
        orr_source_close(src);
        return orr_fail(err, ORR_ERR_NOMEM, "model: out of memory building the distribution functions");
    }
    split_particles(m);
    plan_dust(m, dust_particles);
    fill_info(&src->info, params);
    src->info.count = (int64_t)count_kept(m);

    size_t cap = (uint64_t)chunk_size < m->total ? chunk_size : (size_t)m->total;
    st = orr_chunk_alloc(&src->chunk, cap, 0, FIELD_NAMES, MODEL_FIELDS, err);
    if (st != ORR_OK) {
        orr_source_close(src);
        return st;
    }
    *out = src;
    return ORR_OK;
}

orr_status orr_model_source_open_dust(const orr_model_params *params, long long dust_particles, size_t chunk_size,
                                      orr_source **out, orr_error *err)
{
    return open_model(params, dust_particles, chunk_size, 0, out, err);
}

orr_status orr_model_source_open_exact(const orr_model_params *params, long long dust_particles, size_t chunk_size,
                                       orr_source **out, orr_error *err)
{
    return open_model(params, dust_particles, chunk_size, 1, out, err);
}

const orr_named orr_model_galaxies_names[] = {
    {"pair", ORR_MODEL_PAIR}, {"mw", ORR_MODEL_MW}, {"m31", ORR_MODEL_M31}, {NULL, 0}};

int orr_model_galaxies_named(const char *word)
{
    int g;
    return orr_named_value(orr_model_galaxies_names, word, &g) ? g : -1;
}
