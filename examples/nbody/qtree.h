/* The example N-body code's second tree: an octree with quadrupole moments
 * walked once per group of nearby particles (Barnes 1990, J. Comp. Phys. 87,
 * 161), with per-particle Plummer softening and potentials. It replaces the
 * monopole tree (tree.h, kept as the reference the bench compares with).
 *
 * Opening criterion (the "bmax" criterion of Salmon & Warren 1994): a cell
 * of centre of mass c is taken whole for a group of centre g and radius
 * r_g when |c - g| - r_g > b_max / theta, b_max being the largest distance
 * from c to any of the cell's particles. Every particle of the group is then
 * at least b_max / theta from c, so the error bound holds for each of them.
 *
 * The groups of a super-group (the largest nodes with at most QT_SUPER
 * particles, ~8 groups) walk the tree together, once: each node is tested
 * for the groups that opened all its ancestors, so each group gets the
 * lists of its own walk from the root, and the cells all of them take
 * whole are listed (and their moments converted) once, for all. */
#ifndef NBODY_QTREE_H
#define NBODY_QTREE_H

#include <stddef.h>
#include <stdint.h>

typedef struct qt_node {
    double com[3];
    double mass;
    double quad[6];   /* traceless quadrupole sum m (3 y_a y_b - y^2 delta_ab): xx yy zz xy xz yz */
    double bmax;      /* largest distance from com to one of its particles */
    double eps2;      /* mass-weighted mean softening^2 of its particles */
    int child[8];     /* -1 where empty; all -1 in a leaf */
    size_t first, count; /* its particles: order[first .. first + count) */
} qt_node; /* (its cube's centre and size only the build uses: not kept) */

/* Whether a node is a leaf (no children). */
static inline int qt_is_leaf(const qt_node *nd)
{
    for (int k = 0; k < 8; k++)
        if (nd->child[k] >= 0)
            return 0;
    return 1;
}

/* A node's centre of mass and b_max, the node after its subtree in the
 * depth-first order, and its mass, quadrupole and mean softening^2 in
 * float: what the walk reads (qtree.c, index_walk). */
typedef struct qt_walk_node {
    double com[3];
    double bmax;
    size_t next;
    float moments[8]; /* m, q0..q5, eps2 */
} qt_walk_node;

typedef struct qt_tree {
    qt_node *nodes;
    size_t nnodes, cap;
    size_t *order;          /* tree position -> the caller's particle */
    size_t *scratch;        /* scratch, key, key_tmp: the build's counting sorts */
    uint64_t *key, *key_tmp; /* each particle's octant at every level (qtree.c, point_key) */
    size_t n;
    int *groups; /* the nodes walked as groups: the largest with at most QT_GROUP particles */
    size_t ngroups, groups_cap;
    int *supers;               /* super-groups: the largest nodes with at most QT_SUPER particles */
    size_t *super_first_group; /* super s holds groups super_first_group[s] .. [s + 1] - 1 */
    size_t nsupers, supers_cap;
    int root_walks; /* set by the caller: every group walks the tree from its root, without its super-group's walk
                       (the walk before super-groups, kept for `bench_nbody steps` and `substeps` to compare) */
    double *px, *py, *pz, *pm, *pe2; /* particles in tree order (structure of arrays) */
    qt_walk_node *walk;              /* nnodes of them, for the walk */
    /* qt_build_with_moments: particles cells_first + c, c < ncells (in the
     * caller's order) are cells of their own with quadrupole xquad[6 c ..] and
     * b_max xbmax[c] (an MPI rank's imported cells, domain.c); ncells 0 in
     * qt_build. Read by the walk too. */
    const double *xquad, *xbmax;
    size_t cells_first, ncells;
    size_t walk_cap;
} qt_tree;

#ifndef QT_LEAF
#define QT_LEAF 16
#endif
#ifndef QT_GROUP
#define QT_GROUP 64
#endif
#ifndef QT_SUPER
#define QT_SUPER 512
#endif
#ifndef QT_FAR
#define QT_FAR 2.8 /* cells beyond QT_FAR / theta times a super-group's radius act through its field
                      (qtree_kernels.h): 4 radii at theta = 0.7, none as theta -> 0 */
#endif
#ifndef QT_FIELD_MIN
#define QT_FIELD_MIN 64 /* the least particles of a super-group with a field (its grid costs 27 or 54 targets) */
#endif

/* Builds the tree over n particles (pos: x, y, z of particle i at 3i;
 * eps: each particle's Plummer softening), on every OpenMP thread when
 * there are several (qtree.c, build_part): the same tree, node for node,
 * on any thread count. Returns 0, or -1 when out of memory. */
int qt_build(qt_tree *t, const double *pos, const double *mass, const double *eps, size_t n);

/* The same over particles of which ncells from cells_first on are cells
 * of another rank's tree (domain.c): particle cells_first + c has its own
 * traceless quadrupole quad[6 c .. 6 c + 6) about its position (its centre
 * of mass) and b_max bmax[c], which the cells holding it add up, and which
 * a leaf opened near a group passes on to the group's lists as a cell. quad
 * and bmax must stay valid while the tree is walked. */
int qt_build_with_moments(qt_tree *t, const double *pos, const double *mass, const double *eps, const double *quad,
                          const double *bmax, size_t cells_first, size_t ncells, size_t n);

/* Frees what only a build uses (its sorts' scratch arrays), until the
 * next build: less memory while the tree is walked. */
void qt_drop_build_scratch(qt_tree *t);

/* Accelerations (and potentials, if pot is not NULL) of particles first ..
 * first + count - 1, into acc[0 .. 3 count) and pot[0 .. count): G times the
 * Plummer-softened sums, a pair i, j softened with eps^2 = (eps_i^2 + eps_j^2) / 2
 * (particles of one kind: their own eps; the rule is linear in eps^2, so a
 * cell's mean eps^2 stands for its particles exactly to first order).
 * Threaded (OpenMP) over groups. Returns the number of particle-cell and
 * particle-particle interactions. */
double qt_accelerations_of(const qt_tree *t, double G, double theta, size_t first, size_t count, double *acc,
                           double *pot);

/* The same for the particles o of that range with active[o] != 0 only (the
 * others' acc and pot are left as they were): the forces of a block time
 * step, where only the particles whose step ends are kicked. They are
 * those of qt_accelerations_of, bit for bit. A super-group with no active
 * particle costs nothing; in one with some, only the groups with active
 * particles build lists (the others are tested only where the super-group
 * may share a cell). active NULL: every particle of the range. */
double qt_accelerations_masked(const qt_tree *t, double G, double theta, size_t first, size_t count,
                               const unsigned char *active, double *acc, double *pot);

/* Direct summation with the same softening rule, for particles first ..
 * first + count - 1 (the reference of tests and the bench). */
void qt_direct(const double *pos, const double *mass, const double *eps, size_t n, double G, size_t first,
               size_t count, double *acc, double *pot);

void qt_free(qt_tree *t);

#endif
