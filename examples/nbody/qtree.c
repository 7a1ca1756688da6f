#include "qtree.h"
#include "qtree_kernels.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#define MAX_DEPTH 48 /* beyond this a cell holds coincident particles: a leaf however many */
#define KEY_LEVELS 21 /* levels of octants a particle's key holds (3 bits each, 63 in all) */

/* Where a build puts the nodes, groups and super-groups it makes: the
 * tree's own arrays (tree_pool), or a part's (qt_part, below), numbered
 * from 0. */
typedef struct qt_pool {
    qt_node *nodes;
    size_t nnodes, cap, first_cap; /* first_cap: the room the first node takes (0: 1024) */
    int *groups;
    size_t ngroups, groups_cap;
    int *supers;
    size_t *super_first_group;
    size_t nsupers, supers_cap;
} qt_pool;

static qt_pool tree_pool(const qt_tree *t)
{
    return (qt_pool){.nodes = t->nodes,
                     .nnodes = t->nnodes,
                     .cap = t->cap,
                     .groups = t->groups,
                     .ngroups = t->ngroups,
                     .groups_cap = t->groups_cap,
                     .supers = t->supers,
                     .super_first_group = t->super_first_group,
                     .nsupers = t->nsupers,
                     .supers_cap = t->supers_cap};
}

static void set_tree_pool(qt_tree *t, const qt_pool *p)
{
    t->nodes = p->nodes;
    t->nnodes = p->nnodes;
    t->cap = p->cap;
    t->groups = p->groups;
    t->ngroups = p->ngroups;
    t->groups_cap = p->groups_cap;
    t->supers = p->supers;
    t->super_first_group = p->super_first_group;
    t->nsupers = p->nsupers;
    t->supers_cap = p->supers_cap;
}

/* Makes *array, of elements of size bytes, hold cap of them: 0, or -1
 * when out of memory (the array as it was). */
static int grow_array(void **array, size_t cap, size_t size)
{
    void *a = realloc(*array, cap * size);
    if (!a)
        return -1;
    *array = a;
    return 0;
}

/* Room in the pool for at least nodes nodes, groups groups and supers
 * super-groups (the super-groups' first groups with them, and the end
 * mark): each array grown if it held less; 0, or -1 when out of memory
 * (what it held kept). */
static int pool_room(qt_pool *p, size_t nodes, size_t groups, size_t supers)
{
    if (nodes > p->cap) {
        if (grow_array((void **)&p->nodes, nodes, sizeof *p->nodes) != 0)
            return -1;
        p->cap = nodes;
    }
    if (groups > p->groups_cap) {
        if (grow_array((void **)&p->groups, groups, sizeof *p->groups) != 0)
            return -1;
        p->groups_cap = groups;
    }
    if (supers > p->supers_cap) {
        if (grow_array((void **)&p->supers, supers, sizeof *p->supers) != 0 ||
            grow_array((void **)&p->super_first_group, supers, sizeof *p->super_first_group) != 0)
            return -1;
        p->supers_cap = supers;
    }
    return 0;
}

static int new_node(qt_pool *p)
{
    if (p->nnodes == p->cap && pool_room(p, p->cap ? 2 * p->cap : p->first_cap ? p->first_cap : 1024, 0, 0) != 0)
        return -1;
    qt_node *nd = &p->nodes[p->nnodes];
    memset(nd, 0, sizeof *nd);
    for (int k = 0; k < 8; k++)
        nd->child[k] = -1;
    return (int)p->nnodes++;
}

static int add_group(qt_pool *p, int node)
{
    if (p->ngroups == p->groups_cap && pool_room(p, 0, p->groups_cap ? 2 * p->groups_cap : 256, 0) != 0)
        return -1;
    p->groups[p->ngroups++] = node;
    return 0;
}

/* Records node as a super-group whose groups start at the next one added. */
static int add_super(qt_pool *p, int node)
{
    if (p->nsupers + 1 >= p->supers_cap && pool_room(p, 0, 0, p->supers_cap ? 2 * p->supers_cap : 64) != 0)
        return -1;
    p->supers[p->nsupers] = node;
    p->super_first_group[p->nsupers++] = p->ngroups;
    p->super_first_group[p->nsupers] = p->ngroups; /* until the next super or the end of the build */
    return 0;
}

/* The 21 low bits of v spread to every third bit (bit i to bit 3 i). */
static uint64_t spread_bits(uint64_t v)
{
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffULL;
    v = (v | v << 16) & 0x1f0000ff0000ffULL;
    v = (v | v << 8) & 0x100f00f00f00f00fULL;
    v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
    v = (v | v << 2) & 0x1249249249249249ULL;
    return v;
}

/* A point's key in the cube of side 1 / scale from corner lo: its octant
 * at each level, 3 bits a level from the top (bit 0 of each x, 1 y, 2 z,
 * as the build numbers octants), its coordinates cut to 2^21 steps. */
static uint64_t point_key(const double x[3], const double lo[3], double scale)
{
    uint64_t key = 0;
    for (int a = 0; a < 3; a++) {
        const double q = (x[a] - lo[a]) * scale, top = (double)((1 << KEY_LEVELS) - 1);
        const uint64_t step = !(q > 0) ? 0 : q >= top ? (uint64_t)top : (uint64_t)q; /* NaN: 0, not undefined */
        key |= spread_bits(step) << a;
    }
    return key;
}

/* A node's mass, centre of mass and mean softening^2 from the sums of m,
 * m x and m eps^2 over its particles (massless ones: its cube's centre). */
static void set_mass_centre(qt_node *nd, double m, const double c[3], double e2, const double centre[3])
{
    for (int k = 0; k < 3; k++)
        nd->com[k] = m > 0 ? c[k] / m : centre[k];
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

/* Which of another rank's cells (qt_build_with_moments) particle j of the
 * tree order is; t->ncells or more when it is a particle. */
static size_t cell_of(const qt_tree *t, size_t j)
{
    return t->order[j] - t->cells_first; /* wraps round for particles before the cells */
}

/* A leaf holding cells of another rank's tree: their own quadrupoles add
 * to its (the shift from each cell's centre to the leaf's is already in,
 * as for a particle; the nodes above take them from their children). */
static void add_cells_quads(const qt_tree *t, const qt_node *nd, double q[6])
{
    for (size_t j = nd->first; j < nd->first + nd->count; j++) {
        const size_t c = cell_of(t, j);
        for (int k = 0; c < t->ncells && k < 6; k++)
            q[k] += t->xquad[6 * c + k];
    }
}

/* b_max of a node holding such cells: reaching past each cell's centre by
 * the cell's own b_max. */
static double cells_reach(const qt_tree *t, const qt_node *nd, double b)
{
    for (size_t j = nd->first; j < nd->first + nd->count; j++) {
        const size_t c = cell_of(t, j);
        if (c >= t->ncells)
            continue;
        double y[3] = {t->px[j] - nd->com[0], t->py[j] - nd->com[1], t->pz[j] - nd->com[2]};
        b = fmax(b, sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]) + t->xbmax[c]);
    }
    return b;
}

/* The largest squared distance from point c to one of particles first ..
 * first + count - 1 (tree order). */
static double farthest2(const qt_tree *t, const double c[3], size_t first, size_t count)
{
    double b2 = 0;
    for (size_t j = first; j < first + count; j++) {
        const double y[3] = {t->px[j] - c[0], t->py[j] - c[1], t->pz[j] - c[2]};
        const double r2 = y[0] * y[0] + y[1] * y[1] + y[2] * y[2];
        b2 = r2 > b2 ? r2 : b2; /* not fmax: a call into libm for every particle */
    }
    return b2;
}

/* Mass, centre of mass, traceless quadrupole and mean softening^2 of a
 * leaf, from its particles (pe2 already squared). Its com holds its cube's
 * centre until then, for a leaf without mass. */
static void leaf_moments(const qt_tree *t, qt_node *nd)
{
    double m = 0, c[3] = {0, 0, 0}, e2 = 0;
    for (size_t j = nd->first; j < nd->first + nd->count; j++) {
        m += t->pm[j];
        c[0] += t->pm[j] * t->px[j];
        c[1] += t->pm[j] * t->py[j];
        c[2] += t->pm[j] * t->pz[j];
        e2 += t->pm[j] * t->pe2[j];
    }
    const double centre[3] = {nd->com[0], nd->com[1], nd->com[2]};
    set_mass_centre(nd, m, c, e2, centre);
    double q[6] = {0};
    for (size_t j = nd->first; j < nd->first + nd->count; j++) {
        double y[3] = {t->px[j] - nd->com[0], t->py[j] - nd->com[1], t->pz[j] - nd->com[2]};
        add_quad(q, t->pm[j], y);
    }
    if (t->ncells)
        add_cells_quads(t, nd, q);
    memcpy(nd->quad, q, sizeof q);
}

/* The same for a node above leaves, from its children's moments (their
 * quadrupoles moved to its centre of mass: each particle's moments are
 * summed once, in its leaf, not once a level). Its children's moments
 * must be made. */
static void moments_from_children(const qt_tree *t, qt_node *nd)
{
    double m = 0, c[3] = {0, 0, 0}, e2 = 0;
    for (int k = 0; k < 8; k++) {
        if (nd->child[k] < 0)
            continue;
        const qt_node *ch = &t->nodes[nd->child[k]];
        m += ch->mass;
        for (int a = 0; a < 3; a++)
            c[a] += ch->mass * ch->com[a];
        e2 += ch->mass * ch->eps2;
    }
    const double centre[3] = {nd->com[0], nd->com[1], nd->com[2]};
    set_mass_centre(nd, m, c, e2, centre);
    double q[6] = {0};
    for (int k = 0; k < 8; k++) {
        if (nd->child[k] < 0)
            continue;
        const qt_node *ch = &t->nodes[nd->child[k]];
        const double y[3] = {ch->com[0] - nd->com[0], ch->com[1] - nd->com[1], ch->com[2] - nd->com[2]};
        for (int i = 0; i < 6; i++)
            q[i] += ch->quad[i];
        add_quad(q, ch->mass, y);
    }
    memcpy(nd->quad, q, sizeof q);
}

/* A node's b_max once its centre of mass is known: from its particles, the
 * exact value the opening criterion needs (a bound from its children's
 * would open more cells). */
static void finish_bmax(const qt_tree *t, qt_node *nd)
{
    nd->bmax = sqrt(farthest2(t, nd->com, nd->first, nd->count));
    if (t->ncells)
        nd->bmax = cells_reach(t, nd, nd->bmax);
}

/* Splits a cell's particles (first .. first + count - 1, at depth depth)
 * into its octants: a stable counting sort of their keys and order by the
 * keys' 3 bits of that level (16 bytes a particle moved, where sorting the
 * positions, masses and softenings with them moved 48). Below the keys'
 * last level (particles closer than 2^-21 of the root's cube) the cell is
 * cut into 8 runs of particles in their order: cells that overlap, but
 * each with its exact moments and b_max, so coincident particles still
 * come in groups. */
static void split_cell(qt_tree *t, size_t first, size_t count, int depth, size_t counts[8], size_t starts[8])
{
    const int below_keys = depth >= KEY_LEVELS, shift = below_keys ? 0 : 3 * (KEY_LEVELS - 1 - depth);
    for (int k = 0; below_keys && k < 8; k++)
        counts[k] = count / 8 + ((size_t)k < count % 8);
    for (size_t j = first; !below_keys && j < first + count; j++)
        counts[t->key[j] >> shift & 7]++;
    starts[0] = first;
    for (int k = 1; k < 8; k++)
        starts[k] = starts[k - 1] + counts[k - 1];
    if (below_keys)
        return;
    size_t fill[8];
    memcpy(fill, starts, sizeof fill);
    for (size_t j = first; j < first + count; j++) {
        const size_t to = fill[t->key[j] >> shift & 7]++;
        t->key_tmp[to] = t->key[j];
        t->scratch[to] = t->order[j];
    }
    memcpy(&t->key[first], &t->key_tmp[first], count * sizeof *t->key);
    memcpy(&t->order[first], &t->scratch[first], count * sizeof *t->order);
}

/* The centre of octant k of the cell (centre, half) at depth depth (below
 * the keys' last level, split_cell's runs: the cell's own). */
static void child_centre(const double centre[3], double half, int depth, int k, double cc[3])
{
    for (int a = 0; a < 3; a++)
        cc[a] = depth >= KEY_LEVELS ? centre[a] : centre[a] + ((k >> a) & 1 ? 0.5 : -0.5) * half;
}

/* A new node of pool p for the cell about centre over the particles
 * first .. first + count - 1 of the tree order, its com the cube's centre
 * until its moments are made (tree_moments); its index in p, or -1 when
 * out of memory. */
static int cell_node(qt_pool *p, size_t first, size_t count, const double centre[3])
{
    int id = new_node(p);
    if (id < 0)
        return -1;
    qt_node *nd = &p->nodes[id];
    nd->first = first;
    nd->count = count;
    memcpy(nd->com, centre, sizeof nd->com);
    return id;
}

/* Builds the subtree of the cell (centre, half) over the particles first ..
 * first + count - 1 of the tree-order arrays, its nodes, groups and
 * super-groups into pool p, depth first; the node's index in p, or -1 when
 * out of memory. */
static int build_node(qt_tree *t, qt_pool *p, size_t first, size_t count, const double centre[3], double half,
                      int depth, int in_group, int in_super)
{
    int id = cell_node(p, first, count, centre);
    if (id < 0)
        return -1;
    if (!in_super && count <= QT_SUPER) {
        if (add_super(p, id) != 0)
            return -1;
        in_super = 1;
    }
    if (!in_group && count <= QT_GROUP) {
        if (add_group(p, id) != 0)
            return -1;
        in_group = 1;
    }
    if (count <= QT_LEAF || depth >= MAX_DEPTH)
        return id; /* a leaf */
    size_t counts[8] = {0}, starts[8];
    split_cell(t, first, count, depth, counts, starts);
    for (int k = 0; k < 8; k++) {
        if (!counts[k])
            continue;
        double cc[3];
        child_centre(centre, half, depth, k, cc);
        int child = build_node(t, p, starts[k], counts[k], cc, 0.5 * half, depth + 1, in_group, in_super);
        if (child < 0)
            return -1;
        p->nodes[id].child[k] = child; /* the pool may have moved */
    }
    return id;
}

/* ---- the build on every thread ------------------------------------------ */

/* A piece of the tree built by one thread: a cell of more than
 * QT_PART_MIN particles split on its own (one node in its pool, its
 * octants' parts in child), or a subtree built whole by build_node. The
 * pieces are spliced in depth-first order after (splice_parts), so the
 * tree is the one a build on one thread makes, node for node and bit for
 * bit: every node's moments come from its own particles in their order,
 * and each cell's particles are sorted by the same counting sort, whoever
 * runs it. Why: the build was serial, about a sixth of a step's wall time
 * on two threads at 5 x 10^5 particles (docs/nbody.md), and more of it the
 * more threads share the walk. */
typedef struct qt_part {
    qt_pool pool;
    struct qt_part *child[8];
    size_t node0, group0, super0; /* where its nodes, groups and super-groups go in the tree */
} qt_part;

#ifndef QT_PART_MIN
#define QT_PART_MIN 8192 /* cells of more particles than this are split as parts of their own */
#endif
_Static_assert(QT_PART_MIN >= QT_SUPER && QT_SUPER >= QT_GROUP && QT_GROUP >= QT_LEAF,
               "a split cell is no group, super-group or leaf");

static void set_failed(int *failed)
{
#pragma omp atomic write
    *failed = 1;
}

/* Builds part over the cell's particles, its octants as tasks of their own
 * (OpenMP tasks, run by the threads of the enclosing parallel region). A
 * cell of more particles than QT_PART_MIN is split as build_node would
 * split it (no group or super-group holds it: QT_PART_MIN >= QT_SUPER). */
static void build_part(qt_tree *t, qt_part *part, size_t first, size_t count, const double centre[3], double half,
                       int depth, int *failed)
{
    if (count <= QT_PART_MIN || depth >= MAX_DEPTH) {
        part->pool.first_cap = depth >= MAX_DEPTH ? 1 : count / 4 + 16; /* about 0.24 nodes a particle at 5 x 10^5 */
        if (build_node(t, &part->pool, first, count, centre, half, depth, 0, 0) < 0)
            set_failed(failed);
        return;
    }
    part->pool.first_cap = 1;
    if (cell_node(&part->pool, first, count, centre) < 0) {
        set_failed(failed);
        return;
    }
    size_t counts[8] = {0}, starts[8];
    split_cell(t, first, count, depth, counts, starts);
    for (int k = 0; k < 8; k++) {
        if (!counts[k])
            continue;
        qt_part *c = calloc(1, sizeof *c);
        if (!c) {
            set_failed(failed);
            return;
        }
        part->child[k] = c;
        double cc[3];
        child_centre(centre, half, depth, k, cc);
        const size_t at = starts[k], n = counts[k];
#pragma omp task firstprivate(c, cc, at, n)
        build_part(t, c, at, n, cc, 0.5 * half, depth + 1, failed);
    }
}

/* Gives each part the place of its nodes, groups and super-groups in the
 * tree: depth first, a part's own before its octants' in octant order, as
 * build_node would make them; into list, the parts in that order. */
static void place_parts(qt_part *p, size_t *nodes, size_t *groups, size_t *supers, qt_part **list, size_t *nparts)
{
    p->node0 = *nodes;
    p->group0 = *groups;
    p->super0 = *supers;
    *nodes += p->pool.nnodes;
    *groups += p->pool.ngroups;
    *supers += p->pool.nsupers;
    if (list)
        list[*nparts] = p;
    ++*nparts;
    for (int k = 0; k < 8; k++)
        if (p->child[k])
            place_parts(p->child[k], nodes, groups, supers, list, nparts);
}

/* Copies part p into its place in the tree, its node numbers shifted. */
static void copy_part(qt_tree *t, const qt_part *p)
{
    const qt_pool *q = &p->pool;
    for (size_t i = 0; i < q->nnodes; i++) {
        qt_node nd = q->nodes[i];
        for (int k = 0; k < 8; k++)
            if (nd.child[k] >= 0)
                nd.child[k] += (int)p->node0;
        t->nodes[p->node0 + i] = nd;
    }
    for (int k = 0; k < 8; k++) /* a split cell's octants: their parts' first nodes */
        if (p->child[k])
            t->nodes[p->node0].child[k] = (int)p->child[k]->node0;
    for (size_t g = 0; g < q->ngroups; g++)
        t->groups[p->group0 + g] = q->groups[g] + (int)p->node0;
    for (size_t s = 0; s < q->nsupers; s++) {
        t->supers[p->super0 + s] = q->supers[s] + (int)p->node0;
        t->super_first_group[p->super0 + s] = q->super_first_group[s] + p->group0;
    }
}

static void free_parts(qt_part *p)
{
    for (int k = 0; k < 8; k++)
        if (p->child[k])
            free_parts(p->child[k]);
    free(p->pool.nodes);
    free(p->pool.groups);
    free(p->pool.supers);
    free(p->pool.super_first_group);
    free(p);
}

/* Room in the tree's arrays for nodes nodes, groups groups and supers
 * super-groups (and the end mark after them); 0, or -1 when out of memory. */
static int room_in_tree(qt_tree *t, size_t nodes, size_t groups, size_t supers)
{
    qt_pool p = tree_pool(t);
    int st = pool_room(&p, nodes, groups, supers + 1);
    set_tree_pool(t, &p);
    return st;
}

/* The parts, built, spliced into the tree's arrays (each part copied on
 * some thread: their places are known). */
static int splice_parts(qt_tree *t, qt_part *root)
{
    size_t nodes = 0, groups = 0, supers = 0, nparts = 0;
    place_parts(root, &nodes, &groups, &supers, NULL, &nparts);
    qt_part **list = malloc(nparts * sizeof *list);
    if (!list || room_in_tree(t, nodes, groups, supers) != 0) {
        free(list);
        return -1;
    }
    nodes = groups = supers = nparts = 0;
    place_parts(root, &nodes, &groups, &supers, list, &nparts);
#pragma omp parallel for schedule(dynamic, 1)
    for (long k = 0; k < (long)nparts; k++)
        copy_part(t, list[k]);
    free(list);
    t->nnodes = nodes;
    t->ngroups = groups;
    t->nsupers = supers;
    return 0;
}

static int threads_available(void)
{
#ifdef _OPENMP
    return omp_get_max_threads();
#else
    return 1;
#endif
}

/* The tree's nodes over its n particles, in the cell (centre, half): on
 * every thread in parts when there are several threads and particles
 * enough, else by build_node alone; the same tree either way. */
static int build_nodes(qt_tree *t, size_t n, const double centre[3], double half)
{
    if (n <= QT_PART_MIN || threads_available() == 1) {
        qt_pool p = tree_pool(t);
        int root = build_node(t, &p, 0, n, centre, half, 0, 0, 0);
        set_tree_pool(t, &p);
        return root < 0 ? -1 : 0;
    }
    qt_part *root = calloc(1, sizeof *root);
    if (!root)
        return -1;
    int failed = 0;
#pragma omp parallel
#pragma omp single
    build_part(t, root, 0, n, centre, half, 0, &failed);
    int st = failed ? -1 : splice_parts(t, root);
    free_parts(root);
    return st;
}

static void free_build_scratch(qt_tree *t)
{
    free(t->scratch);
    free(t->key);
    free(t->key_tmp);
    t->scratch = NULL;
    t->key = t->key_tmp = NULL;
}

static int resize(qt_tree *t, size_t n)
{
    free(t->order);
    free(t->px);
    free_build_scratch(t);
    t->order = malloc(n * sizeof *t->order);
    t->scratch = malloc(n * sizeof *t->scratch);
    t->key = malloc(n * sizeof *t->key);
    t->key_tmp = malloc(n * sizeof *t->key_tmp);
    t->px = malloc(5 * n * sizeof *t->px);
    t->n = n;
    if (!t->order || !t->scratch || !t->key || !t->key_tmp || !t->px)
        return -1;
    t->py = t->px + n;
    t->pz = t->py + n;
    t->pm = t->pz + n;
    t->pe2 = t->pm + n;
    return 0;
}

/* The walk's compact copy of the nodes (make_lists): nodes are made in
 * depth-first order (build_node), so a node's subtree is the nodes from it
 * to its `next`; a leaf's next is the node after it. What the walk reads,
 * in 72 bytes a node instead of the node's 144, read forwards: a group
 * visits ~600 nodes and takes ~500 of them whole (the Milky Way model), so
 * the cells' moments are kept ready in float. First the subtrees' ends
 * (tree_moments uses them), then the copy, once the moments are made. */
static int subtree_ends(qt_tree *t)
{
    if (t->walk_cap < t->nnodes) {
        free(t->walk);
        t->walk = malloc(t->cap * sizeof *t->walk);
        t->walk_cap = t->walk ? t->cap : 0;
        if (!t->walk)
            return -1;
    }
    for (size_t id = t->nnodes; id-- > 0;) {
        const qt_node *nd = &t->nodes[id];
        size_t next = id + 1;
        for (int k = 0; k < 8; k++) /* the last child's subtree ends the node's */
            if (nd->child[k] >= 0)
                next = t->walk[nd->child[k]].next;
        t->walk[id].next = next;
    }
    return 0;
}

static void copy_to_walk(qt_tree *t)
{
#pragma omp parallel for schedule(static)
    for (size_t id = 0; id < t->nnodes; id++) {
        const qt_node *nd = &t->nodes[id];
        qt_walk_node *w = &t->walk[id];
        memcpy(w->com, nd->com, sizeof w->com);
        w->bmax = nd->bmax;
        w->moments[0] = (float)nd->mass;
        for (int q = 0; q < 6; q++)
            w->moments[1 + q] = (float)nd->quad[q];
        w->moments[7] = (float)nd->eps2;
    }
}

/* The moments of every node of the subtree of node id (its nodes id ..
 * next - 1, each parent before its children): from the last back. */
static void subtree_moments(qt_tree *t, size_t id)
{
    for (size_t k = t->walk[id].next; k-- > id;) {
        qt_node *nd = &t->nodes[k];
        if (qt_is_leaf(nd))
            leaf_moments(t, nd);
        else
            moments_from_children(t, nd);
        finish_bmax(t, nd);
    }
}

/* The moments of node id's subtree, its octants' subtrees as tasks of
 * their own while they hold more than QT_PART_MIN particles: each node's
 * from its own children and particles, so the same on any thread count. */
static void moments_task(qt_tree *t, size_t id)
{
    qt_node *nd = &t->nodes[id];
    if (nd->count <= QT_PART_MIN || qt_is_leaf(nd)) {
        subtree_moments(t, id);
        return;
    }
    for (int k = 0; k < 8; k++) {
        const int child = nd->child[k];
        if (child >= 0) {
#pragma omp task firstprivate(child)
            moments_task(t, (size_t)child);
        }
    }
#pragma omp taskwait
    moments_from_children(t, nd);
    finish_bmax(t, nd);
}

static void tree_moments(qt_tree *t)
{
    if (!t->nnodes)
        return;
#pragma omp parallel
#pragma omp single
    moments_task(t, 0);
}

/* The cube about all n particles: its centre and half its side, a little
 * more than the particles' extent (every key's coordinates below 2^21). */
static void root_cube(const double *pos, size_t n, double centre[3], double *half)
{
    double lo0 = INFINITY, lo1 = INFINITY, lo2 = INFINITY, hi0 = -INFINITY, hi1 = -INFINITY, hi2 = -INFINITY;
    /* The positions are finite (nbody.c checks): comparisons, not fmin and
     * fmax's NaN rules in calls into libm. Least and largest are exact, so
     * the same on any thread count. */
#pragma omp parallel for schedule(static) reduction(min : lo0, lo1, lo2) reduction(max : hi0, hi1, hi2)
    for (size_t i = 0; i < n; i++) {
        const double *x = &pos[3 * i];
        lo0 = x[0] < lo0 ? x[0] : lo0;
        lo1 = x[1] < lo1 ? x[1] : lo1;
        lo2 = x[2] < lo2 ? x[2] : lo2;
        hi0 = x[0] > hi0 ? x[0] : hi0;
        hi1 = x[1] > hi1 ? x[1] : hi1;
        hi2 = x[2] > hi2 ? x[2] : hi2;
    }
    const double lo[3] = {lo0, lo1, lo2}, hi[3] = {hi0, hi1, hi2};
    *half = 0;
    for (int k = 0; k < 3; k++) {
        centre[k] = n ? 0.5 * (lo[k] + hi[k]) : 0.0;
        *half = fmax(*half, n ? 0.5 * (hi[k] - lo[k]) : 0.0);
    }
    *half = *half * 1.0001 + 1e-12;
}

int qt_build(qt_tree *t, const double *pos, const double *mass, const double *eps, size_t n)
{
    return qt_build_with_moments(t, pos, mass, eps, NULL, NULL, 0, 0, n);
}

void qt_drop_build_scratch(qt_tree *t)
{
    free_build_scratch(t);
    /* The node pools' room to grow (up to as much again as they hold) given
     * back: the walk reads only the nodes built, and with --decompose this
     * is a rank's largest block of memory (bench/bench_decompose.sh). */
    qt_node *nodes = t->nnodes ? realloc(t->nodes, t->nnodes * sizeof *nodes) : NULL;
    qt_walk_node *walk = t->nnodes ? realloc(t->walk, t->nnodes * sizeof *walk) : NULL;
    if (nodes) {
        t->nodes = nodes;
        t->cap = t->nnodes;
    }
    if (walk) {
        t->walk = walk;
        t->walk_cap = t->nnodes;
    }
}

int qt_build_with_moments(qt_tree *t, const double *pos, const double *mass, const double *eps, const double *quad,
                          const double *bmax, size_t cells_first, size_t ncells, size_t n)
{
    t->xquad = quad;
    t->xbmax = bmax;
    t->cells_first = cells_first;
    t->ncells = quad && bmax ? ncells : 0;
    t->nnodes = 0;
    t->ngroups = 0;
    t->nsupers = 0;
    if ((n != t->n || !t->order || !t->scratch || !t->key) && resize(t, n) != 0)
        return -1;
    double centre[3], half;
    root_cube(pos, n, centre, &half);
    const double corner[3] = {centre[0] - half, centre[1] - half, centre[2] - half};
    const double scale = (double)(1 << KEY_LEVELS) / (2 * half);
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < n; i++) {
        t->order[i] = i;
        t->key[i] = point_key(&pos[3 * i], corner, scale);
    }
    if (build_nodes(t, n, centre, half) != 0)
        return -1;
    if (t->nsupers)
        t->super_first_group[t->nsupers] = t->ngroups;
    /* The walk reads particles in tree order, contiguously. */
#pragma omp parallel for schedule(static)
    for (size_t j = 0; j < n; j++) {
        const size_t i = t->order[j];
        t->px[j] = pos[3 * i];
        t->py[j] = pos[3 * i + 1];
        t->pz[j] = pos[3 * i + 2];
        t->pm[j] = mass[i];
        t->pe2[j] = eps[i] * eps[i];
    }
    if (subtree_ends(t) != 0)
        return -1;
    tree_moments(t);
    copy_to_walk(t);
    return 0;
}

/* ---- walk --------------------------------------------------------------- */

/* Grows a list's structure-of-arrays block to hold `need` entries of each
 * field, keeping the first `used`. */
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

/* A cell taken whole: its offset from the group, then its moments in float
 * as index_walk stored them. */
static int push_cell(qt_lists *l, const qt_walk_node *w, const double g[3])
{
    if (grow(&l->c, &l->cap_cell, l->ncell, l->ncell + 1, QT_CELL_FIELDS) != 0)
        return -1;
    size_t k = l->ncell++, cap = l->cap_cell;
    float *c = l->c + k;
    c[QT_CX * cap] = (float)(w->com[0] - g[0]);
    c[QT_CY * cap] = (float)(w->com[1] - g[1]);
    c[QT_CZ * cap] = (float)(w->com[2] - g[2]);
    for (int f = 0; f < 8; f++)
        c[(QT_CM + f) * cap] = w->moments[f];
    return 0;
}

/* Particle j (tree order) of a tree with cells among its particles
 * (qt_build_with_moments), when it is one, as a cell to push. */
static int cell_particle(const qt_tree *t, size_t j, qt_walk_node *w)
{
    const size_t c = cell_of(t, j);
    if (c >= t->ncells)
        return 0;
    w->com[0] = t->px[j];
    w->com[1] = t->py[j];
    w->com[2] = t->pz[j];
    w->bmax = t->xbmax[c];
    w->moments[0] = (float)t->pm[j];
    for (int q = 0; q < 6; q++)
        w->moments[1 + q] = (float)t->xquad[6 * c + q];
    w->moments[7] = (float)t->pe2[j];
    return 1;
}

static int push_leaf(qt_lists *l, const qt_tree *t, const qt_node *nd, const double g[3])
{
    if (grow(&l->p, &l->cap_part, l->npart, l->npart + nd->count, QT_PART_FIELDS) != 0)
        return -1;
    size_t cap = l->cap_part;
    for (size_t j = nd->first; j < nd->first + nd->count; j++) {
        qt_walk_node cell;
        if (cell_particle(t, j, &cell)) { /* another rank's cell: its quadrupole too */
            if (push_cell(l, &cell, g) != 0)
                return -1;
            cap = l->cap_part;
            continue;
        }
        float *p = l->p + l->npart++;
        p[QT_PX * cap] = (float)(t->px[j] - g[0]);
        p[QT_PY * cap] = (float)(t->py[j] - g[1]);
        p[QT_PZ * cap] = (float)(t->pz[j] - g[2]);
        p[QT_PM * cap] = (float)t->pm[j];
        p[QT_PE2 * cap] = (float)t->pe2[j];
    }
    return 0;
}

/* Zero-mass entries from `from` to `to` in each of a block's fields
 * (softening^2 1 in field e2, so they stay finite): they add exactly
 * nothing. */
static void pad_block(float *block, size_t cap, int fields, int e2, size_t from, size_t to)
{
    for (int f = 0; f < fields; f++)
        for (size_t k = from; k < to; k++)
            block[f * cap + k] = f == e2 ? 1.0f : 0.0f;
}

/* The lists padded to the kernels' multiple of QT_LIST_LANES. */
static int pad_lists(qt_lists *l)
{
    size_t nc = qt_padded(l->ncell), np = qt_padded(l->npart);
    if (grow(&l->c, &l->cap_cell, l->ncell, nc, QT_CELL_FIELDS) != 0 ||
        grow(&l->p, &l->cap_part, l->npart, np, QT_PART_FIELDS) != 0)
        return -1;
    pad_block(l->c, l->cap_cell, QT_CELL_FIELDS, QT_CE2, l->ncell, nc);
    pad_block(l->p, l->cap_part, QT_PART_FIELDS, QT_PE2, l->npart, np);
    return 0;
}

/* Whether a cell w is far enough from the sphere (centre c, radius r) to be
 * taken whole: |com - c| - r > b_max / theta, tested squared (no square
 * root). Every point of the sphere is then at least b_max / theta from the
 * cell's centre of mass. */
static int far_enough(const qt_walk_node *w, const double c[3], double r, double inv_theta)
{
    double d[3] = {w->com[0] - c[0], w->com[1] - c[1], w->com[2] - c[2]};
    double reach = r + w->bmax * inv_theta;
    return d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > reach * reach;
}

/* The interaction lists of group g walked from the root: every cell
 * passing the b_max criterion for the group's bounding sphere (its centre
 * of mass, radius b_max) is taken whole; leaves that do not are taken
 * particle by particle. theta <= 1 guarantees a cell holding the group is
 * always opened (see qtree.h). The walk runs through the compact
 * depth-first copy (index_walk): forward through memory, a cell taken whole
 * skipping its subtree. */
static int make_lists(const qt_tree *t, const qt_node *g, double theta, qt_lists *l)
{
    l->ncell = l->npart = 0;
    const double inv_theta = 1.0 / theta;
    for (size_t id = 0; id < t->nnodes;) {
        const qt_walk_node *w = &t->walk[id];
        if (far_enough(w, g->com, g->bmax, inv_theta)) {
            if (push_cell(l, w, g->com) != 0)
                return -1;
            id = w->next;
            continue;
        }
        if (w->next == id + 1 && push_leaf(l, t, &t->nodes[id], g->com) != 0) /* a leaf */
            return -1;
        id++; /* into the children, or past a leaf */
    }
    return pad_lists(l);
}

/* The groups of a super-group walking the tree together (multi_walk): the
 * k-th is the tree's group number group[k], its lists own[k]; bit k of a
 * mask stands for it. */
#define QT_WALKERS 64

typedef struct qt_walkers {
    int n;
    size_t group[QT_WALKERS];
    qt_lists own[QT_WALKERS], shared, far; /* far: shared cells beyond far_r (multi_walk), for the field */
    qt_field field;
} qt_walkers;

/* The groups whose bits are set in mask that find cell w far enough. */
static uint64_t far_for(const qt_tree *t, const qt_walkers *wk, uint64_t mask, const qt_walk_node *w,
                        double inv_theta)
{
    uint64_t far = 0;
    for (uint64_t m = mask; m; m &= m - 1) {
        int k = __builtin_ctzll(m);
        const qt_node *g = &t->nodes[t->groups[wk->group[k]]];
        if (far_enough(w, g->com, g->bmax, inv_theta))
            far |= (uint64_t)1 << k;
    }
    return far;
}

/* Every walking group of a super-group s gets the lists its own walk from
 * the root would give (make_lists), in one walk for all: a node is tested
 * for the groups that opened all its ancestors, so each group tests the
 * nodes it would test alone. A cell all of them take whole goes once to
 * the shared list, relative to the super-group's centre of mass; a cell
 * only some take goes to theirs, and the others walk on into it. The tree's
 * top levels and far cells, which all of a super-group's ~8 groups visit
 * alike, are so walked once, and each of them converted to float once.
 * Only the groups whose bits are set in need get lists: the others are
 * tested only while no group has taken a node whole (below such a node no
 * cell can be shared), so a block step's sub-step pays little for a
 * super-group's groups without active particles, and the needed groups'
 * lists are those a walk of all would give them. */
static int multi_walk(const qt_tree *t, const qt_node *s, double theta, double far_r, uint64_t need,
                      qt_walkers *wk)
{
    const double inv_theta = 1.0 / theta;
    const uint64_t all = wk->n == 64 ? ~(uint64_t)0 : ((uint64_t)1 << wk->n) - 1;
    struct {
        size_t end;
        uint64_t mask;
    } stack[MAX_DEPTH + 2];
    int top = 0;
    uint64_t mask = all;
    wk->shared.ncell = wk->shared.npart = wk->far.ncell = wk->far.npart = 0;
    for (int k = 0; k < wk->n; k++)
        wk->own[k].ncell = wk->own[k].npart = 0;
    for (size_t id = 0; id < t->nnodes;) {
        while (top > 0 && id >= stack[top - 1].end) /* out of the subtree where some groups stopped */
            mask = stack[--top].mask;
        const qt_walk_node *w = &t->walk[id];
        uint64_t far = far_for(t, wk, mask, w, inv_theta), near = mask & ~far;
        if (far == all) {
            /* Far: all its particles beyond far_r (their pull smooth over the super-group). */
            double d[3] = {w->com[0] - s->com[0], w->com[1] - s->com[1], w->com[2] - s->com[2]};
            double reach = far_r + w->bmax;
            int beyond = far_r > 0 && d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > reach * reach;
            if (push_cell(beyond ? &wk->far : &wk->shared, w, s->com) != 0)
                return -1;
            id = w->next;
            continue;
        }
        for (uint64_t m = far & need; m; m &= m - 1) {
            int k = __builtin_ctzll(m);
            if (push_cell(&wk->own[k], w, t->nodes[t->groups[wk->group[k]]].com) != 0)
                return -1;
        }
        /* Below a node some group took whole no cell can be shared, so
         * there only the needed groups walk on. */
        const uint64_t inside = near == all ? all : near & need;
        if (!inside) {
            id = w->next;
            continue;
        }
        if (w->next == id + 1) { /* a leaf: its particles, for those it is not far enough from */
            for (uint64_t m = near & need; m; m &= m - 1) {
                int k = __builtin_ctzll(m);
                if (push_leaf(&wk->own[k], t, &t->nodes[id], t->nodes[t->groups[wk->group[k]]].com) != 0)
                    return -1;
            }
        } else if (inside != mask) { /* into its children for the groups that opened it */
            stack[top].end = w->next;
            stack[top++].mask = mask;
            mask = inside;
        }
        id++;
    }
    if (pad_lists(&wk->shared) != 0 || pad_lists(&wk->far) != 0)
        return -1;
    for (uint64_t m = need; m; m &= m - 1)
        if (pad_lists(&wk->own[__builtin_ctzll(m)]) != 0)
            return -1;
    return 0;
}

/* Whether the caller asked for particle i (of the whole set). */
static int wanted(size_t i, size_t first, size_t count, const unsigned char *active)
{
    return i >= first && i < first + count && (!active || active[i - first]);
}

/* The group's particles that the caller asked for, gathered for the
 * kernels (qtree_kernels.h) as offsets from centre c; their tree-order
 * indices into js. */
static void gather_targets(const qt_tree *t, const qt_node *g, const double c[3], size_t first, size_t count,
                           const unsigned char *active, qt_targets *tg, size_t *js)
{
    tg->n = 0;
    for (size_t j = g->first; j < g->first + g->count; j++) {
        if (!wanted(t->order[j], first, count, active))
            continue;
        js[tg->n] = j;
        tg->x[tg->n] = (float)(t->px[j] - c[0]);
        tg->y[tg->n] = (float)(t->py[j] - c[1]);
        tg->z[tg->n] = (float)(t->pz[j] - c[2]);
        tg->e2[tg->n] = (float)t->pe2[j];
        tg->n++;
    }
}

/* Whether node nd holds a particle the caller asked for. */
static int any_wanted(const qt_tree *t, const qt_node *nd, size_t first, size_t count, const unsigned char *active)
{
    for (size_t j = nd->first; j < nd->first + nd->count; j++)
        if (wanted(t->order[j], first, count, active))
            return 1;
    return 0;
}

/* The gathered particles of a group (gather_targets) against its lists l
 * and, inside a super-group, the super-group's shared cells and the field
 * of its far cells, if any (ts: the same particles as offsets from the
 * super-group's centre of mass; shared NULL: none). */
static void apply_lists(const qt_tree *t, const qt_lists *shared, const qt_field *field, const qt_targets *ts,
                        const qt_lists *l, double G, size_t first, const qt_targets *tg, const size_t *js,
                        double *acc, double *pot)
{
    qt_sums cs, ps, ss;
    qt_cells_on(l, tg, &cs);
    qt_parts_on(l, tg, &ps);
    if (shared)
        qt_cells_on(shared, ts, &ss);
    if (shared && field)
        qt_field_on(field, ts, &ss);
    for (size_t n = 0; n < tg->n; n++) {
        size_t j = js[n], o = t->order[j] - first;
        double a[3] = {(double)cs.ax[n] + ps.ax[n], (double)cs.ay[n] + ps.ay[n], (double)cs.az[n] + ps.az[n]};
        double phi = (double)cs.phi[n] + ps.phi[n];
        if (shared) {
            a[0] += ss.ax[n];
            a[1] += ss.ay[n];
            a[2] += ss.az[n];
            phi += ss.phi[n];
        }
        if (tg->e2[n] > 0)
            phi += t->pm[j] / sqrt((double)tg->e2[n]); /* its own term */
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

/* A thread's working lists. */
typedef struct qt_work {
    qt_lists own;
    qt_walkers *walkers;
} qt_work;

static void free_lists(qt_lists *l)
{
    free(l->c);
    free(l->p);
}

static void free_work(qt_work *w)
{
    free_lists(&w->own);
    if (w->walkers) {
        for (int k = 0; k < QT_WALKERS; k++)
            free_lists(&w->walkers->own[k]);
        free_lists(&w->walkers->shared);
        free_lists(&w->walkers->far);
        free(w->walkers);
    }
}

/* The forces of the requested particles of group k, walked from the root;
 * its interactions, or -1 when out of memory. */
static double group_from_root(const qt_tree *t, size_t k, double G, double theta, size_t first, size_t count,
                              const unsigned char *active, qt_work *w, double *acc, double *pot)
{
    const qt_node *g = &t->nodes[t->groups[k]];
    qt_targets tg;
    size_t js[QT_GROUP];
    gather_targets(t, g, g->com, first, count, active, &tg, js);
    if (!tg.n) /* a group with none of the requested particles costs nothing */
        return 0;
    if (make_lists(t, g, theta, &w->own) != 0)
        return -1;
    apply_lists(t, NULL, NULL, NULL, &w->own, G, first, &tg, js, acc, pot);
    return (double)tg.n * (double)(w->own.ncell + w->own.npart);
}

_Static_assert(QT_GROUP >= 27, "a super-group's field grid is 27 targets");

/* The field of a super-group's far cells (qt_field): their pull at the 27
 * points of its grid, with the least and the largest softening^2 of its
 * particles (the same whatever particles are asked for); the interactions
 * that took. */
static double far_field(const qt_tree *t, const qt_node *sn, const qt_lists *far, qt_field *f)
{
    double e2lo = INFINITY, e2hi = -INFINITY;
    for (size_t j = sn->first; j < sn->first + sn->count; j++) {
        const double e2 = t->pe2[j]; /* finite: comparisons, not fmin and fmax's calls into libm */
        e2lo = e2 < e2lo ? e2 : e2lo;
        e2hi = e2 > e2hi ? e2 : e2hi;
    }
    f->h = (float)sn->bmax;
    f->e2lo = (float)e2lo;
    f->inv_de2 = (float)e2hi > (float)e2lo ? 1.0f / ((float)e2hi - (float)e2lo) : 0.0f;
    qt_targets grid;
    grid.n = 27;
    for (int k = 0; k < 27; k++) {
        grid.x[k] = (float)(k % 3 - 1) * f->h;
        grid.y[k] = (float)(k / 3 % 3 - 1) * f->h;
        grid.z[k] = (float)(k / 9 - 1) * f->h;
    }
    qt_sums lo, hi;
    for (int k = 0; k < 27; k++)
        grid.e2[k] = (float)e2lo;
    qt_cells_on(far, &grid, &lo);
    hi = lo;
    if (f->inv_de2 > 0) {
        for (int k = 0; k < 27; k++)
            grid.e2[k] = (float)e2hi;
        qt_cells_on(far, &grid, &hi);
    }
    const float *l[4] = {lo.ax, lo.ay, lo.az, lo.phi}, *h[4] = {hi.ax, hi.ay, hi.az, hi.phi};
    for (int q = 0; q < 4; q++)
        for (int k = 0; k < 27; k++) {
            f->f0[q][k] = l[q][k];
            f->d[q][k] = h[q][k] - l[q][k];
        }
    return (f->inv_de2 > 0 ? 54.0 : 27.0) * (double)far->ncell;
}

/* The forces of the requested particles of super-group s's groups, their
 * lists made in one walk (multi_walk); the interactions, or -1 when out of
 * memory. A super-group of more groups than a mask holds (a rare, uneven
 * one) walks them one by one. */
static double super_group(const qt_tree *t, size_t s, double G, double theta, size_t first, size_t count,
                          const unsigned char *active, qt_work *w, double *acc, double *pot)
{
    const size_t g0 = t->super_first_group[s], g1 = t->super_first_group[s + 1];
    double total = 0;
    if (g1 - g0 > QT_WALKERS) {
        for (size_t k = g0; k < g1 && total >= 0; k++) {
            double done = group_from_root(t, k, G, theta, first, count, active, w, acc, pot);
            total = done < 0 ? -1 : total + done;
        }
        return total;
    }
    if (!w->walkers && !(w->walkers = calloc(1, sizeof *w->walkers)))
        return -1;
    const qt_node *sn = &t->nodes[t->supers[s]];
    /* All its groups walk, wanted or not: which cells are shared, and so
     * the forces' round-off and the far field, must not depend on the
     * particles asked for (an MPI rank's share, a block step's active
     * ones). Only the groups with wanted particles get lists. */
    qt_walkers *wk = w->walkers;
    wk->n = (int)(g1 - g0);
    uint64_t need = 0;
    for (size_t k = g0; k < g1; k++) {
        wk->group[k - g0] = k;
        if (any_wanted(t, &t->nodes[t->groups[k]], first, count, active))
            need |= (uint64_t)1 << (k - g0);
    }
    if (!need)
        return 0;
    const int with_field = sn->count >= QT_FIELD_MIN && sn->bmax > 0;
    if (multi_walk(t, sn, theta, with_field ? QT_FAR / theta * sn->bmax : 0, need, wk) != 0)
        return -1;
    const int field = wk->far.ncell > 0;
    if (field)
        total += far_field(t, sn, &wk->far, &wk->field);
    for (int k = 0; k < wk->n; k++) {
        const qt_node *g = &t->nodes[t->groups[wk->group[k]]];
        qt_targets tg, ts;
        size_t js[QT_GROUP];
        gather_targets(t, g, g->com, first, count, active, &tg, js);
        if (!tg.n)
            continue;
        gather_targets(t, g, sn->com, first, count, active, &ts, js);
        apply_lists(t, &wk->shared, field ? &wk->field : NULL, &ts, &wk->own[k], G, first, &tg, js, acc, pot);
        total += (double)tg.n * (double)(wk->shared.ncell + wk->own[k].ncell + wk->own[k].npart + field);
    }
    return total;
}

double qt_accelerations_masked(const qt_tree *t, double G, double theta, size_t first, size_t count,
                               const unsigned char *active, double *acc, double *pot)
{
    double total = 0;
    int failed = 0;
    /* A block step's sub-steps walk by super-group too: the groups without
     * active particles only test the nodes where their super-group may
     * share cells (multi_walk), and the active particles get the forces the
     * full step would give them, bit for bit. */
    const int root_walks = t->root_walks;
    const long n = (long)(root_walks ? t->ngroups : t->nsupers);
#pragma omp parallel reduction(+ : total) reduction(| : failed)
    {
        qt_work w = {0};
#pragma omp for schedule(dynamic, 1)
        for (long k = 0; k < n; k++) {
            if (failed)
                continue;
            double done = root_walks ? group_from_root(t, (size_t)k, G, theta, first, count, active, &w, acc, pot)
                                        : super_group(t, (size_t)k, G, theta, first, count, active, &w, acc, pot);
            if (done < 0)
                failed = 1;
            else
                total += done;
        }
        free_work(&w);
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
    free_build_scratch(t);
    free(t->groups);
    free(t->supers);
    free(t->super_first_group);
    free(t->px);
    free(t->walk);
    memset(t, 0, sizeof *t);
}
