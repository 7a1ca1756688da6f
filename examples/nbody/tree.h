/* A Barnes-Hut octree for the example N-body code: monopole moments,
 * Plummer softening, leaves of a few particles. Positions, masses and
 * accelerations are double. */
#ifndef NBODY_TREE_H
#define NBODY_TREE_H

#include <stddef.h>

typedef struct bh_node {
    double com[3];     /* centre of mass */
    double mass;
    double centre[3];  /* the cube's centre */
    double half;       /* half its side */
    int child[8];      /* child nodes, -1 where empty; all -1 in a leaf */
    size_t first, count; /* a leaf's particles: order[first .. first + count) */
    int leaf;
} bh_node;

typedef struct bh_tree {
    bh_node *nodes;
    size_t nnodes, cap;
    size_t *order;     /* particle indices, grouped by leaf */
    size_t *scratch;
    size_t n;
} bh_tree;

/* Builds the tree over n particles (pos: x, y, z of particle i at 3i). */
int bh_build(bh_tree *t, const double *pos, const double *mass, size_t n);

/* Gravitational accelerations of every particle, G times the usual sum with
 * Plummer softening eps, opening angle theta (a cell of side s at distance d
 * from the particle is taken whole when s < theta d). Threaded (OpenMP).
 * Returns the number of particle-cell and particle-particle interactions. */
double bh_accelerations(const bh_tree *t, const double *pos, const double *mass, double G, double eps,
                        double theta, double *acc);

/* The same for particles first .. first + count - 1 only, into acc[0 ..
 * 3 count): a process's own particles, the tree being over all of them. */
double bh_accelerations_of(const bh_tree *t, const double *pos, const double *mass, double G, double eps,
                           double theta, size_t first, size_t count, double *acc);

/* The same by direct summation, O(n^2): the reference for tests. */
void direct_accelerations(const double *pos, const double *mass, size_t n, double G, double eps, double *acc);

void bh_free(bh_tree *t);

#endif
