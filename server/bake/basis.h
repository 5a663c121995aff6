/* The wind projection basis of Diener 2008 section 4: p_i = C ∫_Ω D(s) φ_i(s) ds over all
 * elements, with φ_i interpolated by the element shape functions of the appendix (linear
 * axial, cubic Hermite lateral), so that at run time f_i = |v| v·p_i (eq. 15). */
#ifndef GALE_BASIS_H
#define GALE_BASIS_H

#include "crown_load.h"
#include "fem.h"

/* p[3 m + k] (n_modes 3-vectors, tree frame) from the modes phi[n_modes][f->n_dof] of f;
 * D = 2 r_e per element, drag_c = C = ½ ρ_air C_D [kg/m^3]. Integrated by 3-point Gauss
 * quadrature, exact for the cubic shape functions. cl spreads the load between the wood
 * and point loads at the tips (crown_load.h); NULL: the wood alone. */
void basis_compute(const fem_model *f, const double *phi, int n_modes, double drag_c,
                   const crown_load *cl, double *p);

#endif
