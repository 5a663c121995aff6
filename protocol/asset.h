/* The baked species asset: everything a client needs to draw and move one species of
 * tree, and everything the server needs to simulate it. One versioned binary file per
 * species, little-endian, fixed-width fields, checksummed; ASSET.md has the byte
 * layout. This module turns bytes into an asset and back; it does no file I/O. */
#ifndef GALE_ASSET_H
#define GALE_ASSET_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>

#include "err.h"

/* Newest version this build reads and writes; it reads every version from
 * ASSET_VERSION_MIN. A file with no optional section is written as version 1, so readers
 * of version 1 keep reading it (ASSET.md "Versions"). */
#define ASSET_VERSION 2
#define ASSET_VERSION_MIN 1
#define ASSET_MAX_LODS 4

/* All arrays are owned by the asset and freed by asset_fini. Per-mode per-node arrays
 * are laid out mode-major: x[(m * n_nodes + i) * 3 + k]. Tree frame: z up, root at the
 * origin, metres. */
typedef struct asset {
    /* provenance */
    char species[64];      /* species name, NUL-terminated */
    uint64_t source_hash;  /* hash of what it was baked from (input bytes, modes, bake version) */
    char *params_json;     /* owned: the parameters it was baked from, as JSON text */

    /* rest skeleton */
    uint32_t n_nodes;
    int32_t *parent;       /* [n_nodes]; -1 for the root, else parent[i] < i */
    float *rest;           /* [3 n_nodes] rest positions [m] */
    float *radius;         /* [n_nodes] [m] */
    float height_m;        /* max z of the rest skeleton */

    /* source node ids (optional SRID section): where each node came from in the skeleton
     * CSV; NULL for a skeleton without ids (grown from a species' L-system) */
    uint32_t *source_id;     /* [n_nodes] or NULL: the CSV id of node i, all distinct */
    float source_origin[3];  /* the CSV position of the root [m]: CSV = rest + origin;
                              * 0 when source_id is NULL */

    /* modes (Diener 2008 sections 3-4) */
    uint32_t n_modes;
    float *omega;          /* [n_modes] natural angular frequency [rad/s], ascending */
    float *gamma;          /* [n_modes] damping [1/s], γ_i = α + β ω_i² (eq. 9) */
    float *wind_basis;     /* [n_modes][3] p_i: modal force f_i = |v| v·p_i, v in tree frame */
    float *phi;            /* [n_modes][n_nodes][3] linear mode translation, mass-normalised */
    float *phi_rot;        /* [n_modes][n_nodes][3] linear mode rotation [rad per unit q] */

    /* static correction of the truncated modes (optional SRES section; PHYSICS.md "Static
     * correction"): r_k, the translation of each node that the modes left out add in a
     * steady unit wind force w_k; NULL without the section */
    float *static_res;     /* [ASSET_STATIC_COLS][n_nodes][3] [m per m²/s²] or NULL */

    /* length-true pose (PHYSICS.md "Length-true pose"; section CORR): segment p -> i is
     * R(Σ q̃ v_i) (rest_i - rest_p + Σ q̃ w_i) hung from p's posed end, q̃ = a atan(b q) */
    float *corr_v;         /* [n_modes][n_nodes][3] segment rotation vector per unit q̃ [rad] */
    float *corr_w;         /* [n_modes][n_nodes][3] segment axial stretch per unit q̃ [m] */
    float *corr_a;         /* [n_modes] */
    float *corr_b;         /* [n_modes]; 0: q̃ = q (what gale-bake writes) */

    /* tube mesh of trunk and branches, skinned to the skeleton */
    uint32_t n_verts;
    float *mesh_pos;       /* [3 n_verts] rest position [m] */
    float *mesh_normal;    /* [3 n_verts] unit */
    uint32_t *mesh_bone;   /* [2 n_verts] the two nodes a vertex follows */
    float *mesh_weight;    /* [n_verts] weight of mesh_bone[2v+1]; bone 2v gets 1 - w */
    uint32_t n_indices;
    uint32_t *mesh_index;  /* [n_indices] triangles, LOD 0 first */
    uint32_t n_lods;       /* 1..ASSET_MAX_LODS, finest first */
    uint32_t lod_first[ASSET_MAX_LODS]; /* first index of each LOD in mesh_index */
    uint32_t lod_count[ASSET_MAX_LODS]; /* index count of each LOD */

    /* leaves on terminal nodes */
    uint32_t n_leaves;
    uint32_t *leaf_node;   /* [n_leaves] node the leaf follows */
    float *leaf_offset;    /* [3 n_leaves] from that node's rest position [m] */
    float *leaf_normal;    /* [3 n_leaves] blade normal, unit */
    float *leaf_size;      /* [n_leaves] blade length [m] */

    /* look */
    float bark_rgb[3];
    float leaf_rgb[3];
    uint32_t leaf_shape;   /* 0 broad leaf, 1 palm leaflet, 2 needle tuft */
} asset;

/* Columns of the static correction: one per wind-basis component x, y, z. */
#define ASSET_STATIC_COLS 3u

/* The force vector w̃ [m²/s²] the modal state q implies (ASSET.md "SRES"): the least
 * squares fit of the modal forces that hold the modes where they are, ω_i² q_i ≈ p_i·w,
 * w̃ = (Σ_i p_i p_iᵀ)⁺ Σ_i ω_i² q_i p_i, as w̃ = A q with A[k][i] (3 x n_modes, written to
 * A) from omega and wind_basis (⁺: pseudo-inverse, eigenvalues below 1e-9 of the largest
 * dropped). A steady wind's q_i = p_i·w / ω_i² gives w̃ = w. */
void asset_static_map(const float *omega, const float *wind_basis, uint32_t n_modes, double *A);

/* The drawn mode shapes φ̂_i = phi_i + Σ_k r_k A_k,i (A of asset_static_map over all the
 * asset's modes, r_k of its SRES section; φ̂ = phi without it) into out[n_modes][n_nodes][3]:
 * what gale-bake gives asset_pose_fields, so the length-true pose's slope at q = 0. */
void asset_pose_shapes(const asset *a, float *out);

/* The linear pose rest + Σ_i q_i φ̂_i of the first n_modes_used modes into out[3 n_nodes],
 * φ̂_i = phi_i + Σ_k r_k A_k,i with the SRES section's r_k (φ̂ = phi without it): the slope
 * at q = 0 of the length-true pose gale-bake writes. */
void asset_linear(const asset *a, const float *q, uint32_t n_modes_used, float *out);

/* Encodes a into a new buffer (*out, malloc'd, caller frees) of *len bytes: version 2
 * with an SRID section when a->source_id is set and an SRES section when a->static_res
 * is, else version 1. */
int asset_encode(const asset *a, uint8_t **out, size_t *len, gale_err *err);

/* Decodes len bytes into *a (caller-owned struct; arrays owned by it, free with
 * asset_fini). Truncated, corrupt, oversized or wrong-version input is rejected with
 * a message naming the field and offset; *a is then left empty. `name` is used in
 * messages (a file name or URL). */
int asset_decode(const uint8_t *buf, size_t len, const char *name, asset *a, gale_err *err);

/* Frees every array of *a and zeroes it. NULL is a no-op. */
void asset_fini(asset *a);

/* The saturated modal coordinate q̃ = a atan(b q) of the pose (Diener 2008 section 5.2,
 * eq. 16); b = 0 leaves it linear, q̃ = q. The one C copy of the formula: shaders/skel.frag
 * is its GLSL twin, held to asset_reconstruct by tests/test_render.c. */
static inline float asset_corr_qt(float a, float b, float q)
{
    return b != 0.0f ? a * atanf(b * q) : q;
}

/* The length-true pose's fields from the linear mode translations (ASSET.md "CORR"): for
 * each mode and segment p -> i with rest vector s and Δ = φ_i − φ_p, the rotation vector
 * v = s × Δ / |s|² and the axial stretch w = s (s·Δ) / |s|², so that v × s + w = Δ and the
 * pose's slope at q = 0 is φ. Root rows (and a zero-length segment's v) are 0; w then
 * carries Δ whole. phi, v, w: [n_modes][n_nodes][3]; parent[i] < i for i > 0. */
void asset_pose_fields(const float *rest, const int32_t *parent, uint32_t n_nodes,
                       const float *phi, uint32_t n_modes, float *v, float *w);

/* The C reference pose (the GPU does the same, shaders/skel.frag): node positions
 * out[3 n_nodes], the root at rest and each node its parent's posed position plus its
 * posed segment R(Θ) (s + e), Θ = Σ_i q̃_i v_i, e = Σ_i q̃_i w_i, s the rest segment,
 * q̃_i = asset_corr_qt(a_i, b_i, q_i), over the first n_modes_used modes of q. Without
 * the CORR arrays, the linear response rest + Σ_i q_i φ_i. */
void asset_reconstruct(const asset *a, const float *q, uint32_t n_modes_used, float *out);

/* The same pose for one node only, x[3], for arrays laid out as in an asset (v, w:
 * [mode][node][3]; corr_a, corr_b: [mode]; parent[n_nodes], -1 at the root) of a tree
 * with n_nodes nodes, using n_modes modes of q. Costs the node's depth x n_modes. */
void asset_reconstruct_node(const float *rest, const int32_t *parent, const float *corr_v,
                            const float *corr_w, const float *corr_a, const float *corr_b,
                            uint32_t n_nodes, const float *q, uint32_t n_modes, uint32_t node,
                            float x[3]);

#endif
