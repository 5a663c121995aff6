// web/hold.js against gale-client's reduced view (gale-web-hold-table, built from
// client/playout/hold.c by tests/web/CMakeLists.txt): over the same scenes, points and
// limits, the same centre, the same trees held, and the same radius, edge and view radius.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { holdCentre, holdNearest, holdViewRadius } from '../../web/hold.js';

const a = process.argv.slice(2);
if (a.includes('--help') || a.length !== 1) {
    console.log('usage: node test_hold_js.mjs GALE_WEB_HOLD_TABLE');
    process.exit(a.includes('--help') ? 0 : 2);
}
const lines = execFileSync(a[0], { encoding: 'utf8', maxBuffer: 64 << 20 }).trim().split('\n').map((l) => JSON.parse(l));
let rows = null, scene = '', cases = 0, reduced = 0;
for (const l of lines) {
    if (l.scene) {
        scene = l.scene;
        rows = [];
        for (let i = 0; i < l.xy.length; i += 2) rows.push([0, l.xy[i], l.xy[i + 1], 0, 0, 1]);
        assert.deepEqual(holdCentre(rows), l.centre, `${scene}: centre`);
        continue;
    }
    const h = holdNearest(rows, l.cx, l.cy, l.limit), where = `${scene}: ${l.limit} nearest (${l.cx}, ${l.cy})`;
    assert.equal(h.n_held, l.n_held, `${where}: trees held`);
    assert.deepEqual(Array.from(h.held), l.held, `${where}: which trees`);
    assert.equal(h.radius_m, l.radius_m, `${where}: radius`);
    assert.equal(h.edge_m, l.edge_m, `${where}: edge`);
    assert.equal(holdViewRadius(h, 7.5), l.view_radius_m, `${where}: view radius`);
    cases++;
    reduced += l.n_held > 0 && l.n_held < rows.length;
}
assert.ok(cases >= 60 && reduced >= 30, `${cases} cases, ${reduced} of them reduced`);
console.log(`hold: ${cases} cases (${reduced} reduced) agree`);
