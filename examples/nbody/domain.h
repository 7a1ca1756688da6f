/* orrery-nbody --decompose: each MPI rank holds its own particles only.
 *
 * Particles are ordered along a Peano-Hilbert curve through the cube
 * about all of them; the curve is cut into one piece a rank holding as
 * many particles as can be (domain_migrate), and each particle's whole
 * record goes to its piece's rank in one all-to-all exchange. For the
 * forces (domain_gravity) each rank builds a tree over its own particles
 * and sends every other rank the part of it that rank's particles need:
 * the cells that the opening criterion takes whole for every point of
 * that rank's bounding box (as cells: centre of mass, mass, quadrupole,
 * b_max, softening) and the particles of the leaves it opens (a locally
 * essential tree, Salmon 1991). Each rank then builds one tree over its
 * particles and what it received and walks it for its own particles.
 *
 * Every order is fixed (the curve's, then the particles' ids; the ranks'
 * in rank order), so a run gives the same bits on any number of threads
 * for a given number of ranks. The trees differ between rank counts, so
 * forces do too, within the tree's own error. docs/nbody.md. */
#ifndef NBODY_DOMAIN_H
#define NBODY_DOMAIN_H

#include <stdint.h>

#include "bodies.h"
#include "qtree.h"

/* What the last domain_gravity imported (this rank's). */
typedef struct domain_stats {
    size_t cells, particles;
} domain_stats;

/* The key of a point of the integer grid x[3] (each below 2^21) along the
 * Peano-Hilbert curve that visits every point of the 2^21-cube, one step
 * between neighbours (Skilling 2004, AIP Conf. Proc. 707, 381). */
uint64_t domain_hilbert_key(const uint32_t x[3]);

/* Sends every particle (its whole record: position, velocity,
 * acceleration, potential, mass, id, type, block-step level, fields) to
 * the rank whose piece of the curve holds it, and sorts each rank's
 * particles along the curve (ties by id). Softenings are set anew from the
 * types (halo: eps_halo, else eps; tracers are softened by
 * domain_soften_tracers), and the tracers (lighter than b->tracer_mass)
 * found among the particles now here. Collective; 0, or -1 on every rank
 * (a message on stderr). */
int domain_migrate(bodies *b, double eps, double eps_halo, int rank, int size);

/* The accelerations and potentials of this rank's particles (all, or those
 * with active[i] set) from its own and the other ranks' trees. Collective,
 * every rank with or without active particles. The interactions, or -1 on
 * every rank when memory runs out. */
double domain_gravity(qt_tree *t, bodies *b, double G, double theta, const unsigned char *active, int rank, int size,
                      domain_stats *stats);

/* Sums over every rank's particles of m and m v (e[0] the mass, e[1 .. 3]
 * the momentum), exact in fixed point: the same bits on any number of
 * ranks, in any order. Collective; 0 or -1. */
int domain_mass_momentum(const bodies *b, double e[4]);

/* The k least squared distances from x to the particles among pos, mass
 * (n of them) that are not tracers (lighter than light), into d2[0 .. k) as
 * a max-heap (d2[0] the k-th); infinite where there are fewer. A tracer's
 * softening comes from it, over every position (nbody.c) or over a rank's
 * own (domain_soften_tracers). */
void nearest_non_tracers(const double *pos, const double *mass, size_t n, double light, const double x[3], int k,
                         double *d2);

/* Softens each tracer at sqrt(2) times the distance of its k-th nearest
 * non-tracer particle, searched on every rank (never less than eps).
 * Collective; 0 or -1. */
int domain_soften_tracers(bodies *b, int k, double eps, int rank, int size);

#endif
