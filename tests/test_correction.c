/* Strong-wind correction (server/correction.c, Diener 2008 section 5.2): poses keep
 * branch lengths, the fit reproduces the linear mode at small q, and it reduces the
 * branch-length error at the stated amplitude. */
#include <math.h>
#include <stdlib.h>

#include "bake_tree.h"
#include "check.h"
#include "correction.h"
#include "eigen.h"
#include "fem.h"

static void run_tree(int n, int nm, double *lin, double *cor)
{
    skeleton s;
    gale_err err;
    fem_model f;
    eigen_result er;
    CHECK(bake_tree_generate(n, 9, &s, &err) == GALE_OK);
    CHECK(fem_build(&s, NULL, &f, &err) == GALE_OK);
    CHECK(eigen_lowest(&f, nm, &er, &err) == GALE_OK);
    double *tr = malloc((size_t)nm * n * 3 * sizeof *tr);
    double *rot = malloc((size_t)nm * n * 3 * sizeof *rot);
    double *rest = malloc((size_t)n * 3 * sizeof *rest);
    for (int i = 0; i < 3 * n; i++) {
        rest[i] = s.pos[i];
    }
    fem_split_modes(&f, er.phi, nm, tr, rot);
    corr_result cr;
    CHECK(corr_fit(rest, f.parent, n, tr, rot, nm, NULL, &cr, &err) == GALE_OK);
    CHECK(cr.err_pose < 1e-9);
    CHECK_NEAR(cr.amp_rot_rad, 0.35, 0);
    /* small q: q̃ v + q̃² w ≈ q φ (relative to the mode's largest translation), 5% */
    for (int m = 0; m < nm; m++) {
        const double q = 1e-3 * cr.q_amp[m];
        const double qt = cr.a[m] * atan(cr.b[m] * q);
        double worst = 0, big = 0;
        for (int c = 0; c < 3 * n; c++) {
            const double u = qt * cr.v[(size_t)m * 3 * n + c] + qt * qt * cr.w[(size_t)m * 3 * n + c];
            worst = fmax(worst, fabs(u - q * tr[(size_t)m * 3 * n + c]));
            big = fmax(big, fabs(q * tr[(size_t)m * 3 * n + c]));
        }
        /* the poses rotate segments by the mean of their nodes' rotations, whose first
         * order term matches the Hermite φ to the element's discretisation error; the
         * least-squares fit over the whole range adds a little more */
        CHECK(worst < 0.05 * big);
    }
    *lin = cr.err_linear;
    *cor = cr.err_corrected;
    corr_result_fini(&cr);
    free(tr), free(rot), free(rest);
    eigen_result_fini(&er);
    fem_fini(&f);
    skeleton_fini(&s);
}

static void test_reduces_length_error(void)
{
    double lin, cor;
    run_tree(400, 16, &lin, &cor);
    fprintf(stderr, "  400 nodes, 16 modes, 0.35 rad: length error linear %.4f, corrected %.4f\n",
            lin, cor);
    CHECK(lin > 0.02);  /* the linear modes do stretch at this amplitude */
    CHECK(cor < 0.5 * lin);
}

static void test_bad_desc(void)
{
    corr_result cr;
    gale_err err;
    const double rest[6] = { 0, 0, 0, 0, 0, 1 }, z[6] = { 0 };
    const int parent[2] = { -1, 0 };
    CHECK(corr_fit(rest, parent, 2, z, z, 1, &(corr_desc){ .n_samples = 4 }, &cr, &err) ==
          GALE_E_RANGE);
    CHECK_STR_HAS(err.msg, "n_samples 4");
}

int main(void)
{
    RUN(test_reduces_length_error);
    RUN(test_bad_desc);
    return check_report();
}
