/* Culling and level of detail for gale_render: the view frustum's planes, and per tree
 * whether it is drawn, and at which levels of lod_policy.h: posed (how many modes, which mesh
 * LOD, every leaf or a share, dithering into the next) and/or an impostor. Pure CPU code:
 * callable without a GL context. */
#ifndef GALE_RENDER_CULL_H
#define GALE_RENDER_CULL_H

#include <math.h>
#include <stdbool.h>
#include <stdint.h>

#include "lod_policy.h"
#include "render.h"

/* What culling needs of a species. */
typedef struct render_cull_species {
    float height_m;  /* rest height above the root [m] */
    float crown_r_m; /* horizontal reach from the trunk axis [m] */
    uint32_t n_modes;
    uint32_t n_lods; /* mesh LODs, >= 1 */
} render_cull_species;

/* How a frame scales the policy (lod_policy.h). */
typedef struct render_lod_desc {
    float mode_dist_m; /* modes start to drop past this distance */
    float scale;       /* × FULL's and THIN's outer distances and the mesh step (the frame's
                          budget and the governor); the impostors' reach is kept */
} render_lod_desc;

enum {
    RENDER_LOD_FULL = 1u,      /* posed: skeleton, bark and leaves (every leaf or thinned) */
    RENDER_LOD_BILLBOARD = 2u, /* drawn as an impostor (with FULL while fading) */
};

typedef struct render_tree_lod {
    uint32_t flags;    /* 0 = culled, else RENDER_LOD_FULL and/or RENDER_LOD_BILLBOARD */
    uint32_t level;    /* the coarsest level it is drawn at (LOD_FULL .. LOD_IMPOSTOR) */
    float thin_t;      /* 0 = every leaf .. 1 = the thinned leaves alone (dithered between) */
    float bill_t;      /* 0 = posed tree .. 1 = impostor alone (dithered between) */
    float n_modes;     /* modes reconstructed: all up to mode_dist_m, then ~1/d, >= 4,
                          at most the level's lod_modes_max */
    uint32_t mesh_lod; /* mesh LOD k < n_lods */
    float mesh_fade;   /* 0..1: dither from LOD k toward k + 1 */
} render_tree_lod;

/* The six frustum planes (a, b, c, d; inside where a x + b y + c z + d > 0) of a
 * column-major view-projection matrix with OpenGL clip conventions. */
void render_cull_planes(const float viewproj[16], float planes[6][4]);

/* Whether one tree is in the frustum (a bounding sphere around its crown, widened for
 * sway; planes NULL: known inside), and its distance [m] from eye to the sphere's centre. */
bool render_cull_visible(const float planes[6][4], const float eye[3],
                         const render_instance *in, const render_cull_species *s,
                         float *dist_m);

/* The LOD of a tree at distance dist_m (lod_policy.h, scaled by d). stays_posed: a debris
 * piece, which no impostor draws: it is never an impostor, and over THIN's fade band it
 * fades out (bill_t, with no impostor fading in); past THIN it is not drawn. A fallen,
 * uprooted or snapped tree is not one: past THIN it is an impostor as a standing tree is,
 * laid along its fall (render_bill_fall, shaders/bill.vert). Past the impostors' reach,
 * flags 0. */
render_tree_lod render_lod_pick(float dist_m, const render_cull_species *s,
                                const render_lod_desc *d, bool stays_posed);
/* render_lod_pick written to *out: the frame's pass writes each tree's LOD in place (a
 * struct returned through the stack and copied cost a stalled store per tree). */
void render_lod_pick_into(float dist_m, const render_cull_species *s, const render_lod_desc *d,
                          bool stays_posed, render_tree_lod *out);

/* render_cull_visible, then render_lod_pick of a standing tree; a culled tree has flags 0
 * and the other fields zero. */
render_tree_lod render_cull_tree(const float planes[6][4], const float eye[3],
                                 const render_instance *in, const render_cull_species *s,
                                 const render_lod_desc *d);

/* The frame's budget (lod_policy.h LOD_BUDGET_*) without sorting the trees: their
 * distances in a histogram per species (RENDER_LOD_BINS bins even in √d over the impostors'
 * reach),
 * the cost of one tree of each species at each level, and the largest scale <= max_scale
 * whose worst case (a bin's trees at its near edge, both levels inside a fade band, both
 * meshes inside a mesh fade) fits. */
#define RENDER_LOD_BINS 256u
typedef struct render_lod_cost {
    float full_leaves;              /* every leaf's triangles */
    float mesh[ASSET_MAX_LODS];     /* the bark's triangles at each mesh LOD */
    uint32_t n_lods;                /* mesh LODs, >= 1 */
    float thin;                     /* the coarsest bark and the thinned leaves */
    float impostor;                 /* 2 */
    float nodes;                    /* skeleton nodes posed for one tree at FULL or THIN */
} render_lod_cost;
/* felled_hist (NULL: none): per bin, the felled trees whose root plate or stump a tree posed
 * there (FULL or THIN) draws besides itself, each costed at RENDER_FELLED_TRIS_MAX. */
float render_lod_budget(const uint32_t *hist, const uint32_t *felled_hist,
                        const render_lod_cost *cost, uint32_t n_species, float max_scale,
                        double budget_triangles, double budget_nodes);

/* What a felled tree posed (FULL or THIN) adds: an uprooted one's root plate (shaders/plate.vert:
 * two fans and a side band of 24 segments) or a snapped one's stump (shaders/stump.vert:
 * 7 triangles a segment, 12 segments); the budget takes the larger for either. */
#define RENDER_PLATE_TRIS (4u * 24u)
#define RENDER_STUMP_TRIS (7u * 12u)
#define RENDER_FELLED_TRIS_MAX RENDER_PLATE_TRIS

/* The leaves drawn of n_leaves at a level's share (lod_policy.h): round(n × share), at
 * least 1; 0 for a share of 0. The page takes the same (web/render_list.js). */
uint32_t render_leaves_at(uint32_t n_leaves, float share);

/* A tree's fall as its impostor list entry's third component holds it (shaders/bill.vert,
 * common.glsl bill_fallen; the page's web/render_list.js impFall): 0 standing (fall_rad not
 * > 0); else 1 + fall_az_rad in 1/256 turns (rounded, 0..255) + min(fall_rad, π/2) / π. */
float render_bill_fall_code(float fall_rad, float fall_az_rad);

/* The histogram bin of distance dist_m; RENDER_LOD_BINS past the impostors' reach. */
uint32_t render_lod_bin(float dist_m);
/* The near edge [m] of histogram bin b. */
float render_lod_bin_near_m(uint32_t b);

/* The sphere render_cull_tree tests: centre c [m] and radius [m]. */
float render_cull_sphere(const render_instance *in, const render_cull_species *s, float c[3]);
/* Whether a sphere (centre c, radius rad) is in view (planes NULL: known to be, as the trees
 * of a cell wholly inside), and its centre's distance from eye into *dist_m. Inline: the
 * frame calls it once a tree. */
static inline bool render_cull_sphere_visible(const float planes[6][4], const float eye[3],
                                              const float c[3], float rad, float *dist_m)
{
    for (int k = 0; planes && k < 6; k++) {
        if (!(planes[k][0] * c[0] + planes[k][1] * c[1] + planes[k][2] * c[2] + planes[k][3] >
              -rad)) {
            return false;
        }
    }
    float dx = c[0] - eye[0], dy = c[1] - eye[1], dz = c[2] - eye[2];
    *dist_m = sqrtf(dx * dx + dy * dy + dz * dz);
    return true;
}

/* The scene's trees in cells of a 2D grid, each with the box that holds the culling
 * spheres of its trees (render_cull_tree's), so a frame tests cells against the frustum
 * and only the trees of cells the frustum cuts one by one: trees of a cell outside are
 * culled with it, those of a cell inside all kept without their own test. */
typedef struct render_cell {
    float lo[3], hi[3];    /* box of the cell's trees' spheres [m] */
    uint32_t first, count; /* its trees: tree[first .. first + count) */
} render_cell;

typedef struct render_cells {
    render_cell *cell;  /* owned: [n_cells], the empty ones left out */
    uint32_t n_cells;
    uint32_t *tree;     /* owned: [n_trees] tree indices, cell by cell */
    /* owned: [n_trees], in tree[]'s order: each tree's culling sphere (centre [m], radius
       [m]) and species, so a frame's pass over the cells in view reads memory in order and
       never the instances themselves */
    float (*sphere)[4];
    uint32_t *species;
    /* owned: [n_trees], in tree[]'s order: what a tree's impostor keeps of its leaves
       (0..1), and its fall as the impostor list entry's third component holds it (0
       standing; 1 + azimuth in 1/256 turns + fall angle / π for a tipped tree: render:
       render_bill_fall); the caller keeps both (render: render_bill_leaf_set), so a far
       cell's impostors, lying trees among them, are listed from them alone */
    float *bill_leaf;
    float *bill_fall;
    uint32_t *at_of;    /* owned: [n_trees] each tree's place in tree[] */
    uint32_t *bulk;     /* owned: [n_cells] scratch: a frame's cells drawn as impostors whole */
    uint32_t *cell_of;  /* owned: [n_trees] each tree's cell */
    uint8_t *where;     /* owned: [n_cells] scratch for a frame's render_cell_test */
    uint32_t n_trees;
} render_cells;

/* About this many trees a cell: fewer cells to test against more trees tested alone. */
#define RENDER_CELL_TREES 64u

/* Buckets trees [0, n) of inst (species indexing sp) into cells. 0, or -1 out of memory
 * (g then empty). Frees what g held before. */
int render_cells_build(render_cells *g, const render_instance *inst, uint32_t n,
                       const render_cull_species *sp);
void render_cells_free(render_cells *g);

enum { RENDER_CELL_OUT = 0, RENDER_CELL_CUT = 1, RENDER_CELL_IN = 2 };

/* Where a cell's box lies against the six frustum planes: all outside one plane (OUT),
 * inside all (IN), else CUT. */
int render_cell_test(const render_cell *c, const float planes[6][4]);

/* The narrowest cone about the frustum's centre line that holds the whole frustum of a
 * column-major view-projection matrix (symmetric or off-axis, OpenGL clip conventions),
 * with its apex at eye: what a client asks the server for (PROTOCOL.md view "frustum", a
 * cone). axis is a unit vector; fov_deg the full cone angle; far_m the greatest depth of
 * the frustum along the axis. Returns false for a matrix without an inverse. */
bool render_cull_cone(const float viewproj[16], const float eye[3], float axis[3],
                      float *fov_deg, float *far_m);

#endif
