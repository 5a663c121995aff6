/* Frame-element stiffness and consistent mass of a tree skeleton (Diener 2008 section 3.1
 * and appendix): axial EA/L, bending 12EI/L³ in both planes, torsion GJ/L; mass from the
 * same linear / cubic Hermite shape functions, plus torsional inertia ρJ. Root clamped. */
#include "fem.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void fem_material_resolve(fem_material *m)
{
    if (m->E_pa <= 0.0) {
        m->E_pa = 1e10;
    }
    if (m->rho_kg_m3 <= 0.0) {
        m->rho_kg_m3 = 1000.0;
    }
    if (m->G_pa <= 0.0) {
        m->G_pa = m->E_pa / 2.6;
    }
}

static void put_sym(double *a, int i, int j, double v)
{
    a[i * 12 + j] = v;
    a[j * 12 + i] = v;
}

void fem_element_local(double L, double r, const fem_material *m, double k[144], double mass[144])
{
    const double A = M_PI * r * r, Iy = M_PI * r * r * r * r / 4.0, J = 2.0 * Iy;
    const double E = m->E_pa, G = m->G_pa, rho = m->rho_kg_m3;
    const double L2 = L * L, L3 = L2 * L;
    memset(k, 0, 144 * sizeof *k);
    memset(mass, 0, 144 * sizeof *mass);
    /* axial (0, 6) and torsion (3, 9): linear shape functions */
    put_sym(k, 0, 0, E * A / L), put_sym(k, 6, 6, E * A / L), put_sym(k, 0, 6, -E * A / L);
    put_sym(k, 3, 3, G * J / L), put_sym(k, 9, 9, G * J / L), put_sym(k, 3, 9, -G * J / L);
    const double ma = rho * A * L / 6.0, mt = rho * J * L / 6.0;
    put_sym(mass, 0, 0, 2 * ma), put_sym(mass, 6, 6, 2 * ma), put_sym(mass, 0, 6, ma);
    put_sym(mass, 3, 3, 2 * mt), put_sym(mass, 9, 9, 2 * mt), put_sym(mass, 3, 9, mt);
    /* Bending, cubic Hermite. Plane x-y: (uy1, rz1, uy2, rz2) with rz = duy/dx; plane x-z:
     * (uz1, ry1, uz2, ry2) with ry = -duz/dx, hence the sign flips s on the couplings. */
    const double b = E * Iy / L3, mb = rho * A * L / 420.0;
    const int dofs[2][4] = { { 1, 5, 7, 11 }, { 2, 4, 8, 10 } };
    for (int plane = 0; plane < 2; plane++) {
        const double s = plane == 0 ? 1.0 : -1.0;
        const double kb[4][4] = {
            { 12, s * 6 * L, -12, s * 6 * L },
            { s * 6 * L, 4 * L2, -s * 6 * L, 2 * L2 },
            { -12, -s * 6 * L, 12, -s * 6 * L },
            { s * 6 * L, 2 * L2, -s * 6 * L, 4 * L2 },
        };
        const double mm[4][4] = {
            { 156, s * 22 * L, 54, -s * 13 * L },
            { s * 22 * L, 4 * L2, s * 13 * L, -3 * L2 },
            { 54, s * 13 * L, 156, -s * 22 * L },
            { -s * 13 * L, -3 * L2, -s * 22 * L, 4 * L2 },
        };
        for (int i = 0; i < 4; i++) {
            for (int j = 0; j < 4; j++) {
                k[dofs[plane][i] * 12 + dofs[plane][j]] = b * kb[i][j];
                mass[dofs[plane][i] * 12 + dofs[plane][j]] = mb * mm[i][j];
            }
        }
    }
}

void fem_element_frame(const double d[3], double frame[9])
{
    const double n = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    double ex[3] = { d[0] / n, d[1] / n, d[2] / n };
    /* the global axis least aligned with ex */
    int a = 0;
    for (int i = 1; i < 3; i++) {
        if (fabs(ex[i]) < fabs(ex[a])) {
            a = i;
        }
    }
    double ref[3] = { 0, 0, 0 };
    ref[a] = 1.0;
    double ez[3] = { ex[1] * ref[2] - ex[2] * ref[1], ex[2] * ref[0] - ex[0] * ref[2],
                     ex[0] * ref[1] - ex[1] * ref[0] };
    const double nz = sqrt(ez[0] * ez[0] + ez[1] * ez[1] + ez[2] * ez[2]);
    for (int i = 0; i < 3; i++) {
        ez[i] /= nz;
    }
    double ey[3] = { ez[1] * ex[2] - ez[2] * ex[1], ez[2] * ex[0] - ez[0] * ex[2],
                     ez[0] * ex[1] - ez[1] * ex[0] };
    memcpy(frame, ex, sizeof ex);
    memcpy(frame + 3, ey, sizeof ey);
    memcpy(frame + 6, ez, sizeof ez);
}

/* out (6x6 row-major) = T^T a T for the (row block ra, col block ca) 6x6 block of a 12x12
 * local matrix, T = diag(R, R) with R the 3x3 frame (rows ex, ey, ez). */
static void to_global(const double *a12, int ra, int ca, const double R[9], double out[36])
{
    for (int bi = 0; bi < 2; bi++) {
        for (int bj = 0; bj < 2; bj++) {
            double loc[3][3], tmp[3][3];
            for (int i = 0; i < 3; i++) {
                for (int j = 0; j < 3; j++) {
                    loc[i][j] = a12[(ra * 6 + bi * 3 + i) * 12 + ca * 6 + bj * 3 + j];
                }
            }
            /* tmp = loc R */
            for (int i = 0; i < 3; i++) {
                for (int j = 0; j < 3; j++) {
                    tmp[i][j] = loc[i][0] * R[0 * 3 + j] + loc[i][1] * R[1 * 3 + j] +
                                loc[i][2] * R[2 * 3 + j];
                }
            }
            /* out = R^T tmp */
            for (int i = 0; i < 3; i++) {
                for (int j = 0; j < 3; j++) {
                    out[(bi * 3 + i) * 6 + bj * 3 + j] = R[0 * 3 + i] * tmp[0][j] +
                                                         R[1 * 3 + i] * tmp[1][j] +
                                                         R[2 * 3 + i] * tmp[2][j];
                }
            }
        }
    }
}

int fem_build(const skeleton *s, const fem_material *m, fem_model *f, gale_err *err)
{
    memset(f, 0, sizeof *f);
    if (s->n < 2) {
        return gale_errf(err, GALE_E_RANGE, "fem: skeleton has %d nodes, expected at least 2",
                         s->n);
    }
    const int n = s->n;
    f->mat = m ? *m : (fem_material){ 0 };
    fem_material_resolve(&f->mat);
    f->n_nodes = n;
    f->n_dof = 6 * (n - 1);
    f->parent = malloc((size_t)n * sizeof *f->parent);
    f->kd = calloc((size_t)n * 36, sizeof *f->kd);
    f->md = calloc((size_t)n * 36, sizeof *f->md);
    f->ko = calloc((size_t)n * 36, sizeof *f->ko);
    f->mo = calloc((size_t)n * 36, sizeof *f->mo);
    f->frame = calloc((size_t)n * 9, sizeof *f->frame);
    f->len_m = calloc((size_t)n, sizeof *f->len_m);
    f->radius_m = calloc((size_t)n, sizeof *f->radius_m);
    if (!f->parent || !f->kd || !f->md || !f->ko || !f->mo || !f->frame || !f->len_m ||
        !f->radius_m) {
        fem_fini(f);
        return gale_errf(err, GALE_E_NOMEM, "fem: out of memory for %d nodes", n);
    }
    memcpy(f->parent, s->parent, (size_t)n * sizeof *f->parent);
    if (s->parent[0] != -1) {
        fem_fini(f);
        return gale_errf(err, GALE_E_RANGE, "fem: node 0 must be the root (parent -1), got %d",
                         s->parent[0]);
    }
    double kl[144], ml[144], blk[36];
    for (int i = 1; i < n; i++) {
        const int p = s->parent[i];
        const int id = s->src_id ? s->src_id[i] : i;
        if (p < 0 || p >= i) {
            fem_fini(f);
            return gale_errf(err, GALE_E_RANGE,
                             "fem: node %d: parent %d is not an earlier node", id, p);
        }
        double d[3];
        for (int k = 0; k < 3; k++) {
            d[k] = (double)s->pos[3 * i + k] - (double)s->pos[3 * p + k];
        }
        const double L = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        const double r = 0.5 * ((double)s->radius[i] + (double)s->radius[p]);
        if (!(L > 0.0) || !isfinite(L)) {
            fem_fini(f);
            return gale_errf(err, GALE_E_RANGE, "fem: node %d: zero-length edge to its parent",
                             id);
        }
        if (!(s->radius[i] > 0.0f) || !(s->radius[p] > 0.0f) || !isfinite(r)) {
            fem_fini(f);
            return gale_errf(err, GALE_E_RANGE,
                             "fem: node %d: radius must be > 0, got %g (parent %g)", id,
                             (double)s->radius[i], (double)s->radius[p]);
        }
        f->len_m[i] = L;
        f->radius_m[i] = r;
        double *R = f->frame + 9 * i;
        fem_element_frame(d, R);
        fem_element_local(L, r, &f->mat, kl, ml);
        /* end node i: block (1,1); start node p: (0,0); coupling (i, p): (1,0) */
        to_global(kl, 1, 1, R, blk);
        for (int k = 0; k < 36; k++) {
            f->kd[36 * i + k] += blk[k];
        }
        to_global(ml, 1, 1, R, blk);
        for (int k = 0; k < 36; k++) {
            f->md[36 * i + k] += blk[k];
        }
        if (p > 0) {
            to_global(kl, 0, 0, R, blk);
            for (int k = 0; k < 36; k++) {
                f->kd[36 * p + k] += blk[k];
            }
            to_global(ml, 0, 0, R, blk);
            for (int k = 0; k < 36; k++) {
                f->md[36 * p + k] += blk[k];
            }
            to_global(kl, 1, 0, R, f->ko + 36 * i);
            to_global(ml, 1, 0, R, f->mo + 36 * i);
        }
    }
    return GALE_OK;
}

void fem_fini(fem_model *f)
{
    if (!f) {
        return;
    }
    free(f->parent);
    free(f->kd);
    free(f->md);
    free(f->ko);
    free(f->mo);
    free(f->frame);
    free(f->len_m);
    free(f->radius_m);
    memset(f, 0, sizeof *f);
}

/* y = A x for the block tree matrix with diagonal blocks d and parent couplings o. */
static void mul_blocks(const fem_model *f, const double *restrict d, const double *restrict o,
                       const double *restrict x, double *restrict y)
{
    const int n = f->n_nodes;
    memset(y, 0, (size_t)f->n_dof * sizeof *y);
    for (int i = 1; i < n; i++) {
        const double *restrict a = d + 36 * i, *restrict xi = x + FEM_DOF(i);
        double yi[6];
        for (int r = 0; r < 6; r++) {
            yi[r] = a[r * 6 + 0] * xi[0] + a[r * 6 + 1] * xi[1] + a[r * 6 + 2] * xi[2] +
                    a[r * 6 + 3] * xi[3] + a[r * 6 + 4] * xi[4] + a[r * 6 + 5] * xi[5];
        }
        const int p = f->parent[i];
        if (p > 0) {
            const double *restrict b = o + 36 * i, *restrict xp = x + FEM_DOF(p);
            double *restrict yp = y + FEM_DOF(p);
            for (int r = 0; r < 6; r++) {
                yi[r] += b[r * 6 + 0] * xp[0] + b[r * 6 + 1] * xp[1] + b[r * 6 + 2] * xp[2] +
                         b[r * 6 + 3] * xp[3] + b[r * 6 + 4] * xp[4] + b[r * 6 + 5] * xp[5];
            }
            for (int c = 0; c < 6; c++) {
                yp[c] += b[0 * 6 + c] * xi[0] + b[1 * 6 + c] * xi[1] + b[2 * 6 + c] * xi[2] +
                         b[3 * 6 + c] * xi[3] + b[4 * 6 + c] * xi[4] + b[5 * 6 + c] * xi[5];
            }
        }
        /* children (higher indices) add into y_i later, so accumulate */
        double *restrict yo = y + FEM_DOF(i);
        for (int r = 0; r < 6; r++) {
            yo[r] += yi[r];
        }
    }
}

void fem_mul_k(const fem_model *f, const double *x, double *y)
{
    mul_blocks(f, f->kd, f->ko, x, y);
}

void fem_mul_m(const fem_model *f, const double *x, double *y)
{
    mul_blocks(f, f->md, f->mo, x, y);
}

void fem_dense(const fem_model *f, double *k, double *mass)
{
    const int nd = f->n_dof;
    memset(k, 0, (size_t)nd * (size_t)nd * sizeof *k);
    memset(mass, 0, (size_t)nd * (size_t)nd * sizeof *mass);
    for (int i = 1; i < f->n_nodes; i++) {
        const int p = f->parent[i], a = FEM_DOF(i);
        for (int r = 0; r < 6; r++) {
            for (int c = 0; c < 6; c++) {
                k[(size_t)(a + r) * nd + a + c] = f->kd[36 * i + r * 6 + c];
                mass[(size_t)(a + r) * nd + a + c] = f->md[36 * i + r * 6 + c];
                if (p > 0) {
                    const int b = FEM_DOF(p);
                    k[(size_t)(a + r) * nd + b + c] = f->ko[36 * i + r * 6 + c];
                    k[(size_t)(b + c) * nd + a + r] = f->ko[36 * i + r * 6 + c];
                    mass[(size_t)(a + r) * nd + b + c] = f->mo[36 * i + r * 6 + c];
                    mass[(size_t)(b + c) * nd + a + r] = f->mo[36 * i + r * 6 + c];
                }
            }
        }
    }
}

void fem_split_modes(const fem_model *f, const double *phi, int n_modes, double *trans,
                     double *rot)
{
    const int n = f->n_nodes;
    for (int m = 0; m < n_modes; m++) {
        const double *x = phi + (size_t)m * f->n_dof;
        double *t = trans + (size_t)m * 3 * n, *r = rot + (size_t)m * 3 * n;
        for (int k = 0; k < 3; k++) {
            t[k] = r[k] = 0.0;
        }
        for (int i = 1; i < n; i++) {
            for (int k = 0; k < 3; k++) {
                t[3 * i + k] = x[FEM_DOF(i) + k];
                r[3 * i + k] = x[FEM_DOF(i) + 3 + k];
            }
        }
    }
}
