/* Sub-trees of broken branches: see damage_cut.h. */
#include "damage_cut.h"

#include <string.h>

void damage_cut_mask(const int32_t *parent, uint32_t n_nodes, const uint32_t *cut, uint32_t n_cut,
                     bool keep_only, uint8_t *out)
{
    /* out[] first marks the cut nodes, then every node takes its parent's state unless
     * marked itself: parents come first (ASSET.md "Node numbering") */
    memset(out, 0, n_nodes);
    for (uint32_t k = 0; k < n_cut; k++) {
        if (cut[k] < n_nodes) {
            out[cut[k]] = 1;
        }
    }
    for (uint32_t i = 1; i < n_nodes; i++) {
        if (!out[i] && parent[i] >= 0) {
            out[i] = out[parent[i]];
        }
    }
    for (uint32_t i = 0; i < n_nodes; i++) {
        out[i] = keep_only ? out[i] : (uint8_t)!out[i];
    }
}

uint32_t damage_cut_tree_range(const uint64_t *keys, uint32_t n, uint32_t t, uint32_t *first)
{
    const uint64_t lo_k = (uint64_t)t << 32, hi_k = lo_k | 0xFFFFFFFFu;
    uint32_t lo = 0, hi = n;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (keys[mid] < lo_k) {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    uint32_t end = lo;
    while (end < n && keys[end] <= hi_k) {
        end++;
    }
    *first = lo;
    return end - lo;
}
