// web/jitter.js and the browser's blend of quantised snapshots against gale-client's jitter
// buffer (gale-web-jitter-table, built from client/playout/jitter.c by tests/web/CMakeLists.txt):
// over the same inserts (in order, out of order, duplicate, late, evicting, across a change
// of steps and a reset) the buffer answers the same, samples fall between the same ticks,
// the stats agree, and q blended from the quantised values with the shader's weights
// (blendWeights, rounded to f32 as the uniforms are) matches the native client's q within
// 1e-6 of Σ_k |c_k q_k| (both round the weights and products to f32: a few units in the
// last place of the largest term).
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { Jitter, blendWeights } from '../../web/jitter.js';

const a = process.argv.slice(2);
if (a.includes('--help') || a.length !== 1) {
    console.log('usage: node test_jitter_js.mjs GALE_WEB_JITTER_TABLE');
    process.exit(a.includes('--help') ? 0 : 2);
}
const lines = execFileSync(a[0], { encoding: 'utf8' }).trim().split('\n').map((l) => JSON.parse(l));
const sc = lines[0].scene;
const ops = lines.filter((l) => l.op);
const stats = lines.find((l) => l.stats).stats;
const j = new Jitter(sc.n_trees * sc.stride, sc.capacity, 0.1);
const RESULT = ['inserted', 'duplicate', 'late'];
const qw = new Float32Array(4 * sc.stride);
let worst = 0, samples = 0, blends = 0, held = 0;
for (const o of ops) {
    if (o.op === 'reset') {
        j.reset();
        continue;
    }
    if (o.op === 'insert') {
        const r = j.insert(o.tick, o.t_s, Int16Array.from(o.Q), { step: o.step.map((s) => Float32Array.from(s)) });
        assert.equal(r, RESULT[o.result], `insert tick ${o.tick} at ${o.t_s} s`);
        continue;
    }
    const w = j.weights(o.t_s);
    const where = `sample at ${o.t_s} s`;
    if (o.result !== 0) {
        assert.equal(w, null, `${where}: empty`);
        continue;
    }
    samples++;
    assert.ok(w && w.n >= 1 && w.n <= 4, `${where}: weights`);
    const ticks = w.n === 1 ? [w.snaps[0].tick, w.snaps[0].tick] : [w.snaps[0].tick, w.snaps[1].tick];
    assert.deepEqual(ticks, [o.tick0, o.tick1], `${where}: bracketing ticks`);
    if (w.n === 1) held++;
    if (w.n === 4) blends++;
    for (let t = 0; t < sc.n_trees; t++) {
        blendWeights(w, sc.species[t], qw);
        for (let m = 0; m < sc.stride; m++) {
            const i = t * sc.stride + m;
            let v = 0, mag = 0;
            for (let k = 0; k < w.n; k++) {
                v += qw[4 * m + k] * w.snaps[k].q[i];
                mag += Math.abs(qw[4 * m + k] * w.snaps[k].q[i]);
            }
            const tol = 1e-6 * mag + 1e-12, d = Math.abs(v - o.q[i]);
            worst = Math.max(worst, d / tol);
            assert.ok(d <= tol, `${where}: tree ${t} mode ${m}: ${v} blended, ${o.q[i]} in client/playout/jitter.c`);
        }
    }
}
for (const k of Object.keys(stats)) assert.equal(j.stats[k], stats[k], `stats.${k}`);
assert.ok(samples >= 25 && blends >= 10 && held >= 4, `the sequence samples blends of four and holds (${samples}, ${blends}, ${held})`);
console.log(JSON.stringify({ ok: true, samples, blends_of_four: blends, held, worst_of_tolerance: worst, stats: j.stats }));
