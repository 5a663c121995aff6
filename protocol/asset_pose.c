/* The C reference pose of a baked tree from its modal state: the strong-wind form of
 * Diener 2008 section 5.2 (asset.h asset_corr_qt), for every node or for one. The GPU's
 * shaders/skel.frag computes the same. */
#include "asset.h"

#include <stdbool.h>

void asset_reconstruct(const asset *a, const float *q, uint32_t n_modes_used, float *out)
{
    size_t nn = a->n_nodes;
    if (n_modes_used > a->n_modes) {
        n_modes_used = a->n_modes;
    }
    for (size_t i = 0; i < 3 * nn; i++) {
        out[i] = a->rest[i];
    }
    bool corr = a->corr_v && a->corr_w && a->corr_a && a->corr_b;
    for (size_t m = 0; m < n_modes_used; m++) {
        const float *v = corr ? a->corr_v + 3 * m * nn : a->phi + 3 * m * nn;
        const float *w = corr ? a->corr_w + 3 * m * nn : NULL;
        float qt = corr ? asset_corr_qt(a->corr_a[m], a->corr_b[m], q[m]) : q[m];
        float qt2 = qt * qt;
        for (size_t i = 0; i < 3 * nn; i++) {
            out[i] += qt * v[i] + (w ? qt2 * w[i] : 0.0f);
        }
    }
}

void asset_reconstruct_node(const float *rest, const float *corr_v, const float *corr_w,
                            const float *corr_a, const float *corr_b, uint32_t n_nodes,
                            const float *q, uint32_t n_modes, uint32_t node, float x[3])
{
    for (int k = 0; k < 3; k++) {
        x[k] = rest[3 * (size_t)node + (size_t)k];
    }
    for (uint32_t m = 0; m < n_modes; m++) {
        const float qt = asset_corr_qt(corr_a[m], corr_b[m], q[m]);
        const size_t o = ((size_t)m * n_nodes + node) * 3;
        for (size_t k = 0; k < 3; k++) {
            x[k] += qt * corr_v[o + k] + qt * qt * corr_w[o + k];
        }
    }
}
