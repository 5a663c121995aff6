// Each frame's level of every tree in view (web/lod_policy.js): by its distance, with
// hysteresis per tree, under the frame's hard budget. The budget is met without sorting
// the trees: their distances go into a histogram per species, and the largest scale of
// the policy's distances whose worst case (every tree at the finest level its hysteresis
// could keep, at its bin's near edge) fits the budget is taken; the trees' levels are
// then chosen at that scale, each no finer than that worst case, so the frame never costs
// more than the histogram said.
import { LOD, LOD_LEVELS, LOD_OUTER_M, LOD_HYSTERESIS, LOD_MESH_STEP_M, LOD_BUDGET_TRIANGLES, LOD_BUDGET_TREES,
    LOD_BUDGET_NODES, LOD_GROW_PER_FRAME } from './lod_policy.js';

const BINS = 512;
const SCALE_STEP = 0.9; // the budget's search: the distances scaled down by this a try
const SCALE_MIN = 1e-3;

// The level of distance d at distance scale s (policy distances × s), NONE past the last.
export function levelAt(d, s) {
    for (let l = 0; l < LOD_LEVELS; l++) if (d < LOD_OUTER_M[l] * s) return l;
    return LOD.NONE;
}

// The bark mesh's level (the asset's LOD) of a tree at distance d drawn at level `level`.
export function meshLod(d, level, n_lods) {
    return level === LOD.FULL ? Math.min(n_lods - 1, Math.floor(d / LOD_MESH_STEP_M)) : n_lods - 1;
}

export class LodSelect {
    constructor(n_trees) {
        this.level = new Uint8Array(n_trees).fill(LOD.NONE); // each tree's level last frame it was in view
        this.seen = new Uint32Array(n_trees); // the frame it was last in view (0: never)
        this.frame = 0;
        this.scale = 1; // the budget's scale of the policy's distances, last frame
        this.hist = null;
    }

    // The farthest distance the next frame may draw: the cull's far_m.
    reach_m() {
        return LOD_OUTER_M[LOD_LEVELS - 1] * Math.min(1, this.scale * LOD_GROW_PER_FRAME) * (1 + LOD_HYSTERESIS);
    }

    // trees[0..n) in view at distances dist, of species speciesOf(t); cost[s][level][mesh
    // lod]: triangles of one tree of species s (null: a species not drawn); nodes[s]: its
    // nodes posed; budget: { triangles, trees, nodes }. Writes each tree's level into
    // out[0..n) and returns { scale, and the worst case's triangles, trees, nodes }.
    select(trees, dist, n, speciesOf, cost, out, budget = {}, nodes = []) {
        const maxTris = budget.triangles ?? LOD_BUDGET_TRIANGLES, maxTrees = budget.trees ?? LOD_BUDGET_TREES;
        const maxNodes = budget.nodes ?? LOD_BUDGET_NODES;
        const sMax = Math.min(1, this.scale * LOD_GROW_PER_FRAME), reach = LOD_OUTER_M[LOD_LEVELS - 1] * sMax * (1 + LOD_HYSTERESIS);
        const ns = cost.length, w = reach / BINS;
        if (!this.hist || this.hist.length !== ns * BINS) this.hist = new Uint32Array(ns * BINS);
        const hist = this.hist;
        hist.fill(0);
        for (let i = 0; i < n; i++) {
            const s = speciesOf(trees[i]);
            if (!cost[s]) continue;
            const b = Math.floor(dist[i] / w);
            if (b < BINS) hist[s * BINS + b]++;
        }
        // the worst case at scale s: each bin's trees at the level of its near edge, the
        // outer distances widened by the hysteresis
        const worst = (sc) => {
            let tris = 0, count = 0, posed = 0;
            for (let s = 0; s < ns; s++) {
                const c = cost[s];
                if (!c) continue;
                const nl = c[0].length;
                for (let b = 0; b < BINS; b++) {
                    const k = hist[s * BINS + b];
                    if (!k) continue;
                    const d = b * w, l = levelAt(d, sc * (1 + LOD_HYSTERESIS));
                    if (l === LOD.NONE) break;
                    tris += k * c[l][meshLod(d, l, nl)];
                    count += k;
                    posed += k * (nodes[s] || 0);
                }
            }
            return { tris, count, posed };
        };
        // grown when that fits; else last frame's scale when it still fits (a view at the
        // budget's edge keeps its distances); else down until it fits
        const over = (r) => r.tris > maxTris || r.count > maxTrees || r.posed > maxNodes;
        let sc = sMax, wc = worst(sc);
        if (over(wc) && sc > this.scale) {
            sc = this.scale;
            wc = worst(sc);
        }
        while (over(wc) && sc > SCALE_MIN) {
            sc *= SCALE_STEP;
            wc = worst(sc);
        }
        // closer to the edge of the budget between a fitting scale and the step above it
        if (sc < this.scale || (sc < sMax && !over(wc))) {
            let hiS = Math.min(sMax, sc / SCALE_STEP);
            for (let k = 0; k < 4 && !over(wc); k++) {
                const mid = 0.5 * (sc + hiS), wm = worst(mid);
                if (over(wm)) hiS = mid;
                else {
                    sc = mid;
                    wc = wm;
                }
            }
        }
        this.scale = sc;
        const f = ++this.frame, lo = sc * (1 - LOD_HYSTERESIS), hi = sc * (1 + LOD_HYSTERESIS);
        for (let i = 0; i < n; i++) {
            const t = trees[i], d = dist[i];
            let l = levelAt(d, sc);
            const p = this.seen[t] === f - 1 ? this.level[t] : LOD.NONE;
            if (!cost[speciesOf(t)] || Math.floor(d / w) >= BINS) l = LOD.NONE;
            else if (p !== LOD.NONE && l > p) l = Math.max(p, levelAt(d, hi)); // coarser: only past the widened edge
            else if (p !== LOD.NONE && l < p) l = Math.min(p, levelAt(d, lo)); // finer: only inside the narrowed edge
            out[i] = l;
            this.level[t] = l;
            this.seen[t] = l === LOD.NONE ? 0 : f;
        }
        return { scale: sc, triangles: wc.tris, trees: wc.count, nodes: wc.posed };
    }
}
