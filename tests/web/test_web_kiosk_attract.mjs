// The kiosk page's attract mode against a real gale-server (web/attract.js): with
// ?attract=8, after the visitor set the dial (gale_wind_dial 1 in /metrics) and left it
// alone, the page releases the dial (gale_wind_dial 0, the scenario's wind back), hides its
// panel, says how to wake it and tours the cameras (the camera moves); a touch wakes it,
// restores the kiosk's camera and panel and is not taken as a control (the dial stays
// released); touches keep it awake.
import assert from 'node:assert/strict';
import { writeFileSync, mkdirSync } from 'node:fs';
import path from 'node:path';
import { args, startServer, startBrowser, waitFor, readMetric, until } from './harness.mjs';

const [server, work, config] = args('usage: node test_web_kiosk_attract.mjs GALE_SERVER WORK_DIR SCENE.json');
const TOKEN = 'web-attract-test-91c2';
// long beside the time one touch takes on a loaded machine (a fill waits for the page's
// animation frames), so a visitor who keeps touching never sees the attract mode
const IDLE_S = 8;
mkdirSync(work, { recursive: true });
const tokenFile = path.join(work, 'token');
writeFileSync(tokenFile, `${TOKEN}\n`, { mode: 0o600 });
const srv = await startServer(server, ['--cache', path.join(work, '..', 'cache'), '--config', config, '--kiosk-token-file', tokenFile]);
const metric = (name) => readMetric(srv.url, name);
const camOf = (page) => page.evaluate(() => { const c = window.gale.cam; return { target: [...c.target], distance: c.distance, yaw: c.yaw, pitch: c.pitch }; });
const ctx = await startBrowser(work, { width: 800, height: 600 });
const out = {};
try {
    const page = await ctx.newPage();
    await page.goto(`${srv.url}/kiosk?attract=${IDLE_S}#token=${TOKEN}`);
    await waitFor(page, () => window.gale && window.gale.framesDrawn >= 3 && window.gale.weather, null, 120, 'kiosk live and drawn');
    const own = await camOf(page);
    // the visitor keeps touching the dial for longer than the idle time: no attract mode
    const t0 = Date.now();
    let left = t0, gap_ms = 0;
    for (let v = 20; Date.now() - t0 < (IDLE_S + 2) * 1000; v = v === 20 ? 21 : 20) {
        await page.locator('#dial').fill(String(v));
        gap_ms = Math.max(gap_ms, Date.now() - left);
        left = Date.now();
        await new Promise((r) => setTimeout(r, 500));
    }
    out.longest_between_touches_ms = gap_ms;
    assert.equal(await page.evaluate(() => document.getElementById('attract').hidden), true, 'attract mode while the visitor was busy');
    assert.equal(await metric('gale_wind_dial'), 1, 'the dial holds the wind while the visitor is there');
    // then nobody: the dial released, the panel away, the tour on
    await until(async () => (await metric('gale_wind_dial')) === 0, IDLE_S + 20, 'dial released after the idle time');
    out.released_after_s = (Date.now() - left) / 1000;
    assert.ok(out.released_after_s >= IDLE_S - 0.2, `released ${out.released_after_s} s after the last touch, idle time ${IDLE_S} s`);
    const shown = await page.evaluate(() => ({ msg: !document.getElementById('attract').hidden, panel: !document.getElementById('panel').hidden,
        text: document.getElementById('attract').textContent }));
    assert.ok(shown.msg && !shown.panel, `attract mode shows its line, not the panel: ${JSON.stringify(shown)}`);
    // the camera moves on the page's animation frames, which come seconds apart on a
    // loaded machine: the second reading waits for frames drawn after the interval
    const tour0 = await camOf(page), tour0_ms = Date.now();
    await new Promise((r) => setTimeout(r, 1500));
    const drawn = await page.evaluate(() => window.gale.framesDrawn);
    await waitFor(page, (d) => window.gale.framesDrawn >= d + 2, drawn, 60, 'frames drawn on the tour');
    const tour1 = await camOf(page);
    out.tour_yaw_rad_per_s = (tour1.yaw - tour0.yaw) / ((Date.now() - tour0_ms) / 1000);
    assert.notDeepEqual(tour0, own, 'the tour moved the camera from the kiosk\'s');
    assert.ok(tour1.yaw > tour0.yaw, 'the tour turns');
    await page.screenshot({ path: path.join(work, 'attract.png') });
    // a touch wakes it: the kiosk's camera and panel back, the dial untouched
    await page.mouse.click(200, 400);
    await waitFor(page, () => document.getElementById('attract').hidden && !document.getElementById('panel').hidden, null, 10, 'woken by a touch');
    assert.deepEqual(await camOf(page), own, 'the kiosk\'s own camera back');
    await new Promise((r) => setTimeout(r, 1000));
    assert.equal(await metric('gale_wind_dial'), 0, 'the waking touch is not a control');
    await page.screenshot({ path: path.join(work, 'woken.png') });
    assert.deepEqual(ctx.errors, []);
    console.log(JSON.stringify({ ...out, attract_line: shown.text, ok: true }));
} finally {
    await ctx.close();
    await srv.stop();
}
