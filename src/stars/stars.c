/* Stars spawned from particles (stars/stars.h). */
#include "stars/stars.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "core/colourimetry.h"
#include "particles/population.h"
#include "stars/kernel_flux.h"

/* The colour table's B-V range: O stars to late M dwarfs. */
#define BV_FIRST (-0.35)
#define BV_STEP (2.55 / 255.0)
/* A particle's stars are searched as if they were no nearer the observer
 * than this, parsecs: its stars too faint to be seen from here stay in its
 * glow even where one falls nearer (a red dwarf within 10 pc), which keeps
 * the draws of a particle around the observer to those of M_V < limit. */
#define NEAREST_SEARCH_PC 10.0
/* Kernel sigmas a particle's stars are searched beyond its distance. */
#define SEARCH_SIGMAS 3.0
/* Salt of the stars' draws, so they are unrelated to the populations'. */
#define STARS_SALT 0x53746172734c4655ull

void orr_stars_defaults(orr_stars_settings *s)
{
    memset(s, 0, sizeof *s);
    s->limit = 8.0;
    s->light_unit = 1.0;
    s->glow_max_deg = 30.0;
    s->mass_unit = 1e10;
    s->length_unit = 1000.0;
    s->seed = 1;
    s->max_stars = 2000000;
    s->list = 1;
}

void orr_star_batch_free(orr_star_batch *b)
{
    orr_chunk_free(&b->stars);
    for (int k = 0; k < 3; k++)
        free(b->xyz[k]);
    free(b->info);
    memset(b, 0, sizeof *b);
}

orr_status orr_stars_prepare(orr_stars *st, const orr_stars_settings *set, const char *path, orr_error *err)
{
    memset(st, 0, sizeof *st);
    st->set = *set;
    if (!isfinite(set->limit) || set->limit < -30 || set->limit > 30)
        return orr_fail(err, ORR_ERR_USAGE, "%s: stars.limit: %g is not an apparent V magnitude in [-30, 30]", path,
                        set->limit);
    if (!(set->light_unit > 0) || !isfinite(set->light_unit))
        return orr_fail(err, ORR_ERR_USAGE, "%s: stars.light_unit: %g solar V luminosities is not a positive number",
                        path, set->light_unit);
    if (!(set->mass_unit > 0) || !isfinite(set->mass_unit))
        return orr_fail(err, ORR_ERR_USAGE, "%s: stars.mass_unit: %g solar masses is not a positive number", path,
                        set->mass_unit);
    if (!(set->length_unit > 0) || !isfinite(set->length_unit))
        return orr_fail(err, ORR_ERR_USAGE, "%s: stars.length_unit: %g parsecs is not a positive number", path,
                        set->length_unit);
    if (!(set->spread >= 0) || !isfinite(set->spread))
        return orr_fail(err, ORR_ERR_USAGE, "%s: stars.spread: %g is not a length >= 0 (0: from each particle's mass)",
                        path, set->spread);
    if (!(set->glow_max_deg > 0) || !(set->glow_max_deg <= 90))
        return orr_fail(err, ORR_ERR_USAGE, "%s: stars.glow_max: %g degrees; give (0, 90]", path, set->glow_max_deg);
    if (set->max_stars < 1)
        return orr_fail(err, ORR_ERR_USAGE, "%s: stars.max: %lld; at least 1 star", path, set->max_stars);
    orr_lf_solar_neighbourhood(&st->lf);
    st->light_per_mass = orr_lf_light_per_mass(&st->lf);
    for (int k = 0; k < 256; k++) {
        double xyz[3];
        double t = orr_bv_to_teff(BV_FIRST + k * BV_STEP, ORR_BV_MAMAJEK);
        if (!orr_blackbody_xyz(t, ORR_CMF_CIE1931, xyz) || !(xyz[1] > 0))
            return orr_fail(err, ORR_ERR_INTERNAL, "stars: no blackbody colour at %g K", t);
        st->colour_xy[0][k] = (float)(xyz[0] / xyz[1]);
        st->colour_xy[1][k] = (float)(xyz[2] / xyz[1]);
    }
    return ORR_OK;
}

void orr_stars_begin_frame(orr_stars *st)
{
    st->drawn = 0;
    st->capped = 0;
}

/* ---- the draws: a pure function of (seed, particle id, star, slot) ---- */

static uint64_t particle_key(const orr_stars *st, uint64_t id)
{
    return orr_hash64(orr_hash64(id) ^ orr_hash64(st->set.seed ^ STARS_SALT));
}

/* Uniform in (0, 1): never 0, so its logarithm is finite. */
static double draw(uint64_t key, uint64_t slot)
{
    return ((double)(orr_hash64(key + slot) >> 11) + 0.5) * 0x1.0p-53;
}

/* Slots of star k's draws: its gap along the count, three for its offset,
 * one for its colour. */
#define SLOTS_PER_STAR 8

/* Two standard normal deviates from two uniforms (Box-Muller): the
 * pair's length and angle. */
static void normal_polar(double u1, double u2, double *r, double *phi)
{
    *r = sqrt(-2.0 * log(u1));
    *phi = 2.0 * 3.14159265358979323846 * u2;
}

static void normal_pair(double u1, double u2, double *a, double *b)
{
    double r, phi;
    normal_polar(u1, u2, &r, &phi);
    *a = r * cos(phi);
    *b = r * sin(phi);
}

/* normal_pair's first deviate alone, the same bits. */
static double normal_first(double u1, double u2)
{
    double r, phi;
    normal_polar(u1, u2, &r, &phi);
    return r * cos(phi);
}

/* Whether a star of absolute magnitude abs_v at least at_least_pc from the
 * eye is surely fainter than the limit: with a margin of a millionth, far
 * above the rounding of its distance, so a star this rejects is one the
 * exact test would reject. */
static int surely_too_faint(double abs_v, double at_least_pc, double limit)
{
    const double nearest = at_least_pc * (1.0 - 1e-6);
    return nearest > 0.01 && abs_v + 5.0 * log10(nearest / 10.0) > limit + 1e-6;
}

/* ---- the batch ---- */

/* Stars 0 .. n-1 of from into to, from star at on (to has room). */
static void copy_stars(orr_star_batch *to, size_t at, const orr_star_batch *from, size_t n)
{
    if (n == 0)
        return;
    memcpy(to->stars.x + at, from->stars.x, n * sizeof(float));
    memcpy(to->stars.y + at, from->stars.y, n * sizeof(float));
    memcpy(to->stars.z + at, from->stars.z, n * sizeof(float));
    memcpy(to->stars.mass + at, from->stars.mass, n * sizeof(float));
    memcpy(to->stars.id + at, from->stars.id, n * sizeof(uint64_t));
    memcpy(to->stars.type + at, from->stars.type, n);
    memcpy(to->info + at, from->info, n * sizeof *from->info);
    for (int k = 0; k < 3; k++)
        memcpy(to->xyz[k] + at, from->xyz[k], n * sizeof(float));
}

static orr_status grow_batch(orr_star_batch *b, size_t need, orr_error *err)
{
    if (need <= b->capacity)
        return ORR_OK;
    size_t cap = b->capacity ? b->capacity : 4096;
    while (cap < need)
        cap *= 2;
    orr_chunk bigger;
    if (orr_chunk_alloc(&bigger, cap, 0, NULL, 0, err))
        return ORR_ERR_NOMEM;
    float *xyz[3] = {NULL, NULL, NULL};
    orr_star_info *info = malloc(cap * sizeof *info);
    for (int k = 0; k < 3; k++)
        xyz[k] = malloc(cap * sizeof(float));
    if (!info || !xyz[0] || !xyz[1] || !xyz[2]) {
        orr_chunk_free(&bigger);
        free(info);
        for (int k = 0; k < 3; k++)
            free(xyz[k]);
        return orr_fail(err, ORR_ERR_NOMEM, "stars: out of memory for %zu spawned stars", cap);
    }
    size_t n = b->stars.n;
    orr_star_batch to = {bigger, {xyz[0], xyz[1], xyz[2]}, info, cap};
    copy_stars(&to, 0, b, n);
    orr_star_batch_free(b);
    b->stars = bigger;
    b->stars.n = n;
    for (int k = 0; k < 3; k++)
        b->xyz[k] = xyz[k];
    b->info = info;
    b->capacity = cap;
    return ORR_OK;
}

/* ---- one particle ---- */

/* The sigma of a particle of m solar masses' stars about it, parsecs: half
 * the spacing of such particles at the luminosity function's own density
 * (the solar neighbourhood's), 85 pc at 2.35e5 solar masses: neighbouring
 * particles' stars overlap, and the stars stay within the disc's thickness
 * (a wider sigma thins them in the plane, where the brightest are). */
static double kernel_sigma_pc(const orr_stars *st, double m)
{
    if (st->set.spread > 0)
        return st->set.spread * st->set.length_unit;
    return 0.5 * cbrt(m / st->lf.mass_density);
}

double orr_stars_kernel_length(const orr_stars *st, double mass)
{
    return 2.0 * kernel_sigma_pc(st, mass * st->set.mass_unit) / st->set.length_unit;
}

static void star_colour(const orr_stars *st, double bv, float *x_over_y, float *z_over_y)
{
    double pos = (bv - BV_FIRST) / BV_STEP;
    int k = pos <= 0 ? 0 : pos >= 255 ? 254 : (int)pos;
    double t = pos <= 0 ? 0 : pos >= 255 ? 1 : pos - k;
    *x_over_y = (float)(st->colour_xy[0][k] + t * (st->colour_xy[0][k + 1] - st->colour_xy[0][k]));
    *z_over_y = (float)(st->colour_xy[1][k] + t * (st->colour_xy[1][k + 1] - st->colour_xy[1][k]));
}

/* Particle i seen from eye: its distance and its kernel's sigma, parsecs,
 * the distance its stars are searched from and the faintest absolute
 * magnitude among them that could be seen one by one from there. */
typedef struct particle_seen {
    double r_pc, sigma_pc, nearest_pc, m_lim;
} particle_seen;

static particle_seen seen_from(const orr_stars *st, orr_vec3 eye, const orr_chunk *c, size_t i)
{
    particle_seen s;
    const orr_vec3 p = orr_v3(c->x[i], c->y[i], c->z[i]);
    s.r_pc = orr_v3_norm(orr_v3_sub(p, eye)) * st->set.length_unit;
    s.sigma_pc = kernel_sigma_pc(st, (double)c->mass[i] * st->set.mass_unit);
    const double nearest = s.r_pc - SEARCH_SIGMAS * s.sigma_pc;
    s.nearest_pc = nearest > NEAREST_SEARCH_PC ? nearest : NEAREST_SEARCH_PC;
    s.m_lim = st->set.limit - 5.0 * log10(s.nearest_pc / 10.0);
    return s;
}

/* Draws particle i's stars into out, at most room of them (*capped set
 * when a further one was due), *taken the light (Y) they took. */
static orr_status spawn_particle(const orr_stars *st, orr_vec3 eye, const orr_chunk *c, size_t i, float y_light,
                                 long long room, orr_star_batch *out, double *taken, int *capped, orr_error *err)
{
    const double pc = st->set.length_unit;
    /* The particle stands for the stars of m solar masses of the local
     * disc: as many as give its light (stars.light_unit). */
    const double m = (double)y_light * st->set.light_unit / st->light_per_mass;
    *taken = 0;
    if (!(m > 0) || !(c->mass[i] > 0))
        return ORR_OK;
    const orr_vec3 p = orr_v3(c->x[i], c->y[i], c->z[i]);
    const particle_seen seen = seen_from(st, eye, c, i);
    const double sigma = seen.sigma_pc;
    /* The faintest star of the particle that could be seen one by one. */
    const double m_lim = seen.m_lim;
    if (m_lim <= ORR_LF_M_BRIGHT)
        return ORR_OK;
    const double lambda = m * orr_lf_count_brighter(&st->lf, m_lim);
    const uint64_t key = particle_key(st, c->id[i]);
    const double per_light = 1.0 / st->set.light_unit; /* Y per solar luminosity */
    const size_t first = out->stars.n;
    double u = 0, given = 0;
    int lf_step = 0; /* where u / m last fell in the function's table: it only grows */
    for (uint32_t k = 0;; k++) {
        const uint64_t slot = (uint64_t)k * SLOTS_PER_STAR;
        u -= log(draw(key, slot));
        if (u > lambda)
            break;
        if ((long long)(out->stars.n - first) >= room) {
            *capped = 1;
            break;
        }
        double abs_v = orr_lf_magnitude_from(&st->lf, u / m, &lf_step), ox, oy;
        /* The height first: a star as far from the eye in z alone as would
         * make it too faint is rejected before the rest of its offset (most
         * of a heavy particle's candidates near the eye, each a sine, a
         * cosine and a logarithm saved). Its distance is at least that
         * height's, so the stars drawn are the same, bit for bit. */
        const double oz = normal_first(draw(key, slot + 3), draw(key, slot + 4));
        const double qz = p.z + oz * (sigma / pc);
        if (surely_too_faint(abs_v, fabs(qz - eye.z) * pc, st->set.limit))
            continue; /* its light stays in the glow, as below */
        normal_pair(draw(key, slot + 1), draw(key, slot + 2), &ox, &oy);
        const orr_vec3 q = orr_v3_add(p, orr_v3_scale(orr_v3(ox, oy, oz), sigma / pc));
        double d_pc = orr_v3_norm(orr_v3_sub(q, eye)) * pc;
        d_pc = d_pc > 0.01 ? d_pc : 0.01;
        const double v = abs_v + 5.0 * log10(d_pc / 10.0);
        if (v > st->set.limit)
            continue; /* too faint from here: its light stays in the glow */
        if (grow_batch(out, out->stars.n + 1, err))
            return ORR_ERR_NOMEM;
        const size_t n = out->stars.n++;
        const double w = per_light * orr_lf_luminosity(abs_v);
        const double bv = orr_lf_star_bv(abs_v, draw(key, slot + 5));
        float xy, zy;
        star_colour(st, bv, &xy, &zy);
        out->stars.x[n] = (float)q.x, out->stars.y[n] = (float)q.y, out->stars.z[n] = (float)q.z;
        out->stars.mass[n] = 0.0f;
        out->stars.id[n] = c->id[i];
        out->stars.type[n] = c->type[i];
        out->xyz[0][n] = (float)w * xy, out->xyz[1][n] = (float)w, out->xyz[2][n] = (float)w * zy;
        out->info[n] = (orr_star_info){abs_v, v, (float)bv, c->id[i], k};
        given += w;
    }
    /* Rarely a near particle's bright stars outshine it: they share its
     * light then, and nothing is left for its glow. */
    if (given > y_light) {
        const double scale = y_light / given;
        for (size_t n = first; n < out->stars.n; n++)
            for (int k = 0; k < 3; k++)
                out->xyz[k][n] = (float)(out->xyz[k][n] * scale);
        given = y_light;
    }
    *taken = given;
    return ORR_OK;
}

/* What a particle's stars leave of its light: its light less theirs, in
 * its own colour. */
static void leave_light(float *const *xyz, size_t i, double taken)
{
    if (taken <= 0)
        return;
    const float y = xyz[1][i];
    const double left = y - taken, keep = left > 0 ? left / y : 0.0;
    xyz[0][i] = (float)(xyz[0][i] * keep);
    xyz[2][i] = (float)(xyz[2][i] * keep);
    xyz[1][i] = (float)(left > 0 ? left : 0.0);
}

static int spawns_here(const orr_stars *st, uint64_t exclude_id, const orr_chunk *c, size_t i)
{
    return orr_stars_spawns(st, c->type[i]) && c->id[i] != exclude_id;
}

/* The chunk's particles one after another, stars.max counted as they come. */
static orr_status spawn_in_order(orr_stars *st, orr_vec3 eye, uint64_t exclude_id, const orr_chunk *c,
                                 float *const *xyz, orr_star_batch *out, orr_error *err)
{
    for (size_t i = 0; i < c->n; i++) {
        if (!spawns_here(st, exclude_id, c, i))
            continue;
        const size_t before = out->stars.n;
        double taken;
        int capped = 0;
        if (spawn_particle(st, eye, c, i, xyz[1][i], st->set.max_stars - st->drawn, out, &taken, &capped, err))
            return ORR_ERR_NOMEM;
        st->drawn += (long long)(out->stars.n - before);
        st->capped |= capped;
        leave_light(xyz, i, taken);
    }
    return ORR_OK;
}

/* Below this many particles a chunk is drawn on one thread. */
#define SPAWN_PARALLEL_MIN 4096
#define SPAWN_SHARES 64 /* a chunk's shares, each at least SPAWN_PARALLEL_MIN / SPAWN_SHARES particles */

/* The chunk's particles in SPAWN_SHARES contiguous shares, each into a
 * batch of its own, taken by the threads as they come free, then the
 * batches joined in the particles' order: the same stars, in the same
 * order, as spawn_in_order, whatever the threads. More shares than threads
 * because the work is uneven: a particle near the eye draws many
 * candidates, and the near particles of a chunk may sit together. If the
 * shares together reach what is left of stars.max (*redo), nothing is kept
 * and spawn_in_order counts it out instead (stars.max is a safety cap, two
 * million by default, not a frame's usual count). */
static orr_status spawn_on_threads(orr_stars *st, orr_vec3 eye, uint64_t exclude_id, const orr_chunk *c,
                                   float *const *xyz, orr_star_batch *out, int *redo, orr_error *err)
{
    const int nshares = SPAWN_SHARES;
    orr_star_batch *share = calloc((size_t)nshares, sizeof *share);
    double *taken = malloc(c->n * sizeof *taken);
    orr_error *share_err = calloc((size_t)nshares, sizeof *share_err);
    orr_status *share_st = calloc((size_t)nshares, sizeof *share_st);
    const long long room = st->set.max_stars - st->drawn;
    orr_status status = share && taken && share_err && share_st
                            ? ORR_OK
                            : orr_fail(err, ORR_ERR_NOMEM, "stars: out of memory for the threads' shares of %zu particles",
                                       c->n);
    /* The shares' stars so far. Once they fill the room the chunk is redone
     * in order, so a share stops there: at most the room and one particle's
     * stars a thread are held. */
    long long drawn_all = 0;
    if (status == ORR_OK) {
#pragma omp parallel for schedule(dynamic, 1)
        for (int t = 0; t < nshares; t++) {
            const size_t lo = c->n * (size_t)t / (size_t)nshares, hi = c->n * (size_t)(t + 1) / (size_t)nshares;
            int capped = 0;
            for (size_t i = lo; i < hi && !share_st[t] && !capped; i++) {
                long long so_far;
#pragma omp atomic read
                so_far = drawn_all;
                if (so_far >= room)
                    break;
                taken[i] = 0;
                if (!spawns_here(st, exclude_id, c, i))
                    continue;
                const size_t before = share[t].stars.n;
                share_st[t] = spawn_particle(st, eye, c, i, xyz[1][i], room - so_far, &share[t], &taken[i], &capped,
                                             &share_err[t]);
                const long long added = (long long)(share[t].stars.n - before);
#pragma omp atomic update
                drawn_all += added;
            }
        }
        size_t total = 0;
        for (int t = 0; t < nshares && status == ORR_OK; t++) {
            if (share_st[t])
                status = orr_fail(err, share_st[t], "%s", share_err[t].msg);
            total += share[t].stars.n;
        }
        *redo = status == ORR_OK && (long long)total >= room;
        if (status == ORR_OK && !*redo && (status = grow_batch(out, total, err)) == ORR_OK) {
            for (int t = 0; t < nshares; t++) {
                copy_stars(out, out->stars.n, &share[t], share[t].stars.n);
                out->stars.n += share[t].stars.n;
            }
            st->drawn += (long long)total;
            for (size_t i = 0; i < c->n; i++)
                leave_light(xyz, i, taken[i]);
        }
    }
    for (int t = 0; share && t < nshares; t++)
        orr_star_batch_free(&share[t]);
    free(share);
    free(taken);
    free(share_err);
    free(share_st);
    return status;
}

orr_status orr_stars_spawn(orr_stars *st, orr_vec3 eye, uint64_t exclude_id, const orr_chunk *c,
                           float *const *xyz, orr_star_batch *out, orr_error *err)
{
    out->stars.n = 0;
    int redo = 1;
    if (c->n >= SPAWN_PARALLEL_MIN && omp_get_max_threads() > 1) {
        orr_status s = spawn_on_threads(st, eye, exclude_id, c, xyz, out, &redo, err);
        if (s)
            return s;
    }
    return redo ? spawn_in_order(st, eye, exclude_id, c, xyz, out, err) : ORR_OK;
}

/* ---- the glow's flux (docs/sky.md, "The glow's flux") ---- */

/* What w(s) needs: the faintest magnitude searched and the limit. */
typedef struct drawn_share {
    const orr_stars *st;
    double m_lim;
} drawn_share;

/* The share of a particle's light in the stars drawn when they lie at s
 * parsecs from the observer: those brighter than m_lim (the draw takes no
 * others) whose apparent V from s reaches the limit. */
static double drawn_at(double s, const void *user)
{
    const drawn_share *d = user;
    if (!(s > 0))
        return orr_lf_light_brighter(&d->st->lf, d->m_lim) / d->st->light_per_mass;
    const double seen = d->st->set.limit - 5.0 * log10(s / 10.0);
    return orr_lf_light_brighter(&d->st->lf, seen < d->m_lim ? seen : d->m_lim) / d->st->light_per_mass;
}

/* The flux per unit of light of what particle i's stars leave, 1/pc^2: the
 * mean of 1/s^2 over its kernel of the stars not drawn. The stars drawn
 * are those that fall near enough to be seen, so those left lie farther
 * on average; with E[1/s^2] over the whole kernel the glow would count
 * the near side twice, once as stars and once in the glow. */
static double glow_inv_r2_pc(const orr_stars *st, const particle_seen *seen)
{
    const double all = orr_kernel_inv_r2(seen->r_pc, seen->sigma_pc);
    if (seen->m_lim <= ORR_LF_M_BRIGHT)
        return all; /* (no star of it is drawn) */
    /* No star is seen beyond the distance at which the brightest would be
     * at the limit; the share drawn has a kink where the search begins. */
    const double farthest = 10.0 * pow(10.0, 0.2 * (st->set.limit - ORR_LF_M_BRIGHT));
    const drawn_share d = {st, seen->m_lim};
    const orr_kernel_part drawn =
        orr_kernel_weighted(seen->r_pc, seen->sigma_pc, 0.0, farthest, seen->nearest_pc, drawn_at, &d);
    const double light_left = 1.0 - drawn.light, flux_left = all - drawn.flux;
    /* (When the stars take almost all of it the glow is nothing either way.) */
    if (!(light_left > 1e-9))
        return all;
    return flux_left > 0 ? flux_left / light_left : 0.0;
}

void orr_stars_glow_dimming(const orr_stars *st, orr_vec3 eye, const orr_chunk *c, float *dimming)
{
    const double pc2 = st->set.length_unit * st->set.length_unit;
    const long n = (long)c->n;
#pragma omp parallel for schedule(dynamic, 256)
    for (long i = 0; i < n; i++) {
        if (!orr_stars_spawns(st, c->type[i]))
            continue;
        const particle_seen seen = seen_from(st, eye, c, (size_t)i);
        dimming[i] = (float)(glow_inv_r2_pc(st, &seen) * pc2);
    }
}
