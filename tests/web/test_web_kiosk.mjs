// The kiosk page against a real gale-server with a kiosk token: the token given in the URL
// fragment is kept in localStorage and leaves the address bar, and is in no query string
// nor page source; the wind dial sets the server's wind (gale_wind_sustained_meters_per_second and
// gale_wind_dial in /metrics) and the HUD reads the category the server's WEATHER names;
// leaving releases the dial; a wrong token is refused on the setup screen. At Category 4
// the picture takes the storm look (web/storm_fx.js): the drawn frame's top band (misty
// horizon and sky) and the whole frame are darker and greyer than at calm.
import assert from 'node:assert/strict';
import { writeFileSync } from 'node:fs';
import path from 'node:path';
import { args, startServer, startBrowser, waitFor, readMetric, until } from './harness.mjs';
import { dialTo } from './kiosk_touch.mjs';

const [server, work, config] = args('usage: node test_web_kiosk.mjs GALE_SERVER WORK_DIR SCENE.json');
const TOKEN = 'web-kiosk-test-7f3a';
const { mkdirSync } = await import('node:fs');
mkdirSync(work, { recursive: true });
const tokenFile = path.join(work, 'token');
writeFileSync(tokenFile, `${TOKEN}\n`, { mode: 0o600 });
const srv = await startServer(server, ['--cache', path.join(work, '..', 'cache'), '--config', config, '--kiosk-token-file', tokenFile]);
const metric = (name) => readMetric(srv.url, name);
// Mean luma (Rec. 709, 0..255) and mean chroma (max - min channel) of the canvas's last
// drawn frame (preserveDrawingBuffer), over its top quarter and over the whole of it.
const pictureStats = (page) => page.evaluate(() => {
    const src = window.gale.canvas, c = document.createElement('canvas');
    c.width = src.width;
    c.height = src.height;
    const g = c.getContext('2d');
    g.drawImage(src, 0, 0);
    const band = (y0, y1) => {
        const d = g.getImageData(0, y0, c.width, y1 - y0).data;
        let l = 0, ch = 0;
        for (let i = 0; i < d.length; i += 4) {
            l += 0.2126 * d[i] + 0.7152 * d[i + 1] + 0.0722 * d[i + 2];
            ch += Math.max(d[i], d[i + 1], d[i + 2]) - Math.min(d[i], d[i + 1], d[i + 2]);
        }
        const n = d.length / 4;
        return { luma: l / n, chroma: ch / n };
    };
    return { top: band(0, Math.floor(c.height / 4)), all: band(0, c.height) };
});
const twoFrames = (page) => page.evaluate(() => new Promise((r) => { const n = window.gale.framesDrawn; const t = () => (window.gale.framesDrawn > n + 1 ? r() : setTimeout(t, 50)); t(); }));
// The picture as the kiosk shows it, then with the orbit tilted to look 10° up for a
// moment, so that the top half of the frame is sky (its stats and a screenshot of it).
const measure = async (page, name) => {
    const view = await pictureStats(page);
    const pitch = await page.evaluate(() => { const p = window.gale.cam.pitch; window.gale.cam.pitch = 0.1745; return p; });
    await twoFrames(page);
    const sky = (await pictureStats(page)).top;
    await page.screenshot({ path: path.join(work, `kiosk-${name}-sky.png`) });
    await page.evaluate((p) => { window.gale.cam.pitch = p; }, pitch);
    await twoFrames(page);
    return { view: view.all, sky };
};
// Share of the frame's pixels the rain and spray change: the same state drawn twice, with
// the storm look as streamed and without its rain (any channel off by more than 16 levels).
const rainShare = (page) => page.evaluate(() => {
    const g = window.gale, fx = g.r.fx;
    const wet = atob(g.still(true).pixels);
    g.r.fx = { ...fx, rain_layers: 0, spray: 0 };
    const dry = atob(g.still(true).pixels);
    g.r.fx = fx;
    g.frozen = false;
    let n = 0;
    for (let i = 0; i < wet.length; i += 4) {
        for (let k = 0; k < 3; k++) {
            if (Math.abs(wet.charCodeAt(i + k) - dry.charCodeAt(i + k)) > 16) { n++; break; }
        }
    }
    return n / (wet.length / 4);
});
const ctx = await startBrowser(work, { width: 800, height: 600 });
const out = {};
try {
    const page = await ctx.newPage();
    const requests = [];
    page.on('request', (r) => requests.push(r.url()));
    // (attract mode an hour away: a slow first frame here must not send the panel away)
    await page.goto(`${srv.url}/kiosk?attract=3600#token=${TOKEN}`);
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
    // a breeze is named by its Beaufort force, never "Tropical depression"
    assert.ok(/Beaufort \d/.test(out.calm_hud) && !/Tropical/.test(out.calm_hud), `HUD at calm reads: ${out.calm_hud}`);
    out.calm_picture = await measure(page, 'calm');
    out.calm_fx = await page.evaluate(() => window.gale.r.fx);
    assert.equal(await metric('gale_wind_dial'), 0);

    // 60 m/s = 117 kn: Saffir-Simpson Category 4 (113-136 kn)
    await dialTo(page, 60, { from: 5 });
    await until(async () => (await metric('gale_wind_dial')) === 1 && Math.abs((await metric('gale_wind_sustained_meters_per_second')) - 60) < 1, 60, 'server wind 60 m/s from the dial (the dial moves it 4 m/s a second)');
    out.metric_sustained_ms = await metric('gale_wind_sustained_meters_per_second');
    await waitFor(page, () => window.gale.weather && window.gale.weather.ss_class === 5 && /Category 4 hurricane/.test(document.getElementById('hud').textContent), null, 30, 'HUD reads Category 4');
    await twoFrames(page);
    await page.screenshot({ path: path.join(work, 'kiosk-cat4.png') });
    out.cat4_hud = await page.textContent('#hud');
    // the dial holds the wind: the steady scenario's title ("Calm") is not shown over it
    // as gale-client's HUD: the dial said, the steady scenario's title ("Calm") not
    assert.ok(/dialled at the kiosk/.test(out.cat4_hud) && !/\bCalm\b/.test(out.cat4_hud), `HUD under a dialled Category 4 reads: ${out.cat4_hud}`);
    assert.equal(await page.textContent('#hud-says'), 'Category 4 hurricane', 'the class a screen reader is told');
    out.cat4_picture = await measure(page, 'cat4');
    out.cat4_fx = await page.evaluate(() => window.gale.r.fx);
    out.cat4_rain_share = await rainShare(page);
    // the storm look at Category 4: sky, light and fog of web/storm_fx.js (its numbers are
    // client/render/storm_fx.c's, test_web_storm_fx); floors well inside what it draws (the sky
    // about 0.65 of calm's luma and 0.2 of its chroma, the kiosk's view 0.64 and 0.19, rain
    // on about 5 % of the pixels at 800×600)
    const [c, s] = [out.calm_picture, out.cat4_picture];
    assert.ok(s.sky.luma < 0.8 * c.sky.luma, `sky luma ${s.sky.luma} at Category 4, ${c.sky.luma} calm: not darker`);
    assert.ok(s.sky.chroma < 0.4 * c.sky.chroma, `sky chroma ${s.sky.chroma} at Category 4, ${c.sky.chroma} calm: not greyer`);
    assert.ok(s.view.luma < 0.8 * c.view.luma, `picture luma ${s.view.luma} at Category 4, ${c.view.luma} calm: not darker`);
    assert.ok(s.view.chroma < 0.4 * c.view.chroma, `picture chroma ${s.view.chroma} at Category 4, ${c.view.chroma} calm: not greyer`);
    assert.ok(out.cat4_rain_share > 0.02, `rain changes ${out.cat4_rain_share} of the pixels at Category 4`);
    assert.ok(out.cat4_fx.intensity > 0.85 && out.cat4_fx.rain_layers === 1, `storm look at 60 m/s: ${JSON.stringify(out.cat4_fx)}`);
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
