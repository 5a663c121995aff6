/* The clients' level-of-detail policy: which trees a frame draws and how finely, and what
 * a client asks the server to stream. The page holds the same numbers (web/lod_policy.js);
 * tests/web/test_lod_policy_js.mjs holds the two to each other. Distances are from the eye
 * to a tree's middle [m]. */
#ifndef GALE_LOD_POLICY_H
#define GALE_LOD_POLICY_H

#include <math.h>

/* Levels, finest first. FULL: every leaf on the asset's bark meshes by distance; THIN: a
 * deterministic share of the leaves, each grown so the crown covers as much, on the
 * coarsest bark mesh, posed with the few modes the server sends past lod_m; IMPOSTOR: a
 * billboard of the species at rest that sways with the tree's lowest modes and keeps the
 * share of its crown the storm left; a fallen tree's lies along its fall, unswayed
 * (shaders/bill.vert). A debris piece is never an impostor: past THIN it is not drawn. */
enum { LOD_FULL = 0, LOD_THIN = 1, LOD_IMPOSTOR = 2, LOD_LEVELS = 3 };

/* Outer distance of each level [m]; past the last nothing is drawn: the whole 2 km
 * landscape from the aerial camera (2 km off, its far corner 3.4 km). */
static const float lod_outer_m[LOD_LEVELS] = { 90.0f, 250.0f, 4000.0f };

/* The share of a species' leaves drawn at each level (1 / a whole number; 0: none, the
 * impostor shows the crown), and each drawn leaf's size × lod_leaf_grow: √(1 / share)
 * would keep the leaves' area, but fewer larger leaves overlap less, so a thinned crown
 * covered 10 % more pixels than the whole one (tests/test_render.c's dolly); 0.9 of it
 * keeps the coverage within 1 %. Whether the bark is drawn. */
static const float lod_leaf_share[LOD_LEVELS] = { 1.0f, 1.0f / 4.0f, 0.0f };
static const float lod_leaf_grow[LOD_LEVELS] = { 1.0f, 1.8f, 0.0f };
static const int lod_bark[LOD_LEVELS] = { 1, 1, 0 };

/* The modes a tree of each level is posed with at most. */
static const int lod_modes_max[LOD_LEVELS] = { 64, 4, 2 };

/* The modes an impostor sways with (shaders/bill.vert). */
#define LOD_IMPOSTOR_MODES 2

/* The last share of a level's outer distance cross-fades, dithered, into the next: a
 * tree in the band is drawn at both levels, complementary pixels each. */
#define LOD_FADE_SHARE 0.2f

/* A level switched whole (the page's) changes only past its outer distance × (1 ± this). */
#define LOD_HYSTERESIS 0.08f

/* The bark mesh's own levels within FULL: one per this many metres. */
#define LOD_MESH_STEP_M 30.0f

/* A frame's budget: triangles of bark, leaves and impostors together, and nodes posed by
 * the skeleton pass. Over either, FULL's and THIN's distances are scaled down until the
 * frame fits; the distances grow back by at most LOD_GROW_PER_FRAME a frame. */
#define LOD_BUDGET_TRIANGLES 1000000
#define LOD_BUDGET_NODES 2000000
#define LOD_BUDGET_DRAWS 100
#define LOD_GROW_PER_FRAME 1.25f

/* What a client asks of the server (PROTOCOL.md `view`): the stream's far_m is the last
 * level's outer distance, lod_m FULL's (past it the server's few modes suffice). */
#define VIEW_FAR_M (lod_outer_m[LOD_LEVELS - 1])
#define VIEW_LOD_M (lod_outer_m[LOD_FULL])

/* The calm fog's distance [m]: at least FOG_MIN_M, and the scene's radius (half the
 * diagonal of its trees' box) × FOG_PER_SCENE_RADIUS_M, so a large scene seen from above
 * is not all fog (the 2 km landscape: 2.8 km, its middle seen from the aerial camera 57 %
 * clear, its far corner 33 %, the impostors' reach 17 %). */
#define FOG_MIN_M 450.0f
#define FOG_PER_SCENE_RADIUS_M 2.0f

/* The calm fog's distance [m] of a scene whose trees' box in x, y is lo .. hi [m]. */
static inline float fog_for_scene(const float lo[2], const float hi[2])
{
    float dx = hi[0] - lo[0], dy = hi[1] - lo[1];
    float radius_m = 0.5f * sqrtf(dx * dx + dy * dy);
    float fog_m = FOG_PER_SCENE_RADIUS_M * radius_m;
    return fog_m > FOG_MIN_M ? fog_m : FOG_MIN_M;
}

#endif
