/* The quadrupole group tree's force kernels (qtree.c builds the lists):
 * a group's particles against its interaction lists of cells and of
 * particles, in float, relative to the group's centre of mass.
 *
 * Vectorised over the group's particles, one particle a lane, the list's
 * entries broadcast to every lane: each particle's sums run over its lists
 * in their order whatever the vector width, so the SSE2, AVX2 and AVX-512
 * copies (qtree_kernels.c) give the same forces bit for bit, equal to the
 * plain scalar loop's (tests/examples/test_nbody_kernels.c). */
#ifndef NBODY_QTREE_KERNELS_H
#define NBODY_QTREE_KERNELS_H

#include <stddef.h>

#include "qtree.h"

/* A thread's interaction lists for one group, gathered into contiguous
 * float records relative to the group's centre of mass (records, not
 * separate arrays: the kernels broadcast each entry to every lane, which
 * costs the same from anywhere, and one record is written in one go): cells taken whole
 * (mass, quadrupole, softening^2) and particles of opened leaves. Float is
 * safe here: offsets from the group are at most the system's size and need
 * ~1e-7 relative precision against the tree's ~1e-3 errors; sums are over
 * at most ~1e4 terms. */
typedef struct qt_lists {
    size_t ncell, npart, cap_cell, cap_part;
    float *c; /* cell k: x y z m q0..q5 e2 at c[QT_CELL_FIELDS k + QT_CX ...] */
    float *p; /* particle k: x y z m e2 at p[QT_PART_FIELDS k + QT_PX ...] */
} qt_lists;

enum { QT_CX, QT_CY, QT_CZ, QT_CM, QT_CQ0, QT_CQ1, QT_CQ2, QT_CQ3, QT_CQ4, QT_CQ5, QT_CE2, QT_CELL_FIELDS };
enum { QT_PX, QT_PY, QT_PZ, QT_PM, QT_PE2, QT_PART_FIELDS };

/* Room for a group's particles and the padding of its last vector. */
#define QT_GROUP_ROOM (QT_GROUP + 16)

/* The group's particles whose forces are wanted: n of them, offsets from
 * the group's centre of mass and softening^2. The kernels also read the
 * lanes up to the next multiple of 4 (or 8 or 16) beyond n, which
 * qt_pad_targets fills with harmless values. */
typedef struct qt_targets {
    size_t n;
    _Alignas(64) float x[QT_GROUP_ROOM];
    _Alignas(64) float y[QT_GROUP_ROOM];
    _Alignas(64) float z[QT_GROUP_ROOM];
    _Alignas(64) float e2[QT_GROUP_ROOM];
} qt_targets;

/* Each target's sums over one list: acceleration and potential, without G. */
typedef struct qt_sums {
    _Alignas(64) float ax[QT_GROUP_ROOM];
    _Alignas(64) float ay[QT_GROUP_ROOM];
    _Alignas(64) float az[QT_GROUP_ROOM];
    _Alignas(64) float phi[QT_GROUP_ROOM];
} qt_sums;

/* Fills the lanes after the last target (offset 0, softening^2 1: finite). */
void qt_pad_targets(qt_targets *g);

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

#endif
