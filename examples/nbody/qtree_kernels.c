/* Why over the group's particles rather than over the list (as before):
 * groups hold 17 particles on average (at most QT_GROUP), lists ~800
 * entries, so a list entry loaded once serves a whole vector of particles
 * and the sums stay in registers without a horizontal reduction per
 * particle; and each lane sums in list order, so the result does not
 * depend on the vector width. The price is the idle lanes of a group's last
 * vector, which blocks of 16, 8 and 4 lanes keep small. Measured on the
 * Milky Way model (bench_nbody, docs/nbody.md): this, with the AVX-512
 * copy, is several times faster than the list-vectorised loops. */
#include "qtree_kernels.h"

#include <math.h>

#include "core/simd.h"

void qt_pad_targets(qt_targets *g)
{
    for (size_t i = g->n; i < g->n + 16 && i < QT_GROUP_ROOM; i++) {
        g->x[i] = g->y[i] = g->z[i] = 0;
        g->e2[i] = 1;
    }
}

/* The cells' pull on `lanes` targets from index i0 (one vector, or a few). */
static ORR_ALWAYS_INLINE void cells_block(const qt_lists *l, const qt_targets *g, size_t i0, const int lanes,
                                          qt_sums *out)
{
    const float *x = g->x + i0, *y = g->y + i0, *z = g->z + i0, *e2 = g->e2 + i0;
    float ax[16] = {0}, ay[16] = {0}, az[16] = {0}, ph[16] = {0};
    for (size_t k = 0; k < l->ncell; k++) {
        const float *c = l->c + QT_CELL_FIELDS * k;
        const float cx = c[QT_CX], cy = c[QT_CY], cz = c[QT_CZ];
        const float m = c[QT_CM], ce2 = c[QT_CE2];
        const float q0 = c[QT_CQ0], q1 = c[QT_CQ1], q2 = c[QT_CQ2];
        const float q3 = c[QT_CQ3], q4 = c[QT_CQ4], q5 = c[QT_CQ5];
#pragma omp simd
        for (int i = 0; i < lanes; i++) {
            float dx = x[i] - cx, dy = y[i] - cy, dz = z[i] - cz;
            float r2 = dx * dx + dy * dy + dz * dz + 0.5f * (e2[i] + ce2);
            float inv = 1.0f / sqrtf(r2), inv2 = inv * inv, inv3 = inv * inv2, inv5 = inv3 * inv2;
            float qx = q0 * dx + q3 * dy + q4 * dz, qy = q3 * dx + q1 * dy + q5 * dz, qz = q4 * dx + q5 * dy + q2 * dz;
            float dqd = dx * qx + dy * qy + dz * qz;
            float s = -m * inv3 - 2.5f * dqd * inv5 * inv2;
            ax[i] += s * dx + qx * inv5;
            ay[i] += s * dy + qy * inv5;
            az[i] += s * dz + qz * inv5;
            ph[i] -= m * inv + 0.5f * dqd * inv5;
        }
    }
    for (int i = 0; i < lanes; i++) {
        out->ax[i0 + i] = ax[i];
        out->ay[i0 + i] = ay[i];
        out->az[i0 + i] = az[i];
        out->phi[i0 + i] = ph[i];
    }
}

/* The particles' pull on `lanes` targets from index i0. */
static ORR_ALWAYS_INLINE void parts_block(const qt_lists *l, const qt_targets *g, size_t i0, const int lanes,
                                          qt_sums *out)
{
    const float *x = g->x + i0, *y = g->y + i0, *z = g->z + i0, *e2 = g->e2 + i0;
    float ax[16] = {0}, ay[16] = {0}, az[16] = {0}, ph[16] = {0};
    for (size_t k = 0; k < l->npart; k++) {
        const float *p = l->p + QT_PART_FIELDS * k;
        const float px = p[QT_PX], py = p[QT_PY], pz = p[QT_PZ];
        const float m = p[QT_PM], pe2 = p[QT_PE2];
#pragma omp simd
        for (int i = 0; i < lanes; i++) {
            float dx = px - x[i], dy = py - y[i], dz = pz - z[i];
            float r2 = dx * dx + dy * dy + dz * dz + 0.5f * (e2[i] + pe2);
            float inv = 1.0f / sqrtf(r2), m3 = m * inv * inv * inv;
            ax[i] += m3 * dx;
            ay[i] += m3 * dy;
            az[i] += m3 * dz;
            ph[i] -= m * inv;
        }
    }
    for (int i = 0; i < lanes; i++) {
        out->ax[i0 + i] = ax[i];
        out->ay[i0 + i] = ay[i];
        out->az[i0 + i] = az[i];
        out->phi[i0 + i] = ph[i];
    }
}

/* Blocks of 16 lanes, the last one of 8 or 4 when that covers what is left:
 * each a constant width, so each compiles to whole vectors of its target. */
#define FOR_BLOCKS(block, l, g, out)                                                                               \
    do {                                                                                                           \
        size_t i0 = 0;                                                                                             \
        for (; i0 + 8 < (g)->n; i0 += 16)                                                                          \
            block(l, g, i0, 16, out);                                                                              \
        if (i0 + 4 < (g)->n)                                                                                       \
            block(l, g, i0, 8, out);                                                                               \
        else if ((g)->n > i0)                                                                                      \
            block(l, g, i0, 4, out);                                                                               \
    } while (0)

ORR_WIDE_VECTOR_CLONES
void qt_cells_on(const qt_lists *l, const qt_targets *g, qt_sums *out)
{
    FOR_BLOCKS(cells_block, l, g, out);
}

ORR_WIDE_VECTOR_CLONES
void qt_parts_on(const qt_lists *l, const qt_targets *g, qt_sums *out)
{
    FOR_BLOCKS(parts_block, l, g, out);
}
