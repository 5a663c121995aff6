/* The static correction of the truncated modes (PHYSICS.md "Static correction"): the
 * mode-acceleration method (Williams 1945; residual flexibility, Craig & Kurdila 2006
 * section 14.3) adds to the kept modes' response Σ φ_i q_i the quasi-static response of
 * the modes left out, u_res = (K⁻¹ − Σ_i φ_i φ_iᵀ / ω_i²) F. The drag is F = Σ_k w_k F_k
 * (basis_load), so the residual is baked once per wind-basis column k, and the pose reads
 * w back from the modal state (asset_static_map), so no byte of the wire changes. */
#ifndef GALE_STATICS_H
#define GALE_STATICS_H

#include <stdint.h>

#include "err.h"
#include "fem.h"

/* res[k][f->n_dof] (k = 0, 1, 2) = K⁻¹ F_k − Σ_i φ_i G_i,k for the load vectors F[3 d + k]
 * of basis_load, the modes phi[n_modes][n_dof] and G of modal_static.h from the asset's
 * omega and wind_basis (so that a steady wind's q, which the simulation computes from
 * those, plus the residual is K⁻¹ F to the floats' rounding). Fails when K is not
 * positive definite or out of memory. */
int statics_residual(const fem_model *f, const double *F, const double *phi, uint32_t n_modes,
                     const float *omega, const float *wind_basis, double *res, gale_err *err);

#endif
