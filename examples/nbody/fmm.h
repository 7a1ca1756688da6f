/* A fast multipole method over the quadrupole tree (qtree.h), after
 * Dehnen (2000, ApJ 536, L39; 2002, J. Comput. Phys. 179, 27): one walk of
 * the tree against itself; two cells far enough apart (b_max,A + b_max,B <
 * theta |c_A - c_B|) act on each other once, each adding the other's
 * monopole and quadrupole to a Taylor expansion of the potential about its
 * own centre of mass, to third order (cell-cell, both ways from the same
 * derivatives); two leaves too close act particle by particle, each pair
 * once (both ways). The expansions are then passed down the tree, shifted
 * to each child's centre, and evaluated at each particle.
 *
 * The derivatives of the Plummer-softened 1/r to fifth order come from
 * the recurrence of Lindsay & Krasny (2001, J. Comput. Phys. 172, 879) for
 * the Taylor coefficients of (|x|^2 + eps^2)^(-1/2). Softening as qtree's:
 * a pair is softened with (eps_i^2 + eps_j^2) / 2, a cell by its particles'
 * mean eps^2.
 *
 * Kept as a measured peer of the tree walk (bench_nbody fmm,
 * docs/nbody.md "A fast multipole method, measured"), not used by
 * orrery-nbody. */
#ifndef NBODY_FMM_H
#define NBODY_FMM_H

#include <stddef.h>

#include "qtree.h"

typedef struct fmm_counts {
    double cell_cell;  /* cell pairs that acted through expansions */
    double pair;       /* particle pairs summed directly (each once) */
} fmm_counts;

/* Accelerations (G times the softened sums, 3 a particle, in the caller's
 * order, as qt_accelerations_of gives them) and potentials (pot may be
 * NULL) of all t->n particles of a tree built by qt_build. One thread.
 * Returns 0, or -1 when out of memory. */
int fmm_accelerations(const qt_tree *t, double G, double theta, double *acc, double *pot, fmm_counts *counts);

#endif
