// web/cull_grid.js, web/lod_select.js and web/view_stream.js under Node, no browser:
// - the cell grid's trees in view are exactly those of a brute-force test of every tree
//   (each tree's box, the cube of half-side its height about its base, against the
//   frustum's planes by its eight corners, and its middle within far_m), for orbit
//   cameras over a 20,000-tree scene and an off-axis wall tile's view, with their distances;
// - the levels chosen never cost more than the budget (triangles, trees posed, nodes), and a camera
//   rocking across a level's edge by less than the hysteresis flips no tree;
// - the view cone holds the frustum: its half angle is atan √(tan²(hfov/2) + tan²(vfov/2))
//   for a symmetric frustum, and every far corner of an off-axis one is inside it;
// - the view sender sends at most 4 views a second while the camera moves, none while it
//   is still, and one when it stops.
import assert from 'node:assert/strict';
import { CellGrid } from '../../web/cull_grid.js';
import { LodSelect } from '../../web/lod_select.js';
import { LOD, LOD_OUTER_M, LOD_HYSTERESIS, LOD_FELLED_TRIANGLES } from '../../web/lod_policy.js';
import { perspective, lookAt, mul, invert } from '../../web/view_math.js';
import { offaxis } from '../../web/wall_view.js';
import { frustumCone, frustumView, ViewSender } from '../../web/view_stream.js';

let seed = 12345;
const rnd = () => ((seed = (seed * 1103515245 + 12345) >>> 0) / 4294967296);

// 20,000 trees on 1.2 km × 0.8 km, ground heights ±15 m, heights 6-30 m, three species
const N = 20000, rows = [], height = new Float32Array(N);
for (let t = 0; t < N; t++) {
    const x = -600 + 1200 * rnd(), y = -400 + 800 * rnd();
    rows.push([t % 3, x, y, 15 * Math.sin(x / 90) * Math.cos(y / 70), 0, 1]);
    height[t] = 6 + 24 * rnd();
}
const grid = new CellGrid(rows, height), speciesOf = Uint8Array.from(rows, (r) => r[0]);

// the brute force: the six planes from the matrix's rows, a box out when its eight corners
// are all behind one plane
function bruteForce(m, eye, far_m) {
    const row = (i) => [m[i], m[4 + i], m[8 + i], m[12 + i]];
    const r = [0, 1, 2, 3].map(row), planes = [];
    for (const [k, s] of [[0, 1], [0, -1], [1, 1], [1, -1], [2, 1], [2, -1]]) planes.push(r[3].map((v, j) => v + s * r[k][j]));
    const out = new Map();
    for (let t = 0; t < N; t++) {
        const [, x, y, z] = rows[t], h = height[t];
        const d = Math.hypot(x - eye[0], y - eye[1], z + h / 2 - eye[2]);
        if (d > far_m) continue;
        let outside = false;
        for (const p of planes) {
            let behind = 0;
            for (const cx of [x - h, x + h]) for (const cy of [y - h, y + h]) for (const cz of [z - h, z + h]) {
                behind += p[0] * cx + p[1] * cy + p[2] * cz + p[3] < 0;
            }
            if (behind === 8) { outside = true; break; }
        }
        if (!outside) out.set(t, d);
    }
    return out;
}

function orbit(target, dist, yaw, pitch, fovy, aspect, far = 3000) {
    const f = [Math.cos(pitch) * Math.cos(yaw), Math.cos(pitch) * Math.sin(yaw), Math.sin(pitch)];
    const eye = target.map((v, k) => v - f[k] * dist);
    const view = lookAt(eye, target, [0, 0, 1]);
    return { eye, view, viewproj: mul(perspective(fovy, aspect, 0.3, far), view), fovy, aspect };
}

const cams = [];
for (let k = 0; k < 12; k++) {
    cams.push({ ...orbit([-500 + 1000 * rnd(), -300 + 600 * rnd(), 4], 10 + 400 * rnd(), 6.283 * rnd(), -0.05 - 1.2 * rnd(), 0.5 + 0.6 * rnd(), 0.8 + rnd()), far: 100 + 1200 * rnd() });
}
// a wall tile's off-axis frustum (the wall's eye 2 m before glass 3 m × 2 m, off to one side)
{
    const { rot, proj } = offaxis([1, -1, 0], [4, -1, 0], [1, 1, 0], [0, 0, 2], 0.3, 3000);
    const camView = lookAt([0, -300, 40], [0, 0, 0], [0, 0, 1]);
    const toWall = new Float32Array([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 2, 1]);
    const view = mul(rot, mul(toWall, camView));
    const vp = mul(proj, view);
    const eye = frustumCone(view, vp).eye;
    cams.push({ eye, view, viewproj: vp, far: 900, wall: true });
}
let total = 0, t_ms = 0;
for (const c of cams) {
    const want = bruteForce(c.viewproj, c.eye, c.far);
    const t0 = performance.now();
    const o = grid.gather(c.viewproj, c.eye, c.far);
    t_ms += performance.now() - t0;
    const got = new Map();
    for (let i = 0; i < o.n; i++) got.set(o.trees[i], o.dist[i]);
    assert.equal(got.size, o.n, 'a tree gathered twice');
    for (const t of want.keys()) assert.ok(got.has(t), `tree ${t} in view by brute force, not gathered (camera ${JSON.stringify(c.eye)})`);
    for (const [t, d] of got) {
        assert.ok(want.has(t), `tree ${t} gathered, out of view by brute force`);
        assert.ok(Math.abs(d - want.get(t)) < 1e-3 * Math.max(1, d), `tree ${t}: distance ${d}, brute force ${want.get(t)}`);
    }
    total += want.size;
}
assert.ok(total > 1000, `the cameras see ${total} trees in all: expected many`);

// levels under the budget: costs per species, level and mesh LOD (finer costs more; an
// impostor its quad's 2 triangles, no skeleton row: a tree fading into it costs both)
const cost = [[[60000, 30000, 15000], [7000, 7000, 7000], [2, 2, 2]], [[12000, 3000, 3000], [1200, 1200, 1200], [2, 2, 2]],
    [[20000, 6000, 4000], [1600, 1600, 1600], [2, 2, 2]]];
const meshOf = (d, l) => (l === LOD.FULL ? Math.min(2, Math.floor(d / 30)) : 2);
const nodes = [3180, 633, 1135];
for (const budget of [{ triangles: 1e6, trees: 2048, nodes: 2e6 }, { triangles: 2e5, trees: 300, nodes: 1e9 }, { triangles: 5e6, trees: 50, nodes: 1e9 },
    { triangles: 1e9, trees: 1e6, nodes: 3e5 }]) {
    const sel = new LodSelect(N), lv = new Uint8Array(N), share = new Float32Array(N);
    for (const c of cams) {
        for (let rep = 0; rep < 3; rep++) {
            const o = grid.gather(c.viewproj, c.eye, sel.reach_m());
            const r = sel.select(o.trees, o.dist, o.n, speciesOf, cost, lv, budget, nodes, share);
            let tris = 0, trees = 0, posed = 0;
            for (let i = 0; i < o.n; i++) {
                if (lv[i] === LOD.NONE) continue;
                const cs = cost[rows[o.trees[i]][0]];
                if (share[i] > 0) tris += cs[LOD.IMPOSTOR][2];
                if (share[i] >= 1) continue; // wholly its impostor, no skeleton row
                tris += cs[lv[i]][meshOf(o.dist[i], lv[i])];
                trees++;
                posed += nodes[rows[o.trees[i]][0]];
            }
            assert.ok(tris <= budget.triangles && trees <= budget.trees && posed <= budget.nodes,
                `${tris} triangles, ${trees} trees, ${posed} nodes over ${JSON.stringify(budget)} (scale ${r.scale})`);
            assert.ok(tris <= r.triangles && trees <= r.trees && posed <= r.nodes, 'the frame costs more than its worst case');
        }
    }
}
// felled trees: every other one lies, and each posed draws its root plate or stump besides
// its own few triangles (cheap trees, so the plates are most of the cost); still within
{
    const cheap = [[[300, 200, 150], [60, 60, 60], [2, 2, 2]], [[200, 150, 100], [40, 40, 40], [2, 2, 2]],
        [[250, 180, 120], [50, 50, 50], [2, 2, 2]]];
    const felled = new Float32Array(4 * N);
    for (let t = 0; t < N; t += 2) felled[4 * t + 2] = 1.5;
    const budget = { triangles: 4e4, trees: 1e6, nodes: 1e12, felled };
    const sel = new LodSelect(N), lv = new Uint8Array(N), share = new Float32Array(N);
    let worst = 0;
    for (const c of cams) {
        for (let rep = 0; rep < 3; rep++) {
            const o = grid.gather(c.viewproj, c.eye, sel.reach_m());
            const r = sel.select(o.trees, o.dist, o.n, speciesOf, cheap, lv, budget, nodes, share);
            let tris = 0;
            for (let i = 0; i < o.n; i++) {
                if (lv[i] === LOD.NONE) continue;
                const cs = cheap[rows[o.trees[i]][0]];
                if (share[i] > 0) tris += cs[LOD.IMPOSTOR][2];
                if (share[i] >= 1) continue;
                tris += cs[lv[i]][meshOf(o.dist[i], lv[i])] + (felled[4 * o.trees[i] + 2] ? LOD_FELLED_TRIANGLES : 0);
            }
            worst = Math.max(worst, tris);
            assert.ok(tris <= budget.triangles && tris <= r.triangles, `${tris} triangles with the felled trees' plates over ${budget.triangles} (scale ${r.scale}, worst case ${r.triangles})`);
        }
    }
    assert.ok(worst > 0.3 * budget.triangles, `the felled trees' frames use ${worst} triangles of ${budget.triangles}: the budget binds`);
}
// hysteresis: a camera rocking by 3 % of a distance back and forth, no tree flips
{
    const sel = new LodSelect(N), lv = new Uint8Array(N), big = { triangles: 1e12, trees: 1e9 };
    const c = orbit([0, 0, 4], 200, 0.3, -0.4, 0.9, 1.5), far = LOD_OUTER_M[2];
    const levels = [];
    for (let k = 0; k < 8; k++) {
        const eye = c.eye.map((v, j) => v + (k % 2 ? 1 : -1) * 0.015 * LOD_OUTER_M[0] * (j === 0 ? 1 : 0));
        const o = grid.gather(c.viewproj, eye, far);
        sel.select(o.trees, o.dist, o.n, speciesOf, cost, lv, big);
        const m = new Map();
        for (let i = 0; i < o.n; i++) m.set(o.trees[i], lv[i]);
        levels.push(m);
    }
    let flips = 0, edge = 0;
    for (const [t, l] of levels[2]) {
        if (levels[3].get(t) !== undefined && levels[3].get(t) !== l && levels[4].get(t) === l) flips++;
    }
    for (const [t] of levels[2]) {
        const d = Math.hypot(rows[t][1] - c.eye[0], rows[t][2] - c.eye[1]);
        if (LOD_OUTER_M.some((b) => Math.abs(d - b) < 0.03 * b)) edge++;
    }
    assert.ok(LOD_HYSTERESIS > 0.03, 'the test rocks the camera within the hysteresis');
    assert.ok(edge > 10, `only ${edge} trees near a level's edge`);
    assert.equal(flips, 0, `${flips} trees flipped level with the camera rocking`);
}

// the cone of a symmetric frustum: atan √(tan²(hfov/2) + tan²(vfov/2))
for (const [fovy, aspect] of [[0.8726646, 16 / 9], [0.5, 1], [1.2, 0.5]]) {
    const c = orbit([10, 20, 4], 60, 1.1, -0.5, fovy, aspect);
    const cone = frustumCone(c.view, c.viewproj);
    const tv = Math.tan(fovy / 2), th = tv * aspect, want = 2 * Math.atan(Math.hypot(tv, th)) * 180 / Math.PI;
    assert.ok(Math.abs(cone.fov_deg - want) < 1e-3, `cone ${cone.fov_deg}° for fovy ${fovy}, aspect ${aspect}: expected ${want}°`);
    assert.ok(Math.hypot(...cone.eye.map((v, k) => v - c.eye[k])) < 1e-3, 'the cone\'s apex is the eye');
    const f = [10 - c.eye[0], 20 - c.eye[1], 4 - c.eye[2]], l = Math.hypot(...f);
    assert.ok(cone.dir.every((v, k) => Math.abs(v - f[k] / l) < 1e-5), 'the cone\'s axis is the view\'s');
    const v = frustumView(cone, 500, 90);
    assert.ok(v.kind === 'frustum' && v.fov_deg >= want && v.fov_deg <= 179 && v.far_m === 500 && v.lod_m === 90);
}
{
    const c = cams[cams.length - 1], cone = frustumCone(c.view, c.viewproj), inv = invert(c.viewproj);
    for (const [x, y] of [[-1, -1], [1, -1], [-1, 1], [1, 1]]) {
        const p = [0, 1, 2, 3].map((r) => inv[r] * x + inv[4 + r] * y + inv[8 + r] + inv[12 + r]);
        const v = [0, 1, 2].map((k) => p[k] / p[3] - cone.eye[k]), l = Math.hypot(...v);
        const ang = Math.acos(v.reduce((a, x2, k) => a + x2 * cone.dir[k], 0) / l) * 180 / Math.PI;
        assert.ok(ang <= cone.fov_deg / 2 + 1e-3, `an off-axis far corner ${ang}° off the axis, the cone's half angle ${cone.fov_deg / 2}°`);
    }
}

// the sender: a camera turning 1° every 1/60 s for 2.9 s, then still for 2 s
{
    const sent = [];
    const s = new ViewSender((m) => { sent.push(m); return true; });
    for (let k = 0; k <= 300; k++) {
        const t = k / 60, a = Math.min(t, 2.9) * 60 * Math.PI / 180;
        s.update(frustumView({ eye: [0, 0, 2], dir: [Math.cos(a), Math.sin(a), 0], fov_deg: 60 }, 500, 90), t);
        sent.forEach((m) => { m.t = m.t ?? t; });
    }
    const moving = sent.filter((m) => m.t <= 2.9), after = sent.filter((m) => m.t > 2.9);
    assert.ok(moving.length >= 8 && moving.length <= 12, `${moving.length} views sent in 2.9 s of turning: expected 4 a second`);
    for (let i = 1; i < moving.length; i++) assert.ok(moving[i].t - moving[i - 1].t >= 0.25 - 1e-9, 'two views within 0.25 s');
    assert.equal(after.length, 1, `${after.length} views sent after the camera stopped: expected the one where it stopped`);
    const a = 2.9 * 60 * Math.PI / 180;
    assert.ok(Math.abs(after[0].view.dir[0] - Math.cos(a)) < 1e-5 && Math.abs(after[0].view.dir[1] - Math.sin(a)) < 1e-5 && after[0].t <= 3.5, 'the last view is where the camera stopped');
}
console.log(JSON.stringify({ trees: N, cells: grid.nx * grid.ny, cell_m: grid.cell_m, cameras: cams.length, in_view: total, gather_ms_each: t_ms / cams.length, ok: true }));
