/* A globular cluster's colour-magnitude diagram as a sampler: each star gets
 * an absolute magnitude M_V, an intrinsic colour (B-V)_0 and an evolutionary
 * phase, drawn from a schematic metal-poor ([Fe/H] ~ -1.5) cluster shaped
 * after M3 (NGC 5272). docs/nightfall.md gives the fiducial points, the
 * population fractions and their sources. */
#ifndef ORR_SOURCE_GC_CMD_H
#define ORR_SOURCE_GC_CMD_H

#include "source/models/rng.h"

/* Evolutionary phases; the King source uses them as particle types. */
typedef enum orr_gc_phase {
    ORR_GC_MAIN_SEQUENCE = 1,
    ORR_GC_SUBGIANT = 2,
    ORR_GC_RED_GIANT = 3,
    ORR_GC_HORIZONTAL_BRANCH = 4,
    ORR_GC_ASYMPTOTIC_GIANT = 5,
} orr_gc_phase;

#define ORR_GC_PHASES 5

typedef struct orr_gc_star {
    double mv; /* absolute V magnitude */
    double bv; /* intrinsic B-V colour */
    orr_gc_phase phase;
} orr_gc_star;

/* The expected fraction of stars in a phase (the fractions add up to 1). */
double orr_gc_phase_fraction(orr_gc_phase phase);

/* The fiducial colour of a phase's sequence at magnitude mv (no scatter);
 * for the horizontal branch mv is ignored and NAN returned. Used by tests
 * to check drawn stars lie on their sequence. */
double orr_gc_fiducial_bv(orr_gc_phase phase, double mv);

/* One star from the diagram, using only draws from r (so a particle's star
 * is a pure function of its own generator). */
orr_gc_star orr_gc_draw(orr_rng *r);

#endif
