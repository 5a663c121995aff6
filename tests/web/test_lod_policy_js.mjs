// web/lod_policy.js against gale-client's policy (gale-web-lod-table, built from
// client/render/lod_policy.h and render_lod.c by tests/web/CMakeLists.txt): every number the
// two clients share is the same, each level keeps as many leaves for the same leaf count,
// a scene's box gives the same fog distance, and a standing tree outside the fade bands is
// at the same level at the same distance, and a fallen tree's impostor row holds the same
// fall (render_bill_fall_code, impFall).
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import * as P from '../../web/lod_policy.js';
import { levelAt } from '../../web/lod_select.js';
import { impFall } from '../../web/render_list.js';

const a = process.argv.slice(2);
if (a.includes('--help') || a.length !== 1) {
    console.log('usage: node test_lod_policy_js.mjs GALE_WEB_LOD_TABLE');
    process.exit(a.includes('--help') ? 0 : 2);
}
const c = JSON.parse(execFileSync(a[0], { encoding: 'utf8' }));
const f32 = (x) => Math.fround(x);
let n = 0;
for (const [name, want] of Object.entries(c)) {
    if (['leaves_at', 'fog', 'levels', 'bill_fall'].includes(name)) continue;
    assert.ok(name in P, `web/lod_policy.js has no ${name}`);
    const got = P[name];
    if (name === 'LOD') {
        for (const [k, v] of Object.entries(want)) assert.equal(got[k], v, `LOD.${k}`);
    } else if (Array.isArray(want)) {
        assert.equal(got.length, want.length, `${name}: length`);
        want.forEach((v, i) => assert.equal(typeof v === 'number' ? f32(got[i]) : got[i], typeof v === 'number' ? f32(v) : v, `${name}[${i}]`));
    } else {
        assert.equal(f32(got), f32(want), name);
    }
    n++;
}
for (const [count, ...want] of c.leaves_at) {
    want.forEach((k, l) => assert.equal(P.leavesAt(count, P.LOD_LEAF_SHARE[l]), k, `leavesAt(${count}) at level ${l}`));
}
for (const [x0, y0, x1, y1, want] of c.fog) {
    assert.ok(Math.abs(P.fogForScene([x0, y0], [x1, y1]) - want) <= 1e-3 * want, `fog of box ${x0},${y0}..${x1},${y1}`);
}
for (const [d, want] of c.levels) {
    assert.equal(levelAt(d, 1), want, `level at ${d} m`);
}
for (const [fall, az, want] of c.bill_fall) {
    // (the damage code of a tree of that fall, no leaves lost, standing on its root: the angle)
    const got = Math.fround(impFall(fall, az));
    assert.ok(Math.abs(got - want) <= 4e-5 && Math.floor(got) === Math.floor(want), `impFall(${fall}, ${az}): ${got}, gale-client ${want}`);
}
console.log(`lod policy: ${n} numbers, ${c.leaves_at.length} leaf counts, ${c.fog.length} fog boxes, ${c.levels.length} distances, ${c.bill_fall.length} falls agree`);
