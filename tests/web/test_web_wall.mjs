// A browser wall tile beside native ones in one wall group (configs/walls/flat-2x2.json,
// the clearing scene): the browser's tile c1r0 joins, a kiosk sets the group's camera, a
// native gale-client tile c0r0 joins (the group counts 2 in /metrics), then a native c1r0
// draws the same tile: the browser's picture of c1r0 (Kooima off-axis from the same file)
// is compared with the native one: mean difference, pixels off by more than 32 levels, and
// 8-pixel blocks whose means are off by more than 16 (leaves flutter with each client's own
// clock, so single pixels of foliage differ; the blocks hold the picture's layout).
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import { writeFileSync, readFileSync, mkdirSync } from 'node:fs';
import path from 'node:path';
import { args, startServer, startBrowser, waitFor, readMetric } from './harness.mjs';

const [server, work, config, client, wallFile] = args('usage: node test_web_wall.mjs GALE_SERVER WORK_DIR SCENE.json GALE_CLIENT WALL.json');
mkdirSync(work, { recursive: true });
const TOKEN = 'web-wall-test-5c1e';
const tokenFile = path.join(work, 'token');
writeFileSync(tokenFile, `${TOKEN}\n`, { mode: 0o600 });
const srv = await startServer(server, ['--cache', path.join(work, '..', 'cache'), '--config', config, '--kiosk-token-file', tokenFile]);
const metric = (name) => readMetric(srv.url, name);
const W = 480, H = 270;
const native = (tile, png, frames) => new Promise((resolve, reject) => {
    const p = spawn(client, ['--url', `ws://127.0.0.1:${srv.port}`, '--role', 'wall-tile', '--wall', wallFile, '--tile', tile,
        '--headless', '--frames', String(frames), '--size', `${W}x${H}`, '--screenshot', png], { stdio: ['ignore', 'ignore', 'pipe'] });
    let log = '';
    p.stderr.on('data', (d) => { log += d; });
    const timer = setTimeout(() => p.kill('SIGKILL'), 200000);
    p.on('exit', (c) => { clearTimeout(timer); return c === 0 ? resolve(log) : reject(new Error(`gale-client ${tile} exited ${c}:\n${log}`)); });
});
const ctx = await startBrowser(work, { width: W, height: H });
const out = {};
try {
    const tile = await ctx.newPage();
    await tile.goto(`${srv.url}/wall?file=${path.basename(wallFile, '.json')}&tile=c1r0`);
    await waitFor(tile, () => window.gale && window.gale.wallGroup && window.gale.wallGroup.frames >= 3 && window.gale.framesDrawn >= 3, null, 120, 'browser tile drawing in its group');
    assert.equal(await metric('gale_wall_tiles'), 1);
    // the group's camera from a kiosk: every tile takes it, a later joiner too
    const kiosk = await ctx.newPage();
    await kiosk.goto(`${srv.url}/kiosk#token=${TOKEN}`);
    await waitFor(kiosk, () => window.gale && window.gale.conn && window.gale.conn.status.state === 'live', null, 60, 'kiosk live');
    await kiosk.evaluate(() => window.gale.conn.send({ type: 'wall_camera', wall: 'flat-2x2', target_m: [0, 6, 5], distance_m: 34, yaw_deg: 80, pitch_deg: -12 }));
    await kiosk.close();
    await waitFor(tile, () => window.gale.wallGroup.frames > 10, null, 60, 'browser tile drawing');
    const g = await tile.evaluate(() => ({ ...window.gale.wallGroup, errors: window.gale.errors, decode: window.gale.conn.stats.errors }));
    assert.equal(g.decode, 0);
    assert.deepEqual(g.errors, []);
    out.browser_group = { frames: g.frames, skipped: g.skipped, frame: g.frame };
    // the browser tile holds its last frame (and stays in the group) while the native
    // ones draw: two software renderers on two cores would starve each other
    await tile.evaluate(() => { window.gale.frozen = true; });
    // a native tile beside it: the group holds both while it runs
    const beside = native('c0r0', path.join(work, 'native-c0r0.png'), 20);
    let both = 0;
    for (let i = 0; i < 200 && !both; i++) {
        both = (await metric('gale_wall_tiles')) === 2;
        await new Promise((r) => setTimeout(r, 100));
    }
    out.native_c0r0_log = (await beside).split('\n').filter((l) => /wall/.test(l)).slice(0, 3);
    assert.ok(both, 'the native tile joined the browser tile\'s group');
    // the same tile natively, and the two pictures compared in the page
    await native('c1r0', path.join(work, 'native-c1r0.png'), 10);
    const drawn = await tile.evaluate(() => { window.gale.frozen = false; return window.gale.wallGroup.frames; });
    await waitFor(tile, (n) => window.gale.wallGroup.frames > n + 3, drawn, 60, 'browser tile drawing again');
    await tile.screenshot({ path: path.join(work, 'browser-c1r0.png') });
    const png = readFileSync(path.join(work, 'native-c1r0.png')).toString('base64');
    const cmp = await tile.evaluate(async (b64) => {
        const still = window.gale.still(true); // rows bottom first
        const img = new Image();
        img.src = `data:image/png;base64,${b64}`;
        await img.decode();
        const c = document.createElement('canvas');
        c.width = still.w;
        c.height = still.h;
        const x = c.getContext('2d');
        x.drawImage(img, 0, 0, still.w, still.h);
        const nat = x.getImageData(0, 0, still.w, still.h).data; // rows top first
        const raw = atob(still.pixels);
        let sum = 0, big = 0;
        for (let y = 0; y < still.h; y++) for (let i = 0; i < still.w; i++) {
            const a = 4 * ((still.h - 1 - y) * still.w + i), b = 4 * (y * still.w + i);
            let d = 0;
            for (let k = 0; k < 3; k++) d += Math.abs(raw.charCodeAt(a + k) - nat[b + k]);
            sum += d / 3;
            big += d / 3 > 32;
        }
        // 8 × 8 blocks: a leaf that flutters to a neighbouring pixel moves no block mean much
        const B = 8, bw = Math.floor(still.w / B), bh = Math.floor(still.h / B);
        let blocks = 0, bad = 0;
        for (let by = 0; by < bh; by++) for (let bx = 0; bx < bw; bx++) {
            let d = 0;
            for (let k = 0; k < 3; k++) {
                let ma = 0, mb = 0;
                for (let y = by * B; y < by * B + B; y++) for (let i = bx * B; i < bx * B + B; i++) {
                    ma += raw.charCodeAt(4 * ((still.h - 1 - y) * still.w + i) + k);
                    mb += nat[4 * (y * still.w + i) + k];
                }
                d += Math.abs(ma - mb) / (B * B) / 3;
            }
            blocks++;
            bad += d > 16;
        }
        const n = still.w * still.h;
        return { mean_abs_diff: sum / n, frac_over_32: big / n, blocks_8px_over_16: bad / blocks, native_size: [img.width, img.height] };
    }, png);
    out.compare_c1r0 = cmp;
    assert.deepEqual(cmp.native_size, [W, H]);
    assert.ok(cmp.blocks_8px_over_16 < 0.15, `browser and native c1r0 differ in ${(100 * cmp.blocks_8px_over_16).toFixed(1)} % of 8-pixel blocks (> 15 %): ${JSON.stringify(cmp)}`);
    assert.ok(cmp.frac_over_32 < 0.3, `browser and native c1r0 differ in ${(100 * cmp.frac_over_32).toFixed(1)} % of pixels (> 30 %)`);
    assert.ok(cmp.mean_abs_diff < 30, `mean difference ${cmp.mean_abs_diff.toFixed(1)} levels (> 30)`);
    console.log(JSON.stringify({ ...out, ok: true }));
} finally {
    await ctx.close();
    await srv.stop();
}
