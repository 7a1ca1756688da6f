/* The quadrupole group tree's force kernels (qtree.c builds the lists):
 * a group's particles against its interaction lists of cells and of
 * particles, in float, relative to the group's centre of mass.
 *
 * Vectorised over the lists, 16 entries a step, each of 16 partial sums
 * taking every 16th entry, the partial sums added in a fixed order at the
 * end: the same operations whatever the vector width, so the SSE2, AVX2 and
 * AVX-512 copies (qtree_kernels.c) give the same forces bit for bit, equal
 * to a plain scalar loop's that sums the same way
 * (tests/examples/test_nbody_kernels.c). */
#ifndef NBODY_QTREE_KERNELS_H
#define NBODY_QTREE_KERNELS_H

#include <stddef.h>

#include "qtree.h"

/* A thread's interaction lists for one group, gathered into contiguous
 * float arrays relative to the group's centre of mass so the loops over
 * them vectorise: cells taken whole (mass, quadrupole, softening^2) and
 * particles of opened leaves. Float is
 * safe here: offsets from the group are at most the system's size and need
 * ~1e-7 relative precision against the tree's ~1e-3 errors; sums are over
 * at most ~1e4 terms. */
typedef struct qt_lists {
    size_t ncell, npart, cap_cell, cap_part;
    float *c; /* per cell: x y z m q0..q5 e2, 11 arrays of cap_cell */
    float *p; /* per particle: x y z m e2, 5 arrays of cap_part */
} qt_lists;

/* The kernels take the lists QT_LIST_LANES entries at a time: each list
 * is followed by zero-mass entries (softening^2 1: finite, adding exactly
 * nothing) up to qt_padded(its length), which its arrays have room for. */
#define QT_LIST_LANES 16

static inline size_t qt_padded(size_t n)
{
    return (n + QT_LIST_LANES - 1) / QT_LIST_LANES * QT_LIST_LANES;
}

enum { QT_CX, QT_CY, QT_CZ, QT_CM, QT_CQ0, QT_CQ1, QT_CQ2, QT_CQ3, QT_CQ4, QT_CQ5, QT_CE2, QT_CELL_FIELDS };
enum { QT_PX, QT_PY, QT_PZ, QT_PM, QT_PE2, QT_PART_FIELDS };

/* The group's particles whose forces are wanted: n of them, offsets from
 * the group's centre of mass and softening^2. */
typedef struct qt_targets {
    size_t n;
    float x[QT_GROUP], y[QT_GROUP], z[QT_GROUP], e2[QT_GROUP];
} qt_targets;

/* Each target's sums over one list: acceleration and potential, without G. */
typedef struct qt_sums {
    float ax[QT_GROUP], ay[QT_GROUP], az[QT_GROUP], phi[QT_GROUP];
} qt_sums;

/* Softened monopole + quadrupole of the list's cells at each target
 * (x, y, z), offsets d = x - com, softened with (eps_i^2 + <eps^2>_cell) / 2:
 * the pair rule averaged over the cell to first order in eps^2, so a cell
 * mixing halo and disc particles costs no systematic error:
 *   Phi = -[M / r + (d.Q.d) / (2 r^5)],  a = -grad Phi
 *       = -M d / r^3 + Q.d / r^5 - 5/2 (d.Q.d) d / r^7,
 * with r^2 = |d|^2 + eps^2 (the usual softened expansion; cells taken whole
 * are far beyond the softening). */
void qt_cells_on(const qt_lists *l, const qt_targets *g, qt_sums *out);

/* Plummer-softened pulls of the list's particles on each target; a target
 * in the list (its own leaf) gets no force from itself (zero offset) and
 * -m / eps in the potential, which the caller removes. */
void qt_parts_on(const qt_lists *l, const qt_targets *g, qt_sums *out);

/* The pull of a super-group's far cells (qtree.c: those farther than
 * QT_FAR times its radius h from its centre of mass) as a field: their
 * acceleration and potential computed at the 27 points of the grid
 * {-h, 0, h}^3 about the centre (k = a + 3 b + 9 c for offsets (a - 1, b - 1,
 * c - 1) h), once with the least softening^2 of the super-group's
 * particles (f0) and once with the largest (d: that minus f0, 0 when they
 * are the same). */
typedef struct qt_field {
    float h, e2lo, inv_de2; /* inv_de2: 1 / (largest - least softening^2), or 0 */
    float f0[4][27], d[4][27]; /* ax, ay, az, phi */
} qt_field;

/* The field at each target (offsets from the super-group's centre, within
 * h of it): interpolated by the tensor product of quadratic Lagrange
 * polynomials through the grid, and linearly in the target's softening^2
 * (the pair rule's eps^2 enters as r^2 + eps^2 / 2, and far cells are
 * many softening lengths away). The far field is smooth over the
 * super-group: for a cell at distance D the interpolation's error is of
 * order (h / D)^3 of its pull. Vectorised over the targets, one a lane,
 * with no sums across lanes: the same bits on every vector width. Adds to
 * out. */
void qt_field_on(const qt_field *f, const qt_targets *g, qt_sums *out);

#endif
