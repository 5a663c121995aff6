/* The C reference pose of a baked tree from its modal state, for every node or for one:
 * the skinned skeleton of ASSET.md "CORR" and PHYSICS.md "Length-true pose". Each segment
 * p -> i is its rest vector s_i plus the axial stretch Σ q̃_m w_m,i, turned by the rotation
 * vector Θ_i = Σ q̃_m v_m,i (Rodrigues), and hung from its parent's posed end. Lengths
 * change only by the modes' own axial strain, whatever the mix of modes; the slope at
 * q = 0 is φ exactly (v × s + w = φ_i − φ_p). The GPU's shaders/skel.frag computes the
 * same, held to this by tests/test_render.c. */
#include "asset.h"

#include <math.h>
#include <stdbool.h>

void asset_pose_fields(const float *rest, const int32_t *parent, uint32_t n_nodes,
                       const float *phi, uint32_t n_modes, float *v, float *w)
{
    const size_t nc = 3 * (size_t)n_nodes;
    for (uint32_t m = 0; m < n_modes; m++) {
        const float *ph = phi + m * nc;
        float *vm = v + m * nc, *wm = w + m * nc;
        for (size_t k = 0; k < 3; k++) {
            vm[k] = wm[k] = 0.0f;
        }
        for (uint32_t i = 1; i < n_nodes; i++) {
            const size_t p = (size_t)parent[i], o = 3 * (size_t)i;
            double s[3], d[3], l2 = 0.0, sd = 0.0;
            for (size_t k = 0; k < 3; k++) {
                s[k] = (double)rest[o + k] - (double)rest[3 * p + k];
                d[k] = (double)ph[o + k] - (double)ph[3 * p + k];
                l2 += s[k] * s[k];
                sd += s[k] * d[k];
            }
            if (!(l2 > 0.0)) {
                for (size_t k = 0; k < 3; k++) {
                    vm[o + k] = 0.0f, wm[o + k] = (float)d[k];
                }
                continue;
            }
            /* (s × Δ) × s = |s|² Δ − (s·Δ) s: the rotation carries Δ's part across s */
            vm[o] = (float)((s[1] * d[2] - s[2] * d[1]) / l2);
            vm[o + 1] = (float)((s[2] * d[0] - s[0] * d[2]) / l2);
            vm[o + 2] = (float)((s[0] * d[1] - s[1] * d[0]) / l2);
            for (size_t k = 0; k < 3; k++) {
                wm[o + k] = (float)(s[k] * sd / l2);
            }
        }
    }
}

/* d = R(th) (s + e): the posed segment, in double so that small poses keep their digits. */
static void posed_segment(const double th[3], const double s[3], double d[3])
{
    const double t2 = th[0] * th[0] + th[1] * th[1] + th[2] * th[2];
    /* sin t / t and (1 - cos t) / t² by their series below 1e-4 rad, where the closed
     * forms lose digits */
    double sa, ca;
    if (t2 < 1e-8) {
        sa = 1.0 - t2 / 6.0;
        ca = 0.5 - t2 / 24.0;
    } else {
        const double t = sqrt(t2);
        sa = sin(t) / t;
        ca = (1.0 - cos(t)) / t2;
    }
    const double c[3] = { th[1] * s[2] - th[2] * s[1], th[2] * s[0] - th[0] * s[2],
                          th[0] * s[1] - th[1] * s[0] };
    const double cc[3] = { th[1] * c[2] - th[2] * c[1], th[2] * c[0] - th[0] * c[2],
                           th[0] * c[1] - th[1] * c[0] };
    for (size_t k = 0; k < 3; k++) {
        d[k] = s[k] + sa * c[k] + ca * cc[k];
    }
}

/* Posed segment of node i (> 0) with parent p. */
static void segment(const float *rest, const float *v, const float *w, const float *ca,
                    const float *cb, uint32_t nn, const float *q, uint32_t nm, uint32_t i,
                    uint32_t p, double d[3])
{
    double th[3] = { 0, 0, 0 }, s[3];
    for (size_t k = 0; k < 3; k++) {
        s[k] = (double)rest[3 * (size_t)i + k] - (double)rest[3 * (size_t)p + k];
    }
    for (uint32_t m = 0; m < nm; m++) {
        const double qt = (double)asset_corr_qt(ca[m], cb[m], q[m]);
        const size_t o = ((size_t)m * nn + i) * 3;
        for (size_t k = 0; k < 3; k++) {
            th[k] += qt * (double)v[o + k];
            s[k] += qt * (double)w[o + k];
        }
    }
    posed_segment(th, s, d);
}

void asset_reconstruct(const asset *a, const float *q, uint32_t n_modes_used, float *out)
{
    const size_t nn = a->n_nodes;
    if (n_modes_used > a->n_modes) {
        n_modes_used = a->n_modes;
    }
    const bool corr = a->corr_v && a->corr_w && a->corr_a && a->corr_b && a->parent;
    if (!corr) {
        /* no pose fields: the linear modal response rest + Σ q φ̂ */
        asset_linear(a, q, n_modes_used, out);
        return;
    }
    /* parent[i] < i: a parent is posed before its children */
    for (size_t i = 0; i < nn; i++) {
        const int32_t p = a->parent[i];
        if (p < 0) {
            for (size_t k = 0; k < 3; k++) {
                out[3 * i + k] = a->rest[3 * i + k];
            }
            continue;
        }
        double d[3];
        segment(a->rest, a->corr_v, a->corr_w, a->corr_a, a->corr_b, (uint32_t)nn, q,
                n_modes_used, (uint32_t)i, (uint32_t)p, d);
        for (size_t k = 0; k < 3; k++) {
            out[3 * i + k] = (float)((double)out[3 * (size_t)p + k] + d[k]);
        }
    }
}

void asset_reconstruct_node(const float *rest, const int32_t *parent, const float *corr_v,
                            const float *corr_w, const float *corr_a, const float *corr_b,
                            uint32_t n_nodes, const float *q, uint32_t n_modes, uint32_t node,
                            float x[3])
{
    /* the sum of the posed segments from the node up to the root, then the root */
    double acc[3] = { 0, 0, 0 };
    uint32_t i = node;
    for (uint32_t guard = 0; guard < n_nodes && parent[i] >= 0; guard++) {
        const uint32_t p = (uint32_t)parent[i];
        double d[3];
        segment(rest, corr_v, corr_w, corr_a, corr_b, n_nodes, q, n_modes, i, p, d);
        for (size_t k = 0; k < 3; k++) {
            acc[k] += d[k];
        }
        i = p;
    }
    for (size_t k = 0; k < 3; k++) {
        x[k] = (float)((double)rest[3 * (size_t)i + k] + acc[k]);
    }
}
