/* The split of a tree's wind load between its wood and its leaves: see crown_load.h. */
#include "crown_load.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void crown_load_tips(uint32_t n, const int32_t *parent, uint8_t *tip)
{
    memset(tip, 1, n);
    for (uint32_t i = 1; i < n; i++) {
        tip[parent[i]] = 0;
    }
    if (n > 0) {
        tip[0] = 0; /* the root bears no load of its own */
    }
}

crown_load crown_load_split(uint32_t n, const int32_t *parent, const float *pos,
                            const float *radius, double leaf_share)
{
    crown_load c = { .wood = 1.0, .tip_m2 = 0.0, .n_tips = 0 };
    uint8_t *tip = n >= 2 ? malloc(n) : NULL;
    if (!tip) {
        return c;
    }
    crown_load_tips(n, parent, tip);
    /* first moments of height: Σ_e D_e L_e (z_mid - z_0) of the wood, Σ (z_tip - z_0) */
    const double z0 = pos[2];
    double h_wood = 0.0, h_tips = 0.0;
    for (uint32_t i = 1; i < n; i++) {
        const uint32_t q = (uint32_t)parent[i];
        double l2 = 0.0;
        for (int k = 0; k < 3; k++) {
            const double d = (double)pos[3 * i + k] - (double)pos[3 * q + k];
            l2 += d * d;
        }
        const double dl = ((double)radius[i] + (double)radius[q]) * sqrt(l2);
        h_wood += dl * (0.5 * ((double)pos[3 * i + 2] + (double)pos[3 * q + 2]) - z0);
        if (tip[i]) {
            c.n_tips++;
            h_tips += (double)pos[3 * i + 2] - z0;
        }
    }
    free(tip);
    if (leaf_share > 1.0) {
        leaf_share = 1.0;
    }
    if (leaf_share > 0.0 && h_wood > 0.0 && h_tips > 0.0) {
        c.wood = 1.0 - leaf_share;
        c.tip_m2 = leaf_share * h_wood / h_tips;
    }
    return c;
}
