/* The built-in model: a Milky Way-like disc galaxy and an Andromeda-like one
 * on an approach orbit, with marker particles for the Sun and the two central
 * black holes. Units: kpc, 1e10 solar masses, km/s. Particle i is a pure
 * function of (seed, i), so the output does not depend on the chunk size.
 * docs/model.md describes the components, ids and types. */
#ifndef ORR_SOURCE_MODEL_H
#define ORR_SOURCE_MODEL_H

#include <stdint.h>

#include "core/names.h"
#include "source/source.h"

/* Well-known ids of the marker particles. */
#define ORR_MODEL_ID_MW_BH 1
#define ORR_MODEL_ID_M31_BH 2
#define ORR_MODEL_ID_SUN 3

/* Particle types (Gadget-like numbering). */
#define ORR_MODEL_TYPE_HALO 1
#define ORR_MODEL_TYPE_DISC 2
#define ORR_MODEL_TYPE_BULGE 3
#define ORR_MODEL_TYPE_SUN 4
#define ORR_MODEL_TYPE_BH 5

#define ORR_MODEL_PARTICLES_MAX 2000000000LL

/* Which galaxies the model holds (orr_model_params.galaxies). */
#define ORR_MODEL_PAIR 0 /* the Milky Way and M31 on their approach orbit */
#define ORR_MODEL_MW 1   /* the Milky Way alone, at rest at the origin, with the Sun */
#define ORR_MODEL_M31 2  /* M31 alone, at rest at the origin */

#define ORR_MODEL_DISC_Q_DEFAULT 1.5
#define ORR_MODEL_DISC_Q_MAX 100.0
#define ORR_MODEL_M31_WEIGHT_MAX 64.0 /* the largest m31_weight accepted (and 1 / it the least) */

/* The words for orr_model_params.galaxies (scene key input.model.galaxies,
 * the --galaxies options), in its order. */
#define ORR_MODEL_GALAXIES_WORDS "pair, mw or m31"
/* "pair", "mw", "m31": ORR_MODEL_PAIR, _MW, _M31. */
extern const orr_named orr_model_galaxies_names[];
/* ORR_MODEL_PAIR, _MW or _M31 for "pair", "mw" or "m31"; -1 for any other word. */
int orr_model_galaxies_named(const char *word);

typedef struct orr_model_params {
    long long particles;   /* total, markers included; at least 100 */
    uint64_t seed;
    double separation_kpc; /* distance between the two galaxy centres (780 today); pair only */
    int galaxies;          /* ORR_MODEL_PAIR (0, the default), ORR_MODEL_MW or ORR_MODEL_M31 */
    double disc_q;         /* Toomre Q of the discs at 2.43 scale lengths; 0 selects 1.5 */
    unsigned types;        /* bit t set: emit particles of type t; 0 emits all. The markers
                            * (Sun, black holes) are emitted whatever it says. The others are
                            * the same particles as with 0, those of other types never drawn. */
    double dust_clumping;  /* the gas discs' clumping: sigma of the log of their density (0: smooth;
                            * source/models/model_dust.h) */
    double m31_weight;     /* pair only: each of M31's particles weighs this many times the Milky Way's
                            * of the same kind (disc, bulge or halo), so the Milky Way, where Future
                            * Sky's observer is, gets more of the N particles; 0 selects 1 (docs/model.md) */
} orr_model_params;

orr_status orr_model_source_open(const orr_model_params *params, size_t chunk_size, orr_source **out,
                                 orr_error *err);
/* The same with the dusty gas discs (source/models/model_dust.h): dust_particles
 * gas particles (type 0) appended after the others; 0 gives the stream of
 * orr_model_source_open. */
orr_status orr_model_source_open_dust(const orr_model_params *params, long long dust_particles, size_t chunk_size,
                                      orr_source **out, orr_error *err);
/* The same model drawn by the exact per-particle recipe the tables of
 * docs/model.md ("Tables") stand in for (bit for bit the model before
 * them): the disc's dynamics computed anew for every star, libm's angles.
 * About 3 times slower, and not bit-identical to orr_model_source_open_dust
 * (its tables agree to 2e-5, sigma_z^2 to 7e-4; positions to 1e-15): for
 * tests and bench/bench_model.c. */
orr_status orr_model_source_open_exact(const orr_model_params *params, long long dust_particles, size_t chunk_size,
                                       orr_source **out, orr_error *err);

#endif
