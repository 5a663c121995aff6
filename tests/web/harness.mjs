// What every browser test of web/ shares: a real gale-server on 127.0.0.1 (a free port,
// read from its "listening on" line), Debian's chromium driven by playwright-core
// (headless, WebGL2 through SwiftShader, a fresh profile under the build directory, no
// browser download), and a bounded wait for a condition in the page.
import { spawn } from 'node:child_process';
import { existsSync, mkdtempSync, mkdirSync } from 'node:fs';
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
