// What every browser test of web/ shares: a real gale-server on 127.0.0.1 (a free port,
// read from its "listening on" line), Debian's chromium driven by playwright-core
// (headless, WebGL2 through SwiftShader, a fresh profile under the build directory, no
// browser download), and a bounded wait for a condition in the page.
import { spawn } from 'node:child_process';
import { existsSync, mkdtempSync, mkdirSync, readFileSync } from 'node:fs';
import path from 'node:path';
import { pathToFileURL } from 'node:url';

export const CHROMIUM = process.env.GALE_CHROMIUM || '/usr/bin/chromium';
// playwright-core from the folder npm ci installed it into ($GALE_WEB_DEPS)
async function driver() {
    const deps = process.env.GALE_WEB_DEPS;
    if (!deps) throw new Error('GALE_WEB_DEPS: expected the folder npm ci installed playwright-core into (the build tree\'s tests/web)');
    if (!existsSync(CHROMIUM)) throw new Error(`${CHROMIUM}: no chromium (deploy/install-deps.sh installs Debian's)`);
    return (await import(pathToFileURL(path.resolve(deps, 'node_modules/playwright-core/index.mjs')).href)).chromium;
}

export function args(usage) {
    const a = process.argv.slice(2);
    if (a.includes('--help')) {
        console.log(usage);
        process.exit(0);
    }
    return a;
}

// The visitor's texts the build wrote beside gale-server (BUILD/lang-gen/lang_texts.js,
// BUILD/server/gale-server), handed to web/lang.js, for a test that formats the page's words
// itself.
export async function useTexts(serverBin) {
    const file = path.resolve(path.dirname(serverBin), '..', 'lang-gen', 'lang_texts.js');
    const { LANG_CODES, TEXTS } = await import(pathToFileURL(file).href);
    (await import('../../web/lang.js')).setTexts(LANG_CODES, TEXTS);
}

// gale-server with extra arguments; resolves to { url, port, proc, log(), stop() }.
export function startServer(bin, extra = [], { port = 0, env = {} } = {}) {
    return new Promise((resolve, reject) => {
        const proc = spawn(bin, ['--port', String(port), ...extra], { env: { ...process.env, ...env }, stdio: ['ignore', 'pipe', 'pipe'] });
        let log = '';
        const timer = setTimeout(() => { proc.kill('SIGKILL'); reject(new Error(`gale-server did not listen within 60 s:\n${log}`)); }, 60000);
        const onData = (d) => {
            log += d;
            const m = log.match(/listening on 127\.0\.0\.1 port (\d+)/);
            if (m && timer) {
                clearTimeout(timer);
                const p = Number(m[1]);
                resolve({
                    port: p, url: `http://127.0.0.1:${p}`, proc, log: () => log,
                    stop: (sig = 'SIGTERM') => new Promise((res) => {
                        if (proc.exitCode !== null) return res(proc.exitCode);
                        proc.once('exit', (c) => res(c));
                        proc.kill(sig);
                    }),
                });
            }
        };
        proc.stdout.on('data', onData);
        proc.stderr.on('data', onData);
        proc.once('exit', (c) => { clearTimeout(timer); reject(new Error(`gale-server exited ${c}:\n${log}`)); });
    });
}

// A browser context with its own profile under dir; console errors and page errors are
// collected in ctx.errors.
export async function startBrowser(dir, { width = 800, height = 600, extraArgs = [] } = {}) {
    mkdirSync(dir, { recursive: true });
    const profile = mkdtempSync(path.join(dir, 'profile-'));
    const chromium = await driver();
    const ctx = await chromium.launchPersistentContext(profile, {
        executablePath: CHROMIUM,
        headless: true,
        viewport: { width, height },
        args: ['--headless', '--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
            '--disable-background-networking', '--disable-component-update', '--disable-sync', '--no-first-run', ...extraArgs],
    });
    ctx.errors = [];
    ctx.on('page', (p) => watch(ctx, p));
    for (const p of ctx.pages()) watch(ctx, p);
    return ctx;
}

function watch(ctx, page) {
    page.on('pageerror', (e) => ctx.errors.push(`pageerror: ${e.message}`));
    page.on('console', (m) => { if (m.type() === 'error') ctx.errors.push(`console: ${m.text()}`); });
}

// Polls fn() in the page until it returns a truthy value or timeout_s passes.
export async function waitFor(page, fn, arg, timeout_s, what) {
    try {
        return await page.waitForFunction(fn, arg, { timeout: timeout_s * 1000, polling: 100 });
    } catch (e) {
        const st = await page.evaluate(() => window.gale && window.gale.status ? JSON.stringify(window.gale.status()) : 'no window.gale').catch(() => '?');
        throw new Error(`${what}: not within ${timeout_s} s (page status ${st})`);
    }
}

// The value of one unlabelled metric of the server at URL; fails naming it when absent.
export async function readMetric(url, name) {
    const text = await (await fetch(`${url}/metrics`)).text();
    const m = text.match(new RegExp(`^${name} (\\S+)$`, 'm'));
    if (!m) throw new Error(`${name} not in ${url}/metrics`);
    return Number(m[1]);
}

// Polls fn (async) every 0.2 s until it returns something true; throws naming what after
// timeout_s.
export async function until(fn, timeout_s, what) {
    const end = Date.now() + timeout_s * 1000;
    for (;;) {
        const v = await fn();
        if (v) return v;
        if (Date.now() > end) throw new Error(`${what}: not within ${timeout_s} s`);
        await new Promise((r) => setTimeout(r, 200));
    }
}

// Kiosk messages from page (any page, about:blank too) over a WebSocket of its own to
// wsUrl: a kiosk hello with token and a view of nothing (it needs no state), then each
// message, then it hangs up a second later. Resolves to what the server closed it with
// (an empty list: every message was taken).
export function sendAsKiosk(page, wsUrl, token, messages) {
    return page.evaluate(([u, token, messages]) => new Promise((resolve) => {
        const ws = new WebSocket(u), said = [];
        ws.onopen = () => {
            ws.send(JSON.stringify({ type: 'hello', protocol: 1, role: 'kiosk', token, view: { kind: 'circle', x: 1e5, y: 1e5, radius_m: 1, lod_m: 1 } }));
            for (const m of messages) ws.send(JSON.stringify(m));
            setTimeout(() => { ws.close(); resolve(said); }, 1000);
        };
        ws.onclose = (e) => { said.push(`closed ${e.code} ${e.reason}`); resolve(said); };
    }), [wsUrl, token, messages]);
}

// A PNG file's pixels, decoded in page: { w, h, rgba } (RGBA rows top first, base64).
export function decodePng(page, file) {
    return page.evaluate(async (b64) => {
        const img = new Image();
        img.src = `data:image/png;base64,${b64}`;
        await img.decode();
        const c = document.createElement('canvas');
        c.width = img.width;
        c.height = img.height;
        const x = c.getContext('2d');
        x.drawImage(img, 0, 0);
        const px = x.getImageData(0, 0, c.width, c.height).data;
        let bin = '';
        for (let i = 0; i < px.length; i += 0x8000) bin += String.fromCharCode.apply(null, px.subarray(i, i + 0x8000));
        return { w: img.width, h: img.height, rgba: btoa(bin) };
    }, readFileSync(file).toString('base64'));
}

// The pinhole projection of a page's camera (eye, target, fov_y_deg, z up) onto a w × h
// frame: p [m] to [x, y from the bottom, depth] [px, px, m]; .fy is the vertical focal
// factor (a length l at depth z spans l * fy * h / 2 / z pixels).
export function projector(cam, w, h) {
    const sub = (p, q) => p.map((x, k) => x - q[k]);
    const dot = (p, q) => p[0] * q[0] + p[1] * q[1] + p[2] * q[2];
    const unit = (p) => p.map((x) => x / Math.hypot(...p));
    const cross = (p, q) => [p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0]];
    const f = unit(sub(cam.target, cam.eye)), s = unit(cross(f, [0, 0, 1])), u = cross(s, f);
    const fy = 1 / Math.tan((cam.fov_y_deg * Math.PI) / 360), fx = fy * h / w;
    const project = (p) => {
        const d = sub(p, cam.eye), z = dot(d, f);
        return [(1 + fx * dot(d, s) / z) * w / 2, (1 + fy * dot(d, u) / z) * h / 2, z];
    };
    project.fy = fy;
    return project;
}

// A page's picture against gale-client's of the same size (RGBA bytes; `page` rows bottom
// first as still() reads them, `native` rows top first as a PNG holds them): the mean
// absolute difference [levels], the fraction of pixels off by more than 32 levels, and of
// 8 × 8 blocks whose channel means are off by more than 16 (a leaf that flutters to a
// neighbouring pixel moves no block mean much), over the pixels and blocks skip(x, y)
// (y from the top) leaves in.
export function comparePictures(page, native, w, h, skip = () => false) {
    const at = (y, x) => [4 * ((h - 1 - y) * w + x), 4 * (y * w + x)];
    let sum = 0, big = 0, n = 0;
    for (let y = 0; y < h; y++) for (let x = 0; x < w; x++) {
        if (skip(x, y)) continue;
        const [a, b] = at(y, x);
        let d = 0;
        for (let k = 0; k < 3; k++) d += Math.abs(page[a + k] - native[b + k]);
        sum += d / 3;
        big += d / 3 > 32;
        n++;
    }
    const B = 8;
    let blocks = 0, bad = 0;
    for (let by = 0; by < Math.floor(h / B); by++) for (let bx = 0; bx < Math.floor(w / B); bx++) {
        if (skip(bx * B, by * B) || skip(bx * B + B - 1, by * B + B - 1)) continue;
        let d = 0;
        for (let k = 0; k < 3; k++) {
            let ma = 0, mb = 0;
            for (let y = by * B; y < by * B + B; y++) for (let x = bx * B; x < bx * B + B; x++) {
                const [a, b] = at(y, x);
                ma += page[a + k];
                mb += native[b + k];
            }
            d += Math.abs(ma - mb) / (B * B) / 3;
        }
        blocks++;
        bad += d > 16;
    }
    return { mean_abs_diff: sum / n, frac_over_32: big / n, blocks_8px_over_16: bad / blocks, compared_px: n };
}
