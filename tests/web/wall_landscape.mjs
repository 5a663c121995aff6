// The 2 km landscape (configs/scenes/landscape-2km.json, 100,000 trees) on a 2 × 2 wall
// (configs/walls/flat-2x2.json) of one browser tile (c1r0) and three gale-client tiles, in
// one wall group under one camera a kiosk sets: over the town and the south-west pines
// towards the north-east, the far stands as impostors in the upper tiles. Not a ctest test
// (the welcome is 4.3 MB and software GL draws a landscape slowly); deploy/wall-landscape.sh
// runs it.
//
// The server starts on the calm scenario. Calm: the wall at one group frame
// (wall-calm.png: the page's c1r0 beside gale-client's c0r0, c0r1 and c1r1 at their
// bezels' spacing; wall-calm-native.png with gale-client's c1r0), the page's c1r0 against
// gale-client's (comparePictures, as test_web_wall; beside-c1r0-calm.png), then the far
// impostors' motion: gale-client's c1r0 draws consecutive group frames (--screenshot-every
// 1) and the page draws the same instants (still()), both without the storm look (rain
// streaks and fog would move or hide the picture whatever the trees do); the mean absolute
// frame-to-frame difference over the tile's far region (the pixels whose ray meets the
// ground more than FAR_M away: every tree there is an impostor; motion-WHAT-pair.png,
// motion-WHAT-changed.png). Then a kiosk (gale-ctl) dials Category 3 and, once the storm
// has stripped the crowns it strips, the motion is measured again; then Category 4 and
// the wall again (wall-storm.png). Prints one JSON object, with the load average at each
// phase and the trees the server felled against those the page holds as fallen.
import { spawn } from 'node:child_process';
import { writeFileSync, readFileSync, mkdirSync, readdirSync, unlinkSync } from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { args, startServer, startBrowser, waitFor, readMetric, until, comparePictures, sendAsKiosk, decodePng } from './harness.mjs';
import { tileCorners } from '../../web/wall_view.js';

const USAGE = 'usage: node wall_landscape.mjs GALE_SERVER GALE_CLIENT GALE_CTL OUT_DIR TOKEN_FILE [WxH]';
const [server, client, ctl, work, tokenFile, size = '640x360'] = args(USAGE);
if (!tokenFile) {
    console.error(USAGE);
    process.exit(2);
}
const [W, H] = size.split('x').map(Number);
const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..', '..');
const SCENE = path.join(ROOT, 'configs/scenes/landscape-2km.json');
const CALM = path.join(ROOT, 'configs/scenarios/calm.json');
const WALL_FILE = path.join(ROOT, 'configs/walls/flat-2x2.json');
const WALL = JSON.parse(readFileSync(WALL_FILE, 'utf8'));
const TILE_B = 'c1r0'; // the browser's tile
const NATIVE_TILES = ['c0r0', 'c0r1', 'c1r1'];
// over the town and the south-west pines towards the north-east: the eye 90 m up, 390 m
// short of the target; the upper tiles see only impostors (ground 390 m and more away),
// the lower ones the pines near as posed trees, the houses, and the oak and palm stands
const CAMERA = { target_m: [60, 60, 0], distance_m: 400, yaw_deg: 45, pitch_deg: -13 };
const RATE_HZ = 2; // the group's frames: 0.5 s apart, which gale-client keeps up with here
// each frame shows its instant less this: more than a period, so that a tile that draws a
// frame a period ahead of its instant has the stream's snapshots of that instant by then
const DELAY_MS = 800;
const CAT3_MS = 53.5; // the middle of Category 3 (configs/scenarios/cat3.json's wind)
const CAT4_MS = 64; // the middle of Category 4
// past THIN's reach (250 m) and its hysteresis (8 %): only impostors
const FAR_M = 300;
// snapshots the page holds while gale-client draws (5 s at 30 a second; 6.4 MB each at
// 100,000 trees × 32 modes, twice: the jitter buffer and the GPU's ring, which SwiftShader
// refuses at 240)
const HOLD = 150;
const WALL_FRAMES = 4; // frames each wall tile draws at least
// gale-client's frames for the motion; of the last MOTION_LAST, the pairs one group frame
// apart (a loaded machine skips some) are measured, at most MOTION_PAIRS of them
const MOTION_FRAMES = 8;
const MOTION_LAST = 6;
const MOTION_PAIRS = 4;

mkdirSync(work, { recursive: true });
const TOKEN = readFileSync(tokenFile, 'utf8').split('\n')[0];
const loadavg = () => readFileSync('/proc/loadavg', 'utf8').split(' ').slice(0, 3).map(Number);
const t0 = Date.now();
const say = (s) => console.error(`wall-landscape: ${((Date.now() - t0) / 1000).toFixed(1)} s: ${s}`);
const out = { scene: 'landscape-2km', wall: WALL.name, tile_px: [W, H], camera: CAMERA, rate_hz: RATE_HZ, delay_ms: DELAY_MS, far_m: FAR_M, load_average: { start: loadavg() } };

const srv = await startServer(server, ['--cache', path.join(work, '..', 'cache'), '--config', SCENE, '--scenario', CALM, '--kiosk-token-file', tokenFile]);
const metric = (name) => readMetric(srv.url, name);
const url = `ws://127.0.0.1:${srv.port}`;
// a process; { proc, done } where done resolves to its output, or rejects when it exits
// other than 0 (or is still running after timeout_s)
const start = (bin, argv, timeout_s) => {
    const proc = spawn(bin, argv, { stdio: ['ignore', 'pipe', 'pipe'] });
    let log = '';
    proc.stdout.on('data', (d) => { log += d; });
    proc.stderr.on('data', (d) => { log += d; });
    const done = new Promise((resolve, reject) => {
        const timer = setTimeout(() => proc.kill('SIGKILL'), timeout_s * 1000);
        proc.on('exit', (c) => { clearTimeout(timer); return c === 0 ? resolve(log) : reject(new Error(`${path.basename(bin)} ${argv.slice(-6).join(' ')} exited ${c}:\n${log.slice(-3000)}`)); });
    });
    return { proc, done };
};
const kioskCtl = (...cmd) => start(ctl, ['--url', url, '--token-file', tokenFile, '--wait', '60', ...cmd], 120).done;
// gale-client as tile T, writing PNG (its last frame) and PNG's .frames (frame log)
const nativeStart = (tile, png, frames, extra = []) => start(client, ['--url', url, '--wall', WALL_FILE, '--tile', tile, '--headless',
    '--frames', String(frames), '--size', `${W}x${H}`, '--screenshot', png, '--cache', path.join(work, '..', 'cache-client'),
    '--frame-log', png.replace(/\.png$/, '.frames'), ...extra], 600);
const native = (...a) => nativeStart(...a).done;
// --screenshot-every's pictures of PNG: PREFIX-NNNNNN.png
const numbered = (png, frame) => png.replace(/\.png$/, `-${String(frame).padStart(6, '0')}.png`);
const dropNumbered = (png) => {
    const base = path.basename(png, '.png');
    for (const f of readdirSync(path.dirname(png))) if (new RegExp(`^${base}-\\d{6}\\.png$`).test(f)) unlinkSync(path.join(path.dirname(png), f));
};
// a frame log's lines: [mono_us, server_us, frame]
const frameLog = (png) => readFileSync(png.replace(/\.png$/, '.frames'), 'utf8').trim().split('\n').filter((l) => l).map((l) => l.split(' ').map(Number));

const ctx = await startBrowser(work, { width: W, height: H });
try {
    // the browser's tile first: its join sets the group's clock (RATE_HZ, DELAY_MS)
    const tile = await ctx.newPage();
    await tile.goto(`${srv.url}/wall?file=${WALL.name}&tile=${TILE_B}&rate=${RATE_HZ}&delay=${DELAY_MS}`);
    await waitFor(tile, () => window.gale && window.gale.wallGroup && window.gale.wallGroup.frames >= 1, null, 300, 'the browser tile presenting');
    say('browser tile in its group');
    // the kiosk: a WebSocket of its own from a blank page (a kiosk page would load and
    // draw the landscape too); it sets the group's camera and hangs up
    const helper = await ctx.newPage(); // (about:blank: nothing to fetch)
    const setCamera = async () => {
        const r = await sendAsKiosk(helper, url, TOKEN, [{ type: 'wall_camera', wall: WALL.name, ...CAMERA }]);
        if (r.length) throw new Error(`kiosk: ${r.join('; ')}`);
        await waitFor(tile, (t) => { const c = window.gale.camera(); return c && c.target.every((x, k) => Math.abs(x - t[k]) < 1e-3); }, CAMERA.target_m, 120, 'the browser tile taking the kiosk\'s camera');
    };
    await setCamera();
    await waitFor(tile, (n) => window.gale.wallGroup.frames > n, await tile.evaluate(() => window.gale.wallGroup.frames), 300, 'a browser frame under the camera');
    await tile.screenshot({ path: path.join(work, 'browser-c1r0-live.png') });
    out.browser_snapshots_held = await tile.evaluate((n) => window.gale.holdSnapshots(n), HOLD);
    // pin(t): the page takes no snapshot past its newest once that reaches t (and the two
    // after it that the blend of t reads), so that each still() below finds the instants
    // it draws however long the ones before took; it goes on reading the socket. unpin()
    // lets them in again.
    await tile.evaluate(() => {
        const j = window.gale.jitter, insert = j.insert;
        window.galeCut = Infinity;
        j.insert = function (tick, t, q, meta) {
            if (t > window.galeCut) {
                this.stats.late++;
                return 'late';
            }
            return insert.call(this, tick, t, q, meta);
        };
    });
    const pin = async (t_s) => {
        await waitFor(tile, (t) => { const s = window.gale.jitter.snaps; return s.length > 2 && s[s.length - 3].t >= t; }, t_s, 60, `the browser's snapshots past ${t_s} s`);
        return tile.evaluate((t) => {
            const s = window.gale.jitter.snaps;
            window.galeCut = s[s.length - 1].t;
            // the snapshots' spacing about t: 33 ms when the page takes every one
            const near = s.filter((x) => Math.abs(x.t - t) < 3);
            const gaps = near.slice(1).map((x, i) => x.t - near[i].t).sort((a, b) => a - b);
            return { held_s: [s[0].t, s[s.length - 1].t], gap_ms_median: gaps.length ? 1e3 * gaps[gaps.length >> 1] : null, gap_ms_max: gaps.length ? 1e3 * gaps[gaps.length - 1] : null };
        }, t_s);
    };
    const unpin = () => tile.evaluate(() => { window.galeCut = Infinity; });
    // the page takes no snapshot past its newest from now on
    const pinNow = () => tile.evaluate(() => { const s = window.gale.jitter.snaps; window.galeCut = s[s.length - 1].t; });
    const heldNow = () => tile.evaluate(() => { const s = window.gale.jitter.snaps; return { held_s: [s[0].t, s[s.length - 1].t], snapshots: s.length }; });
    // (the page's frames would starve gale-client's on two cores; it still takes the stream)
    await tile.evaluate(() => { window.gale.frozen = true; });

    // The browser's picture of server instant at.shown_s at shader time at.t_s, in the
    // page ({ w, h, rgba: RGBA rows top first, base64 }); { held_s } when its jitter buffer
    // does not hold the instant. showTrees false: the ground and sky alone.
    const still = (at, showTrees = true) => tile.evaluate(([at, showTrees]) => {
        const snaps = window.gale.jitter.snaps;
        const held = snaps.length > 1 && at.shown_s >= snaps[0].t && at.shown_s <= snaps[snaps.length - 1].t;
        if (!held) return { held_s: [snaps[0].t, snaps[snaps.length - 1].t] };
        const t = performance.now();
        const s = window.gale.still(showTrees, at.shown_s, at.t_s); // rows bottom first
        const raw = atob(s.pixels), w = s.w, h = s.h, px = new Uint8Array(w * h * 4);
        for (let y = 0; y < h; y++) for (let i = 0; i < 4 * w; i++) px[4 * y * w + i] = raw.charCodeAt(4 * (h - 1 - y) * w + i);
        let bin = '';
        for (let i = 0; i < px.length; i += 0x8000) bin += String.fromCharCode.apply(null, px.subarray(i, i + 0x8000));
        return { w, h, rgba: btoa(bin), ms: performance.now() - t, fx: window.gale.r.fx };
    }, [at, showTrees]);
    // PNG files to RGBA (rows top first, base64), and RGBA tiles to one PNG, in the helper page
    const decode = (file) => decodePng(helper, file);
    // tiles { c0r0: {w, h, rgba}, ... } placed as the wall holds them (rows 1: the top row
    // only): the gap between two tiles' pictures is their bezels (hidden glass), drawn dark
    const compose = async (tiles, file, rows = 2) => {
        const t = WALL.tiles[0], gx = Math.round(W * (t.bezel_m[0] + t.bezel_m[1]) / t.size_m[0]), gy = Math.round(H * (t.bezel_m[2] + t.bezel_m[3]) / t.size_m[1]);
        const png = await helper.evaluate(([tiles, W, H, gx, gy, rows]) => {
            const c = document.createElement('canvas');
            c.width = 2 * W + gx;
            c.height = rows * H + (rows - 1) * gy;
            const x = c.getContext('2d');
            x.fillStyle = '#111';
            x.fillRect(0, 0, c.width, c.height);
            for (const [name, t] of Object.entries(tiles)) {
                const col = Number(name[1]), row = Number(name[3]), raw = atob(t.rgba), img = x.createImageData(t.w, t.h);
                for (let i = 0; i < raw.length; i++) img.data[i] = raw.charCodeAt(i);
                x.putImageData(img, col * (W + gx), row * (H + gy));
            }
            return c.toDataURL('image/png');
        }, [tiles, W, H, gx, gy, rows]);
        writeFileSync(path.join(work, file), Buffer.from(png.split(',')[1], 'base64'));
    };
    const rgba = (t) => Buffer.from(t.rgba, 'base64');
    // comparePictures takes the page's rows bottom first
    const flip = (buf, w, h) => {
        const o = Buffer.alloc(buf.length);
        for (let y = 0; y < h; y++) buf.copy(o, 4 * w * (h - 1 - y), 4 * w * y, 4 * w * (y + 1));
        return o;
    };
    const luma = (px) => {
        let l = 0;
        for (let i = 0; i < px.length; i += 4) l += 0.2126 * px[i] + 0.7152 * px[i + 1] + 0.0722 * px[i + 2];
        return l / (px.length / 4);
    };
    // the instant a gale-client frame log's line shows, and its shader time from the log's
    // first whole second (render_rel_time), for still()
    const instant = (lines, i) => ({ frame: lines[i][2], shown_s: lines[i][1] * 1e-6, t_s: (lines[i][1] - Math.floor(lines[0][1] * 1e-6) * 1e6) * 1e-6 });

    // The wall at one instant: the four tiles natively (c1r0 too, for the comparison),
    // each writing every frame, until each has drawn WALL_FRAMES; then the page takes no
    // more snapshots and they stop. The instant is the frame of gale-client's c1r0, of
    // those the page holds, that the other tiles' frames lie nearest (the least of the
    // largest distance to a tile's nearest frame, the latest of equals: on two cores the
    // lower tiles draw one group frame in several); each tile's picture is its frame
    // nearest it, the page's c1r0 that instant. Composed with the page's c1r0
    // (wall-WHAT.png) and with gale-client's (wall-WHAT-native.png), and the two c1r0
    // compared.
    async function wall(what) {
        const tiles = [TILE_B, ...NATIVE_TILES];
        const png = (t) => path.join(work, `native-${t}-${what}.png`);
        const loadStart = loadavg();
        for (const t of tiles) dropNumbered(png(t));
        const runs = tiles.map((t) => nativeStart(t, png(t), 100000, ['--screenshot-every', '1']));
        const frames = (t) => { try { return frameLog(png(t)).length; } catch { return 0; } };
        try {
            await until(async () => {
                for (const r of runs) if (r.proc.exitCode !== null) throw new Error(`${what}: a tile ended early: ${await r.done.catch((e) => e.message)}`);
                return tiles.every((t) => frames(t) >= WALL_FRAMES);
            }, 600, `${what}: ${WALL_FRAMES} frames from every tile`);
        } finally {
            await pinNow();
            for (const r of runs) r.proc.kill('SIGTERM');
            await Promise.allSettled(runs.map((r) => r.done));
        }
        await Promise.all(runs.map((r) => r.done));
        const logs = Object.fromEntries(tiles.map((t) => [t, frameLog(png(t))]));
        const nearest = (t, f) => logs[t].reduce((a, l) => (Math.abs(l[2] - f) < Math.abs(a[2] - f) ? l : a));
        // of gale-client c1r0's frames whose instant the page holds (a snapshot either side)
        const { held_s: [h0, h1] } = await heldNow(), l0 = logs[TILE_B][0];
        const instantOf = (f) => (l0[1] + (f - l0[2]) * 1e6 / RATE_HZ) * 1e-6;
        let best = null;
        for (const f of new Set(tiles.flatMap((t) => logs[t].map((l) => l[2])))) {
            if (!(instantOf(f) > h0 + 0.1 && instantOf(f) < h1 - 0.1) || nearest(TILE_B, f)[2] !== f) continue;
            const worst = Math.max(...tiles.map((t) => Math.abs(nearest(t, f)[2] - f)));
            if (!best || worst < best.worst || (worst === best.worst && f > best.f)) best = { f, worst };
        }
        if (!best) throw new Error(`${what}: no frame of the tiles' within the page's snapshots ${h0}..${h1} s`);
        const chosen = {};
        for (const t of tiles) {
            const l = nearest(t, best.f);
            chosen[t] = { frame: l[2], shown_s: l[1] * 1e-6, frames_drawn: logs[t].length };
            // the frame kept as native-TILE-WHAT.png, the others dropped
            writeFileSync(png(t), readFileSync(numbered(png(t), l[2])));
            dropNumbered(png(t));
        }
        const lb = logs[TILE_B], at = instant(lb, lb.findIndex((l) => l[2] === chosen[TILE_B].frame));
        const page = await still(at);
        await unpin();
        if (!page.rgba) throw new Error(`${what}: the page's jitter buffer (${page.held_s}) no longer holds gale-client's c1r0 instant ${at.shown_s} s`);
        const pics = { [TILE_B]: page };
        for (const t of NATIVE_TILES) pics[t] = await decode(png(t));
        await compose(pics, `wall-${what}.png`);
        const nat = await decode(png(TILE_B));
        await compose({ ...pics, [TILE_B]: nat }, `wall-${what}-native.png`);
        await compose({ c0r0: page, c1r0: nat }, `beside-c1r0-${what}.png`, 1);
        const cmp = comparePictures(flip(rgba(page), W, H), rgba(nat), W, H);
        const shown = Object.values(chosen).map((v) => v.shown_s);
        return { compare_c1r0: { ...cmp, luma_browser: luma(rgba(page)), luma_native: luma(rgba(nat)), still_ms: page.ms },
            frames: chosen, instant_spread_s: Math.max(...shown) - Math.min(...shown),
            storm_fx: page.fx, browser_snapshots: await heldNow(), load_average: { start: loadStart, end: loadavg() } };
    }

    // The far region of tile c1r0: pixels (y from the top) whose ray from the camera meets
    // the ground (z = 0) more than FAR_M from the eye, horizontally. The tile's pixel lies
    // on its glass (wall frame: the camera's axes, x right, y up, z back) and the ray runs
    // from the wall's eye through it.
    const farMask = (() => {
        const [pa, pb, pc] = tileCorners(WALL.tiles.find((t) => t.name === TILE_B));
        const c = CAMERA, yaw = c.yaw_deg * Math.PI / 180, pitch = c.pitch_deg * Math.PI / 180;
        const f = [Math.cos(pitch) * Math.cos(yaw), Math.cos(pitch) * Math.sin(yaw), Math.sin(pitch)];
        const eye = c.target_m.map((t, k) => t - f[k] * c.distance_m);
        const s = [Math.sin(yaw), -Math.cos(yaw), 0]; // f × z, unit
        const u = [s[1] * f[2] - s[2] * f[1], s[2] * f[0] - s[0] * f[2], s[0] * f[1] - s[1] * f[0]];
        const m = new Uint8Array(W * H);
        for (let y = 0; y < H; y++) for (let x = 0; x < W; x++) {
            const a = (x + 0.5) / W, b = 1 - (y + 0.5) / H;
            const p = [0, 1, 2].map((k) => pa[k] + a * (pb[k] - pa[k]) + b * (pc[k] - pa[k]) - WALL.eye_m[k]);
            const d = [0, 1, 2].map((k) => s[k] * p[0] + u[k] * p[1] - f[k] * p[2]);
            if (d[2] >= 0) continue;
            const r = -eye[2] / d[2];
            m[y * W + x] = r * Math.hypot(d[0], d[1]) > FAR_M ? 1 : 0;
        }
        return m;
    })();
    out.far_region_share = farMask.reduce((a, b) => a + b, 0) / (W * H);
    // mean absolute difference [levels, of the three channels] over the far region, and
    // the share of its pixels that changed by more than 8 levels
    const farDiff = (p, q) => {
        let sum = 0, moved = 0, n = 0;
        for (let i = 0; i < W * H; i++) {
            if (!farMask[i]) continue;
            const d = (Math.abs(p[4 * i] - q[4 * i]) + Math.abs(p[4 * i + 1] - q[4 * i + 1]) + Math.abs(p[4 * i + 2] - q[4 * i + 2])) / 3;
            sum += d;
            moved += d > 8;
            n++;
        }
        return { mean: sum / n, moved: moved / n };
    };
    const mean = (a) => a.reduce((x, y) => x + y, 0) / a.length;

    // The far impostors' motion: gale-client's c1r0 without the storm look draws
    // consecutive group frames, each written (--screenshot-every 1); the page draws the
    // same instants; each pair one group frame apart is compared over the far region. The
    // page's ground and sky alone at the last pair: what moves without the trees (nothing,
    // without the storm look).
    async function motion(what) {
        const loadStart = loadavg();
        const dmg0 = await damage(), leaf0 = await leafSum();
        await tile.evaluate(() => { window.gale.stormQuality = 0; }); // STORM_FX_OFF, from the next WEATHER
        const png = path.join(work, `motion-${what}.png`);
        dropNumbered(png);
        await native(TILE_B, png, MOTION_FRAMES, ['--storm-fx', 'off', '--screenshot-every', '1']);
        const lines = frameLog(png);
        const period = 1 / RATE_HZ, last = lines.slice(-MOTION_LAST).map((l, i) => instant(lines, lines.length - MOTION_LAST + i));
        // consecutive frames drawn, the closest together (one group frame apart unless the
        // machine was too busy for that)
        const all = last.slice(1).map((b, i) => [last[i], b]);
        const gap = Math.min(...all.map(([a, b]) => b.frame - a.frame));
        const pairs = all.filter(([a, b]) => b.frame - a.frame === gap).slice(-MOTION_PAIRS);
        const pinned = await pin(pairs[pairs.length - 1][1].shown_s);
        const pages = new Map(), natives = new Map();
        for (const at of pairs.flat()) {
            if (pages.has(at.frame)) continue;
            const p = await still(at);
            if (!p.rgba) throw new Error(`motion ${what}: the page's jitter buffer (${p.held_s}) no longer holds ${at.shown_s} s`);
            pages.set(at.frame, p);
            natives.set(at.frame, rgba(await decode(numbered(png, at.frame))));
        }
        const [ba, bb] = pairs[pairs.length - 1];
        const bare = [await still(ba, false), await still(bb, false)];
        // the trees the page's stream moves: per species, those sent with modes and those
        // whose first two modes are not 0 in the snapshot that each instant blends most of
        const moving = await tile.evaluate((ats) => {
            const g = window.gale, inst = g.welcome.instances;
            return ats.map((t) => {
                const w = g.jitter.weightsAt(t), s = w.snaps[w.c[0] >= w.c[1] || w.n < 2 ? 0 : 1];
                const per = g.welcome.species.map((x) => ({ species: x.name, sent: 0, moving: 0 }));
                for (let i = 0; i < inst.length; i++) {
                    if (!(g.modes[i] > 0)) continue;
                    per[inst[i][0]].sent++;
                    per[inst[i][0]].moving += s.q[i * g.stride] !== 0 || s.q[i * g.stride + 1] !== 0;
                }
                return { at_s: t, blend: Array.from({ length: w.n }, (_, k) => [w.snaps[k].tick, +w.c[k].toFixed(3)]), per };
            });
        }, [ba.shown_s, bb.shown_s]);
        await unpin();
        const dmg1 = await damage();
        await tile.evaluate(() => { window.gale.stormQuality = 1; }); // STORM_FX_LOW, the default
        // the two clients at each instant, as the wall's c1r0 is compared
        const alike = [...pages.keys()].map((f) => comparePictures(flip(rgba(pages.get(f)), W, H), natives.get(f), W, H));
        const n = pairs.map(([a, b]) => farDiff(natives.get(a.frame), natives.get(b.frame)));
        const b = pairs.map(([a, bq]) => farDiff(rgba(pages.get(a.frame)), rgba(pages.get(bq.frame))));
        // the first pair's pictures, browser left, native right, to look at
        const [fa, fb] = pairs[0];
        const nat = (f) => ({ w: W, h: H, rgba: natives.get(f).toString('base64') });
        await compose({ c0r0: pages.get(fa.frame), c1r0: nat(fa.frame), c0r1: pages.get(fb.frame), c1r1: nat(fb.frame) }, `motion-${what}-pair.png`);
        // and what changed between them, 8 times brighter, the far region's edge marked
        const changed = (p, q) => {
            const o = Buffer.alloc(4 * W * H);
            for (let i = 0; i < W * H; i++) {
                const d = Math.min(255, 8 * (Math.abs(p[4 * i] - q[4 * i]) + Math.abs(p[4 * i + 1] - q[4 * i + 1]) + Math.abs(p[4 * i + 2] - q[4 * i + 2])) / 3);
                const edge = farMask[i] && (i < W || !farMask[i - W]);
                o[4 * i] = edge ? 255 : d;
                o[4 * i + 1] = edge ? 0 : d;
                o[4 * i + 2] = edge ? 0 : d;
                o[4 * i + 3] = 255;
            }
            return { w: W, h: H, rgba: o.toString('base64') };
        };
        await compose({ c0r0: changed(rgba(pages.get(fa.frame)), rgba(pages.get(fb.frame))), c1r0: changed(natives.get(fa.frame), natives.get(fb.frame)) }, `motion-${what}-changed.png`, 1);
        dropNumbered(png);
        return {
            frames: last.map((a) => a.frame), pairs: pairs.map(([a, bq]) => [a.frame, bq.frame]), dt_s: gap * period,
            native: { far_mean_abs_diff: mean(n.map((d) => d.mean)), far_moved_over_8: mean(n.map((d) => d.moved)), per_pair: n.map((d) => +d.mean.toFixed(3)) },
            browser: { far_mean_abs_diff: mean(b.map((d) => d.mean)), far_moved_over_8: mean(b.map((d) => d.moved)), per_pair: b.map((d) => +d.mean.toFixed(3)) },
            browser_without_trees: bare[0].rgba && bare[1].rgba ? farDiff(rgba(bare[0]), rgba(bare[1])).mean : null,
            browser_vs_native: { mean_abs_diff: mean(alike.map((c) => c.mean_abs_diff)), blocks_8px_over_16: mean(alike.map((c) => c.blocks_8px_over_16)) },
            browser_snapshots: pinned, browser_trees: moving,
            wind_ms: await metric('gale_wind_sustained_meters_per_second'),
            felled_meanwhile: dmg1.felled - dmg0.felled, leaf_32nds_lost_meanwhile: leaf0 - await leafSum(),
            load_average: { start: loadStart, end: loadavg() },
        };
    }
    const damage = async () => {
        const s = await metric('gale_trees_snapped_total'), u = await metric('gale_trees_uprooted_total');
        // and the trees the page holds as fallen (its DAMAGE view)
        const known = await tile.evaluate(() => window.gale.damage.view.fallen.reduce((a, f) => a + (f > 0), 0));
        return { snapped: s, uprooted: u, felled: s + u, branches: await metric('gale_branches_broken_total'), browser_holds_fallen: known };
    };
    // a kiosk dials ms: the server's wind reaches it (the dial ramps at 4 m/s a second),
    // then settle_s more for the trees to take it up
    async function dial(ms, settle_s) {
        await kioskCtl('wind', '--speed', String(ms));
        // (/metrics gives whole m/s)
        await until(async () => Math.abs((await metric('gale_wind_sustained_meters_per_second')) - ms) <= 1, 120, `the server's wind at ${ms} m/s`);
        await waitFor(tile, (v) => window.gale.weather && Math.abs(window.gale.weather.sustained_ms - v) < 0.5, ms, 60, `${ms} m/s in the browser tile's WEATHER`);
        await new Promise((r) => setTimeout(r, settle_s * 1000));
    }
    // The crowns' leaf area the page holds, summed over the trees (32nds): a storm strips
    // it towards a floor (server/PHYSICS.md "Leaf stripping", 10 s time constant), which
    // changes the impostors' pictures as their sway does; the motion is measured once it
    // has held for hold_s.
    const leafSum = () => tile.evaluate(() => window.gale.damage.view.level.reduce((a, l) => a + l, 0));
    async function stripped(hold_s) {
        let last = await leafSum(), since = Date.now();
        await until(async () => {
            const now = await leafSum();
            if (now !== last) [last, since] = [now, Date.now()];
            return Date.now() - since > hold_s * 1000;
        }, 180, 'the crowns\' leaf levels holding');
    }

    out.calm = await wall('calm');
    say(`calm wall: ${JSON.stringify(out.calm.compare_c1r0)}`);
    out.motion_calm = await motion('calm');
    say(`calm motion: ${JSON.stringify(out.motion_calm)}`);
    await dial(CAT3_MS, 0);
    await stripped(15);
    out.motion_cat3 = await motion('cat3');
    say(`Category 3 motion: ${JSON.stringify(out.motion_cat3)}`);
    // (null: calm's frames were the same pictures, nothing in the far region moved)
    const ratio = (k) => out.motion_calm[k].far_mean_abs_diff > 0 ? out.motion_cat3[k].far_mean_abs_diff / out.motion_calm[k].far_mean_abs_diff : null;
    out.motion_ratio = { native: ratio('native'), browser: ratio('browser') };
    await dial(CAT4_MS, 20);
    await waitFor(tile, () => window.gale.r.fx && window.gale.r.fx.rain > 0, null, 60, 'the storm look back on the browser tile');
    out.storm = await wall('storm');
    say(`storm wall: ${JSON.stringify(out.storm.compare_c1r0)}`);
    out.damage = await damage();
    out.storm_luma_ratio = { browser: out.storm.compare_c1r0.luma_browser / out.calm.compare_c1r0.luma_browser,
        native: out.storm.compare_c1r0.luma_native / out.calm.compare_c1r0.luma_native };
    out.browser_errors = ctx.errors;
    out.load_average.end = loadavg();
    out.seconds = (Date.now() - t0) / 1000;
    console.log(JSON.stringify(out));
} finally {
    await ctx.close();
    await srv.stop();
}
