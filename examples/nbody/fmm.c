/* A fast multipole method over the quadrupole tree: fmm.h says what and
 * whose. Multi-indices k = (kx, ky, kz) of order |k| <= 5 are numbered by
 * order, then kx, then ky, both descending: 0 is (0,0,0), 1-3 order one,
 * 4-9 order two, 10-19 three; the expansions keep orders up to three (20
 * coefficients), the quadrupoles acting on them need derivatives up to
 * five (56). */
#include "fmm.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define FMM_NLOCAL 20    /* coefficients up to order 3 */
#define FMM_NDERIV 56    /* up to order 5 */
#define FMM_DIRECT 64    /* two nodes of at most this many particle pairs are summed directly */

/* The index tables, made once a call (cheap): what the recurrence, the
 * cell-cell terms, the shifts and the evaluation at a particle read. */
typedef struct fmm_tables {
    int k[FMM_NDERIV][3];
    int order[FMM_NDERIV];
    int index[6][6][6];
    /* recurrence: a_k from a_{k - e_i} (down1) and a_{k - 2 e_i} (down2); -1 where k_i too small */
    int down1[FMM_NDERIV][3], down2[FMM_NDERIV][3];
    /* cell-cell: the quadrupole q (one of 4..9) on coefficient p reads a_{p+q} times binom(p+q, q) */
    int up_q[FMM_NLOCAL][6];
    double binom_q[FMM_NLOCAL][6];
    /* shift: L'_p = sum over q >= p of binom(q, p) L_q d^(q - p) */
    int nshift[FMM_NLOCAL];
    int shift_q[FMM_NLOCAL][FMM_NLOCAL], shift_m[FMM_NLOCAL][FMM_NLOCAL];
    double shift_c[FMM_NLOCAL][FMM_NLOCAL];
} fmm_tables;

static double binom(int n, int k)
{
    double b = 1;
    for (int i = 1; i <= k; i++)
        b = b * (double)(n - k + i) / (double)i;
    return b;
}

static void make_tables(fmm_tables *tb)
{
    memset(tb->index, -1, sizeof tb->index);
    int id = 0;
    for (int n = 0; n <= 5; n++)
        for (int a = n; a >= 0; a--)
            for (int b = n - a; b >= 0; b--) {
                int c = n - a - b;
                tb->k[id][0] = a;
                tb->k[id][1] = b;
                tb->k[id][2] = c;
                tb->order[id] = n;
                tb->index[a][b][c] = id++;
            }
    for (int i = 0; i < FMM_NDERIV; i++)
        for (int d = 0; d < 3; d++) {
            int k1[3] = {tb->k[i][0], tb->k[i][1], tb->k[i][2]}, k2[3];
            memcpy(k2, k1, sizeof k2);
            k1[d] -= 1;
            k2[d] -= 2;
            tb->down1[i][d] = k1[d] >= 0 ? tb->index[k1[0]][k1[1]][k1[2]] : -1;
            tb->down2[i][d] = k2[d] >= 0 ? tb->index[k2[0]][k2[1]][k2[2]] : -1;
        }
    for (int p = 0; p < FMM_NLOCAL; p++) {
        for (int j = 0; j < 6; j++) {
            int q = 4 + j, s[3];
            double c = 1;
            for (int d = 0; d < 3; d++) {
                s[d] = tb->k[p][d] + tb->k[q][d];
                c *= binom(s[d], tb->k[q][d]);
            }
            tb->up_q[p][j] = tb->index[s[0]][s[1]][s[2]];
            tb->binom_q[p][j] = c;
        }
        tb->nshift[p] = 0;
        for (int q = 0; q < FMM_NLOCAL; q++) {
            int m[3], ok = 1;
            double c = 1;
            for (int d = 0; d < 3; d++) {
                m[d] = tb->k[q][d] - tb->k[p][d];
                ok &= m[d] >= 0;
                if (m[d] >= 0)
                    c *= binom(tb->k[q][d], tb->k[p][d]);
            }
            if (!ok)
                continue;
            int s = tb->nshift[p]++;
            tb->shift_q[p][s] = q;
            tb->shift_m[p][s] = tb->index[m[0]][m[1]][m[2]];
            tb->shift_c[p][s] = c;
        }
    }
}

/* The Taylor coefficients a_k = D^k g / k! of g(x) = (|x|^2 + e2)^(-1/2) at
 * x = R, |k| <= 5 (Lindsay & Krasny's recurrence, in this sign convention:
 * |k| u a_k = -(2|k| - 1) sum_i R_i a_{k - e_i} - (|k| - 1) sum_i a_{k - 2 e_i},
 * u = |R|^2 + e2; checked against g(R + h e_x) = 1 / (R + h) at e2 = 0), and
 * their derivatives b_k by e2 (the same recurrence differentiated by u at
 * fixed R: |k| u b_k = -|k| a_k - (2|k| - 1) sum_i R_i b_{k - e_i}
 * - (|k| - 1) sum_i b_{k - 2 e_i}). */
static void derivatives(const fmm_tables *tb, const double R[3], double e2, double a[FMM_NDERIV],
                        double b[FMM_NDERIV])
{
    const double u = R[0] * R[0] + R[1] * R[1] + R[2] * R[2] + e2, inv_u = 1.0 / u;
    a[0] = 1.0 / sqrt(u);
    b[0] = -0.5 * a[0] * inv_u;
    for (int i = 1; i < FMM_NDERIV; i++) {
        const int n = tb->order[i];
        double s1 = 0, s2 = 0, t1 = 0, t2 = 0;
        for (int d = 0; d < 3; d++) {
            if (tb->down1[i][d] >= 0) {
                s1 += R[d] * a[tb->down1[i][d]];
                t1 += R[d] * b[tb->down1[i][d]];
            }
            if (tb->down2[i][d] >= 0) {
                s2 += a[tb->down2[i][d]];
                t2 += b[tb->down2[i][d]];
            }
        }
        a[i] = -((2 * n - 1) * s1 + (n - 1) * s2) * inv_u / n;
        b[i] = -(n * a[i] + (2 * n - 1) * t1 + (n - 1) * t2) * inv_u / n;
    }
}

/* The monomials r^m, |m| <= 3. */
static void monomials(const fmm_tables *tb, const double r[3], double m[FMM_NLOCAL])
{
    m[0] = 1;
    for (int i = 1; i < FMM_NLOCAL; i++) {
        int d = tb->k[i][0] ? 0 : tb->k[i][1] ? 1 : 2;
        m[i] = m[tb->down1[i][d]] * r[d];
    }
}

typedef struct fmm_run {
    const qt_tree *t;
    fmm_tables tb;
    double theta2;
    /* per node: the potential's Taylor coefficients about its centre of
     * mass, for a particle of softening^2 e2: local[p] + local[FMM_NLOCAL + p] e2
     * (the pair rule makes the pull of every cell depend on the target's own
     * softening, to first order: a cell of halo and disc particles) */
    double (*local)[2 * FMM_NLOCAL];
    double *ax, *ay, *az, *phi;  /* per particle in tree order: the direct sums */
    double (*second)[6];         /* per node: its second moments (quad / 3, traceless) in multi-index order */
    fmm_counts counts;
} fmm_run;

/* Adds to expansion l (of a node of mean softening^2 e2_sink) the pull of a
 * source of mass m and second moments sq, from its derivatives a and b
 * (by e2) at the pair's mean softening^2, negated for odd orders when flip
 * (the source on the other side: a_k(-R) = (-1)^|k| a_k(R)). */
static void add_source(const fmm_tables *tb, double m, const double sq[6], const double *a, const double *b,
                       double e2_sink, int flip, double *l)
{
    for (int p = 0; p < FMM_NLOCAL; p++) {
        double term = m * a[p], term_e2 = m * b[p]; /* the potential's, and its derivative by e2 */
        for (int j = 0; j < 6; j++) {
            const int up = tb->up_q[p][j];
            const double c = tb->binom_q[p][j] * sq[j];
            term += c * a[up];
            term_e2 += c * b[up];
        }
        if (flip && (tb->order[p] & 1)) {
            term = -term;
            term_e2 = -term_e2;
        }
        /* a target of softening^2 e2 pairs at (e2 + e2_source) / 2, the
         * derivatives' e2 plus (e2 - e2_sink) / 2 */
        l[p] += -term + 0.5 * e2_sink * term_e2;
        l[FMM_NLOCAL + p] += -0.5 * term_e2;
    }
}

/* Cells A and B on each other through their expansions: the potential of
 * B's monopole and quadrupole about A's centre, and A's about B's, from the
 * same derivatives. */
static void cell_cell(fmm_run *run, int A, int B)
{
    const qt_node *na = &run->t->nodes[A], *nb = &run->t->nodes[B];
    const fmm_tables *tb = &run->tb;
    double R[3] = {na->com[0] - nb->com[0], na->com[1] - nb->com[1], na->com[2] - nb->com[2]};
    double a[FMM_NDERIV], b[FMM_NDERIV];
    derivatives(tb, R, 0.5 * (na->eps2 + nb->eps2), a, b);
    add_source(tb, nb->mass, run->second[B], a, b, na->eps2, 0, run->local[A]);
    add_source(tb, na->mass, run->second[A], a, b, nb->eps2, 1, run->local[B]);
    run->counts.cell_cell += 1;
}

/* Particles j and k on each other, softened by their mean eps^2. */
static inline void pair(fmm_run *run, size_t j, size_t k)
{
    const qt_tree *t = run->t;
    const double dx = t->px[j] - t->px[k], dy = t->py[j] - t->py[k], dz = t->pz[j] - t->pz[k];
    const double u = dx * dx + dy * dy + dz * dz + 0.5 * (t->pe2[j] + t->pe2[k]);
    const double inv = 1.0 / sqrt(u), inv3 = inv * inv * inv;
    const double fj = t->pm[k] * inv3, fk = t->pm[j] * inv3;
    run->ax[j] -= fj * dx;
    run->ay[j] -= fj * dy;
    run->az[j] -= fj * dz;
    run->ax[k] += fk * dx;
    run->ay[k] += fk * dy;
    run->az[k] += fk * dz;
    run->phi[j] -= t->pm[k] * inv;
    run->phi[k] -= t->pm[j] * inv;
}

static void direct(fmm_run *run, const qt_node *na, const qt_node *nb)
{
    for (size_t j = na->first; j < na->first + na->count; j++)
        for (size_t k = nb->first; k < nb->first + nb->count; k++)
            pair(run, j, k);
    run->counts.pair += (double)na->count * (double)nb->count;
}

static void direct_self(fmm_run *run, const qt_node *na)
{
    for (size_t j = na->first; j < na->first + na->count; j++)
        for (size_t k = j + 1; k < na->first + na->count; k++)
            pair(run, j, k);
    run->counts.pair += 0.5 * (double)na->count * (double)(na->count - 1);
}

/* Two distinct nodes on each other (Dehnen's mutual walk): through their
 * expansions when far enough apart, directly when small or both leaves,
 * or else the larger split. */
static void interact(fmm_run *run, int A, int B)
{
    const qt_node *na = &run->t->nodes[A], *nb = &run->t->nodes[B];
    const double d[3] = {na->com[0] - nb->com[0], na->com[1] - nb->com[1], na->com[2] - nb->com[2]};
    const double reach = na->bmax + nb->bmax;
    if (reach * reach < run->theta2 * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2])) {
        cell_cell(run, A, B);
        return;
    }
    const int leaf_a = qt_is_leaf(na), leaf_b = qt_is_leaf(nb);
    if ((leaf_a && leaf_b) || (double)na->count * (double)nb->count <= FMM_DIRECT) {
        direct(run, na, nb);
        return;
    }
    if (!leaf_a && (leaf_b || na->bmax >= nb->bmax)) {
        for (int c = 0; c < 8; c++)
            if (na->child[c] >= 0)
                interact(run, na->child[c], B);
    } else {
        for (int c = 0; c < 8; c++)
            if (nb->child[c] >= 0)
                interact(run, A, nb->child[c]);
    }
}

/* A node's particles on each other. */
static void interact_self(fmm_run *run, int A)
{
    const qt_node *na = &run->t->nodes[A];
    if (qt_is_leaf(na) || 0.5 * (double)na->count * (double)na->count <= FMM_DIRECT) {
        direct_self(run, na);
        return;
    }
    for (int c = 0; c < 8; c++) {
        if (na->child[c] < 0)
            continue;
        interact_self(run, na->child[c]);
        for (int e = c + 1; e < 8; e++)
            if (na->child[e] >= 0)
                interact(run, na->child[c], na->child[e]);
    }
}

/* Each node's expansion passed to its children, shifted to their centres;
 * at the leaves evaluated at each particle and added to its direct sums. */
static void pass_down(fmm_run *run, double G, double *acc, double *pot)
{
    const qt_tree *t = run->t;
    const fmm_tables *tb = &run->tb;
    for (size_t id = 0; id < t->nnodes; id++) { /* depth-first: a parent before its children */
        const qt_node *nd = &t->nodes[id];
        const double *l = run->local[id];
        for (int c = 0; c < 8; c++) {
            if (nd->child[c] < 0)
                continue;
            const qt_node *ch = &t->nodes[nd->child[c]];
            const double d[3] = {ch->com[0] - nd->com[0], ch->com[1] - nd->com[1], ch->com[2] - nd->com[2]};
            double m[FMM_NLOCAL];
            monomials(tb, d, m);
            double *lc = run->local[nd->child[c]];
            for (int h = 0; h < 2 * FMM_NLOCAL; h += FMM_NLOCAL)
                for (int p = 0; p < FMM_NLOCAL; p++) {
                    double s = 0;
                    for (int k = 0; k < tb->nshift[p]; k++)
                        s += tb->shift_c[p][k] * l[h + tb->shift_q[p][k]] * m[tb->shift_m[p][k]];
                    lc[h + p] += s;
                }
        }
        if (!qt_is_leaf(nd))
            continue;
        for (size_t j = nd->first; j < nd->first + nd->count; j++) {
            const double r[3] = {t->px[j] - nd->com[0], t->py[j] - nd->com[1], t->pz[j] - nd->com[2]};
            double m[FMM_NLOCAL], phi = 0, g[3] = {0, 0, 0};
            monomials(tb, r, m);
            for (int p = 0; p < FMM_NLOCAL; p++) {
                const double lp = l[p] + l[FMM_NLOCAL + p] * t->pe2[j];
                phi += lp * m[p];
                for (int k = 0; k < 3; k++)
                    if (tb->down1[p][k] >= 0) /* d/dx_k of r^p is p_k r^(p - e_k) */
                        g[k] += lp * tb->k[p][k] * m[tb->down1[p][k]];
            }
            const size_t o = t->order[j];
            acc[3 * o] = G * (run->ax[j] - g[0]);
            acc[3 * o + 1] = G * (run->ay[j] - g[1]);
            acc[3 * o + 2] = G * (run->az[j] - g[2]);
            if (pot)
                pot[o] = G * (run->phi[j] + phi);
        }
    }
}

int fmm_accelerations(const qt_tree *t, double G, double theta, double *acc, double *pot, fmm_counts *counts)
{
    fmm_run run = {.t = t, .theta2 = theta * theta};
    make_tables(&run.tb);
    run.local = calloc(t->nnodes, sizeof *run.local);
    run.second = malloc(t->nnodes * sizeof *run.second);
    run.ax = calloc(4 * t->n, sizeof *run.ax);
    if (!run.local || !run.second || !run.ax) {
        free(run.local);
        free(run.second);
        free(run.ax);
        return -1;
    }
    run.ay = run.ax + t->n;
    run.az = run.ay + t->n;
    run.phi = run.az + t->n;
    /* indices 4..9 are xx xy xz yy yz zz; the tree keeps xx yy zz xy xz yz */
    static const int from_quad[6] = {0, 3, 4, 1, 5, 2};
    for (size_t id = 0; id < t->nnodes; id++)
        for (int j = 0; j < 6; j++)
            run.second[id][j] = t->nodes[id].quad[from_quad[j]] / 3.0;
    if (t->nnodes > 0) {
        interact_self(&run, 0);
        pass_down(&run, G, acc, pot);
    }
    *counts = run.counts;
    free(run.local);
    free(run.second);
    free(run.ax);
    return 0;
}
