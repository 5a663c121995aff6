/* Lowest natural modes of a frame model, K φ = ω² M φ (Diener 2008 section 3.2), by
 * ARPACK's implicitly restarted Lanczos in shift-invert mode: the operator (K^{-1} M)²
 * is applied with the zero-fill tree Cholesky of K (tree_chol.h) and sparse M products,
 * so work and memory grow linearly with the node count. */
#ifndef GALE_EIGEN_H
#define GALE_EIGEN_H

#include "err.h"
#include "fem.h"

typedef struct eigen_result {
    int n_modes;         /* modes found (= requested) */
    int n_dof;           /* entries of each mode vector */
    double *omega2;      /* owned [n_modes] ω² [rad²/s²], ascending */
    double *phi;         /* owned [n_modes][n_dof] mass-normalised: φ_i^T M φ_j = δ_ij */
    int iterations;      /* Lanczos restart cycles (0 on the dense path) */
    int n_op;            /* solves with the tree Cholesky of K (M products alongside) */
    double max_residual; /* max_i |K φ_i - ω_i² M φ_i| / |K φ_i| */
    double ortho_error;  /* max_ij |φ_i^T M φ_j - δ_ij| */
    int dense;           /* 1 when the model was small enough for the dense LAPACK path */
} eigen_result;

/* Computes the n_modes lowest modes of f (1 <= n_modes < f->n_dof). Models with few DOFs
 * (n_dof < 2 n_modes + 24) go through a dense LAPACK solve; all others use ARPACK with a
 * deterministic start vector, so the same model gives the same modes. *r owns its arrays
 * afterwards (eigen_result_fini). Fails with GALE_E_NUMERIC when K is not positive
 * definite or the iteration does not converge, with ARPACK's code. */
int eigen_lowest(const fem_model *f, int n_modes, eigen_result *r, gale_err *err);

/* Frees the arrays; NULL is a no-op. */
void eigen_result_fini(eigen_result *r);

#endif
