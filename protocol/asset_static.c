/* The static correction of the truncated modes as the pose applies it (ASSET.md "SRES",
 * PHYSICS.md "Static correction"): the force vector read back from the modal state and
 * the linear pose with the correction. gale-bake folds the same into the CORR fields. */
#include "asset.h"

#include <math.h>
#include <stddef.h>

/* Eigenvalues and vectors of the symmetric 3x3 a (cyclic Jacobi): a becomes diagonal, v
 * holds the eigenvectors in its columns. */
static void jacobi3(double a[3][3], double v[3][3])
{
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            v[i][j] = i == j;
        }
    }
    for (int sweep = 0; sweep < 50; sweep++) {
        const double off = fabs(a[0][1]) + fabs(a[0][2]) + fabs(a[1][2]);
        if (off == 0.0) {
            break;
        }
        for (int p = 0; p < 2; p++) {
            for (int q = p + 1; q < 3; q++) {
                if (a[p][q] == 0.0) {
                    continue;
                }
                const double th = 0.5 * (a[q][q] - a[p][p]) / a[p][q];
                const double t = (th >= 0 ? 1.0 : -1.0) / (fabs(th) + sqrt(th * th + 1.0));
                const double cs = 1.0 / sqrt(t * t + 1.0), sn = t * cs;
                for (int k = 0; k < 3; k++) { /* a = Jᵀ a J */
                    const double x = a[k][p], y = a[k][q];
                    a[k][p] = cs * x - sn * y;
                    a[k][q] = sn * x + cs * y;
                }
                for (int k = 0; k < 3; k++) {
                    const double x = a[p][k], y = a[q][k];
                    a[p][k] = cs * x - sn * y;
                    a[q][k] = sn * x + cs * y;
                }
                for (int k = 0; k < 3; k++) {
                    const double x = v[k][p], y = v[k][q];
                    v[k][p] = cs * x - sn * y;
                    v[k][q] = sn * x + cs * y;
                }
            }
        }
    }
}

void asset_static_map(const float *omega, const float *wind_basis, uint32_t n_modes, double *A)
{
    double nrm[3][3] = { { 0 } }, v[3][3], inv[3][3] = { { 0 } };
    for (uint32_t i = 0; i < n_modes; i++) {
        for (int r = 0; r < 3; r++) {
            for (int c = 0; c < 3; c++) {
                nrm[r][c] += (double)wind_basis[3 * i + (uint32_t)r] * (double)wind_basis[3 * i + (uint32_t)c];
            }
        }
    }
    jacobi3(nrm, v);
    double top = 0.0;
    for (int j = 0; j < 3; j++) {
        top = nrm[j][j] > top ? nrm[j][j] : top;
    }
    for (int j = 0; j < 3; j++) {
        if (!(nrm[j][j] > 1e-9 * top)) {
            continue; /* a direction no mode's load reaches: its w is not seen in q */
        }
        for (int r = 0; r < 3; r++) {
            for (int c = 0; c < 3; c++) {
                inv[r][c] += v[r][j] * v[c][j] / nrm[j][j];
            }
        }
    }
    for (uint32_t i = 0; i < n_modes; i++) {
        const double w2 = (double)omega[i] * (double)omega[i];
        for (int k = 0; k < 3; k++) {
            double s = 0.0;
            for (int j = 0; j < 3; j++) {
                s += inv[k][j] * (double)wind_basis[3 * i + (uint32_t)j];
            }
            A[(size_t)k * n_modes + i] = s * w2;
        }
    }
}

void asset_linear(const asset *a, const float *q, uint32_t n_modes_used, float *out)
{
    const size_t nn = a->n_nodes;
    if (n_modes_used > a->n_modes) {
        n_modes_used = a->n_modes;
    }
    for (size_t i = 0; i < 3 * nn; i++) {
        out[i] = a->rest[i];
    }
    for (size_t m = 0; m < n_modes_used; m++) {
        const float *v = a->phi + 3 * m * nn;
        for (size_t i = 0; i < 3 * nn; i++) {
            out[i] += q[m] * v[i];
        }
    }
    if (!a->static_res || !a->omega || !a->wind_basis || n_modes_used == 0) {
        return;
    }
    /* the modes left out: r (A q), A over the modes used */
    double A[3 * 256], w[3] = { 0, 0, 0 };
    if (n_modes_used > 256) {
        return;
    }
    asset_static_map(a->omega, a->wind_basis, n_modes_used, A);
    for (size_t k = 0; k < 3; k++) {
        for (size_t m = 0; m < n_modes_used; m++) {
            w[k] += A[k * n_modes_used + m] * (double)q[m];
        }
    }
    for (size_t i = 0; i < 3 * nn; i++) {
        double r = 0.0;
        for (size_t k = 0; k < 3; k++) {
            r += (double)a->static_res[k * 3 * nn + i] * w[k];
        }
        out[i] = (float)((double)out[i] + r);
    }
}

void asset_pose_shapes(const asset *a, float *out)
{
    const size_t nn = a->n_nodes, nm = a->n_modes, nc = 3 * nn;
    double A[3 * 256];
    const int fold = a->static_res && a->omega && a->wind_basis && nm <= 256;
    if (fold) {
        asset_static_map(a->omega, a->wind_basis, a->n_modes, A);
    }
    for (size_t m = 0; m < nm; m++) {
        for (size_t j = 0; j < nc; j++) {
            double v = (double)a->phi[m * nc + j];
            for (size_t k = 0; fold && k < 3; k++) {
                v += (double)a->static_res[k * nc + j] * A[k * nm + m];
            }
            out[m * nc + j] = (float)v;
        }
    }
}
