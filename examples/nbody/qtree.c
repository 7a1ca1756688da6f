#include "qtree.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_DEPTH 48 /* beyond this a cell holds coincident particles: a leaf however many */

static int new_node(qt_tree *t)
{
    if (t->nnodes == t->cap) {
        size_t cap = t->cap ? 2 * t->cap : 1024;
        qt_node *nodes = realloc(t->nodes, cap * sizeof *nodes);
        if (!nodes)
            return -1;
        t->nodes = nodes;
        t->cap = cap;
    }
    qt_node *nd = &t->nodes[t->nnodes];
    memset(nd, 0, sizeof *nd);
    for (int k = 0; k < 8; k++)
        nd->child[k] = -1;
    return (int)t->nnodes++;
}

static int add_group(qt_tree *t, int node)
{
    if (t->ngroups == t->groups_cap) {
        size_t cap = t->groups_cap ? 2 * t->groups_cap : 256;
        int *g = realloc(t->groups, cap * sizeof *g);
        if (!g)
            return -1;
        t->groups = g;
        t->groups_cap = cap;
    }
    t->groups[t->ngroups++] = node;
    return 0;
}

static int octant(const double *p, const double *c)
{
    return (p[0] >= c[0]) | (p[1] >= c[1]) << 1 | (p[2] >= c[2]) << 2;
}

/* A node's mass, centre of mass and mean softening^2 from the sums of m,
 * m x and m eps^2 over its particles. */
static void set_mass_centre(qt_node *nd, double m, const double c[3], double e2)
{
    for (int k = 0; k < 3; k++)
        nd->com[k] = m > 0 ? c[k] / m : nd->centre[k];
    nd->mass = m;
    nd->eps2 = m > 0 ? e2 / m : 0.0;
}

/* Adds m (3 y y - y^2 I) to the traceless quadrupole q (xx yy zz xy xz yz). */
static void add_quad(double q[6], double m, const double y[3])
{
    double y2 = y[0] * y[0] + y[1] * y[1] + y[2] * y[2];
    q[0] += m * (3 * y[0] * y[0] - y2);
    q[1] += m * (3 * y[1] * y[1] - y2);
    q[2] += m * (3 * y[2] * y[2] - y2);
    q[3] += m * 3 * y[0] * y[1];
    q[4] += m * 3 * y[0] * y[2];
    q[5] += m * 3 * y[1] * y[2];
}

/* Mass, centre of mass, traceless quadrupole, b_max and mean softening^2
 * of a node, from its particles directly (each particle is visited once per
 * level: N log N in all, a small part of a step). */
static void node_moments(qt_tree *t, qt_node *nd, const double *pos, const double *mass, const double *eps)
{
    double m = 0, c[3] = {0, 0, 0}, e2 = 0;
    for (size_t j = nd->first; j < nd->first + nd->count; j++) {
        size_t i = t->order[j];
        m += mass[i];
        for (int k = 0; k < 3; k++)
            c[k] += mass[i] * pos[3 * i + k];
        e2 += mass[i] * eps[i] * eps[i];
    }
    set_mass_centre(nd, m, c, e2);
    double q[6] = {0}, b2 = 0;
    for (size_t j = nd->first; j < nd->first + nd->count; j++) {
        size_t i = t->order[j];
        double y[3] = {pos[3 * i] - nd->com[0], pos[3 * i + 1] - nd->com[1], pos[3 * i + 2] - nd->com[2]};
        add_quad(q, mass[i], y);
        b2 = fmax(b2, y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
    }
    memcpy(nd->quad, q, sizeof q);
    nd->bmax = sqrt(b2);
}

typedef struct build_in {
    const double *pos, *mass, *eps;
} build_in;

static int build_node(qt_tree *t, const build_in *in, size_t first, size_t count, const double centre[3],
                      double half, int depth, int in_group)
{
    int id = new_node(t);
    if (id < 0)
        return -1;
    qt_node *nd = &t->nodes[id];
    memcpy(nd->centre, centre, sizeof nd->centre);
    nd->half = half;
    nd->first = first;
    nd->count = count;
    node_moments(t, nd, in->pos, in->mass, in->eps);
    if (!in_group && count <= QT_GROUP) {
        if (add_group(t, id) != 0)
            return -1;
        in_group = 1;
    }
    if (count <= QT_LEAF || depth >= MAX_DEPTH) {
        nd->leaf = 1;
        return id;
    }
    /* Counting sort of the cell's particles by octant. */
    size_t counts[8] = {0}, starts[8], fill[8];
    for (size_t j = first; j < first + count; j++)
        counts[octant(&in->pos[3 * t->order[j]], centre)]++;
    starts[0] = first;
    for (int k = 1; k < 8; k++)
        starts[k] = starts[k - 1] + counts[k - 1];
    memcpy(fill, starts, sizeof fill);
    for (size_t j = first; j < first + count; j++) {
        size_t i = t->order[j];
        t->scratch[fill[octant(&in->pos[3 * i], centre)]++] = i;
    }
    memcpy(&t->order[first], &t->scratch[first], count * sizeof *t->order);
    for (int k = 0; k < 8; k++) {
        if (!counts[k])
            continue;
        double cc[3];
        for (int a = 0; a < 3; a++)
            cc[a] = centre[a] + ((k >> a) & 1 ? 0.5 : -0.5) * half;
        int child = build_node(t, in, starts[k], counts[k], cc, 0.5 * half, depth + 1, in_group);
        if (child < 0)
            return -1;
        t->nodes[id].child[k] = child; /* the pool may have moved */
    }
    return id;
}

static int resize(qt_tree *t, size_t n)
{
    free(t->order);
    free(t->scratch);
    free(t->px);
    t->order = malloc(n * sizeof *t->order);
    t->scratch = malloc(n * sizeof *t->scratch);
    t->px = malloc(5 * n * sizeof *t->px);
    t->n = n;
    if (!t->order || !t->scratch || !t->px)
        return -1;
    t->py = t->px + n;
    t->pz = t->py + n;
    t->pm = t->pz + n;
    t->pe2 = t->pm + n;
    return 0;
}

int qt_build(qt_tree *t, const double *pos, const double *mass, const double *eps, size_t n)
{
    t->nnodes = 0;
    t->ngroups = 0;
    if ((n != t->n || !t->order) && resize(t, n) != 0)
        return -1;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < n; i++) {
        t->order[i] = i;
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], pos[3 * i + k]);
            hi[k] = fmax(hi[k], pos[3 * i + k]);
        }
    }
    double centre[3], half = 0;
    for (int k = 0; k < 3; k++) {
        centre[k] = n ? 0.5 * (lo[k] + hi[k]) : 0.0;
        half = fmax(half, n ? 0.5 * (hi[k] - lo[k]) : 0.0);
    }
    half = half * 1.0001 + 1e-12;
    build_in in = {pos, mass, eps};
    if (build_node(t, &in, 0, n, centre, half, 0, 0) < 0)
        return -1;
    /* The walk reads particles in tree order, contiguously. */
    for (size_t j = 0; j < n; j++) {
        size_t i = t->order[j];
        t->px[j] = pos[3 * i];
        t->py[j] = pos[3 * i + 1];
        t->pz[j] = pos[3 * i + 2];
        t->pm[j] = mass[i];
        t->pe2[j] = eps[i] * eps[i];
    }
    return 0;
}

/* A parent's moments from its children's: masses and first moments add;
 * each child's quadrupole moves to the parent's centre of mass by the
 * parallel-axis rule, Q += m_c (3 d d - d^2 I), d = com_c - com. */
static void moments_from_children(qt_node *nodes, qt_node *nd)
{
    double m = 0, c[3] = {0, 0, 0}, e2 = 0;
    for (int k = 0; k < 8; k++)
        if (nd->child[k] >= 0) {
            const qt_node *ch = &nodes[nd->child[k]];
            m += ch->mass;
            e2 += ch->mass * ch->eps2;
            for (int a = 0; a < 3; a++)
                c[a] += ch->mass * ch->com[a];
        }
    set_mass_centre(nd, m, c, e2);
    double q[6] = {0}, b = 0;
    for (int k = 0; k < 8; k++)
        if (nd->child[k] >= 0) {
            const qt_node *ch = &nodes[nd->child[k]];
            double d[3] = {ch->com[0] - nd->com[0], ch->com[1] - nd->com[1], ch->com[2] - nd->com[2]};
            for (int a = 0; a < 6; a++)
                q[a] += ch->quad[a];
            add_quad(q, ch->mass, d);
            b = fmax(b, sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) + ch->bmax);
        }
    memcpy(nd->quad, q, sizeof q);
    nd->bmax = b;
}

void qt_refresh(qt_tree *t, const double *pos)
{
    for (size_t j = 0; j < t->n; j++) {
        size_t i = t->order[j];
        t->px[j] = pos[3 * i];
        t->py[j] = pos[3 * i + 1];
        t->pz[j] = pos[3 * i + 2];
    }
    /* Children are made after their parents: backwards, every child is
     * done before its parent. Leaves use the tree-order copies (the same
     * positions) and the masses and softenings of the build. */
    for (size_t id = t->nnodes; id-- > 0;) {
        qt_node *nd = &t->nodes[id];
        if (!nd->leaf) {
            moments_from_children(t->nodes, nd);
            continue;
        }
        double m = 0, c[3] = {0, 0, 0}, e2 = 0;
        for (size_t j = nd->first; j < nd->first + nd->count; j++) {
            m += t->pm[j];
            c[0] += t->pm[j] * t->px[j];
            c[1] += t->pm[j] * t->py[j];
            c[2] += t->pm[j] * t->pz[j];
            e2 += t->pm[j] * t->pe2[j];
        }
        set_mass_centre(nd, m, c, e2);
        double q[6] = {0}, b2 = 0;
        for (size_t j = nd->first; j < nd->first + nd->count; j++) {
            double y[3] = {t->px[j] - nd->com[0], t->py[j] - nd->com[1], t->pz[j] - nd->com[2]};
            add_quad(q, t->pm[j], y);
            b2 = fmax(b2, y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
        }
        memcpy(nd->quad, q, sizeof q);
        nd->bmax = sqrt(b2);
    }
}

/* ---- walk --------------------------------------------------------------- */

/* A thread's interaction lists for one group, gathered into contiguous
 * float arrays relative to the group's centre of mass so the loops over
 * them vectorise: cells taken whole (mass, quadrupole, softening^2) and
 * particles of opened leaves. Float is safe here: offsets from the group
 * are at most the system's size and need ~1e-7 relative precision against
 * the tree's ~1e-3 errors; sums are over at most ~1e4 terms. */
typedef struct lists {
    size_t ncell, npart, cap_cell, cap_part;
    float *c; /* per cell: x y z m q0..q5 e2, 11 arrays of cap_cell */
    float *p; /* per particle: x y z m e2, 5 arrays of cap_part */
} lists;

enum { CX, CY, CZ, CM, CQ0, CQ1, CQ2, CQ3, CQ4, CQ5, CE2, CELL_FIELDS };
enum { PX, PY, PZ, PM, PE2, PART_FIELDS };

/* Grows one structure-of-arrays block, keeping the first `used` entries. */
static int grow(float **block, size_t *cap, size_t used, size_t need, int fields)
{
    if (need <= *cap)
        return 0;
    size_t cap2 = 2 * need + 256;
    float *b = malloc(cap2 * (size_t)fields * sizeof *b);
    if (!b)
        return -1;
    for (int f = 0; f < fields && *block; f++)
        memcpy(b + (size_t)f * cap2, *block + (size_t)f * *cap, used * sizeof *b);
    free(*block);
    *block = b;
    *cap = cap2;
    return 0;
}

static int push_cell(lists *l, const qt_node *nd, const double g[3])
{
    if (grow(&l->c, &l->cap_cell, l->ncell, l->ncell + 1, CELL_FIELDS) != 0)
        return -1;
    float *c = l->c;
    size_t k = l->ncell++, cap = l->cap_cell;
    c[CX * cap + k] = (float)(nd->com[0] - g[0]);
    c[CY * cap + k] = (float)(nd->com[1] - g[1]);
    c[CZ * cap + k] = (float)(nd->com[2] - g[2]);
    c[CM * cap + k] = (float)nd->mass;
    for (int q = 0; q < 6; q++)
        c[(CQ0 + q) * cap + k] = (float)nd->quad[q];
    c[CE2 * cap + k] = (float)nd->eps2;
    return 0;
}

static int push_leaf(lists *l, const qt_tree *t, const qt_node *nd, const double g[3])
{
    if (grow(&l->p, &l->cap_part, l->npart, l->npart + nd->count, PART_FIELDS) != 0)
        return -1;
    float *p = l->p;
    size_t cap = l->cap_part;
    for (size_t j = nd->first; j < nd->first + nd->count; j++) {
        size_t k = l->npart++;
        p[PX * cap + k] = (float)(t->px[j] - g[0]);
        p[PY * cap + k] = (float)(t->py[j] - g[1]);
        p[PZ * cap + k] = (float)(t->pz[j] - g[2]);
        p[PM * cap + k] = (float)t->pm[j];
        p[PE2 * cap + k] = (float)t->pe2[j];
    }
    return 0;
}

/* The interaction lists of group g: every cell passing the b_max criterion
 * for the group's bounding sphere (its centre of mass, radius b_max) is
 * taken whole; leaves that do not are taken particle by particle. theta <= 1
 * guarantees a cell holding the group is always opened (see qtree.h). */
static int make_lists(const qt_tree *t, const qt_node *g, double theta, lists *l)
{
    int stack[8 * MAX_DEPTH + 8];
    int top = 0;
    l->ncell = l->npart = 0;
    stack[top++] = 0;
    while (top > 0) {
        int id = stack[--top];
        const qt_node *nd = &t->nodes[id];
        double d[3] = {nd->com[0] - g->com[0], nd->com[1] - g->com[1], nd->com[2] - g->com[2]};
        double dist = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) - g->bmax;
        if (dist > 0 && dist * theta > nd->bmax) {
            if (push_cell(l, nd, g->com) != 0)
                return -1;
        } else if (nd->leaf) {
            if (push_leaf(l, t, nd, g->com) != 0)
                return -1;
        } else {
            for (int k = 0; k < 8; k++)
                if (nd->child[k] >= 0)
                    stack[top++] = nd->child[k];
        }
    }
    return 0;
}

/* Softened monopole + quadrupole of the list's cells at the particle
 * (x, y, z), offsets d = x - com, softened with (eps_i^2 + <eps^2>_cell) / 2:
 * the pair rule averaged over the cell to first order in eps^2, so a cell
 * mixing halo and disc particles costs no systematic error:
 *   Phi = -[M / r + (d.Q.d) / (2 r^5)],  a = -grad Phi
 *       = -M d / r^3 + Q.d / r^5 - 5/2 (d.Q.d) d / r^7,
 * with r^2 = |d|^2 + eps^2 (the usual softened expansion; cells taken whole
 * are far beyond the softening). Adds to a[3] and *phi (without G). */
static void cells_on(const lists *l, float x, float y, float z, float e2i, double a[3], double *phi)
{
    const size_t cap = l->cap_cell;
    const float *c = l->c;
    float ax = 0, ay = 0, az = 0, ph = 0;
#pragma omp simd reduction(+ : ax, ay, az, ph)
    for (size_t k = 0; k < l->ncell; k++) {
        float dx = x - c[CX * cap + k], dy = y - c[CY * cap + k], dz = z - c[CZ * cap + k];
        float r2 = dx * dx + dy * dy + dz * dz + 0.5f * (e2i + c[CE2 * cap + k]);
        float inv = 1.0f / sqrtf(r2), inv2 = inv * inv, inv3 = inv * inv2, inv5 = inv3 * inv2;
        float q0 = c[CQ0 * cap + k], q1 = c[CQ1 * cap + k], q2 = c[CQ2 * cap + k];
        float q3 = c[CQ3 * cap + k], q4 = c[CQ4 * cap + k], q5 = c[CQ5 * cap + k];
        float qx = q0 * dx + q3 * dy + q4 * dz, qy = q3 * dx + q1 * dy + q5 * dz, qz = q4 * dx + q5 * dy + q2 * dz;
        float dqd = dx * qx + dy * qy + dz * qz, m = c[CM * cap + k];
        float s = -m * inv3 - 2.5f * dqd * inv5 * inv2;
        ax += s * dx + qx * inv5;
        ay += s * dy + qy * inv5;
        az += s * dz + qz * inv5;
        ph -= m * inv + 0.5f * dqd * inv5;
    }
    a[0] += ax;
    a[1] += ay;
    a[2] += az;
    *phi += ph;
}

/* Plummer-softened pulls of the list's particles; the particle itself is in
 * the list (its own leaf) and adds no force (zero offset) and -m / eps to
 * the potential, which the caller removes. */
static void parts_on(const lists *l, float x, float y, float z, float e2i, double a[3], double *phi)
{
    const size_t cap = l->cap_part;
    const float *p = l->p;
    float ax = 0, ay = 0, az = 0, ph = 0;
#pragma omp simd reduction(+ : ax, ay, az, ph)
    for (size_t k = 0; k < l->npart; k++) {
        float dx = p[PX * cap + k] - x, dy = p[PY * cap + k] - y, dz = p[PZ * cap + k] - z;
        float r2 = dx * dx + dy * dy + dz * dz + 0.5f * (e2i + p[PE2 * cap + k]);
        float inv = 1.0f / sqrtf(r2), m = p[PM * cap + k], m3 = m * inv * inv * inv;
        ax += m3 * dx;
        ay += m3 * dy;
        az += m3 * dz;
        ph -= m * inv;
    }
    a[0] += ax;
    a[1] += ay;
    a[2] += az;
    *phi += ph;
}

/* Whether the caller asked for particle i (of the whole set). */
static int wanted(size_t i, size_t first, size_t count, const unsigned char *active)
{
    return i >= first && i < first + count && (!active || active[i - first]);
}

/* The group's particles that the caller asked for, against its lists. */
static void apply_lists(const qt_tree *t, const qt_node *g, const lists *l, double G, size_t first, size_t count,
                        const unsigned char *active, double *acc, double *pot)
{
    for (size_t j = g->first; j < g->first + g->count; j++) {
        size_t i = t->order[j];
        if (!wanted(i, first, count, active))
            continue;
        float x = (float)(t->px[j] - g->com[0]), y = (float)(t->py[j] - g->com[1]), z = (float)(t->pz[j] - g->com[2]);
        float e2i = (float)t->pe2[j];
        double a[3] = {0, 0, 0}, phi = 0;
        cells_on(l, x, y, z, e2i, a, &phi);
        parts_on(l, x, y, z, e2i, a, &phi);
        if (e2i > 0)
            phi += t->pm[j] / sqrt((double)e2i); /* its own term */
        size_t o = i - first;
        for (int k = 0; k < 3; k++)
            acc[3 * o + k] = G * a[k];
        if (pot)
            pot[o] = G * phi;
    }
}

double qt_accelerations_of(const qt_tree *t, double G, double theta, size_t first, size_t count, double *acc,
                           double *pot)
{
    return qt_accelerations_masked(t, G, theta, first, count, NULL, acc, pot);
}

double qt_accelerations_masked(const qt_tree *t, double G, double theta, size_t first, size_t count,
                               const unsigned char *active, double *acc, double *pot)
{
    double total = 0;
    int failed = 0;
    const long ng = (long)t->ngroups;
#pragma omp parallel reduction(+ : total) reduction(| : failed)
    {
        lists l = {0};
#pragma omp for schedule(dynamic, 4)
        for (long k = 0; k < ng; k++) {
            const qt_node *g = &t->nodes[t->groups[k]];
            size_t mine = 0; /* groups with none of the requested particles cost nothing */
            for (size_t j = g->first; j < g->first + g->count; j++)
                mine += wanted(t->order[j], first, count, active);
            if (!mine || failed)
                continue;
            if (make_lists(t, g, theta, &l) != 0) {
                failed = 1;
                continue;
            }
            apply_lists(t, g, &l, G, first, count, active, acc, pot);
            total += (double)mine * (double)(l.ncell + l.npart);
        }
        free(l.c);
        free(l.p);
    }
    return failed ? -1.0 : total;
}

void qt_direct(const double *pos, const double *mass, const double *eps, size_t n, double G, size_t first,
               size_t count, double *acc, double *pot)
{
#pragma omp parallel for schedule(static)
    for (size_t o = 0; o < count; o++) {
        size_t i = first + o;
        double a[3] = {0, 0, 0}, phi = 0;
        for (size_t q = 0; q < n; q++) {
            if (q == i)
                continue;
            double d[3] = {pos[3 * q] - pos[3 * i], pos[3 * q + 1] - pos[3 * i + 1], pos[3 * q + 2] - pos[3 * i + 2]};
            double r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + 0.5 * (eps[i] * eps[i] + eps[q] * eps[q]);
            double inv = 1.0 / sqrt(r2), m3 = mass[q] * inv * inv * inv;
            for (int k = 0; k < 3; k++)
                a[k] += m3 * d[k];
            phi -= mass[q] * inv;
        }
        for (int k = 0; k < 3; k++)
            acc[3 * o + k] = G * a[k];
        if (pot)
            pot[o] = G * phi;
    }
}

void qt_free(qt_tree *t)
{
    free(t->nodes);
    free(t->order);
    free(t->scratch);
    free(t->groups);
    free(t->px);
    memset(t, 0, sizeof *t);
}
