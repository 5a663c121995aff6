/* The length-true pose (protocol/asset_pose.c, PHYSICS.md "Length-true pose") graded by
 * this file's own combined-mode computation, not by the bake's figures: on each shipped
 * species at 32 modes, a static wind pose of all modes keeps branch lengths within 1 % at
 * 20 % of height deflection, and at 0.1 % of height the pose is within 0.1 % of the linear
 * modal response Σ q φ; the fields' slope at q = 0 is φ exactly. On a hand-built L frame
 * every mode alone, axial and torsional ones included, has the linear mode as its slope. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bake.h"
#include "check.h"
#include "lsystem.h"
#include "species.h"

/* q_i = p_i·dir / ω_i² : the static response to a unit steady wind along dir */
static void static_q(const asset *a, const double dir[3], double *q)
{
    for (uint32_t m = 0; m < a->n_modes; m++) {
        const float *p = a->wind_basis + 3 * m;
        const double w = (double)a->omega[m];
        q[m] = ((double)p[0] * dir[0] + (double)p[1] * dir[1] + (double)p[2] * dir[2]) / (w * w);
    }
}

/* u = Σ q φ [3n], returns max |u_i| */
static double linear(const asset *a, const double *q, uint32_t only, double *u)
{
    const size_t nc = 3 * (size_t)a->n_nodes;
    memset(u, 0, nc * sizeof *u);
    for (uint32_t m = 0; m < a->n_modes; m++) {
        if (only != UINT32_MAX && m != only) {
            continue;
        }
        for (size_t c = 0; c < nc; c++) {
            u[c] += q[m] * (double)a->phi[m * nc + c];
        }
    }
    double mx = 0.0;
    for (uint32_t i = 0; i < a->n_nodes; i++) {
        mx = fmax(mx, sqrt(u[3 * i] * u[3 * i] + u[3 * i + 1] * u[3 * i + 1] +
                           u[3 * i + 2] * u[3 * i + 2]));
    }
    return mx;
}

static double length_change(const asset *a, const float *x)
{
    double worst = 0.0;
    for (uint32_t i = 1; i < a->n_nodes; i++) {
        const int32_t p = a->parent[i];
        double l0 = 0, l1 = 0;
        for (int k = 0; k < 3; k++) {
            const double s0 = (double)a->rest[3 * i + k] - (double)a->rest[3 * p + k];
            const double s1 = (double)x[3 * i + k] - (double)x[3 * p + k];
            l0 += s0 * s0, l1 += s1 * s1;
        }
        worst = fmax(worst, fabs(sqrt(l1 / l0) - 1.0));
    }
    return worst;
}

/* max |pose − rest − u| / max |u| for modal state k q */
static double small_q_error(const asset *a, const double *q, double k, uint32_t only)
{
    const size_t nc = 3 * (size_t)a->n_nodes;
    double *qs = calloc(a->n_modes, sizeof *qs), *u = malloc(nc * sizeof *u);
    float *qf = calloc(a->n_modes, sizeof *qf), *x = malloc(nc * sizeof *x);
    for (uint32_t m = 0; m < a->n_modes; m++) {
        qs[m] = only == UINT32_MAX || m == only ? k * q[m] : 0.0;
        qf[m] = (float)qs[m];
        qs[m] = (double)qf[m]; /* grade the q the pose sees */
    }
    const double umax = linear(a, qs, UINT32_MAX, u);
    asset_reconstruct(a, qf, a->n_modes, x);
    double e = 0.0;
    for (uint32_t i = 0; i < a->n_nodes; i++) {
        double d2 = 0.0;
        for (int c = 0; c < 3; c++) {
            const double d = (double)x[3 * i + c] - (double)a->rest[3 * i + c] - u[3 * i + c];
            d2 += d * d;
        }
        e = fmax(e, sqrt(d2));
    }
    free(qs), free(u), free(qf), free(x);
    return umax > 0.0 ? e / umax : 0.0;
}

/* mode m alone: max |(x(kq) − x(−kq)) / 2 − k φ| / max |k φ| */
static double slope_error(const asset *a, double k, uint32_t m)
{
    const size_t nc = 3 * (size_t)a->n_nodes;
    float *qf = calloc(a->n_modes, sizeof *qf), *xp = malloc(nc * sizeof *xp), *xm = malloc(nc * sizeof *xm);
    qf[m] = (float)k;
    asset_reconstruct(a, qf, a->n_modes, xp);
    qf[m] = (float)-k;
    asset_reconstruct(a, qf, a->n_modes, xm);
    const double kq = (double)(float)k;
    double e = 0.0, umax = 0.0;
    for (uint32_t i = 0; i < a->n_nodes; i++) {
        double d2 = 0.0, u2 = 0.0;
        for (int c = 0; c < 3; c++) {
            const double u = kq * (double)a->phi[m * nc + 3 * i + c];
            const double d = 0.5 * ((double)xp[3 * i + c] - (double)xm[3 * i + c]) - u;
            d2 += d * d, u2 += u * u;
        }
        e = fmax(e, sqrt(d2)), umax = fmax(umax, sqrt(u2));
    }
    free(qf), free(xp), free(xm);
    return umax > 0.0 ? e / umax : 0.0;
}

/* slope_error against the drawn shapes sh instead of the asset's φ */
static double slope_error_shapes(asset *a, float *sh, double k, uint32_t m)
{
    float *phi = a->phi;
    a->phi = sh;
    const double e = slope_error(a, k, m);
    a->phi = phi;
    return e;
}

static int bake_species(const char *name, asset *a)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/configs/species/%s.json", GALE_SOURCE_DIR, name);
    gale_err err;
    memset(&err, 0, sizeof err);
    species sp;
    skeleton s;
    memset(&s, 0, sizeof s);
    int rc = species_load(path, &sp, &err);
    if (rc == GALE_OK) {
        rc = lsystem_generate(&sp.gen, &s, &err);
    }
    bake_desc d = { .n_modes = 32 };
    if (rc == GALE_OK) {
        rc = bake_run(&s, &sp, &d, a, NULL, &err);
    }
    if (rc != GALE_OK) {
        fprintf(stderr, "%s: %s\n", name, err.msg);
    }
    skeleton_fini(&s);
    return rc;
}

static void grade_species(const char *name)
{
    asset a;
    memset(&a, 0, sizeof a);
    CHECK(bake_species(name, &a) == GALE_OK);
    if (!a.n_nodes) {
        return;
    }
    /* the pose's slope at q = 0 is the drawn shape φ̂ (φ with the static correction,
     * asset_pose_shapes): the linear response below is graded against it */
    float *shapes = malloc((size_t)a.n_modes * a.n_nodes * 3 * sizeof *shapes);
    asset_pose_shapes(&a, shapes);
    free(a.phi);
    a.phi = shapes;
    const size_t nc = 3 * (size_t)a.n_nodes;
    double *q = malloc(a.n_modes * sizeof *q), *u = malloc(nc * sizeof *u);
    float *qf = malloc(a.n_modes * sizeof *qf), *x = malloc(nc * sizeof *x), *xl = malloc(nc * sizeof *xl);
    const double h = (double)a.height_m;
    const double dirs[2][3] = { { 1, 0, 0 }, { 0.6, 0.8, 0 } };
    for (int dd = 0; dd < 2; dd++) {
        static_q(&a, dirs[dd], q);
        const double u1 = linear(&a, q, UINT32_MAX, u);
        CHECK(u1 > 0.0);
        const double fr[2] = { 0.2, 0.1 };
        for (int f = 0; f < 2; f++) {
            const double k = fr[f] * h / u1;
            for (uint32_t m = 0; m < a.n_modes; m++) {
                qf[m] = (float)(k * q[m]);
            }
            asset_reconstruct(&a, qf, a.n_modes, x);
            for (size_t c = 0; c < nc; c++) {
                xl[c] = (float)((double)a.rest[c] + k * u[c]);
            }
            const double el = length_change(&a, xl), ep = length_change(&a, x);
            printf("%s dir %d at %.0f%% of height: branch length change linear %.3f%%, "
                   "pose %.4f%%\n",
                   name, dd, 100.0 * fr[f], 100.0 * el, 100.0 * ep);
            CHECK(ep <= 0.01);
        }
        const double e1 = small_q_error(&a, q, 1e-3 * h / u1, UINT32_MAX);
        printf("%s dir %d at 0.1%% of height: |pose - linear| / |linear| = %.4f%%\n", name, dd,
               100.0 * e1);
        /* the pose's second-order part is about θ/2 of the largest segment rotation θ: the
         * twigs' own bend under the leaves' load (the static correction) turns their short
         * segments most, 0.30 % on pine at 0.1 % of height (0.07 % without it) */
        CHECK(e1 <= 4e-3);
    }
    /* slope at q = 0: v × s + w = φ_i − φ_p, every mode and segment */
    double worst = 0.0, scale = 0.0;
    for (uint32_t m = 0; m < a.n_modes; m++) {
        const float *ph = a.phi + m * nc, *v = a.corr_v + m * nc, *w = a.corr_w + m * nc;
        CHECK(a.corr_b[m] == 0.0f || fabs((double)a.corr_a[m] * (double)a.corr_b[m] - 1.0) < 1e-6);
        for (uint32_t i = 1; i < a.n_nodes; i++) {
            const int32_t p = a.parent[i];
            double s[3], d[3];
            for (int k = 0; k < 3; k++) {
                s[k] = (double)a.rest[3 * i + k] - (double)a.rest[3 * p + k];
                d[k] = (double)ph[3 * i + k] - (double)ph[3 * p + k];
                scale = fmax(scale, fabs(d[k]));
            }
            const double vx = v[3 * i], vy = v[3 * i + 1], vz = v[3 * i + 2];
            const double r[3] = { vy * s[2] - vz * s[1] + (double)w[3 * i],
                                  vz * s[0] - vx * s[2] + (double)w[3 * i + 1],
                                  vx * s[1] - vy * s[0] + (double)w[3 * i + 2] };
            for (int k = 0; k < 3; k++) {
                worst = fmax(worst, fabs(r[k] - d[k]));
            }
        }
    }
    printf("%s slope at q = 0: max |v x s + w - dphi| = %.3g (max |dphi| %.3g)\n", name, worst,
           scale);
    CHECK(worst <= 1e-5 * scale);
    free(q), free(u), free(qf), free(x), free(xl);
    asset_fini(&a);
}

static void test_oak(void)
{
    grade_species("oak");
}
static void test_pine(void)
{
    grade_species("pine");
}
static void test_palm(void)
{
    grade_species("palm");
}

/* An L frame: a 4 m vertical stem with a 2 m horizontal arm at the top. All its modes,
 * the stem's axial and torsional ones among them (torsion swings the arm), each alone at
 * small q follow the linear response. */
static void test_l_frame_every_mode(void)
{
    skeleton s;
    gale_err err;
    memset(&err, 0, sizeof err);
    const int n = 13;
    CHECK(skeleton_alloc(&s, n, &err) == GALE_OK);
    for (int i = 0; i < n; i++) {
        s.parent[i] = i - 1;
        s.radius[i] = 0.05f;
        if (i <= 8) {
            s.pos[3 * i + 2] = 0.5f * (float)i;
        } else {
            s.pos[3 * i] = 0.5f * (float)(i - 8);
            s.pos[3 * i + 2] = 4.0f;
        }
    }
    species sp;
    species_default(&sp);
    asset a;
    memset(&a, 0, sizeof a);
    const int nm = 24;
    CHECK(bake_run(&s, &sp, &(bake_desc){ .n_modes = nm }, &a, NULL, &err) == GALE_OK);
    float *shapes = malloc((size_t)a.n_modes * a.n_nodes * 3 * sizeof *shapes);
    asset_pose_shapes(&a, shapes);
    int axial = 0, torsion = 0;
    const size_t nc = 3 * (size_t)n;
    for (uint32_t m = 0; m < a.n_modes; m++) {
        const float *ph = a.phi + m * nc, *pr = a.phi_rot + m * nc;
        /* a stem mode with vertical motion at the arm's joint: axial; with rotation about z
         * at the joint dominating: torsion */
        const double dz = fabs(ph[3 * 8 + 2]), dxy = hypot(ph[3 * 8], ph[3 * 8 + 1]);
        const double rz = fabs(pr[3 * 4 + 2]), rxy = hypot(pr[3 * 4], pr[3 * 4 + 1]);
        axial += dz > 3.0 * dxy;
        torsion += rz > 3.0 * rxy;
        /* the mode's largest segment rotation per unit q, |Δ⊥| / |s| */
        double rmax = 0.0, umax = 0.0;
        for (int i = 1; i < n; i++) {
            const int p = s.parent[i];
            double sg[3], d[3], l2 = 0.0, sd = 0.0, d2 = 0.0;
            for (int c = 0; c < 3; c++) {
                sg[c] = (double)s.pos[3 * i + c] - (double)s.pos[3 * p + c];
                d[c] = (double)ph[3 * i + c] - (double)ph[3 * p + c];
                l2 += sg[c] * sg[c], sd += sg[c] * d[c], d2 += d[c] * d[c];
            }
            rmax = fmax(rmax, sqrt(fmax(d2 - sd * sd / l2, 0.0) / l2));
            const double u0 = ph[3 * i], u1 = ph[3 * i + 1], u2 = ph[3 * i + 2];
            umax = fmax(umax, sqrt(u0 * u0 + u1 * u1 + u2 * u2));
        }
        /* symmetric difference (x(q) − x(−q)) / 2 has no second-order term, so at 0.01 rad
         * of largest segment rotation (or 4 cm of largest displacement for a mode without
         * rotation) it is the slope to ~1e-5 */
        const double k1 = rmax * 0.04 > 1e-2 * umax ? 1e-2 / rmax : 0.04 / umax;
        /* the pose's slope is the drawn shape φ̂ (φ with the static correction) */
        const double es = slope_error_shapes(&a, shapes, k1, m);
        if (!(es <= 1e-3)) {
            fprintf(stderr, "L frame mode %u: slope error %.4g\n", m, es);
        }
        CHECK(es <= 1e-3);
    }
    printf("L frame: %d axial-dominated and %d torsion-dominated modes of %u\n", axial, torsion,
           a.n_modes);
    CHECK(axial >= 1 && torsion >= 1);
    free(shapes);
    asset_fini(&a);
    skeleton_fini(&s);
}

int main(void)
{
    RUN(test_l_frame_every_mode);
    RUN(test_oak);
    RUN(test_pine);
    RUN(test_palm);
    return check_report();
}
