/* The sparse shift-invert eigen path (server/eigen.c): against a dense LAPACK solve of
 * the same model, M-orthonormality to 1e-8, residuals, determinism, bad requests. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <lapacke.h>

#include "bake_tree.h"
#include "check.h"
#include "eigen.h"
#include "fem.h"

static void test_against_dense(void)
{
    skeleton s;
    gale_err err;
    fem_model f;
    eigen_result er;
    CHECK(bake_tree_generate(70, 11, &s, &err) == GALE_OK);
    CHECK(fem_build(&s, NULL, &f, &err) == GALE_OK);
    CHECK(eigen_lowest(&f, 12, &er, &err) == GALE_OK);
    CHECK(!er.dense);
    const int nd = f.n_dof;
    double *k = malloc((size_t)nd * nd * sizeof *k), *m = malloc((size_t)nd * nd * sizeof *m);
    double *w = malloc((size_t)nd * sizeof *w);
    fem_dense(&f, k, m);
    CHECK(LAPACKE_dsygv(LAPACK_ROW_MAJOR, 1, 'N', 'U', nd, k, nd, m, nd, w) == 0);
    for (int i = 0; i < 12; i++) {
        CHECK_NEAR(er.omega2[i], w[i], 1e-9 * w[i]);
        if (i > 0) {
            CHECK(er.omega2[i] >= er.omega2[i - 1]);
        }
    }
    CHECK(er.ortho_error < 1e-8);
    CHECK(er.max_residual < 1e-8);
    fprintf(stderr, "  70 nodes: %d restarts, %d solves, residual %.2e, ortho %.2e\n",
            er.iterations, er.n_op, er.max_residual, er.ortho_error);
    free(k), free(m), free(w);
    eigen_result_fini(&er);
    fem_fini(&f);
    skeleton_fini(&s);
}

static void test_large_orthonormal_deterministic(void)
{
    skeleton s;
    gale_err err;
    fem_model f;
    eigen_result a, b;
    CHECK(bake_tree_generate(1200, 5, &s, &err) == GALE_OK);
    CHECK(fem_build(&s, NULL, &f, &err) == GALE_OK);
    CHECK(eigen_lowest(&f, 32, &a, &err) == GALE_OK);
    CHECK(eigen_lowest(&f, 32, &b, &err) == GALE_OK);
    /* independent M-orthonormality check (not the solver's own figure) */
    const int nd = f.n_dof;
    double *mx = malloc((size_t)nd * sizeof *mx), worst = 0;
    for (int i = 0; i < 32; i++) {
        fem_mul_m(&f, a.phi + (size_t)i * nd, mx);
        for (int j = 0; j < 32; j++) {
            double d = 0;
            for (int c = 0; c < nd; c++) {
                d += a.phi[(size_t)j * nd + c] * mx[c];
            }
            worst = fmax(worst, fabs(d - (i == j)));
        }
    }
    CHECK(worst < 1e-8);
    CHECK(a.max_residual < 1e-8);
    CHECK(memcmp(a.phi, b.phi, (size_t)32 * nd * sizeof *a.phi) == 0);
    CHECK(memcmp(a.omega2, b.omega2, 32 * sizeof *a.omega2) == 0);
    /* a 10 m tree: the first frequency in the range real trees have (0.2..3 Hz) */
    const double f1 = sqrt(a.omega2[0]) / (2 * M_PI);
    CHECK(f1 > 0.2 && f1 < 3.0);
    fprintf(stderr, "  1200 nodes: f1 %.3f Hz, ortho %.2e, residual %.2e\n", f1, worst,
            a.max_residual);
    free(mx);
    eigen_result_fini(&a);
    eigen_result_fini(&b);
    fem_fini(&f);
    skeleton_fini(&s);
}

static void test_small_dense_path_and_bad_requests(void)
{
    skeleton s;
    gale_err err;
    fem_model f;
    eigen_result er;
    CHECK(bake_tree_generate(5, 1, &s, &err) == GALE_OK);
    CHECK(fem_build(&s, NULL, &f, &err) == GALE_OK);
    CHECK(eigen_lowest(&f, 6, &er, &err) == GALE_OK);
    CHECK(er.dense);
    CHECK(er.ortho_error < 1e-8);
    eigen_result_fini(&er);
    CHECK(eigen_lowest(&f, 24, &er, &err) == GALE_E_RANGE);
    CHECK_STR_HAS(err.msg, "24 modes requested, expected 1..23");
    CHECK(eigen_lowest(&f, 0, &er, &err) == GALE_E_RANGE);
    fem_fini(&f);
    skeleton_fini(&s);
}

int main(void)
{
    RUN(test_against_dense);
    RUN(test_large_orthonormal_deterministic);
    RUN(test_small_dense_path_and_bad_requests);
    return check_report();
}
