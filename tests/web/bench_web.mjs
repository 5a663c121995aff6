// Benchmark of the browser client (prints JSON; not a test): headless chromium (SwiftShader
// WebGL2) on the viewer page of a real gale-server, for the town block (the embedded
// default scene) and the 100,000-tree landscape (configs/scenes/landscape-2km.json), and
// with --scenes also a generated forest of 4,000 trees. Per scene: JS CPU of the page's
// stages, median and p95 [ms]: decode (web/wire.js) and insert (the copy of the quantised
// values into the jitter buffer, web/jitter.js), per snapshot; interp (the Hermite weights
// and the skeleton pass's per-species weights: the GPU dequantises and blends) and upload
// (of the snapshots a frame is the first to blend into the GPU's ring, web/render_skel.js
// setMix), per drawn frame; page load to the first drawn frame; bytes fetched (pages,
// shaders, assets over HTTP, the WebSocket stream). Per drawn frame, counted by a wrapper
// of WebGL2's draw calls that the benchmark puts into the page (so that any build of the
// page is measured alike): draw calls, triangles and vertices; and where the page reports
// them (window.gale.lod): the cull's CPU time, trees per level, view messages sent. The
// measured window runs --seconds after the first frame, and at least until --frames more
// frames were drawn (a software GPU may take a minute a frame). --draw N: the viewer's
// ?max_trees=N (0: none). --cameras street,roof,aerial: each scene from those of the kiosk's
// presets (the viewer's ?camera=, gale-client's --camera) in turn, one page each, in place of
// the viewer's default orbit; --size WxH the page's (default 800x600). js_cpu_per_frame_ms: the four stages' medians (p95s, means)
// summed. ref_ms: the same page's time for a fixed multiply-add over 4,000 × 32 floats,
// 100 times: the machine's pace in this run.
//   GALE_WEB_DEPS=build/tests/web node tests/web/bench_web.mjs build/server/gale-server OUT_DIR
//       [--seconds S] [--frames N] [--draw N] [--scenes town,landscape,forest]
//       [--cameras street,roof,aerial] [--size WxH]
import { writeFileSync, mkdirSync, readFileSync } from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { args, startServer, startBrowser, waitFor } from './harness.mjs';

const a = args('usage: node bench_web.mjs GALE_SERVER OUT_DIR [--seconds S] [--frames N] [--draw N] [--scenes town,landscape,forest] [--cameras street,roof,aerial] [--size WxH]');
const [server, work] = a;
const opt = (k, d) => (a.includes(k) ? Number(a[a.indexOf(k) + 1]) : d);
const seconds = opt('--seconds', 20), draw = opt('--draw', 0), frames = opt('--frames', 2);
const scenes = (a.includes('--scenes') ? a[a.indexOf('--scenes') + 1] : 'town,landscape').split(',');
const cameras = a.includes('--cameras') ? a[a.indexOf('--cameras') + 1].split(',') : [''];
const size = (a.includes('--size') ? a[a.indexOf('--size') + 1] : '800x600').split('x').map(Number);
if (size.length !== 2 || !(size[0] > 0 && size[1] > 0)) throw new Error('--size: expected WxH, as 1920x1080');
const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
mkdirSync(work, { recursive: true });

// 4,000 trees: the town block's species, forests of 1,334 / 1,333 / 1,333 on 600 m × 600 m
const def = JSON.parse(readFileSync(path.join(root, 'configs/scenes/default.json'), 'utf8'));
const big = { ...def, name: 'forest-4000', obstacles: [], trees: [] };
delete big.wind;
big.species = def.species.map((s) => ({ ...s, file: path.join(root, 'configs/species', path.basename(s.file)) }));
big.forest = def.species.map((s, i) => ({ species: s.name, count: i === 0 ? 1334 : 1333, area_min: [-300, -300],
    area_max: [300, 300], min_spacing_m: 3, seed: 21 + i, scale: [0.8, 1.15] }));
const bigPath = path.join(work, 'forest-4000.json');
writeFileSync(bigPath, JSON.stringify(big, null, 1));

// Counts every draw call of WebGL2 in the page: calls, vertices and triangles (TRIANGLES
// only), into window.__glDraws.
function countDraws() {
    const c = window.__glDraws = { calls: 0, vertices: 0, triangles: 0 };
    const P = WebGL2RenderingContext.prototype;
    const wrap = (name, count) => {
        const f = P[name];
        P[name] = function (...x) {
            const v = count(x);
            c.calls++;
            c.vertices += v;
            if (x[0] === 4) c.triangles += v / 3; // gl.TRIANGLES
            return f.apply(this, x);
        };
    };
    wrap('drawArrays', (x) => x[2]);
    wrap('drawElements', (x) => x[1]);
    wrap('drawArraysInstanced', (x) => x[2] * x[3]);
    wrap('drawElementsInstanced', (x) => x[1] * x[4]);
}

// The scene's server, and a page for each camera in turn: { camera: figures } (the
// viewer's default orbit under '').
async function run(name, extra) {
    const srv = await startServer(server, ['--cache', path.join(work, 'cache'), ...extra]);
    const ctx = await startBrowser(path.join(work, name), { width: size[0], height: size[1] });
    try {
        const out = {};
        for (const cam of cameras) out[cam || 'default'] = await runPage(ctx, srv, cam ? `${name}-${cam}` : name, cam);
        return cameras.length === 1 && !cameras[0] ? out.default : out;
    } finally {
        await ctx.close();
        await srv.stop();
    }
}

async function runPage(ctx, srv, name, cam) {
    const page = await ctx.newPage();
    try {
        await page.addInitScript(countDraws);
        const q = [draw > 0 ? `max_trees=${draw}` : '', cam ? `camera=${cam}` : ''].filter(Boolean).join('&');
        await page.goto(`${srv.url}/${q ? `?${q}` : ''}`);
        await waitFor(page, () => window.gale && window.gale.framesDrawn >= 1, null, 900, `${name}: first frame`);
        await page.evaluate(() => { for (const k of Object.keys(window.gale.perf)) window.gale.perf[k] = []; window.gale.ws0 = window.gale.conn.stats.bytes; window.gale.t0 = performance.now();
            window.gale.up0 = window.gale.r.stats.uploads || 0; window.gale.j0 = { ...window.gale.jitter.stats };
            window.gale.f0 = window.gale.framesDrawn; window.gale.d0 = { ...window.__glDraws }; });
        const t0 = Date.now();
        await new Promise((r) => setTimeout(r, seconds * 1000));
        await waitFor(page, (n) => window.gale.framesDrawn - window.gale.f0 >= n, frames, 900, `${name}: ${frames} frames`);
        const window_s = (Date.now() - t0) / 1000;
        const res = await page.evaluate(() => {
            const g = window.gale;
            const res = performance.getEntriesByType('resource');
            const http = res.reduce((s, e) => s + (e.transferSize || e.encodedBodySize || 0), 0);
            const nav = performance.getEntriesByType('navigation')[0];
            const x = new Float32Array(4000 * 32).fill(1), y = new Float32Array(4000 * 32);
            const t = performance.now();
            for (let k = 0; k < 100; k++) for (let i = 0; i < x.length; i++) y[i] = y[i] * 0.5 + x[i] * 0.25;
            const ref = performance.now() - t;
            const ps = g.perfSummary(), sum = (k) => ['decode', 'insert', 'interp', 'upload'].reduce((a, s) => a + ps[s][k], 0);
            const nf = g.framesDrawn - g.f0, d = window.__glDraws;
            const lod = typeof g.lodStats === 'function' ? g.lodStats() : null;
            return { trees: g.welcome.instances.length, js_cpu_per_frame_ms: { median_sum: sum('median_ms'), p95_sum: sum('p95_ms'), mean_sum: sum('mean_ms') }, modes_max: g.stride, drawn_trees: g.r.stats.trees_drawn, perf: g.perfSummary(),
                first_frame_ms: g.firstFrame_ms, frames_drawn: nf, frames_drawn_per_s: nf / ((performance.now() - g.t0) / 1000),
                per_frame: { draw_calls: (d.calls - g.d0.calls) / nf, triangles: (d.triangles - g.d0.triangles) / nf, vertices: (d.vertices - g.d0.vertices) / nf },
                lod,
                bytes: { http, page_html: nav ? nav.transferSize : null, assets: g.bytesAssets, ws_per_s: (g.conn.stats.bytes - g.ws0) / ((performance.now() - g.t0) / 1000) },
                decode_errors: g.conn.stats.errors, ref_ms: ref,
                snapshots_uploaded_per_frame: ((g.r.stats.uploads || 0) - g.up0) / Math.max(1, g.perf.interp.length),
                jitter: Object.fromEntries(Object.entries(g.jitter.stats).map(([k, v]) => [k, v - (g.j0[k] || 0)])) };
        });
        res.window_s = window_s;
        // the picture (a software GPU may take minutes a frame: not waited for past 5 min)
        await page.screenshot({ path: path.join(work, `${name}.png`), timeout: 300000 }).catch((e) => { res.screenshot_error = e.message.split('\n')[0]; });
        return res;
    } finally {
        await page.close();
    }
}

const out = { seconds, frames, draw_cap: draw, size: `${size[0]}x${size[1]}`, load_avg_before: os.loadavg(), scenes: {} };
const landscape = path.join(root, 'configs/scenes/landscape-2km.json');
for (const sc of scenes) {
    if (sc === 'town') out.scenes.town_block = await run('town', []);
    else if (sc === 'landscape') out.scenes.landscape_2km = await run('landscape', ['--config', landscape]);
    else if (sc === 'forest') out.scenes.forest_4000 = await run('forest', ['--config', bigPath]);
    else throw new Error(`--scenes: ${sc}: expected town, landscape or forest`);
    // each scene as it ends, on stderr: a long run cut short keeps what it measured
    console.error(JSON.stringify({ [sc]: Object.values(out.scenes).at(-1) }));
}
out.load_avg_after = os.loadavg();
console.log(JSON.stringify(out, null, 1));
