// web/damage.js and web/falling_path.js against gale-client's C (gale-web-damage-table,
// built from client/motion/tip_fall.c, damage_clock.c, falling_path.c and protocol/wire.h by
// tests/web/CMakeLists.txt): the tip-over angle within 1e-12 rad (both in double), the
// break height, the event clock and the kept leaf slots exactly, the shared falling-leaf
// path sample by sample exactly (both in float32, every operation rounded alike), and each
// leaf's variation exactly, its positions within 1e-5 m + 1e-6 relative (sinf/cosf of the
// yaw may differ from the correctly rounded ones by an ulp) and its landing time within 1e-4 s;
// the cut mask of broken branches exactly; a broken branch's tumbling fall in a steady wind
// (web/debris_path.js, in double where the C steps in float) within 1 mm and 1e-5 of each
// rotation entry over 100 s.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { tipFallAngle, tipFallBreak_m, damageEventStart_s, leafKept, DamageView, DAMAGE } from '../../web/damage.js';
import { fallingPathBuild, fallingVar, fallingPathEval, fallingPathLandTime } from '../../web/falling_path.js';
import { damageCutMask } from '../../web/damage.js';
import { DebrisPath, debrisFrameMatrix, debrisFrameAngles } from '../../web/debris_path.js';

const a = process.argv.slice(2);
if (a.includes('--help') || a.length !== 1) {
    console.log('usage: node test_damage_js.mjs GALE_WEB_DAMAGE_TABLE');
    process.exit(a.includes('--help') ? 0 : 2);
}
const rows = execFileSync(a[0], { encoding: 'utf8', maxBuffer: 64 << 20 }).trim().split('\n').map((l) => JSON.parse(l));
const by = (k) => rows.filter((r) => r.k === k);
const out = {};

let worst = 0;
for (const r of by('tip')) {
    const js = tipFallAngle(r.t_s, r.h_m);
    worst = Math.max(worst, Math.abs(js - r.rad));
    assert.ok(Math.abs(js - r.rad) <= 1e-12, `tip_fall_angle(${r.t_s} s, ${r.h_m} m): C ${r.rad}, JS ${js}`);
}
out.tip = { n: by('tip').length, worst_rad: worst };
for (const r of by('break')) assert.equal(tipFallBreak_m(r.tree), Math.fround(r.m), `tip_fall_break_m(${r.tree})`);
for (const r of by('clock')) {
    const js = damageEventStart_s(r.frame_tick, r.time_us, r.event_tick, r.hz);
    if (r.start_s === null) assert.ok(Number.isNaN(js), `damage_event_start_s(${r.frame_tick}, ${r.event_tick}): C NaN, JS ${js}`);
    else assert.ok(Math.abs(js - r.start_s) <= 1e-9, `damage_event_start_s(${r.frame_tick}, ${r.event_tick}): C ${r.start_s}, JS ${js}`);
}
const kept = by('kept')[0];
let nk = 0;
for (const [name, bits] of Object.entries(kept)) {
    if (!name.startsWith('tree')) continue;
    const tree = Number(name.slice(4));
    kept.levels.forEach((lv, l) => {
        for (let s = 0; s < 64; s++) {
            assert.equal(leafKept(tree, s * 7, lv), bits[l * 64 + s] === 1, `wire_damage_leaf_kept(${tree}, ${s * 7}, ${lv})`);
            nk++;
        }
    });
}
out.kept_compared = nk;

// the view: events are idempotent, a full frame heals first
const v = new DamageView(4);
v.apply(false, [{ tree: 2, node: 9, kind: DAMAGE.BRANCH, value: 0, tick: 5 }, { tree: 1, node: 3, kind: DAMAGE.BRANCH, value: 0, tick: 5 },
    { tree: 2, node: 9, kind: DAMAGE.BRANCH, value: 0, tick: 6 }, { tree: 3, kind: DAMAGE.SNAP, value: 64, tick: 7 },
    { tree: 3, kind: DAMAGE.UPROOT, value: 9, tick: 8 }, { tree: 0, kind: DAMAGE.STRIP, value: 20, tick: 8 }, { tree: 0, kind: DAMAGE.STRIP, value: 25, tick: 9 }]);
assert.deepEqual(v.broken, [1 * 2 ** 32 + 3, 2 * 2 ** 32 + 9]);
assert.deepEqual([v.fallen[3], v.fall_az[3], v.level[0]], [DAMAGE.SNAP, 64, 20]);
assert.equal(v.apply(true, [{ tree: 9, kind: DAMAGE.SNAP, value: 0, tick: 1 }]), 1);
assert.deepEqual([v.broken.length, v.fallen[3], v.level[0]], [0, 0, 32]);

const p = by('path')[0];
const js = fallingPathBuild();
assert.equal(js.n, p.n);
assert.equal(js.dt, Math.fround(p.dt));
assert.deepEqual(js.start, p.start);
assert.deepEqual(js.cont, p.cont);
assert.equal(js.fall_speed, Math.fround(p.fall_speed));
let firstOff = -1;
for (let i = 0; i < p.pos.length && firstOff < 0; i++) if (js.pos[i] !== Math.fround(p.pos[i])) firstOff = i;
assert.equal(firstOff, -1, `path sample ${Math.floor(firstOff / 3)}: C ${p.pos.slice(firstOff - firstOff % 3, firstOff - firstOff % 3 + 3)}, JS ${Array.from(js.pos.subarray(firstOff - firstOff % 3, firstOff - firstOff % 3 + 3))}`);
for (let i = 0; i < p.quat.length; i++) assert.equal(js.quat[i], Math.fround(p.quat[i]), `path orientation ${Math.floor(i / 4)}`);
out.path = { samples: p.n, start: p.start, cont: p.cont, fall_speed_ms: p.fall_speed, exact: true };

let worstPos = 0, worstLand = 0;
for (const r of by('leaf')) {
    const lv = fallingVar(js, r.seed);
    assert.deepEqual([lv.start, lv.yaw, lv.sx, lv.sy, lv.seed], [r.start, Math.fround(r.yaw), Math.fround(r.sx), Math.fround(r.sy), r.vseed], `falling_var_from_seed(${r.seed})`);
    r.tau.forEach((tau, i) => {
        const pj = fallingPathEval(js, lv, Math.fround(tau));
        for (let k = 0; k < 3; k++) {
            const c = r.pos[3 * i + k], d = Math.abs(pj[k] - c);
            worstPos = Math.max(worstPos, d);
            assert.ok(d <= 1e-5 + 1e-6 * Math.abs(c), `falling_path_eval(seed ${r.seed}, ${tau} s)[${k}]: C ${c}, JS ${pj[k]}`);
        }
    });
    const land = fallingPathLandTime(js, lv, Math.fround(r.h0), 600);
    worstLand = Math.max(worstLand, Math.abs(land - r.land_s));
    assert.ok(Math.abs(land - r.land_s) <= 1e-4, `falling_path_land_time(seed ${r.seed}, ${r.h0} m): C ${r.land_s}, JS ${land}`);
}
out.leaves = { n: by('leaf').length, worst_pos_m: worstPos, worst_land_s: worstLand };

for (const r of by('cut')) assert.deepEqual(Array.from(damageCutMask([-1, 0, 0, 1, 1, 2, 3, 3, 5, 6, 7, 7], [3, 5], r.keep === 1)), r.mask, `damage_cut_mask keep ${r.keep}`);
const deb = by('debris');
const r0 = debrisFrameMatrix(0.3, 0.2, 1.1);
r0.forEach((x, i) => assert.ok(Math.abs(x - deb[0].r0[i]) < 1e-6, `debris_frame_matrix[${i}]: C ${deb[0].r0[i]}, JS ${x}`));
const dp = new DebrisPath(7, 33, 100, [1, 2, 9], r0, [0.2, 0.1, 1], 2.5);
let worstC = 0, worstR = 0;
for (const r of deb) {
    dp.advance(r.t_s, (p) => [15, -4 + 0.1 * p[2], 0.5]);
    assert.equal(dp.landed, r.landed === 1, `debris landed at ${r.t_s} s`);
    assert.equal(dp.done(), r.done === 1, `debris done at ${r.t_s} s`);
    for (let k = 0; k < 3; k++) worstC = Math.max(worstC, Math.abs(dp.c[k] - r.c[k]));
    const rot = dp.rotation();
    for (let k = 0; k < 9; k++) worstR = Math.max(worstR, Math.abs(rot[k] - r.r[k]));
    assert.ok(Math.abs(dp.sink_m() - r.sink_m) < 1e-3, `debris sink at ${r.t_s} s: C ${r.sink_m}, JS ${dp.sink_m()}`);
    const ang = debrisFrameAngles(r.r);
    assert.ok(Math.abs(ang.fall - r.angles[1]) < 1e-5 && Math.abs(ang.yaw - r.angles[0]) < 1e-4, `debris_frame_angles at ${r.t_s} s`);
}
assert.ok(worstC < 1e-3, `debris centre off by ${worstC} m`);
assert.ok(worstR < 1e-5, `debris rotation off by ${worstR}`);
out.debris = { samples: deb.length, landed: deb[deb.length - 1].landed, worst_centre_m: worstC, worst_rotation: worstR };
console.log(JSON.stringify({ ...out, ok: true }));
