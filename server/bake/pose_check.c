/* Pose figures of the bake report (pose_check.h). */
#include "pose_check.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void pose_check_static_q(const asset *a, const drag_law *d, double u_ms, float *q)
{
    const double s = d ? (double)drag_law_scale(d, (float)u_ms) : 1.0;
    for (uint32_t m = 0; m < a->n_modes; m++) {
        const double w = (double)a->omega[m];
        q[m] = (float)(s * u_ms * u_ms * (double)a->wind_basis[3 * m] / (w * w));
    }
}

static double max_disp(const asset *a, const float *x)
{
    double worst = 0.0;
    for (uint32_t i = 0; i < a->n_nodes; i++) {
        double d2 = 0.0;
        for (int k = 0; k < 3; k++) {
            const double d = (double)x[3 * i + k] - (double)a->rest[3 * i + k];
            d2 += d * d;
        }
        worst = fmax(worst, sqrt(d2));
    }
    return worst;
}

static double len_err(const asset *a, const float *x)
{
    double worst = 0.0;
    for (uint32_t i = 1; i < a->n_nodes; i++) {
        const uint32_t p = (uint32_t)a->parent[i];
        double l0 = 0.0, l1 = 0.0;
        for (int k = 0; k < 3; k++) {
            const double s0 = (double)a->rest[3 * i + k] - (double)a->rest[3 * p + k];
            const double s1 = (double)x[3 * i + k] - (double)x[3 * p + k];
            l0 += s0 * s0, l1 += s1 * s1;
        }
        worst = fmax(worst, fabs(sqrt(l1 / l0) - 1.0));
    }
    return worst;
}

/* the linear pose, the length-true pose's slope at q = 0 (asset_linear) */
static void linear(const asset *a, const float *q, float *x)
{
    asset_linear(a, q, a->n_modes, x);
}

void pose_check_run(const asset *a, const drag_law *d, pose_check *pc)
{
    memset(pc, 0, sizeof *pc);
    const size_t nc = 3 * (size_t)a->n_nodes, nm = a->n_modes;
    float *q0 = malloc(nm * sizeof *q0), *q = malloc(nm * sizeof *q);
    float *xl = malloc(nc * sizeof *xl), *xp = malloc(nc * sizeof *xp);
    if (!q0 || !q || !xl || !xp || !(a->height_m > 0.0f)) {
        free(q0), free(q), free(xl), free(xp);
        return;
    }
    pose_check_static_q(a, NULL, 20.0, q0);
    linear(a, q0, xl);
    const double u0 = max_disp(a, xl), h = (double)a->height_m;
    const double frac[3] = { 0.2, 0.1, 0.001 };
    for (int f = 0; f < 3 && u0 > 0.0; f++) {
        const double k = frac[f] * h / u0;
        for (size_t m = 0; m < nm; m++) {
            q[m] = (float)(k * (double)q0[m]);
        }
        linear(a, q, xl);
        asset_reconstruct(a, q, a->n_modes, xp);
        if (f == 0) {
            pc->len_linear_20 = len_err(a, xl), pc->len_pose_20 = len_err(a, xp);
        } else if (f == 1) {
            pc->len_linear_10 = len_err(a, xl), pc->len_pose_10 = len_err(a, xp);
        } else {
            double e = 0.0, ul = 0.0;
            for (uint32_t i = 0; i < a->n_nodes; i++) {
                double d2 = 0.0, l2 = 0.0;
                for (int c = 0; c < 3; c++) {
                    const double r = (double)a->rest[3 * i + c];
                    const double dl = (double)xl[3 * i + c] - r, dp = (double)xp[3 * i + c] - r;
                    d2 += (dp - dl) * (dp - dl), l2 += dl * dl;
                }
                e = fmax(e, sqrt(d2)), ul = fmax(ul, sqrt(l2));
            }
            pc->small_q_err = ul > 0.0 ? e / ul : 0.0;
        }
    }
    for (int s = 0; s < POSE_CHECK_SPEEDS; s++) {
        const double u = 10.0 + 20.0 * s;
        pc->speed_ms[s] = u;
        pose_check_static_q(a, NULL, u, q);
        asset_reconstruct(a, q, a->n_modes, xp);
        pc->defl_rigid_m[s] = max_disp(a, xp);
        pose_check_static_q(a, d, u, q);
        asset_reconstruct(a, q, a->n_modes, xp);
        pc->defl_stream_m[s] = max_disp(a, xp);
    }
    free(q0), free(q), free(xl), free(xp);
}
