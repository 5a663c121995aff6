// web/attract.js against gale-client's attract mode (gale-web-attract-table, built from
// client/kiosk/attract.c, camera.c and camera_preset.c by tests/web/CMakeLists.txt): over the
// same scene the tour's orbit agrees at times through every stop (target and distance
// within 1e-4 of their size, angles within 1e-5 rad: the C code computes in float), and
// the idle clock answers a sequence of ticks and touches the same.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { Attract, cameraTour } from '../../web/attract.js';

const a = process.argv.slice(2);
if (a.includes('--help') || a.length !== 1) {
    console.log('usage: node test_attract_js.mjs GALE_WEB_ATTRACT_TABLE');
    process.exit(a.includes('--help') ? 0 : 2);
}
const lines = execFileSync(a[0], { encoding: 'utf8' }).trim().split('\n').map((l) => JSON.parse(l));
const scene = lines[0].scene;
const tours = lines.filter((l) => l.tour).map((l) => l.tour);
const clocks = lines.filter((l) => l.clock).map((l) => l.clock);
assert.ok(scene && tours.length >= 8 && clocks.length >= 8, 'the table has a scene, a tour and a clock');
let worst = 0;
const stops = new Set();
for (const c of tours) {
    const js = cameraTour(c.t_s, scene.instances, scene.species);
    stops.add(js.stop);
    const near = (got, want, tol, what) => {
        const d = Math.abs(got - want);
        worst = Math.max(worst, d / tol);
        assert.ok(d <= tol, `tour at ${c.t_s} s: ${what} is ${got} in the browser, ${want} in client/kiosk/camera_preset.c`);
    };
    const size = Math.max(1, c.distance, ...c.target.map(Math.abs));
    for (let k = 0; k < 3; k++) near(js.target[k], c.target[k], 1e-4 * size, `target[${k}]`);
    near(js.distance, c.distance, 1e-4 * size, 'distance');
    near(js.yaw, c.yaw, 1e-5, 'yaw');
    near(js.pitch, c.pitch, 1e-5, 'pitch');
}
assert.equal(stops.size, 4, 'the times pass every stop of the tour');
let at = null;
for (const c of clocks) {
    if (!at) at = new Attract(c.idle_s, 0);
    const r = c.op === 'tick' ? at.tick(c.t_s) : at.input(c.t_s);
    assert.equal(r, c.result, `${c.op} at ${c.t_s} s`);
    assert.equal(at.active, c.active, `active after ${c.op} at ${c.t_s} s`);
    assert.equal(at.card(c.t_s), c.card, `the card after ${c.op} at ${c.t_s} s`);
    assert.equal(at.card(c.t_s + 12), c.card_later, `the card 12 s after ${c.op} at ${c.t_s} s`);
}
assert.ok(clocks.some((c) => c.card_later === 1), 'the water card comes in turn');
assert.equal(new Attract(0, 0).idle_s, 90);
console.log(JSON.stringify({ tour_points: tours.length, clock_steps: clocks.length, worst_share_of_tol: worst, ok: true }));
