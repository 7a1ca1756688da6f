/* Populations: named groups of particles, each with its own colour and
 * luminance rule (docs/colour.md).
 *
 * A set holds rules in order; each particle belongs to the first population
 * whose selection it passes, or to none (weights 0). A selection is the AND
 * of optional tests: particle type, id range, a field's range, and a random
 * draw with a probability that may depend on a field. The random draw is a
 * pure function of (particle id, set seed, population name), so a particle
 * gets the same population in every frame, in any chunk, on any thread or
 * MPI rank.
 *
 * The weights handed to the splatter are X, Y, Z = L * (X/Y, 1, Z/Y) of the
 * particle's colour: summing them per pixel and synthesising gives the image
 * (post/colour.h). They live here rather than in post/ because they are
 * per-particle attributes computed on chunks, before the splat. */
#ifndef ORR_PARTICLES_POPULATION_H
#define ORR_PARTICLES_POPULATION_H

#include <stddef.h>
#include <stdint.h>

#include "core/error.h"
#include "particles/chunk.h"
#include "core/colourimetry.h"

#define ORR_POPULATION_MAX 32
#define ORR_POPULATION_NAME_MAX 32

/* ---- the id hash ------------------------------------------------------------ */

/* SplitMix64's output function (Steele, Lea & Flood 2014): a bijection on
 * 64-bit integers whose every output bit depends on every input bit. */
uint64_t orr_hash64(uint64_t x);

/* A uniform number in [0, 1) (53 random bits) that depends only on the id,
 * the seed and a salt (a population's, from its name). */
double orr_id_uniform(uint64_t id, uint64_t seed, uint64_t salt);

/* FNV-1a of a string: a population's salt, so renaming or reordering the
 * other populations does not change its draws. */
uint64_t orr_name_salt(const char *name);

/* ---- selection ------------------------------------------------------------------ */

typedef enum {
    ORR_PROB_CONSTANT = 0, /* p */
    ORR_PROB_EXP,          /* exp(-(v - v0) / dv), clipped to [0, 1] */
    ORR_PROB_LOGISTIC,     /* 1 / (1 + exp((v - v0) / dv)): a smooth step, 1/2 at v0 */
} orr_prob_kind;

/* "constant", "exp" or "logistic"; returns 0 on an unknown name. */
int orr_prob_kind_from_name(const char *name, orr_prob_kind *kind);
const char *orr_prob_kind_name(orr_prob_kind kind);

typedef struct orr_pop_select {
    uint32_t types;             /* bit t set: type t qualifies; 0: every type */
    int has_id_range;           /* when set: id_min <= id <= id_max */
    uint64_t id_min, id_max;
    char range_field[ORR_FIELD_NAME_MAX]; /* "" = no field test; else min <= v <= max */
    double field_min, field_max;          /* +-INFINITY for an open end */
    int random;                           /* when set: a draw u < p(v) */
    orr_prob_kind prob;
    char prob_field[ORR_FIELD_NAME_MAX]; /* v for EXP and LOGISTIC */
    double p;                            /* CONSTANT: in [0, 1] */
    double v0, dv;                       /* EXP, LOGISTIC: dv != 0 (negative flips the slope) */
} orr_pop_select;

/* The probability p(v) of a random selection, in [0, 1]; 0 for NaN v. */
double orr_pop_probability(const orr_pop_select *sel, double v);

/* ---- colour and luminance ----------------------------------------------------------- */

typedef enum {
    ORR_POPCOLOUR_FIXED = 0,       /* one colour for the whole population */
    ORR_POPCOLOUR_TEMPERATURE,     /* a blackbody at the field's value, K */
    ORR_POPCOLOUR_BV,              /* a blackbody at T_eff(B-V) of the field */
    ORR_POPCOLOUR_SSP,             /* B-V of a stellar population of the field's age (core/ssp.h) */
} orr_popcolour_kind;

/* What an SSP colour's field holds. */
typedef enum {
    ORR_SSP_CLOCK_AGE = 0,      /* the population's age: age = field * unit_yr */
    ORR_SSP_CLOCK_TIME,         /* its formation time: age = (now - field) * unit_yr */
    ORR_SSP_CLOCK_SCALE_FACTOR, /* its formation scale factor: age = t(now) - t(field) */
} orr_ssp_clock;

extern const orr_named orr_ssp_clock_names[];

typedef struct orr_pop_ssp {
    orr_ssp_clock clock;
    double unit_yr; /* AGE, TIME: years per unit of the field and of now, > 0 */
    /* TIME, SCALE_FACTOR: "now"; without has_now, the snapshot's own time
     * (orr_population_assign_at's snapshot_time). */
    int has_now;
    double now;
    double h, omega_m; /* SCALE_FACTOR: a flat LCDM cosmology (core/ssp.h) */
    /* The metal mass fraction Z: a field, or one value for every particle
     * when the name is "". */
    char metallicity_field[ORR_FIELD_NAME_MAX];
    double metallicity;
} orr_pop_ssp;

/* The SSP defaults: an age field in years, Z = 0.0152 (PARSEC's solar
 * value), Planck 2018's h = 0.674, omega_m = 0.315 for scale factors. */
void orr_pop_ssp_defaults(orr_pop_ssp *ssp);

typedef struct orr_pop_colour {
    orr_popcolour_kind kind;
    orr_colour fixed;              /* FIXED */
    char field[ORR_FIELD_NAME_MAX]; /* TEMPERATURE, BV; SSP: the age or formation field */
    orr_cmf cmf;                   /* TEMPERATURE, BV, SSP */
    orr_bv_relation bv_rel;        /* BV, SSP */
    orr_pop_ssp ssp;               /* SSP */
} orr_pop_colour;

typedef enum {
    ORR_POPLUM_CONSTANT = 0, /* L = scale */
    ORR_POPLUM_MASS,         /* L = scale * mass */
    ORR_POPLUM_FIELD,        /* L = scale * field */
    ORR_POPLUM_MAGNITUDE,    /* L = scale * 10^(-0.4 field), e.g. V */
    ORR_POPLUM_SSP,          /* L = scale * mass * L_V/M of the SSP colour's population */
} orr_poplum_kind;

typedef struct orr_pop_luminance {
    orr_poplum_kind kind;
    char field[ORR_FIELD_NAME_MAX]; /* FIELD, MAGNITUDE */
    double scale;                   /* > 0 */
} orr_pop_luminance;

typedef struct orr_population {
    char name[ORR_POPULATION_NAME_MAX];
    orr_pop_select select;
    orr_pop_colour colour;
    orr_pop_luminance lum;
} orr_population;

/* A population that takes every particle, white (sRGB 1, 1, 1), L = 1. */
void orr_population_defaults(orr_population *p, const char *name);

/* ---- sets ------------------------------------------------------------------------------ */

typedef struct orr_population_set {
    uint64_t seed;
    int n;
    orr_population pop[ORR_POPULATION_MAX];
    /* Filled by orr_population_add: */
    uint64_t salt[ORR_POPULATION_MAX];
    double fixed_xyz[ORR_POPULATION_MAX][3]; /* FIXED colours, Y = 1 */
} orr_population_set;

void orr_population_set_init(orr_population_set *s, uint64_t seed);

/* Checks p and appends a copy. Fails (ORR_ERR_USAGE, naming the population
 * and the key) on an empty or duplicate name, a full set, a bad colour, a
 * luminance scale not > 0, a probability outside [0, 1], dv = 0, a field
 * test or rule without a field name, or an empty range. */
orr_status orr_population_add(orr_population_set *s, const orr_population *p, orr_error *err);

/* Index of the population called name, or -1. */
int orr_population_find(const orr_population_set *s, const char *name);

/* For particles start .. start+count-1 of the chunk, at the time
 * snapshot_time of the snapshot (the "now" of SSP colours that do not set
 * their own; NaN when unknown): pop[i] gets the index of
 * particle start+i's population (-1 for none; pop may be NULL) and X, Y, Z
 * its weights. With only >= 0, particles of other populations get weights 0
 * (their pop[] is still filled): rendering each population alone and adding
 * the planes gives the combined image. Fails with ORR_ERR_USAGE when a rule
 * names a field the chunk lacks, and ORR_ERR_DATA (naming the particle's
 * index in the source, its id and the field) on a temperature not > 0 or NaN,
 * a NaN B-V, a NaN age or metallicity, a formation scale factor not > 0,
 * or a luminance that is negative or not finite; ORR_ERR_USAGE when an SSP
 * colour needs the snapshot's time and snapshot_time is NaN (or, for scale
 * factors, not > 0). */
orr_status orr_population_assign_at(const orr_population_set *s, double snapshot_time, const orr_chunk *c,
                                    size_t start, size_t count, int only, int32_t *pop, float *X, float *Y, float *Z,
                                    orr_error *err);

/* The same without a snapshot time (NaN). */
orr_status orr_population_assign(const orr_population_set *s, const orr_chunk *c, size_t start, size_t count,
                                 int only, int32_t *pop, float *X, float *Y, float *Z, orr_error *err);

#endif
