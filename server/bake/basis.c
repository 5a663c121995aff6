/* Diener 2008 eq. 13-15: the modal wind load of a uniform wind, precomputed per mode as
 * p_i = C Σ_e R^e ∫ D N^e(s) φ_i^e ds, the element integral taken in the element frame.
 * The integral is linear in φ_i, so it is the dot product of φ_i with one nodal load
 * vector per wind component (the consistent load of the drag, basis_load): the static
 * correction (statics.c) solves K u = F with the same vectors. */
#include "basis.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int basis_load(const fem_model *f, double drag_c, const crown_load *cl, double *F)
{
    const double wood = cl ? cl->wood : 1.0, tip_m2 = cl ? cl->tip_m2 : 0.0;
    uint8_t *tip = tip_m2 > 0.0 ? malloc((size_t)f->n_nodes) : NULL;
    if (tip_m2 > 0.0 && !tip) {
        return -1;
    }
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
    memset(F, 0, (size_t)f->n_dof * 3 * sizeof *F);
    for (int i = 1; i < f->n_nodes; i++) {
        const int par = f->parent[i];
        const double *R = f->frame + 9 * i, L = f->len_m[i];
        const double s = drag_c * wood * 2.0 * f->radius_m[i] * L; /* C D ds = C 2 r L dξ */
        double *a = par > 0 ? F + 3 * FEM_DOF(par) : NULL, *b = F + 3 * FEM_DOF(i);
        for (int k = 0; k < 3; k++) {
            /* the unit load w_k in the element frame: row r of R is element axis r */
            const double l0 = s * R[k], l1 = s * R[3 + k], l2 = s * R[6 + k];
            /* the appendix shape matrix N^e transposed: uy pairs with rz = duy/dx, uz with
             * ry = -duz/dx; both nodes' translation and rotation, back in the tree frame */
            const double fa[6] = { il[0] * l0, ih[0] * l1, ih[0] * l2, 0.0, -L * ih[1] * l2,
                                   L * ih[1] * l1 };
            const double fb[6] = { il[1] * l0, ih[2] * l1, ih[2] * l2, 0.0, -L * ih[3] * l2,
                                   L * ih[3] * l1 };
            for (int c = 0; c < 3; c++) {
                const double tb = R[c] * fb[0] + R[3 + c] * fb[1] + R[6 + c] * fb[2];
                const double rb = R[c] * fb[3] + R[3 + c] * fb[4] + R[6 + c] * fb[5];
                b[3 * c + k] += tb;
                b[3 * (3 + c) + k] += rb;
                if (a) {
                    a[3 * c + k] += R[c] * fa[0] + R[3 + c] * fa[1] + R[6 + c] * fa[2];
                    a[3 * (3 + c) + k] += R[c] * fa[3] + R[3 + c] * fa[4] + R[6 + c] * fa[5];
                }
            }
        }
        /* the leaves' point load at a tip, on its translation */
        if (tip && tip[i]) {
            for (int k = 0; k < 3; k++) {
                b[3 * k + k] += drag_c * tip_m2;
            }
        }
    }
    free(tip);
    return 0;
}

void basis_project(const fem_model *f, const double *phi, int n_modes, const double *F,
                   double *p)
{
    for (int m = 0; m < n_modes; m++) {
        const double *x = phi + (size_t)m * f->n_dof;
        double acc[3] = { 0, 0, 0 };
        for (int d = 0; d < f->n_dof; d++) {
            for (int k = 0; k < 3; k++) {
                acc[k] += x[d] * F[3 * d + k];
            }
        }
        for (int k = 0; k < 3; k++) {
            p[3 * m + k] = acc[k];
        }
    }
}

int basis_compute(const fem_model *f, const double *phi, int n_modes, double drag_c,
                  const crown_load *cl, double *p)
{
    double *F = malloc((size_t)f->n_dof * 3 * sizeof *F);
    if (!F || basis_load(f, drag_c, cl, F) != 0) {
        free(F);
        return -1;
    }
    basis_project(f, phi, n_modes, F, p);
    free(F);
    return 0;
}
