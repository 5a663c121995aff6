// The viewer page holding fewer trees than a scene has (web/WEB.md "Reduced view";
// tests/data/slow_client_scene.json: 300 palms) against a real gale-server, with
// ?hold_trees=100&lang=es:
// - it holds and draws the 100 trees nearest the scene's centre, the very trees a count of
//   the test's own finds from the welcome (read over a WebSocket of its own), and asks the
//   server for their circle, which then streams those alone;
// - its HUD says so in the page's language (configs/lang's hud.reduced), the console
//   once, and nothing is an error;
// - a server restarted on its port brings the same scene: the page reconnects with the
//   circle in its hello, holds the same trees, streams the same 100 and says nothing anew.
import assert from 'node:assert/strict';
import path from 'node:path';
import { args, startServer, startBrowser, waitFor, useTexts } from './harness.mjs';
import { t } from '../../web/lang.js';

const [server, work, config] = args('usage: node test_web_hold.mjs GALE_SERVER WORK_DIR SCENE.json');
const HOLD = 100;
await useTexts(server);
const serverArgs = ['--cache', path.join(work, '..', 'cache'), '--config', config];
let srv = await startServer(server, serverArgs);
const ctx = await startBrowser(work, { width: 480, height: 360 });
const said = [];
const state = (page) => page.evaluate(() => ({ lod: window.gale.lodStats(), held: Array.from(window.gale.held ? window.gale.held.held : []),
    drawn: window.gale.welcome.instances.length, r_trees: window.gale.r.n_trees, hud: document.getElementById('hud').textContent,
    errors: window.gale.errors, conn: window.gale.conn.status, decodeErrors: window.gale.conn.stats.errors }));
try {
    const page = await ctx.newPage();
    page.on('console', (m) => { if (m.text().includes('more than this page holds')) said.push(m.text()); });
    await page.goto(`${srv.url}/?hold_trees=${HOLD}&lang=es`);
    await waitFor(page, () => window.gale && window.gale.framesDrawn >= 2, null, 120, 'two frames');

    // the count of the test's own: the welcome's trees over another connection, the 100
    // nearest the mean of their x and y
    const rows = await page.evaluate((url) => new Promise((resolve, reject) => {
        const ws = new WebSocket(url);
        ws.onopen = () => ws.send(JSON.stringify({ type: 'hello', protocol: 1, role: 'viewer' }));
        ws.onmessage = (e) => {
            if (typeof e.data !== 'string') return;
            const m = JSON.parse(e.data);
            if (m.type === 'welcome') {
                ws.close();
                resolve(m.instances);
            }
        };
        ws.onerror = () => reject(new Error('the test\'s own connection failed'));
    }), srv.url.replace('http:', 'ws:') + '/');
    const n = rows.length, cx = rows.reduce((a, r) => a + r[1], 0) / n, cy = rows.reduce((a, r) => a + r[2], 0) / n;
    const byDist = rows.map((r, i) => [Math.hypot(r[1] - cx, r[2] - cy), i]).sort((a, b) => a[0] - b[0]);
    assert.ok(n > HOLD && byDist[HOLD][0] - byDist[HOLD - 1][0] > 0.005, `${n} trees, the ${HOLD}th and next nearest ${byDist[HOLD - 1][0]}, ${byDist[HOLD][0]} m`);
    const nearest = byDist.slice(0, HOLD).map((d) => d[1]).sort((a, b) => a - b);

    let s = await state(page);
    assert.deepEqual(s.held, nearest, 'the trees held are the nearest');
    assert.equal(s.drawn, HOLD);
    assert.equal(s.r_trees, HOLD, 'the renderer holds the trees held alone');
    assert.equal(s.lod.trees_held, HOLD);
    assert.equal(s.lod.scene_trees, n);
    assert.ok(Math.abs(s.lod.reduced.radius_m - byDist[HOLD - 1][0]) < 1e-3, `radius ${s.lod.reduced.radius_m}`);
    assert.equal(s.lod.reduced.why, `?hold_trees=${HOLD}`);
    assert.equal(s.lod.reduced.view.kind, 'circle');
    // the stream: the circle sent once, the server streaming the trees held alone
    await waitFor(page, (k) => window.gale.lodStats().trees_per_snapshot === k, HOLD, 60, 'the stream of the trees held alone');
    s = await state(page);
    assert.equal(s.lod.views_sent, 1);
    assert.deepEqual(s.lod.view, s.lod.reduced.view);
    // what a visitor reads
    const text = t('es', 'hud.reduced', HOLD, n);
    assert.ok(text.startsWith(`Vista reducida: los ${HOLD} árboles más cercanos de ${n}`), text);
    assert.equal(s.lod.reduced.text, text);
    assert.ok(s.hud.split('\n').includes(text), `the HUD: ${JSON.stringify(s.hud)}`);
    assert.equal(said.length, 1, said.join('\n'));
    assert.match(said[0], new RegExp(`the scene has ${n} trees, more than this page holds \\(\\?hold_trees=${HOLD}\\): holding the ${HOLD} nearest`));
    assert.deepEqual(s.errors, []);
    assert.deepEqual(ctx.errors, []);

    // the server restarted on its port: the same scene, the same trees and circle
    const first = await page.evaluate(() => { window.firstWelcome = window.gale.sceneWelcome; return window.gale.lodStats().view; });
    const port = srv.port;
    await srv.stop();
    await waitFor(page, () => window.gale.conn.status.state !== 'live', null, 30, 'the loss seen');
    srv = await startServer(server, serverArgs, { port });
    await waitFor(page, () => window.gale.sceneWelcome !== window.firstWelcome && window.gale.ready && window.gale.conn.status.state === 'live', null, 120, 'the scene again');
    const frames = await page.evaluate(() => window.gale.conn.stats.frames);
    await waitFor(page, (k) => window.gale.conn.stats.frames >= k + 3, frames, 60, 'three frames after the reconnection');
    s = await state(page);
    assert.deepEqual(s.held, nearest, 'the same trees held');
    assert.equal(s.lod.trees_per_snapshot, HOLD, 'the stream of the trees held alone again');
    assert.deepEqual(s.lod.view, first);
    assert.equal(s.lod.views_sent, 1, 'no view sent anew: the hello carried it');
    assert.equal(said.length, 1, 'said once');
    assert.equal(s.decodeErrors, 0);
    assert.deepEqual(s.errors, []);
    // (the browser logs each refused connection while the server is away)
    assert.deepEqual(ctx.errors.filter((e) => !/WebSocket connection to .* failed/.test(e)), []);
    console.log(JSON.stringify({ ok: true, trees: n, held: HOLD, radius_m: s.lod.reduced.radius_m, view: s.lod.view }));
} finally {
    await ctx.close();
    await srv.stop();
}
