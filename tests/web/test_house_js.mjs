// web/house.js against gale-client's house mesh (gale-web-house-table, built from
// client/render/render_house.c by tests/web/CMakeLists.txt): for boxes long in x, long in y, a
// thin slab (roof pitch capped), a square and a point, the same vertices in the same order,
// every float within 1e-5 of the box's size (the C code computes in float).
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { houseMesh, housesMesh, HOUSE_FLOATS, HOUSE_VERTS } from '../../web/house.js';

const a = process.argv.slice(2);
if (a.includes('--help') || a.length !== 1) {
    console.log('usage: node test_house_js.mjs GALE_WEB_HOUSE_TABLE');
    process.exit(a.includes('--help') ? 0 : 2);
}
const rows = execFileSync(a[0], { encoding: 'utf8' }).trim().split('\n').map((l) => JSON.parse(l));
assert.ok(rows.length >= 5);
let worst = 0;
for (const { box, mesh } of rows) {
    const b = box.map(Math.fround);
    const js = new Float64Array(HOUSE_VERTS * HOUSE_FLOATS);
    assert.equal(houseMesh(b, js), mesh.length, `box ${box}: float count`);
    const size = Math.max(1, ...b.map(Math.abs));
    for (let k = 0; k < mesh.length; k++) {
        const d = Math.abs(js[k] - mesh[k]) / size;
        worst = Math.max(worst, d);
        assert.ok(d <= 1e-5, `box ${box}: vertex ${Math.floor(k / HOUSE_FLOATS)} float ${k % HOUSE_FLOATS} is ${js[k]} in the browser, ${mesh[k]} in client/render/render_house.c`);
    }
}
const all = housesMesh(rows.map((r) => r.box));
assert.equal(all.length, rows.length * HOUSE_VERTS * HOUSE_FLOATS);
console.log(JSON.stringify({ boxes: rows.length, worst_share_of_size: worst, ok: true }));
