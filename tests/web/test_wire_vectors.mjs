// web/wire.js against the binary test vectors of protocol/PROTOCOL.md (the ones the C
// tests read, tests/test_spec_vectors.c): each decoded to the values the spec states; then
// corruptions each decoder must refuse. node test_wire_vectors.mjs PROTOCOL.md
import assert from 'node:assert/strict';
import { Decoder, MSG, dequantise, WireError, forestEvents } from '../../web/wire.js';
import { readVectors } from './spec_vectors.mjs';

const path = process.argv[2];
if (!path || path === '--help') {
    console.log('usage: node test_wire_vectors.mjs PATH/TO/PROTOCOL.md');
    process.exit(path ? 0 : 2);
}
const vec = readVectors(path).hex;
const KNOWN = ['KEYFRAME', 'DELTA', 'LEAVES', 'WIND', 'WEATHER', 'WEATHER-STEADY', 'DAMAGE',
    'DAMAGE-FULL', 'FOREST', 'BUNDLE', 'BUNDLE-KEYFRAME'];
for (const name of KNOWN) assert.ok(vec[name], `no vector ${name} in ${path}`);
for (const name of Object.keys(vec)) assert.ok(KNOWN.includes(name), `${path}: vector ${name} is not one this test knows`);
const byType = {};
for (const name of ['KEYFRAME', 'DELTA', 'LEAVES', 'WIND', 'WEATHER', 'DAMAGE', 'FOREST']) {
    assert.equal(vec[name][6], MSG[name], `${name}: type byte`);
    byType[MSG[name]] = vec[name];
}
let checks = 0;
const near = (a, b, tol, what) => {
    assert.ok(Math.abs(a - b) <= tol, `${what}: expected ${b} ± ${tol}, got ${a}`);
    checks++;
};

// KEYFRAME: tick 120, 2 000 000 us, seq 5, Q tree 0 [3, -2], tree 2 [7], tree 1 not sent
const d = new Decoder();
const k = d.decode(byType[MSG.KEYFRAME]);
assert.equal(k.hdr.tick, 120);
assert.equal(k.hdr.server_time_us, 2000000);
assert.equal(k.state.seq, 5);
assert.deepEqual([...k.state.n_modes], [2, 0, 1]);
assert.deepEqual([...k.state.q], [3, -2, 0, 0, 7, 0]);
const qf = dequantise(k.state, new Float32Array(6));
near(qf[0], 0.003, 1e-9, 'q tree 0 mode 0');
near(qf[1], -0.004, 1e-9, 'q tree 0 mode 1');
near(qf[4], 0.007, 1e-9, 'q tree 2 mode 0 (species 0 step 0.001)');
checks += 6;

// decoded into a reused snapshot (the decoder keeps spares) holding other values: those
// past each tree's modes are zeroed too (the browser's skeleton pass blends them as held)
const dz = new Decoder();
dz.spare.push({ seq: 0, n_modes: new Uint8Array(3), q: new Int16Array(6).fill(99) });
assert.deepEqual([...dz.decode(byType[MSG.KEYFRAME]).state.q], [3, -2, 0, 0, 7, 0], 'keyframe into a reused snapshot');
checks++;

// DELTA on it: seq 6, tick 122, Q tree 0 [4, -2], tree 2 [7]
const dl = d.decode(byType[MSG.DELTA]);
assert.equal(dl.hdr.tick, 122);
assert.equal(dl.hdr.server_time_us, 2033333);
assert.equal(dl.state.seq, 6);
assert.deepEqual([...dl.state.q], [4, -2, 0, 0, 7, 0]);
checks += 4;

// the same DELTA again is a gap (holds 6, wants 6 + 1): a state error, state unchanged
assert.throws(() => d.decode(byType[MSG.DELTA]), (e) => e.state && /gap/.test(e.message));
assert.equal(d.last.seq, 6);
// a DELTA before any KEYFRAME
assert.throws(() => new Decoder().decode(byType[MSG.DELTA]), (e) => e.state && /no keyframe/.test(e.message));
checks += 3;

// LEAVES: instance 2, slot 17, spawn_tick 118, seed 0xdeadbeef
const lv = d.decode(byType[MSG.LEAVES]);
assert.deepEqual(lv.leaves, [{ instance: 2, slot: 17, spawn_tick: 118, seed: 0xdeadbeef }]);
checks++;

// WIND: corner (-64, -64, 4), cell 8, scale 0.1, 2 × 1, cells (10, -5, 0), (127, -127, 1)
const w = d.decode(byType[MSG.WIND]).wind;
assert.deepEqual([w.x0_m, w.y0_m, w.z_m, w.cell_m, w.nx, w.ny], [-64, -64, 4, 8, 2, 1]);
near(w.scale_ms, 0.1, 1e-7, 'scale_ms');
assert.deepEqual([...w.cells], [10, -5, 0, 127, -127, 1]);
checks += 2;

// WEATHER: Andrew near landfall
const we = d.decode(byType[MSG.WEATHER]).weather;
assert.equal(we.sustained_ms, 50);
assert.equal(we.gust_ms, 62.5);
assert.equal(we.dir_from_deg, 45);
assert.deepEqual([we.ss_class, we.beaufort, we.flags, we.storm_class], [4, 12, 9, 5]);
assert.deepEqual([we.pressure_hpa, we.central_hpa, we.distance_km, we.bearing_deg], [950, 922, 20, 90]);
assert.equal(we.utc_offset_min, -240);
assert.equal(new Date(we.utc_min * 60000).toISOString(), '1992-08-24T09:05:00.000Z');
assert.deepEqual([we.storm_min, we.replay_pos_s, we.replay_len_s, we.replay_speed], [-10, 180, 402, 50]);
assert.equal(we.name, 'Andrew 1992');
checks += 9;

// DAMAGE: tree 2 branch at node 17 tick 118; tree 5 uprooted towards 64/256 turn, tick 120
const dm = d.decode(byType[MSG.DAMAGE]).damage;
assert.equal(dm.full, false);
assert.deepEqual(dm.events.map((e) => [e.tree, e.node, e.kind, e.value, e.tick]),
    [[2, 17, 1, 0, 118], [5, 0xffffffff, 3, 64, 120]]);
checks += 2;

// WEATHER-STEADY: a kiosk's dial, no storm, no clock: the "none" values of a clear flag
const ws = new Decoder().decode(vec['WEATHER-STEADY']).weather;
assert.deepEqual([ws.sustained_ms, ws.gust_ms, ws.dir_from_deg], [20, 26.5, 270]);
assert.deepEqual([ws.ss_class, ws.beaufort, ws.flags, ws.storm_class], [1, 8, 2, 255]);
assert.deepEqual([ws.pressure_hpa, ws.central_hpa, ws.distance_km, ws.utc_min, ws.storm_min], [1013, 0, -1, 0, 0]);
assert.equal(ws.name, 'gale');
checks += 4;

// DAMAGE-FULL: the whole state; tree 0 kept 20/32 of its leaves, tree 1 snapped
const df = new Decoder().decode(vec['DAMAGE-FULL']).damage;
assert.equal(df.full, true);
assert.deepEqual(df.events.map((e) => [e.tree, e.node, e.kind, e.value, e.tick]),
    [[0, 0xffffffff, 4, 20, 110], [1, 0xffffffff, 2, 200, 115]]);
checks += 2;

// FOREST: trees 0..2 from tree 0; tree 0 standing at 20/32, tree 1 snapped at 200/256 turn
// (tick 115) with its crown whole, tree 2 uprooted at 64/256 (tick 118) with 8/32 left
const fo = new Decoder().decode(vec.FOREST);
assert.deepEqual([fo.hdr.type, fo.hdr.tick, fo.hdr.server_time_us, fo.types], [8, 120, 2000000, 1 << MSG.FOREST]);
assert.deepEqual([fo.forest.first, fo.forest.count], [0, 3]);
assert.ok(fo.forest.state instanceof Uint8Array);
assert.deepEqual([...fo.forest.state], [0x14, 0xa0, 0xc8]);
assert.deepEqual(fo.forest.falls, [{ az: 200, tick: 115 }, { az: 64, tick: 118 }]);
assert.equal(fo.damage, undefined);
// as DAMAGE events (PROTOCOL.md): (0, STRIP 20, tick 120), (1, SNAP 200, tick 115),
// (2, UPROOT 64, tick 118), (2, STRIP 8, tick 120), each as the DAMAGE decoder's
const W = 0xffffffff;
assert.deepEqual(forestEvents(fo), [
    { tree: 0, node: W, kind: 4, value: 20, tick: 120, kindName: 'STRIP' },
    { tree: 1, node: W, kind: 2, value: 200, tick: 115, kindName: 'SNAP' },
    { tree: 2, node: W, kind: 3, value: 64, tick: 118, kindName: 'UPROOT' },
    { tree: 2, node: W, kind: 4, value: 8, tick: 120, kindName: 'STRIP' }]);
assert.deepEqual(Object.keys(forestEvents(fo)[0]), Object.keys(df.events[0]), 'FOREST events shaped as DAMAGE events');
assert.deepEqual(forestEvents(d.decode(byType[MSG.LEAVES])), [], 'no FOREST, no events');
checks += 10;
// listed from tree 5: the same bytes name trees 5..7 (events and errors)
const fo5 = Uint8Array.from(vec.FOREST);
fo5[0x14] = 5;
assert.deepEqual(forestEvents(new Decoder().decode(fo5)).map((e) => [e.tree, e.kind, e.value, e.tick]),
    [[5, 4, 20, 120], [6, 2, 200, 115], [7, 3, 64, 118], [7, 4, 8, 120]]);
// a calm forest: count 0, 28 bytes, no events
const calm = Uint8Array.from(vec.FOREST.subarray(0, 28));
calm[0x18] = 0;
const fc = new Decoder().decode(calm);
assert.deepEqual([fc.forest.count, fc.forest.state.length, fc.forest.falls.length, forestEvents(fc).length], [0, 0, 0, 0]);
checks += 2;
// the refusals, in protocol/msg_forest.c's words
const forestBad = (bytes, text) => {
    assert.throws(() => new Decoder().decode(bytes), (e) => e instanceof WireError && !e.state && e.message === text,
        `expected "${text}"`);
    checks++;
};
const forestAt = (at, val) => { const c = Uint8Array.from(vec.FOREST); c[at] = val; return c; };
forestBad(forestAt(0x1c, 0x54), 'wire: FOREST tick 120: tree 0 at byte 28: expected level <= 32 and fall 0, 2 or 3, got 0x54'); // fall bits 1
forestBad(forestAt(0x1e, 0xe1), 'wire: FOREST tick 120: tree 2 at byte 30: expected level <= 32 and fall 0, 2 or 3, got 0xe1'); // level 33
forestBad(forestAt(0x1c, 0x21), 'wire: FOREST tick 120: tree 0 at byte 28: expected level <= 32 and fall 0, 2 or 3, got 0x21'); // level 33 standing
forestBad(forestAt(0x1c, 0x94), 'wire: FOREST tick 120: length: expected 46 bytes for 3 trees, 3 fallen, got 41'); // a third fall unsaid
forestBad(vec.FOREST.subarray(0, 40), 'wire: FOREST tick 120: length: expected 41 bytes for 3 trees, 2 fallen, got 40'); // a fall cut
forestBad(vec.FOREST.subarray(0, 30), 'wire: FOREST tick 120: length: expected >= 31 bytes for 3 trees, got 30');
forestBad(vec.FOREST.subarray(0, 26), 'wire: FOREST tick 120: first, count at byte 20: truncated');
const grown = new Uint8Array(vec.FOREST.length + 1);
grown.set(vec.FOREST);
forestBad(grown, 'wire: FOREST tick 120: length: expected 41 bytes for 3 trees, 2 fallen, got 42'); // a trailing byte
const far = Uint8Array.from(vec.FOREST);
new DataView(far.buffer).setUint32(0x14, 262142, true);
forestBad(far, 'wire: FOREST tick 120: count at byte 24: expected first + count <= 262144, got 262142 + 3');
new DataView(far.buffer).setUint32(0x14, 262141, true); // the last tree the protocol has
assert.deepEqual(forestEvents(new Decoder().decode(far)).map((e) => e.tree), [262141, 262142, 262143, 262143]);
const huge = Uint8Array.from(vec.FOREST);
new DataView(huge.buffer).setUint32(0x18, 0xffffffff, true);
forestBad(huge, 'wire: FOREST tick 120: count at byte 24: expected first + count <= 262144, got 0 + 4294967295');
forestBad(forestAt(6, 9), 'wire: type at byte 6: expected 1..8, got 9');
checks++;

// BUNDLE-KEYFRAME: every member a snapshot can carry, decoded by a new decoder
const bk = new Decoder().decode(vec['BUNDLE-KEYFRAME']);
assert.equal(bk.state.seq, 5);
assert.deepEqual([...bk.state.q], [3, -2, 0, 0, 7, 0]);
assert.equal(bk.leaves.length, 1);
assert.deepEqual([...bk.wind.cells], [10, -5, 0, 127, -127, 1]);
assert.equal(bk.damage.full, true);
assert.equal(bk.weather.name, 'Andrew 1992');
assert.equal(bk.types, (1 << MSG.KEYFRAME) | (1 << MSG.LEAVES) | (1 << MSG.WIND) |
    (1 << MSG.WEATHER) | (1 << MSG.DAMAGE));
checks += 7;

// BUNDLE of the DELTA and the LEAVES (the spec's 94 bytes, built as it says) on the KEYFRAME
const delta = byType[MSG.DELTA], leaves = byType[MSG.LEAVES];
const bundle = new Uint8Array(20 + 1 + 4 + delta.length + 4 + leaves.length);
bundle.set(delta.subarray(0, 20));
bundle[6] = MSG.BUNDLE;
bundle[20] = 2;
const dv = new DataView(bundle.buffer);
dv.setUint32(21, delta.length, true);
bundle.set(delta, 25);
dv.setUint32(25 + delta.length, leaves.length, true);
bundle.set(leaves, 29 + delta.length);
assert.equal(bundle.length, 94);
assert.deepEqual([...bundle], [...vec.BUNDLE], 'the BUNDLE vector is the DELTA and LEAVES wrapped');
const d2 = new Decoder();
d2.decode(byType[MSG.KEYFRAME]);
const b = d2.decode(bundle);
assert.equal(b.state.seq, 6);
assert.deepEqual([...b.state.q], [4, -2, 0, 0, 7, 0]);
assert.equal(b.leaves.length, 1);
assert.equal(b.types, (1 << MSG.DELTA) | (1 << MSG.LEAVES));
checks += 4;

// a KEYFRAME's BUNDLE with the whole damage state, DAMAGE-FULL and then FOREST (gale-server's
// order): one frame with both; the FOREST's events at the bundle's tick; a second FOREST
// refuses it
const wrap = (frames) => {
    const n = frames.reduce((s, f) => s + 4 + f.length, 21), out = new Uint8Array(n), dw = new DataView(out.buffer);
    out.set(frames[0].subarray(0, 20));
    out[6] = MSG.BUNDLE;
    out[20] = frames.length;
    let p = 21;
    for (const f of frames) { dw.setUint32(p, f.length, true); out.set(f, p + 4); p += 4 + f.length; }
    return out;
};
const bf = new Decoder().decode(wrap([byType[MSG.KEYFRAME], vec['DAMAGE-FULL'], vec.FOREST]));
assert.equal(bf.types, (1 << MSG.KEYFRAME) | (1 << MSG.DAMAGE) | (1 << MSG.FOREST));
assert.equal(bf.state.seq, 5);
assert.equal(bf.damage.full, true);
assert.deepEqual(bf.forest.falls, fo.forest.falls);
assert.deepEqual(forestEvents(bf), forestEvents(fo));
assert.throws(() => new Decoder().decode(wrap([byType[MSG.KEYFRAME], vec.FOREST, vec.FOREST])), /frame 3 of 3: a second FOREST/);
// a broken FOREST inside refuses the whole BUNDLE, its state frame not taken
const d4 = new Decoder();
assert.throws(() => d4.decode(wrap([byType[MSG.KEYFRAME], vec['DAMAGE-FULL'], forestAt(0x1c, 0x54)])),
    /wire: BUNDLE tick 120: frame 3 of 3: wire: FOREST tick 120: tree 0 at byte 28: expected level <= 32/);
assert.equal(d4.last, null);
checks += 8;

// Refusals: every one-byte change below breaks a rule the spec states.
const bad = (bytes, at, val, re, dec = new Decoder()) => {
    const c = Uint8Array.from(bytes);
    c[at] = val;
    assert.throws(() => dec.decode(c), re, `byte ${at} = ${val}`);
    checks++;
};
bad(byType[MSG.KEYFRAME], 0, 0x48, /magic/);
bad(byType[MSG.KEYFRAME], 7, 1, /flags/);
bad(byType[MSG.KEYFRAME], 0x2b, 2, /species of tree 0/); // species index >= n_species
bad(byType[MSG.KEYFRAME], 0x37, 0x23, /predictor/);      // predictor 1 in a KEYFRAME
bad(byType[MSG.KEYFRAME], 0x3a, 0x8e, /padding/);       // a padding bit set
bad(byType[MSG.DAMAGE], 0x1f, 5, /kind/);
bad(byType[MSG.WEATHER], 0x20, 7, /ss_class/);
bad(byType[MSG.WIND], 0x28, 0, /nx/);
assert.throws(() => new Decoder().decode(byType[MSG.KEYFRAME].subarray(0, 58)), /truncated/);
const longer = new Uint8Array(byType[MSG.LEAVES].length + 1);
longer.set(byType[MSG.LEAVES]);
assert.throws(() => new Decoder().decode(longer), /trailing/);
// a bundle whose inner DELTA is broken leaves the decoder on seq 5
const d3 = new Decoder();
d3.decode(byType[MSG.KEYFRAME]);
const bb = Uint8Array.from(bundle);
bb[25 + 0x1a] = 0x3f; // predictor 1, width 31
assert.throws(() => d3.decode(bb), /frame 1 of 2/);
assert.equal(d3.last.seq, 5);
checks += 3;

// Outside input: 20,000 corruptions of the vectors (bytes changed, cut, grown; a seeded
// xorshift) each decode or throw a WireError, nothing else, and a refused frame leaves the
// decoder as it was (it still takes the DELTA on its KEYFRAME).
let seed = 0x9e3779b9, refused = 0;
const rnd = (n) => {
    seed ^= seed << 13; seed >>>= 0; seed ^= seed >>> 17; seed ^= seed << 5; seed >>>= 0;
    return seed % n;
};
const all = Object.values(vec);
for (let i = 0; i < 20000; i++) {
    const src = all[rnd(all.length)];
    let c = Uint8Array.from(src);
    const kind = rnd(3);
    if (kind === 0) for (let k = 0, n = 1 + rnd(4); k < n; k++) c[rnd(c.length)] = rnd(256);
    else if (kind === 1) c = c.subarray(0, rnd(c.length));
    else { const g = new Uint8Array(c.length + 1 + rnd(8)); g.set(c); g.fill(rnd(256), c.length); c = g; }
    const dec = new Decoder();
    dec.decode(byType[MSG.KEYFRAME]);
    try {
        dec.decode(c);
    } catch (e) {
        assert.ok(e instanceof WireError, `corruption ${i}: ${e.constructor.name}: ${e.message}`);
        assert.equal(dec.last.seq, 5, `corruption ${i}: a refused frame changed the decoder`);
        refused++;
    }
}
checks++;
console.log(JSON.stringify({ vectors: Object.keys(vec).length, checks, corruptions: 20000, refused, ok: true }));
