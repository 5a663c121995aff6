/* gale_render: draws a forest from baked species assets and per-tree modal vectors q.
 * Skeletons are rebuilt on the GPU in the length-true pose (PHYSICS.md; Diener 2008 5.1),
 * tube meshes skinned from them (Singh sections 2.1-2.4), leaves and falling leaves on one
 * shared path (Vazquez 2008 sections 3-5), LOD down to billboards. OpenGL 3.3 core. */
#ifndef GALE_RENDER_H
#define GALE_RENDER_H

#include <stdbool.h>
#include <stdint.h>

#include "asset.h"
#include "err.h"
#include "storm_fx.h"
#include "wire_limits.h"

/* World frame: z up, metres, ground plane z = 0 (as the asset's tree frame). */

typedef struct render render;
struct GLFWwindow;

typedef struct render_desc {
    int width, height;         /* framebuffer size [px]; 0 = 1280 x 720 */
    bool headless;             /* offscreen: EGL (surfaceless or device), else a hidden
                                  GLFW window (needs X, e.g. Xvfb) */
    bool vsync;                /* windowed only */
    const char *title;         /* window title; NULL = "gale" */
    const char *shader_dir;    /* where the .vert/.frag files are read at run time;
                                  NULL = $GALE_SHADER_DIR, else GALE_SOURCE_DIR "/shaders" */
    uint32_t max_trees;        /* instances held at first; 0 = 8192; grows to the scene */
    uint32_t max_falling;      /* ring of falling + landed leaves; 0 = 16384. The oldest
                                  record is reused when full (landed leaves kept up to this) */
    float lod_mode_dist;       /* distance [m] where the mode count starts to drop; 0 = 40 */
    float fog_dist;            /* distance [m] of ~63 % fog; 0 = 450 */
} render_desc;

/* One tree of the scene. Its q (render_set_q) has the species' n_modes entries. */
typedef struct render_instance {
    uint32_t species;          /* id from render_add_species */
    float pos[3];              /* root position, world [m] */
    float yaw;                 /* rotation about z [rad] */
    float scale;               /* uniform scale; 0 = 1 */
    float fall_rad;            /* tipped over its root by this angle (0 standing, π/2 lying) */
    float fall_az_rad;         /* towards this azimuth, world, from +x towards +y */
    uint32_t leaf_lost;        /* leaf levels stripped, 0 (full crown)..WIRE_DAMAGE_LEVELS */
    uint32_t uprooted;         /* nonzero: tipped over its root plate, which it lifts */
} render_instance;

/* Camera. view/proj are derived from eye/target/up/fov unless `matrices` is set, in
 * which case view and proj (column-major, OpenGL clip conventions) are used as given
 * (off-axis wall tiles). */
typedef struct render_camera {
    float eye[3], target[3], up[3]; /* world; up zero = +z */
    float fov_y_deg;               /* vertical field of view; 0 = 50 */
    float z_near, z_far;           /* [m]; 0 = 0.3, 4500 (past the impostors' reach) */
    /* distance along the view of the camera's subject, the trees it looks at [m]; the storm
     * look keeps its fog and rain thin up to it (storm_fx.subject_clear); 0 = none */
    float subject_m;
    bool matrices;
    float view[16], proj[16];
} render_camera;

/* Coarse wind the caller passes on (the streamed slice). Cell (i,j,k) of a grid of
 * nx*ny*nz cells has its centre at origin + ((i+.5) dx, (j+.5) dy, (k+.5) dz) and velocity
 * v[3 (i + nx (j + ny k))] [m/s], world frame. nx = 0: the uniform `uniform` vector only. */
typedef struct render_wind {
    float uniform[3];          /* [m/s], used when there is no grid and outside it */
    uint32_t nx, ny, nz;
    float origin[3];           /* [m] */
    float cell[3];             /* cell size [m] */
    const float *v;            /* borrowed for the call; copied */
} render_wind;

/* A shed leaf as streamed: it leaves slot `slot` of tree `tree` at spawn_time_s (the same
 * clock as render_frame's time_s; the caller turns ticks into seconds). */
typedef struct render_leaf_seed {
    uint32_t tree;             /* instance index */
    uint32_t slot;             /* leaf slot of that tree's species */
    double spawn_time_s;
    uint32_t seed;             /* variation seed */
} render_leaf_seed;

typedef struct render_stats {
    uint32_t trees_full;       /* drawn as skinned meshes this frame */
    uint32_t trees_thin;       /* of trees_full, those with thinned leaves (some fading) */
    uint32_t trees_billboard;  /* drawn as impostors this frame (some posed too while fading) */
    uint32_t trees_culled;
    uint32_t draw_calls;
    uint32_t falling_live;     /* leaf records in the ring */
    uint64_t leaves_drawn;     /* attached leaves drawn */
    uint32_t stumps;           /* stumps of snapped trees drawn */
    uint64_t triangles;        /* scene triangles drawn (trees, leaves, billboards, houses,
                                  damage, falling leaves; not the skeleton pass's quads,
                                  the sky's and the rain's full-screen triangle) */
    double cull_ms;            /* CPU time culling and choosing levels of detail [ms] */
    float lod_scale;           /* the scale of FULL's and THIN's distances the budget took */
} render_stats;

/* Creates the GL context (window or offscreen) and all GPU state. NULL on failure with
 * the reason in err. Free with render_destroy. */
render *render_create(const render_desc *desc, gale_err *err);

/* Destroys everything render_create made, the context included. NULL is a no-op. */
void render_destroy(render *r);

/* The GLFW window when windowed, for input, HUD and swapping; NULL when headless.
 * The GL context is current on the creating thread. */
struct GLFWwindow *render_window(render *r);

/* Species one renderer holds: every species a welcome may name, so a scene the client
 * accepts never fails for want of room on the GPU side. */
#define RENDER_MAX_SPECIES WIRE_MAX_SPECIES
_Static_assert(RENDER_MAX_SPECIES >= WIRE_MAX_SPECIES,
               "render: must hold every species a welcome may carry (WIRE_MAX_SPECIES)");

/* Uploads one species (skeleton, modes, correction, mesh with LODs, leaves, look) and
 * renders its billboard impostor. The asset is not kept: the caller may free it after.
 * Returns the species id (0, 1, ...) or a negative GALE_E_* with err set (GALE_E_RANGE
 * past RENDER_MAX_SPECIES). */
int render_add_species(render *r, const asset *a, gale_err *err);

/* Sets the scene's trees (copied). Instance index = tree index for q and leaf seeds.
 * Resets q to zero and clears falling leaves; the per-tree storage grows to n (at most
 * RENDER_MAX_TREES). 0 or negative GALE_E_* (GALE_E_NOMEM: no scene is held then). */
#define RENDER_MAX_TREES (1u << 22)
int render_set_instances(render *r, uint32_t n, const render_instance *inst, gale_err *err);
/* The most trees of n_modes q each render_set_instances can take on this GPU: its texture
 * buffers' texels (GL_MAX_TEXTURE_BUFFER_SIZE) over a tree's (two for its instance, n_modes
 * for its q), less the room the storage grows by and the debris slots; at most
 * RENDER_MAX_TREES. What memory allows is found only by trying (GALE_E_NOMEM). */
uint32_t render_max_trees(const render *r, uint32_t n_modes);
/* Storm damage of tree t, applied at the next render_trees_commit: tipped by fall_rad (a
 * snapped or uprooted tree lying on the ground) and its crown thinned to the leaf slots
 * wire_damage_leaf_kept keeps at WIRE_DAMAGE_LEVELS - leaf_lost (far away, its billboard by
 * the same share). Trees out of range are ignored. */
void render_set_damage(render *r, uint32_t t, float fall_rad, float fall_az_rad,
                       uint32_t leaf_lost);
/* Whether fallen tree t was uprooted (it tips about its base and lifts its root plate)
 * rather than snapped (it tips about its break, tip_fall_break_m, above a stump that
 * stays); at the next render_trees_commit. */
void render_set_uprooted(render *r, uint32_t t, bool uprooted);
/* Sends the instances' falls to the GPU. */
void render_trees_commit(render *r);

/* Branches broken off (PROTOCOL.md "DAMAGE" BRANCH): keys (tree << 32 | node), ascending
 * (damage_view's `broken`), n of them (copied; replaces the previous set). The whole
 * sub-tree of each node (wood and leaves) is no longer drawn on that tree; keys naming a
 * tree or node outside the scene draw nothing. 0, or GALE_E_NOMEM / GALE_E_ARG (not
 * ascending) with err set. */
int render_set_broken(render *r, uint32_t n, const uint64_t *keys, gale_err *err);

/* Debris pieces drawn at most at once. */
#define RENDER_MAX_DEBRIS 64u

/* A branch broken off tree `tree` at node `node`, drawn as a rigid piece: the sub-tree of
 * that node in the rest pose of the tree's species, at the tree's scale and leaf level,
 * placed as an instance is (a point p of the tree frame at pos + R · (scale · p), R =
 * tipped by fall_rad (0..π) towards fall_az_rad after yaw, shaders/common.glsl
 * tree_frame). */
typedef struct render_debris {
    uint32_t tree, node;
    float pos[3];
    float yaw, fall_rad, fall_az_rad;
} render_debris;

/* Sets the debris pieces of the following frames (copied; n <= RENDER_MAX_DEBRIS; n = 0
 * clears). 0, or GALE_E_RANGE (too many, a tree outside the scene, a node outside its
 * species, angles not finite) with err set. */
int render_set_debris(render *r, uint32_t n, const render_debris *d, gale_err *err);

/* Stages q for one tree (n must equal its species' n_modes, else error). Staged q goes
 * to the GPU in one upload at the next render_frame. */
int render_set_q(render *r, uint32_t tree, const float *q, uint32_t n, gale_err *err);

/* The staging array itself, for writing q without a copy: tree t's modes are at
 * q[t * stride + i], i < n_modes of its species. Valid until render_set_instances. */
float *render_q_staging(render *r, uint32_t *stride);

/* Houses: at most this many, every house a welcome may carry. */
#define RENDER_MAX_OBSTACLES WIRE_MAX_OBSTACLES
_Static_assert(RENDER_MAX_OBSTACLES >= WIRE_MAX_OBSTACLES,
               "render: must hold every house a welcome may carry (WIRE_MAX_OBSTACLES)");

/* Sets the scene's obstacles (copied; replaces the previous set; n = 0 clears): n
 * axis-aligned boxes, min_max[6 i .. 6 i + 5] = min x, y, z, max x, y, z in world [m],
 * min <= max. Each is drawn as a house filling its box: plastered walls with windows,
 * a pitched roof (ridge along the longer side) taking the top of the box. Builds the
 * mesh here, never per frame. 0 or negative GALE_E_* with err set. */
int render_set_obstacles(render *r, uint32_t n, const float *min_max, gale_err *err);

/* Sets the coarse wind (copied); drives leaf flutter and falling-leaf drift. */
int render_set_wind(render *r, const render_wind *w, gale_err *err);

/* Sets the storm look (storm_fx.h: sky, light, fog, rain) of the following frames
 * (copied); NULL = calm, the look a new renderer starts with. */
void render_set_storm(render *r, const storm_fx *fx);

/* Starts one falling leaf from the tree's current (staged) pose. Bad tree/slot is an
 * error; a full ring reuses the oldest record. */
int render_add_falling_leaf(render *r, const render_leaf_seed *s, gale_err *err);

/* Drops every falling and landed leaf. */
void render_clear_falling(render *r);

/* Draws one frame of the scene at time_s (seconds, the caller's clock; flutter and
 * falling leaves use it) into the default framebuffer (window) or the offscreen one.
 * Afterwards that framebuffer stays bound with depth test off and blending set for
 * overlays, so the caller may draw a HUD on top, then call render_present. */
int render_frame(render *r, const render_camera *cam, double time_s, gale_err *err);

/* Swaps buffers (windowed); headless: glFinish. */
void render_present(render *r);

/* Changes the framebuffer size (window resize, or offscreen re-allocation). */
int render_resize(render *r, int width, int height, gale_err *err);
void render_size(const render *r, int *width, int *height);

/* Reads the last frame as tightly packed RGB, top row first: width*height*3 bytes. */
int render_read_rgb(render *r, uint8_t *rgb, gale_err *err);

/* Writes the last frame as a PNG file. */
int render_write_png(render *r, const char *path, gale_err *err);

/* Reconstructs tree `tree`'s skeleton on the GPU with the same shader the frame uses,
 * all modes, and reads it back: out[3 n_nodes] node positions in the tree frame (before
 * the instance transform), to compare with asset_reconstruct. */
int render_read_skeleton(render *r, uint32_t tree, float *out, gale_err *err);

/* The piece that breaks off tree `tree` at `node` (its sub-tree), in the tree frame at unit
 * scale: centre (mean of its rest nodes), axis (from the break towards the centre; along
 * the node's segment for a lone tip) and extent_m (centre to farthest node). 0, or
 * GALE_E_RANGE / GALE_E_NOMEM with err set. */
int render_piece_shape(render *r, uint32_t tree, uint32_t node, float centre[3], float axis[3],
                       float *extent_m, gale_err *err);

/* Height of tree t as drawn: its species' rest height times its scale [m]; 0 outside. */
float render_tree_height_m(const render *r, uint32_t tree);

/* The coarse wind [m/s] at world point p, as falling leaves and debris feel it (the grid
 * of render_set_wind, else its uniform vector). */
void render_wind_sample(const render *r, const float p[3], float out[3]);

/* Which nodes the skeleton pass draws for tree k (k < n_trees) or debris piece
 * k - n_trees: out[n_nodes] 1 drawn, 0 hidden (a broken-off sub-tree; on a piece, every
 * node outside it), to compare with damage_cut_mask. */
int render_read_attached(render *r, uint32_t k, uint8_t *out, gale_err *err);

/* Caps the scale of the level-of-detail distances (lod_mode_dist, FULL's and THIN's of
 * lod_policy.h) from the next frame on: 1 as created, less draws more trees thinned and
 * as impostors (governor.h); the frame's budget may scale them further. */
void render_set_lod_scale(render *r, float scale);

/* What the last frame saw: its view-projection matrix (column-major) and eye [m], and the
 * distance [m] past which no tree is drawn with every leaf (FULL's outer, scaled). */
void render_last_view(const render *r, float viewproj[16], float eye[3], float *full_m);

/* Draws the scene from the next frame on at this share of the target's width and height
 * (0.25 .. 1; else 1), scaled up onto the target before overlays (governor.h). */
void render_set_res_scale(render *r, float scale);

/* The calm fog's distance [m] from the next frame on (> 0; the storm closes it in by its
 * own share). lod_policy.h's fog_for_scene gives a scene's. */
void render_set_fog_dist(render *r, float fog_m);

/* Counters of the last frame. */
render_stats render_get_stats(const render *r);

#endif
