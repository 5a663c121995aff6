/* Leaves-first block Cholesky of a tree-structured SPD matrix: eliminating node i before
 * its parent p only updates the pivot block of p (A_pp -= L_pi L_pi^T), so the factor has
 * exactly the sparsity of A. Each step is a 6x6 dense Cholesky and two triangular solves. */
#include "tree_chol.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* In-place lower Cholesky of a 6x6 row-major block; the upper part is zeroed. Returns
 * -1 when a pivot is not positive. */
static int chol6(double *a)
{
    for (int j = 0; j < 6; j++) {
        double s = a[j * 6 + j];
        for (int k = 0; k < j; k++) {
            s -= a[j * 6 + k] * a[j * 6 + k];
        }
        if (!(s > 0.0)) {
            return -1;
        }
        const double djj = sqrt(s);
        a[j * 6 + j] = djj;
        for (int i = j + 1; i < 6; i++) {
            double t = a[i * 6 + j];
            for (int k = 0; k < j; k++) {
                t -= a[i * 6 + k] * a[j * 6 + k];
            }
            a[i * 6 + j] = t / djj;
        }
        for (int i = 0; i < j; i++) {
            a[i * 6 + j] = 0.0;
        }
    }
    return 0;
}

/* Inverts a lower-triangular 6x6 block in place (the result is lower triangular). */
static void inv_lower6(double *l)
{
    double inv[36] = { 0 };
    for (int j = 0; j < 6; j++) {
        inv[j * 6 + j] = 1.0 / l[j * 6 + j];
        for (int i = j + 1; i < 6; i++) {
            double s = 0.0;
            for (int k = j; k < i; k++) {
                s += l[i * 6 + k] * inv[k * 6 + j];
            }
            inv[i * 6 + j] = -s / l[i * 6 + i];
        }
    }
    memcpy(l, inv, sizeof inv);
}

/* x = W x for lower-triangular W (6x6): the forward solve with W = L^{-1}. */
static inline void fwd6(const double *restrict w, double *restrict x)
{
    double y[6];
    for (int i = 0; i < 6; i++) {
        double s = 0.0;
        for (int k = 0; k <= i; k++) {
            s += w[i * 6 + k] * x[k];
        }
        y[i] = s;
    }
    memcpy(x, y, sizeof y);
}

/* x = W^T x for lower-triangular W (6x6): the backward solve with W = L^{-1}. */
static inline void bwd6(const double *restrict w, double *restrict x)
{
    double y[6];
    for (int i = 0; i < 6; i++) {
        double s = 0.0;
        for (int k = i; k < 6; k++) {
            s += w[k * 6 + i] * x[k];
        }
        y[i] = s;
    }
    memcpy(x, y, sizeof y);
}

int tree_chol_factor(tree_chol *c, int n_nodes, const int *parent, const double *d,
                     const double *o, gale_err *err)
{
    memset(c, 0, sizeof *c);
    c->n_nodes = n_nodes;
    c->parent = parent;
    c->ld = malloc((size_t)n_nodes * 36 * sizeof *c->ld);
    c->lt = calloc((size_t)n_nodes * 36, sizeof *c->lt);
    if (!c->ld || !c->lt) {
        tree_chol_fini(c);
        return gale_errf(err, GALE_E_NOMEM, "tree_chol: out of memory for %d nodes", n_nodes);
    }
    memcpy(c->ld, d, (size_t)n_nodes * 36 * sizeof *c->ld);
    for (int i = n_nodes - 1; i >= 1; i--) {
        double *l = c->ld + 36 * i;
        if (chol6(l) != 0) {
            tree_chol_fini(c);
            return gale_errf(err, GALE_E_NUMERIC,
                             "tree_chol: pivot block of node %d is not positive definite", i);
        }
        /* keep L_ii^{-1}: the solves then multiply instead of divide */
        inv_lower6(l);
        const int p = parent[i];
        if (p <= 0) {
            continue;
        }
        /* lt = L_ii^{-1} A(i, p) */
        double *t = c->lt + 36 * i;
        const double *a = o + 36 * i;
        for (int r = 0; r < 6; r++) {
            for (int col = 0; col < 6; col++) {
                double acc = 0.0;
                for (int k = 0; k <= r; k++) {
                    acc += l[r * 6 + k] * a[k * 6 + col];
                }
                t[r * 6 + col] = acc;
            }
        }
        /* Schur update of the parent's pivot: A_pp -= lt^T lt */
        double *dp = c->ld + 36 * p;
        for (int r = 0; r < 6; r++) {
            for (int q = 0; q < 6; q++) {
                double s = 0.0;
                for (int k = 0; k < 6; k++) {
                    s += t[k * 6 + r] * t[k * 6 + q];
                }
                dp[r * 6 + q] -= s;
            }
        }
    }
    return GALE_OK;
}

void tree_chol_solve(const tree_chol *c, double *x)
{
    const int n = c->n_nodes;
    /* forward, leaves first: y_i = L_ii^{-1} b_i, then b_p -= L(p,i) y_i = lt^T y_i */
    for (int i = n - 1; i >= 1; i--) {
        double *xi = x + 6 * (i - 1);
        fwd6(c->ld + 36 * i, xi);
        const int p = c->parent[i];
        if (p > 0) {
            const double *t = c->lt + 36 * i;
            double *xp = x + 6 * (p - 1);
            for (int k = 0; k < 6; k++) {
                for (int q = 0; q < 6; q++) {
                    xp[q] -= t[k * 6 + q] * xi[k];
                }
            }
        }
    }
    /* backward, root first: x_i = L_ii^{-T} (y_i - lt x_p) */
    for (int i = 1; i < n; i++) {
        double *xi = x + 6 * (i - 1);
        const int p = c->parent[i];
        if (p > 0) {
            const double *t = c->lt + 36 * i, *xp = x + 6 * (p - 1);
            for (int k = 0; k < 6; k++) {
                double s = 0.0;
                for (int q = 0; q < 6; q++) {
                    s += t[k * 6 + q] * xp[q];
                }
                xi[k] -= s;
            }
        }
        bwd6(c->ld + 36 * i, xi);
    }
}

void tree_chol_fini(tree_chol *c)
{
    if (!c) {
        return;
    }
    free(c->ld);
    free(c->lt);
    memset(c, 0, sizeof *c);
}
