/* Which nodes of a tree stay drawn when branches break off (PROTOCOL.md "DAMAGE" BRANCH:
 * the node named and its whole sub-tree go). Plain C, the reference of the skeleton pass's
 * flag (shaders/skel.frag, client/render/render_damage.c). */
#ifndef GALE_DAMAGE_CUT_H
#define GALE_DAMAGE_CUT_H

#include <stdbool.h>
#include <stdint.h>

/* out[i] = 1 when no node on the way from i up to the root (i included) is one of cut[],
 * else 0; keep_only inverts it (a debris piece: only the sub-trees of cut[]). parent[] as
 * in an asset (parent[0] = -1, parent[i] < i), so one pass in node order decides every
 * node. Cut nodes outside 0..n_nodes-1 are ignored. */
void damage_cut_mask(const int32_t *parent, uint32_t n_nodes, const uint32_t *cut, uint32_t n_cut,
                     bool keep_only, uint8_t *out);

/* The range of tree t in keys[n] (tree << 32 | node, ascending, damage_view's `broken`):
 * *first and the count returned. */
uint32_t damage_cut_tree_range(const uint64_t *keys, uint32_t n, uint32_t t, uint32_t *first);

#endif
