// web/storm_fx.js against client/render/storm_fx.c: the C function's look (gale-web-storm-table,
// built from client/render/storm_fx.c by tests/web/CMakeLists.txt) for a grid of winds, directions
// and qualities, and the browser's for the same inputs, agree field by field within 2e-5
// (the C code computes in float, the page in double: a few float ulps of values <= 200).
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { stormFxFromWeather, stormFxQualityParse, STORM_FX_OFF, STORM_FX_LOW, STORM_FX_HIGH } from '../../web/storm_fx.js';

const a = process.argv.slice(2);
if (a.includes('--help') || a.length !== 1) {
    console.log('usage: node test_storm_fx_js.mjs GALE_WEB_STORM_TABLE');
    process.exit(a.includes('--help') ? 0 : 2);
}
const rows = execFileSync(a[0], { encoding: 'utf8' }).trim().split('\n').map((l) => JSON.parse(l));
assert.ok(rows.length >= 100, `only ${rows.length} rows from ${a[0]}`);
const TOL = 2e-5;
let compared = 0, worst = 0;
for (const c of rows) {
    // the inputs as the wire carries them (float32), printed with 9 digits: read back exactly
    const ms = c.sustained_ms === null ? NaN : Math.fround(c.sustained_ms);
    const js = stormFxFromWeather(ms, Math.fround(c.dir_from_deg), c.q);
    const where = `${ms} m/s from ${c.dir_from_deg}°, quality ${c.q}`;
    for (const [k, v] of Object.entries(c)) {
        if (k === 'sustained_ms' || k === 'dir_from_deg' || k === 'q') continue;
        assert.ok(k in js, `${where}: web/storm_fx.js has no ${k}`);
        const want = Array.isArray(v) ? v : [v], got = Array.isArray(js[k]) ? js[k] : [js[k]];
        assert.equal(got.length, want.length, `${where}: ${k} length`);
        const scale = Math.max(1, Math.hypot(...want));
        for (let i = 0; i < want.length; i++) {
            const d = Math.abs(got[i] - want[i]) / scale;
            worst = Math.max(worst, d);
            assert.ok(d <= TOL, `${where}: ${k}[${i}] is ${got[i]} in the browser, ${want[i]} in client/render/storm_fx.c`);
            compared++;
        }
    }
}
assert.equal(stormFxQualityParse('off'), STORM_FX_OFF);
assert.equal(stormFxQualityParse('low'), STORM_FX_LOW);
assert.equal(stormFxQualityParse('high'), STORM_FX_HIGH);
assert.equal(stormFxQualityParse('medium'), null);
// the storm is on in this grid (not a table of calm looks)
assert.ok(rows.some((c) => c.rain_layers === 3) && rows.some((c) => c.spray > 0.9) && rows.some((c) => c.intensity === 1));
console.log(JSON.stringify({ rows: rows.length, values: compared, worst_rel_diff: worst, ok: true }));
