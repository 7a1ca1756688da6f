/* The quadrupole group tree's force kernels (examples/nbody/qtree_kernels.c)
 * on made-up lists: bit for bit the plain scalar loop that sums the same
 * way (16 partial sums, every 16th entry, added pairwise), whichever copy
 * (SSE2, AVX2, AVX-512) the machine runs, so forces do not depend on the
 * vector width; and within 1e-6 of the same sums in double. The far
 * field's interpolation reproduces a tri-quadratic field, linear in the
 * softening^2, to float round-off. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "qtree_kernels.h"

#define NCELL 301 /* not a multiple of 16: the padding is used */
#define NPART 203

static float rnd(float lo, float hi)
{
    return lo + (hi - lo) * (float)rand() / (float)RAND_MAX;
}

/* A list block of n entries with room for its padding, padded as the
 * kernels expect (zero mass, softening^2 1). */
static float *new_block(size_t n, int fields, int m_field, int e2_field, size_t *cap)
{
    *cap = qt_padded(n);
    float *b = calloc(*cap * (size_t)fields, sizeof *b);
    for (size_t k = n; k < *cap; k++) {
        b[(size_t)m_field * *cap + k] = 0;
        b[(size_t)e2_field * *cap + k] = 1;
    }
    return b;
}

/* Cells 3 to 20 away, more of them towards +x (a net pull); particles of
 * nearby leaves, the first at the first target's place (its own term). */
static void make_lists(qt_lists *l, const qt_targets *g)
{
    l->ncell = NCELL;
    l->npart = NPART;
    l->c = new_block(NCELL, QT_CELL_FIELDS, QT_CM, QT_CE2, &l->cap_cell);
    l->p = new_block(NPART, QT_PART_FIELDS, QT_PM, QT_PE2, &l->cap_part);
    size_t cc = l->cap_cell, pc = l->cap_part;
    for (size_t k = 0; k < NCELL; k++) {
        float r = rnd(3, 20), mu = rnd(-0.5f, 1), ph = rnd(0, 6.2831853f), s = sqrtf(1 - mu * mu);
        float m = rnd(0.5f, 50), q[6] = {rnd(-1, 1), rnd(-1, 1), 0, rnd(-1, 1), rnd(-1, 1), rnd(-1, 1)};
        q[2] = -q[0] - q[1]; /* traceless */
        l->c[QT_CX * cc + k] = r * mu;
        l->c[QT_CY * cc + k] = r * s * cosf(ph);
        l->c[QT_CZ * cc + k] = r * s * sinf(ph);
        l->c[QT_CM * cc + k] = m;
        for (int a = 0; a < 6; a++)
            l->c[(QT_CQ0 + a) * cc + k] = m * q[a];
        l->c[QT_CE2 * cc + k] = rnd(0.0025f, 0.01f);
    }
    for (size_t k = 0; k < NPART; k++) {
        l->p[QT_PX * pc + k] = k ? rnd(-2, 2) : g->x[0];
        l->p[QT_PY * pc + k] = k ? rnd(-2, 2) : g->y[0];
        l->p[QT_PZ * pc + k] = k ? rnd(-2, 2) : g->z[0];
        l->p[QT_PM * pc + k] = rnd(0.1f, 1);
        l->p[QT_PE2 * pc + k] = k % 2 ? 0.0025f : 0.01f;
    }
}

/* One cell's or particle's terms on a target, in the kernels' expressions;
 * f[0..3]: ax ay az phi. */
static void cell_terms(const qt_lists *l, size_t k, float x, float y, float z, float e2i, float f[4])
{
    const float *c = l->c + k;
    size_t cap = l->cap_cell;
    float dx = x - c[QT_CX * cap], dy = y - c[QT_CY * cap], dz = z - c[QT_CZ * cap];
    float r2 = dx * dx + dy * dy + dz * dz + 0.5f * (e2i + c[QT_CE2 * cap]);
    float inv = 1.0f / sqrtf(r2), inv2 = inv * inv, inv3 = inv * inv2, inv5 = inv3 * inv2;
    float q0 = c[QT_CQ0 * cap], q1 = c[QT_CQ1 * cap], q2 = c[QT_CQ2 * cap];
    float q3 = c[QT_CQ3 * cap], q4 = c[QT_CQ4 * cap], q5 = c[QT_CQ5 * cap];
    float qx = q0 * dx + q3 * dy + q4 * dz, qy = q3 * dx + q1 * dy + q5 * dz, qz = q4 * dx + q5 * dy + q2 * dz;
    float dqd = dx * qx + dy * qy + dz * qz, m = c[QT_CM * cap];
    float s = -m * inv3 - 2.5f * dqd * inv5 * inv2;
    f[0] = s * dx + qx * inv5;
    f[1] = s * dy + qy * inv5;
    f[2] = s * dz + qz * inv5;
    f[3] = m * inv + 0.5f * dqd * inv5; /* subtracted */
}

static void part_terms(const qt_lists *l, size_t k, float x, float y, float z, float e2i, float f[4])
{
    const float *p = l->p + k;
    size_t cap = l->cap_part;
    float dx = p[QT_PX * cap] - x, dy = p[QT_PY * cap] - y, dz = p[QT_PZ * cap] - z;
    float r2 = dx * dx + dy * dy + dz * dz + 0.5f * (e2i + p[QT_PE2 * cap]);
    float inv = 1.0f / sqrtf(r2), m = p[QT_PM * cap], m3 = m * inv * inv * inv;
    f[0] = m3 * dx;
    f[1] = m3 * dy;
    f[2] = m3 * dz;
    f[3] = m * inv;
}

typedef void terms_fn(const qt_lists *, size_t, float, float, float, float, float[4]);

/* The scalar loop summing as the kernels do: entry k into partial sum
 * k mod 16 (padding included), then halves added pairwise. */
static void scalar_sums(const qt_lists *l, size_t n, terms_fn *terms, const qt_targets *g, qt_sums *out)
{
    for (size_t i = 0; i < g->n; i++) {
        float part[4][QT_LIST_LANES] = {{0}};
        for (size_t k = 0; k < qt_padded(n); k++) {
            float f[4];
            terms(l, k, g->x[i], g->y[i], g->z[i], g->e2[i], f);
            for (int a = 0; a < 3; a++)
                part[a][k % QT_LIST_LANES] += f[a];
            part[3][k % QT_LIST_LANES] -= f[3];
        }
        for (int a = 0; a < 4; a++)
            for (int w = QT_LIST_LANES / 2; w > 0; w /= 2)
                for (int j = 0; j < w; j++)
                    part[a][j] += part[a][j + w];
        out->ax[i] = part[0][0], out->ay[i] = part[1][0], out->az[i] = part[2][0], out->phi[i] = part[3][0];
    }
}

/* The largest relative difference of the kernels' sums from the same sums
 * in double (acceleration vectors, potentials). */
static double worst_against_double(const qt_lists *l, size_t n, terms_fn *terms, const qt_targets *g,
                                   const qt_sums *s)
{
    double worst = 0;
    for (size_t i = 0; i < g->n; i++) {
        double sum[4] = {0, 0, 0, 0};
        for (size_t k = 0; k < n; k++) {
            float f[4];
            terms(l, k, g->x[i], g->y[i], g->z[i], g->e2[i], f);
            for (int a = 0; a < 4; a++)
                sum[a] += f[a];
        }
        double d[3] = {s->ax[i] - sum[0], s->ay[i] - sum[1], s->az[i] - sum[2]};
        double da = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        double a = sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
        worst = fmax(worst, da / a);
        worst = fmax(worst, fabs(s->phi[i] + sum[3]) / sum[3]);
    }
    return worst;
}

static int same_bits(const qt_sums *a, const qt_sums *b, size_t n)
{
    return memcmp(a->ax, b->ax, n * sizeof *a->ax) == 0 && memcmp(a->ay, b->ay, n * sizeof *a->ay) == 0 &&
           memcmp(a->az, b->az, n * sizeof *a->az) == 0 && memcmp(a->phi, b->phi, n * sizeof *a->phi) == 0;
}

/* n targets at random within the cube of half-side half. */
static void random_targets(qt_targets *g, size_t n, float half)
{
    g->n = n;
    for (size_t i = 0; i < n; i++) {
        g->x[i] = rnd(-half, half);
        g->y[i] = rnd(-half, half);
        g->z[i] = rnd(-half, half);
    }
}

/* A tri-quadratic polynomial in the offset (x, y, z) / h, linear in the
 * softening^2 e2: what the far field's interpolation reproduces exactly. */
static double quadratic(int q, double x, double y, double z, double e2)
{
    return 1.0 + q - 0.7 * x + 0.3 * y * y - 0.2 * x * z + 0.15 * x * x * y * z * z + 0.05 * x * x * y * y * z * z +
           (2.0 - q) * e2 * (1.0 + 0.5 * x);
}

/* The field at random places within h of the centre against the
 * polynomial its grid was filled from; the worst difference. */
static double field_error(void)
{
    static qt_field f;
    const double h = 0.8, e2lo = 0.0025, e2hi = 0.01;
    f.h = (float)h;
    f.e2lo = (float)e2lo;
    f.inv_de2 = (float)(1.0 / (e2hi - e2lo));
    for (int q = 0; q < 4; q++)
        for (int k = 0; k < 27; k++) {
            double x = k % 3 - 1, y = k / 3 % 3 - 1, z = k / 9 - 1;
            f.f0[q][k] = (float)quadratic(q, x, y, z, e2lo);
            f.d[q][k] = (float)(quadratic(q, x, y, z, e2hi) - quadratic(q, x, y, z, e2lo));
        }
    static qt_targets g;
    static qt_sums out;
    random_targets(&g, QT_GROUP - 5, 0.55f);
    for (size_t i = 0; i < g.n; i++) {
        g.e2[i] = i % 3 ? 0.0025f : rnd(0.0025f, 0.01f);
        out.ax[i] = 1.0f; /* the field is added to what is there */
        out.ay[i] = out.az[i] = out.phi[i] = 0.0f;
    }
    qt_field_on(&f, &g, &out);
    double worst = 0;
    for (size_t i = 0; i < g.n; i++) {
        const float *v[4] = {&out.ax[i], &out.ay[i], &out.az[i], &out.phi[i]};
        for (int q = 0; q < 4; q++) {
            double want = quadratic(q, g.x[i] / h, g.y[i] / h, g.z[i] / h, g.e2[i]) + (q == 0);
            worst = fmax(worst, fabs(*v[q] - want) / fabs(want));
        }
    }
    return worst;
}

int main(void)
{
    srand(11);
    static qt_targets g;
    random_targets(&g, QT_GROUP - 3, 0.5f);
    for (size_t i = 0; i < g.n; i++)
        g.e2[i] = i % 2 ? 0.0025f : 0.01f;
    qt_lists l;
    make_lists(&l, &g);
    static qt_sums kernel, scalar;

    qt_cells_on(&l, &g, &kernel);
    scalar_sums(&l, l.ncell, cell_terms, &g, &scalar);
    CHECK(same_bits(&kernel, &scalar, g.n));
    double cells_err = worst_against_double(&l, l.ncell, cell_terms, &g, &kernel);

    qt_parts_on(&l, &g, &kernel);
    scalar_sums(&l, l.npart, part_terms, &g, &scalar);
    CHECK(same_bits(&kernel, &scalar, g.n));
    double parts_err = worst_against_double(&l, l.npart, part_terms, &g, &kernel);
    fprintf(stderr, "largest relative difference from double sums: cells %.2g, particles %.2g\n", cells_err,
            parts_err);
    CHECK(cells_err < 1e-6);
    CHECK(parts_err < 1e-6);

    double field_err = field_error();
    fprintf(stderr, "far field against a tri-quadratic field: largest relative difference %.2g\n", field_err);
    CHECK(field_err < 2e-6);

    /* A group of one, and an empty list. */
    g.n = 1;
    size_t ncell = l.ncell;
    l.ncell = 0;
    qt_cells_on(&l, &g, &kernel);
    CHECK(kernel.ax[0] == 0 && kernel.phi[0] == 0);
    l.ncell = ncell;
    free(l.c);
    free(l.p);
    return check_summary();
}
