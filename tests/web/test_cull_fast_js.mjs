// The far cells listed whole (web/cull_grid.js gather's whole, web/lod_select.js
// wholeBand, web/render_list.js drawList) against the reference walk of every tree in view
// one by one (RendererList.listWhole false), under Node on the 2 km landscape of 100,000
// trees (tests/web/landscape_scene.mjs): frame after frame, from the air down to low over
// the middle and back, from afar with trees past the impostors' reach and from overhead, the two give the same skeleton rows, impostor list (in order),
// groups, stats and budget, and keep the same level for every tree (the hysteresis' memory);
// also with trees lying (impostors laid along their fall, in cells listed whole too) and
// leaves lost in a storm, with the governor's cap on the scale
// moving, and with a triangle budget that the impostors alone exceed (the impostors'
// reach pulled in: no cell is then listed whole).
import assert from 'node:assert/strict';
import { landscape, CAMERAS, viewProj } from './landscape_scene.mjs';

const fast = landscape().r, ref = landscape().r;
ref.listWhole = false;
const N = fast.n_trees;

// one frame on both from eye toward target: the lists compared; the trees listed whole
function frame(eye, target, what, fovy_deg = 50, far_m = 3000) {
    const vp = viewProj(eye, target, fovy_deg, far_m);
    fast.viewproj = ref.viewproj = vp;
    const a = fast.drawList({ eye }, null), b = ref.drawList({ eye }, null);
    assert.equal(ref.grid.out.whole.n, 0, `${what}: the reference listed a cell whole`);
    assert.equal(a.rows, b.rows, `${what}: skeleton rows`);
    assert.deepEqual(a.groups, b.groups, `${what}: groups`);
    assert.deepEqual(a.imps, b.imps, `${what}: impostors per species`);
    assert.deepEqual(a.drawn, b.drawn, `${what}: trees posed`);
    assert.deepEqual(fast.listData.subarray(0, 4 * a.rows), ref.listData.subarray(0, 4 * b.rows), `${what}: skeleton list`);
    const ni = fast.stats.impostors;
    assert.equal(ni, ref.stats.impostors, `${what}: impostors`);
    const ia = fast.impData.subarray(0, 4 * ni), ib = ref.impData.subarray(0, 4 * ni);
    for (let e = 0; e < 4 * ni; e++) if (ia[e] !== ib[e]) assert.fail(`${what}: impostor ${e >> 2} field ${e & 3}: ${ia[e]}, tree by tree ${ib[e]}`);
    for (const k of ['trees_drawn', 'levels', 'lod_scale', 'lod_scale_far', 'lod_worst']) assert.deepEqual(fast.stats[k], ref.stats[k], `${what}: stats.${k}`);
    // every tree's level as the next frame's hysteresis reads it (the two grids' places are alike)
    for (let at = 0; at < N; at++) {
        const la = fast.lod.lastLevel(at), lb = ref.lod.lastLevel(at);
        if (la !== lb) assert.fail(`${what}: tree ${fast.grid.trees[at]}: level ${la}, tree by tree ${lb}`);
    }
    frames++;
    return fast.grid.out.whole.trees;
}

const lerp = (p, q, u) => p.map((v, k) => v + u * (q[k] - v));
const [, airEye, airTarget] = CAMERAS[0], [, lowEye, lowTarget] = CAMERAS[1];
let whole = 0, frames = 0;
// from the air down to low over the middle and back, in steps large enough to move the
// budget's scale, then a camera rocking across the levels' edges
const path = [];
for (let k = 0; k <= 12; k++) path.push([lerp(airEye, lowEye, k / 12), lerp(airTarget, lowTarget, k / 12)]);
for (let k = 11; k >= 6; k--) path.push([lerp(airEye, lowEye, k / 12), lerp(airTarget, lowTarget, k / 12)]);
for (let k = 0; k < 6; k++) path.push([lowEye.map((v, j) => v + (k % 2 ? 6 : -6) * (j < 2)), lowTarget]);
// from afar, the square's far half past the impostors' reach (the far plane 6 km off):
// out and back across it
for (const off of [0, 150, 300, 150, 0, 300]) path.push([[-3000 - off, -3000 - off, 300], [0, 0, 0], 50, 6000]);
// from overhead, 150 m above the middle, 100°: cells wholly in view that are near
for (const off of [0, 20, 40, 20, 0]) path.push([[off, 0, 150], [off + 1, 0, 0], 100]);
// rising from there: trees THIN a frame ago pass THIN's outer distance into its hysteresis
for (let z = 160; z <= 320; z += 8) path.push([[0, 0, z], [1, 0, 0], 100]);
for (const [eye, target, fovy, far] of path) {
    whole += frame(eye, target, `frame ${frames} at ${eye.map((v) => v.toFixed(0))}`, fovy, far);
}
const first = frame(airEye, airTarget, 'aerial');
assert.ok(first > 0.8 * fast.stats.trees_drawn, `from the air ${first} of ${fast.stats.trees_drawn} trees listed whole: expected most`);

// a storm: trees lying here and there (impostors with their fall), leaves lost (the
// impostors' share)
for (const r of [fast, ref]) {
    for (let t = 5; t < N; t += 11) r.treeData[8 * t + 6] = 4 * (1 + (t % 3)) + (t % 2 ? 256 : 0);
    for (let t = 0; t < N; t += 401) {
        r.treeData[8 * t + 6] += 0.2 + 1.3 * ((t % 5) / 4);
        r.treeData[8 * t + 7] = -3 + 0.01 * (t % 600);
    }
    for (let t = 3; t < N; t += 13) r.leafAttached[t] = 0.25 + 0.5 * ((t % 7) / 7);
    r.placeDamage();
}
for (const [name, eye, target] of CAMERAS) {
    for (let k = 0; k < 3; k++) whole += frame(eye.map((v) => v + 2 * k), target, `${name} in the storm, frame ${k}`);
    let lyingImp = 0;
    for (let e = 0; e < fast.stats.impostors; e++) lyingImp += fast.impData[4 * e + 2] >= 1;
    assert.ok(fast.grid.out.whole.n > 0 && lyingImp > 0, `${name} in the storm: cells listed whole, ${lyingImp} lying impostors`);
}
// the governor caps the scale, then lets it go
for (const cap of [0.5, 0.2, 1]) {
    fast.lod.cap = ref.lod.cap = cap;
    for (const [name, eye, target] of CAMERAS) whole += frame(eye, target, `${name} at cap ${cap}`);
}
// a budget the impostors alone exceed: the impostors' reach comes in, tree by tree
for (const r of [fast, ref]) r.frameTriangles = 1e5;
for (let k = 0; k < 3; k++) {
    frame(airEye.map((v) => v - 3 * k), airTarget, `aerial over budget, frame ${k}`);
    assert.ok(fast.stats.lod_scale_far < 1 && fast.grid.out.whole.n === 0, `over budget: the impostors' reach ${fast.stats.lod_scale_far}, ${fast.grid.out.whole.n} cells whole`);
}
console.log(JSON.stringify({ trees: N, frames, trees_listed_whole: whole, ok: true }));
