/* The wind projection basis (server/basis.c, Diener 2008 section 4) against a brute-force
 * fine quadrature of the coordinate-free element interpolation, and against the closed
 * form C D ∫ φ dx of a cantilever's first bending pair. */
#include <math.h>
#include <stdlib.h>

#include "bake_tree.h"
#include "basis.h"
#include "check.h"
#include "crown_load.h"
#include "eigen.h"
#include "fem.h"

/* Displacement at ξ of the element parent -> i in the global frame without any element
 * frame: axial part linear; lateral part Hermite with end slopes θ × e_x. */
static void interp(const fem_model *f, const double *x, int i, double xi, double out[3])
{
    const int p = f->parent[i];
    const double zero[6] = { 0 };
    const double *a = p > 0 ? x + FEM_DOF(p) : zero, *b = x + FEM_DOF(i);
    const double *e = f->frame + 9 * i, L = f->len_m[i];
    const double n1 = 1 - 3 * xi * xi + 2 * xi * xi * xi, n3 = 3 * xi * xi - 2 * xi * xi * xi;
    const double n2 = xi - 2 * xi * xi + xi * xi * xi, n4 = xi * xi * xi - xi * xi;
    const double ta[3] = { a[4] * e[2] - a[5] * e[1], a[5] * e[0] - a[3] * e[2],
                           a[3] * e[1] - a[4] * e[0] };
    const double tb[3] = { b[4] * e[2] - b[5] * e[1], b[5] * e[0] - b[3] * e[2],
                           b[3] * e[1] - b[4] * e[0] };
    const double aa = a[0] * e[0] + a[1] * e[1] + a[2] * e[2];
    const double ba = b[0] * e[0] + b[1] * e[1] + b[2] * e[2];
    for (int k = 0; k < 3; k++) {
        const double pa = a[k] - aa * e[k], pb = b[k] - ba * e[k];
        out[k] = ((1 - xi) * aa + xi * ba) * e[k] + n1 * pa + n3 * pb + L * (n2 * ta[k] + n4 * tb[k]);
    }
}

static void test_fine_quadrature(void)
{
    skeleton s;
    gale_err err;
    fem_model f;
    eigen_result er;
    CHECK(bake_tree_generate(80, 3, &s, &err) == GALE_OK);
    CHECK(fem_build(&s, NULL, &f, &err) == GALE_OK);
    CHECK(eigen_lowest(&f, 8, &er, &err) == GALE_OK);
    const double C = 0.6;
    double p[8 * 3];
    basis_compute(&f, er.phi, 8, C, NULL, p);
    const int steps = 2000;
    for (int m = 0; m < 8; m++) {
        double acc[3] = { 0, 0, 0 }, scale = 0;
        for (int i = 1; i < f.n_nodes; i++) {
            const double d = 2.0 * f.radius_m[i], h = f.len_m[i] / steps;
            for (int k = 0; k < steps; k++) {
                double u[3];
                interp(&f, er.phi + (size_t)m * er.n_dof, i, (k + 0.5) / steps, u);
                for (int c = 0; c < 3; c++) {
                    acc[c] += C * d * h * u[c];
                }
            }
        }
        for (int c = 0; c < 3; c++) {
            scale = fmax(scale, fabs(acc[c]));
        }
        for (int c = 0; c < 3; c++) {
            CHECK_NEAR(p[3 * m + c], acc[c], 1e-6 * scale);
        }
    }
    eigen_result_fini(&er);
    fem_fini(&f);
    skeleton_fini(&s);
}

static void test_cantilever_closed_form(void)
{
    const int n_el = 40;
    const double L = 4.0, r = 0.05, rho = 1000.0, C = 0.6, A = M_PI * r * r;
    skeleton s;
    gale_err err;
    CHECK(skeleton_alloc(&s, n_el + 1, &err) == GALE_OK);
    for (int i = 0; i <= n_el; i++) {
        s.parent[i] = i - 1;
        s.pos[3 * i + 2] = (float)(L * i / n_el);
        s.radius[i] = (float)r;
    }
    fem_model f;
    eigen_result er;
    CHECK(fem_build(&s, NULL, &f, &err) == GALE_OK);
    CHECK(eigen_lowest(&f, 2, &er, &err) == GALE_OK);
    double p[6];
    basis_compute(&f, er.phi, 2, C, NULL, p);
    /* analytic first mode φ(x), normalised so that ρA ∫ φ² dx = 1 */
    const double bl = 1.87510407, be = bl / L;
    const double sg = (cosh(bl) + cos(bl)) / (sinh(bl) + sin(bl));
    double i1 = 0, i2 = 0;
    const int steps = 100000;
    for (int k = 0; k < steps; k++) {
        const double x = (k + 0.5) * L / steps;
        const double ph = cosh(be * x) - cos(be * x) - sg * (sinh(be * x) - sin(be * x));
        i1 += ph * L / steps;
        i2 += ph * ph * L / steps;
    }
    const double expect = C * 2 * r * fabs(i1) / sqrt(rho * A * i2);
    /* the pair is degenerate and spans both bending planes: each plane's mode loads
     * along its own direction with C D ∫ φ dx, so the norm over the pair is √2 that */
    const double got = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2] + p[3] * p[3] + p[4] * p[4] +
                            p[5] * p[5]);
    CHECK_NEAR(got, sqrt(2.0) * expect, 1e-4 * expect);
    CHECK_NEAR(p[2], 0.0, 1e-9 * expect); /* bending modes do not load along the axis */
    CHECK_NEAR(p[5], 0.0, 1e-9 * expect);
    eigen_result_fini(&er);
    fem_fini(&f);
    skeleton_fini(&s);
}

/* ASSET.md "Wind basis", its test vector: a 3-node skeleton (root (0,0,0) r 0.2, node 1
 * (0,0,2) r 0.1, node 2 (1,0,2) r 0.05), C 0.6, leaf share 0.6 (wood 0.4, tip 0.27 m²),
 * and four displacement fields in place of modes, each worked out by hand in the spec:
 * every free node moved by x̂; node 2 moved by ŷ; node 2 turned about z; node 1 turned
 * about y. */
static void test_spec_vector(void)
{
    int parent[3] = { -1, 0, 1 };
    float pos[9] = { 0, 0, 0, 0, 0, 2, 1, 0, 2 }, radius[3] = { 0.2f, 0.1f, 0.05f };
    skeleton s = { .n = 3, .parent = parent, .pos = pos, .radius = radius };
    gale_err err;
    fem_model f;
    CHECK(fem_build(&s, NULL, &f, &err) == GALE_OK);
    const crown_load cl = crown_load_split(3, parent, pos, radius, 0.6);
    CHECK_NEAR(cl.wood, 0.4, 1e-12);
    CHECK_NEAR(cl.tip_m2, 0.27, 1e-7); /* radii in f32 */
    /* free dofs: node 1 at 0..5, node 2 at 6..11 (ux uy uz rx ry rz) */
    double phi[4][12] = { { 0 } };
    phi[0][0] = phi[0][6] = 1.0;
    phi[1][7] = 1.0;
    phi[2][11] = 1.0;
    phi[3][4] = 1.0;
    double p[12];
    CHECK(basis_compute(&f, &phi[0][0], 4, 0.6, &cl, p) == 0);
    const double want[12] = { 0.27, 0, 0, 0, 0.18, 0, 0, -0.003, 0, -0.024, 0, -0.003 };
    for (int k = 0; k < 12; k++) {
        CHECK_NEAR(p[k], want[k], 1e-7);
    }
    fem_fini(&f);
}

int main(void)
{
    RUN(test_spec_vector);
    RUN(test_fine_quadrature);
    RUN(test_cantilever_closed_form);
    return check_report();
}
