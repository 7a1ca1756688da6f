/* Vectorised over the list, QT_LIST_LANES entries a step, each lane
 * keeping its own partial sums (entries k = lane mod 16), added at the end
 * in a fixed order: the same sums on SSE2 (four 4-wide registers a
 * quantity), AVX2 (two) and AVX-512 (one), so the forces do not depend on
 * the machine. Why over the list rather than over the group's particles
 * (one particle a lane, the entries broadcast): groups hold 17 particles
 * on average, so a group's last vector of 16 particles is mostly empty
 * (69 % of lanes busy on the Milky Way model), while lists are ~800
 * entries long (~97 % busy). Both do the same operations a lane, and the
 * loads of the list's entries are not what limits either; measured, the
 * list-vectorised loops made the forces ~1.1x faster (docs/nbody.md). */
#include "qtree_kernels.h"

#include <math.h>

#include "core/simd.h"

/* The 16 partial sums' total, halves added pairwise: a fixed order. */
static ORR_ALWAYS_INLINE float total16(float s[QT_LIST_LANES])
{
    for (int w = QT_LIST_LANES / 2; w > 0; w /= 2)
        for (int j = 0; j < w; j++)
            s[j] += s[j + w];
    return s[0];
}

/* Target i's four totals into out. */
static ORR_ALWAYS_INLINE void store_totals(float ax[QT_LIST_LANES], float ay[QT_LIST_LANES], float az[QT_LIST_LANES],
                                           float ph[QT_LIST_LANES], qt_sums *out, size_t i)
{
    out->ax[i] = total16(ax);
    out->ay[i] = total16(ay);
    out->az[i] = total16(az);
    out->phi[i] = total16(ph);
}

/* The cells' pull on target i of g into out. */
static ORR_ALWAYS_INLINE void cells_on_one(const qt_lists *l, const qt_targets *g, size_t i, qt_sums *out)
{
    const float x = g->x[i], y = g->y[i], z = g->z[i], e2i = g->e2[i];
    const size_t cap = l->cap_cell, n = qt_padded(l->ncell);
    float ax[QT_LIST_LANES] = {0}, ay[QT_LIST_LANES] = {0}, az[QT_LIST_LANES] = {0}, ph[QT_LIST_LANES] = {0};
    for (size_t k = 0; k < n; k += QT_LIST_LANES) {
        const float *c = l->c + k;
#pragma omp simd
        for (int j = 0; j < QT_LIST_LANES; j++) {
            float dx = x - c[QT_CX * cap + j], dy = y - c[QT_CY * cap + j], dz = z - c[QT_CZ * cap + j];
            float r2 = dx * dx + dy * dy + dz * dz + 0.5f * (e2i + c[QT_CE2 * cap + j]);
            float inv = 1.0f / sqrtf(r2), inv2 = inv * inv, inv3 = inv * inv2, inv5 = inv3 * inv2;
            float q0 = c[QT_CQ0 * cap + j], q1 = c[QT_CQ1 * cap + j], q2 = c[QT_CQ2 * cap + j];
            float q3 = c[QT_CQ3 * cap + j], q4 = c[QT_CQ4 * cap + j], q5 = c[QT_CQ5 * cap + j];
            float qx = q0 * dx + q3 * dy + q4 * dz, qy = q3 * dx + q1 * dy + q5 * dz, qz = q4 * dx + q5 * dy + q2 * dz;
            float dqd = dx * qx + dy * qy + dz * qz, m = c[QT_CM * cap + j];
            float s = -m * inv3 - 2.5f * dqd * inv5 * inv2;
            ax[j] += s * dx + qx * inv5;
            ay[j] += s * dy + qy * inv5;
            az[j] += s * dz + qz * inv5;
            ph[j] -= m * inv + 0.5f * dqd * inv5;
        }
    }
    store_totals(ax, ay, az, ph, out, i);
}

/* The particles' pull on target i of g into out. */
static ORR_ALWAYS_INLINE void parts_on_one(const qt_lists *l, const qt_targets *g, size_t i, qt_sums *out)
{
    const float x = g->x[i], y = g->y[i], z = g->z[i], e2i = g->e2[i];
    const size_t cap = l->cap_part;
    const float *px = l->p + QT_PX * cap, *py = l->p + QT_PY * cap, *pz = l->p + QT_PZ * cap;
    const float *pm = l->p + QT_PM * cap, *pe2 = l->p + QT_PE2 * cap;
    float ax[QT_LIST_LANES] = {0}, ay[QT_LIST_LANES] = {0}, az[QT_LIST_LANES] = {0}, ph[QT_LIST_LANES] = {0};
    for (size_t k = 0; k < qt_padded(l->npart); k += QT_LIST_LANES)
#pragma omp simd
        for (int j = 0; j < QT_LIST_LANES; j++) {
            float dx = px[k + j] - x, dy = py[k + j] - y, dz = pz[k + j] - z;
            float r2 = dx * dx + dy * dy + dz * dz + 0.5f * (e2i + pe2[k + j]);
            float inv = 1.0f / sqrtf(r2), m = pm[k + j], m3 = m * inv * inv * inv;
            ax[j] += m3 * dx;
            ay[j] += m3 * dy;
            az[j] += m3 * dz;
            ph[j] -= m * inv;
        }
    store_totals(ax, ay, az, ph, out, i);
}

/* The clones are static, called through plain external functions: Clang
 * (14) names a cloned function's resolver so that callers in other files
 * do not find it, as the render code's clones (src/core/simd.h) are static
 * for the same reason. */
ORR_WIDE_VECTOR_CLONES
static void cells_on_all(const qt_lists *l, const qt_targets *g, qt_sums *out)
{
    for (size_t i = 0; i < g->n; i++)
        cells_on_one(l, g, i, out);
}

ORR_WIDE_VECTOR_CLONES
static void parts_on_all(const qt_lists *l, const qt_targets *g, qt_sums *out)
{
    for (size_t i = 0; i < g->n; i++)
        parts_on_one(l, g, i, out);
}

void qt_cells_on(const qt_lists *l, const qt_targets *g, qt_sums *out)
{
    cells_on_all(l, g, out);
}

void qt_parts_on(const qt_lists *l, const qt_targets *g, qt_sums *out)
{
    parts_on_all(l, g, out);
}

/* The quadratic Lagrange polynomials through -1, 0 and 1, at u. */
static ORR_ALWAYS_INLINE void lagrange3(float u, float w[3])
{
    w[0] = 0.5f * u * (u - 1.0f);
    w[1] = 1.0f - u * u;
    w[2] = 0.5f * u * (u + 1.0f);
}

/* One target a lane: the same operations in the same order on any width. */
ORR_WIDE_VECTOR_CLONES
static void field_on_all(const qt_field *f, const qt_targets *g, qt_sums *out)
{
    const float inv_h = 1.0f / f->h;
#pragma omp simd
    for (size_t i = 0; i < g->n; i++) {
        float wx[3], wy[3], wz[3];
        lagrange3(g->x[i] * inv_h, wx);
        lagrange3(g->y[i] * inv_h, wy);
        lagrange3(g->z[i] * inv_h, wz);
        const float s = (g->e2[i] - f->e2lo) * f->inv_de2;
        float ax = 0, ay = 0, az = 0, ph = 0;
        for (int k = 0; k < 27; k++) {
            const float w = wx[k % 3] * wy[k / 3 % 3] * wz[k / 9];
            ax += w * (f->f0[0][k] + s * f->d[0][k]);
            ay += w * (f->f0[1][k] + s * f->d[1][k]);
            az += w * (f->f0[2][k] + s * f->d[2][k]);
            ph += w * (f->f0[3][k] + s * f->d[3][k]);
        }
        out->ax[i] += ax;
        out->ay[i] += ay;
        out->az[i] += az;
        out->phi[i] += ph;
    }
}

void qt_field_on(const qt_field *f, const qt_targets *g, qt_sums *out)
{
    field_on_all(f, g, out);
}
