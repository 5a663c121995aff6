/* The wind projection basis of Diener 2008 section 4: p_i = C ∫_Ω D(s) φ_i(s) ds over all
 * elements, with φ_i interpolated by the element shape functions of the appendix (linear
 * axial, cubic Hermite lateral), so that at run time f_i = |v| v·p_i (eq. 15). */
#ifndef GALE_BASIS_H
#define GALE_BASIS_H

#include "crown_load.h"
#include "fem.h"

/* The nodal load of a unit wind force vector w = e_k (k = 0, 1, 2; tree frame) into
 * F[3 d + k] for the f->n_dof free dofs d: the consistent load C ∫ wood D N^eT R^e e_k ds of
 * the drag on every element plus C tip_m2 e_k on each tip's translation (crown_load.h;
 * cl NULL: the wood alone), drag_c = C = ½ ρ_air C_D [kg/m^3], D = 2 r_e per element.
 * Integrated by 3-point Gauss quadrature, exact for the cubic shape functions. -1 when out
 * of memory, else 0. */
int basis_load(const fem_model *f, double drag_c, const crown_load *cl, double *F);

/* p[3 m + k] = φ_mᵀ F_k for the modes phi[n_modes][f->n_dof] and a load F[3 d + k] of
 * basis_load. */
void basis_project(const fem_model *f, const double *phi, int n_modes, const double *F,
                   double *p);

/* p[3 m + k] (n_modes 3-vectors, tree frame) from the modes phi[n_modes][f->n_dof] of f:
 * basis_load, then basis_project. -1 when out of memory, else 0. */
int basis_compute(const fem_model *f, const double *phi, int n_modes, double drag_c,
                  const crown_load *cl, double *p);

#endif
