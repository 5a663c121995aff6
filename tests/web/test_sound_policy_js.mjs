// web/sound_policy.js against gale-client's sound policy (gale-web-sound-table, built from
// client/audio/sound_policy.h, sound_caption.c and sound_mix.c by tests/web/CMakeLists.txt):
// every number the two clients share is the same, and each law gives the same value (within
// 1e-5 relative: the C side computes in float) over a range of speeds, lengths, distances,
// bearings and diameters, the quiet preset resolves alike, the caption tables are the same
// keys and texts in the same order and pick the same captions.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import * as P from '../../web/sound_policy.js';

const a = process.argv.slice(2);
if (a.includes('--help') || a.length !== 1) {
    console.log('usage: node test_sound_policy_js.mjs GALE_WEB_SOUND_TABLE');
    process.exit(a.includes('--help') ? 0 : 2);
}
const c = JSON.parse(execFileSync(a[0], { encoding: 'utf8' }));
const val = (v) => (v === '-inf' ? -Infinity : v === 'inf' ? Infinity : v);
function near(got, want, what) {
    want = val(want);
    if (!Number.isFinite(want)) return assert.equal(got, want, what);
    assert.ok(Math.abs(got - want) <= 1e-5 * Math.max(1, Math.abs(want)), `${what}: page ${got}, client ${want}`);
}
let n = 0;
for (const [name, want] of Object.entries(c.numbers)) {
    assert.ok(name in P, `web/sound_policy.js has no ${name}`);
    const got = P[name];
    if (Array.isArray(want)) {
        assert.equal(got.length, want.length, `${name}: length`);
        want.forEach((v, i) => assert.equal(Math.fround(got[i]), Math.fround(v), `${name}[${i}]`));
    } else if (typeof want === 'object') {
        for (const [k, v] of Object.entries(want)) assert.equal(got[k], v, `${name}.${k}`);
    } else {
        assert.equal(Math.fround(got), Math.fround(val(want)), name);
    }
    n++;
}
for (const [u, bed, body, howl, g0, g1, g2, r1, r2, rdb] of c.by_speed) {
    near(P.bedDb(u), bed, `bedDb(${u})`);
    near(P.bodyHz(u), body, `bodyHz(${u})`);
    near(P.howlShare(u), howl, `howlShare(${u})`);
    [g0, g1, g2].forEach((g, k) => near(P.bandGain(k, u), g, `bandGain(${k}, ${u})`));
    near(P.rustleHz(u, 500, 1), r1, `rustleHz(${u}, 500, 1)`);
    near(P.rustleHz(u, 8000, 0.4), r2, `rustleHz(${u}, 8000, 0.4)`);
    near(P.rustleDb(u), rdb, `rustleDb(${u})`);
}
for (const [u, k, len, hz, db] of c.aeolian) {
    near(P.strouhalHz(u, P.SOUND_CLASS_D_M[k]), hz, `strouhalHz(${u}, class ${k})`);
    near(P.aeolDb(len, u, P.SOUND_CLASS_D_M[k]), db, `aeolDb(${len}, ${u}, class ${k})`);
}
for (const [d, w, ...ev] of c.by_distance) {
    near(P.nearWeight(d), w, `nearWeight(${d})`);
    ev.forEach((db, k) => near(P.eventLevelDb(k, d), db, `eventLevelDb(${k}, ${d})`));
}
for (const [rel, pan, gl, gr] of c.by_bearing) {
    near(P.soundPan(rel), pan, `soundPan(${rel})`);
    const [l, r] = P.panGains(pan);
    near(l, gl, `panGains(${pan})[0]`);
    near(r, gr, `panGains(${pan})[1]`);
}
for (const [d, k] of c.classes) assert.equal(P.classOf(d), k, `classOf(${d})`);
for (const [v, ceil, q, rv, rc] of c.loudness) {
    const got = P.resolveLoudness(v, ceil, q === 1);
    near(got.volume_db, rv, `resolveLoudness(${v}, ${ceil}, ${q}).volume_db`);
    near(got.ceiling_dbfs, rc, `resolveLoudness(${v}, ${ceil}, ${q}).ceiling_dbfs`);
}
assert.deepEqual(P.SOUND_CAPTIONS, c.captions, 'the caption tables');
for (const [u, hz, tone, ev, keys] of c.picks) {
    assert.deepEqual(P.captionPick(u, hz, tone, ev), keys, `captionPick(${u}, ${hz}, ${tone}, ${ev})`);
}
console.log(`sound policy: ${n} numbers, ${c.by_speed.length} speeds, ${c.aeolian.length} tones, ${c.by_distance.length} distances, ${c.by_bearing.length} bearings, ${c.classes.length} diameters, ${c.captions.length} captions, ${c.picks.length} picks agree`);
