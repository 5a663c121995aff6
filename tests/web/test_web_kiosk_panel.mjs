// The kiosk page's touch panel (web/kiosk_dial.js, kiosk_panel.js, kiosk.js) against a real
// gale-server whose scenario library holds 25 scenarios (the shipped 12 and 13 more replays,
// stand-ins for a storm library: copies of Andrew 1992's track under other names), with a
// finger (tests/web/kiosk_touch.mjs):
// - dragging the dial sends wind speed_ms a few times a second and the value under the
//   finger on release, no direction until one is chosen; the compass sends dir_deg =
//   270° − bearing with the dialled speed (PROTOCOL.md "The kiosk's touch panel"); the dial
//   then shows the server's WEATHER (figure, needle angle, lit band), the compass its
//   direction, the caption the class's text of web/kiosk_text.js;
// - the lit scenario follows WEATHER: a steady scenario picked is lit alone, a dialled storm
//   lights none ("Gusty afternoon" is not left lit), a replay is lit and its controls shown
//   (×10, pause, landfall each sent and shown back), a dial during the replay lights none;
// - the replay library pages: every replay is reachable through the pager;
// - every visible control is at least 44 × 44 CSS px and every visible text at least 4.5:1
//   over its backing (relative luminance, WCAG 2.x; an unknown scene behind a translucent
//   backing taken as white or black, whichever is worse), at 1280×720 and 1920×1080, at
//   calm, in a dialled Category 4 and in a replay;
// - with less motion asked for (prefers-reduced-motion, emulated) the storm has no rain
//   streaks, and they come back when it is not;
// - reset sends reset. Screenshots of each state at both sizes go to WORK_DIR.
import assert from 'node:assert/strict';
import { readFileSync, writeFileSync, mkdirSync, readdirSync } from 'node:fs';
import path from 'node:path';
import { args, startServer, startBrowser, waitFor, readMetric, until, useTexts } from './harness.mjs';
import { dialTo, compassTo } from './kiosk_touch.mjs';
import { dialAngle, towardDeg, ssClass } from '../../web/kiosk_scale.js';
import { unitSustained, UNIT } from '../../web/hud_text.js';
import { kt, caption } from '../../web/kiosk_text.js';

const [server, work, root] = args('usage: node test_web_kiosk_panel.mjs GALE_SERVER WORK_DIR SOURCE_ROOT');
const TOKEN = 'web-kiosk-panel-5d21';
await useTexts(server);
mkdirSync(work, { recursive: true });
const tokenFile = path.join(work, 'token');
writeFileSync(tokenFile, `${TOKEN}\n`, { mode: 0o600 });

// the library: configs/scenes/clearing.json (species by absolute path) beside a scenarios
// folder of the shipped scenarios and 13 more replays
const lib = path.join(work, 'lib');
mkdirSync(path.join(lib, 'scenes'), { recursive: true });
mkdirSync(path.join(lib, 'scenarios'), { recursive: true });
const scene = JSON.parse(readFileSync(path.join(root, 'configs/scenes/clearing.json'), 'utf8'));
for (const sp of scene.species) sp.file = path.join(root, 'configs/species', path.basename(sp.file));
writeFileSync(path.join(lib, 'scenes/clearing.json'), JSON.stringify(scene));
const shipped = path.join(root, 'configs/scenarios');
// the shipped library: its replays by title (a replay is a file with a "hurricane" section)
const REPLAYS = [];
for (const f of readdirSync(shipped).filter((x) => x.endsWith('.json'))) {
    const text = readFileSync(path.join(shipped, f), 'utf8');
    writeFileSync(path.join(lib, 'scenarios', f), text);
    const j = JSON.parse(text);
    if (j.kind === 'hurricane') REPLAYS.push(j.name);
}
assert.ok(REPLAYS.length >= 15, `the shipped library holds ${REPLAYS.length} replays`);
const srv = await startServer(server, ['--cache', path.join(work, '..', 'cache'), '--config', path.join(lib, 'scenes/clearing.json'),
    '--kiosk-token-file', tokenFile]);
const metric = (name) => readMetric(srv.url, name);

// Every visible control's size and every visible text's contrast over its backing.
const audit = (page) => page.evaluate(() => {
    const rgba = (s) => {
        const m = s.match(/rgba?\(([^)]+)\)/);
        if (!m) return null;
        const v = m[1].split(/[\s,/]+/).filter(Boolean).map(Number);
        return [v[0], v[1], v[2], v.length > 3 ? v[3] : 1];
    };
    const over = (top, under) => [0, 1, 2].map((k) => top[k] * top[3] + under[k] * (1 - top[3]));
    const lum = (c) => {
        const f = (x) => { x /= 255; return x <= 0.04045 ? x / 12.92 : ((x + 0.055) / 1.055) ** 2.4; };
        return 0.2126 * f(c[0]) + 0.7152 * f(c[1]) + 0.0722 * f(c[2]);
    };
    const ratio = (a, b) => { const [l1, l2] = [lum(a), lum(b)].sort((x, y) => y - x); return (l1 + 0.05) / (l2 + 0.05); };
    const shown = (e) => e.getClientRects().length > 0 && getComputedStyle(e).visibility !== 'hidden';
    // the backing layers of an element, page first: every ancestor's background colour and,
    // for SVG text, the SVG discs and rings drawn under its centre
    const layers = (e) => {
        const out = [];
        for (let a = e; a && a.nodeType === 1; a = a.parentElement) {
            const c = rgba(getComputedStyle(a).backgroundColor);
            if (c && c[3] > 0 && !(a instanceof SVGElement)) out.unshift(c);
        }
        if (e instanceof SVGTextElement) {
            const b = e.getBBox(), x = b.x + b.width / 2, y = b.y + b.height / 2;
            for (const c of e.ownerSVGElement.querySelectorAll('circle')) {
                if (c.style.display === 'none') continue;
                const cs = getComputedStyle(c), r = Number(c.getAttribute('r')), d = Math.hypot(x - Number(c.getAttribute('cx') || 0), y - Number(c.getAttribute('cy') || 0));
                const sw = Number(c.getAttribute('stroke-width') || 0);
                if (cs.fill !== 'none' && d <= r) out.push(rgba(cs.fill).map((v, k) => (k === 3 ? v * Number(cs.fillOpacity) : v)));
                else if (cs.stroke !== 'none' && Math.abs(d - r) <= sw / 2) out.push(rgba(cs.stroke));
            }
        }
        return out;
    };
    const texts = [];
    for (const e of document.querySelectorAll('body *')) {
        if (!shown(e) || e.closest('[hidden]') || e.closest('svg') && !(e instanceof SVGTextElement)) continue;
        const own = [...e.childNodes].some((n) => n.nodeType === 3 && n.textContent.trim());
        if (!own) continue;
        const cs = getComputedStyle(e), fg = rgba(e instanceof SVGElement ? cs.fill : cs.color);
        let worst = Infinity;
        for (const base of [[255, 255, 255], [0, 0, 0]]) {
            let bg = base;
            for (const l of layers(e)) bg = over(l, bg);
            worst = Math.min(worst, ratio(over(fg, bg), bg));
        }
        texts.push({ text: e.textContent.trim().slice(0, 40), id: e.id || e.className.baseVal || e.className || e.tagName, ratio: worst });
    }
    const controls = [];
    for (const e of document.querySelectorAll('button, [role=slider], input, select, a[href]')) {
        if (!shown(e) || e.closest('[hidden]')) continue;
        const r = e.getBoundingClientRect();
        controls.push({ what: e.id || e.textContent.trim().slice(0, 30) || e.getAttribute('aria-label'), w: r.width, h: r.height });
    }
    return { texts, controls };
});
const checkAudit = async (page, what) => {
    const a = await audit(page);
    const low = a.texts.filter((t) => t.ratio < 4.5);
    assert.deepEqual(low, [], `${what}: text under 4.5:1 over its backing`);
    const small = a.controls.filter((c) => c.w < 44 || c.h < 44);
    assert.deepEqual(small, [], `${what}: controls under 44 × 44 px`);
    assert.ok(a.texts.length > 20 && a.controls.length > 10, `${what}: ${a.texts.length} texts, ${a.controls.length} controls audited`);
    return { texts: a.texts.length, controls: a.controls.length, min_ratio: Math.min(...a.texts.map((t) => t.ratio)),
        min_control_px: Math.min(...a.controls.map((c) => Math.min(c.w, c.h))) };
};
const lit = (page) => page.evaluate(() => [...document.querySelectorAll('button.scen[aria-pressed=true]')].map((b) => b.textContent));
const shot = async (page, name) => {
    for (const [w, h] of [[1280, 720], [1920, 1080]]) {
        await page.setViewportSize({ width: w, height: h });
        await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
        await page.screenshot({ path: path.join(work, `panel-${name}-${w}x${h}.png`) });
        out.audit[`${name}_${w}`] = await checkAudit(page, `${name} at ${w}×${h}`);
    }
    await page.setViewportSize({ width: 1280, height: 720 });
    await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
};

const ctx = await startBrowser(work, { width: 1280, height: 720 });
const out = { audit: {} };
const T0 = Date.now();
const step = (what) => process.stderr.write(`${((Date.now() - T0) / 1000).toFixed(1)} s: ${what}\n`);
try {
    const page = await ctx.newPage();
    const sent = [];
    page.on('websocket', (ws) => ws.on('framesent', (f) => {
        if (typeof f.payload !== 'string') return;
        const m = JSON.parse(f.payload);
        if (m.type === 'wind' || m.type === 'reset') sent.push({ ...m, at_ms: Date.now() });
    }));
    // the messages sent after the k-th once at least n more have come (the page's socket
    // frames reach the test a little after the page sends them) and a moment has passed
    const settle = async (k, n = 1) => {
        await until(async () => sent.length >= k + n, 20, `${n} message(s) sent`);
        await new Promise((r) => setTimeout(r, 400));
    };
    const since = (k) => sent.slice(k).map(({ at_ms, token, ...m }) => { assert.equal(token, TOKEN, 'every control message carries the token'); return m; });
    await page.goto(`${srv.url}/kiosk?attract=3600#token=${TOKEN}`);
    await waitFor(page, () => window.gale && window.gale.framesDrawn >= 3 && window.gale.weather && window.gale.welcome, null, 120, 'kiosk live and drawn');
    out.scenarios = await page.evaluate(() => window.gale.welcome.scenarios.length);
    assert.equal(out.scenarios, 25, 'the library\'s 25 scenarios');
    await shot(page, 'calm');

    step('every replay reachable');
    // every replay reachable through the pager; the steady winds all on their page(s)
    const names = new Set();
    const pages = await page.evaluate(() => (document.querySelector('#replays .page-at') || { textContent: '1 / 1' }).textContent);
    out.replay_pages = Number(pages.split('/')[1]);
    assert.ok(out.replay_pages >= 2, `16 replays at 1280×720 page: ${pages}`);
    for (let p = 0; p < out.replay_pages; p++) {
        const at = await page.$eval('#replays .page-at', (e) => e.textContent);
        assert.equal(at, `${p + 1} / ${out.replay_pages}`, 'the pager says which page');
        for (const t of await page.$$eval('#replays button.scen', (bs) => bs.map((b) => b.textContent))) names.add(t);
        await page.click('#replays .page-next');
    }
    out.replays_seen = [...names];
    for (const n of REPLAYS) assert.ok(names.has(n), `replay ${n} not reachable through the pager: ${[...names].join(', ')}`);
    assert.equal(names.size, 16);

    step('the dial');
    // the dial: a drag from a breeze to Category 4
    let k = sent.length;
    const t0 = Date.now();
    await dialTo(page, 64, { from: 5, steps: 12, ms: 1500 });
    const drag_s = (Date.now() - t0) / 1000;
    await settle(k, 2);
    let msgs = since(k);
    out.dial_messages = msgs.length;
    assert.ok(msgs.length >= 2 && msgs.length <= drag_s / 0.25 + 2, `${msgs.length} messages over a ${drag_s} s drag: a few a second`);
    for (const m of msgs) assert.deepEqual(Object.keys(m).sort(), ['speed_ms', 'type'], `a dial message: ${JSON.stringify(m)}`);
    const dialled = msgs.at(-1).speed_ms;
    assert.ok(Math.abs(dialled - 64) < 1, `released at ${dialled} m/s, the finger at 64`);
    await until(async () => (await metric('gale_wind_dial')) === 1 && Math.abs((await metric('gale_wind_sustained_meters_per_second')) - dialled) < 0.5, 60, 'the server\'s wind at the dialled speed');
    await waitFor(page, (v) => Math.abs(window.gale.weather.sustained_ms - v) < 0.5 && (window.gale.weather.flags & 2), dialled, 30, 'WEATHER at the dialled speed');
    const face = await page.evaluate(() => {
        const d = document.getElementById('dial'), w = window.gale.weather;
        return { ms: w.sustained_ms, num: d.querySelector('.dial-num').textContent, band: d.dataset.band,
            angle: Number(d.querySelector('.dial-needle').dataset.angle), hint: d.querySelector('.dial-hint').textContent,
            lit: d.querySelector('.dial-label.on').textContent, caption: document.getElementById('caption').textContent, ss: w.ss_class };
    });
    // English reads mph first, kept inside the category's range
    assert.equal(face.num, kt('dial.mph', unitSustained(face.ms, UNIT.MPH, ssClass(face.ms))), 'the dial\'s figure is WEATHER\'s');
    assert.equal(face.angle, dialAngle(face.ms), 'the needle at WEATHER\'s wind');
    assert.equal(face.band, '7', 'the Category 4 band lit');
    assert.equal(face.lit, kt('band.cat4'));
    assert.equal(face.hint, kt('dial.held'), 'the dial says it holds the wind');
    assert.equal(face.ss, 5);
    assert.equal(face.caption, caption('cat4'), 'the Category 4 caption');
    assert.deepEqual(await lit(page), [], 'a dialled storm lights no scenario');

    step('the compass');
    // the compass: wind from the north-west, with the dialled speed
    k = sent.length;
    await compassTo(page, 315);
    await settle(k);
    msgs = since(k);
    assert.equal(msgs.length, 1, `one message for a touch on the compass: ${JSON.stringify(msgs)}`);
    assert.ok(Math.abs(msgs[0].dir_deg - towardDeg(315)) < 1.5 && msgs[0].speed_ms === dialled, `compass message ${JSON.stringify(msgs[0])}: dir_deg 270 − 315 + 360 = ${towardDeg(315)}, speed ${dialled}`);
    await waitFor(page, () => Math.abs(window.gale.weather.dir_from_deg - 315) < 2, null, 30, 'WEATHER from the north-west');
    assert.equal(await page.$eval('#compass .comp-title', (e) => e.textContent), kt('compass.title', kt('compass.NW')));

    step('less motion asked');
    // less motion asked for: no rain streaks in the storm; back when not asked
    assert.equal(await page.evaluate(() => window.gale.r.fx.rain_layers), 1, 'rain streaks at Category 4');
    await page.emulateMedia({ reducedMotion: 'reduce' });
    await waitFor(page, () => window.gale.r.fx.rain_layers === 0 && window.gale.r.fx.rain > 0, null, 20, 'no rain streaks with less motion');
    await shot(page, 'cat4');
    await page.emulateMedia({ reducedMotion: 'no-preference' });
    await waitFor(page, () => window.gale.r.fx.rain_layers === 1, null, 20, 'rain streaks back');

    step('a steady scenario');
    // a steady scenario: lit alone; then a dialled storm: nothing lit
    k = sent.length;
    await page.click('#steady button.scen >> text=Gusty afternoon');
    await settle(k);
    assert.deepEqual(since(k), [{ type: 'wind', scenario: 'gusty' }]);
    await waitFor(page, () => window.gale.weather.name === 'Gusty afternoon' && !(window.gale.weather.flags & 2), null, 30, 'WEATHER runs Gusty afternoon');
    await waitFor(page, () => [...document.querySelectorAll('button.scen[aria-pressed=true]')].map((b) => b.textContent).join() === 'Gusty afternoon', null, 10, 'Gusty afternoon lit');
    // the dial shows the scenario's wind, not the one dialled before
    await waitFor(page, () => !document.getElementById('dial').querySelector('.dial-hint.dial-accent') && Math.abs(window.gale.weather.sustained_ms - 11) < 3
        && document.querySelector('#dial .dial-num').textContent === `${Math.floor(window.gale.weather.sustained_ms / 0.44704 + 0.5)} mph`, null, 60, 'the dial at Gusty afternoon\'s wind (in mph, a breeze\'s: no category to keep it in)');
    await dialTo(page, 64, { from: 20, steps: 6, ms: 600 });
    await waitFor(page, () => window.gale.weather.flags & 2, null, 30, 'the dial holds the wind');
    await page.evaluate(() => new Promise((r) => setTimeout(r, 500)));
    out.dialled_weather_name = await page.evaluate(() => window.gale.weather.name);
    assert.deepEqual(await lit(page), [], `a dialled storm (WEATHER name "${out.dialled_weather_name}") lights no scenario`);

    step('a replay');
    // a replay: lit, its controls shown and answering
    assert.equal(await page.evaluate(() => document.getElementById('replay').hidden), true, 'no replay controls without a replay');
    for (let p = 0; p < out.replay_pages && !(await page.$('#replays button.scen >> text=Charley 2004')); p++) await page.click('#replays .page-next');
    k = sent.length;
    await page.click('#replays button.scen >> text=Charley 2004');
    await settle(k);
    assert.deepEqual(since(k), [{ type: 'wind', scenario: 'charley2004' }]);
    await waitFor(page, () => (window.gale.weather.flags & 1) && window.gale.weather.name === 'Charley 2004', null, 30, 'WEATHER replays Charley');
    await waitFor(page, () => !document.getElementById('replay').hidden, null, 10, 'replay controls shown');
    assert.deepEqual(await lit(page), ['Charley 2004'], 'the running replay lit');
    k = sent.length;
    await page.click('[data-speed="10"]');
    await waitFor(page, () => Math.abs(window.gale.weather.replay_speed - 10) < 0.5, null, 30, 'replay at ×10');
    await waitFor(page, () => document.querySelector('[data-speed="10"]').getAttribute('aria-pressed') === 'true', null, 5, '×10 lit');
    await page.click('#pause');
    await waitFor(page, () => window.gale.weather.flags & 16, null, 30, 'replay paused');
    await waitFor(page, () => document.getElementById('pause-text').textContent === 'Play', null, 5, 'the pause button offers play');
    await page.click('#landfall');
    await waitFor(page, () => Math.abs(window.gale.weather.storm_min) < 1, null, 30, 'replay at landfall');
    await settle(k, 3);
    assert.deepEqual(since(k), [{ type: 'wind', replay_speed: 10 }, { type: 'wind', replay_paused: true }, { type: 'wind', replay_at_min: 0 }]);
    await waitFor(page, (t) => document.getElementById('replay-at').textContent === t, kt('replay.at'), 5, 'the replay says it is at landfall');
    out.replay_head = await page.$eval('.replay-head', (e) => e.textContent.replace(/\s+/g, ' ').trim());
    await shot(page, 'replay');
    step('a dial during the replay');
    // a dial during the replay lights none
    await dialTo(page, 30, { from: 40, steps: 4, ms: 400 });
    await waitFor(page, () => window.gale.weather.flags & 2, null, 30, 'the dial holds the wind in the replay');
    assert.deepEqual(await lit(page), [], 'a dial during a replay lights no scenario');
    step('reset');
    // reset
    k = sent.length;
    await page.click('#reset');
    await settle(k);
    assert.deepEqual(since(k), [{ type: 'reset' }]);
    await until(async () => (await metric('gale_wind_dial')) === 0, 30, 'reset dropped the dial');
    // keys move the dial a whole m/s a press, from the last one pressed
    k = sent.length;
    await page.focus('#dial');
    await page.keyboard.press('Home');
    for (let i = 0; i < 3; i++) await page.keyboard.press('ArrowUp');
    await settle(k, 4);
    assert.deepEqual(since(k).map((m) => m.speed_ms), [0, 1, 2, 3], 'Home and three ArrowUp presses');
    assert.deepEqual(ctx.errors, []);
    console.log(JSON.stringify({ ...out, ok: true }));
} finally {
    await ctx.close();
    await srv.stop();
}
