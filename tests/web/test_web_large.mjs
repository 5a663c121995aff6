// The viewer page on a scene larger than the page once held (tests/data/forest_20k_scene.json:
// 20,000 trees on 900 m × 900 m) against a real gale-server:
// - it opens the scene and draws a first frame (5-42 s at load averages 10-25; 120 s
//   allowed), culled and levelled within the budget of web/lod_policy.js (draw calls,
//   triangles, trees posed);
// - it sends the server a view of its frustum, and the stream shrinks: fewer trees a
//   snapshot and fewer bytes a state frame than a page that sends none (?view=all); moving
//   its camera sends a new view, its eye the camera's, which the server follows;
// - a page given less memory than the scene needs (?hold_mb=1) says so on the page and
//   still draws, on its first connection.
import assert from 'node:assert/strict';
import path from 'node:path';
import { args, startServer, startBrowser, waitFor } from './harness.mjs';
import { LOD_BUDGET_TRIANGLES, LOD_BUDGET_DRAWS, LOD_BUDGET_TREES } from '../../web/lod_policy.js';

const [server, work, config] = args('usage: node test_web_large.mjs GALE_SERVER WORK_DIR SCENE.json');
const srv = await startServer(server, ['--cache', path.join(work, '..', 'cache'), '--config', config]);
const ctx = await startBrowser(work, { width: 480, height: 360 });
const stats = (page) => page.evaluate(() => ({ lod: window.gale.lodStats(), errors: window.gale.errors, trees: window.gale.welcome.instances.length,
    bytes: window.gale.conn.stats.bytes, frames: window.gale.conn.stats.frames, decodeErrors: window.gale.conn.stats.errors,
    first_ms: window.gale.firstFrame_ms, message: window.gale.status().message }));
// the stream's bytes a second over s seconds and at least 3 frames, and the trees of the
// last snapshot
async function stream(page, s) {
    const a = await stats(page);
    const t0 = Date.now();
    await new Promise((r) => setTimeout(r, s * 1000));
    await waitFor(page, (n) => window.gale.conn.stats.frames >= n, a.frames + 3, 120, 'three frames of the stream');
    const b = await stats(page);
    return { bytes_per_s: (b.bytes - a.bytes) / ((Date.now() - t0) / 1000), bytes_per_frame: (b.bytes - a.bytes) / Math.max(1, b.frames - a.frames),
        trees_per_snapshot: b.lod.trees_per_snapshot };
}
const out = {};
const t_start = Date.now();
const step = (what) => console.error(`${((Date.now() - t_start) / 1000).toFixed(1)} s: ${what}`);
try {
    // the page following its camera
    const page = await ctx.newPage();
    const t0 = Date.now();
    await page.goto(`${srv.url}/`);
    await waitFor(page, () => window.gale && window.gale.framesDrawn >= 1, null, 120, 'a first frame');
    out.first_frame_s = (Date.now() - t0) / 1000;
    step(`following page: first frame after ${out.first_frame_s} s`);
    let s = await stats(page);
    assert.equal(s.trees, 20000);
    assert.deepEqual(s.errors, []);
    assert.equal(s.decodeErrors, 0);
    assert.ok(s.lod.draws <= LOD_BUDGET_DRAWS, `${s.lod.draws} draw calls`);
    // the budget is the trees'; the skeleton pass's quads, sky and houses come on top
    assert.ok(s.lod.triangles <= LOD_BUDGET_TRIANGLES + 4 * LOD_BUDGET_TREES + 20000, `${s.lod.triangles} triangles`);
    assert.ok(s.lod.trees_drawn > 100 && s.lod.trees_drawn <= LOD_BUDGET_TREES, `${s.lod.trees_drawn} trees drawn`);
    out.first = s.lod;
    await waitFor(page, () => window.gale.lodStats().views_sent >= 1 && window.gale.lodStats().trees_per_snapshot < 20000, null, 120, 'a view sent and followed');
    step('view followed');
    out.followed = await stream(page, 6);

    // down into one corner of the forest, looking across it: a new view, fewer trees still
    const sent0 = (await stats(page)).lod.views_sent;
    await page.evaluate(() => Object.assign(window.gale.cam, { target: [300, 300, 4], distance: 40, pitch: -0.2 }));
    await waitFor(page, (n) => window.gale.lodStats().views_sent > n, sent0, 90, 'a view sent after the camera moved');
    await waitFor(page, () => {
        const v = window.gale.lodStats().view, c = window.gale.camera();
        return Math.hypot(v.eye[0] - c.eye[0], v.eye[1] - c.eye[1], v.eye[2] - c.eye[2]) < 3;
    }, null, 60, 'the view sent is the moved camera\'s');
    await waitFor(page, (n) => window.gale.lodStats().trees_per_snapshot !== n, out.followed.trees_per_snapshot, 120, 'the stream following the moved camera');
    step('moved camera followed');
    out.moved = await stream(page, 4);
    s = await stats(page);
    assert.deepEqual(s.errors, []);
    assert.ok(out.moved.trees_per_snapshot < 0.5 * s.trees, `${out.moved.trees_per_snapshot} trees a snapshot after the move`);
    out.moved_lod = s.lod;
    await page.close();

    // the whole scene: no view sent
    const all = await ctx.newPage();
    await all.goto(`${srv.url}/?view=all`);
    await waitFor(all, () => window.gale && window.gale.framesDrawn >= 1, null, 120, 'the whole-scene page\'s first frame');
    step('whole scene: first frame');
    out.whole = await stream(all, 6);
    const sa = await stats(all);
    assert.equal(sa.lod.views_sent, 0, 'a page with ?view=all sent a view');
    assert.equal(out.whole.trees_per_snapshot, sa.trees, 'the whole scene: every tree in every snapshot');
    await all.close();

    assert.ok(out.followed.trees_per_snapshot < 0.5 * out.whole.trees_per_snapshot, `${out.followed.trees_per_snapshot} trees a snapshot in view, ${out.whole.trees_per_snapshot} without`);
    // bytes a state frame: a page slower than the stream is sent fewer, each a keyframe
    // (SERVER.md "Slow readers"), so bytes a second follow its pace as much as the view
    assert.ok(out.followed.bytes_per_frame < 0.5 * out.whole.bytes_per_frame, `${out.followed.bytes_per_frame} B a frame in view, ${out.whole.bytes_per_frame} without`);

    // less memory than the scene needs: a message, a reduced view, no reconnect loop
    const small = await ctx.newPage();
    await small.goto(`${srv.url}/?hold_mb=1`);
    await waitFor(small, () => window.gale && window.gale.framesDrawn >= 1, null, 120, 'the reduced page\'s first frame');
    s = await stats(small);
    assert.match(s.message, /more than this browser can hold: the first \d+ move/);
    assert.ok(s.lod.trees_held > 0 && s.lod.trees_held < 20000, `${s.lod.trees_held} trees held`);
    const conn = await small.evaluate(() => ({ status: window.gale.conn.status, lastClose: window.gale.conn.stats.lastClose }));
    console.error(JSON.stringify(conn), srv.log().split('\n').filter((l) => /closing|slow/.test(l)).slice(-5).join('\n'));
    assert.equal(conn.status.state, 'live', JSON.stringify(conn));
    assert.equal(s.decodeErrors, 0);
    out.reduced = { trees_held: s.lod.trees_held, message: s.message };
    assert.deepEqual(ctx.errors, []);
    console.log(JSON.stringify({ ...out, ok: true }));
} catch (e) {
    console.log(JSON.stringify(out));
    throw e;
} finally {
    await ctx.close();
    await srv.stop();
}
