// web/kiosk_scale.js and web/kiosk_text.js against gale-client's kiosk panel
// (gale-web-kiosk-table, built from client/kiosk/ by tests/web/CMakeLists.txt): the dial's
// band edges, sweep, top and labels, its angle at speeds through every band and the speed
// at angles over the sweep and beyond (float32, to the bit), the replay speeds, the
// messages a sequence of touches sends, the scenario lit for WEATHER names, the caption of
// every class and force, the compass points and band names in every language (the page's
// words are the shared texts' the build wrote, LANG_TEXTS_JS, each page key naming one that
// every language has); the band colours against kiosk_ui_draw.c's tables.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { pathToFileURL } from 'node:url';
import * as S from '../../web/kiosk_scale.js';
import { KIOSK_KEYS, kt, captionKey, caption, setKioskLang } from '../../web/kiosk_text.js';
import { setTexts } from '../../web/lang.js';

const a = process.argv.slice(2);
if (a.includes('--help') || a.length !== 3) {
    console.log('usage: node test_kiosk_js.mjs GALE_WEB_KIOSK_TABLE LANG_TEXTS_JS KIOSK_UI_DRAW_C');
    process.exit(a.includes('--help') ? 0 : 2);
}
const [table, textsJs, drawC] = a;
const { LANG_CODES, TEXTS } = await import(pathToFileURL(textsJs).href);
setTexts(LANG_CODES, TEXTS);
const c = JSON.parse(execFileSync(table, { encoding: 'utf8' }));
const f32 = Math.fround;
const n = {};

assert.equal(S.DIAL_MAX_MS, c.DIAL_MAX_MS, 'DIAL_MAX_MS');
assert.equal(S.DIAL_SWEEP_RAD, f32(c.DIAL_SWEEP_RAD), 'DIAL_SWEEP_RAD');
assert.equal(S.BANDS, c.BANDS, 'BANDS');
assert.deepEqual(S.BAND_LOWER_MS, c.BAND_LOWER_MS.map(f32), 'BAND_LOWER_MS');
assert.deepEqual(S.BAND_KEYS.map((k) => kt(k)), c.band_labels, 'band labels');
assert.deepEqual(S.REPLAY_SPEEDS, c.REPLAY_SPEEDS, 'REPLAY_SPEEDS');
for (const [v, angle, band] of c.angles) {
    const x = v === null ? NaN : v;
    assert.equal(S.dialAngle(x), f32(angle), `dialAngle(${v})`);
    assert.equal(S.bandOf(v === null ? 0 : f32(x)), band, `bandOf(${v})`);
}
n.angles = c.angles.length;
for (const [angle, v] of c.speeds) assert.equal(S.dialSpeed(f32(angle)), f32(v), `dialSpeed(${angle})`);
n.speeds = c.speeds.length;

// the touches kiosk_table.c makes, in its order
const m = new S.DialMessages();
const scen = ['gusty', 'andrew1992'];
for (const want of c.messages) {
    let got;
    if (want.act === 1) got = m.speed(f32(want.value));
    else if (want.act === 2) got = m.dir(f32(want.value));
    else if (want.act === 3) got = m.scenario(scen[want.index]);
    else if (want.act === 7) got = m.reset();
    else assert.fail(`act ${want.act}`);
    const exp = want.type === 1 ? { type: 'reset' } : { type: 'wind' };
    if ('speed_ms' in want) exp.speed_ms = f32(want.speed_ms);
    if ('dir_deg' in want) exp.dir_deg = f32(want.dir_deg);
    if ('scenario' in want) exp.scenario = want.scenario;
    assert.deepEqual(got, exp, `message of act ${want.act} value ${want.value}`);
}
n.messages = c.messages.length;

const list = c.scenarios.map(([name, title]) => ({ name, title }));
for (const [name, want] of c.running) {
    assert.equal(S.runningIndex({ name, flags: 0 }, list), want, `WEATHER name "${name}" lights`);
    // a dialled wind lights none, whatever name WEATHER carries (the dial holds it back)
    assert.equal(S.runningIndex({ name, flags: 2 }, list), -1, `WEATHER name "${name}" with DIAL lights none`);
}
n.running = c.running.length;

for (const [lang, ss, b, text] of c.captions) {
    setKioskLang(lang);
    assert.equal(caption(captionKey(ss, b)), text, `caption in ${lang} of class ${ss} force ${b}`);
}
n.captions = c.captions.length;
for (const [lang, d, name] of c.compass) {
    setKioskLang(lang);
    assert.equal(kt(S.compassKey(d)), name, `compass point in ${lang} of ${d}°`);
}
assert.equal(kt(S.compassKey(NaN)), '?');
n.compass = c.compass.length;
for (const [lang, b, name] of c.band_names) {
    setKioskLang(lang);
    assert.equal(kt(S.BAND_KEYS[b]), name, `band ${b} in ${lang}`);
}
// every page key names a text every language has
for (const lang of LANG_CODES) {
    for (const [page, key] of Object.entries(KIOSK_KEYS)) assert.ok(TEXTS[lang][key] !== undefined, `${page}: ${key} missing in ${lang}`);
}
setKioskLang('en');
n.page_keys = Object.keys(KIOSK_KEYS).length;

// kiosk_ui_draw.c's colour tables, read from its source
const src = readFileSync(drawC, 'utf8');
const floats = (s) => [...s.matchAll(/-?\d+\.\d+f/g)].map((x) => parseFloat(x[0]));
const body = (name) => {
    const mm = src.match(new RegExp(`static const float ${name}\\[[^=]*=\\s*\\{([\\s\\S]*?)\\};`));
    assert.ok(mm, `${drawC}: no table ${name}`);
    return floats(mm[1]);
};
const bands = body('band_rgb');
assert.equal(bands.length, 3 * S.BANDS, 'band_rgb: 3 floats a band');
S.BAND_RGB.forEach((rgb, b) => assert.deepEqual(rgb, bands.slice(3 * b, 3 * b + 3), `band ${b}'s colour`));
for (const [name, js] of [['ink', S.INK], ['dim_ink', S.DIM_INK], ['accent', S.ACCENT], ['dark_ink', S.DARK_INK],
    ['panel_rgba', S.PANEL_RGBA], ['button_rgba', S.BUTTON_RGBA], ['pressed_rgba', S.PRESSED_RGBA]]) {
    const cv = body(name);
    assert.deepEqual(js, cv.slice(0, js.length), `${name}`);
}
const dim = src.match(/on \? 1\.0f : (\d\.\d+)f/);
assert.ok(dim, `${drawC}: no dimmed band alpha`);
assert.equal(S.BAND_DIM_ALPHA, parseFloat(dim[1]), 'a dimmed band\'s alpha');

// kt: arguments in place, a missing key as itself
assert.equal(kt('dial.ms', 60), '60 m/s');
assert.equal(kt('replay.pos', '1:00', '5:00'), 'Replay 1:00 of 5:00');
assert.equal(kt('no.such.key'), 'no.such.key');
console.log(JSON.stringify({ ...n, ok: true }));
