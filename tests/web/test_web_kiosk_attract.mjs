// The kiosk page's attract mode against a real gale-server (web/attract.js): with
// ?attract=16, after the visitor set the dial (gale_wind_dial 1 in /metrics) and left it
// alone, the page releases the dial (gale_wind_dial 0, the scenario's wind back), hides its
// panel, says how to wake it and tours the cameras (the camera moves); a touch wakes it,
// restores the kiosk's camera and panel and is not taken as a control (the dial stays
// released); touches keep it awake. Before the tour a warning counts down (half the idle
// time here, 20 s at the default 90): a touch takes it away, keeps the visitor's dial and
// sends nothing. A browser asking for less motion (prefers-reduced-motion, emulated) gets a
// tour that turns at most half as fast (0.2 of it: web/attract.js).
import assert from 'node:assert/strict';
import { writeFileSync, mkdirSync } from 'node:fs';
import path from 'node:path';
import { args, startServer, startBrowser, waitFor, readMetric, until } from './harness.mjs';
import { dialTo } from './kiosk_touch.mjs';

const [server, work, config] = args('usage: node test_web_kiosk_attract.mjs GALE_SERVER WORK_DIR SCENE.json');
const TOKEN = 'web-attract-test-91c2';
// long beside the time one touch takes on a loaded machine (a fill waits for the page's
// animation frames), so a visitor who keeps touching never sees the attract mode
const IDLE_S = 16;
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
    const sent = [];
    page.on('websocket', (ws) => ws.on('framesent', (f) => { if (typeof f.payload === 'string') sent.push(JSON.parse(f.payload)); }));
    await page.goto(`${srv.url}/kiosk?attract=${IDLE_S}#token=${TOKEN}`);
    await waitFor(page, () => window.gale && window.gale.framesDrawn >= 3 && window.gale.weather, null, 120, 'kiosk live and drawn');
    // (a flag the page keeps if the warning ever shows while the visitor is busy)
    await page.evaluate(() => new MutationObserver(() => { if (!document.getElementById('idle').hidden) window.warnedAt = Date.now(); })
        .observe(document.getElementById('idle'), { attributes: true }));
    const own = await camOf(page);
    // the visitor keeps touching the dial for longer than the idle time: no attract mode
    const t0 = Date.now();
    let left = t0, gap_ms = 0;
    for (let v = 20; Date.now() - t0 < (IDLE_S + 2) * 1000; v = v === 20 ? 21 : 20) {
        await dialTo(page, v, { steps: 2, ms: 100 });
        gap_ms = Math.max(gap_ms, Date.now() - left);
        left = Date.now();
        await new Promise((r) => setTimeout(r, 500));
    }
    out.longest_between_touches_ms = gap_ms;
    assert.equal(await page.evaluate(() => document.getElementById('attract').hidden), true, 'attract mode while the visitor was busy');
    assert.equal(await metric('gale_wind_dial'), 1, 'the dial holds the wind while the visitor is there');
    const warnedBusy = await page.evaluate(() => window.warnedAt || 0);
    assert.ok(warnedBusy === 0 || warnedBusy > left, 'the warning showed while the visitor was busy');
    // the warning: shown with the seconds left, half the idle time before the tour
    await waitFor(page, () => !document.getElementById('idle').hidden, null, IDLE_S + 10, 'the warning before the tour');
    out.warned_after_s = (Date.now() - left) / 1000;
    const warning = await page.evaluate(() => ({ text: document.getElementById('idle').textContent, attract: !document.getElementById('attract').hidden }));
    const secs = Number((warning.text.match(/(\d+) s\b/) || [])[1]);
    assert.ok(secs >= 1 && secs <= IDLE_S / 2, `the warning counts the seconds left (at most ${IDLE_S / 2}): ${warning.text}`);
    assert.ok(!warning.attract, 'the warning comes before the tour, not with it');
    out.warning = warning.text.replace(/\s+/g, ' ').trim();
    await page.screenshot({ path: path.join(work, 'warning.png') });
    // a touch keeps the controls: the warning goes, the dial holds, nothing is sent
    const sent0 = sent.length;
    await page.mouse.click(400, 300);
    await waitFor(page, () => document.getElementById('idle').hidden, null, 10, 'the warning dismissed by a touch');
    left = Date.now();
    await new Promise((r) => setTimeout(r, 1000));
    assert.equal(await metric('gale_wind_dial'), 1, 'the touch on the warning kept the dial');
    assert.deepEqual(sent.slice(sent0).filter((m) => m.type !== 'ping'), [], 'the touch on the warning is not a control');
    assert.equal(await page.evaluate(() => document.getElementById('attract').hidden), true, 'no tour after the touch');
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
    // less motion asked for: the next tour turns slower
    await page.emulateMedia({ reducedMotion: 'reduce' });
    await waitFor(page, () => !document.getElementById('attract').hidden, null, IDLE_S + 20, 'the tour again with less motion');
    const slow0 = await camOf(page), slow0_ms = Date.now();
    await new Promise((r) => setTimeout(r, 1500));
    const drawn2 = await page.evaluate(() => window.gale.framesDrawn);
    await waitFor(page, (d) => window.gale.framesDrawn >= d + 2, drawn2, 60, 'frames drawn on the slow tour');
    const slow1 = await camOf(page);
    out.reduced_tour_yaw_rad_per_s = (slow1.yaw - slow0.yaw) / ((Date.now() - slow0_ms) / 1000);
    assert.ok(out.reduced_tour_yaw_rad_per_s > 0 && out.reduced_tour_yaw_rad_per_s < 0.5 * out.tour_yaw_rad_per_s,
        `tour turns ${out.reduced_tour_yaw_rad_per_s} rad/s with less motion, ${out.tour_yaw_rad_per_s} without`);
    assert.deepEqual(ctx.errors, []);
    console.log(JSON.stringify({ ...out, attract_line: shown.text, ok: true }));
} finally {
    await ctx.close();
    await srv.stop();
}
