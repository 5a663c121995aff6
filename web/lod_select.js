// Each frame's level of every tree in view (web/lod_policy.js): by its distance, with
// hysteresis per tree, under the frame's hard budget. The budget is met without sorting
// the trees: their distances go into a histogram per species, and the largest scale of
// the policy's distances whose worst case (every tree at the finest level its hysteresis
// could keep, at its bin's near edge) fits the budget is taken (FULL's and THIN's; the
// impostors' reach only when they alone, 2 triangles a tree, would not fit); the trees' levels are
// then chosen at that scale, each no finer than that worst case, so the frame never costs
// more than the histogram said. Between THIN and IMPOSTOR a tree cross-fades over the last
// LOD_FADE_SHARE of THIN's outer distance: a share of it in the impostor that grows with
// its distance, 1 from that distance on, whatever its level. A tree that lies (fallen,
// uprooted, snapped) is chosen as a standing one is: its impostor lies along its fall
// (web/render_list.js impFall, web/imp_shader.js).
import { LOD, LOD_LEVELS, LOD_OUTER_M, LOD_HYSTERESIS, LOD_MESH_STEP_M, LOD_BUDGET_TRIANGLES, LOD_BUDGET_TREES, LOD_FELLED_TRIANGLES,
    LOD_BUDGET_NODES, LOD_BUDGET_DRAWS, LOD_GROW_PER_FRAME, LOD_FADE_SHARE } from './lod_policy.js';

const BINS = 512;
const SCALE_STEP = 0.9; // the budget's search: the distances scaled down by this a try
const SCALE_MIN = 1e-3;
const NEVER = 0xffffffff; // a frame select never reaches

// The level of distance d at distance scale s (the policy's distances × s) and the last
// level's scale sf (its outer distance × sf), NONE past the last.
export function levelAt(d, s, sf = 1) {
    for (let l = 0; l < LOD_LEVELS - 1; l++) if (d < LOD_OUTER_M[l] * s) return l;
    return d < LOD_OUTER_M[LOD_LEVELS - 1] * sf ? LOD_LEVELS - 1 : LOD.NONE;
}

// The bark mesh's level (the asset's LOD) of a tree at distance d drawn at level `level`.
export function meshLod(d, level, n_lods) {
    return level === LOD.FULL ? Math.min(n_lods - 1, Math.floor(d / LOD_MESH_STEP_M)) : n_lods - 1;
}

// The share of a tree at distance d in its impostor at distance scale s: 0 inside the last
// LOD_FADE_SHARE of THIN's outer distance, rising linearly to 1 at that distance.
export function impostorShare(d, s) {
    const e = LOD_OUTER_M[LOD.THIN] * s, e0 = e * (1 - LOD_FADE_SHARE);
    return d <= e0 ? 0 : d >= e ? 1 : (d - e0) / (e - e0);
}

function bitCount(x) {
    let m = 0;
    for (; x; x &= x - 1) m++;
    return m;
}

// Draw calls a frame's trees cost besides the per species ones: sky, houses, plates,
// stumps, falling leaves, rain, and a debris piece's meshes.
export const LOD_DRAWS_FIXED = 8;

export class LodSelect {
    constructor(n_trees) {
        this.level = new Uint8Array(n_trees).fill(LOD.NONE); // each tree's level last frame it was in view
        this.seen = new Uint32Array(n_trees); // the frame it was last in view (0: never)
        // the frame each cell was last listed whole (NEVER: not yet), its trees then
        // impostors, and each tree's cell (select's whole: web/cull_grid.js; none: one cell)
        this.cellWhole = new Uint32Array(1).fill(NEVER);
        this.cellOf = new Int32Array(n_trees);
        this.frame = 0;
        this.scale = 1; // the budget's scale of FULL's and THIN's distances, last frame
        this.cap = 1; // the frame-time governor's cap on that scale (web/governor.js)
        this.scaleFar = 1; // and of the impostors' reach
        this.hist = null;
    }

    // The farthest distance the next frame may draw: the cull's far_m.
    reach_m() {
        return LOD_OUTER_M[LOD_LEVELS - 1] * Math.min(1, this.scaleFar * LOD_GROW_PER_FRAME) * (1 + LOD_HYSTERESIS);
    }

    // The band of distances in which a frame may list a cell's trees whole (web/cull_grid.js
    // gather's whole), given the species cost draws (select's cost): from the first bin
    // of the budget's histogram past THIN's reach at the largest scale this frame may take,
    // widened by the hysteresis, to the impostors' reach narrowed by it. A standing tree
    // of a drawn species there is an impostor alone (share 1) at any scale the budget picks,
    // whatever its level last frame, and its bin and the cell's nearest one cost the
    // budget the same: select gives such a cell's trees that level without looking at
    // them. Reused each call.
    wholeBand(cost) {
        const sMax = Math.min(this.cap, this.scale * LOD_GROW_PER_FRAME), fMax = Math.min(1, this.scaleFar * LOD_GROW_PER_FRAME);
        const b = this.band || (this.band = { near_m: 0, far_m: 0, bin_m: 0, drawn: null });
        if (!b.drawn || b.drawn.length !== cost.length) b.drawn = new Uint8Array(cost.length);
        for (let s = 0; s < cost.length; s++) b.drawn[s] = cost[s] ? 1 : 0;
        b.near_m = LOD_OUTER_M[LOD.THIN] * (sMax * (1 + LOD_HYSTERESIS));
        b.far_m = LOD_OUTER_M[LOD.IMPOSTOR] * (fMax * (1 - LOD_HYSTERESIS));
        b.bin_m = LOD_OUTER_M[LOD_LEVELS - 1] * fMax * (1 + LOD_HYSTERESIS) / BINS;
        return b;
    }

    // ids[0..n) in view at distances dist, of species species[id]: the trees' own numbers,
    // or any others below n_trees that a caller keeps each tree under from frame to frame
    // (web/render_list.js: its place in the cells, web/cull_grid.js), which index this
    // selection's memory of each tree's level; cost[s][level][mesh lod]:
    // triangles of one tree of species s at FULL and THIN, of its impostor at IMPOSTOR
    // (null: a species not drawn); nodes[s]: its nodes posed; budget: { triangles, trees,
    // nodes, draws } (trees and nodes: those the skeleton pass poses, FULL and THIN), and
    // optionally felled (per id a row of 4 whose third value is not 0 for a felled tree:
    // web/render_list.js placeImp), each posed one costing LOD_FELLED_TRIANGLES more.
    // Writes each tree's
    // level into out[0..n) and its share in its impostor into share[0..n) (0 < share < 1:
    // drawn both at THIN and as an impostor; 1: as an impostor alone, also at THIN kept by
    // the hysteresis), and returns { scale, scale_far (the impostors' reach's), and the
    // worst case's triangles, trees, nodes, draws }. whole: web/cull_grid.js gather's
    // out.whole (its ids places), gathered in the band of wholeBand(cost): each of its
    // cells' trees an impostor alone; null when the budget would pull the impostors'
    // reach in this frame (whole cells then do not hold), with nothing changed: the caller
    // gathers again without them.
    select(ids, dist, n, species, cost, out, budget = {}, nodes = [], share = null, whole = null) {
        const maxTris = budget.triangles ?? LOD_BUDGET_TRIANGLES, maxTrees = budget.trees ?? LOD_BUDGET_TREES;
        const felled = budget.felled ?? null;
        const maxNodes = budget.nodes ?? LOD_BUDGET_NODES, maxDraws = (budget.draws ?? LOD_BUDGET_DRAWS) - LOD_DRAWS_FIXED;
        const sMax = Math.min(this.cap, this.scale * LOD_GROW_PER_FRAME), fMax = Math.min(1, this.scaleFar * LOD_GROW_PER_FRAME);
        const reach = LOD_OUTER_M[LOD_LEVELS - 1] * fMax * (1 + LOD_HYSTERESIS);
        const ns = cost.length, w = reach / BINS;
        if (!this.drawn || this.drawn.length !== ns) this.drawn = new Uint8Array(ns);
        const drawn = this.drawn;
        for (let s = 0; s < ns; s++) drawn[s] = cost[s] ? 1 : 0;
        if (whole && whole.n) {
            // listed in another frame's band (the governor's cap moved since)
            const b = whole.band;
            if (!b || b.near_m !== LOD_OUTER_M[LOD.THIN] * (sMax * (1 + LOD_HYSTERESIS)) || b.bin_m !== w ||
                b.far_m !== LOD_OUTER_M[LOD.IMPOSTOR] * (fMax * (1 - LOD_HYSTERESIS))) return null;
        }
        if (!this.hist || this.hist.length !== ns * BINS) this.hist = new Uint32Array(ns * BINS);
        if (!this.felledHist) this.felledHist = new Uint32Array(BINS);
        const hist = this.hist, felledHist = this.felledHist, nw = whole ? whole.n : 0;
        hist.fill(0);
        felledHist.fill(0);
        if (nw) this.histWhole(whole, w);
        this.histTrees(ids, dist, n, species, w);
        if (felled) this.histFelled(ids, dist, n, species, w, felled);
        // the worst case at scale s: each bin's trees at the level of its near edge, the
        // outer distances widened by the hysteresis; a standing tree past FULL is THIN up to
        // THIN's outer distance and an impostor from its fade on (the fade ignores the
        // hysteresis); the draws: per species the skeleton pass's two, a bark mesh and a
        // leaf level each, one for its impostors
        const worst = (sc, sf) => {
            let tris = 0, count = 0, posed = 0, draws = 0;
            const e = LOD_OUTER_M[LOD.THIN] * sc, e0 = e * (1 - LOD_FADE_SHARE);
            // a felled tree posed (short of THIN's outer distance) draws its plate or stump too
            for (let b = 0; felled && b < BINS && b * w < e; b++) tris += felledHist[b] * LOD_FELLED_TRIANGLES;
            for (let s = 0; s < ns; s++) {
                const c = cost[s];
                if (!c) continue;
                const nl = c[0].length;
                let meshes = 0, levels = 0, imp = false;
                for (let b = 0; b < BINS; b++) {
                    const k = hist[s * BINS + b];
                    if (!k) continue;
                    const d = b * w;
                    const l = levelAt(d, sc * (1 + LOD_HYSTERESIS), sf * (1 + LOD_HYSTERESIS));
                    if (l === LOD.NONE) break;
                    let thin = l === LOD.THIN;
                    // (a FULL bin reaches the fade only at a tiny scale)
                    if (l !== LOD.FULL) thin = d < e;
                    const bill = d + w > e0;
                    if (l === LOD.FULL) {
                        const m = meshLod(d, l, nl);
                        tris += k * c[l][m];
                        meshes |= 1 << m;
                        levels |= 1;
                    }
                    if (thin) {
                        tris += k * c[LOD.THIN][nl - 1];
                        meshes |= 1 << (nl - 1);
                        levels |= 2;
                    }
                    if (l === LOD.FULL || thin) {
                        count += k;
                        posed += k * (nodes[s] || 0);
                    }
                    if (bill) {
                        tris += k * c[LOD.IMPOSTOR][nl - 1];
                        imp = true;
                    }
                }
                draws += (levels ? 2 : 0) + bitCount(meshes) + bitCount(levels) + (imp ? 1 : 0);
            }
            return { tris, count, posed, draws };
        };
        // grown when that fits; else last frame's scale when it still fits (a view at the
        // budget's edge keeps its distances); else down until it fits
        const over = (r) => r.tris > maxTris || r.count > maxTrees || r.posed > maxNodes || r.draws > maxDraws;
        let sc = sMax, sf = fMax, wc = worst(sc, sf);
        if (over(wc) && sc > this.scale) {
            sc = this.scale;
            wc = worst(sc, sf);
        }
        while (over(wc) && sc > SCALE_MIN) {
            sc *= SCALE_STEP;
            wc = worst(sc, sf);
        }
        // the impostors alone over the budget (hundreds of thousands in view): their reach in
        if (over(wc) && sf > this.scaleFar) {
            sf = this.scaleFar;
            wc = worst(sc, sf);
        }
        while (over(wc) && sf > SCALE_MIN) {
            sf *= SCALE_STEP;
            wc = worst(sc, sf);
        }
        // closer to the edge of the budget between a fitting scale and the step above it
        if (sc < this.scale || (sc < sMax && !over(wc))) {
            let hiS = Math.min(sMax, sc / SCALE_STEP);
            for (let k = 0; k < 4 && !over(wc); k++) {
                const mid = 0.5 * (sc + hiS), wm = worst(mid, sf);
                if (over(wm)) hiS = mid;
                else {
                    sc = mid;
                    wc = wm;
                }
            }
        }
        if (nw && sf !== fMax) return null;
        this.scale = sc;
        this.scaleFar = sf;
        const f = ++this.frame;
        if (whole) this.wholeLevels(whole, f);
        this.levels(ids, dist, n, species, out, share, sc, sf, reach, f);
        return { scale: sc, scale_far: sf, triangles: wc.tris, trees: wc.count, nodes: wc.posed, draws: wc.draws + LOD_DRAWS_FIXED };
    }

    // select's passes over the trees, each loop last in a function of its own (the JIT's
    // code for a loop entered mid-call then holds no later step it has not yet seen run).

    // The budget's histogram (bins of w [m]; per species its trees' bins): a whole cell's trees in the bin of its nearest distance
    // (past THIN's, as each tree's own: the same cost at every scale this frame may take).
    histWhole(whole, w) {
        const hist = this.hist, run = whole.run, gns = whole.ns, nc = whole.nc, nw = whole.n;
        for (let k = 0; k < nw; k++) {
            const c = whole.cell[k], b = Math.floor(whole.near_m[k] / w);
            for (let s = 0; s < gns; s++) {
                const m = run[s * nc + c + 1] - run[s * nc + c];
                if (m && b < BINS) hist[s * BINS + b] += m;
            }
        }
    }

    // And select's trees one by one.
    histTrees(ids, dist, n, species, w) {
        const hist = this.hist, drawn = this.drawn;
        for (let i = 0; i < n; i++) {
            const t = ids[i], s = species[t];
            if (!drawn[s]) continue;
            const b = Math.floor(dist[i] / w);
            if (b < BINS) hist[s * BINS + b]++;
        }
    }

    // And the felled ones among them (a whole cell's lie past THIN: never posed).
    histFelled(ids, dist, n, species, w, felled) {
        const fh = this.felledHist, drawn = this.drawn;
        for (let i = 0; i < n; i++) {
            const t = ids[i];
            if (!drawn[species[t]] || felled[4 * t + 2] === 0) continue;
            const b = Math.floor(dist[i] / w);
            if (b < BINS) fh[b]++;
        }
    }

    // The whole cells of frame f: their trees impostors alone, as levels reads them
    // next frame (lastLevel).
    wholeLevels(whole, f) {
        if (this.cellWhole.length !== whole.cell.length) this.cellWhole = new Uint32Array(whole.cell.length).fill(NEVER);
        this.cellOf = whole.cellOf;
        const cw = this.cellWhole;
        for (let k = 0; k < whole.n; k++) cw[whole.cell[k]] = f;
    }

    // Tree id's level at the last frame select ran (NONE: not drawn, or not in view), as
    // the hysteresis reads it: its own, or IMPOSTOR in a cell listed whole.
    lastLevel(id) {
        const f = this.frame;
        if (this.seen[id] === f) return this.level[id];
        return this.cellWhole[this.cellOf[id]] === f ? LOD.IMPOSTOR : LOD.NONE;
    }

    // The level and impostor share of each of select's trees at frame f, scales sc and sf.
    levels(ids, dist, n, species, out, share, sc, sf, reach, f) {
        const seen = this.seen, level = this.level, drawn = this.drawn, lo = 1 - LOD_HYSTERESIS, hi = 1 + LOD_HYSTERESIS;
        const cw = this.cellWhole, cellOf = this.cellOf;
        // the edges at this scale, inlined (levelAt), and the arrays read per tree held
        // here: the loop runs over every tree in view (100,000 from over the landscape)
        const eFull = LOD_OUTER_M[LOD.FULL] * sc, eThin = LOD_OUTER_M[LOD.THIN] * sc, eFar = LOD_OUTER_M[LOD.IMPOSTOR] * sf;
        const eFade = eThin * (1 - LOD_FADE_SHARE);
        for (let i = 0; i < n; i++) {
            const t = ids[i], d = dist[i];
            let l = d < eFull ? LOD.FULL : d < eThin ? LOD.THIN : d < eFar ? LOD.IMPOSTOR : LOD.NONE, sh = 0;
            // its level last frame: its own, or an impostor in a cell listed whole (read
            // for every tree: the JIT's code then has seen both)
            const pw = cw[cellOf[t]] === f - 1 ? LOD.IMPOSTOR : LOD.NONE, p = seen[t] === f - 1 ? level[t] : pw;
            if (!drawn[species[t]] || d >= reach) l = LOD.NONE;
            else if (p !== LOD.NONE && l > p) l = Math.max(p, levelAt(d, sc * hi, sf * hi)); // coarser: only past the widened edge
            else if (p !== LOD.NONE && l < p) l = Math.min(p, levelAt(d, sc * lo, sf * lo)); // finer: only inside the narrowed edge
            if (l === LOD.THIN || l === LOD.IMPOSTOR) {
                if (d > eFade) {
                    // inside THIN's outer distance THIN, fading; past it the hysteresis
                    // keeps a THIN tree's level, wholly in its impostor (share 1, no
                    // skeleton row), so a camera rocking there flips nothing
                    sh = impostorShare(d, sc);
                    if (sh < 1) l = LOD.THIN;
                } else l = LOD.THIN;
            }
            out[i] = l;
            if (share !== null) share[i] = sh;
            level[t] = l;
            seen[t] = l === LOD.NONE ? 0 : f;
        }
    }
}
