// The 2 km landscape's scale under Node, shared by test_imp_js, test_cull_fast_js and
// bench_cull: 100,000 trees in a 2 km square (ground ±8 m), three species of the baked
// assets' sizes, on a RendererList (web/render_list.js) with no GL (its data textures are
// stand-ins), and the two cameras over it (1280 × 720, 50°).
import { RendererList } from '../../web/render_list.js';
import { LOD_BUDGET_TREES } from '../../web/lod_policy.js';
import { perspective, lookAt, mul } from '../../web/view_math.js';

// The trees as the welcome's rows [species, x, y, z, yaw, scale], the species, and a
// renderer set up for them (setupCulling).
export function landscape(N = 100000) {
    let seed = 777;
    const rnd = () => ((seed = (seed * 1103515245 + 12345) >>> 0) / 4294967296);
    const rows = [];
    for (let t = 0; t < N; t++) {
        const x = -1000 + 2000 * rnd(), y = -1000 + 2000 * rnd();
        rows.push([t % 3, x, y, 8 * Math.sin(x / 130) * Math.cos(y / 170), 6.283 * rnd(), 0.8 + 0.4 * rnd()]);
    }
    // oak, pine, palm: nodes, leaves, bark LODs' indices, height [m], crown radius [m]
    const species = [[3180, 6000, [72000, 36000, 12072], 22, 9], [1135, 4000, [30000, 15000, 6000], 28, 5], [633, 800, [12000, 6000, 3000], 14, 6]].map(([nn, nlv, lods, h, cr]) => ({
        n_nodes: nn, n_modes: 32, n_leaves: nlv, n_lods: 3, lod_count: lods, lod_first: [0, 0, 0], height: h, crown_r: cr,
        a: { n_leaves: nlv, leaf_offset: new Float32Array(3 * nlv), leaf_node: new Uint32Array(nlv), leaf_normal: new Float32Array(3 * nlv), leaf_size: new Float32Array(nlv).fill(0.1) },
    }));
    const r = Object.create(RendererList.prototype);
    Object.assign(r, { species, n_trees: N, debris: [], q_trees: Infinity, max_rows: LOD_BUDGET_TREES, maxTex: 16384, stats: {},
        treeData: new Float32Array(8 * N), dataTex: (c, n) => ({ w: n, n }) });
    r.setupCulling(rows);
    return { r, rows, species };
}

// Above the square's south-west corner, looking across it to the north-east; low over its
// middle (FULL and THIN near, fading, the budget's scale below 1, the impostors' reach whole).
export const CAMERAS = [['aerial', [-1150, -1150, 600], [0, 0, 0]], ['low', [-100, -100, 40], [200, 150, 0]]];

// The view-projection of a 1280 × 720 frame of fovy_deg (50°) from eye to target (z up),
// its far plane far_m (3,000 m) off.
export function viewProj(eye, target, fovy_deg = 50, far_m = 3000) {
    return mul(perspective(fovy_deg * Math.PI / 180, 1280 / 720, 0.3, far_m), lookAt(eye, target, [0, 0, 1]));
}
