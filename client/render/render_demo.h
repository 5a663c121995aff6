/* Small in-code species assets for gale_render's tests, tool and benchmark while no baked
 * asset is at hand: a branching skeleton with made-up (but smooth, root-clamped) mode shapes
 * and the length-true pose fields derived from them, a two-LOD tube mesh skinned to it, and
 * leaf slots. */
#ifndef GALE_RENDER_DEMO_H
#define GALE_RENDER_DEMO_H

#include <stdint.h>

#include "asset.h"
#include "err.h"
#include "render.h"

typedef struct render_demo_desc {
    uint32_t n_nodes;      /* about this many skeleton nodes; 0 = 60 */
    uint32_t n_modes;      /* 0 = 8 (at least 2) */
    uint32_t leaves_per_tip; /* leaves per terminal node; 0 = 8 */
    float height_m;        /* 0 = 9 */
    uint32_t leaf_shape;   /* 0 broad, 1 palm leaflet, 2 needle tuft */
    uint32_t seed;         /* 0 = 1 */
} render_demo_desc;

/* Fills *a (zeroed first) with arrays it owns; free with render_demo_free. */
int render_demo_asset(asset *a, const render_demo_desc *desc, gale_err *err);

/* Frees the arrays of a demo asset and zeroes it. */
void render_demo_free(asset *a);

/* A q pose for wind `wind` [m/s] in the tree frame at time t: static deflection
 * f_i / ω_i² with f_i = |v| v·p_i (Diener 2008 section 4), plus a small oscillation. */
void render_demo_pose(const asset *a, const float wind[3], float t, uint32_t tree, float *q);

/* n trees on a jittered grid of `spacing` metres around the origin, random species, yaw
 * and scale 0.8..1.2, from seed. */
void render_demo_forest(render_instance *out, uint32_t n, uint32_t n_species, float spacing,
                        uint32_t seed);

#endif
