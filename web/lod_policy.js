// The client's level-of-detail policy: which trees a frame draws and how finely, and what
// the page asks the server to stream. One place for the numbers, so that the native client
// can mirror them. Distances are from the eye to a tree's middle (its base raised by half
// its height) [m]; a frame's budget pushes FULL's and THIN's distances in by one factor
// when the trees in view would cost more, the impostors' only when they alone would
// (web/lod_select.js).

// Levels, finest first. NONE: not drawn.
export const LOD = { FULL: 0, THIN: 1, IMPOSTOR: 2, NONE: 255 };
export const LOD_LEVELS = 3;

// Outer distance of each level [m]: every leaf and the finer bark meshes within FULL (the
// clearing's and the town block's near trees look as they always did); past it a
// deterministic subset of the leaves, each scaled up so the crown covers as much, on the
// coarsest bark mesh; past THIN the species' impostor (Singh section 2, Oliapuram LOD:
// a quad turned about the vertical toward the eye, the tree at rest seen from the side),
// two triangles a tree and no skeleton row, so that every tree of a 2 km landscape in
// view can be drawn (the aerial camera is 2 km off, the landscape's far corner 3.4 km);
// past IMPOSTOR none.
export const LOD_OUTER_M = [90, 250, 4000];

// The share of a species' leaves drawn at each level (1 / a whole number), and each drawn
// leaf's size × LOD_LEAF_GROW: √(1 / share) would keep the leaves' area, but fewer larger
// leaves overlap less, so a thinned crown covered 10 % more pixels than the whole one;
// 0.9 of it keeps the coverage within 1 % (tests/test_render.c's dolly); whether its bark
// is drawn. An impostor draws neither: its texture holds both.
export const LOD_LEAF_SHARE = [1, 1 / 4, 0];
export const LOD_LEAF_GROW = [1, 1.8, 0];
export const LOD_BARK = [true, true, false];

// The leaves drawn of a species of `count` at a level of share `share`: the share rounded,
// at least one, none at a share of 0 (the impostor's).
export function leavesAt(count, share) {
    if (!count || !(share > 0)) return 0;
    return Math.min(count, Math.max(1, Math.round(Math.fround(count * share))));
}

// The modes a tree of each level is posed with at most: past FULL the server's LOD count
// (gale-server sends 4 past lod_m), also when it streams the whole scene; the skeleton
// pass reads every mode of every node, so this is most of a posed tree's cost. An
// impostor sways with its lowest LOD_IMPOSTOR_MODES (web/imp_sway.js).
export const LOD_MODES_MAX = [64, 4, 2];
export const LOD_IMPOSTOR_MODES = 2;

// The last share of THIN's outer distance where a tree is drawn both ways, THIN dithered
// out and its impostor dithered in (the screen door of shaders/common.glsl dither_keep:
// the two keep complementary pixels), so that no tree pops as it crosses the edge.
export const LOD_FADE_SHARE = 0.2;

// The calm fog distance [m]: max(FOG_MIN_M, FOG_PER_SCENE_RADIUS_M × the scene's radius),
// the radius half the diagonal of the trees' bounding box in x, y (web/render_sky.js), so
// that the clearing keeps the native renderer's 450 m (client/render/render.c) and an
// aerial view of the 2 km landscape is not all fog (2.8 km: its middle seen from the aerial
// camera 57 % clear, its far corner 33 %). A storm scales it (web/storm_fx.js).
export const FOG_MIN_M = 450;
export const FOG_PER_SCENE_RADIUS_M = 2.0;

// The calm fog distance [m] of a scene whose trees' box in x, y is lo .. hi [m].
export function fogForScene(lo, hi) {
    const radius_m = 0.5 * Math.hypot(hi[0] - lo[0], hi[1] - lo[1]);
    return Math.max(FOG_MIN_M, FOG_PER_SCENE_RADIUS_M * radius_m);
}

// A tree moves to a coarser level only past its level's outer distance × (1 + this), and
// back to a finer one only inside that level's outer distance × (1 − this): a camera
// still at a boundary never makes a tree flip from frame to frame.
export const LOD_HYSTERESIS = 0.08;

// The bark mesh's own levels within FULL: one per this many metres (the asset's LODs,
// as gale-client's render picks them); coarser levels take the asset's coarsest.
export const LOD_MESH_STEP_M = 30;

// A frame's hard budget (a 1920×1080 picture on a modest GPU): triangles of bark, leaves and
// impostors (2 a tree) together, trees posed by the skeleton pass (FULL and THIN only) (one row of each skeleton texture, as
// wide as the largest species: 3,180 nodes × 2,048 rows of RGBA32F is 104 MB a texture).
// Over either, every distance above is scaled down until the frame fits.
export const LOD_BUDGET_TRIANGLES = 1000000;
export const LOD_BUDGET_TREES = 2048;
// and nodes posed (the skeleton pass's fragments, twice: 630 oaks of 3,180 nodes, 3,160
// palms of 633)
export const LOD_BUDGET_NODES = 2000000;
// What a felled tree posed adds to the budget (web/render_damage.js): an uprooted one's root
// plate (4 × 24 triangles) or a snapped one's stump (7 × 12); the larger for either.
export const LOD_FELLED_TRIANGLES = 4 * 24;
// Draw calls a frame may issue; the draws are per species and level (a few dozen: one a
// species for all its impostors), and web/render_gl.js counts them against this.
export const LOD_BUDGET_DRAWS = 100;
// The distances may grow back by this factor a frame once the view costs less (a
// sudden jump would flood one frame).
export const LOD_GROW_PER_FRAME = 1.25;

// What the page asks of the server (PROTOCOL.md `view`): the draw distance is the stream's
// far_m, and lod_m, past which trees are sent with the server's few modes, the FULL
// level's outer distance (past it the crown is thinned and its sway is the coarse modes').
export const VIEW_FAR_M = LOD_OUTER_M[LOD_LEVELS - 1];
export const VIEW_LOD_M = LOD_OUTER_M[LOD.FULL];
// A view message at most this often [s], only when the eye moved more than VIEW_MOVE_M or
// the direction turned more than VIEW_TURN_DEG, and once more VIEW_SETTLE_S after the
// camera stops (the last view is the one the server keeps).
export const VIEW_MIN_INTERVAL_S = 0.25;
export const VIEW_MOVE_M = 2;
export const VIEW_TURN_DEG = 2;
export const VIEW_SETTLE_S = 0.3;

// The grid the trees are bucketed into at welcome: about this many trees a cell, cells no
// smaller than VIEW_CELL_MIN_M across.
export const CELL_TREES = 32;
export const CELL_MIN_M = 8;
