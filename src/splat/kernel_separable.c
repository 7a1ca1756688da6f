/* The separable expansion of the column kernel F over the plane.
 *
 * F(x, y) = phi(x^2 + y^2) is even in x and in y, so as the kernel of an
 * integral operator on [-2, 2] it is symmetric and its eigenfunctions f_k
 * (orthonormal, even) give F(x, y) = sum_k lambda_k f_k(x) f_k(y). The
 * eigenvalues fall off fast (for the cubic spline |lambda_k / lambda_0| =
 * 1.4e-2, 1.0e-3, 7.7e-4, 4.3e-4, 5.7e-5, 3.7e-5, 2.2e-5, then 1.4e-5), so a
 * few terms hold F to about 1e-5 of its peak, and the integral of F over a
 * rectangle becomes a sum of products of one-dimensional integrals
 * E_k(x) = integral of f_k from 0 to x. That makes a kernel's pixel
 * weights an outer product: splat/sph.c draws mid-sized kernels with it.
 *
 * The eigenfunctions come from a Galerkin method on the cumulative table's
 * cells (piecewise constants on [0, 2] in n cells of width d; with the
 * even extension the operator is 2 integral over [0, 2], so the matrix is
 * (2 / d) times the cells' integrals of F), by subspace iteration; E_k at
 * the cell edges are then exact sums of the cells, and between them a
 * cubic Hermite interpolant whose slopes f_k come from the cell averages
 * by the fourth-order formula for a value at a cell edge. */
#include "splat/kernel_separable.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/vecmath.h"

/* Subspace iteration carries more vectors than it keeps, so the kept ones
 * converge at the rate |lambda_BLOCK / lambda_RANK| an iteration (about
 * 0.05 for these kernels). */
#define BLOCK (2 * ORR_KERNEL_SEP_RANK)
#define MAX_ITERATIONS 200
#define RESIDUAL_TOL 1e-11 /* of |lambda_0|, for every kept pair */

/* out = a v for the n x n matrix a and the n x BLOCK block v (row-major). */
static void multiply(const double *a, int n, const double *v, double *out)
{
    memset(out, 0, sizeof(double) * (size_t)n * BLOCK);
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            const double aij = a[(size_t)i * n + j];
            for (int c = 0; c < BLOCK; c++)
                out[(size_t)i * BLOCK + c] += aij * v[(size_t)j * BLOCK + c];
        }
}

/* Makes the columns of v orthonormal (modified Gram-Schmidt, twice: once
 * leaves round-off at the level of the columns' condition). */
static void orthonormalise(double *v, int n)
{
    for (int pass = 0; pass < 2; pass++)
        for (int c = 0; c < BLOCK; c++) {
            for (int b = 0; b < c; b++) {
                double dot = 0.0;
                for (int i = 0; i < n; i++)
                    dot += v[(size_t)i * BLOCK + b] * v[(size_t)i * BLOCK + c];
                for (int i = 0; i < n; i++)
                    v[(size_t)i * BLOCK + c] -= dot * v[(size_t)i * BLOCK + b];
            }
            double norm = 0.0;
            for (int i = 0; i < n; i++)
                norm += v[(size_t)i * BLOCK + c] * v[(size_t)i * BLOCK + c];
            norm = norm > 0.0 ? 1.0 / sqrt(norm) : 0.0;
            for (int i = 0; i < n; i++)
                v[(size_t)i * BLOCK + c] *= norm;
        }
}

/* Diagonalises the symmetric BLOCK x BLOCK matrix h in place by cyclic
 * Jacobi rotations; q receives the eigenvectors as columns. */
static void jacobi(double h[BLOCK][BLOCK], double q[BLOCK][BLOCK])
{
    for (int i = 0; i < BLOCK; i++)
        for (int j = 0; j < BLOCK; j++)
            q[i][j] = i == j;
    for (int sweep = 0; sweep < 100; sweep++) {
        double off = 0.0, diag = 0.0;
        for (int i = 0; i < BLOCK; i++)
            for (int j = 0; j < BLOCK; j++)
                *(i == j ? &diag : &off) += h[i][j] * h[i][j];
        if (off <= 1e-30 * diag)
            return;
        for (int p = 0; p < BLOCK; p++)
            for (int r = p + 1; r < BLOCK; r++) {
                if (h[p][r] == 0.0)
                    continue;
                /* The rotation by angle a with tan 2a = 2 h_pr / (h_rr - h_pp)
                 * zeroes h_pr; t = tan a, the smaller root. */
                const double theta = (h[r][r] - h[p][p]) / (2.0 * h[p][r]);
                const double t = (theta >= 0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
                const double c = 1.0 / sqrt(t * t + 1.0), s = t * c;
                for (int k = 0; k < BLOCK; k++) { /* columns p, r */
                    const double hp = h[k][p], hr = h[k][r];
                    h[k][p] = c * hp - s * hr;
                    h[k][r] = s * hp + c * hr;
                }
                for (int k = 0; k < BLOCK; k++) { /* rows p, r */
                    const double hp = h[p][k], hr = h[r][k];
                    h[p][k] = c * hp - s * hr;
                    h[r][k] = s * hp + c * hr;
                }
                for (int k = 0; k < BLOCK; k++) {
                    const double qp = q[k][p], qr = q[k][r];
                    q[k][p] = c * qp - s * qr;
                    q[k][r] = s * qp + c * qr;
                }
            }
    }
}

/* Rayleigh-Ritz on the orthonormal block v: rotates v into the Ritz
 * vectors, sorted by |lambda| (largest first), and returns the largest
 * residual |a v_k - lambda_k v_k| of the first ORR_KERNEL_SEP_RANK, over
 * |lambda_0|. av is scratch. */
static double ritz(const double *a, int n, double *v, double *av, double *lambda)
{
    double h[BLOCK][BLOCK], q[BLOCK][BLOCK];
    multiply(a, n, v, av);
    for (int b = 0; b < BLOCK; b++)
        for (int c = 0; c < BLOCK; c++) {
            double s = 0.0;
            for (int i = 0; i < n; i++)
                s += v[(size_t)i * BLOCK + b] * av[(size_t)i * BLOCK + c];
            h[b][c] = s;
        }
    for (int b = 0; b < BLOCK; b++) /* exactly symmetric */
        for (int c = 0; c < b; c++)
            h[b][c] = h[c][b] = 0.5 * (h[b][c] + h[c][b]);
    jacobi(h, q);
    int order[BLOCK];
    for (int b = 0; b < BLOCK; b++)
        order[b] = b;
    for (int b = 1; b < BLOCK; b++) /* insertion sort by |lambda| */
        for (int c = b; c > 0 && fabs(h[order[c]][order[c]]) > fabs(h[order[c - 1]][order[c - 1]]); c--) {
            const int t = order[c];
            order[c] = order[c - 1];
            order[c - 1] = t;
        }
    double row[BLOCK], arow[BLOCK], worst = 0.0;
    for (int i = 0; i < n; i++) {
        for (int b = 0; b < BLOCK; b++) {
            row[b] = arow[b] = 0.0;
            for (int c = 0; c < BLOCK; c++) {
                row[b] += v[(size_t)i * BLOCK + c] * q[c][order[b]];
                arow[b] += av[(size_t)i * BLOCK + c] * q[c][order[b]];
            }
        }
        for (int b = 0; b < BLOCK; b++) {
            v[(size_t)i * BLOCK + b] = row[b];
            av[(size_t)i * BLOCK + b] = arow[b];
        }
    }
    for (int b = 0; b < BLOCK; b++)
        lambda[b] = h[order[b]][order[b]];
    for (int b = 0; b < ORR_KERNEL_SEP_RANK; b++) {
        double r2 = 0.0;
        for (int i = 0; i < n; i++) {
            const double r = av[(size_t)i * BLOCK + b] - lambda[b] * v[(size_t)i * BLOCK + b];
            r2 += r * r;
        }
        worst = fmax(worst, sqrt(r2) / fabs(lambda[0]));
    }
    return worst;
}

/* The leading eigenpairs of the symmetric n x n matrix a: v (n x BLOCK)
 * receives the eigenvectors as columns, lambda the eigenvalues. */
static orr_status eigenpairs(const double *a, int n, double *v, double *lambda, orr_error *err)
{
    double *av = orr_malloc(sizeof(double) * (size_t)n * BLOCK, "kernel expansion scratch", err);
    if (!av)
        return ORR_ERR_NOMEM;
    /* Start from even cosines on [0, 2]: the eigenfunctions are smooth
     * and even, so these are close to them. */
    for (int i = 0; i < n; i++)
        for (int c = 0; c < BLOCK; c++)
            v[(size_t)i * BLOCK + c] = cos(ORR_PI * c * (i + 0.5) / n);
    orthonormalise(v, n);
    double residual = INFINITY;
    for (int it = 0; it < MAX_ITERATIONS && residual > RESIDUAL_TOL; it++) {
        multiply(a, n, v, av);
        memcpy(v, av, sizeof(double) * (size_t)n * BLOCK);
        orthonormalise(v, n);
        if (it % 4 == 3)
            residual = ritz(a, n, v, av, lambda);
    }
    free(av);
    if (residual > RESIDUAL_TOL)
        return orr_fail(err, ORR_ERR_INTERNAL, "kernel expansion: eigenvectors did not converge (residual %.3g)",
                        residual);
    return ORR_OK;
}

/* The value at cell edge i of the function whose cell averages are avg[0 ..
 * n - 1] on [0, 2] (even about 0, zero beyond 2): fourth order. */
static double edge_value(const double *avg, int n, int i)
{
    double c[4];
    for (int o = 0; o < 4; o++) {
        int j = i - 2 + o;
        j = j < 0 ? -1 - j : j; /* even about 0 */
        c[o] = j < n ? avg[j] : 0.0;
    }
    return (-c[0] + 7.0 * c[1] + 7.0 * c[2] - c[3]) / 12.0;
}

orr_status orr_kernel_fill_separable(orr_kernel *k, const double *cell, int n, orr_error *err)
{
    const double d = ORR_KERNEL_SUPPORT / n;
    double *a = orr_malloc(sizeof(double) * (size_t)n * n, "kernel expansion scratch", err);
    double *v = orr_malloc(sizeof(double) * (size_t)n * BLOCK, "kernel expansion scratch", err);
    double *e = orr_malloc(sizeof(double) * (size_t)(n + 1) * 2, "kernel expansion scratch", err);
    k->separable = orr_malloc(sizeof(float) * (ORR_KERNEL_SEP_N + 2) * ORR_KERNEL_SEP_RANK,
                              "kernel separable table", err);
    orr_status st = a && v && e && k->separable ? ORR_OK : ORR_ERR_NOMEM;
    double lambda[BLOCK];
    if (!st) {
        for (size_t i = 0; i < (size_t)n * n; i++)
            a[i] = 2.0 / d * cell[i];
        st = eigenpairs(a, n, v, lambda, err);
    }
    for (int r = 0; !st && r < ORR_KERNEL_SEP_RANK; r++) {
        /* Cell averages of f_r, normalised so that the integral of f_r^2
         * over [-2, 2] is 1 (the eigenvector has unit length), with
         * sqrt |lambda_r| folded in; E_r at the cell edges and f_r there. */
        const double scale = sqrt(fabs(lambda[r]) / (2.0 * d));
        double *avg = a /* free once the eigenvectors are known */, *edge_e = e, *edge_f = e + n + 1;
        for (int i = 0; i < n; i++)
            avg[i] = scale * v[(size_t)i * BLOCK + r];
        edge_e[0] = 0.0;
        for (int i = 0; i < n; i++)
            edge_e[i + 1] = edge_e[i] + d * avg[i];
        for (int i = 0; i <= n; i++)
            edge_f[i] = edge_value(avg, n, i);
        for (int j = 0; j <= ORR_KERNEL_SEP_N; j++) {
            const double x = ORR_KERNEL_SUPPORT * j / ORR_KERNEL_SEP_N, c = x / d;
            const int i = c < n ? (int)c : n - 1;
            const double s = c - i, s2 = s * s, s3 = s2 * s;
            const double value = (2 * s3 - 3 * s2 + 1) * edge_e[i] + (s3 - 2 * s2 + s) * d * edge_f[i] +
                                 (-2 * s3 + 3 * s2) * edge_e[i + 1] + (s3 - s2) * d * edge_f[i + 1];
            k->separable[(size_t)j * ORR_KERNEL_SEP_RANK + r] = (float)value;
        }
        k->separable[(size_t)(ORR_KERNEL_SEP_N + 1) * ORR_KERNEL_SEP_RANK + r] =
            k->separable[(size_t)ORR_KERNEL_SEP_N * ORR_KERNEL_SEP_RANK + r];
        k->separable_sign[r] = lambda[r] < 0 ? -1.0f : 1.0f;
    }
    free(a);
    free(v);
    free(e);
    return st;
}
