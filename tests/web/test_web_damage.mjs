// Storm damage and falling leaves in the browser against a real gale-server (the 7-tree
// clearing) and a native gale-client. A viewer page watches while a kiosk dials a storm:
// trees uproot (their falls animated from the events), crowns are stripped, branches break
// off and fall as debris, leaves are torn off; the kiosk dials calm again. Then:
// - falling leaves: the watching page, its camera close to where most torn leaves are,
//   draws a still with and one without them; each leaf's place, computed here from the
//   ring with web/falling_path.js (the C path formula, tests/web/test_damage_js.mjs) as
//   shaders/fall.vert does, must be changed in the picture, and little else;
// - the same damaged state natively and in the browser: a native gale-client and a fresh
//   page join late (both from the full DAMAGE with their keyframe) and draw the default
//   view; the pictures are compared outside the native HUD's boxes (mean difference,
//   pixels off by more than 32 levels, 8-pixel blocks off by more than 16 on average);
// - where each fallen tree stood, its crown in the intact picture of the same page is
//   gone in the damaged one;
// - a snapped stem (PROTOCOL.md's DAMAGE-FULL vector, tree 1 snapped, given to the page as
//   if received): one stump drawn, the stem above the break gone, the stump where the stem was;
// - far away (320 m, an impostor) a fallen tree lies along its fall: seen steeply from
//   above, fallen across the view each way against standing, its changed pixels' middle
//   lies more than 2 m along the fall from its base (far_fallen.png: a picture of it);
// - after a reconnect the page holds the server's damage again.
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import { writeFileSync, readFileSync, mkdirSync } from 'node:fs';
import path from 'node:path';
import { args, startServer, startBrowser, waitFor, until, projector, comparePictures } from './harness.mjs';
import { readVectors } from './spec_vectors.mjs';

const [server, work, config, client, protocolMd] = args('usage: node test_web_damage.mjs GALE_SERVER WORK_DIR SCENE.json GALE_CLIENT PROTOCOL.md');
const SNAP_FULL = Array.from(readVectors(protocolMd).hex['DAMAGE-FULL']);
mkdirSync(work, { recursive: true });
const TOKEN = 'web-damage-test-7d2a';
writeFileSync(path.join(work, 'token'), `${TOKEN}\n`, { mode: 0o600 });
const srv = await startServer(server, ['--cache', path.join(work, '..', 'cache'), '--config', config, '--kiosk-token-file', path.join(work, 'token')]);
const W = 640, H = 480;
const native = (png) => new Promise((resolve, reject) => {
    const p = spawn(client, ['--url', `ws://127.0.0.1:${srv.port}`, '--headless', '--frames', '12', '--size', `${W}x${H}`, '--storm-fx', 'off',
        '--cache', path.join(work, 'client-cache'), '--screenshot', png], { stdio: ['ignore', 'ignore', 'pipe'] });
    let log = '';
    p.stderr.on('data', (d) => { log += d; });
    const timer = setTimeout(() => p.kill('SIGKILL'), 120000);
    p.on('exit', (c) => { clearTimeout(timer); return c === 0 ? resolve(log) : reject(new Error(`gale-client exited ${c}:\n${log}`)); });
});
const sleep = (s) => new Promise((r) => setTimeout(r, s * 1000));
const diffAt = (a, b, w) => (x, y) => {
    const i = 4 * (y * w + x);
    return Math.abs(a[i] - b[i]) + Math.abs(a[i + 1] - b[i + 1]) + Math.abs(a[i + 2] - b[i + 2]);
};
const damageOf = (page) => page.evaluate(() => {
    const v = window.gale.damage.view;
    return { fallen: Array.from(v.fallen), az: Array.from(v.fall_az), level: Array.from(v.level), broken: v.broken.slice() };
});

const ctx = await startBrowser(work, { width: W, height: H });
const out = {};
try {
    const watch = await ctx.newPage();
    await watch.goto(`${srv.url}/?storm_fx=off`);
    await waitFor(watch, () => window.gale && window.gale.framesDrawn >= 3, null, 120, 'the watching page drawing');
    const kiosk = await ctx.newPage();
    await kiosk.goto(`${srv.url}/kiosk#token=${TOKEN}`);
    await waitFor(kiosk, () => window.gale && window.gale.conn && window.gale.conn.status.state === 'live', null, 60, 'kiosk live');
    // the kiosk holds the dial while connected; it need not draw meanwhile
    await kiosk.evaluate((t) => { window.gale.frozen = true; window.gale.conn.send({ type: 'wind', token: t, speed_ms: 60, dir_deg: 90 }); }, TOKEN);
    // the storm until two trees lie and a fall was seen under way
    let tipping = 0, debris = 0, last = null;
    await until(async () => {
        last = await watch.evaluate(() => ({ tipping: window.gale.damage.tipping, fallen: window.gale.damage.view.fallen.filter((x) => x).length, drawn: window.gale.framesDrawn,
            debris: window.gale.r.debris.length }));
        if (last.tipping > 0 && tipping === 0) await watch.screenshot({ path: path.join(work, 'falling.png') }); // a fall under way
        tipping = Math.max(tipping, last.tipping);
        debris = Math.max(debris, last.debris);
        return last.fallen >= 2 && tipping > 0 && last.debris > 0;
    }, 90, 'two trees fallen, a fall seen under way, a branch broken off').catch((e) => { throw new Error(`${e.message}: ${JSON.stringify({ last, tipping })}`); });
    await sleep(3); // the last falls finish; more leaves are torn off
    await kiosk.evaluate((t) => window.gale.conn.send({ type: 'wind', token: t, speed_ms: 0, dir_deg: 90 }), TOKEN);
    await kiosk.close();
    // the wind eases off over seconds: wait until the damage has stood for 3 s (and the
    // standing trees settle)
    let seen = await damageOf(watch), since = Date.now();
    await until(async () => {
        const now = await damageOf(watch);
        if (JSON.stringify(now) !== JSON.stringify(seen)) {
            seen = now;
            since = Date.now();
        }
        return Date.now() - since > 3000;
    }, 40, 'the damage standing still after the storm');
    const pieces = await watch.evaluate(() => window.gale.r.debris.length);
    await watch.screenshot({ path: path.join(work, 'watched.png') });
    out.damage = { ...seen, tipping_seen: tipping, debris_seen: Math.max(debris, pieces) };
    // the branches broke while the page watched: they fell as pieces, which lie now
    assert.ok(pieces >= 1, `${pieces} debris pieces lying for ${seen.broken.length} broken branches`);

    // falling leaves, where the C path formula puts them
    const lf = await watch.evaluate(async () => {
        const g = window.gale, r = g.r;
        g.frozen = true;
        const { fallingPathEval } = await import('/web/falling_path.js');
        const u = g.shown_s - r.t_base; // fall.vert's u_time
        const leaves = [];
        for (let i = 0; i < r.ringCount; i++) {
            const e = i * 21, o = r.ring;
            const tau = u - o[e + 3];
            if (tau < 0) continue;
            const te = Math.min(tau, o[e + 10]);
            const v = { start: o[e + 7], yaw: o[e + 4], sx: o[e + 5], sy: o[e + 6], seed: r.ringU32[e + 11] };
            const d = fallingPathEval(r.path, v, te);
            leaves.push([o[e] + d[0] + o[e + 8] * te, o[e + 1] + d[1] + o[e + 9] * te, Math.max(o[e + 2] + d[2], 0), o[e + 19]]);
        }
        // the camera close to the densest patch of leaves: the leaf with the most others
        // within 3 m
        let best = 0, most = -1;
        for (let i = 0; i < leaves.length; i += Math.ceil(leaves.length / 400)) {
            let n = 0;
            for (const l of leaves) n += Math.hypot(l[0] - leaves[i][0], l[1] - leaves[i][1], l[2] - leaves[i][2]) < 3;
            if (n > most) { most = n; best = i; }
        }
        g.cam.target = leaves[best].slice(0, 3);
        g.cam.distance = 10;
        g.cam.pitch = -0.7;
        const on = g.still(true);
        r.hideFalling = true;
        const off = g.still(true);
        r.hideFalling = false;
        g.still(true); // the canvas shows them for the screenshot
        return { leaves, on, off, n_ring: r.ringCount, shed: g.leavesShed };
    });
    await watch.screenshot({ path: path.join(work, 'leaves.png') });
    {
        const a = Buffer.from(lf.on.pixels, 'base64'), b = Buffer.from(lf.off.pixels, 'base64');
        const d = diffAt(a, b, W), proj = projector(lf.on.cam, W, H);
        const near = new Uint8Array(W * H);
        let inView = 0, hit = 0;
        for (const [x, y, z, size] of lf.leaves) {
            const [px, py, depth] = proj([x, y, z]);
            if (depth < 0.5 || px < 3 || py < 3 || px >= W - 3 || py >= H - 3) continue;
            const rpx = Math.max(3, Math.ceil((size * H) / depth)); // a leaf's reach on screen, generous
            for (let dy = -rpx; dy <= rpx; dy++) for (let dx = -rpx; dx <= rpx; dx++) {
                const qx = Math.round(px) + dx, qy = Math.round(py) + dy;
                if (qx >= 0 && qy >= 0 && qx < W && qy < H) near[qy * W + qx] = 1;
            }
            inView++;
            let c = 0;
            for (let dy = -2; dy <= 2 && !c; dy++) for (let dx = -2; dx <= 2 && !c; dx++) c = d(Math.round(px) + dx, Math.round(py) + dy) > 24;
            hit += c;
        }
        let away = 0, awayPx = 0;
        for (let i = 0; i < W * H; i++) {
            if (near[i]) continue;
            awayPx++;
            away += d(i % W, Math.floor(i / W)) > 24;
        }
        out.leaves = { ring: lf.n_ring, shed: lf.shed, in_view: inView, changed_at_leaf: +(hit / Math.max(inView, 1)).toFixed(3), changed_away: away, away_px: awayPx };
        assert.ok(inView >= 15, `only ${inView} torn leaves in the close view: ${JSON.stringify(out.leaves)}`);
        assert.ok(hit >= 0.6 * inView, `the picture changed at ${hit} of ${inView} leaves' places (expected >= 60 %)`);
        assert.ok(away <= 0.01 * awayPx, `${away} of ${awayPx} pixels away from every leaf changed (expected <= 1 %)`);
    }
    await watch.close();

    // the same damaged state, natively and in a page that joins late
    await native(path.join(work, 'native.png'));
    const page = await ctx.newPage();
    await page.goto(`${srv.url}/?storm_fx=off`);
    await waitFor(page, () => window.gale && window.gale.framesDrawn >= 5, null, 120, 'the late page drawing');
    // The late page's picture comes from the keyframe's full DAMAGE, shown at the jitter
    // buffer's delay: it may take some frames on a loaded machine. Damage only grows, so a
    // tree hit after the watching page closed is real damage the late page must hold too.
    let late = await damageOf(page);
    const holds = (a, b) => a.fallen.every((k, t) => k === b.fallen[t] || (k === 0 && b.fallen[t] !== 0)) &&
        a.level.every((k, t) => b.level[t] <= k) && a.broken.every((x) => b.broken.some((y) => JSON.stringify(y) === JSON.stringify(x)));
    await until(async () => {
        late = await damageOf(page);
        return JSON.stringify(late) === JSON.stringify(seen);
    }, 20, 'the late page holding the damage the watching one saw').catch(() => {});
    if (JSON.stringify(late) !== JSON.stringify(seen)) {
        assert.ok(holds(seen, late), `the late page lacks damage the watching one saw: ${JSON.stringify({ late, seen })}`);
        console.log(`damage grew after the watching page closed: ${JSON.stringify({ late, seen })}`);
        seen = late;
    }
    const st = await page.evaluate(() => ({ stats: window.gale.conn.stats, errors: window.gale.errors, r: window.gale.r.stats, inst: window.gale.welcome.instances,
        sp: window.gale.r.species.map((s) => [s.height, s.crown_r, s.crown_c]) }));
    assert.equal(st.stats.errors, 0, `decode errors: ${st.stats.lastError}`);
    assert.deepEqual(st.errors, []);
    assert.equal(st.r.plates, seen.fallen.filter((k) => k === 3).length, 'a root plate per uprooted tree');
    await page.evaluate(() => { window.gale.frozen = true; });
    await page.screenshot({ path: path.join(work, 'browser.png') });
    const png = readFileSync(path.join(work, 'native.png')).toString('base64');
    const two = await page.evaluate(async (b64) => {
        const g = window.gale, still = g.still(true); // rows bottom first
        const img = new Image();
        img.src = `data:image/png;base64,${b64}`;
        await img.decode();
        const c = document.createElement('canvas');
        c.width = still.w;
        c.height = still.h;
        const x = c.getContext('2d');
        x.drawImage(img, 0, 0, still.w, still.h);
        const nat = x.getImageData(0, 0, still.w, still.h).data; // rows top first
        const bytes = (bin) => btoa(Array.from({ length: Math.ceil(bin.length / 0x8000) }, (_, i) => String.fromCharCode.apply(null, bin.subarray(i * 0x8000, (i + 1) * 0x8000))).join(''));
        return { w: still.w, h: still.h, page: still.pixels, native: bytes(nat), native_size: [img.width, img.height] };
    }, png);
    // the native HUD's boxes (gale-client draws them into its picture; the page's HUD is
    // HTML over the canvas): the text box top left (seven lines with the expert line, the
    // wind line's two units and gust across 80 % of a 640 px picture), the compass top right,
    // the caption
    const hud = (i, y) => (i < 0.82 * two.w && y < 0.42 * two.h) || (i > 0.8 * two.w && y < 0.25 * two.h) || y > 0.85 * two.h;
    const d = comparePictures(Buffer.from(two.page, 'base64'), Buffer.from(two.native, 'base64'), two.w, two.h, hud);
    const cmp = { mean_abs_diff: +d.mean_abs_diff.toFixed(2), frac_over_32: +d.frac_over_32.toFixed(4), blocks_8px_over_16: +d.blocks_8px_over_16.toFixed(4),
        compared_px: d.compared_px, native_size: two.native_size };
    out.native_vs_browser = cmp;
    assert.deepEqual(cmp.native_size, [W, H]);
    assert.ok(cmp.blocks_8px_over_16 < 0.06, `browser and native differ in ${(100 * cmp.blocks_8px_over_16).toFixed(1)} % of 8-pixel blocks (>= 6 %): ${JSON.stringify(cmp)}`);
    assert.ok(cmp.frac_over_32 < 0.12, `browser and native differ in ${(100 * cmp.frac_over_32).toFixed(1)} % of pixels (>= 12 %)`);
    assert.ok(cmp.mean_abs_diff < 10, `mean difference ${cmp.mean_abs_diff} levels (>= 10)`);

    // the intact forest in the same page: each fallen tree's crown stood where it no longer
    // is, stripped crowns lost leaves, and the broken branches are gone
    const pics = await page.evaluate(async () => {
        const g = window.gale, r = g.r, n = r.n_trees;
        const damaged = g.still(true);
        // the broken branches close up: about each of the first four breaks (the node where
        // its tree, standing or lying, holds it at rest: tree_frame about the pivot), with and
        // without the cut lists; the pieces themselves left out (one that broke off a lying
        // crown lies where it hung)
        const cam0 = { ...g.cam, target: g.cam.target.slice() }, close = [], pieces = r.debris;
        const { debrisFrameMatrix } = await import('/web/debris_path.js');
        r.setDebris([]);
        const cl = g.damage.cutLists((t) => r.species[g.welcome.instances[t][0]].n_nodes);
        for (const key of g.damage.view.broken.slice(0, 4)) {
            const t = Math.floor(key / 2 ** 32), node = key % 2 ** 32, row = g.welcome.instances[t], a = r.species[row[0]].a;
            const R = debrisFrameMatrix(row[4], g.damage.fallAngle(t, g.shown_s), g.damage.view.fall_az[t] * Math.PI / 128);
            const piv = g.damage.pivot_m(t), p = [a.rest[3 * node], a.rest[3 * node + 1], a.rest[3 * node + 2] - piv];
            g.cam.target = [0, 1, 2].map((i) => row[1 + i] + row[5] * (R[i] * p[0] + R[3 + i] * p[1] + R[6 + i] * p[2] + (i === 2 ? piv : 0)));
            g.cam.distance = 6;
            r.setCuts(cl.head, cl.nodes);
            const cut = g.still(true);
            r.setCuts(new Float32Array(4 * n), new Float32Array(1));
            close.push({ tree: `${t}:${node}`, cut, uncut: g.still(true) });
        }
        r.setDebris(pieces);
        g.damageGen = -1;
        Object.assign(g.cam, cam0);
        r.setDamage(new Float32Array(n), new Float32Array(n), new Uint8Array(n));
        const intact = g.still(true);
        g.damageGen = -1;
        g.damage.dirty = true;
        g.applyDamage(g.shown_s);
        return { damaged, intact, close };
    });
    {
        const a = Buffer.from(pics.damaged.pixels, 'base64'), b = Buffer.from(pics.intact.pixels, 'base64');
        const d = diffAt(a, b, W), proj = projector(pics.damaged.cam, W, H);
        let cut = 0;
        const perTree = {};
        for (const c of pics.close) {
            const du = diffAt(Buffer.from(c.cut.pixels, 'base64'), Buffer.from(c.uncut.pixels, 'base64'), W);
            let k = 0;
            for (let i = 0; i < W * H; i++) k += du(i % W, Math.floor(i / W)) > 24;
            perTree[c.tree] = k;
            cut += k;
        }
        out.broken_branches = { n: seen.broken.length, px_changed: perTree };
        assert.ok(seen.broken.length >= 1, 'no branch broke in the storm');
        // a small branch low inside a crown can be hidden from its close view by its own
        // tree's foliage: most, not every, close view shows its cut
        const shown = Object.values(perTree).filter((k) => k >= 100).length;
        assert.ok(shown >= 1 && 2 * shown >= Object.keys(perTree).length,
            `${shown} of ${Object.keys(perTree).length} broken branches changed >= 100 pixels of their close views: ${JSON.stringify(perTree)}`);
        out.fallen_crowns = [];
        out.stripped_crowns = [];
        seen.fallen.forEach((k, t) => {
            if (!k) {
                if (seen.level[t] > 26) return;
            }
            const [sp, x, y, z, yaw, scale] = st.inst[t], [, cr, cc] = st.sp[sp];
            const cy = Math.cos(yaw), sy = Math.sin(yaw);
            const c = proj([x + scale * (cy * cc[0] - sy * cc[1]), y + scale * (sy * cc[0] + cy * cc[1]), z + scale * cc[2]]);
            if (c[0] < 8 || c[1] < 8 || c[0] > W - 8 || c[1] > H - 8) return;
            const rpx = (cr * scale * H / 2 / Math.tan(25 * Math.PI / 180)) / c[2], kk = Math.max(2, Math.round(rpx / 3));
            let m = 0, ch = 0;
            for (let dy = -kk; dy <= kk; dy++) for (let dx = -kk; dx <= kk; dx++) {
                const px = Math.round(c[0] + dx), py = Math.round(c[1] + dy);
                if (px < 0 || py < 0 || px >= W || py >= H) continue;
                m++;
                ch += d(px, py) > 24;
            }
            (k ? out.fallen_crowns : out.stripped_crowns).push({ tree: t, at: c.slice(0, 2).map(Math.round), level: seen.level[t], changed: +(ch / m).toFixed(2) });
        });
        assert.ok(out.fallen_crowns.length >= 2, `expected at least 2 fallen trees' crowns in view, got ${out.fallen_crowns.length}`);
        for (const c of out.fallen_crowns) assert.ok(c.changed >= 0.3, `tree ${c.tree}: ${c.changed} of its standing crown's window changed when it fell (expected >= 0.3)`);
        for (const c of out.stripped_crowns) assert.ok(c.changed >= 0.03, `tree ${c.tree}: ${c.changed} of its crown's window changed when stripped to ${c.level}/32 (expected >= 0.03)`);
    }

    // a snapped stem, from the DAMAGE-FULL vector (the whole state: tree 0 stripped to
    // 20/32, tree 1 snapped towards 200/256 of a turn; the rest healed)
    const snap = await page.evaluate(async (bytes) => {
        const g = window.gale, r = g.r, n = r.n_trees;
        const { Decoder } = await import('/web/wire.js');
        const { tipFallBreak_m } = await import('/web/damage.js');
        g.onFrame(new Decoder().decode(Uint8Array.from(bytes)));
        g.applyDamage(g.shown_s);
        const row = g.welcome.instances[1], az = g.damage.view.fall_az[1] * Math.PI / 128;
        // side on to the fall, level with the break
        Object.assign(g.cam, { target: [row[1], row[2], 1.2], distance: 7, yaw: az + Math.PI / 2, pitch: -0.15 });
        const snapped = g.still(true);
        const stats = { stumps: r.stats.stumps, plates: r.stats.plates, fallen: Array.from(g.damage.view.fallen) };
        const code = Float32Array.from(g.damage.code);
        r.setDamage(new Float32Array(n), new Float32Array(n), new Uint8Array(n));
        const standing = g.still(true);
        r.setDamage(code, g.damage.az, new Uint8Array(n));
        g.still(true); // the canvas shows the snapped stem for the screenshot
        return { snapped, standing, stats, break_m: tipFallBreak_m(1) * row[5], base: row.slice(1, 4) };
    }, SNAP_FULL);
    await page.screenshot({ path: path.join(work, 'snapped.png') });
    {
        assert.deepEqual(snap.stats, { stumps: 1, plates: 0, fallen: [0, 2, 0, 0, 0, 0, 0] });
        const d = diffAt(Buffer.from(snap.snapped.pixels, 'base64'), Buffer.from(snap.standing.pixels, 'base64'), W);
        const proj = projector(snap.snapped.cam, W, H);
        const win = (z) => {
            const c = proj([snap.base[0], snap.base[1], snap.base[2] + z]);
            let m = 0, ch = 0;
            for (let dy = -2; dy <= 2; dy++) for (let dx = -2; dx <= 2; dx++, m++) ch += d(Math.round(c[0]) + dx, Math.round(c[1]) + dy) > 24;
            return +(ch / m).toFixed(2);
        };
        out.snapped = { break_m: +snap.break_m.toFixed(3), stump_changed: win(0.4 * snap.break_m), above_changed: win(snap.break_m + 2.5) };
        assert.ok(out.snapped.stump_changed <= 0.3, `the stump below the break differs from the standing stem (${out.snapped.stump_changed} of its window)`);
        assert.ok(out.snapped.above_changed >= 0.7, `the stem 2.5 m above the break is still there (${out.snapped.above_changed} of its window changed)`);
    }

    // far away a fallen tree is an impostor laid along its fall (web/imp_shader.js,
    // shaders/common.glsl bill_fallen, as gale-client's test_render_damage): the tree
    // farthest from the others seen from 320 m through a 10° lens, steeply from above,
    // fallen across the view one way, then the other, against it standing: many pixels
    // change, and their middle lies along the fall from its base (the standing crown's
    // pixels lie about the base across the view)
    const far = await page.evaluate(() => {
        const g = window.gale, r = g.r, n = r.n_trees, rows = g.welcome.instances;
        let t = 0, best = -1;
        for (let i = 0; i < n; i++) {
            let m = Infinity;
            for (let j = 0; j < n; j++) if (j !== i) m = Math.min(m, Math.hypot(rows[j][1] - rows[i][1], rows[j][2] - rows[i][2]));
            if (m > best) { best = m; t = i; }
        }
        const cam0 = { ...g.cam, target: g.cam.target.slice() }, row = rows[t];
        Object.assign(g.cam, { target: [row[1], row[2], row[3]], distance: 320, yaw: 0.3, pitch: -1.2, fov_y_deg: 10 });
        const code = new Float32Array(n), az = new Float32Array(n), up = new Uint8Array(n);
        r.setDamage(code, az, up);
        const standing = g.still(true), levels = r.stats.levels.slice();
        const e = standing.cam.eye, across = Math.atan2(row[2] - e[1], row[1] - e[0]) + Math.PI / 2;
        const fallen = [];
        for (const a of [across, across + Math.PI]) {
            code[t] = Math.PI / 2;
            az[t] = a;
            r.setDamage(code, az, up);
            fallen.push({ az: a, pic: g.still(true), levels: r.stats.levels.slice() });
        }
        // a picture (far_fallen.png, without the HUD): it lies across the view among the
        // standing impostors
        Object.assign(g.cam, { pitch: -0.9, fov_y_deg: 12 });
        const pic = g.still(true), c = document.createElement('canvas');
        c.width = pic.w;
        c.height = pic.h;
        const x = c.getContext('2d'), im = x.createImageData(pic.w, pic.h), raw = atob(pic.pixels), row4 = 4 * pic.w;
        for (let y = 0; y < pic.h; y++) for (let i = 0; i < row4; i++) im.data[y * row4 + i] = raw.charCodeAt((pic.h - 1 - y) * row4 + i);
        x.putImageData(im, 0, 0);
        g.farCam0 = cam0;
        return { tree: t, base: row.slice(1, 4), apart_m: best, standing, levels, fallen, png: c.toDataURL('image/png').split(',')[1] };
    });
    writeFileSync(path.join(work, 'far_fallen.png'), Buffer.from(far.png, 'base64'));
    await page.evaluate(() => {
        const g = window.gale;
        g.damageGen = -1;
        Object.assign(g.cam, g.farCam0);
        g.damage.dirty = true;
        g.applyDamage(g.shown_s);
    });
    {
        const proj = projector(far.standing.cam, W, H), b = proj(far.base);
        out.far_fallen = { tree: far.tree, apart_m: +far.apart_m.toFixed(1), levels: far.levels, sides: [] };
        assert.deepEqual(far.levels, [0, 0, far.levels[2]], 'from 320 m the trees are impostors alone');
        for (const f of far.fallen) {
            assert.deepEqual(f.levels, far.levels, 'a fallen tree 320 m off is an impostor too');
            const d = diffAt(Buffer.from(f.pic.pixels, 'base64'), Buffer.from(far.standing.pixels, 'base64'), W);
            // the fall's direction on screen and the length of 3 m along it
            const tip = proj([far.base[0] + 3 * Math.cos(f.az), far.base[1] + 3 * Math.sin(f.az), far.base[2]]);
            const ux = tip[0] - b[0], uy = tip[1] - b[1], l3 = Math.hypot(ux, uy);
            let changed = 0, sum = 0, beyond = 0;
            for (let y = 0; y < H; y++) for (let x = 0; x < W; x++) {
                if (d(x, y) <= 24) continue;
                const along = ((x - b[0]) * ux + (y - b[1]) * uy) / l3;
                changed++;
                sum += along;
                beyond += along > l3;
            }
            const s = { changed_px: changed, beyond_3m_px: beyond, middle_along_m: +(changed ? 3 * sum / changed / l3 : 0).toFixed(2), px_per_3m: +l3.toFixed(1) };
            out.far_fallen.sides.push(s);
            assert.ok(changed >= 100 && beyond >= 40 && s.middle_along_m > 2, `tree ${far.tree} fallen towards ${f.az.toFixed(2)} rad: ${JSON.stringify(s)} (expected >= 100 px changed, >= 40 more than 3 m along the fall, their middle > 2 m along it)`);
        }
    }

    // a reconnect: the page gets the whole damage again with its keyframe
    const before = await page.evaluate(() => window.gale.conn.stats.frames);
    await page.evaluate(() => { window.gale.frozen = false; window.gale.conn.ws.close(); });
    await waitFor(page, (n) => window.gale.conn.status.state === 'live' && window.gale.conn.stats.frames > n + 10 && window.gale.framesDrawn > 0, before, 60, 'live again after the reconnect');
    assert.deepEqual(await damageOf(page), seen, 'the damage after a reconnect');
    assert.deepEqual(ctx.errors, []);
    console.log(JSON.stringify({ ...out, ok: true }));
} finally {
    await ctx.close();
    await srv.stop();
}
