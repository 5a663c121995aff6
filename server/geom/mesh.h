/* Drawable geometry of a baked tree: the tube mesh of trunk and branches with skin
 * weights (Singh, section 2.1: vertex weighting) and coarser LODs, and the leaf slots on
 * terminal nodes. */
#ifndef GALE_MESH_H
#define GALE_MESH_H

#include "asset.h"
#include "err.h"
#include "skeleton.h"
#include "species.h"

/* Fills a's mesh_*, lod_*, leaf_* and look fields (bark_rgb, leaf_rgb, leaf_shape) from
 * the rest skeleton and the species. The arrays become owned by a (those fields must not
 * own arrays yet; they are overwritten). Three LODs: 8-sided tubes, then 4-sided ones
 * without the thinnest twigs, then only the main limbs. Deterministic. */
int mesh_build(const skeleton *s, const species *sp, asset *a, gale_err *err);

#endif
