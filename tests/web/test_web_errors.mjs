// What the page says and does when things go wrong, each against a real gale-server:
// a server restart (1001, then refused connections: the page keeps retrying and draws
// again on the same port), a server it cannot reach, a protocol version the server
// refuses (the page made to say protocol 2: the server's own 4003), an asset whose bytes
// do not match the welcome's hash, and a browser without WebGL2 (chromium --disable-webgl).
import assert from 'node:assert/strict';
import path from 'node:path';
import { args, startServer, startBrowser, waitFor } from './harness.mjs';

const [server, work, config] = args('usage: node test_web_errors.mjs GALE_SERVER WORK_DIR SCENE.json');
const cache = path.join(work, '..', 'cache');
let srv = await startServer(server, ['--cache', cache, '--config', config]);
const port = srv.port;
const ctx = await startBrowser(work, { width: 480, height: 360 });
const said = {};
const status = (p) => p.evaluate(() => (document.getElementById('status').hidden ? '' : document.getElementById('status').textContent));
const saysSoon = (p, re, s, what) => waitFor(p, ([src, flags]) => {
    const el = document.getElementById('status');
    return !el.hidden && new RegExp(src, flags).test(el.textContent);
}, [re.source, re.flags], s, what);
try {
    // restart: stopped (1001), away a while, started again on the same port
    const page = await ctx.newPage();
    await page.goto(`${srv.url}/`);
    await waitFor(page, () => window.gale && window.gale.framesDrawn >= 2, null, 120, 'viewer drawing');
    await srv.stop('SIGTERM');
    await saysSoon(page, /restarting|Lost the connection/, 20, 'restart said');
    said.restart = await status(page);
    await new Promise((r) => setTimeout(r, 1500));
    said.away = await status(page);
    assert.match(said.away, /Reconnecting|Retrying/);
    const before = await page.evaluate(() => [window.gale.framesDrawn, window.gale.conn.stats.frames]);
    srv = await startServer(server, ['--cache', cache, '--config', config], { port });
    await waitFor(page, ([d, f]) => window.gale.conn.status.state === 'live' && window.gale.framesDrawn > d + 2 && window.gale.conn.stats.frames > f + 10, before, 60, 'drawing again after the restart');
    assert.equal(await status(page), '', 'the message is gone once live');
    assert.equal(await page.evaluate(() => window.gale.conn.stats.errors), 0);
    await page.close();

    // unreachable: the page's files from the server, its WebSocket to a port nobody serves
    const p2 = await ctx.newPage();
    await p2.route('http://127.0.0.1:9/**', async (route) => {
        const u = new URL(route.request().url());
        const res = await fetch(`${srv.url}${u.pathname}${u.search}`);
        await route.fulfill({ status: res.status, headers: Object.fromEntries(res.headers), body: Buffer.from(await res.arrayBuffer()) });
    });
    await p2.goto('http://127.0.0.1:9/');
    await saysSoon(p2, /Cannot reach the gale server at 127\.0\.0\.1:9/, 30, 'unreachable said');
    said.unreachable = await status(p2);
    await p2.close();

    // version: the page's hello says protocol 2; the real server refuses it (4003)
    const p3 = await ctx.newPage();
    await p3.addInitScript(() => {
        const send = WebSocket.prototype.send;
        WebSocket.prototype.send = function (d) {
            return send.call(this, typeof d === 'string' ? d.replace('"protocol":1', '"protocol":2') : d);
        };
    });
    await p3.goto(`${srv.url}/`);
    await saysSoon(p3, /Version mismatch/, 30, 'version mismatch said');
    said.version = await status(p3);
    assert.match(said.version, /expected 1, got 2/);
    await p3.close();

    // asset hash: one byte of every asset flipped on the way
    const p4 = await ctx.newPage();
    await p4.route('**/assets/**', async (route) => {
        const res = await fetch(route.request().url());
        const body = Buffer.from(await res.arrayBuffer());
        body[body.length - 1] ^= 1;
        await route.fulfill({ status: 200, body, contentType: 'application/octet-stream' });
    });
    await p4.goto(`${srv.url}/`);
    await saysSoon(p4, /Asset hash mismatch/, 60, 'hash mismatch said');
    said.hash = await status(p4);
    assert.equal(await p4.evaluate(() => window.gale.framesDrawn), 0, 'nothing drawn from refused bytes');
    await p4.close();
} finally {
    await ctx.close();
}
// no WebGL2
const ctx2 = await startBrowser(path.join(work, 'nowebgl2'), { width: 480, height: 360, extraArgs: ['--disable-webgl'] });
try {
    const p5 = await ctx2.newPage();
    await p5.goto(`${srv.url}/`);
    await saysSoon(p5, /no WebGL2/, 30, 'WebGL2 missing said');
    said.webgl2 = await status(p5);
    await p5.screenshot({ path: path.join(work, 'no-webgl2.png') });
} finally {
    await ctx2.close();
    await srv.stop();
}
console.log(JSON.stringify({ said, ok: true }));
