// The far trees' impostors under Node, no browser (web/imp_sway.js, web/lod_select.js,
// web/render_list.js):
// - the crown's sway and the quad's offset against a hand computation on a tiny asset,
//   and the quad's extent against client/render/render_species.c's numbers;
// - a line of trees: FULL, THIN, fading (both), impostors past THIN's outer distance, none
//   past IMPOSTOR's, a fallen tree the same;
// - a fallen tree's impostor row (impFall): 0 standing, 1 + azimuth in 1/256 turns + fall
//   angle / π lying, and on the landscape a far fallen tree listed as an impostor with it,
//   tree by tree and in a cell listed whole;
// - the 2 km landscape's scale: 100,000 trees in a 2 km square seen from the air draw every
//   tree in view (the frustum and the draw distance by brute force), within the frame's
//   budget of triangles and draw calls; the cull and levels' CPU time is printed.
import assert from 'node:assert/strict';
import { impostorQuad, crownSway, swayOffset, IMP_SWAY_MAX } from '../../web/imp_sway.js';
import { LodSelect } from '../../web/lod_select.js';
import { IMP_TRIANGLES, impFall } from '../../web/render_list.js';
import { LOD, LOD_OUTER_M, LOD_FADE_SHARE, LOD_BUDGET_TRIANGLES, LOD_BUDGET_DRAWS, LOD_BUDGET_TREES, LOD_IMPOSTOR_MODES } from '../../web/lod_policy.js';
import { frustumPlanes, boxInFrustum } from '../../web/cull_grid.js';
import { landscape, CAMERAS, viewProj } from './landscape_scene.mjs';

const near = (a, b, tol, what) => assert.ok(Math.abs(a - b) <= tol, `${what}: ${a}, expected ${b} (tolerance ${tol})`);

// --- the sway on a tiny asset: 4 nodes, 3 modes (the third ignored), 4 leaves
{
    const a = { n_nodes: 4, n_modes: 3, n_leaves: 4, rest: new Float32Array([0, 0, 0, 0, 0, 2, 1, 0, 4, -1, 0, 5]),
        leaf_node: new Uint32Array([2, 2, 2, 1]), phi: new Float32Array(3 * 3 * 4) };
    // phi[mode][node][3]
    const set = (m, j, v) => a.phi.set(v, (m * 4 + j) * 3);
    set(0, 1, [0.1, 0.0, 0.0]); set(0, 2, [0.3, 0.1, -0.02]); set(0, 3, [9, 9, 9]);
    set(1, 1, [0.0, 0.2, 0.0]); set(1, 2, [-0.1, 0.4, 0.0]); set(1, 3, [9, 9, 9]);
    set(2, 2, [5, 5, 5]);
    const sw = crownSway(a);
    // by hand: w = [0, 1, 3, 0]; z_c = (1·2 + 3·4) / 4 = 3.5; c_0 = (0.1 + 3·0.3, 3·0.1, 3·−0.02) / 4
    near(sw.z_c_m, 3.5, 1e-6, 'z_c');
    const c0 = [0.25, 0.075, -0.015], c1 = [-0.075, 0.35, 0];
    for (let d = 0; d < 3; d++) {
        near(sw.c[d], c0[d], 1e-6, `c_0[${d}]`);
        near(sw.c[3 + d], c1[d], 1e-6, `c_1[${d}]`);
    }
    assert.equal(sw.c.length, 3 * LOD_IMPOSTOR_MODES);
    const q = [0.5, -2];
    const s = [0, 1, 2].map((d) => q[0] * c0[d] + q[1] * c1[d]); // Σ_k q_k c_k (no saturation)
    // the lean: z / z_c, at most IMP_SWAY_MAX
    for (const [z, f] of [[-1, 0], [0, 0], [1.75, 0.5], [3.5, 1], [7, 2], [20, IMP_SWAY_MAX]]) {
        const o = swayOffset(sw, q, z);
        for (let d = 0; d < 3; d++) near(o[d], f * s[d], 1e-6, `offset at z ${z} [${d}]`);
    }
    // q saturated as the pose's, q̃ = a atan(b q) (Diener 2008 eq. 16): a = 1.2, b = 1 / 1.2
    const sat = crownSway({ ...a, corr_a: new Float32Array([1.2, 1.2, 1.2]), corr_b: new Float32Array([1 / 1.2, 1 / 1.2, 1 / 1.2]) });
    const qt = q.map((v) => Math.fround(1.2) * Math.atan(Math.fround(1 / 1.2) * v));
    const st = [0, 1, 2].map((d) => qt[0] * c0[d] + qt[1] * c1[d]);
    const os = swayOffset(sat, q, 3.5);
    for (let d = 0; d < 3; d++) near(os[d], st[d], 1e-6, `saturated offset [${d}]`);
    assert.ok(Math.abs(st[1]) < Math.abs(s[1]) - 0.05, 'the saturation can tell');
    // no leaves: the highest node alone
    const bare = crownSway({ ...a, n_leaves: 0, leaf_node: new Uint32Array(0) });
    near(bare.z_c_m, 5, 1e-6, 'z_c of a bare tree');
    near(bare.c[0], 9, 1e-6, 'c_0 of a bare tree');
    // a species of one mode: the second is 0
    const one = crownSway({ ...a, n_modes: 1, phi: a.phi.subarray(0, 12) });
    assert.deepEqual(Array.from(one.c.subarray(3)), [0, 0, 0]);
    // the quad (species_impostor): hw = 1.05 r + 0.2, bottom −0.05 h, top 1.06 h + 0.2
    const qd = impostorQuad(20, 6);
    near(qd.hw_m, 6.5, 1e-9, 'half width');
    near(qd.bottom_m, -1, 1e-9, 'bottom');
    near(qd.top_m, 21.4, 1e-9, 'top');
}

// --- a line of trees along x from the eye: their levels and shares (a fallen tree's alike)
{
    const ds = [];
    for (let d = 10; d < 2800; d += 5) ds.push(d);
    const n = ds.length, trees = Int32Array.from(ds, (_, i) => i), dist = Float32Array.from(ds);
    const cost = [[[9000, 9000, 9000], [900, 900, 900], [2, 2, 2]]];
    const sel = new LodSelect(n), lv = new Uint8Array(n), share = new Float32Array(n);
    const r = sel.select(trees, dist, n, new Uint8Array(n), cost, lv, { triangles: 1e12, trees: 1e9, nodes: 1e12 }, [100], share);
    assert.equal(r.scale, 1);
    const fade0 = LOD_OUTER_M[LOD.THIN] * (1 - LOD_FADE_SHARE);
    for (let i = 0; i < n; i++) {
        const d = ds[i];
        let want = d < LOD_OUTER_M[LOD.FULL] ? LOD.FULL : d < LOD_OUTER_M[LOD.THIN] ? LOD.THIN : d < LOD_OUTER_M[LOD.IMPOSTOR] ? LOD.IMPOSTOR : LOD.NONE;
        const sh = want === LOD.THIN ? Math.max(0, (d - fade0) / (LOD_OUTER_M[LOD.THIN] - fade0)) : want === LOD.IMPOSTOR ? 1 : 0;
        assert.equal(lv[i], want, `tree at ${d} m: level ${lv[i]}, expected ${want}`);
        near(share[i], sh, 1e-6, `impostor share at ${d} m`);
    }
    assert.ok(share.some((x) => x > 0 && x < 1), 'no tree fading');
}

// --- a fallen tree's impostor row: its fall, and a far one listed with it
{
    near(impFall(0, 1.0), 0, 0, 'standing');
    near(impFall(8, 2.0), 0, 0, 'standing, leaves lost');
    near(impFall(Math.PI / 2, 0), 1.5, 1e-7, 'lying towards +x');
    near(impFall(256 + 4 * 3 + 0.7, Math.PI / 2), 1 + 64 + 0.7 / Math.PI, 1e-6, 'snapped, towards +y, leaves lost');
    near(impFall(3.0, -Math.PI / 2), 1 + 192 + 0.5, 1e-6, 'tumbled past π/2, towards -y: lies flat');
    near(impFall(1.0, 2 * Math.PI - 1e-4), 1 + 1 / Math.PI, 1e-6, 'a whole turn is azimuth 0');
    // on the landscape from the air: trees far off fallen towards +x, every one listed as an
    // impostor with its fall (tree by tree, and in a cell listed whole alike)
    const N = 20000, { r } = landscape(N), [, eye, target] = CAMERAS[0];
    r.viewproj = viewProj(eye, target);
    const fallen = [];
    for (let t = 7; t < N; t += 97) {
        r.treeData[8 * t + 6] = 1.5 + (t % 2 ? 256 : 0);
        r.treeData[8 * t + 7] = 0;
        fallen.push(t);
    }
    r.placeDamage();
    r.drawList({ eye }, null);
    const ni = r.stats.impostors, got = new Map();
    for (let e = 0; e < ni; e++) got.set(r.impData[4 * e], r.impData[4 * e + 2]);
    let listed = 0;
    for (const t of fallen) {
        if (!got.has(t)) continue;
        listed++;
        near(got.get(t), 1 + 1.5 / Math.PI, 1e-6, `fallen tree ${t}'s impostor`);
    }
    for (const [t, f] of got) if (!fallen.includes(t)) assert.equal(f, 0, `standing tree ${t}'s impostor`);
    assert.ok(listed > 0.5 * fallen.length && r.grid.out.whole.n > 0, `${listed} of ${fallen.length} fallen trees listed as impostors, ${r.grid.out.whole.n} cells whole`);
}

// --- the landscape's scale: 100,000 trees in a 2 km square, an aerial camera
{
    const N = 100000, { r, rows, species } = landscape(N);
    for (const [name, eye, target] of CAMERAS) {
        const viewproj = viewProj(eye, target);
        r.viewproj = viewproj;
        const frames = [];
        let out;
        for (let k = 0; k < 8; k++) {
            const t0 = performance.now();
            out = r.drawList({ eye }, null);
            frames.push(performance.now() - t0);
        }
        // in view by brute force: the box of half-side its height about its base not wholly
        // outside a plane, its middle within IMPOSTOR's outer distance
        const pl = frustumPlanes(viewproj);
        let inView = 0;
        for (let t = 0; t < N; t++) {
            const [s, x, y, z, , sc] = rows[t], hh = species[s].height * sc;
            const d = Math.hypot(x - eye[0], y - eye[1], z + hh / 2 - eye[2]);
            if (d < LOD_OUTER_M[LOD.IMPOSTOR] && boxInFrustum(pl, x - hh, y - hh, z - hh, x + hh, y + hh, z + hh) >= 0) inView++;
        }
        const st = r.stats;
        // the triangles and draws the passes issue (web/render_gl.js draw): per group its
        // skeleton pass (2), a bark mesh and a leaf level each, per species its impostors
        let tris = 0, draws = 8, rowsPosed = 0;
        for (const g of out.groups) {
            const sp = species[g.s], lvl = r.leafLevels(sp);
            draws += 2 + g.bark.length + g.leaves.length;
            rowsPosed += g.n;
            for (const [, n, m] of g.bark) tris += n * sp.lod_count[m] / 3;
            for (const [, n, l] of g.leaves) tris += n * 2 * lvl[l].n;
        }
        for (const g of out.imps) {
            draws++;
            tris += IMP_TRIANGLES * g.n;
        }
        const sorted = frames.slice(1).sort((a, b) => a - b);
        console.log(JSON.stringify({ camera: name, trees: N, in_view: inView, drawn: st.trees_drawn, levels: st.levels, impostors: st.impostors, triangles: tris, draws,
            scale: st.lod_scale, scale_far: st.lod_scale_far, cull_lod_ms: { first: frames[0], median: sorted[sorted.length >> 1], max: sorted[sorted.length - 1] } }));
        assert.ok(inView > (name === 'aerial' ? 50000 : 5000), `${inView} trees in view: expected most of the square`);
        assert.equal(st.trees_drawn, inView, `${name}: every tree in view drawn`);
        assert.ok(st.impostors > 0.9 * inView, `${name}: ${st.impostors} impostors of ${inView} trees`);
        assert.ok(tris <= LOD_BUDGET_TRIANGLES, `${name}: ${tris} triangles`);
        assert.ok(draws <= LOD_BUDGET_DRAWS, `${name}: ${draws} draws`);
        assert.ok(rowsPosed <= LOD_BUDGET_TREES, `${name}: ${rowsPosed} trees posed`);
        if (name === 'low') assert.ok(st.levels[LOD.FULL] + st.levels[LOD.THIN] > 0 && st.lod_scale < 1, `${name}: ${st.levels} at scale ${st.lod_scale}`);
        // a tree fading is drawn both ways, THIN keeping the pixels its impostor leaves
        // (dither_keep: THIN 1 − share, the impostor −share)
        const thinFade = new Map();
        for (let row = 0; row < out.rows; row++) thinFade.set(r.listData[4 * row], r.listData[4 * row + 3]);
        let fading = 0;
        for (let e = 0; e < st.impostors; e++) {
            const t = r.impData[4 * e], f = r.impData[4 * e + 3];
            if (f === 1) {
                assert.ok(!thinFade.has(t), `${name}: tree ${t} wholly an impostor also posed`);
                continue;
            }
            fading++;
            assert.ok(f < 0 && f > -1 && thinFade.has(t), `${name}: tree ${t} fading (${f}) without its THIN row`);
            near(thinFade.get(t), 1 + f, 1e-6, `${name}: tree ${t}'s THIN fade`);
        }
        if (name === 'low') assert.ok(fading > 0, `${name}: no tree fading`);
    }
}
console.log(JSON.stringify({ ok: true }));
