/* Block Cholesky factorisation of a symmetric positive definite matrix with tree
 * structure (6x6 blocks, each node coupled only to its parent), eliminated leaves first:
 * no fill-in, O(n) work and memory. The solver behind the shift-invert eigen path
 * (PHYSICS.md "Modes"). */
#ifndef GALE_TREE_CHOL_H
#define GALE_TREE_CHOL_H

#include "err.h"

typedef struct tree_chol {
    int n_nodes;       /* node 0 is the eliminated (clamped) root and holds no DOFs */
    const int *parent; /* borrowed [n_nodes], parent[i] < i */
    double *ld;        /* owned [n_nodes][36] inverse L_ii^{-1} of each pivot block's lower
                        * Cholesky factor (lower triangular) */
    double *lt;        /* owned [n_nodes][36] L_ii^{-1} A(i, parent(i)) = L(parent, i)^T */
} tree_chol;

/* Factors A given by diagonal blocks d[36 i] and couplings o[36 i] = A(i, parent(i))
 * (row-major, node 0 ignored; o unused where parent(i) == 0). Free vectors place node i
 * at [6 (i - 1)]. *c keeps `parent` (borrowed) and owns its arrays; tree_chol_fini frees.
 * Fails with GALE_E_NUMERIC naming the node whose pivot is not positive definite. */
int tree_chol_factor(tree_chol *c, int n_nodes, const int *parent, const double *d,
                     const double *o, gale_err *err);

/* Solves A x = b in place (x holds b on entry), 6 (n_nodes - 1) entries. */
void tree_chol_solve(const tree_chol *c, double *x);

/* Frees the factor; NULL or an empty factor is a no-op. */
void tree_chol_fini(tree_chol *c);

#endif
