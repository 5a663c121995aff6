/* Interest and LOD selection for one client's view (PROTOCOL.md "Control messages",
 * view): which trees a snapshot stream carries and with how many modes. Server policy:
 * the wire only carries the per-tree mode counts it yields (wire_state.n_modes). */
#ifndef GALE_VIEW_SELECT_H
#define GALE_VIEW_SELECT_H

#include <stdint.h>

#include "ctl.h"
#include "err.h"

/* Interest and LOD for one client: n_modes[t] = 0 for trees outside the view (a tree
 * counts as inside when any point within margin_m of its base pos[3t..3t+2] is), the
 * tree's full_modes[t] when inside and within v->lod_m of the view origin (circle centre
 * or frustum eye; lod_m = 0: no LOD), else min(full_modes[t], lod_modes) (lod_modes >= 1).
 * CTL_VIEW_ALL keeps every tree. Cannot fail; does not allocate; n_modes[n_trees] is the
 * caller's. This is the rule as PROTOCOL.md states it, tree by tree: the reference that
 * view_select_grid must match. */
void view_select(const ctl_view *v, uint32_t n_trees, const float *pos,
                 const uint8_t *full_modes, float margin_m, uint32_t lod_modes,
                 uint8_t *n_modes);

/* The trees bucketed once into square cells of the ground plane, so that a view walks
 * only the trees of cells it may reach. Each cell keeps the bounding box of its trees'
 * bases; its trees are listed in index order. */
typedef struct view_grid {
    uint32_t n_trees;
    const float *pos;    /* [n_trees * 3] borrowed: the tree bases */
    float x0_m, y0_m;    /* corner of cell (0, 0) */
    float cell_m;
    uint32_t nx, ny;     /* cells along x and y */
    uint32_t *start;     /* owned [nx * ny + 1]: cell c's trees are tree[start[c]..start[c + 1]) */
    uint32_t *tree;      /* owned [n_trees] */
    float *box;          /* owned [nx * ny * 6]: min x, y, z, max x, y, z of the cell's bases */
} view_grid;

/* Buckets n_trees bases pos (borrowed while the grid lasts) into cells of about cell_m,
 * widened so that there are at most VIEW_GRID_MAX_CELLS. Fails only for want of memory
 * or a base that is not finite. */
#define VIEW_GRID_MAX_CELLS 65536u
int view_grid_build(view_grid *g, uint32_t n_trees, const float *pos, float cell_m,
                    gale_err *err);
void view_grid_fini(view_grid *g);

/* view_select over the grid's trees, with the same results: every n_modes[t] is written,
 * and a cell is skipped only when its bounding box lies, with room to spare for the
 * per-tree arithmetic's rounding, outside the view widened by margin_m. */
void view_select_grid(const view_grid *g, const ctl_view *v, const uint8_t *full_modes,
                      float margin_m, uint32_t lod_modes, uint8_t *n_modes);

#endif
