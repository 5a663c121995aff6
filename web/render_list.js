// The frame's draw list: the trees in view (web/cull_grid.js) at their levels
// (web/lod_select.js, the numbers of web/lod_policy.js) laid out for the draws, per
// species its skeleton rows in level order (every leaf on the asset's bark meshes by
// distance, then a share of the leaves on the coarsest mesh), so that each species'
// skeleton pass is two draws, its bark one draw per mesh and its leaves one per level, and
// apart from them its impostors (web/render_imp.js), one draw a species and no skeleton
// row. A counting sort by species and level: never a sort of the trees by distance. A
// cell far enough away (web/lod_select.js wholeBand) is listed whole: its impostors are
// copied in runs from the rows kept for each place, never tree by tree.
// Renderer (web/render_gl.js) takes these methods as its own.
import { CellGrid } from './cull_grid.js';
import { LodSelect, meshLod } from './lod_select.js';
import { LOD, LOD_LEAF_SHARE, LOD_LEAF_GROW, LOD_BARK, LOD_MODES_MAX, LOD_BUDGET_TRIANGLES, leavesAt } from './lod_policy.js';
import { DAMAGE } from './damage.js';

// Triangles of one impostor: its quad.
export const IMP_TRIANGLES = 2;

// A tree's fall as its impostor row's third component holds it (client/render/
// render_internal.h render_bill_fall; web/imp_shader.js lays the quad along it), from its
// damage code z (render_tree_code: fall angle + 4 x leaf levels lost + 256 when snapped)
// and fall azimuth az [rad]: 0 standing; 1 + the azimuth in 1/256 turns (0..255) + the
// fall angle (at most π/2) / π for a tipped one.
export function impFall(z, az) {
    const y = z >= 256 ? z - 256 : z, fall = Math.fround(y - 4 * Math.floor(y * 0.25));
    if (!(fall > 0)) return 0;
    const k = ((Math.floor(Math.fround(az) * (256 / (2 * Math.PI)) + 0.5) % 256) + 256) % 256;
    return 1 + k + Math.min(fall, Math.fround(Math.PI / 2)) / Math.PI;
}

// The impostor rows of species s's places runA[s]..runE[s] (buf[0..imp0): each place's)
// onto the end of its impostors in the frame's list (buf from imp0), the run then empty.
function copyRun(buf, imp0, impStart, runA, runE, s) {
    buf.copyWithin(imp0 + 4 * impStart[s], 4 * runA[s], 4 * runE[s]);
    impStart[s] += runE[s] - runA[s];
    runA[s] = runE[s] = 0;
}

export class RendererList {
    // The welcome's trees into the grid (their heights from the species drawn, 0 for one
    // not loaded); a new selection, none drawn yet; no tree lying, every leaf on.
    setupCulling(rows) {
        const n = rows.length, h = new Float32Array(n);
        for (let t = 0; t < n; t++) {
            const r = rows[t], sp = this.species[r[0]];
            h[t] = sp ? sp.height * (r[5] > 0 ? r[5] : 1) : 0;
        }
        this.grid = new CellGrid(rows, h);
        this.lod = new LodSelect(n);
        this.lodLevel = new Uint8Array(n);
        this.lodShare = new Float32Array(n);
        this.leafAttached = new Float32Array(n).fill(1);
        // each place's impostor row (tree, its share of leaves left, its fall, 1: drawList's) and
        // after them the frame's impostors, so that a run of them is copied within one array
        this.impBuf = new Float32Array(8 * n);
        this.placeImp = this.impBuf.subarray(0, 4 * n);
        this.impData = this.impBuf.subarray(4 * n);
        this.lodCache = null;
        this.placeDamage();
    }

    // The cells' copies, by place (web/cull_grid.js), of each tree's damage that the draw
    // list reads: its impostor's row with its share of leaves (leafLeft) and its fall
    // (impFall). setDamage and setCuts (web/render_damage.js) call it after they change
    // treeData or leafAttached.
    placeDamage() {
        const g = this.grid, td = this.treeData, attached = this.leafAttached, row = this.placeImp;
        for (let at = 0; at < g.n; at++) {
            const t = g.trees[at];
            row[4 * at] = t;
            row[4 * at + 1] = !td || td[8 * t + 6] === 0 ? attached[t] : this.leafLeft(t);
            row[4 * at + 2] = td ? impFall(td[8 * t + 6], td[8 * t + 7]) : 0;
            row[4 * at + 3] = 1;
        }
    }

    // Per species the triangles of one tree at each level and mesh LOD (leafLevels; null
    // for a species not drawn) and its nodes posed, for the selection; built again when a
    // species arrives. Reused each frame.
    lodCosts() {
        const c = this.lodCache, sp = this.species;
        let same = !!c && c.of.length === sp.length;
        for (let s = 0; same && s < sp.length; s++) same = c.of[s] === sp[s];
        if (same) return c;
        this.lodCache = {
            of: sp.slice(),
            cost: sp.map((x) => (x ? (this.leafLevels(x), x.lodCost) : null)),
            nodes: sp.map((x) => (x ? x.n_nodes : 0)),
            n_lods: Math.max(1, ...sp.map((x) => (x ? x.n_lods : 1))),
        };
        return this.lodCache;
    }

    // A species' leaves at FULL and THIN: the data texture of a deterministic share of them
    // (every k-th, spread over the slots) with each leaf's size scaled by √k, and their
    // count; level 0 is the asset's own. Triangles of one tree at each level and mesh LOD
    // (at IMPOSTOR its quad's).
    leafLevels(sp) {
        if (sp.leafLevels) return sp.leafLevels;
        const a = sp.a, n = a.n_leaves;
        sp.leafLevels = LOD_LEAF_SHARE.slice(0, LOD.IMPOSTOR).map((share, l) => {
            if (l === 0 || !n) return { tex: sp.leaf, n };
            const k = leavesAt(n, share), grow = LOD_LEAF_GROW[l], d = new Float32Array(k * 8);
            for (let i = 0; i < k; i++) {
                const j = Math.min(n - 1, Math.floor((i + 0.5) * n / k));
                d.set(a.leaf_offset.subarray(3 * j, 3 * j + 3), 8 * i);
                d[8 * i + 3] = a.leaf_node[j];
                d.set(a.leaf_normal.subarray(3 * j, 3 * j + 3), 8 * i + 4);
                d[8 * i + 7] = a.leaf_size[j] * grow;
            }
            return { tex: this.dataTex(4, k * 2, d), n: k };
        });
        sp.lodCost = sp.leafLevels.map((lv, l) => Array.from({ length: sp.n_lods }, (_, m) =>
            2 * lv.n + (LOD_BARK[l] ? sp.lod_count[l === LOD.FULL ? m : sp.n_lods - 1] / 3 : 0)));
        sp.lodCost.push(new Array(sp.n_lods).fill(IMP_TRIANGLES));
        return sp.leafLevels;
    }

    // The share of tree t's leaves left on its crown (client/render/render.c build_lists):
    // the stripped levels' and the broken branches' (leafAttached, web/render_damage.js).
    leafLeft(t) {
        const z = this.treeData[8 * t + 6], lost = Math.floor((z - 256 * (z >= 256)) * 0.25);
        return (1 - lost / DAMAGE.LEVELS) * this.leafAttached[t];
    }

    // The trees of view cam (eye; viewproj) at their levels into this.list (skeleton rows)
    // and this.impList (impostors); returns the groups the passes draw, each { s, base, n,
    // bark: [[base, n, mesh lod]], leaves: [[base, n, level]] }, the impostors per species
    // { s, base, n }, and the trees posed (for the stumps and plates).
    // modes: per tree mode count (0: not sent: drawn at rest with none).
    // The cells far enough away are listed whole as impostors (web/lod_select.js
    // wholeBand), unless this.listWhole is false: every tree one by one, the same lists.
    drawList(cam, modes) {
        const t0 = performance.now();
        const ns = this.species.length, lc = this.lodCosts(), cost = lc.cost, nl = lc.n_lods;
        const g = this.grid, lod = this.lod, reach = lod.reach_m();
        const budget = this.lodBudget || (this.lodBudget = { trees: 0, triangles: 0, felled: null });
        budget.trees = Math.min(this.max_rows, this.maxSkelRows());
        // the budget (frameTriangles: the whole frame's, LOD_BUDGET_TRIANGLES unless a test
        // sets another) less what the houses and the falling leaves take
        const other = (this.hideHouses ? 0 : (this.houseVerts || 0) / 3) + 2 * (this.ringCount || 0);
        budget.triangles = Math.max(0, (this.frameTriangles ?? LOD_BUDGET_TRIANGLES) - other);
        budget.felled = this.placeImp;
        let o = g.gather(this.viewproj, cam.eye, reach, this.listWhole === false ? null : lod.wholeBand(cost));
        let sel = lod.select(o.at, o.dist, o.n, g.species, cost, this.lodLevel, budget, lc.nodes, this.lodShare, o.whole);
        if (!sel) {
            // the impostors' reach pulled in this frame: the far cells tree by tree
            o = g.gather(this.viewproj, cam.eye, reach, null);
            sel = lod.select(o.at, o.dist, o.n, g.species, cost, this.lodLevel, budget, lc.nodes, this.lodShare, o.whole);
        }
        // keys: per species its FULL rows by mesh LOD, then THIN; impostors apart, per species
        const K = nl + 1, nd = this.debris.length;
        if (!this.listCount || this.listCount.length !== ns * K + 1) {
            this.listCount = new Int32Array(ns * K + 1);
            this.listStart = new Int32Array(ns * K);
            this.impCount = new Int32Array(ns + 1);
            this.impStart = new Int32Array(ns);
            this.runA = new Int32Array(ns);
            this.runE = new Int32Array(ns);
        }
        if (!this.listKeys || this.listKeys.length < o.n + nd) this.listKeys = new Int32Array(o.n + nd + 64);
        const count = this.listCount, impCount = this.impCount;
        this.listCountsRest(o, cam.eye, K);
        const nt = this.listCounts(o, cam.eye, K, nl) + o.whole.trees;
        for (let k = 0; k < ns * K; k++) count[k + 1] += count[k];
        for (let s = 0; s < ns; s++) impCount[s + 1] += impCount[s];
        const n = count[ns * K], ni = impCount[ns];
        this.listStart.set(count.subarray(0, ns * K));
        this.impStart.set(impCount.subarray(0, ns));
        if (!this.listData || this.listData.length < 4 * n) this.listData = new Float32Array(4 * Math.max(16, 2 * n));
        if (!this.drawnTrees || this.drawnTrees.length < n) this.drawnTrees = new Int32Array(Math.max(16, 2 * n));
        const perLevel = [0, 0, 0]; // skeleton rows at FULL and THIN, impostors (a fading tree in both)
        this.listFill(o, modes, perLevel);
        this.listFillEnd(o);
        const groups = [], imps = [];
        for (let s = 0; s < ns; s++) {
            const sp = this.species[s], a = count[s * K], e = count[(s + 1) * K];
            if (sp && impCount[s + 1] > impCount[s]) imps.push({ s, base: impCount[s], n: impCount[s + 1] - impCount[s] });
            if (!sp || a === e) continue;
            const gr = { s, base: a, n: e - a, bark: [], leaves: [] };
            const at = (k) => count[s * K + k];
            // the bark: the FULL rows by mesh; the coarsest mesh's run goes on through the
            // (empty) keys of meshes this species lacks and THIN's rows
            for (let m = 0; m < sp.n_lods; m++) {
                const b = at(m), c = (m === sp.n_lods - 1 ? at(nl + 1) : at(m + 1)) - b;
                if (c) gr.bark.push([b, c, m]);
            }
            for (let l = 0; l < LOD.IMPOSTOR; l++) {
                const b = l === LOD.FULL ? at(0) : at(nl), c = at(l === LOD.FULL ? nl : nl + 1) - b;
                if (c) gr.leaves.push([b, c, l]);
            }
            groups.push(gr);
        }
        this.stats.trees_drawn = nt;
        this.stats.levels = perLevel;
        this.stats.impostors = ni;
        this.stats.lod_scale = sel.scale;
        this.stats.lod_scale_far = sel.scale_far;
        this.stats.lod_worst = sel;
        this.stats.cells_in_view = o.cells_in_view;
        this.stats.cull_ms = performance.now() - t0;
        this.list = this.dataTex(4, Math.max(1, n), this.listData.subarray(0, Math.max(1, n) * 4), this.list);
        if (ni) this.impList = this.dataTex(4, ni, this.impData.subarray(0, ni * 4), this.impList);
        return { groups, imps, drawn: this.drawnTrees.subarray(0, n), rows: n };
    }

    // drawList's first pass over the debris pieces and the cells listed whole (o.whole:
    // web/cull_grid.js gather's): each piece's key (K keys a species: its FULL rows by mesh
    // LOD, then THIN; -1: no skeleton row) into listKeys after the trees', the rows of each
    // key into listCount and the impostors of each species into impCount (both counted
    // from index 1; listCount and impCount zeroed first).
    listCountsRest(o, eye, K) {
        const count = this.listCount.fill(0), impCount = this.impCount.fill(0), keys = this.listKeys, species = this.species;
        // the debris pieces, in the slots after the trees: every leaf, mesh by distance
        for (let k = 0; k < this.debris.length; k++) {
            const d = this.debris[k], sp = species[d.species];
            keys[o.n + k] = sp ? d.species * K + meshLod(Math.hypot(d.pos[0] - eye[0], d.pos[1] - eye[1], d.pos[2] - eye[2]), LOD.FULL, sp.n_lods) : -1;
            if (sp) count[keys[o.n + k] + 1]++;
        }
        // the whole cells' trees: impostors alone
        const W = o.whole, run = W.run, nc = W.nc, wns = Math.min(W.ns, species.length); // (a whole cell holds drawn species alone)
        for (let k = 0; k < W.n; k++) {
            for (let s = 0, r = W.cell[k]; s < wns; s++, r += nc) impCount[s + 1] += run[r + 1] - run[r];
        }
    }

    // And over the trees gathered one by one (o): their keys (nl: THIN's within a
    // species), rows and impostors. Returns the trees drawn among them. (Each of these
    // passes runs its one loop last: the JIT's code for a loop entered mid-call then holds
    // no later step it has not yet seen run.)
    listCounts(o, eye, K, nl) {
        const count = this.listCount, impCount = this.impCount, keys = this.listKeys, g = this.grid, species = this.species;
        const ex = eye[0], ey = eye[1], ez = eye[2];
        // the arrays read per tree held here: the loop runs over every tree in view
        const lodLevel = this.lodLevel, lodShare = this.lodShare, gs = g.species, px = g.px, py = g.py, pz = g.pz, inAt = o.at;
        let nt = 0;
        for (let i = 0; i < o.n; i++) {
            const l = lodLevel[i], at = inAt[i], s = gs[at], sh = lodShare[i];
            keys[i] = -1;
            if (l === LOD.NONE) continue;
            nt++;
            if (sh > 0) impCount[s + 1]++;
            if (sh >= 1) continue; // wholly its impostor
            let key = s * K + nl;
            if (l === LOD.FULL) {
                // the bark mesh by the distance of the tree's base
                const dx = px[at] - ex, dy = py[at] - ey, dz = pz[at] - ez;
                key = s * K + meshLod(Math.sqrt(dx * dx + dy * dy + dz * dz), l, species[s].n_lods);
            }
            keys[i] = key;
            count[key + 1]++;
        }
        return nt;
    }

    // drawList's second pass: the skeleton rows (listData, drawnTrees) and the impostors
    // (impData) of the trees gathered (o) at the places listStart and impStart give
    // (listCounts' counts summed), and the rows at each level and the impostors into
    // perLevel; listFillEnd ends it.
    listFill(o, modes, perLevel) {
        const g = this.grid, keys = this.listKeys, start = this.listStart, impStart = this.impStart;
        const list = this.listData, drawn = this.drawnTrees, imp = this.impData, buf = this.impBuf, imp0 = 4 * g.n, q = this.q_trees;
        const lodLevel = this.lodLevel, lodShare = this.lodShare, gs = g.species, inAt = o.at, inView = o.trees;
        const species = this.species, W = o.whole, run = W.run, nc = W.nc, wns = Math.min(W.ns, species.length);
        // the whole cells' impostors of each species waiting, places runA[s]..runE[s]
        const runA = this.runA.fill(0), runE = this.runE.fill(0);
        perLevel[LOD.IMPOSTOR] += W.trees;
        // the trees in view in the cells' order, each whole cell where it falls among them:
        // a species' impostors in the order of its places, as tree by tree would list them
        for (let k = 0, i = 0; k <= W.n; k++) {
            for (const end = k < W.n ? W.before[k] : o.n; i < end; i++) {
                const t = inView[i], sh = lodShare[i], at = inAt[i], s = gs[at];
                if (sh > 0) {
                    // the impostor: tree, its share of leaves left (leafLeft), its fall
                    // (impFall), its fade in (dither_keep: −sh keeps the pixels that THIN's
                    // 1 − sh leaves)
                    if (runE[s] > runA[s]) copyRun(buf, imp0, impStart, runA, runE, s);
                    const e = 4 * impStart[s]++;
                    imp[e] = t;
                    imp[e + 1] = buf[4 * at + 1];
                    imp[e + 2] = buf[4 * at + 2];
                    imp[e + 3] = sh < 1 ? -sh : 1;
                    perLevel[LOD.IMPOSTOR]++;
                }
                if (keys[i] < 0) continue;
                const row = start[keys[i]]++, sp = species[s];
                // a tree past those whose motion the page holds (App: q_trees) is drawn at
                // rest; the trees past FULL with the few modes the server sends past lod_m
                const nm = t >= q ? 0 : Math.min(modes ? modes[t] : sp.n_modes, sp.n_modes, LOD_MODES_MAX[lodLevel[i]]);
                list[4 * row] = t;
                list[4 * row + 1] = row;
                list[4 * row + 2] = nm;
                list[4 * row + 3] = 1 - sh; // fading out into its impostor
                drawn[row] = t;
                perLevel[lodLevel[i]]++;
            }
            if (k === W.n) break;
            for (let s = 0, r = W.cell[k]; s < wns; s++, r += nc) {
                const a = run[r], e = run[r + 1];
                if (a === e) continue;
                if (runE[s] === a && a > runA[s]) {
                    runE[s] = e;
                    continue;
                }
                if (runE[s] > runA[s]) copyRun(buf, imp0, impStart, runA, runE, s);
                runA[s] = a;
                runE[s] = e;
            }
        }
    }

    // The end of listFill (a pass of its own, so that the JIT's code for listFill's loop
    // holds no call it has not yet seen made): the whole cells' impostors still waiting,
    // and the debris pieces' rows (their rest pose needs no modes).
    listFillEnd(o) {
        const runA = this.runA, runE = this.runE, buf = this.impBuf, imp0 = 4 * this.grid.n, impStart = this.impStart;
        for (let s = 0; s < runA.length; s++) if (runE[s] > runA[s]) copyRun(buf, imp0, impStart, runA, runE, s);
        const keys = this.listKeys, start = this.listStart, list = this.listData, drawn = this.drawnTrees;
        for (let k = 0; k < this.debris.length; k++) {
            if (keys[o.n + k] < 0) continue;
            const row = start[keys[o.n + k]]++;
            list[4 * row] = this.n_trees + k;
            list[4 * row + 1] = row;
            list[4 * row + 2] = 0;
            list[4 * row + 3] = 1;
            drawn[row] = this.n_trees + k;
        }
    }

    // The most rows the skeleton textures may have: the GPU's largest texture.
    maxSkelRows() {
        if (!this.maxTex) this.maxTex = this.gl.getParameter(this.gl.MAX_TEXTURE_SIZE);
        return this.maxTex;
    }
}
