/* Interest and LOD selection for one client's view (PROTOCOL.md "Control messages",
 * view): which trees a snapshot stream carries and with how many modes. Server policy:
 * the wire only carries the per-tree mode counts it yields (wire_state.n_modes). */
#ifndef GALE_VIEW_SELECT_H
#define GALE_VIEW_SELECT_H

#include <stdint.h>

#include "ctl.h"

/* Interest and LOD for one client: n_modes[t] = 0 for trees outside the view (a tree
 * counts as inside when any point within margin_m of its base pos[3t..3t+2] is), the
 * tree's full_modes[t] when inside and within v->lod_m of the view origin (circle centre
 * or frustum eye; lod_m = 0: no LOD), else min(full_modes[t], lod_modes) (lod_modes >= 1).
 * CTL_VIEW_ALL keeps every tree. Cannot fail; does not allocate; n_modes[n_trees] is the
 * caller's. */
void view_select(const ctl_view *v, uint32_t n_trees, const float *pos,
                 const uint8_t *full_modes, float margin_m, uint32_t lod_modes,
                 uint8_t *n_modes);

#endif
