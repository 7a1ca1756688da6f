/* Stars from particles (docs/sky.md, "Stars from particles"): each star
 * particle near the observer spawns the individual stars it stands for, as
 * Galaxia does from an N-body model (Sharma et al. 2011, ApJ 730, 3), and
 * keeps the rest of its light as a diffuse glow.
 *
 * A particle whose light (its population's Y weight) is L solar V
 * luminosities stands for the stars of L / (L/M) solar masses of the
 * solar neighbourhood (stars/luminosity.h: L/M = 1.29): its light, not its
 * mass, sets how many, so a model whose disc is denser than the Galaxy's
 * but whose light is the Galaxy's has the Galaxy's stars. Its stars are
 * a Poisson process along that function's cumulative count, brightest
 * first, drawn from the particle's id and stars.seed alone: the k-th star's
 * magnitude, colour and place in the particle's kernel are the same in
 * every frame, chunk and thread, so stars move with their particle and keep
 * their identity through a film. A frame draws those of a particle's stars
 * that the observer would see one by one (apparent V no fainter than
 * stars.limit, from each star's own distance), each with its own
 * luminosity taken from the particle's light; what is left of the particle's
 * light stays on the particle, so every particle's light is kept exactly.
 *
 * Positions are in the scene's length unit (stars.length_unit parsecs),
 * masses in its mass unit (stars.mass_unit solar masses), light in
 * stars.light_unit solar V luminosities. */
#ifndef ORR_STARS_STARS_H
#define ORR_STARS_STARS_H

#include <stddef.h>
#include <stdint.h>

#include "core/error.h"
#include "core/vecmath.h"
#include "particles/chunk.h"
#include "stars/luminosity.h"

/* The stars.* settings. */
typedef struct orr_stars_settings {
    int enabled;           /* stars.limit given */
    double limit;          /* stars.limit: the faintest apparent V drawn as a star */
    uint32_t types;        /* stars.types: the particle types that spawn stars (0: none) */
    double light_unit;     /* stars.light_unit: solar V luminosities per unit of the particles' Y */
    double mass_unit;      /* stars.mass_unit: solar masses per unit of mass (the kernel's size) */
    double length_unit;    /* stars.length_unit: parsecs per unit of length */
    double spread;         /* stars.spread: the kernel's sigma, length units; 0: from the mass */
    double glow_max_deg;   /* stars.glow_max: the widest glow (its h as an angle), degrees */
    uint64_t seed;         /* stars.seed */
    long long max_stars;   /* stars.max: at most this many drawn in a frame */
    int list;              /* stars.list: each sky map writes NAME-stars.fits */
} orr_stars_settings;

void orr_stars_defaults(orr_stars_settings *s);

/* One star drawn, for the star list. */
typedef struct orr_star_info {
    double abs_v;   /* absolute V magnitude */
    double v;       /* apparent V without dust, from the observer */
    float bv;       /* B-V */
    uint64_t parent; /* the id of the particle it came from */
    uint32_t index;  /* its place among the particle's stars, brightest 0 */
} orr_star_info;

/* The stars drawn from a chunk: a chunk of their own (positions, the
 * parent's id and type) with X, Y, Z weights, and what the list says of
 * each. Grown as needed; reused chunk after chunk. */
typedef struct orr_star_batch {
    orr_chunk stars;
    float *xyz[3];
    orr_star_info *info;
    size_t capacity;
} orr_star_batch;

void orr_star_batch_free(orr_star_batch *b);

/* The prepared stage: settings checked, the luminosity function
 * integrated, the colours of B-V tabulated. */
typedef struct orr_stars {
    orr_stars_settings set;
    orr_lf lf;
    double light_per_mass; /* of the luminosity function, solar units per solar mass */
    /* X/Y and Z/Y of a blackbody at T(B-V), B-V = BV_FIRST + k BV_STEP */
    float colour_xy[2][256];
    /* Per frame: how many drawn so far, and whether stars.max stopped it */
    long long drawn;
    int capped;
} orr_stars;

/* Checks the settings (naming the key that is wrong; path names the scene)
 * and prepares the stage. */
orr_status orr_stars_prepare(orr_stars *st, const orr_stars_settings *set, const char *path, orr_error *err);

/* 1 when particles of this type spawn stars. */
static inline int orr_stars_spawns(const orr_stars *st, uint8_t type)
{
    return type < 32 && (st->set.types & (1u << type));
}

/* The length h (scene units) of the kernel over which a particle of this
 * mass (scene units) spreads its glow: two of its stars' sigmas, the
 * particles' spacing at the luminosity function's density. */
double orr_stars_kernel_length(const orr_stars *st, double mass);

/* Starts a frame: the count of drawn stars back to 0. */
void orr_stars_begin_frame(orr_stars *st);

/* The stars of c's particles of the spawning types (but the particle
 * exclude_id, the observer) seen from eye (world coordinates): drawn into
 * out (replacing what it held), and the particles' X, Y, Z weights reduced
 * to what is left of their light (Y exactly; X and Z keep the particle's
 * chromaticity). */
orr_status orr_stars_spawn(orr_stars *st, orr_vec3 eye, uint64_t exclude_id, const orr_chunk *c,
                           float *const *xyz, orr_star_batch *out, orr_error *err);

/* The glow's dimming (docs/sky.md, "The glow's flux"): for each of c's
 * particles of the spawning types, dimming[i] (1 / length^2, scene units)
 * is the flux at eye per unit of the light its stars leave, the mean of
 * 1/s^2 over its kernel of the stars that the draw leaves in the glow
 * (those too faint from where they fall). Far away it is 1/r^2; near the
 * observer it stays below 1/sigma^2, so a particle passing the observer
 * does not light the whole sky. Other particles' entries are left as they
 * were. Parallel over the particles, each entry a function of its particle
 * alone: the same bits on any number of threads. */
void orr_stars_glow_dimming(const orr_stars *st, orr_vec3 eye, const orr_chunk *c, float *dimming);

#endif
