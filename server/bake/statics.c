/* The static correction of the truncated modes: see statics.h. */
#include "statics.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "modal_static.h"
#include "tree_chol.h"

int statics_residual(const fem_model *f, const double *F, const double *phi, uint32_t n_modes,
                     const float *omega, const float *wind_basis, double *res, gale_err *err)
{
    const size_t nd = (size_t)f->n_dof;
    tree_chol c;
    int rc = tree_chol_factor(&c, f->n_nodes, f->parent, f->kd, f->ko, err);
    if (rc != GALE_OK) {
        return rc;
    }
    for (int k = 0; k < 3; k++) {
        double *u = res + (size_t)k * nd;
        for (size_t d = 0; d < nd; d++) {
            u[d] = F[3 * d + (size_t)k];
        }
        tree_chol_solve(&c, u);
        /* less the kept modes' static share: what the modal state already shows */
        for (uint32_t i = 0; i < n_modes; i++) {
            const double g = modal_static_gain(omega, wind_basis, i, k);
            const double *x = phi + (size_t)i * nd;
            for (size_t d = 0; d < nd; d++) {
                u[d] -= g * x[d];
            }
        }
    }
    tree_chol_fini(&c);
    return GALE_OK;
}
