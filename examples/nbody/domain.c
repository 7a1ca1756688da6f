#include "domain.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "particles/kdtree.h"
#include "ranks.h"
#include "source/models/model.h"

#define KEY_BITS 21
#define KEY_MAX_CELL ((1u << KEY_BITS) - 1)

/* ---- the Peano-Hilbert curve ------------------------------------------ */

uint64_t domain_hilbert_key(const uint32_t in[3])
{
    uint32_t x[3] = {in[0], in[1], in[2]};
    /* Skilling's transform of the axes to the curve's "transpose": undo the
     * rotations and reflections level by level from the top ... */
    for (uint32_t q = 1u << (KEY_BITS - 1); q > 1; q >>= 1) {
        uint32_t p = q - 1;
        for (int i = 0; i < 3; i++) {
            if (x[i] & q) {
                x[0] ^= p; /* reflect */
            } else {
                uint32_t t = (x[0] ^ x[i]) & p; /* swap the low bits of x[0] and x[i] */
                x[0] ^= t;
                x[i] ^= t;
            }
        }
    }
    /* ... then the Gray code ... */
    for (int i = 1; i < 3; i++)
        x[i] ^= x[i - 1];
    uint32_t t = 0;
    for (uint32_t q = 1u << (KEY_BITS - 1); q > 1; q >>= 1)
        if (x[2] & q)
            t ^= q - 1;
    for (int i = 0; i < 3; i++)
        x[i] ^= t;
    /* ... and the transpose's bits interleaved, the top level first. */
    uint64_t key = 0;
    for (int bit = KEY_BITS - 1; bit >= 0; bit--)
        for (int i = 0; i < 3; i++)
            key = key << 1 | ((x[i] >> bit) & 1u);
    return key;
}

/* The cube the keys are cut in: the least corner and grid cells per kpc,
 * from every rank's particles (the same on every rank). */
static int key_frame(const bodies *b, double lo[3], double *scale)
{
    double v[6] = {INFINITY, INFINITY, INFINITY, INFINITY, INFINITY, INFINITY};
    for (size_t i = 0; i < b->n; i++)
        for (int k = 0; k < 3; k++) {
            v[k] = fmin(v[k], b->pos[3 * i + k]);
            v[3 + k] = fmin(v[3 + k], -b->pos[3 * i + k]);
        }
    if (ranks_extreme(v, 6, 0) != 0)
        return -1;
    double side = 0;
    for (int k = 0; k < 3; k++) {
        lo[k] = isfinite(v[k]) ? v[k] : 0;
        side = fmax(side, isfinite(v[k]) ? -v[3 + k] - v[k] : 0);
    }
    *scale = side > 0 ? (double)KEY_MAX_CELL / side : 0;
    return 0;
}

static uint64_t key_of(const double p[3], const double lo[3], double scale)
{
    uint32_t x[3];
    for (int k = 0; k < 3; k++) {
        double c = (p[k] - lo[k]) * scale;
        x[k] = c <= 0 ? 0 : c >= (double)KEY_MAX_CELL ? KEY_MAX_CELL : (uint32_t)c;
    }
    return domain_hilbert_key(x);
}

/* ---- the particles' records ----------------------------------------------- */

/* A particle's place along the curve; ties (two particles in one cell of
 * the grid) by id, then by where it came from, so the order is total. */
typedef struct keyed {
    uint64_t key, id;
    size_t at;
} keyed;

static int by_key(const void *pa, const void *pb)
{
    const keyed *a = pa, *b = pb;
    if (a->key != b->key)
        return a->key < b->key ? -1 : 1;
    if (a->id != b->id)
        return a->id < b->id ? -1 : 1;
    return (a->at > b->at) - (a->at < b->at);
}

/* A record: id, position, velocity, mass, type, level, then the fields
 * (floats); a multiple of 8 bytes. Accelerations and potentials do not
 * travel: the forces are computed anew after every migration. */
enum { R_ID = 0, R_POS = 8, R_VEL = 32, R_MASS = 56, R_TYPE = 64, R_LEVEL = 65, R_FIELDS = 66 };

static size_t record_bytes(const bodies *b)
{
    return ((size_t)R_FIELDS + 4 * (size_t)b->nfields + 7) & ~(size_t)7;
}

static void pack(const bodies *b, size_t i, unsigned char *r)
{
    memcpy(r + R_ID, &b->id[i], 8);
    memcpy(r + R_POS, &b->pos[3 * i], 24);
    memcpy(r + R_VEL, &b->vel[3 * i], 24);
    memcpy(r + R_MASS, &b->mass[i], 8);
    r[R_TYPE] = b->type[i];
    r[R_LEVEL] = b->level ? b->level[i] : 0;
    for (int f = 0; f < b->nfields; f++)
        memcpy(r + R_FIELDS + 4 * f, &b->field[f][i], 4);
}

/* ---- where the curve is cut ------------------------------------------- */

/* How many of the sorted keys s[0 .. n) are at most v. */
static size_t count_at_most(const keyed *s, size_t n, uint64_t v)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (s[mid].key <= v)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* cut[j] (j < size - 1): rank j + 1's particles have keys above it, rank
 * j's at most it: the least key with at least (j + 1) n_all / size
 * particles at or below it, by bisection over the keys (64 rounds of one
 * sum over the ranks). */
static int find_cuts(const keyed *s, size_t n, size_t n_all, int size, uint64_t *cut)
{
    int m = size - 1;
    uint64_t *lo = calloc((size_t)m + 1, sizeof *lo), *hi = malloc(((size_t)m + 1) * sizeof *hi),
             *count = malloc(((size_t)m + 1) * sizeof *count);
    int ok = lo && hi && count;
    for (int j = 0; ok && j < m; j++)
        hi[j] = (uint64_t)1 << (3 * KEY_BITS);
    for (int round = 0; ok && round < 64; round++) {
        for (int j = 0; j < m; j++)
            count[j] = count_at_most(s, n, lo[j] + (hi[j] - lo[j]) / 2);
        ok = ranks_sum_u64(count, m) == 0;
        for (int j = 0; ok && j < m; j++) {
            uint64_t mid = lo[j] + (hi[j] - lo[j]) / 2, target = (uint64_t)n_all * (uint64_t)(j + 1) / (uint64_t)size;
            if (count[j] >= target)
                hi[j] = mid;
            else
                lo[j] = mid + 1;
        }
    }
    for (int j = 0; ok && j < m; j++)
        cut[j] = lo[j];
    free(lo);
    free(hi);
    free(count);
    return ok ? 0 : -1;
}

/* ---- migration ------------------------------------------------------------ */

/* Particle q of the new order: from the old arrays (at < n_old) or from
 * the received records. */
#define FROM_OLD(at, n_old) ((at) < (n_old))

/* Replaces a per-particle array by its entries in the new order s[0 ..
 * n), each `bytes` long: old ones from old, received ones from the records
 * at offset `off`. 0, or -1 when out of memory. */
static int rebuild(void **array, size_t bytes, const keyed *s, size_t n, size_t n_old, const unsigned char *recv,
                   size_t rec, size_t off)
{
    unsigned char *now = malloc(n * bytes + 1), *old = *array;
    if (!now)
        return -1;
    for (size_t q = 0; q < n; q++) {
        size_t at = s[q].at;
        memcpy(now + q * bytes, FROM_OLD(at, n_old) ? old + at * bytes : recv + (at - n_old) * rec + off, bytes);
    }
    free(old);
    *array = now;
    return 0;
}

/* The new order: the particles that stay and the received ones, along the
 * curve. NULL when out of memory. */
static keyed *new_order(const keyed *s, size_t n_old, const unsigned char *stay, const unsigned char *recv,
                        size_t nrecv, size_t rec, const double lo[3], double scale, size_t *n)
{
    size_t kept = 0;
    for (size_t q = 0; q < n_old; q++)
        kept += stay[q];
    keyed *o = malloc((kept + nrecv + 1) * sizeof *o);
    if (!o)
        return NULL;
    *n = 0;
    for (size_t q = 0; q < n_old; q++)
        if (stay[q])
            o[(*n)++] = s[q];
    for (size_t k = 0; k < nrecv; k++, (*n)++) {
        double p[3];
        memcpy(p, recv + k * rec + R_POS, sizeof p);
        o[*n].key = key_of(p, lo, scale);
        memcpy(&o[*n].id, recv + k * rec + R_ID, 8);
        o[*n].at = n_old + k;
    }
    qsort(o, *n, sizeof *o, by_key);
    return o;
}

/* Every per-particle array in the new order (accelerations and potentials
 * only made room for). */
static int rebuild_all(bodies *b, const keyed *o, size_t n, const unsigned char *recv, size_t rec)
{
    size_t n_old = b->n;
    free(b->acc);
    free(b->pot);
    b->acc = calloc(3 * n + 3, sizeof *b->acc);
    b->pot = calloc(n + 1, sizeof *b->pot);
    int bad = !b->acc || !b->pot;
    bad |= rebuild((void **)&b->pos, 24, o, n, n_old, recv, rec, R_POS);
    bad |= rebuild((void **)&b->vel, 24, o, n, n_old, recv, rec, R_VEL);
    bad |= rebuild((void **)&b->mass, 8, o, n, n_old, recv, rec, R_MASS);
    bad |= rebuild((void **)&b->id, 8, o, n, n_old, recv, rec, R_ID);
    bad |= rebuild((void **)&b->type, 1, o, n, n_old, recv, rec, R_TYPE);
    if (b->level)
        bad |= rebuild((void **)&b->level, 1, o, n, n_old, recv, rec, R_LEVEL);
    for (int f = 0; f < b->nfields; f++)
        bad |= rebuild((void **)&b->field[f], 4, o, n, n_old, recv, rec, R_FIELDS + 4 * (size_t)f);
    b->n = n;
    return bad ? -1 : 0;
}

/* Softenings from the types, and the tracers among this rank's particles. */
static int settle(bodies *b, double eps, double eps_halo)
{
    free(b->eps_all);
    free(b->tracers);
    b->eps_all = malloc((b->n + 1) * sizeof *b->eps_all);
    b->tracers = malloc((b->n + 1) * sizeof *b->tracers);
    if (!b->eps_all || !b->tracers)
        return -1;
    b->ntracers = 0;
    for (size_t i = 0; i < b->n; i++) {
        b->eps_all[i] = b->type[i] == ORR_MODEL_TYPE_HALO ? eps_halo : eps;
        if (bodies_is_tracer(b, i))
            b->tracers[b->ntracers++] = i;
    }
    return 0;
}

/* The records of the particles that leave, in rank order (which the
 * curve's order is), and which stay. */
static unsigned char *pack_leaving(const bodies *b, const keyed *s, const uint64_t *cut, int rank, int size,
                                   unsigned char *stay, size_t *send_bytes)
{
    size_t rec = record_bytes(b), leaving = 0;
    int *dest = malloc((b->n + 1) * sizeof *dest);
    if (!dest)
        return NULL;
    memset(send_bytes, 0, (size_t)size * sizeof *send_bytes);
    int r = 0;
    for (size_t q = 0; q < b->n; q++) {
        while (r < size - 1 && s[q].key > cut[r])
            r++;
        dest[q] = r;
        stay[q] = r == rank;
        if (r != rank) {
            send_bytes[r] += rec;
            leaving++;
        }
    }
    unsigned char *send = malloc(leaving * rec + 1);
    for (size_t q = 0, k = 0; send && q < b->n; q++)
        if (dest[q] != rank)
            pack(b, s[q].at, send + rec * k++);
    free(dest);
    return send;
}

int domain_migrate(bodies *b, double eps, double eps_halo, int rank, int size)
{
    double lo[3], scale;
    if (key_frame(b, lo, &scale) != 0)
        return -1;
    free(b->acc); /* made anew (rebuild_all): less memory while the records travel */
    free(b->pot);
    b->acc = b->pot = NULL;
    keyed *s = malloc((b->n + 1) * sizeof *s);
    uint64_t *cut = malloc((size_t)size * sizeof *cut);
    size_t *bytes = malloc(2 * (size_t)size * sizeof *bytes);
    unsigned char *stay = malloc(b->n + 1);
    int failed = !s || !cut || !bytes || !stay;
    for (size_t i = 0; !failed && i < b->n; i++)
        s[i] = (keyed){key_of(&b->pos[3 * i], lo, scale), b->id[i], i};
    if (!failed)
        qsort(s, b->n, sizeof *s, by_key);
    failed = ranks_any(failed) || find_cuts(s, b->n, b->n_all, size, cut) != 0;
    unsigned char *send = failed ? NULL : pack_leaving(b, s, cut, rank, size, stay, bytes);
    void *recv = NULL;
    failed = failed || ranks_any(!send) || ranks_exchange(send, bytes, &recv, bytes + size) != 0;
    free(send);
    keyed *o = NULL;
    size_t n = 0, rec = record_bytes(b), nrecv = 0;
    for (int r = 0; !failed && r < size; r++)
        nrecv += bytes[size + r] / rec;
    if (!failed)
        failed = !(o = new_order(s, b->n, stay, recv, nrecv, rec, lo, scale, &n)) || rebuild_all(b, o, n, recv, rec) != 0 ||
                 settle(b, eps, eps_halo) != 0;
    free(o);
    free(recv);
    free(s);
    free(cut);
    free(bytes);
    free(stay);
    if (ranks_any(failed)) {
        fprintf(stderr, "orrery-nbody: out of memory moving the particles between the ranks\n");
        return -1;
    }
    return 0;
}

/* ---- the locally essential trees ---------------------------------------- */

/* A box: lo[3], hi[3]; empty when lo > hi. */
typedef struct box {
    double lo[3], hi[3];
} box;

/* Each rank's particles that forces are wanted for are described to the
 * others by BOXES boxes: those of BOXES equal pieces of its particles in
 * the curve's order, each compact (one box about all of a rank's particles
 * would reach from the galaxy's centre to its halo, and every rank would
 * import most of the centre particle by particle). */
#define BOXES 512
#define RANK_BOXES (BOXES + 1) /* and the box about them all, tested first */

static int box_empty(const box *x)
{
    return !(x->lo[0] <= x->hi[0]);
}

/* The boxes about this rank's particles that forces are wanted for, into
 * x[0 .. BOXES), and the box about them all into x[BOXES]. */
static void wanted_boxes(const bodies *b, const unsigned char *active, box *x)
{
    x[BOXES] = (box){{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
    for (int m = 0; m < BOXES; m++) {
        x[m] = (box){{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
        for (size_t i = b->n * (size_t)m / BOXES; i < b->n * (size_t)(m + 1) / BOXES; i++)
            if (!active || active[i])
                for (int k = 0; k < 3; k++) {
                    x[m].lo[k] = fmin(x[m].lo[k], b->pos[3 * i + k]);
                    x[m].hi[k] = fmax(x[m].hi[k], b->pos[3 * i + k]);
                }
        for (int k = 0; k < 3; k++) {
            x[BOXES].lo[k] = fmin(x[BOXES].lo[k], x[m].lo[k]);
            x[BOXES].hi[k] = fmax(x[BOXES].hi[k], x[m].hi[k]);
        }
    }
}

/* The squared distance from point c to box x. */
static double distance2(const double c[3], const box *x)
{
    double d2 = 0;
    for (int k = 0; k < 3; k++) {
        double d = fmax(fmax(x->lo[k] - c[k], c[k] - x->hi[k]), 0.0);
        d2 += d * d;
    }
    return d2;
}

/* Whether cell w may be taken whole by every point of a rank's boxes x[0
 * .. RANK_BOXES): its centre of mass farther than b_max / theta from all
 * of them (at once when it is from the box about them all). */
static int far_from_boxes(const qt_walk_node *w, const box *x, double inv_theta)
{
    const double reach = w->bmax * inv_theta, reach2 = reach * reach;
    if (distance2(w->com, &x[BOXES]) > reach2)
        return 1;
    for (int m = 0; m < BOXES; m++)
        if (!box_empty(&x[m]) && !(distance2(w->com, &x[m]) > reach2))
            return 0;
    return 1;
}

/* An exported cell: position (its centre of mass), mass, softening, quadrupole, b_max. */
#define CELL_DOUBLES 12
/* An exported particle: position, mass, softening. */
#define PART_DOUBLES 5

/* What box x needs of tree t: counts, then (into out when not NULL) the
 * cells taken whole for all of it, then the particles of the leaves it
 * opens. Returns the doubles written: 2 + 12 cells + 5 particles. */
static size_t essential(const qt_tree *t, const box *x, double theta, double *out)
{
    size_t cells = 0, parts = 0;
    if (box_empty(&x[BOXES])) /* no particle wants forces there */
        return 0;
    const double inv_theta = 1.0 / theta;
    for (size_t id = 0; id < t->nnodes;) { /* cells first */
        const qt_walk_node *w = &t->walk[id];
        if (far_from_boxes(w, x, inv_theta)) {
            if (out) {
                const qt_node *nd = &t->nodes[id];
                double *c = out + 2 + CELL_DOUBLES * cells;
                memcpy(c, nd->com, 3 * sizeof *c);
                c[3] = nd->mass;
                c[4] = sqrt(nd->eps2);
                memcpy(c + 5, nd->quad, 6 * sizeof *c);
                c[11] = nd->bmax;
            }
            cells++;
            id = w->next;
        } else {
            id++;
        }
    }
    double *p0 = out ? out + 2 + CELL_DOUBLES * cells : NULL;
    for (size_t id = 0; id < t->nnodes;) { /* then the opened leaves' particles */
        const qt_walk_node *w = &t->walk[id];
        if (far_from_boxes(w, x, inv_theta)) {
            id = w->next;
            continue;
        }
        const qt_node *nd = &t->nodes[id];
        if (w->next == id + 1)
            for (size_t j = nd->first; j < nd->first + nd->count; j++, parts++)
                if (p0) {
                    double *p = p0 + PART_DOUBLES * parts;
                    p[0] = t->px[j];
                    p[1] = t->py[j];
                    p[2] = t->pz[j];
                    p[3] = t->pm[j];
                    p[4] = sqrt(t->pe2[j]);
                }
        id++;
    }
    if (out) {
        out[0] = (double)cells;
        out[1] = (double)parts;
    }
    return 2 + CELL_DOUBLES * cells + PART_DOUBLES * parts;
}

/* Every rank's boxes of wanted particles (all[r RANK_BOXES ..]). */
static int gather_boxes(const bodies *b, const unsigned char *active, int rank, int size, box *all)
{
    size_t *ones = malloc((size_t)size * sizeof *ones);
    if (!ones)
        return -1;
    for (int r = 0; r < size; r++)
        ones[r] = 1;
    wanted_boxes(b, active, &all[(size_t)rank * RANK_BOXES]);
    int st = ranks_gather((double *)all, 6 * RANK_BOXES, ones);
    free(ones);
    return st;
}

/* What every other rank needs of this rank's tree t, in rank order. NULL
 * when out of memory. */
static double *export_essentials(const qt_tree *t, const box *boxes, double theta, int rank, int size,
                                 size_t *send_bytes)
{
    size_t total = 0;
    for (int r = 0; r < size; r++) {
        send_bytes[r] = r == rank ? 0 : essential(t, &boxes[(size_t)r * RANK_BOXES], theta, NULL) * sizeof(double);
        total += send_bytes[r];
    }
    double *send = malloc(total + 1);
    for (int r = 0, at = 0; send && r < size; r++)
        if (send_bytes[r]) {
            essential(t, &boxes[(size_t)r * RANK_BOXES], theta, send + at);
            at += (int)(send_bytes[r] / sizeof(double));
        }
    return send;
}

/* What this rank imported, after its own particles in its arrays of
 * positions, masses and softenings: the cells (their quadrupoles and b_max
 * here), then the particles. */
typedef struct imported {
    size_t cells, particles;
    double *quad, *bmax;
} imported;

/* Grows *a to n entries of `size` bytes (a large block is remapped, not copied). */
static int grow_to(double **a, size_t n)
{
    double *g = realloc(*a, (n + 1) * sizeof *g);
    if (g)
        *a = g;
    return g != NULL;
}

/* Appends the received cells and particles to b's positions, masses and
 * softenings (b->n is left as it is: this rank's own come first). */
static int append_imported(bodies *b, const double *recv, const size_t *recv_bytes, int size, imported *im)
{
    const double *at = recv;
    for (int r = 0; r < size; at += recv_bytes[r] / sizeof(double), r++)
        if (recv_bytes[r]) {
            im->cells += (size_t)at[0];
            im->particles += (size_t)at[1];
        }
    size_t n = b->n + im->cells + im->particles;
    im->quad = malloc(6 * (im->cells + 1) * sizeof *im->quad);
    im->bmax = malloc((im->cells + 1) * sizeof *im->bmax);
    if (!im->quad || !im->bmax || !grow_to(&b->pos, 3 * n) || !grow_to(&b->mass, n) || !grow_to(&b->eps_all, n))
        return -1;
    size_t ic = b->n, ip = b->n + im->cells;
    at = recv;
    for (int r = 0; r < size; at += recv_bytes[r] / sizeof(double), r++) {
        if (!recv_bytes[r])
            continue;
        size_t nc = (size_t)at[0], np = (size_t)at[1];
        for (size_t k = 0; k < nc; k++, ic++) {
            const double *e = at + 2 + CELL_DOUBLES * k;
            memcpy(&b->pos[3 * ic], e, 3 * sizeof *e);
            b->mass[ic] = e[3];
            b->eps_all[ic] = e[4];
            memcpy(&im->quad[6 * (ic - b->n)], e + 5, 6 * sizeof *e);
            im->bmax[ic - b->n] = e[11];
        }
        for (size_t k = 0; k < np; k++, ip++) {
            const double *e = at + 2 + CELL_DOUBLES * nc + PART_DOUBLES * k;
            memcpy(&b->pos[3 * ip], e, 3 * sizeof *e);
            b->mass[ip] = e[3];
            b->eps_all[ip] = e[4];
        }
    }
    return 0;
}

/* b's arrays back to its own particles. */
static void drop_imported(bodies *b, imported *im)
{
    grow_to(&b->pos, 3 * b->n);
    grow_to(&b->mass, b->n);
    grow_to(&b->eps_all, b->n);
    free(im->quad);
    free(im->bmax);
}

double domain_gravity(qt_tree *t, bodies *b, double G, double theta, const unsigned char *active, int rank, int size,
                      domain_stats *stats)
{
    qt_free(t); /* the last step's tree: not kept while this rank's own is built */
    box *boxes = malloc((size_t)size * RANK_BOXES * sizeof *boxes);
    size_t *bytes = malloc(2 * (size_t)size * sizeof *bytes);
    int failed = !boxes || !bytes;
    failed = ranks_any(failed) || gather_boxes(b, active, rank, size, boxes) != 0;
    double *send = NULL;
    void *recv = NULL;
    if (!failed) {
        /* This rank's own tree, for what the others need of it; freed
         * before the tree of all that this rank's forces come from. */
        qt_tree own = {0};
        failed = qt_build(&own, b->pos, b->mass, b->eps_all, b->n) != 0 ||
                 !(send = export_essentials(&own, boxes, theta, rank, size, bytes));
        qt_free(&own);
    }
    free(boxes);
    failed = ranks_any(failed) || ranks_exchange(send, bytes, &recv, bytes + size) != 0;
    free(send);
    imported im = {0};
    double interactions = -1;
    if (!failed && append_imported(b, recv, bytes + size, size, &im) == 0) {
        free(recv);
        recv = NULL;
        size_t n = b->n + im.cells + im.particles;
        if (qt_build_with_moments(t, b->pos, b->mass, b->eps_all, im.quad, im.bmax, b->n, im.cells, n) == 0) {
            qt_drop_build_scratch(t);
            interactions = qt_accelerations_masked(t, G, theta, 0, b->n, active, b->acc, b->pot);
        }
        stats->cells = im.cells;
        stats->particles = im.particles;
    }
    qt_free(t); /* it points into the imported arrays */
    drop_imported(b, &im);
    free(recv);
    free(bytes);
    return ranks_any(interactions < 0) ? -1 : interactions;
}

/* ---- sums and tracers ------------------------------------------------------ */

static double mass_momentum_term(const bodies *b, size_t i, int c)
{
    return c == 0 ? b->mass[i] : b->mass[i] * b->vel[3 * i + c - 1];
}

int domain_mass_momentum(const bodies *b, double e[4])
{
    double big[4] = {0, 0, 0, 0}, scale[4];
    for (size_t i = 0; i < b->n; i++)
        for (int c = 0; c < 4; c++)
            big[c] = fmax(big[c], fabs(mass_momentum_term(b, i, c)));
    if (ranks_extreme(big, 4, 1) != 0)
        return -1;
    /* Each term in units of 2^-s, s such that n_all terms of the largest
     * size stay below 2^62: each rounded alone, summed exactly. */
    for (int c = 0; c < 4; c++) {
        int ex = 0;
        frexp(big[c] * (double)(b->n_all + 1), &ex);
        scale[c] = ldexp(1.0, 62 - ex);
    }
    uint64_t sum[4] = {0, 0, 0, 0};
    for (size_t i = 0; i < b->n; i++)
        for (int c = 0; c < 4; c++)
            sum[c] += (uint64_t)llround(mass_momentum_term(b, i, c) * scale[c]);
    if (ranks_sum_u64(sum, 4) != 0)
        return -1;
    for (int c = 0; c < 4; c++)
        e[c] = (double)(int64_t)sum[c] / scale[c];
    return 0;
}

void nearest_non_tracers(const double *pos, const double *mass, size_t n, double light, const double x[3], int k,
                         double *d2)
{
    for (int j = 0; j < k; j++)
        d2[j] = INFINITY;
    for (size_t i = 0; i < n; i++) {
        if (mass[i] < light)
            continue;
        const double *y = &pos[3 * i];
        double dx = y[0] - x[0], dy = y[1] - x[1], dz = y[2] - x[2], r2 = dx * dx + dy * dy + dz * dz;
        if (r2 < d2[0])
            orr_kd_heap_replace_top(d2, (size_t)k, r2);
    }
}

static int compare_double(const void *pa, const void *pb)
{
    double a = *(const double *)pa, b = *(const double *)pb;
    return (a > b) - (a < b);
}

int domain_soften_tracers(bodies *b, int k, double eps, int rank, int size)
{
    size_t *counts = malloc((size_t)size * sizeof *counts);
    if (ranks_any(!counts) || ranks_counts(b->ntracers, counts) != 0) {
        free(counts);
        return -1;
    }
    size_t all = 0, first = 0;
    for (int r = 0; r < size; r++) {
        first += r < rank ? counts[r] : 0;
        all += counts[r];
    }
    double *where = malloc((3 * all + 1) * sizeof *where);
    double *d2 = malloc(((size_t)size * all * (size_t)k + 1) * sizeof *d2);
    size_t *ones = malloc((size_t)size * sizeof *ones);
    int failed = !where || !d2 || !ones;
    if (ranks_any(failed)) {
        free(where), free(d2), free(ones), free(counts);
        return -1;
    }
    for (size_t j = 0; j < b->ntracers; j++)
        memcpy(&where[3 * (first + j)], &b->pos[3 * b->tracers[j]], 3 * sizeof *where);
    failed = ranks_gather(where, 3, counts) != 0;
    /* Each rank's k nearest to every tracer, then every rank's merged. */
    for (size_t t = 0; !failed && t < all; t++)
        nearest_non_tracers(b->pos, b->mass, b->n, b->tracer_mass, &where[3 * t], k,
                            &d2[((size_t)rank * all + t) * (size_t)k]);
    for (int r = 0; r < size; r++)
        ones[r] = 1;
    failed = failed || ranks_gather(d2, all * (size_t)k, ones) != 0;
    double *merged = malloc(((size_t)size * (size_t)k + 1) * sizeof *merged);
    failed = failed || !merged;
    for (size_t j = 0; !failed && j < b->ntracers; j++) {
        size_t t = first + j;
        for (int r = 0; r < size; r++)
            memcpy(&merged[(size_t)r * (size_t)k], &d2[((size_t)r * all + t) * (size_t)k], (size_t)k * sizeof *merged);
        qsort(merged, (size_t)size * (size_t)k, sizeof *merged, compare_double);
        double r2 = merged[k - 1]; /* fewer than k others: as stars */
        b->eps_all[b->tracers[j]] = isfinite(r2) ? fmax(eps, sqrt(2.0 * r2)) : eps;
    }
    free(merged);
    free(where);
    free(d2);
    free(ones);
    free(counts);
    return ranks_any(failed) ? -1 : 0;
}
