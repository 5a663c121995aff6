/* The bake pipeline: frame model (fem.c), shift-invert modes (eigen.c), Rayleigh damping
 * γ_i = α + β ω_i² (Diener 2008 eq. 9), wind basis (basis.c, section 4), the static
 * correction of the truncated modes (statics.c, PHYSICS.md "Static correction"), the
 * length-true pose's fields (asset_pose_fields, PHYSICS.md "Length-true pose"), mesh
 * (mesh.h); everything the asset holds. */
#include "bake.h"
#include "mono.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "basis.h"
#include "eigen.h"
#include "fem.h"
#include "mesh.h"
#include "statics.h"

uint64_t bake_hash(uint64_t h, const void *data, size_t n)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < n; i++) {
        h ^= p[i];
        h *= 0x100000001b3ull;
    }
    return h;
}

static float *to_float(const double *x, size_t n)
{
    float *y = malloc((n ? n : 1) * sizeof *y);
    if (y) {
        for (size_t i = 0; i < n; i++) {
            y[i] = (float)x[i];
        }
    }
    return y;
}

int bake_run(const skeleton *s, const species *sp, const bake_desc *d, asset *a,
             bake_report *rep, gale_err *err)
{
    const double t0 = mono_s();
    bake_desc bd = d ? *d : (bake_desc){ 0 };
    bake_report r;
    memset(&r, 0, sizeof r);
    memset(a, 0, sizeof *a);
    if (bd.n_modes == 0) {
        bd.n_modes = 32;
    }
    if (bd.n_modes < 1 || bd.n_modes > BAKE_MAX_MODES) {
        return gale_errf(err, GALE_E_RANGE, "bake: %d modes, expected 1..%d", bd.n_modes,
                         BAKE_MAX_MODES);
    }
    const int n = s->n, nm = bd.n_modes;
    if (n < 2) {
        return gale_errf(err, GALE_E_RANGE, "bake: skeleton has %d nodes, expected at least 2",
                         n);
    }
    if (6 * (n - 1) <= nm) {
        return gale_errf(err, GALE_E_RANGE,
                         "bake: %d modes requested but a %d-node skeleton has only %d degrees "
                         "of freedom",
                         nm, n, 6 * (n - 1));
    }
    fem_model f;
    eigen_result er;
    memset(&er, 0, sizeof er);
    double *tr = NULL, *rot = NULL, *rest = NULL, *p = NULL, *F = NULL, *res = NULL;
    double *rtr = NULL, *rrot = NULL;
    float *shape = NULL;
    int rc = fem_build(s, &(fem_material){ sp->E_pa, sp->rho_kg_m3, sp->G_pa }, &f, err);
    if (rc != GALE_OK) {
        return rc;
    }
    for (int i = 1; i < n; i++) {
        r.mass_kg += f.mat.rho_kg_m3 * M_PI * f.radius_m[i] * f.radius_m[i] * f.len_m[i];
    }
    const double t1 = mono_s();
    rc = eigen_lowest(&f, nm, &er, err);
    if (rc != GALE_OK) {
        goto fail;
    }
    const double t2 = mono_s();
    tr = malloc((size_t)nm * n * 3 * sizeof *tr);
    rot = malloc((size_t)nm * n * 3 * sizeof *rot);
    rest = malloc((size_t)n * 3 * sizeof *rest);
    p = malloc((size_t)nm * 3 * sizeof *p);
    F = malloc((size_t)f.n_dof * 3 * sizeof *F);
    res = malloc((size_t)f.n_dof * 3 * sizeof *res);
    rtr = malloc((size_t)n * 9 * sizeof *rtr);
    rrot = malloc((size_t)n * 9 * sizeof *rrot);
    shape = malloc((size_t)nm * n * 3 * sizeof *shape);
    if (!tr || !rot || !rest || !p || !F || !res || !rtr || !rrot || !shape) {
        rc = gale_errf(err, GALE_E_NOMEM, "bake: out of memory for %d modes x %d nodes", nm, n);
        goto fail;
    }
    fem_split_modes(&f, er.phi, nm, tr, rot);
    /* the leaves' share of the drag at the tips, where the mesh puts the leaves */
    const crown_load cl = crown_load_split((uint32_t)n, s->parent, s->pos, s->radius,
                                           sp->leaves_per_tip > 0 ? sp->damage.leaf_drag_share
                                                                  : 0.0);
    if (basis_load(&f, sp->drag_c, &cl, F) != 0) {
        rc = gale_errf(err, GALE_E_NOMEM, "bake: out of memory for the wind basis");
        goto fail;
    }
    basis_project(&f, er.phi, nm, F, p); /* F serves the static correction below too */
    const double t3 = mono_s();
    for (int i = 0; i < 3 * n; i++) {
        rest[i] = (double)s->pos[i];
    }

    /* the asset */
    snprintf(a->species, sizeof a->species, "%s", sp->name);
    a->source_hash = bd.source_hash;
    a->params_json = strdup(bd.params_json ? bd.params_json : "{}");
    a->n_nodes = (uint32_t)n;
    a->parent = malloc((size_t)n * sizeof *a->parent);
    a->rest = malloc((size_t)n * 3 * sizeof *a->rest);
    a->radius = malloc((size_t)n * sizeof *a->radius);
    /* a CSV skeleton's ids, so each asset node can be traced to its row (ASSET.md SRID) */
    if (s->src_id) {
        a->source_id = malloc((size_t)n * sizeof *a->source_id);
        if (!a->source_id) {
            rc = gale_errf(err, GALE_E_NOMEM, "bake: out of memory filling the asset");
            goto fail;
        }
        for (int i = 0; i < n; i++) {
            a->source_id[i] = (uint32_t)s->src_id[i];
        }
        memcpy(a->source_origin, s->src_origin, sizeof a->source_origin);
    }
    a->n_modes = (uint32_t)nm;
    a->omega = malloc((size_t)nm * sizeof *a->omega);
    a->gamma = malloc((size_t)nm * sizeof *a->gamma);
    a->corr_a = malloc((size_t)nm * sizeof *a->corr_a);
    a->corr_b = malloc((size_t)nm * sizeof *a->corr_b);
    a->wind_basis = to_float(p, (size_t)nm * 3);
    a->phi = to_float(tr, (size_t)nm * n * 3);
    a->phi_rot = to_float(rot, (size_t)nm * n * 3);
    a->corr_v = malloc((size_t)nm * n * 3 * sizeof *a->corr_v);
    a->corr_w = malloc((size_t)nm * n * 3 * sizeof *a->corr_w);
    if (!a->params_json || !a->parent || !a->rest || !a->radius || !a->omega || !a->gamma ||
        !a->wind_basis || !a->phi || !a->phi_rot || !a->corr_v || !a->corr_w || !a->corr_a ||
        !a->corr_b) {
        rc = gale_errf(err, GALE_E_NOMEM, "bake: out of memory filling the asset");
        goto fail;
    }
    a->height_m = 0.0f;
    for (int i = 0; i < n; i++) {
        a->parent[i] = s->parent[i];
        a->radius[i] = s->radius[i];
        for (int k = 0; k < 3; k++) {
            a->rest[3 * i + k] = s->pos[3 * i + k];
        }
        if (s->pos[3 * i + 2] > a->height_m) {
            a->height_m = s->pos[3 * i + 2];
        }
    }
    for (int m = 0; m < nm; m++) {
        a->corr_a[m] = 1.0f;
        a->corr_b[m] = 0.0f;
        const double w = sqrt(er.omega2[m]);
        a->omega[m] = (float)w;
        /* Diener 2008 eq. 9: γ_i = α + β ω_i² */
        a->gamma[m] = (float)(sp->rayleigh_alpha + sp->rayleigh_beta * er.omega2[m]);
    }
    /* the static correction: the truncated modes' quasi-static response per wind-basis
     * column (r_k, stored in SRES), carried by each mode's drawn shape in the share that
     * the force vector read back from q gives it: φ̂_i = φ_i + Σ_k r_k A_k,i
     * (asset_pose_shapes), so that a steady wind draws K⁻¹ F (PHYSICS.md "Static
     * correction") */
    rc = statics_residual(&f, F, er.phi, (uint32_t)nm, a->omega, a->wind_basis, res, err);
    if (rc != GALE_OK) {
        goto fail;
    }
    fem_split_modes(&f, res, 3, rtr, rrot);
    a->static_res = to_float(rtr, (size_t)n * 9);
    if (!a->static_res) {
        rc = gale_errf(err, GALE_E_NOMEM, "bake: out of memory filling the asset");
        goto fail;
    }
    asset_pose_shapes(a, shape);
    double rep_static = 0.0;
    for (int i = 0; i < n; i++) {
        const double u = rtr[3 * i] * rtr[3 * i] + rtr[3 * i + 1] * rtr[3 * i + 1] +
                         rtr[3 * i + 2] * rtr[3 * i + 2];
        rep_static = fmax(rep_static, sqrt(u));
    }
    /* the pose is linear in q (q̃ = q): its slope at rest is φ̂, and no saturation is fitted */
    asset_pose_fields(a->rest, a->parent, a->n_nodes, shape, a->n_modes, a->corr_v, a->corr_w);
    const double t4 = mono_s();
    rc = mesh_build(s, sp, a, err);
    if (rc != GALE_OK) {
        goto fail;
    }
    const double t5 = mono_s();

    r.nodes = n;
    r.modes = nm;
    r.seconds_fem = t1 - t0;
    r.seconds_eigen = t2 - t1;
    r.seconds_basis = t3 - t2;
    r.seconds_correction = t4 - t3;
    r.seconds_mesh = t5 - t4;
    r.eigen_dense = er.dense;
    r.eigen_iterations = er.iterations;
    r.eigen_solves = er.n_op;
    r.eigen_residual = er.max_residual;
    r.ortho_error = er.ortho_error;
    r.static_residual_m = rep_static;
    pose_check_run(a, &sp->drag, &r.pose);
    r.seconds = mono_s() - t0;
    if (rep) {
        *rep = r;
    }
    rc = GALE_OK;
    goto done;
fail:
    asset_fini(a);
    memset(a, 0, sizeof *a);
done:
    free(tr), free(rot), free(rest), free(p), free(F), free(res), free(rtr), free(rrot);
    free(shape);
    eigen_result_fini(&er);
    fem_fini(&f);
    return rc;
}

char *bake_report_json(const asset *a, const bake_report *rep)
{
    cJSON *o = cJSON_CreateObject();
    if (!o) {
        return NULL;
    }
    cJSON_AddStringToObject(o, "species", a->species);
    cJSON_AddNumberToObject(o, "nodes", rep->nodes);
    cJSON_AddNumberToObject(o, "modes", rep->modes);
    cJSON_AddNumberToObject(o, "height_m", (double)a->height_m);
    cJSON_AddNumberToObject(o, "mass_kg", rep->mass_kg);
    cJSON *fh = cJSON_AddArrayToObject(o, "frequencies_hz");
    cJSON *dr = cJSON_AddArrayToObject(o, "damping_ratios");
    cJSON *pn = cJSON_AddArrayToObject(o, "wind_basis_norm");
    for (uint32_t m = 0; m < a->n_modes; m++) {
        const double w = (double)a->omega[m];
        cJSON_AddItemToArray(fh, cJSON_CreateNumber(w / (2.0 * M_PI)));
        /* ζ = γ / (2 ω) for q'' + γ q' + ω² q */
        cJSON_AddItemToArray(dr, cJSON_CreateNumber((double)a->gamma[m] / (2.0 * w)));
        const float *p = a->wind_basis + 3 * m;
        cJSON_AddItemToArray(pn, cJSON_CreateNumber(sqrt((double)(p[0] * p[0] + p[1] * p[1] +
                                                                  p[2] * p[2]))));
    }
    cJSON_AddNumberToObject(o, "seconds", rep->seconds);
    const pose_check *pc = &rep->pose;
    cJSON *bl = cJSON_AddObjectToObject(o, "branch_length_error");
    cJSON_AddStringToObject(bl, "pose",
                            "static wind pose along +x, all modes, scaled so the linear "
                            "pose's largest node displacement is the given share of the height");
    cJSON_AddNumberToObject(bl, "linear_at_20pct", pc->len_linear_20);
    cJSON_AddNumberToObject(bl, "pose_at_20pct", pc->len_pose_20);
    cJSON_AddNumberToObject(bl, "linear_at_10pct", pc->len_linear_10);
    cJSON_AddNumberToObject(bl, "pose_at_10pct", pc->len_pose_10);
    cJSON_AddNumberToObject(bl, "small_q_error", pc->small_q_err);
    cJSON *df = cJSON_AddArrayToObject(o, "deflection");
    for (int k = 0; k < POSE_CHECK_SPEEDS; k++) {
        cJSON *row = cJSON_CreateObject();
        cJSON_AddNumberToObject(row, "wind_ms", pc->speed_ms[k]);
        cJSON_AddNumberToObject(row, "rigid_m", pc->defl_rigid_m[k]);
        cJSON_AddNumberToObject(row, "streamlined_m", pc->defl_stream_m[k]);
        cJSON_AddItemToArray(df, row);
    }
    cJSON *e = cJSON_AddObjectToObject(o, "eigen");
    cJSON_AddStringToObject(e, "method", rep->eigen_dense ? "dense LAPACK dsygvd"
                                                          : "ARPACK Lanczos on (K^-1 M)^2, "
                                                            "zero-fill tree Cholesky of K");
    cJSON_AddNumberToObject(e, "restarts", rep->eigen_iterations);
    cJSON_AddNumberToObject(e, "solves", rep->eigen_solves);
    cJSON_AddNumberToObject(e, "max_residual", rep->eigen_residual);
    cJSON_AddNumberToObject(e, "orthonormality_error", rep->ortho_error);
    cJSON_AddNumberToObject(o, "orthonormality_error", rep->ortho_error);
    cJSON_AddNumberToObject(o, "eigen_residual", rep->eigen_residual);
    cJSON_AddNumberToObject(o, "static_correction_max_m_per_w", rep->static_residual_m);
    cJSON *t = cJSON_AddObjectToObject(o, "stage_seconds");
    cJSON_AddNumberToObject(t, "fem", rep->seconds_fem);
    cJSON_AddNumberToObject(t, "eigen", rep->seconds_eigen);
    cJSON_AddNumberToObject(t, "basis", rep->seconds_basis);
    cJSON_AddNumberToObject(t, "correction", rep->seconds_correction);
    cJSON_AddNumberToObject(t, "mesh", rep->seconds_mesh);
    cJSON_AddNumberToObject(o, "mesh_vertices", a->n_verts);
    cJSON_AddNumberToObject(o, "mesh_triangles", a->n_indices / 3);
    cJSON_AddNumberToObject(o, "leaves", a->n_leaves);
    char hash[24];
    snprintf(hash, sizeof hash, "%016llx", (unsigned long long)a->source_hash);
    cJSON_AddStringToObject(o, "source_hash", hash);
    char *text = cJSON_Print(o);
    cJSON_Delete(o);
    return text;
}

void bake_report_print(FILE *out, const asset *a, const bake_report *rep)
{
    fprintf(out, "species %s: %d nodes, height %.2f m, mass %.1f kg\n", a->species, rep->nodes,
            (double)a->height_m, rep->mass_kg);
    fprintf(out, "%d modes (%s, %d restarts, %d solves), residual %.1e, M-orthonormality %.1e\n",
            rep->modes, rep->eigen_dense ? "dense" : "shift-invert Lanczos",
            rep->eigen_iterations, rep->eigen_solves, rep->eigen_residual, rep->ortho_error);
    fprintf(out, "  mode   freq [Hz]  damping ratio  |p| [kg^0.5/m]\n");
    for (uint32_t m = 0; m < a->n_modes; m++) {
        const double w = (double)a->omega[m];
        const float *p = a->wind_basis + 3 * m;
        fprintf(out, "  %4u  %10.4f  %13.4f  %14.4g\n", m + 1, w / (2.0 * M_PI),
                (double)a->gamma[m] / (2.0 * w),
                sqrt((double)(p[0] * p[0] + p[1] * p[1] + p[2] * p[2])));
    }
    const pose_check *pc = &rep->pose;
    fprintf(out,
            "branch-length change, static wind pose of all modes at 20%% (10%%) of height: "
            "%.2f%% (%.2f%%) linear, %.3f%% (%.3f%%) length-true pose; at 0.1%% of height the "
            "pose is within %.4f%% of the linear response\n",
            100.0 * pc->len_linear_20, 100.0 * pc->len_linear_10, 100.0 * pc->len_pose_20,
            100.0 * pc->len_pose_10, 100.0 * pc->small_q_err);
    fprintf(out, "static deflection at the crown's wind speed (largest node displacement):\n");
    fprintf(out, "  wind [m/s]  rigid drag [m]  streamlined [m]  streamlined [%% of height]\n");
    for (int k = 0; k < POSE_CHECK_SPEEDS; k++) {
        fprintf(out, "  %10.0f  %14.2f  %15.2f  %26.1f\n", pc->speed_ms[k], pc->defl_rigid_m[k],
                pc->defl_stream_m[k], 100.0 * pc->defl_stream_m[k] / (double)a->height_m);
    }
    fprintf(out, "mesh %u vertices, %u triangles, %u LODs, %u leaves\n", a->n_verts,
            a->n_indices / 3, a->n_lods, a->n_leaves);
    fprintf(out,
            "bake %.3f s (fem %.3f, eigen %.3f, basis %.3f, correction %.3f, mesh %.3f)\n",
            rep->seconds, rep->seconds_fem, rep->seconds_eigen, rep->seconds_basis,
            rep->seconds_correction, rep->seconds_mesh);
}
