// The kiosk page against a real gale-server with a kiosk token: the token given in the URL
// fragment is kept in localStorage and leaves the address bar, and is in no query string
// nor page source; the wind dial sets the server's wind (gale_wind_sustained_meters_per_second and
// gale_wind_dial in /metrics) and the HUD reads the category the server's WEATHER names;
// leaving releases the dial; a wrong token is refused on the setup screen.
import assert from 'node:assert/strict';
import { writeFileSync } from 'node:fs';
import path from 'node:path';
import { args, startServer, startBrowser, waitFor } from './harness.mjs';

const [server, work, config] = args('usage: node test_web_kiosk.mjs GALE_SERVER WORK_DIR SCENE.json');
const TOKEN = 'web-kiosk-test-7f3a';
const { mkdirSync } = await import('node:fs');
mkdirSync(work, { recursive: true });
const tokenFile = path.join(work, 'token');
writeFileSync(tokenFile, `${TOKEN}\n`, { mode: 0o600 });
const srv = await startServer(server, ['--cache', path.join(work, '..', 'cache'), '--config', config, '--kiosk-token-file', tokenFile]);
const metric = async (name) => {
    const text = await (await fetch(`${srv.url}/metrics`)).text();
    const m = text.match(new RegExp(`^${name} (\\S+)$`, 'm'));
    assert.ok(m, `${name} not in /metrics`);
    return Number(m[1]);
};
const until = async (fn, timeout_s, what) => {
    const end = Date.now() + timeout_s * 1000;
    for (;;) {
        const v = await fn();
        if (v) return v;
        if (Date.now() > end) throw new Error(`${what}: not within ${timeout_s} s`);
        await new Promise((r) => setTimeout(r, 200));
    }
};
const ctx = await startBrowser(work, { width: 800, height: 600 });
const out = {};
try {
    const page = await ctx.newPage();
    const requests = [];
    page.on('request', (r) => requests.push(r.url()));
    await page.goto(`${srv.url}/kiosk#token=${TOKEN}`);
    await waitFor(page, () => window.gale && window.gale.framesDrawn >= 3 && window.gale.weather, null, 120, 'kiosk live and drawn');
    const where = await page.evaluate(() => ({ href: location.href, stored: localStorage.getItem('gale.kiosk.token'),
        html: document.documentElement.outerHTML, panel: !document.getElementById('panel').hidden }));
    assert.equal(where.stored, TOKEN, 'token kept in localStorage');
    assert.ok(!where.href.includes(TOKEN), `token left in the address bar: ${where.href}`);
    assert.ok(!where.html.includes(TOKEN), 'token in the page source');
    for (const u of requests) assert.ok(!u.includes(TOKEN), `token sent in a URL: ${u}`);
    assert.ok(where.panel, 'the panel is shown');
    await page.screenshot({ path: path.join(work, 'kiosk-calm.png') });
    out.calm_hud = await page.textContent('#hud');
    assert.equal(await metric('gale_wind_dial'), 0);

    // 60 m/s = 117 kn: Saffir-Simpson Category 4 (113-136 kn)
    await page.locator('#dial').fill('60');
    await until(async () => (await metric('gale_wind_dial')) === 1 && Math.abs((await metric('gale_wind_sustained_meters_per_second')) - 60) < 0.5, 60, 'server wind 60 m/s from the dial (the dial moves it 4 m/s a second)');
    out.metric_sustained_ms = await metric('gale_wind_sustained_meters_per_second');
    await waitFor(page, () => window.gale.weather && window.gale.weather.ss_class === 5 && /Category 4 hurricane/.test(document.getElementById('hud').textContent), null, 30, 'HUD reads Category 4');
    await page.evaluate(() => new Promise((r) => { const n = window.gale.framesDrawn; const t = () => (window.gale.framesDrawn > n + 1 ? r() : setTimeout(t, 50)); t(); }));
    await page.screenshot({ path: path.join(work, 'kiosk-cat4.png') });
    out.cat4_hud = await page.textContent('#hud');
    assert.deepEqual(ctx.errors, []);

    // leaving releases the dial
    await page.close({ runBeforeUnload: true });
    await until(async () => (await metric('gale_wind_dial')) === 0, 20, 'dial released after the page left');

    // a wrong token: refused, said plainly on the setup screen, not kept
    const fails0 = await metric('gale_kiosk_auth_failures_total');
    const ctx2 = await startBrowser(path.join(work, 'wrong'), { width: 800, height: 600 });
    try {
        const p2 = await ctx2.newPage();
        await p2.goto(`${srv.url}/kiosk#token=not-the-token`);
        await waitFor(p2, () => !document.getElementById('setup').hidden && /refused/.test(document.getElementById('setup-error').textContent), null, 60, 'wrong token refused on the setup screen');
        out.refused = await p2.textContent('#setup-error');
        assert.equal(await p2.evaluate(() => localStorage.getItem('gale.kiosk.token')), null, 'a refused token is not kept');
        await p2.screenshot({ path: path.join(work, 'kiosk-refused.png') });
        assert.ok((await metric('gale_kiosk_auth_failures_total')) > fails0, 'the server counted the wrong token');
        assert.equal(await metric('gale_wind_dial'), 0);
    } finally {
        await ctx2.close();
    }
    console.log(JSON.stringify({ ...out, ok: true }));
} finally {
    await ctx.close();
    await srv.stop();
}
