/* orrery-nbody's particles on one process (nbody.c, domain.c). */
#ifndef NBODY_BODIES_H
#define NBODY_BODIES_H

#include <stddef.h>
#include <stdint.h>

#include "orrery.h"
#include "particles/chunk.h"

/* The particles this process owns, n of them from number first on, and the
 * positions and masses of all n_all of them, which every process holds for
 * the tree (with one process, its slice is all of them). */
typedef struct bodies {
    size_t n, first, n_all;
    double *pos_all, *mass_all; /* x, y, z of particle i at 3i */
    double *pos, *mass;         /* this process's: pos_all + 3 first, mass_all + first */
    size_t *counts;             /* every process's n, in rank order */
    double *vel, *acc, *pot;
    double *eps_all;            /* every particle's softening (all processes') */
    size_t *tracers, ntracers;  /* the tracers' places in the run's order (find_tracers) */
    double tracer_mass;         /* a tracer is lighter than this */
    uint64_t *id;
    uint8_t *type;
    /* The initial conditions' other per-particle fields (the model's "r" and
     * "E0", a snapshot's potential, ...), handed to orrery unchanged every
     * frame so colours chosen by them stay with each particle for the run. */
    int nfields;
    char field_name[ORR_ARRAYS_MAX_FIELDS][ORR_FIELD_NAME_MAX];
    float *field[ORR_ARRAYS_MAX_FIELDS];
    /* With block steps (--eta), each particle's last step: dt / 2^level.
     * It carries over from one step of --dt to the next (a step lengthens
     * only with room to spare, open_step) and into snapshots, so a resume
     * chooses the same steps. NULL without --eta. */
    uint8_t *level;
    double time;
    size_t imported_cells, imported_particles; /* --decompose: what the last full force computation imported */
    int decomposed; /* --decompose: each process holds its own particles only (domain.c); pos_all,
                       mass_all NULL, first 0, eps_all this process's own */
} bodies;

/* Whether this process's particle i is a tracer: lighter than
 * tracer_mass (the model's Sun), with no gravity of its own that matters. */
static inline int bodies_is_tracer(const bodies *b, size_t i)
{
    return b->mass[i] < b->tracer_mass;
}

#endif
