/* Diener 2008 eq. 13-15: the modal wind load of a uniform wind, precomputed per mode as
 * p_i = C Σ_e R^e ∫ D N^e(s) φ_i^e ds, the element integral taken in the element frame. */
#include "basis.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void basis_compute(const fem_model *f, const double *phi, int n_modes, double drag_c,
                   const crown_load *cl, double *p)
{
    const double wood = cl ? cl->wood : 1.0, tip_m2 = cl ? cl->tip_m2 : 0.0;
    uint8_t *tip = tip_m2 > 0.0 ? malloc((size_t)f->n_nodes) : NULL;
    if (tip) {
        crown_load_tips((uint32_t)f->n_nodes, f->parent, tip);
    }
    /* 3-point Gauss-Legendre on [0, 1] */
    const double gx[3] = { 0.5 - 0.5 * sqrt(0.6), 0.5, 0.5 + 0.5 * sqrt(0.6) };
    const double gw[3] = { 5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0 };
    /* ∫ of each shape function over ξ in [0, 1] by the rule above: linear l1, l2; Hermite
     * h1..h4 (h2, h4 without their factor L) */
    double il[2] = { 0, 0 }, ih[4] = { 0, 0, 0, 0 };
    for (int g = 0; g < 3; g++) {
        const double x = gx[g], w = gw[g];
        il[0] += w * (1.0 - x);
        il[1] += w * x;
        ih[0] += w * (1.0 - 3 * x * x + 2 * x * x * x);
        ih[1] += w * (x - 2 * x * x + x * x * x);
        ih[2] += w * (3 * x * x - 2 * x * x * x);
        ih[3] += w * (x * x * x - x * x);
    }
    memset(p, 0, (size_t)n_modes * 3 * sizeof *p);
    for (int m = 0; m < n_modes; m++) {
        const double *x = phi + (size_t)m * f->n_dof;
        double acc[3] = { 0, 0, 0 };
        for (int i = 1; i < f->n_nodes; i++) {
            const int par = f->parent[i];
            const double *R = f->frame + 9 * i, L = f->len_m[i];
            const double zero[6] = { 0, 0, 0, 0, 0, 0 };
            const double *a = par > 0 ? x + FEM_DOF(par) : zero, *b = x + FEM_DOF(i);
            /* both nodes' translation and rotation in the element frame */
            double ua[3], ra[3], ub[3], rb[3];
            for (int r = 0; r < 3; r++) {
                ua[r] = R[3 * r] * a[0] + R[3 * r + 1] * a[1] + R[3 * r + 2] * a[2];
                ra[r] = R[3 * r] * a[3] + R[3 * r + 1] * a[4] + R[3 * r + 2] * a[5];
                ub[r] = R[3 * r] * b[0] + R[3 * r + 1] * b[1] + R[3 * r + 2] * b[2];
                rb[r] = R[3 * r] * b[3] + R[3 * r + 1] * b[4] + R[3 * r + 2] * b[5];
            }
            /* appendix shape matrix N^e: uy pairs with rz = duy/dx, uz with ry = -duz/dx */
            const double loc[3] = {
                il[0] * ua[0] + il[1] * ub[0],
                ih[0] * ua[1] + L * ih[1] * ra[2] + ih[2] * ub[1] + L * ih[3] * rb[2],
                ih[0] * ua[2] - L * ih[1] * ra[1] + ih[2] * ub[2] - L * ih[3] * rb[1],
            };
            const double s = 2.0 * f->radius_m[i] * L; /* D ds = 2 r L dξ */
            for (int k = 0; k < 3; k++) {
                acc[k] += s * (R[k] * loc[0] + R[3 + k] * loc[1] + R[6 + k] * loc[2]);
            }
        }
        /* the leaves' point loads: the translation of each tip */
        double at[3] = { 0, 0, 0 };
        for (int i = 1; tip && i < f->n_nodes; i++) {
            if (tip[i]) {
                for (int k = 0; k < 3; k++) {
                    at[k] += x[FEM_DOF(i) + k];
                }
            }
        }
        for (int k = 0; k < 3; k++) {
            p[3 * m + k] = drag_c * (wood * acc[k] + tip_m2 * at[k]);
        }
    }
    free(tip);
}
