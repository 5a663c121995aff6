/* 3D Euler-Bernoulli frame elements on a tree skeleton (Diener 2008 section 3.1 and
 * appendix; PHYSICS.md "Beam model"): 6 DOF per node, consistent mass with torsional
 * inertia, root clamped, stored as 6x6 blocks in tree order (each node couples only to
 * its parent), which is what makes the zero-fill factorisation of tree_chol.h possible. */
#ifndef GALE_FEM_H
#define GALE_FEM_H

#include "err.h"
#include "skeleton.h"

/* DOF order at a node: ux, uy, uz (translation [m]), rx, ry, rz (rotation [rad]). A
 * free vector holds the n_nodes - 1 non-root nodes: node i (i >= 1) at [6 (i - 1)]. */
#define FEM_DOF(node) (6 * ((node)-1))

typedef struct fem_material {
    double E_pa;      /* Young's modulus [Pa]; 0: 1e10 (Diener 2008 appendix) */
    double rho_kg_m3; /* density [kg/m^3]; 0: 1000 */
    double G_pa;      /* shear modulus [Pa]; 0: E/2.6 (the paper's "G = 2.6E" is a typo) */
} fem_material;

typedef struct fem_model {
    int n_nodes;     /* skeleton nodes; node 0 is the clamped root */
    int n_dof;       /* 6 (n_nodes - 1) free DOFs */
    int *parent;     /* owned [n_nodes] copy of the skeleton's parents */
    double *kd, *md; /* owned [n_nodes][36] diagonal blocks K_ii, M_ii (row-major, node 0 unused) */
    double *ko, *mo; /* owned [n_nodes][36] K(i, parent(i)), M(i, parent(i)); zero when the
                      * parent is the root */
    double *frame;   /* owned [n_nodes][9] element parent(i)->i local frame: rows ex, ey, ez */
    double *len_m;   /* owned [n_nodes] element length [m] (element i ends at node i) */
    double *radius_m; /* owned [n_nodes] element radius: mean of its two nodes' [m] */
    fem_material mat; /* resolved material */
} fem_model;

/* Fills zero fields of *m with the defaults above. */
void fem_material_resolve(fem_material *m);

/* Local 12x12 element matrices (row-major; DOFs of the start node then the end node, in
 * the element frame, x along the element) of a solid circular beam of length L and radius
 * r: A = πr², I = πr⁴/4, J = πr⁴/2. */
void fem_element_local(double L, double r, const fem_material *m, double k[144], double mass[144]);

/* An orthonormal frame with ex along d (|d| > 0); the reference vector for ey is the
 * global axis farthest from d, so vertical elements are as well conditioned as any. */
void fem_element_frame(const double d[3], double frame[9]);

/* Assembles K and M of skeleton s (n >= 2, parent[i] < i, edges of non-zero length).
 * *f owns its arrays afterwards; release with fem_fini. Fails on a zero-length edge or a
 * non-positive radius, naming the node. */
int fem_build(const skeleton *s, const fem_material *m, fem_model *f, gale_err *err);

/* Frees the arrays; NULL or an empty model is a no-op. */
void fem_fini(fem_model *f);

/* y = K x and y = M x on free vectors of n_dof entries (x and y must not alias). */
void fem_mul_k(const fem_model *f, const double *x, double *y);
void fem_mul_m(const fem_model *f, const double *x, double *y);

/* Splits n_modes free vectors phi[n_modes][n_dof] into per-node translations
 * trans[n_modes][n_nodes][3] and rotations rot[n_modes][n_nodes][3], the root rows zero. */
void fem_split_modes(const fem_model *f, const double *phi, int n_modes, double *trans,
                     double *rot);

/* Dense n_dof x n_dof K and M (row-major, caller-allocated), for tests of small models. */
void fem_dense(const fem_model *f, double *k, double *mass);

#endif
