#include "dust/column.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dust/column_walk.h"

#define SUPPORT ORR_DUST_SUPPORT
#define LEAF_MAX 8    /* particles per leaf of the tree */
#define STACK_MAX 128 /* the tree's depth is about log2(n / LEAF_MAX) + 1 */

/* 8-point Gauss-Legendre nodes and weights on [-1, 1]
 * (Abramowitz & Stegun, Table 25.4). */
static const double GL_X[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267, 0.9602898564975363};
static const double GL_W[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};

/* sigma w(sqrt(beta^2 + t^2)), the kernel along a line at impact beta. */
static double along(const orr_kernel *k, double beta, double t)
{
    return k->sigma * orr_kernel_shape(k, sqrt(beta * beta + t * t));
}

/* Integral of along() over [a, b] by 8-point Gauss-Legendre. */
static double gl_along(const orr_kernel *k, double beta, double a, double b)
{
    const double mid = 0.5 * (a + b), half = 0.5 * (b - a);
    double s = 0;
    for (int i = 0; i < 4; i++)
        s += GL_W[i] * (along(k, beta, mid - half * GL_X[i]) + along(k, beta, mid + half * GL_X[i]));
    return s * half;
}

/* I(beta, s) = integral of along() over [0, s] for s = 2 j / NS, each cell
 * split where the line crosses q = 1 (the cubic spline's joint). */
static void fill_row(const orr_kernel *k, double beta, float *row)
{
    const double joint = beta < 1.0 ? sqrt(1.0 - beta * beta) : -1.0;
    double sum = 0;
    row[0] = 0;
    for (int j = 1; j <= ORR_DUST_PCOL_NS; j++) {
        double a = SUPPORT * (j - 1) / ORR_DUST_PCOL_NS, b = SUPPORT * j / ORR_DUST_PCOL_NS;
        if (joint > a && joint < b)
            sum += gl_along(k, beta, a, joint) + gl_along(k, beta, joint, b);
        else
            sum += gl_along(k, beta, a, b);
        row[j] = (float)sum;
    }
}

orr_status orr_dust_set_init(orr_dust_set *s, orr_kernel_kind kernel, orr_error *err)
{
    memset(s, 0, sizeof *s);
    s->kernel_kind = kernel;
    orr_status st = orr_kernel_init(&s->kernel, kernel, err);
    if (st)
        return st;
    s->kernel_ready = 1;
    s->sigma = s->kernel.sigma;
    const size_t rows = ORR_DUST_PCOL_NB + 1, cols = ORR_DUST_PCOL_NS + 1;
    s->pcol = orr_malloc(rows * cols * sizeof *s->pcol, "dust column table", err);
    s->fcol = s->pcol ? orr_malloc((ORR_DUST_FCOL_NU + 1) * sizeof *s->fcol, "dust column table", err) : NULL;
    float *row = s->fcol ? orr_malloc(cols * sizeof *row, "dust column table", err) : NULL;
    if (!row) {
        orr_dust_set_free(s);
        return ORR_ERR_NOMEM;
    }
    for (size_t i = 0; i < rows; i++)
        fill_row(&s->kernel, SUPPORT * (double)i / ORR_DUST_PCOL_NB, s->pcol + i * cols);
    for (int i = 0; i <= ORR_DUST_FCOL_NU; i++) {
        fill_row(&s->kernel, sqrt(SUPPORT * SUPPORT * i / ORR_DUST_FCOL_NU), row);
        s->fcol[i] = 2.0f * row[cols - 1];
    }
    free(row);
    return ORR_OK;
}

void orr_dust_set_free(orr_dust_set *s)
{
    free(s->x);
    free(s->y);
    free(s->z);
    free(s->h);
    free(s->k);
    free(s->ih);
    free(s->kih2);
    free(s->pcol);
    free(s->fcol);
    free(s->nodes);
    if (s->kernel_ready)
        orr_kernel_free(&s->kernel);
    memset(s, 0, sizeof *s);
}

static orr_status grow(orr_dust_set *s, orr_error *err)
{
    size_t cap = s->cap ? 2 * s->cap : 4096;
    float **arrays[5] = {&s->x, &s->y, &s->z, &s->h, &s->k};
    for (int a = 0; a < 5; a++) {
        float *p = realloc(*arrays[a], cap * sizeof *p);
        if (!p)
            return orr_fail(err, ORR_ERR_NOMEM, "out of memory for %zu dust particles", cap);
        *arrays[a] = p;
    }
    s->cap = cap;
    return ORR_OK;
}

orr_status orr_dust_set_add(orr_dust_set *s, float x, float y, float z, float h, float k, orr_error *err)
{
    if (s->n == s->cap) {
        orr_status st = grow(s, err);
        if (st)
            return st;
    }
    s->x[s->n] = x;
    s->y[s->n] = y;
    s->z[s->n] = z;
    s->h[s->n] = h;
    s->k[s->n] = k;
    s->n++;
    return ORR_OK;
}

/* ---- the table ---- */

double orr_dust_partial_column(const orr_dust_set *s, double beta, double sv)
{
    if (!(beta < SUPPORT))
        return 0;
    return orr_dust_pcol(s, fabs(beta), sv);
}

/* ---- the tree ---- */

typedef struct build_ctx {
    orr_dust_set *s;
    uint32_t *idx;
    size_t next; /* next free node */
} build_ctx;

static float centre(const orr_dust_set *s, uint32_t i, int axis)
{
    return axis == 0 ? s->x[i] : axis == 1 ? s->y[i] : s->z[i];
}

/* Partially orders idx[lo, hi) so that idx[mid] has the median key on the
 * axis, no larger keys before it and no smaller after (quickselect with a
 * three-way partition, so equal keys cannot make it quadratic). */
static void select_median(const orr_dust_set *s, uint32_t *idx, size_t lo, size_t hi, size_t mid, int axis)
{
    while (hi - lo > 1) {
        const float pivot = centre(s, idx[lo + (hi - lo) / 2], axis);
        size_t lt = lo, i = lo, gt = hi; /* [lo, lt) < pivot, [lt, i) == pivot, [gt, hi) > pivot */
        while (i < gt) {
            float c = centre(s, idx[i], axis);
            uint32_t t = idx[i];
            if (c < pivot) {
                idx[i++] = idx[lt];
                idx[lt++] = t;
            } else if (c > pivot) {
                idx[i] = idx[--gt];
                idx[gt] = t;
            } else {
                i++;
            }
        }
        if (mid < lt)
            hi = lt;
        else if (mid >= gt)
            lo = gt;
        else
            return;
    }
}

static void node_bounds(const orr_dust_set *s, const uint32_t *idx, size_t lo, size_t hi, orr_dust_node *nd)
{
    for (int a = 0; a < 3; a++) {
        nd->lo[a] = INFINITY;
        nd->hi[a] = -INFINITY;
    }
    for (size_t q = lo; q < hi; q++) {
        uint32_t i = idx[q];
        float r = (float)SUPPORT * s->h[i];
        for (int a = 0; a < 3; a++) {
            /* widened by far more than float rounding, so that the box
             * surely holds the support the walk's double arithmetic sees */
            float c = centre(s, i, a), slack = 1e-6f * (fabsf(c) + r);
            nd->lo[a] = fminf(nd->lo[a], c - r - slack);
            nd->hi[a] = fmaxf(nd->hi[a], c + r + slack);
        }
    }
}

static void build_node(build_ctx *b, size_t node, size_t lo, size_t hi)
{
    orr_dust_node *nd = &b->s->nodes[node];
    node_bounds(b->s, b->idx, lo, hi, nd);
    if (hi - lo <= LEAF_MAX) {
        nd->first = (uint32_t)lo;
        nd->count = (uint32_t)(hi - lo);
        return;
    }
    /* Split at the median of the centres along the box's longest side. */
    int axis = 0;
    for (int a = 1; a < 3; a++)
        if (nd->hi[a] - nd->lo[a] > nd->hi[axis] - nd->lo[axis])
            axis = a;
    size_t mid = lo + (hi - lo) / 2;
    select_median(b->s, b->idx, lo, hi, mid, axis);
    size_t left = b->next;
    b->next += 2;
    nd->first = (uint32_t)left;
    nd->count = 0;
    build_node(b, left, lo, mid);
    build_node(b, left + 1, mid, hi);
}

/* Puts the particle arrays in the tree's order. */
static orr_status reorder(orr_dust_set *s, const uint32_t *idx, orr_error *err)
{
    float *tmp = orr_malloc((s->n ? s->n : 1) * sizeof *tmp, "dust tree", err);
    if (!tmp)
        return ORR_ERR_NOMEM;
    float *arrays[5] = {s->x, s->y, s->z, s->h, s->k};
    for (int a = 0; a < 5; a++) {
        for (size_t q = 0; q < s->n; q++)
            tmp[q] = arrays[a][idx[q]];
        memcpy(arrays[a], tmp, s->n * sizeof *tmp);
    }
    free(tmp);
    return ORR_OK;
}

orr_status orr_dust_set_build(orr_dust_set *s, orr_error *err)
{
    if (s->n > UINT32_MAX / 2)
        return orr_fail(err, ORR_ERR_USAGE, "%zu dust particles: at most %u", s->n, UINT32_MAX / 2);
    free(s->nodes);
    s->nodes = NULL;
    s->nnodes = 0;
    if (s->n == 0)
        return ORR_OK;
    size_t maxnodes = 2 * (s->n / (LEAF_MAX / 2) + 1);
    uint32_t *idx = orr_malloc(s->n * sizeof *idx, "dust tree", err);
    s->nodes = idx ? orr_malloc(maxnodes * sizeof *s->nodes, "dust tree", err) : NULL;
    if (!s->nodes) {
        free(idx);
        return ORR_ERR_NOMEM;
    }
    for (size_t i = 0; i < s->n; i++)
        idx[i] = (uint32_t)i;
    build_ctx b = {s, idx, 1};
    build_node(&b, 0, 0, s->n);
    s->nnodes = b.next;
    orr_status st = reorder(s, idx, err);
    free(idx);
    free(s->ih);
    free(s->kih2);
    s->ih = st ? NULL : orr_malloc(s->n * sizeof *s->ih, "dust tree", err);
    s->kih2 = s->ih ? orr_malloc(s->n * sizeof *s->kih2, "dust tree", err) : NULL;
    if (!st && !s->kih2)
        return ORR_ERR_NOMEM;
    for (size_t i = 0; i < s->n && !st; i++) {
        s->ih[i] = 1.0f / s->h[i];
        s->kih2[i] = (float)((double)s->k[i] / ((double)s->h[i] * s->h[i]));
    }
    return st;
}

/* ---- walking the tree ---- */

/* Whether the segment meets the box. */
static inline int meets_box(const orr_dust_segment *g, const orr_dust_node *nd)
{
    double t0 = 0, t1 = g->len;
    for (int a = 0; a < 3; a++) {
        double ta = (nd->lo[a] - g->o[a]) * g->inv[a], tb = (nd->hi[a] - g->o[a]) * g->inv[a];
        if (ta > tb) {
            double t = ta;
            ta = tb;
            tb = t;
        }
        t0 = ta > t0 ? ta : t0;
        t1 = tb < t1 ? tb : t1;
        if (t0 > t1)
            return 0;
    }
    return 1;
}

static double walk(const orr_dust_set *s, const orr_dust_segment *g)
{
    if (!s->nnodes)
        return 0;
    uint32_t stack[STACK_MAX];
    int top = 0;
    stack[top++] = 0;
    double tau = 0;
    while (top > 0) {
        const orr_dust_node *nd = &s->nodes[stack[--top]];
        if (!meets_box(g, nd))
            continue;
        if (nd->count) {
            for (uint32_t q = 0; q < nd->count; q++)
                tau += orr_dust_share(s, g, s->x[nd->first + q], s->y[nd->first + q], s->z[nd->first + q],
                                      s->ih[nd->first + q], s->kih2[nd->first + q]);
        } else if (top + 2 <= STACK_MAX) {
            /* Right pushed first: the left child is walked first. */
            stack[top++] = nd->first + 1;
            stack[top++] = nd->first;
        }
    }
    return tau;
}

double orr_dust_tau(const orr_dust_set *s, const double eye[3], const double p[3])
{
    orr_dust_segment g;
    if (!orr_dust_star_segment(&g, eye, p))
        return 0; /* the star at the eye: no column */
    return walk(s, &g);
}

double orr_dust_tau_ray(const orr_dust_set *s, const double eye[3], const double dir[3])
{
    orr_dust_segment g;
    if (!orr_dust_make_segment(&g, eye, dir, INFINITY))
        return 0;
    return walk(s, &g);
}

/* ---- brute force ---- */

/* Integral of the kernel (h = 1) along the line at impact beta over
 * t in [a, b], split at the closest point and at the joint q = 1, each
 * piece by 4 x 8-point Gauss-Legendre. */
static double exact_piecewise(const orr_kernel *k, double beta, double a, double b)
{
    double cuts[6] = {a, b, 0, 0, 0, 0};
    int n = 2;
    double j = beta < 1 ? sqrt(1 - beta * beta) : -1;
    double marks[3] = {0.0, -j, j};
    for (int m = 0; m < (j > 0 ? 3 : 1); m++)
        if (marks[m] > a && marks[m] < b)
            cuts[n++] = marks[m];
    /* sort the few cuts */
    for (int x = 1; x < n; x++)
        for (int y = x; y > 0 && cuts[y] < cuts[y - 1]; y--) {
            double t = cuts[y];
            cuts[y] = cuts[y - 1];
            cuts[y - 1] = t;
        }
    double sum = 0;
    for (int p = 0; p + 1 < n; p++) {
        double w = (cuts[p + 1] - cuts[p]) / 4;
        for (int q = 0; q < 4; q++)
            sum += gl_along(k, beta, cuts[p] + q * w, cuts[p] + (q + 1) * w);
    }
    return sum;
}

double orr_dust_tau_exact(const orr_dust_set *s, const double eye[3], const double p[3])
{
    double d[3] = {p[0] - eye[0], p[1] - eye[1], p[2] - eye[2]};
    const double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!(len > 0))
        return 0;
    for (int a = 0; a < 3; a++)
        d[a] /= len;
    double tau = 0;
    for (size_t i = 0; i < s->n; i++) {
        const double h = s->h[i];
        const double v[3] = {s->x[i] - eye[0], s->y[i] - eye[1], s->z[i] - eye[2]};
        const double tc = v[0] * d[0] + v[1] * d[1] + v[2] * d[2];
        /* the closest approach from the cross product, not |v|^2 - tc^2 */
        const double c[3] = {v[1] * d[2] - v[2] * d[1], v[2] * d[0] - v[0] * d[2], v[0] * d[1] - v[1] * d[0]};
        const double b = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) / h;
        if (b >= SUPPORT)
            continue;
        const double half = sqrt(SUPPORT * SUPPORT - b * b);
        const double a0 = fmax(-tc / h, -half), a1 = fmin((len - tc) / h, half);
        if (a1 > a0)
            tau += s->k[i] / (h * h) * exact_piecewise(&s->kernel, b, a0, a1);
    }
    return tau;
}
