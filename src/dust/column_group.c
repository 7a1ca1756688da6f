/* Optical depths of many stars from one eye, sharing the tree's traversal
 * between neighbouring lines of sight (docs/dust.md#method).
 *
 * The stars are sorted by their direction from the eye into the cells of a
 * cube map, each face's square split as a quadtree until a cell holds at
 * most GROUP_MAX stars; a cell's stars are a group, and a cell of at most
 * SUPER_MAX stars a super-group. A super-group walks the tree once, against
 * the cone from the eye that holds all of its segments (its axis, its
 * half-angle, its reach: the farthest star's distance), and keeps every
 * kernel whose support the cone may meet, in the tree's order; each of its
 * groups keeps those its own cone may meet: its candidates (a tree walk for
 * each group cost three times the picking, measured with bench_dust). Each
 * star then sums its share of each candidate (orr_dust_share,
 * column_walk.h): eight stars at once, a star a lane, with AVX-512 or
 * AVX2 (column_lanes.c), one term at a time elsewhere: the same bits.
 *
 * Why the result is each star's own walk's, bit for bit: a kernel adds
 * nonzero only if the star's segment passes through its support; the cone
 * test keeps every such kernel (with slack far above rounding), and the
 * tree's boxes hold every such kernel too (column.c). So the candidates'
 * sum and the single walk (orr_dust_tau) add the same nonzero terms in the
 * same order (the tree's), and the zeros change nothing. A star's value
 * thus does not depend on which group it lands in, how the stars are
 * chunked, or how many threads share the groups. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "core/radix.h"
#include "core/simd.h"
#include "dust/column.h"
#include "dust/column_lanes.h"
#include "dust/column_walk.h"

#define GROUP_MAX 64  /* stars per group, unless its cell is at the finest level */
#define SUPER_MAX 512 /* stars per super-group: its groups pick their candidates from its own */
#define LEVELS 12     /* quadtree levels per cube face: cells down to 1/4096 of a face's side */
#define STACK_MAX 128 /* as column.c: the tree's depth is about log2(n / 8) + 1 */
#define SLACK 1e-6    /* relative widening of the cone's tests, far above double rounding */

/* ---- grouping the stars by direction ---- */

#define NO_KEY UINT64_MAX /* a star without a column (direction keys are below 2^(2 LEVELS + 3)) */

typedef struct star_key {
    uint64_t key; /* cube face, then the cell's Morton code */
    uint32_t i;   /* the star's index */
    double len;   /* its distance from the eye */
} star_key;

/* The cell index in [0, 2^LEVELS) of t in [-1, 1]. */
static uint64_t face_cell(double t)
{
    const double cells = (double)(1u << LEVELS);
    double c = floor((t + 1) * 0.5 * cells);
    return c < 0 ? 0 : c >= cells ? (uint64_t)cells - 1 : (uint64_t)c;
}

/* The cube-map cell of the unit direction d: the face of its largest
 * component, then the two others (divided by it) interleaved bit by bit, so
 * that sorting by the key puts each quadtree cell's stars together. */
static uint64_t direction_key(const double d[3])
{
    const double ax = fabs(d[0]), ay = fabs(d[1]), az = fabs(d[2]);
    int major = ax >= ay && ax >= az ? 0 : ay >= az ? 1 : 2;
    const int u = major == 0 ? 1 : 0, v = major == 2 ? 1 : 2;
    const double m = fabs(d[major]);
    const uint64_t face = (uint64_t)(2 * major + (d[major] < 0));
    const uint64_t cu = face_cell(d[u] / m), cv = face_cell(d[v] / m);
    uint64_t morton = 0;
    for (int b = 0; b < LEVELS; b++)
        morton |= (cu >> b & 1u) << (2 * b + 1) | (cv >> b & 1u) << (2 * b);
    return face << (2 * LEVELS) | morton;
}

/* Splits the sorted keys [lo, hi), which share their cell at `level`
 * (-1: the whole sky), into cells of at most max stars (unless at the
 * finest level); their first indices go to starts, their levels to levels
 * (if not NULL). */
static size_t split_groups(const star_key *k, size_t lo, size_t hi, int level, size_t max, uint32_t *starts,
                           int *levels, size_t ng)
{
    if ((level >= 0 && hi - lo <= max) || level == LEVELS) {
        if (levels)
            levels[ng] = level;
        starts[ng++] = (uint32_t)lo;
        return ng;
    }
    const int shift = 2 * (LEVELS - level - 1);
    for (size_t a = lo; a < hi;) {
        const uint64_t cell = k[a].key >> shift;
        size_t b = a + 1;
        while (b < hi && k[b].key >> shift == cell)
            b++;
        ng = split_groups(k, a, b, level + 1, max, starts, levels, ng);
        a = b;
    }
    return ng;
}

/* ---- a group's cone ---- */

typedef struct cone {
    double e[3];        /* the eye, its apex */
    double a[3];        /* unit axis */
    double cos_a, sin_a; /* of the half-angle */
    double reach;       /* the farthest star's distance */
    int wide;           /* half-angle of 90 degrees or more: no angular test */
} cone;

static void star_point(const float *x, const float *y, const float *z, uint32_t i, double p[3])
{
    p[0] = x[i];
    p[1] = y[i];
    p[2] = z[i];
}

/* The cone from the eye holding the segments to the stars k[0, n). */
static void group_cone(cone *c, const double eye[3], const float *x, const float *y, const float *z,
                       const star_key *k, size_t n)
{
    double sum[3] = {0, 0, 0}, p[3];
    orr_dust_segment g;
    c->reach = 0;
    for (size_t q = 0; q < n; q++) {
        star_point(x, y, z, k[q].i, p);
        if (!orr_dust_star_segment(&g, eye, p))
            continue; /* (not in a group: tau_many leaves such stars out) */
        for (int a = 0; a < 3; a++)
            sum[a] += g.d[a];
        c->reach = fmax(c->reach, g.len);
    }
    const double norm = sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
    double half_angle = 0;
    for (int a = 0; a < 3; a++) {
        c->e[a] = eye[a];
        c->a[a] = norm > 0 ? sum[a] / norm : 0;
    }
    for (size_t q = 0; q < n && norm > 0; q++) {
        star_point(x, y, z, k[q].i, p);
        if (!orr_dust_star_segment(&g, eye, p))
            continue;
        const double dx = g.d[0] - c->a[0], dy = g.d[1] - c->a[1], dz = g.d[2] - c->a[2];
        /* the angle from its chord: accurate for small angles, unlike acos */
        half_angle = fmax(half_angle, 2 * asin(fmin(1.0, 0.5 * sqrt(dx * dx + dy * dy + dz * dz))));
    }
    half_angle += SLACK;
    c->wide = !(norm > 0) || half_angle >= 0.5 * 3.14159265358979323846;
    c->cos_a = cos(half_angle);
    c->sin_a = sin(half_angle);
    c->reach *= 1 + SLACK;
}

/* Whether the ball of radius r about the point v from the eye (d2 = |v|^2,
 * dist = |v|) may meet a segment in the cone: it must start within the
 * reach and lie within the half-angle plus the angle the ball subtends.
 * Errs on the side of yes. */
static inline int cone_may_meet_at(const cone *c, double vx, double vy, double vz, double d2, double dist, double r)
{
    r += SLACK * (r + dist);
    if (dist <= r)
        return 1;
    if (dist - r > c->reach)
        return 0;
    if (c->wide)
        return 1;
    /* dist cos(half-angle + the ball's angle): with sin b = r / dist,
     * dist (cos_a cos b - sin_a sin b) = cos_a sqrt(dist^2 - r^2) - sin_a r,
     * no division. */
    return vx * c->a[0] + vy * c->a[1] + vz * c->a[2] >= c->cos_a * sqrt(d2 - r * r) - c->sin_a * r;
}

/* The same for the ball about (bx, by, bz). */
static inline int cone_may_meet(const cone *c, double bx, double by, double bz, double r)
{
    const double vx = bx - c->e[0], vy = by - c->e[1], vz = bz - c->e[2];
    const double d2 = vx * vx + vy * vy + vz * vz;
    return cone_may_meet_at(c, vx, vy, vz, d2, sqrt(d2), r);
}

static int cone_may_meet_box(const cone *c, const orr_dust_node *nd)
{
    const double hx = 0.5 * ((double)nd->hi[0] - nd->lo[0]), hy = 0.5 * ((double)nd->hi[1] - nd->lo[1]),
                 hz = 0.5 * ((double)nd->hi[2] - nd->lo[2]);
    return cone_may_meet(c, nd->lo[0] + hx, nd->lo[1] + hy, nd->lo[2] + hz, sqrt(hx * hx + hy * hy + hz * hz));
}

/* ---- the candidates ---- */

/* How the stars' terms are summed: one star and one term at a time, or
 * eight stars at a time (column_lanes.h, in the candidates' lanes way). */
typedef enum { TERMS_ONE, TERMS_EIGHT_STARS } terms_way;

/* The kernels a group's cone may meet, as arrays (one per field) so that a
 * star's pass over them runs as vector loops. */
typedef struct candidates {
    size_t n, cap;
    double *vx, *vy, *vz, *v2; /* centre from the eye, and its square: as each star's walk computes them */
    double *dist, *r;          /* |v|, and the support's radius 2h */
    double *near;              /* less than the distance from the eye to the support's nearest point */
    float *ih, *kih2;          /* the kernel's own 1/h and k/h^2 */
    terms_way way;             /* how a star's terms are summed */
    orr_dust_lanes_way lanes;  /* and, eight stars at a time, how */
} candidates;

static void candidates_free(candidates *c)
{
    free(c->vx);
    free(c->vy);
    free(c->vz);
    free(c->v2);
    free(c->dist);
    free(c->r);
    free(c->near);
    free(c->ih);
    free(c->kih2);
}

static int grow_array(void **a, size_t cap, size_t size)
{
    void *p = realloc(*a, cap * size);
    if (p)
        *a = p;
    return p != NULL;
}

static int candidates_grow(candidates *c, size_t need)
{
    size_t cap = c->cap ? 2 * c->cap : 4096;
    while (cap < need)
        cap *= 2;
    void **d[] = {(void **)&c->vx,   (void **)&c->vy, (void **)&c->vz,
                  (void **)&c->v2,   (void **)&c->dist, (void **)&c->r, (void **)&c->near};
    for (size_t a = 0; a < sizeof d / sizeof *d; a++)
        if (!grow_array(d[a], cap, sizeof(double)))
            return 0;
    if (!grow_array((void **)&c->ih, cap, sizeof(float)) || !grow_array((void **)&c->kih2, cap, sizeof(float)))
        return 0;
    c->cap = cap;
    return 1;
}

/* The kernels whose supports the cone may meet, in the tree's order (the
 * walk's left-first order is the particles' order); 0 if out of memory. */
static int gather(const orr_dust_set *s, const cone *cn, candidates *c)
{
    uint32_t stack[STACK_MAX];
    int top = 0;
    stack[top++] = 0;
    c->n = 0;
    while (top > 0) {
        const orr_dust_node *nd = &s->nodes[stack[--top]];
        if (!cone_may_meet_box(cn, nd))
            continue;
        if (!nd->count) {
            if (top + 2 > STACK_MAX)
                return 0;
            stack[top++] = nd->first + 1;
            stack[top++] = nd->first;
            continue;
        }
        for (uint32_t i = nd->first; i < nd->first + nd->count; i++) {
            const double r = ORR_DUST_SUPPORT * s->h[i];
            if (!cone_may_meet(cn, s->x[i], s->y[i], s->z[i], r))
                continue;
            if (c->n == c->cap && !candidates_grow(c, c->n + 1))
                return 0;
            const size_t j = c->n++;
            const double vx = s->x[i] - cn->e[0], vy = s->y[i] - cn->e[1], vz = s->z[i] - cn->e[2];
            const double v2 = vx * vx + vy * vy + vz * vz, dist = sqrt(v2);
            c->vx[j] = vx;
            c->vy[j] = vy;
            c->vz[j] = vz;
            c->v2[j] = v2;
            c->dist[j] = dist;
            c->r[j] = r;
            c->near[j] = dist - r - SLACK * (r + dist);
            c->ih[j] = s->ih[i];
            c->kih2[j] = s->kih2[i];
        }
    }
    return 1;
}

/* A star's column over the group's candidates: their terms summed in the
 * candidates' order, each as orr_dust_share makes it (a term of 0 changes
 * no bit of a sum of terms >= 0). */
static double star_tau(const orr_dust_set *s, const candidates *c, const orr_dust_segment *g)
{
    double sum = 0;
    for (size_t j = 0; j < c->n; j++)
        sum += orr_dust_term(s, g, c->vx[j], c->vy[j], c->vz[j], c->v2[j], c->ih[j], c->kih2[j]);
    return sum;
}

/* Candidate j of from as candidate k of to, as far as the stars' terms
 * and drops need it (not dist and r, which only picking uses). */
static inline void candidate_copy(candidates *to, size_t k, const candidates *from, size_t j)
{
    to->vx[k] = from->vx[j];
    to->vy[k] = from->vy[j];
    to->vz[k] = from->vz[j];
    to->v2[k] = from->v2[j];
    to->near[k] = from->near[j];
    to->ih[k] = from->ih[j];
    to->kih2[k] = from->kih2[j];
}

/* Drops, keeping the order, the candidates whose support begins beyond
 * len, which the group's stars nearer than len cannot meet. */
static void drop_beyond(candidates *c, double len)
{
    size_t kept = 0;
    for (size_t j = 0; j < c->n; j++) {
        candidate_copy(c, kept, c, j);
        kept += c->near[j] < len;
    }
    c->n = kept;
}

/* The candidates of a super-group that a group's cone may meet, in their
 * order: the same test as the group's own walk of the tree would make of
 * each kernel (the same eye), and the super-group's cone holds all of the
 * group's segments, so every kernel a star meets is kept. 0 if out of
 * memory. */
static int pick_candidates(const candidates *from, const cone *cn, candidates *to)
{
    if (to->cap < from->n && !candidates_grow(to, from->n))
        return 0;
    size_t k = 0;
    for (size_t j = 0; j < from->n; j++) {
        candidate_copy(to, k, from, j);
        k += cone_may_meet_at(cn, from->vx[j], from->vy[j], from->vz[j], from->v2[j], from->dist[j], from->r[j]);
    }
    to->n = k;
    return 1;
}

static int farthest_first(const void *pa, const void *pb)
{
    const star_key *a = pa, *b = pb;
    if (a->len != b->len)
        return a->len > b->len ? -1 : 1;
    return (a->i > b->i) - (a->i < b->i);
}

/* tau_V of the stars k[0, n), farthest first, over their candidates c,
 * eight stars at a time (each lane a star; the last lanes of a short eight
 * repeat its last star), after each eight dropping the candidates beyond
 * the next star. */
static void star_lanes_group_tau(const orr_dust_set *s, const double eye[3], const float *x, const float *y,
                                 const float *z, const star_key *k, size_t n, candidates *c, double *tau)
{
    for (size_t q = 0; q < n; q += ORR_DUST_STAR_LANES) {
        orr_dust_star_lanes lanes;
        for (size_t l = 0; l < ORR_DUST_STAR_LANES; l++) {
            double p[3];
            orr_dust_segment g = {.len = 0};
            star_point(x, y, z, k[q + l < n ? q + l : n - 1].i, p);
            orr_dust_star_segment(&g, eye, p); /* (always a segment: tau_many groups only such stars) */
            for (int a = 0; a < 3; a++)
                lanes.d[a][l] = g.d[a];
            lanes.len[l] = g.len;
        }
        const orr_dust_candidate_view view = {c->n, c->vx, c->vy, c->vz, c->v2, c->ih, c->kih2};
        double sums[ORR_DUST_STAR_LANES];
        orr_dust_star_lanes_tau(c->lanes, s, &view, &lanes, sums);
        for (size_t l = 0; l < ORR_DUST_STAR_LANES && q + l < n; l++)
            tau[k[q + l].i] = sums[l];
        if (q + ORR_DUST_STAR_LANES < n)
            drop_beyond(c, k[q + ORR_DUST_STAR_LANES].len);
    }
}

/* tau_V of the group k[0, n) over its candidates c (shared 0: memory ran
 * out, each star on its own walk: the same values), its stars farthest
 * first. */
static void group_tau(const orr_dust_set *s, const double eye[3], const float *x, const float *y, const float *z,
                      star_key *k, size_t n, candidates *c, int shared, double *tau)
{
    qsort(k, n, sizeof *k, farthest_first);
    if (shared && c->way == TERMS_EIGHT_STARS) {
        star_lanes_group_tau(s, eye, x, y, z, k, n, c, tau);
        return;
    }
    for (size_t q = 0; q < n; q++) {
        double p[3];
        star_point(x, y, z, k[q].i, p);
        if (!shared) {
            tau[k[q].i] = orr_dust_tau(s, eye, p);
            continue;
        }
        orr_dust_segment g;
        double sum = 0;
        if (orr_dust_star_segment(&g, eye, p)) /* (always: tau_many groups only such stars) */
            sum = star_tau(s, c, &g);
        tau[k[q].i] = sum;
        if (q % 4 == 0 && q + 1 < n) /* every fourth star: the copies cost as much as the tests they save */
            drop_beyond(c, k[q + 1].len);
    }
}

/* The work of one thread: the candidates of a super-group and of its
 * group. */
typedef struct walker {
    candidates super, group;
} walker;

/* tau_V of a super-group's stars, its groups' starts [first, last) of
 * starts: one traversal of the tree for the super-group, each group
 * picking its candidates from it (a super-group of one group walks the tree
 * for itself). */
static void super_group_tau(const orr_dust_set *s, const double eye[3], const float *x, const float *y,
                            const float *z, star_key *keys, const uint32_t *starts, size_t first, size_t last,
                            walker *w, double *tau)
{
    cone cn;
    star_key *k = keys + starts[first];
    group_cone(&cn, eye, x, y, z, k, starts[last] - starts[first]);
    if (last - first == 1) {
        const int shared = gather(s, &cn, &w->group);
        group_tau(s, eye, x, y, z, k, starts[last] - starts[first], &w->group, shared, tau);
        return;
    }
    const int shared = gather(s, &cn, &w->super);
    for (size_t g = first; g < last; g++) {
        const size_t n = starts[g + 1] - starts[g];
        k = keys + starts[g];
        group_cone(&cn, eye, x, y, z, k, n);
        group_tau(s, eye, x, y, z, k, n, &w->group, shared && pick_candidates(&w->super, &cn, &w->group), tau);
    }
}

/* How this CPU sums the terms, asked for `terms`: eight stars at a time
 * in the lanes way asked for (BEST: the fastest this CPU runs), where the
 * CPU runs it, else one star and one term at a time. */
static void choose_terms_way(orr_dust_terms terms, candidates *c)
{
    c->lanes = terms == ORR_DUST_TERMS_BEST ? orr_dust_star_lanes_best() : ORR_DUST_LANES_AVX2;
    c->way = terms != ORR_DUST_TERMS_PLAIN && c->lanes != ORR_DUST_LANES_PLAIN && orr_dust_star_lanes_runs(c->lanes)
                 ? TERMS_EIGHT_STARS
                 : TERMS_ONE;
}

/* The wanted stars with a column, keyed by direction (tau of the others
 * set to 0, as orr_dust_tau gives them), into keys[0, *m) sorted by key,
 * then index: the keys made in parallel in the stars' order, then a stable
 * radix sort (they were made and sorted by qsort on one thread, about 1 %
 * of the 8K dome master's CPU samples, all of it serial). 0 if out of
 * memory. */
static int sorted_keys(const orr_dust_set *s, const double eye[3], size_t n, const float *x, const float *y,
                       const float *z, const unsigned char *want, double *tau, star_key *keys, size_t *m,
                       orr_error *err)
{
    orr_radix_item *items = orr_malloc((n ? 2 * n : 1) * sizeof *items, "dust star groups", err);
    double *len = items ? orr_malloc((n ? n : 1) * sizeof *len, "dust star groups", err) : NULL;
    if (!len) {
        free(items);
        return 0;
    }
#pragma omp parallel for schedule(static)
    for (long i = 0; i < (long)n; i++) {
        double p[3];
        orr_dust_segment g;
        star_point(x, y, z, (uint32_t)i, p);
        tau[i] = 0; /* not wanted, at the eye, or not finite: no column (as orr_dust_tau) */
        items[i] = (orr_radix_item){NO_KEY, (size_t)i};
        if ((!want || want[i]) && s->nnodes && orr_dust_star_segment(&g, eye, p)) {
            items[i].key = direction_key(g.d);
            len[i] = g.len;
        }
    }
    size_t kept = 0;
    for (size_t i = 0; i < n; i++)
        if (items[i].key != NO_KEY)
            items[kept++] = items[i];
    const orr_radix_item *sorted = orr_radix_sort(items, items + n, kept);
    for (size_t q = 0; q < kept; q++)
        keys[q] = (star_key){sorted[q].key, (uint32_t)sorted[q].index, len[sorted[q].index]};
    *m = kept;
    free(items);
    free(len);
    return 1;
}

orr_status orr_dust_tau_many(const orr_dust_set *s, const double eye[3], size_t n, const float *x, const float *y,
                             const float *z, const unsigned char *want, double *tau, orr_error *err)
{
    return orr_dust_tau_many_with(ORR_DUST_TERMS_BEST, s, eye, n, x, y, z, want, tau, err);
}

orr_status orr_dust_tau_many_with(orr_dust_terms terms, const orr_dust_set *s, const double eye[3], size_t n,
                                  const float *x, const float *y, const float *z, const unsigned char *want,
                                  double *tau, orr_error *err)
{
    if (n > UINT32_MAX - 1)
        return orr_fail(err, ORR_ERR_USAGE, "%zu stars at once: at most %u", n, UINT32_MAX - 1);
    star_key *keys = orr_malloc((n ? n : 1) * sizeof *keys, "dust star groups", err);
    size_t m;
    if (!keys || !sorted_keys(s, eye, n, x, y, z, want, tau, keys, &m, err)) {
        free(keys);
        return ORR_ERR_NOMEM;
    }
    uint32_t *starts = orr_malloc((n + 1) * sizeof *starts, "dust star groups", err);
    uint32_t *supers = starts ? orr_malloc((n + 1) * sizeof *supers, "dust star groups", err) : NULL;
    int *levels = supers ? orr_malloc((n + 1) * sizeof *levels, "dust star groups", err) : NULL;
    if (!levels) {
        free(keys);
        free(starts);
        free(supers);
        return ORR_ERR_NOMEM;
    }
    /* super-groups, then each one's groups: supers[q] becomes the index in
     * starts of super-group q's first group */
    const size_t ns = m ? split_groups(keys, 0, m, -1, SUPER_MAX, supers, levels, 0) : 0;
    supers[ns] = (uint32_t)m;
    size_t ng = 0;
    for (size_t q = 0; q < ns; q++) {
        const uint32_t lo = supers[q];
        supers[q] = (uint32_t)ng;
        ng = split_groups(keys, lo, supers[q + 1], levels[q], GROUP_MAX, starts, NULL, ng);
    }
    supers[ns] = (uint32_t)ng;
    starts[ng] = (uint32_t)m;
#pragma omp parallel
    {
        walker w = {{0}, {0}};
        choose_terms_way(terms, &w.group);
#pragma omp for schedule(dynamic, 1)
        for (long q = 0; q < (long)ns; q++)
            super_group_tau(s, eye, x, y, z, keys, starts, supers[q], supers[q + 1], &w, tau);
        candidates_free(&w.super);
        candidates_free(&w.group);
    }
    free(keys);
    free(starts);
    free(supers);
    free(levels);
    return ORR_OK;
}
