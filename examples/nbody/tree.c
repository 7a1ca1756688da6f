#include "tree.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define LEAF_SIZE 8
#define MAX_DEPTH 48 /* beyond this a cell holds coincident particles: a leaf however many */

static int new_node(bh_tree *t)
{
    if (t->nnodes == t->cap) {
        size_t cap = t->cap ? 2 * t->cap : 1024;
        bh_node *nodes = realloc(t->nodes, cap * sizeof *nodes);
        if (!nodes)
            return -1;
        t->nodes = nodes;
        t->cap = cap;
    }
    bh_node *nd = &t->nodes[t->nnodes];
    memset(nd, 0, sizeof *nd);
    for (int k = 0; k < 8; k++)
        nd->child[k] = -1;
    return (int)t->nnodes++;
}

static int octant(const double *p, const double *c)
{
    return (p[0] >= c[0]) | (p[1] >= c[1]) << 1 | (p[2] >= c[2]) << 2;
}

/* Builds the node for order[first, first + count) in the given cube; its
 * mass and centre of mass are summed from its children. */
static int build_node(bh_tree *t, const double *pos, const double *mass, size_t first, size_t count,
                      const double centre[3], double half, int depth)
{
    int id = new_node(t);
    if (id < 0)
        return -1;
    bh_node *nd = &t->nodes[id];
    memcpy(nd->centre, centre, sizeof nd->centre);
    nd->half = half;
    nd->first = first;
    nd->count = count;
    if (count <= LEAF_SIZE || depth >= MAX_DEPTH) {
        nd->leaf = 1;
        double m = 0, c[3] = {0, 0, 0};
        for (size_t j = first; j < first + count; j++) {
            size_t i = t->order[j];
            m += mass[i];
            for (int k = 0; k < 3; k++)
                c[k] += mass[i] * pos[3 * i + k];
        }
        nd->mass = m;
        for (int k = 0; k < 3; k++)
            nd->com[k] = m > 0 ? c[k] / m : centre[k];
        return id;
    }
    /* Counting sort of the cell's particles by octant. */
    size_t counts[8] = {0}, starts[8];
    for (size_t j = first; j < first + count; j++)
        counts[octant(&pos[3 * t->order[j]], centre)]++;
    starts[0] = first;
    for (int k = 1; k < 8; k++)
        starts[k] = starts[k - 1] + counts[k - 1];
    size_t fill[8];
    memcpy(fill, starts, sizeof fill);
    for (size_t j = first; j < first + count; j++) {
        size_t i = t->order[j];
        t->scratch[fill[octant(&pos[3 * i], centre)]++] = i;
    }
    memcpy(&t->order[first], &t->scratch[first], count * sizeof *t->order);
    double m = 0, c[3] = {0, 0, 0};
    for (int k = 0; k < 8; k++) {
        if (!counts[k])
            continue;
        double cc[3];
        for (int a = 0; a < 3; a++)
            cc[a] = centre[a] + ((k >> a) & 1 ? 0.5 : -0.5) * half;
        int child = build_node(t, pos, mass, starts[k], counts[k], cc, 0.5 * half, depth + 1);
        if (child < 0)
            return -1;
        nd = &t->nodes[id]; /* the pool may have moved */
        nd->child[k] = child;
        const bh_node *ch = &t->nodes[child];
        m += ch->mass;
        for (int a = 0; a < 3; a++)
            c[a] += ch->mass * ch->com[a];
    }
    nd->mass = m;
    for (int a = 0; a < 3; a++)
        nd->com[a] = m > 0 ? c[a] / m : centre[a];
    return id;
}

int bh_build(bh_tree *t, const double *pos, const double *mass, size_t n)
{
    t->nnodes = 0;
    if (n != t->n) {
        free(t->order);
        free(t->scratch);
        t->order = malloc(n * sizeof *t->order);
        t->scratch = malloc(n * sizeof *t->scratch);
        t->n = n;
        if (!t->order || !t->scratch)
            return -1;
    }
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
        centre[k] = 0.5 * (lo[k] + hi[k]);
        half = fmax(half, 0.5 * (hi[k] - lo[k]));
    }
    half = half * 1.0001 + 1e-12;
    return build_node(t, pos, mass, 0, n, centre, half, 0) < 0 ? -1 : 0;
}

/* Plummer-softened pull of mass m at offset d (from the particle toward m). */
static inline void pull(double acc[3], const double d[3], double m, double eps2)
{
    double r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + eps2;
    double inv = 1.0 / sqrt(r2);
    double f = m * inv * inv * inv;
    for (int k = 0; k < 3; k++)
        acc[k] += f * d[k];
}

static double walk(const bh_tree *t, const double *pos, const double *mass, size_t i, double eps2, double theta2,
                   double out[3])
{
    int stack[8 * MAX_DEPTH + 8];
    int top = 0;
    double interactions = 0, acc[3] = {0, 0, 0};
    const double *p = &pos[3 * i];
    stack[top++] = 0;
    while (top > 0) {
        const bh_node *nd = &t->nodes[stack[--top]];
        double d[3] = {nd->com[0] - p[0], nd->com[1] - p[1], nd->com[2] - p[2]};
        double r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        double side = 2 * nd->half;
        if (!nd->leaf && side * side < theta2 * r2) {
            pull(acc, d, nd->mass, eps2);
            interactions++;
        } else if (nd->leaf) {
            for (size_t j = nd->first; j < nd->first + nd->count; j++) {
                size_t q = t->order[j];
                if (q == i)
                    continue;
                double dq[3] = {pos[3 * q] - p[0], pos[3 * q + 1] - p[1], pos[3 * q + 2] - p[2]};
                pull(acc, dq, mass[q], eps2);
                interactions++;
            }
        } else {
            for (int k = 0; k < 8; k++)
                if (nd->child[k] >= 0)
                    stack[top++] = nd->child[k];
        }
    }
    memcpy(out, acc, sizeof acc);
    return interactions;
}

double bh_accelerations(const bh_tree *t, const double *pos, const double *mass, double G, double eps,
                        double theta, double *acc)
{
    return bh_accelerations_of(t, pos, mass, G, eps, theta, 0, t->n, acc);
}

double bh_accelerations_of(const bh_tree *t, const double *pos, const double *mass, double G, double eps,
                           double theta, size_t first, size_t count, double *acc)
{
    double total = 0;
    const long n = (long)count;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : total)
    for (long i = 0; i < n; i++) {
        double *a = &acc[3 * i];
        total += walk(t, pos, mass, first + (size_t)i, eps * eps, theta * theta, a);
        for (int k = 0; k < 3; k++)
            a[k] *= G;
    }
    return total;
}

void direct_accelerations(const double *pos, const double *mass, size_t n, double G, double eps, double *acc)
{
    for (size_t i = 0; i < n; i++) {
        double a[3] = {0, 0, 0};
        for (size_t q = 0; q < n; q++) {
            if (q == i)
                continue;
            double d[3] = {pos[3 * q] - pos[3 * i], pos[3 * q + 1] - pos[3 * i + 1], pos[3 * q + 2] - pos[3 * i + 2]};
            pull(a, d, mass[q], eps * eps);
        }
        for (int k = 0; k < 3; k++)
            acc[3 * i + k] = G * a[k];
    }
}

void bh_free(bh_tree *t)
{
    free(t->nodes);
    free(t->order);
    free(t->scratch);
    memset(t, 0, sizeof *t);
}
