/* Frame elements (server/fem.c) and the tree Cholesky (server/tree_chol.c): a cantilever
 * against the Euler-Bernoulli closed forms of PHYSICS.md "Modal analysis", symmetry,
 * rigid-body null space and mass of the element matrices, K positive definite once
 * clamped, and the zero-fill factorisation against a dense solve. */
#include <math.h>
#include <stdlib.h>

#include <lapacke.h>

#include "bake_tree.h"
#include "check.h"
#include "eigen.h"
#include "fem.h"
#include "tree_chol.h"

/* A straight cantilever of n_el elements along unit direction a, length L, radius r. */
static void cantilever(skeleton *s, int n_el, const double a[3], double L, double r)
{
    gale_err err;
    CHECK(skeleton_alloc(s, n_el + 1, &err) == GALE_OK);
    for (int i = 0; i <= n_el; i++) {
        s->parent[i] = i - 1;
        for (int k = 0; k < 3; k++) {
            s->pos[3 * i + k] = (float)(a[k] * L * i / n_el);
        }
        s->radius[i] = (float)r;
    }
}

enum { AXIAL, BENDING, TORSION };

static int classify(const double *phi, int n_nodes, const double a[3])
{
    double ax = 0, lat = 0, tor = 0;
    for (int i = 1; i < n_nodes; i++) {
        const double *u = phi + FEM_DOF(i), *t = u + 3;
        const double ua = u[0] * a[0] + u[1] * a[1] + u[2] * a[2];
        const double ta = t[0] * a[0] + t[1] * a[1] + t[2] * a[2];
        ax += ua * ua;
        lat += u[0] * u[0] + u[1] * u[1] + u[2] * u[2] - ua * ua;
        tor += ta * ta;
    }
    return ax > lat && ax > tor ? AXIAL : lat > tor ? BENDING : TORSION;
}

/* Max relative error of the first four bending pairs and the first torsional mode of an
 * n_el-element cantilever along a, against PHYSICS.md's closed forms. */
static double cantilever_error(int n_el, const double a[3], int verbose)
{
    const double L = 10.0, r = 0.1, E = 1e10, rho = 1000.0, G = E / 2.6;
    const double A = M_PI * r * r, Iz = M_PI * pow(r, 4) / 4.0;
    const double beta[4] = { 1.87510407, 4.69409113, 7.85475744, 10.99554073 };
    skeleton s;
    fem_model f;
    eigen_result er;
    gale_err err;
    cantilever(&s, n_el, a, L, r);
    CHECK(fem_build(&s, &(fem_material){ E, rho, G }, &f, &err) == GALE_OK);
    CHECK(eigen_lowest(&f, 14, &er, &err) == GALE_OK);
    double fb[14];
    int nb = 0, got_tor = 0;
    double worst = 0.0;
    for (int m = 0; m < er.n_modes; m++) {
        const double hz = sqrt(er.omega2[m]) / (2.0 * M_PI);
        const int type = classify(er.phi + (size_t)m * er.n_dof, f.n_nodes, a);
        if (type == BENDING) {
            fb[nb++] = hz;
        } else if (type == TORSION && !got_tor) {
            got_tor = 1;
            /* Ip = J for a circular section: f = 1/(4L) sqrt(G/ρ) */
            const double ft = 1.0 / (4.0 * L) * sqrt(G * 2 * Iz / (rho * 2 * Iz));
            worst = fmax(worst, fabs(hz / ft - 1.0));
            if (verbose) {
                fprintf(stderr, "  %2d el torsion %.5f Hz (closed %.5f)\n", n_el, hz, ft);
            }
        }
    }
    CHECK(got_tor);
    CHECK(nb >= 8);
    for (int k = 0; k < 4 && 2 * k + 1 < nb; k++) {
        const double fe = beta[k] * beta[k] / (2.0 * M_PI * L * L) * sqrt(E * Iz / (rho * A));
        worst = fmax(worst, fabs(fb[2 * k] / fe - 1.0));
        worst = fmax(worst, fabs(fb[2 * k + 1] / fe - 1.0));
        if (verbose) {
            fprintf(stderr, "  %2d el bending %d: %.5f %.5f Hz (closed %.5f)\n", n_el, k + 1,
                    fb[2 * k], fb[2 * k + 1], fe);
        }
    }
    eigen_result_fini(&er);
    fem_fini(&f);
    skeleton_fini(&s);
    return worst;
}

static void test_cantilever_closed_forms(void)
{
    const double up[3] = { 0, 0, 1 };
    const double n = sqrt(1 + 4 + 9);
    const double oblique[3] = { 1 / n, -2 / n, 3 / n };
    double e10 = cantilever_error(10, up, 0), e20 = cantilever_error(20, up, 0);
    double e40 = cantilever_error(40, up, 1);
    fprintf(stderr, "  max relative error: 10 el %.2e, 20 el %.2e, 40 el %.2e\n", e10, e20, e40);
    CHECK(e40 < 0.005);
    CHECK(e20 < e10);
    CHECK(e40 < e20);
    /* the same beam in an oblique frame */
    CHECK(cantilever_error(40, oblique, 0) < 0.005);
}

static void test_element_matrices(void)
{
    fem_material m = { 0 };
    fem_material_resolve(&m);
    CHECK_NEAR(m.G_pa, 1e10 / 2.6, 1.0);
    double k[144], ms[144];
    const double L = 0.7, r = 0.03;
    fem_element_local(L, r, &m, k, ms);
    for (int i = 0; i < 12; i++) {
        for (int j = 0; j < 12; j++) {
            CHECK(k[i * 12 + j] == k[j * 12 + i]);
            CHECK(ms[i * 12 + j] == ms[j * 12 + i]);
        }
    }
    /* rigid translation along the axis: kinetic energy 2x ½ ρAL */
    double u[12] = { 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0 };
    double e = 0;
    for (int i = 0; i < 12; i++) {
        for (int j = 0; j < 12; j++) {
            e += u[i] * ms[i * 12 + j] * u[j];
        }
    }
    CHECK_NEAR(e, 1000.0 * M_PI * r * r * L, 1e-9);
    /* lateral too (Hermite mass must sum to the same) */
    double w[12] = { 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0 };
    e = 0;
    for (int i = 0; i < 12; i++) {
        for (int j = 0; j < 12; j++) {
            e += w[i] * ms[i * 12 + j] * w[j];
        }
    }
    CHECK_NEAR(e, 1000.0 * M_PI * r * r * L, 1e-9);
}

/* Rigid motions of a whole (unclamped) element in the global frame cost no strain
 * energy: a test of the element matrices and their rotation to the global frame. */
static void test_rigid_body_null_space(void)
{
    skeleton s;
    gale_err err;
    CHECK(skeleton_alloc(&s, 3, &err) == GALE_OK);
    const float p[9] = { 0, 0, 0, 0.3f, -0.2f, 1.1f, 0.9f, 0.4f, 1.5f };
    for (int i = 0; i < 9; i++) {
        s.pos[i] = p[i];
    }
    s.parent[0] = -1, s.parent[1] = 0, s.parent[2] = 1;
    s.radius[0] = 0.05f, s.radius[1] = 0.04f, s.radius[2] = 0.03f;
    fem_model f;
    CHECK(fem_build(&s, NULL, &f, &err) == GALE_OK);
    /* element 2 (node 1 -> 2) is unclamped: K_22 x2 + K_21 x1 = 0 for rigid motion */
    for (int mode = 0; mode < 6; mode++) {
        double x[2][6] = { { 0 } };
        for (int nd = 0; nd < 2; nd++) {
            const double xp[3] = { s.pos[3 * (nd + 1)], s.pos[3 * (nd + 1) + 1], s.pos[3 * (nd + 1) + 2] };
            if (mode < 3) {
                x[nd][mode] = 1.0; /* translation */
            } else {
                double th[3] = { 0 }; /* rotation about the origin: u = θ × x */
                th[mode - 3] = 1.0;
                x[nd][0] = th[1] * xp[2] - th[2] * xp[1];
                x[nd][1] = th[2] * xp[0] - th[0] * xp[2];
                x[nd][2] = th[0] * xp[1] - th[1] * xp[0];
                x[nd][mode] = 1.0;
            }
        }
        /* element-2 contribution to node 2's force: kd[2] (only element 2 ends there) */
        double worst = 0, scale = 0;
        for (int r = 0; r < 6; r++) {
            double y = 0;
            for (int c = 0; c < 6; c++) {
                y += f.kd[36 * 2 + r * 6 + c] * x[1][c] + f.ko[36 * 2 + r * 6 + c] * x[0][c];
                scale = fmax(scale, fabs(f.kd[36 * 2 + r * 6 + c]));
            }
            worst = fmax(worst, fabs(y));
        }
        CHECK(worst < 1e-9 * scale);
    }
    fem_fini(&f);
    skeleton_fini(&s);
}

static void test_symmetric_positive_definite(void)
{
    skeleton s;
    gale_err err;
    CHECK(bake_tree_generate(60, 7, &s, &err) == GALE_OK);
    fem_model f;
    CHECK(fem_build(&s, NULL, &f, &err) == GALE_OK);
    const int nd = f.n_dof;
    double *k = malloc((size_t)nd * nd * sizeof *k), *m = malloc((size_t)nd * nd * sizeof *m);
    fem_dense(&f, k, m);
    double asym_k = 0, asym_m = 0, maxk = 0;
    for (int i = 1; i < f.n_nodes; i++) {
        for (int r = 0; r < 6; r++) {
            for (int c = 0; c < 6; c++) {
                asym_k = fmax(asym_k, fabs(f.kd[36 * i + r * 6 + c] - f.kd[36 * i + c * 6 + r]));
                asym_m = fmax(asym_m, fabs(f.md[36 * i + r * 6 + c] - f.md[36 * i + c * 6 + r]));
                maxk = fmax(maxk, fabs(f.kd[36 * i + r * 6 + c]));
            }
        }
    }
    CHECK(asym_k <= 1e-12 * maxk);
    CHECK(asym_m <= 1e-12);
    /* clamped K and M are positive definite (dense Cholesky) */
    double *kc = malloc((size_t)nd * nd * sizeof *kc);
    for (size_t i = 0; i < (size_t)nd * nd; i++) {
        kc[i] = k[i];
    }
    CHECK(LAPACKE_dpotrf(LAPACK_ROW_MAJOR, 'L', nd, kc, nd) == 0);
    CHECK(LAPACKE_dpotrf(LAPACK_ROW_MAJOR, 'L', nd, m, nd) == 0);
    /* the tree factorisation solves K x = b like the dense one */
    tree_chol c;
    CHECK(tree_chol_factor(&c, f.n_nodes, f.parent, f.kd, f.ko, &err) == GALE_OK);
    double *b = malloc((size_t)nd * sizeof *b), *x = malloc((size_t)nd * sizeof *x);
    double *kx = malloc((size_t)nd * sizeof *kx);
    for (int i = 0; i < nd; i++) {
        b[i] = x[i] = sin(1.3 * i + 0.2);
    }
    tree_chol_solve(&c, x);
    fem_mul_k(&f, x, kx);
    double res = 0, bn = 0;
    for (int i = 0; i < nd; i++) {
        res = fmax(res, fabs(kx[i] - b[i]));
        bn = fmax(bn, fabs(b[i]));
    }
    CHECK(res < 1e-9 * bn);
    /* dense K x agrees with the block product */
    double dk = 0;
    for (int i = 0; i < nd; i++) {
        double y = 0;
        for (int j = 0; j < nd; j++) {
            y += k[(size_t)i * nd + j] * x[j];
        }
        dk = fmax(dk, fabs(y - kx[i]));
    }
    CHECK(dk < 1e-9 * bn);
    /* unclamped: a free-floating pivot is reported, not factored. Drop node 1's own
     * element stiffness so its pivot has nothing holding it. */
    for (int i = 0; i < 36; i++) {
        f.kd[36 * (f.n_nodes - 1) + i] = 0.0;
    }
    tree_chol c2;
    CHECK(tree_chol_factor(&c2, f.n_nodes, f.parent, f.kd, f.ko, &err) == GALE_E_NUMERIC);
    CHECK_STR_HAS(err.msg, "not positive definite");
    tree_chol_fini(&c);
    free(k), free(m), free(kc), free(b), free(x), free(kx);
    fem_fini(&f);
    skeleton_fini(&s);
}

static void test_bad_skeleton(void)
{
    skeleton s;
    gale_err err;
    fem_model f;
    const double up[3] = { 0, 0, 1 };
    cantilever(&s, 3, up, 1.0, 0.1);
    s.pos[3 * 2 + 2] = s.pos[3 * 1 + 2];
    CHECK(fem_build(&s, NULL, &f, &err) == GALE_E_RANGE);
    CHECK_STR_HAS(err.msg, "zero-length");
    s.pos[3 * 2 + 2] = 0.7f;
    s.radius[3] = 0.0f;
    CHECK(fem_build(&s, NULL, &f, &err) == GALE_E_RANGE);
    CHECK_STR_HAS(err.msg, "radius");
    skeleton_fini(&s);
}

int main(void)
{
    RUN(test_element_matrices);
    RUN(test_rigid_body_null_space);
    RUN(test_symmetric_positive_definite);
    RUN(test_cantilever_closed_forms);
    RUN(test_bad_skeleton);
    return check_report();
}
