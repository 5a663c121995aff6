// A browser tile and a native tile swap-locked in one wall group (configs/walls/flat-2x2.json,
// four palms of tests/data/clientnet_scene.json, a real gale-server on 127.0.0.1): the
// native gale-client tile c0r0 starts the group (--swap-lock, 3 Hz, 400 ms budget, which
// SwiftShader keeps up with on a loaded machine), the browser's tile c1r0 joins it.
// Seen from outside, on the server's clock (the native frame log's CLOCK_MONOTONIC is the
// server's; the page's times go through its ping/pong clock):
// - locked: the frames both presented carry one numbering and show one server instant, and
//   the server's swaps close with both tiles in (/metrics gale_wall_swaps_complete_total);
// - the group waits for the slower tile: while the page holds each report (wall_drawn) until
//   100 ms after its frame's instant, the native tile presents each such frame no earlier
//   than that report (and where the browser drew late by itself, likewise);
// - a tile that stalls (the page frozen; gale-client stopped with SIGSTOP) or leaves (the
//   page closed) does not stop the other, which keeps presenting, each frame at most the
//   budget after its instant (PROTOCOL.md "Wall groups");
// and prints how far apart the two presented the frames they share (median, p95).
// Counts, not rates: the lower bounds hold on a loaded machine.
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import { readFileSync, mkdirSync, rmSync } from 'node:fs';
import path from 'node:path';
import { args, startServer, startBrowser, waitFor, readMetric, until } from './harness.mjs';

const [server, work, config, client, wallFile] = args('usage: node test_web_wall_lock.mjs GALE_SERVER WORK_DIR SCENE.json GALE_CLIENT WALL.json');
mkdirSync(work, { recursive: true });
const RATE_HZ = 3, BUDGET_MS = 400;
const frameLog = path.join(work, 'native-c0r0.frames');
rmSync(frameLog, { force: true });
const srv = await startServer(server, ['--cache', path.join(work, '..', 'cache'), '--config', config]);
const metric = (name) => readMetric(srv.url, name);
const sleep = (s) => new Promise((r) => setTimeout(r, s * 1000));
const pct = (a, p) => {
    const s = [...a].sort((x, y) => x - y);
    return s.length ? s[Math.min(s.length - 1, Math.floor(p * (s.length - 1) + 0.5))] : null;
};

// gale-client's frame log: mono_us (at its swap) server_us_shown frame
const nativeFrames = () => readFileSync(frameLog, 'utf8').trim().split('\n').filter(Boolean).map((l) => l.split(' ').map(Number));
let nlog = '';
const native = spawn(client, ['--url', `ws://127.0.0.1:${srv.port}`, '--role', 'wall-tile', '--wall', wallFile, '--tile', 'c0r0',
    '--headless', '--frames', '1000000', '--size', '96x54', '--wait', '120', '--cache', path.join(work, 'native-cache'),
    '--swap-lock', '--rate', String(RATE_HZ), '--budget', String(BUDGET_MS), '--frame-log', frameLog], { stdio: ['ignore', 'ignore', 'pipe'] });
native.stderr.on('data', (d) => { nlog += d; });
const nativeExit = new Promise((res) => native.on('exit', (c, sig) => res(sig || c)));
const ctx = await startBrowser(work, { width: 160, height: 90 });
const out = {};
try {
    await until(() => /wall flat-2x2: joined/.test(nlog), 120, `the native tile joining (its log:\n${nlog})`);
    const tile = await ctx.newPage();
    await tile.goto(`${srv.url}/wall?file=${path.basename(wallFile, '.json')}&tile=c1r0`);
    await waitFor(tile, () => window.gale && window.gale.wallGroup && window.gale.wallGroup.frames >= 20, null, 120, 'browser tile presenting in its group');
    assert.equal(await metric('gale_wall_tiles'), 2);
    const page = () => tile.evaluate(() => {
        const g = window.gale.wallGroup;
        const b = window.gale.clock.samples.reduce((a, s) => (a && a.rtt < s.rtt ? a : s), null);
        return { frames: g.frames, frame: g.frame, drawn: g.drawn, reports: g.reports, swapTimeouts: g.swapTimeouts, skipped: g.skipped,
            log: g.log, swaps: g.swaps, rtt_ms: b ? b.rtt * 1e3 : null, errors: window.gale.errors, decode: window.gale.conn.stats.errors };
    });

    // locked: run a while, then compare the two tiles' presented frames
    const complete0 = await metric('gale_wall_swaps_complete_total');
    await sleep(6);
    const complete1 = await metric('gale_wall_swaps_complete_total');
    const b = await page();
    assert.equal(b.decode, 0);
    assert.deepEqual(b.errors, []);
    assert.ok(b.reports >= 20, `the browser tile reported ${b.reports} frames drawn (wall_drawn)`);
    const nat = new Map(nativeFrames().map(([mono, shown, frame]) => [frame, { mono, shown }]));
    const swapOf = new Map(b.swaps.map(([frame, drawn, members, at]) => [frame, { drawn, members, at }]));
    const delay_us = 100000; // gale-client's --delay, the group's
    // a tile waits for the others' reports until the budget after its frame's instant; a
    // report made later than MARGIN_MS before that may reach it after it presented alone
    // (the report to the server, wall_swap back to gale-client, on a loaded machine)
    const MARGIN_MS = 150;
    const mustWait = (due_us, reported_us) => reported_us <= due_us + (BUDGET_MS - MARGIN_MS) * 1e3;
    let shared = 0, waited = 0, sameInstant = 0;
    const apart = [], nativeLate = [], browserLate = [];
    const tol_us = Math.max(2000, 0.5 * b.rtt_ms * 1e3); // the page's clock estimate
    for (const [frame, due, drawn, presented] of b.log) {
        assert.ok(presented >= due - tol_us, `the browser tile presented frame ${frame} ${(due - presented) / 1e3} ms before its instant`);
        const n = nat.get(frame);
        if (!n) continue;
        shared++;
        sameInstant += n.shown === due - delay_us;
        apart.push((presented - n.mono) / 1e3);
        nativeLate.push((n.mono - due) / 1e3);
        browserLate.push((presented - due) / 1e3);
        const s = swapOf.get(frame);
        if (s && s.drawn === 2 && drawn > due && mustWait(due, drawn)) {
            // the browser was the slower: the native tile had to wait for its report
            waited++;
            assert.ok(n.mono >= drawn - tol_us, `frame ${frame}: the native tile presented at ${n.mono} µs, before the browser reported it drawn at ${drawn} µs (± ${tol_us} µs): the group did not wait for the slower tile`);
        }
    }
    out.locked = { browser: { frames: b.frames, drawn: b.drawn, reports: b.reports, swap_timeouts: b.swapTimeouts, skipped: b.skipped, clock_rtt_ms: b.rtt_ms },
        shared_frames: shared, same_instant: sameInstant, waited_for_browser: waited, complete_swaps: complete1 - complete0,
        browser_minus_native_ms: { median: pct(apart, 0.5), p95: pct(apart.map(Math.abs), 0.95) },
        native_after_instant_ms: { median: pct(nativeLate, 0.5), p95: pct(nativeLate, 0.95) },
        browser_after_instant_ms: { median: pct(browserLate, 0.5), p95: pct(browserLate, 0.95) } };
    console.error(JSON.stringify(out.locked));
    assert.ok(shared >= 8, `the two tiles presented ${shared} frames in common (< 8)`);
    assert.equal(sameInstant, shared, 'every frame both presented shows one server instant');
    assert.ok(complete1 - complete0 >= 6, `${complete1 - complete0} swaps closed with both tiles in (< 6 of about 18)`);

    // the browser the slower tile: for a while the page holds each wall_drawn until
    // LAG_MS after its frame's instant (well within the budget), as a tile drawing late
    // would; every swap closes only with both tiles in, so the native tile presents each
    // such frame (reported in time, mustWait) no earlier than the browser's report
    const LAG_MS = 100;
    await tile.evaluate((lag_ms) => {
        const app = window.gale, g = app.wallGroup, send = app.conn.send.bind(app.conn);
        window.lateReports = [];
        app.conn.send = (m) => {
            if (m.type !== 'wall_drawn' || !g.held || g.held.frame !== m.frame) return send(m);
            const due_s = g.held.due_s;
            const now_s = () => app.clock.serverTime(performance.now() * 1e-3);
            setTimeout(() => {
                const at_s = now_s();
                if (send(m)) window.lateReports.push([m.frame, Math.round(due_s * 1e6), Math.round(at_s * 1e6)]);
            }, Math.max(0, (due_s + lag_ms * 1e-3 - now_s()) * 1e3));
            return true;
        };
    }, LAG_MS);
    const completeSlow0 = await metric('gale_wall_swaps_complete_total');
    await sleep(5);
    const late = await tile.evaluate(() => { const r = window.lateReports; delete window.gale.conn.send; return r; });
    const completeSlow1 = await metric('gale_wall_swaps_complete_total');
    const natSlow = new Map(nativeFrames().map(([mono, , frame]) => [frame, mono]));
    const heldBack = [];
    for (const [frame, due, sent] of late) {
        const mono = natSlow.get(frame);
        if (mono === undefined || !mustWait(due, sent)) continue;
        assert.ok(mono >= sent - tol_us, `frame ${frame}: the native tile presented at ${mono} µs, before the browser reported it drawn at ${sent} µs (± ${tol_us} µs): the group did not wait for the slower tile`);
        heldBack.push((mono - due) / 1e3);
    }
    out.browser_slower = { lag_ms: LAG_MS, late_reports: late.length, reported_in_time_and_presented: heldBack.length, complete_swaps: completeSlow1 - completeSlow0,
        native_after_instant_ms: { min: Math.min(...heldBack), median: pct(heldBack, 0.5) } };
    console.error(JSON.stringify(out.browser_slower));
    assert.ok(heldBack.length >= 5, `the native tile presented ${heldBack.length} of the ${late.length} frames the browser reported late (< 5)`);
    assert.ok(completeSlow1 - completeSlow0 >= 5, `${completeSlow1 - completeSlow0} swaps closed with both tiles in while the browser was the slower (< 5 of about 15)`);
    assert.ok(pct(heldBack, 0.5) >= LAG_MS - 1, `the native tile presented the frames the browser held back a median ${pct(heldBack, 0.5)} ms after their instant (< ${LAG_MS} ms)`);

    // the browser tile stalls (its page frozen, still in the group): the native one goes on
    const stall = async (what, stop, go, count) => {
        const before = await count();
        const t0 = Date.now();
        await stop();
        await sleep(3.5);
        const during = (await count()) - before;
        await go();
        return { what, frames_in_3_5_s: during, ms: Date.now() - t0 };
    };
    const nativeCount = async () => nativeFrames().length;
    const browserCount = () => tile.evaluate(() => window.gale.wallGroup.frames);
    const leftOut0 = await metric('gale_wall_left_out_total');
    out.browser_stalled = await stall('browser frozen', () => tile.evaluate(() => { window.gale.frozen = true; }),
        () => tile.evaluate(() => { window.gale.frozen = false; }), nativeCount);
    out.browser_stalled.left_out = (await metric('gale_wall_left_out_total')) - leftOut0;
    assert.ok(out.browser_stalled.frames_in_3_5_s >= 3, `the native tile presented ${out.browser_stalled.frames_in_3_5_s} frames while the browser tile was frozen`);
    assert.ok(out.browser_stalled.left_out >= 1, 'the frozen browser tile was never left out of a swap');
    await waitFor(tile, (n) => window.gale.wallGroup.frames > n + 5, await browserCount(), 60, 'browser tile presenting again');

    // the native tile stalls: the browser one goes on, each frame the budget after it was
    // drawn (no wall_swap comes for it)
    const b0 = await page();
    out.native_stalled = await stall('gale-client stopped', () => native.kill('SIGSTOP'), () => native.kill('SIGCONT'), browserCount);
    const b1 = await page();
    out.native_stalled.browser_swap_timeouts = b1.swapTimeouts - b0.swapTimeouts;
    assert.ok(out.native_stalled.frames_in_3_5_s >= 3, `the browser tile presented ${out.native_stalled.frames_in_3_5_s} frames while gale-client was stopped`);
    assert.ok(out.native_stalled.browser_swap_timeouts >= 2, `${out.native_stalled.browser_swap_timeouts} browser frames presented on the budget while gale-client was stopped`);
    // (the server closes such a frame's swap when the browser reports the next one)
    const swapAt = new Map(b1.swaps.map(([frame, , , at]) => [frame, at]));
    const waits = b1.log.filter(([frame, , , presented]) => frame > b0.frame && !(swapAt.get(frame) <= presented)).map(([, due, drawn, presented]) => (presented - Math.max(due, drawn)) / 1e3);
    out.native_stalled.browser_wait_ms = { n: waits.length, min: Math.min(...waits), median: pct(waits, 0.5) };
    assert.ok(waits.length >= 2 && Math.min(...waits) >= BUDGET_MS - 1, `browser frames without a swap waited ${JSON.stringify(waits)} ms (expected the ${BUDGET_MS} ms budget)`);

    // the browser tile leaves: the native one goes on alone
    await tile.close();
    await until(async () => (await metric('gale_wall_tiles')) === 1, 30, 'the group down to the native tile');
    out.browser_left = await stall('browser left', async () => {}, async () => {}, nativeCount);
    assert.ok(out.browser_left.frames_in_3_5_s >= 3, `the native tile presented ${out.browser_left.frames_in_3_5_s} frames after the browser tile left`);
    assert.deepEqual(ctx.errors, []);
    console.log(JSON.stringify({ ...out, ok: true }));
} finally {
    native.kill('SIGCONT');
    native.kill('SIGTERM');
    const rc = await Promise.race([nativeExit, sleep(10).then(() => 'timeout')]);
    if (rc === 'timeout') native.kill('SIGKILL');
    out.native_exit = (nlog.match(/wall frames presented .*/) || [''])[0];
    console.error(out.native_exit);
    await ctx.close();
    await srv.stop();
}
