/* Strong-wind correction of Diener 2008 section 5.2: for each mode, length-preserving
 * poses sampled along q (walk from the root, rotate each segment by its nodes' rotations,
 * keep its length) are fitted by u(q) ≈ q̃ v + q̃² w, q̃ = a atan(b q) (eq. 16-17). */
#ifndef GALE_CORRECTION_H
#define GALE_CORRECTION_H

#include "err.h"

typedef struct corr_desc {
    double amp_rot_rad; /* stated strong-wind amplitude: each mode alone at the q where its
                         * largest node rotation is this [rad]; 0: 0.35 (20 degrees) */
    double fit_range;   /* poses are fitted over |q| <= fit_range x that q; 0: 2 */
    int n_samples;      /* poses sampled over the fit range (odd, >= 5); 0: 9 */
} corr_desc;

typedef struct corr_result {
    int n_modes, n_nodes;
    double *v, *w;        /* owned [n_modes][n_nodes][3] */
    double *a, *b;        /* owned [n_modes]; a = 1/b so that q̃ ≈ q for small q */
    double *q_amp;        /* owned [n_modes] the q of the stated amplitude per mode */
    double amp_rot_rad;   /* resolved amplitude */
    double err_linear;    /* max relative branch-length error, u = q φ, |q| <= q_amp */
    double err_corrected; /* the same with u = q̃ v + q̃² w */
    double err_pose;      /* the same for the sampled poses themselves (rounding only) */
} corr_result;

/* Fits the correction for n_modes modes of an n_nodes skeleton: rest[3 n] positions,
 * parent[n] (parent[i] < i, root 0), mode translations phi[n_modes][n][3] and rotations
 * phi_rot[n_modes][n][3] (root rows zero). *r owns its arrays (corr_result_fini). */
int corr_fit(const double *rest, const int *parent, int n_nodes, const double *phi,
             const double *phi_rot, int n_modes, const corr_desc *d, corr_result *r,
             gale_err *err);

/* Frees the arrays; NULL is a no-op. */
void corr_result_fini(corr_result *r);

#endif
