// web/wall_view.js against gale-client's wall geometry (gale-web-wall-table, built from
// client/wall/wall.c by tests/web/CMakeLists.txt) for every wall file of configs/walls/ and
// tests/data/wall_unnormalised.json (normals and ups not unit vectors, as wall_parse
// accepts them, and a tour that starts late): each tile's corners, its view and Kooima projection for two camera views, and the tour's
// camera at a few times, every float within 1e-4 of its size (the C code computes in
// float, the browser in double). The browser reads the same files the server serves.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { tileCorners, tileMatrices, tourAt } from '../../web/wall_view.js';

const a = process.argv.slice(2);
if (a.includes('--help') || a.length < 2) {
    console.log('usage: node test_wall_js.mjs GALE_WEB_WALL_TABLE WALL.json...');
    process.exit(a.includes('--help') ? 0 : 2);
}
const rows = execFileSync(a[0], a.slice(1), { encoding: 'utf8' }).trim().split('\n').map((l) => JSON.parse(l));
const walls = new Map(a.slice(1).map((f) => [f, JSON.parse(readFileSync(f, 'utf8'))]));
let worst = 0, tiles = 0, tours = 0;
const near = (got, want, where) => {
    assert.equal(got.length, want.length, where);
    for (let k = 0; k < want.length; k++) {
        const d = Math.abs(got[k] - want[k]) / Math.max(1, Math.abs(want[k]));
        worst = Math.max(worst, d);
        assert.ok(d <= 1e-4, `${where}[${k}] is ${got[k]} in the browser, ${want[k]} in client/wall/wall.c`);
    }
};
for (const r of rows) {
    const w = walls.get(r.file);
    if (r.tile) {
        const t = w.tiles.find((x) => x.name === r.tile);
        const where = `${r.file} tile ${r.tile}`;
        const [pa, pb, pc] = tileCorners(t);
        near(pa, r.pa, `${where} pa`);
        near(pb, r.pb, `${where} pb`);
        near(pc, r.pc, `${where} pc`);
        const { view, proj } = tileMatrices(w, t, new Float32Array(r.cam_view));
        near(Array.from(view), r.view, `${where} view`);
        near(Array.from(proj), r.proj, `${where} proj`);
        tiles++;
    } else {
        const c = tourAt(w, r.tour_at_s), where = `${r.file} tour at ${r.tour_at_s} s`;
        near(c.target_m, r.target_m, `${where} target_m`);
        near([c.distance_m, c.yaw_deg, c.pitch_deg], [r.distance_m, r.yaw_deg, r.pitch_deg], `${where} distance, yaw, pitch`);
        tours++;
    }
}
// every file's tiles, and a tour checked (not an empty table)
assert.equal(tiles, 2 * [...walls.values()].reduce((n, w) => n + w.tiles.length, 0));
assert.ok(tours >= 8, `${tours} tour times checked`);
console.log(JSON.stringify({ files: walls.size, tile_views: tiles, tour_times: tours, worst_relative: worst, ok: true }));
