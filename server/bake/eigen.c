/* Shift-invert Lanczos (ARPACK dsaupd/dseupd, mode 3, B = M, σ = 0) for the lowest modes
 * of the tree frame model: OP x = (K^{-1} M)² x through the leaves-first block Cholesky,
 * M-inner products by the block sparse product, ω² from Rayleigh quotients. Small models
 * use LAPACK dsygvd. */
#include "eigen.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <arpack/arpack.h>
#include <cblas.h>
#include <lapacke.h>

#include "tree_chol.h"

void eigen_result_fini(eigen_result *r)
{
    if (!r) {
        return;
    }
    free(r->omega2);
    free(r->phi);
    memset(r, 0, sizeof *r);
}

/* Residuals and M-orthonormality of the computed modes (independent of the solver). */
static int check_modes(const fem_model *f, eigen_result *r, gale_err *err)
{
    const int nd = f->n_dof, nm = r->n_modes;
    double *mphi = malloc((size_t)nd * (size_t)nm * sizeof *mphi);
    double *kx = malloc((size_t)nd * sizeof *kx);
    double *g = malloc((size_t)nm * (size_t)nm * sizeof *g);
    if (!mphi || !kx || !g) {
        free(mphi), free(kx), free(g);
        return gale_errf(err, GALE_E_NOMEM, "eigen: out of memory checking %d modes", nm);
    }
    r->max_residual = 0.0;
    for (int m = 0; m < nm; m++) {
        const double *x = r->phi + (size_t)m * nd;
        double *mx = mphi + (size_t)m * nd;
        fem_mul_m(f, x, mx);
        fem_mul_k(f, x, kx);
        /* ω² as the Rayleigh quotient: error second order in the vector's */
        const double xkx = cblas_ddot(nd, x, 1, kx, 1), xmx = cblas_ddot(nd, x, 1, mx, 1);
        if (xmx > 0.0) {
            r->omega2[m] = xkx / xmx;
        }
        double num = 0.0, den = 0.0;
        for (int k = 0; k < nd; k++) {
            const double e = kx[k] - r->omega2[m] * mx[k];
            num += e * e;
            den += kx[k] * kx[k];
        }
        const double res = den > 0.0 ? sqrt(num / den) : (double)INFINITY;
        if (res > r->max_residual || !isfinite(res)) {
            r->max_residual = res;
        }
    }
    for (int m = 1; m < nm; m++) {
        if (r->omega2[m] < r->omega2[m - 1]) {
            r->omega2[m] = r->omega2[m - 1]; /* a degenerate pair within rounding */
        }
    }
    /* G = Φ^T (M Φ): modes are rows of length nd */
    cblas_dgemm(CblasRowMajor, CblasNoTrans, CblasTrans, nm, nm, nd, 1.0, r->phi, nd, mphi, nd,
                0.0, g, nm);
    r->ortho_error = 0.0;
    for (int i = 0; i < nm; i++) {
        for (int j = 0; j < nm; j++) {
            const double e = fabs(g[i * nm + j] - (i == j ? 1.0 : 0.0));
            if (e > r->ortho_error || !isfinite(e)) {
                r->ortho_error = e;
            }
        }
    }
    free(mphi), free(kx), free(g);
    return GALE_OK;
}

static int solve_dense(const fem_model *f, int nm, eigen_result *r, gale_err *err)
{
    const int nd = f->n_dof;
    double *k = malloc((size_t)nd * nd * sizeof *k), *m = malloc((size_t)nd * nd * sizeof *m);
    double *w = malloc((size_t)nd * sizeof *w);
    if (!k || !m || !w) {
        free(k), free(m), free(w);
        return gale_errf(err, GALE_E_NOMEM, "eigen: out of memory for a %d-DOF model", nd);
    }
    fem_dense(f, k, m);
    lapack_int info = LAPACKE_dsygvd(LAPACK_ROW_MAJOR, 1, 'V', 'U', nd, k, nd, m, nd, w);
    if (info != 0) {
        free(k), free(m), free(w);
        return gale_errf(err, GALE_E_NUMERIC,
                         "eigen: dense generalized eigensolve failed (LAPACK info %d)",
                         (int)info);
    }
    /* eigenvectors are the columns of k, M-normalised, ascending */
    for (int j = 0; j < nm; j++) {
        r->omega2[j] = w[j];
        for (int i = 0; i < nd; i++) {
            r->phi[(size_t)j * nd + i] = k[(size_t)i * nd + j];
        }
    }
    r->dense = 1;
    free(k), free(m), free(w);
    return GALE_OK;
}

/* Deterministic start vector: a fixed xorshift sequence in [-1, 1). */
static void start_vector(double *v, int n)
{
    uint64_t s = 0x9E3779B97F4A7C15ull;
    for (int i = 0; i < n; i++) {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        v[i] = (double)(s >> 11) * (2.0 / 9007199254740992.0) - 1.0;
    }
}

static int solve_arpack(const fem_model *f, int nm, eigen_result *r, gale_err *err)
{
    const int nd = f->n_dof;
    /* OP = (K^{-1} M)^2: its eigenvalues 1/ω⁴ separate the wanted modes from the rest
     * twice as well (in ratio) as 1/ω², so the Krylov space needed is smaller; a solve
     * costs O(n) here, the orthogonalisation O(n ncv) per vector (measured: 113 instead
     * of 153 Lanczos vectors for 32 modes of a 3,500-node tree, ncv 50). */
    const int power = 2;
    int ncv = 3 * nm / 2 + 2;
    if (ncv > nd) {
        ncv = nd;
    }
    const int lworkl = ncv * (ncv + 8);
    tree_chol c;
    int rc = tree_chol_factor(&c, f->n_nodes, f->parent, f->kd, f->ko, err);
    if (rc != GALE_OK) {
        return rc;
    }
    double *resid = malloc((size_t)nd * sizeof *resid);
    double *v = malloc((size_t)nd * ncv * sizeof *v);
    double *workd = malloc((size_t)3 * nd * sizeof *workd);
    double *workl = malloc((size_t)lworkl * sizeof *workl);
    double *d = malloc((size_t)nm * sizeof *d);
    double *z = malloc((size_t)nd * nm * sizeof *z);
    a_int *select = calloc((size_t)ncv, sizeof *select);
    double *tmp = malloc((size_t)nd * sizeof *tmp);
    if (!resid || !v || !workd || !workl || !d || !z || !select || !tmp) {
        rc = gale_errf(err, GALE_E_NOMEM, "eigen: out of memory for %d DOFs x %d vectors", nd,
                       ncv);
        goto done;
    }
    start_vector(resid, nd);
    a_int iparam[11] = { 0 }, ipntr[14] = { 0 };
    iparam[0] = 1;   /* exact shifts */
    iparam[2] = 500; /* max restart cycles */
    iparam[6] = 3;   /* shift-invert, generalized: OP = (K - σM)^{-1} M, B = M */
    a_int ido = 0, info = 1; /* info = 1: resid holds the start vector */
    const double tol = 1e-10;
    r->n_op = 0;
    for (;;) {
        dsaupd_c(&ido, "G", nd, "LM", nm, tol, resid, ncv, v, nd, iparam, ipntr, workd, workl,
                 lworkl, &info);
        double *x = workd + ipntr[0] - 1, *y = workd + ipntr[1] - 1;
        if (ido == -1 || ido == 1) {
            if (ido == -1) {
                fem_mul_m(f, x, y);
            } else {
                /* M x is already at ipntr[2] */
                memcpy(y, workd + ipntr[2] - 1, (size_t)nd * sizeof *y);
            }
            tree_chol_solve(&c, y);
            for (int k = 1; k < power; k++) {
                fem_mul_m(f, y, tmp);
                tree_chol_solve(&c, tmp);
                memcpy(y, tmp, (size_t)nd * sizeof *y);
            }
            r->n_op += power;
        } else if (ido == 2) {
            fem_mul_m(f, x, y);
        } else {
            break;
        }
    }
    if (info < 0 || info == 1) {
        rc = gale_errf(err, GALE_E_NUMERIC,
                       "eigen: ARPACK dsaupd failed (info %d, %d of %d modes converged after "
                       "%d restarts)",
                       (int)info, (int)iparam[4], nm, (int)iparam[2]);
        goto done;
    }
    r->iterations = (int)iparam[2];
    dseupd_c(1, "A", select, d, z, nd, 0.0, "G", nd, "LM", nm, tol, resid, ncv, v, nd, iparam,
             ipntr, workd, workl, lworkl, &info);
    if (info != 0) {
        rc = gale_errf(err, GALE_E_NUMERIC, "eigen: ARPACK dseupd failed (info %d)", (int)info);
        goto done;
    }
    /* ascending ω² (dseupd's order is not relied on) */
    int *idx = malloc((size_t)nm * sizeof *idx);
    if (!idx) {
        rc = gale_errf(err, GALE_E_NOMEM, "eigen: out of memory");
        goto done;
    }
    for (int i = 0; i < nm; i++) {
        idx[i] = i;
    }
    for (int i = 1; i < nm; i++) {
        for (int j = i; j > 0 && d[idx[j]] < d[idx[j - 1]]; j--) {
            int t = idx[j];
            idx[j] = idx[j - 1];
            idx[j - 1] = t;
        }
    }
    for (int i = 0; i < nm; i++) {
        /* dseupd returns σ + 1/ν = ω^(2 power); check_modes replaces it by the Rayleigh
         * quotient */
        r->omega2[i] = pow(d[idx[i]], 1.0 / power);
        memcpy(r->phi + (size_t)i * nd, z + (size_t)idx[i] * nd, (size_t)nd * sizeof *z);
    }
    free(idx);
    rc = GALE_OK;
done:
    tree_chol_fini(&c);
    free(resid), free(v), free(workd), free(workl), free(d), free(z), free(select), free(tmp);
    return rc;
}

int eigen_lowest(const fem_model *f, int n_modes, eigen_result *r, gale_err *err)
{
    memset(r, 0, sizeof *r);
    const int nd = f->n_dof;
    if (n_modes < 1 || n_modes >= nd) {
        return gale_errf(err, GALE_E_RANGE,
                         "eigen: %d modes requested, expected 1..%d for a %d-node model",
                         n_modes, nd - 1, f->n_nodes);
    }
    r->n_modes = n_modes;
    r->n_dof = nd;
    r->omega2 = malloc((size_t)n_modes * sizeof *r->omega2);
    r->phi = malloc((size_t)n_modes * nd * sizeof *r->phi);
    if (!r->omega2 || !r->phi) {
        eigen_result_fini(r);
        return gale_errf(err, GALE_E_NOMEM, "eigen: out of memory for %d modes", n_modes);
    }
    /* The BLAS work here is matrix-vector products on a few tens of columns: OpenBLAS
     * threads cost more in wake-ups and spinning than they save (measured), so the whole
     * solve runs single-threaded. */
    const int blas_threads = openblas_get_num_threads();
    openblas_set_num_threads(1);
    int rc = nd < 2 * n_modes + 24 ? solve_dense(f, n_modes, r, err)
                                   : solve_arpack(f, n_modes, r, err);
    if (rc == GALE_OK) {
        /* a sign convention, so the same model always gives the same vectors: the
         * largest-magnitude entry of each mode is positive */
        for (int m = 0; m < n_modes; m++) {
            double *x = r->phi + (size_t)m * nd;
            int best = 0;
            for (int k = 1; k < nd; k++) {
                if (fabs(x[k]) > fabs(x[best])) {
                    best = k;
                }
            }
            if (x[best] < 0.0) {
                for (int k = 0; k < nd; k++) {
                    x[k] = -x[k];
                }
            }
            if (!(r->omega2[m] > 0.0)) {
                rc = gale_errf(err, GALE_E_NUMERIC,
                               "eigen: mode %d has ω² = %g, expected > 0 (K not positive "
                               "definite?)",
                               m + 1, r->omega2[m]);
                break;
            }
        }
    }
    if (rc == GALE_OK) {
        rc = check_modes(f, r, err);
    }
    openblas_set_num_threads(blas_threads);
    if (rc != GALE_OK) {
        eigen_result_fini(r);
    }
    return rc;
}
