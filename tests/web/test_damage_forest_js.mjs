// A FOREST frame taken by the page (web/damage.js frameDamage, as web/app.js takes a frame:
// with the same frame's DAMAGE as one, the trees' fall and level healed first; the sound
// told before DamageFx.take): the trees' fall and level become the
// frame's, the broken branches stay, a tree the frame leaves out stands again with its
// full crown, a tree already lying or falling the same way keeps its fall's start, a new
// recent fall starts at its tick and alone sounds; and a page that joins with the
// keyframe's DAMAGE and FOREST holds the same picture as the one that watched
// (client/app/client_damage.c client_damage_take, protocol/damage_view.c
// damage_view_heal_trees; PROTOCOL.md "FOREST"). Node, no browser.
//   node test_damage_forest_js.mjs
import assert from 'node:assert/strict';
import { Decoder, MSG, forestEvents } from '../../web/wire.js';
import { DamageFx, DamageView, DAMAGE, TIP_FALL, damageEventStart_s, frameDamage } from '../../web/damage.js';
import { Sound, soundOptions } from '../../web/audio.js';

if (process.argv.includes('--help')) {
    console.log('usage: node test_damage_forest_js.mjs');
    process.exit(0);
}
const HZ = 60, N = 8, W = 0xffffffff;
const time_us = (tick) => Math.round((tick * 1e6) / HZ); // the server's clock, 60 ticks a second
const hdrOf = (tick) => ({ type: MSG.DAMAGE, tick, server_time_us: time_us(tick) });

// The bytes of a frame: header of type and tick, then the body.
function frame(type, tick, body) {
    const b = new Uint8Array(20 + body.length), v = new DataView(b.buffer);
    b.set([0x47, 0x41, 0x4c, 0x45, 1, 0, type, 0]);
    v.setUint32(8, tick, true);
    v.setUint32(12, time_us(tick) % 2 ** 32, true);
    v.setUint32(16, Math.floor(time_us(tick) / 2 ** 32), true);
    b.set(body, 20);
    return b;
}
// A FOREST of trees [first, first + trees.length): each { fall: 0/2/3, level, az, tick }.
function forestBytes(tick, first, trees) {
    const body = [], u32 = (x) => [x & 0xff, (x >>> 8) & 0xff, (x >>> 16) & 0xff, x >>> 24];
    body.push(...u32(first), ...u32(trees.length));
    for (const t of trees) body.push((t.fall << 6) | t.level);
    for (const t of trees) if (t.fall) body.push(t.az, ...u32(t.tick));
    return frame(MSG.FOREST, tick, body);
}
// A DAMAGE frame of events { tree, node, kind, value, tick }.
function damageBytes(tick, full, events) {
    const body = [full ? 1 : 0, events.length & 0xff, events.length >> 8], u32 = (x) => [x & 0xff, (x >>> 8) & 0xff, (x >>> 16) & 0xff, x >>> 24];
    for (const e of events) body.push(...u32(e.tree), ...u32(e.node === undefined ? W : e.node), e.kind, e.value, ...u32(e.tick));
    return frame(MSG.DAMAGE, tick, body);
}
function bundle(frames) {
    const n = frames.reduce((s, f) => s + 4 + f.length, 21), b = new Uint8Array(n), v = new DataView(b.buffer);
    b.set(frames[0].subarray(0, 20));
    b[6] = MSG.BUNDLE;
    b[20] = frames.length;
    let p = 21;
    for (const f of frames) { v.setUint32(p, f.length, true); b.set(f, p + 4); p += 4 + f.length; }
    return b;
}
// What web/app.js's onFrame does with a frame's DAMAGE and FOREST (the trees all held).
function onFrame(fx, sound, f) {
    const d = frameDamage(f); // as web/app.js takes a frame
    if (d) {
        sound.onDamage(f.hdr, d, fx.view, HZ);
        fx.take(f.hdr, d);
    }
}
const newFx = () => new DamageFx(N, HZ, () => 10, () => 1);
const newSound = () => new Sound({}, soundOptions(''));
const sameView = (a, b, what) => {
    for (const k of ['fallen', 'fall_az', 'level', 'fall_tick']) assert.deepEqual([...a[k]], [...b[k]], `${what}: ${k}`);
    assert.deepEqual(a.broken, b.broken, `${what}: broken`);
};
let checks = 0;

// The picture before: a branch broken off tree 1, tree 0 stripped to 8 and tree 3 to 12,
// tree 4 to 5; tree 2 snapped 1/12 s ago (falling), tree 5 uprooted long ago (lying), tree 6
// snapped 5/60 s ago (falling).
const fx = newFx(), sound = newSound(), dec = new Decoder();
onFrame(fx, sound, dec.decode(damageBytes(1000, false, [
    { tree: 1, node: 5, kind: DAMAGE.BRANCH, value: 0, tick: 990 },
    { tree: 0, kind: DAMAGE.STRIP, value: 8, tick: 990 },
    { tree: 3, kind: DAMAGE.STRIP, value: 12, tick: 996 },
    { tree: 4, kind: DAMAGE.STRIP, value: 5, tick: 997 },
    { tree: 2, kind: DAMAGE.SNAP, value: 10, tick: 995 },
    { tree: 5, kind: DAMAGE.UPROOT, value: 77, tick: 100 },
    { tree: 6, kind: DAMAGE.SNAP, value: 30, tick: 995 }])));
const v = fx.view, t0_6 = fx.fall_t0_s[6];
assert.ok(Number.isFinite(t0_6) && Number.isFinite(fx.fall_t0_s[2]) && Number.isNaN(fx.fall_t0_s[5]));
assert.deepEqual(sound.pending.map((p) => p.tree), [1, 2, 6], 'the DAMAGE sounds its branch and two recent falls');
checks += 2;

// A FOREST 10 ticks on listing trees 3..7: tree 3 back to 20/32, tree 4 whole, tree 5 as it
// lies, tree 6 as it falls, tree 7 uprooted just now; trees 0..2 left out: whole, standing.
const fo = dec.decode(forestBytes(1010, 3, [
    { fall: 0, level: 20 },
    { fall: 0, level: 32 },
    { fall: 3, level: 32, az: 77, tick: 100 },
    { fall: 2, level: 32, az: 30, tick: 995 },
    { fall: 3, level: 16, az: 128, tick: 1008 }]));
assert.deepEqual(forestEvents(fo).map((e) => [e.tree, e.kind, e.value, e.tick]),
    [[3, DAMAGE.STRIP, 20, 1010], [5, DAMAGE.UPROOT, 77, 100], [6, DAMAGE.SNAP, 30, 995], [7, DAMAGE.UPROOT, 128, 1008], [7, DAMAGE.STRIP, 16, 1010]]);
const gen = v.generation;
const now_s = time_us(1010) * 1e-6 + 1 / 6, angle6 = fx.fallAngle(6, now_s);
assert.ok(angle6 > 0 && angle6 < TIP_FALL.LYING_RAD, 'tree 6 is falling then');
sound.pending.length = 0;
onFrame(fx, sound, fo);
checks++;
// the branch stays
assert.deepEqual(v.broken, [1 * 2 ** 32 + 5]);
assert.ok(v.isBroken(1, 5));
// the frame's state holds: trees 0..2 stand whole (tree 2 no longer fallen), tree 3 at 20
// (raised: the heal before, not a STRIP's lowering alone), tree 4 whole, 5 and 6 as they
// were, tree 7 uprooted towards 128/256 with 16/32 left
assert.deepEqual([...v.fallen], [0, 0, 0, 0, 0, DAMAGE.UPROOT, DAMAGE.SNAP, DAMAGE.UPROOT]);
assert.deepEqual([...v.fall_az], [0, 0, 0, 0, 0, 77, 30, 128]);
assert.deepEqual([...v.fall_tick], [0, 0, 0, 0, 0, 100, 995, 1008]);
assert.deepEqual([...v.level], [32, 32, 32, 20, 32, 32, 32, 16]);
assert.equal(fx.bad, 0);
assert.ok(v.generation > gen && fx.dirty, 'the renderer is told');
checks += 6;
// the fall starts: tree 2 stands (none), tree 5 still lying (none), tree 6 keeps its own,
// bit for bit (it is not new to the picture, so not recomputed: recomputed from the
// FOREST's header it would be the same instant only within the header's clock, here its
// microsecond rounding, on a server the jitter of the instant each frame was encoded);
// tree 7's from its tick
assert.ok(Number.isNaN(fx.fall_t0_s[2]), 'a tree standing again has no fall start');
assert.ok(Number.isNaN(fx.fall_t0_s[5]));
assert.ok(Object.is(fx.fall_t0_s[6], t0_6), `tree 6 keeps its fall start: ${t0_6}, now ${fx.fall_t0_s[6]}`);
assert.ok(Math.abs(damageEventStart_s(1010, time_us(1010), 995, HZ) - t0_6) <= 1e-6, 'the same start from the FOREST\'s tick');
assert.equal(fx.fall_t0_s[7], damageEventStart_s(1010, time_us(1010), 1008, HZ));
for (const t of [0, 1, 3, 4]) assert.ok(Number.isNaN(fx.fall_t0_s[t]), `tree ${t}`);
// a falling tree goes on from where it is: 1/6 s after tick 1010 tree 6 is where it would
// have been without the FOREST, further down than tree 7, which fell 13 ticks later
assert.equal(fx.fallAngle(6, now_s), angle6);
assert.ok(angle6 > fx.fallAngle(7, now_s) && fx.fallAngle(7, now_s) > 0);
assert.equal(fx.fallAngle(2, now_s), 0);
checks += 9;
// only tree 7's recent new fall sounds: tree 6 is not new, tree 5's fall is old, a STRIP
// has no sound
assert.deepEqual(sound.pending.map((p) => [p.tree, p.t0_s]), [[7, fx.fall_t0_s[7]]]);
checks++;

// The same FOREST again changes nothing and sounds nothing.
const before = { fallen: v.fallen.slice(), fall_az: v.fall_az.slice(), level: v.level.slice(), fall_tick: v.fall_tick.slice(), broken: [...v.broken] };
const t0s = fx.fall_t0_s.slice();
sound.pending.length = 0;
onFrame(fx, sound, fo);
sameView(v, before, 'the same FOREST again');
assert.deepEqual([...fx.fall_t0_s].map(String), [...t0s].map(String));
assert.equal(sound.pending.length, 0);
checks += 3;

// The watching page's periodic keyframe 1/6 s later: the whole state's BUNDLE, the DAMAGE
// (full: it heals everything, then the branch) with the FOREST. Taken as one, tree 6's fall
// under way is not new after the heal: it keeps its start and goes on, nothing sounds.
{
    const fallStart = fx.fall_t0_s.slice(), view0 = { fallen: v.fallen.slice(), fall_az: v.fall_az.slice(), level: v.level.slice(), fall_tick: v.fall_tick.slice(), broken: [...v.broken] };
    sound.pending.length = 0;
    onFrame(fx, sound, dec.decode(bundle([damageBytes(1020, true, [{ tree: 1, node: 5, kind: DAMAGE.BRANCH, value: 0, tick: 990 }]),
        forestBytes(1020, 3, [
            { fall: 0, level: 20 },
            { fall: 0, level: 32 },
            { fall: 3, level: 32, az: 77, tick: 100 },
            { fall: 2, level: 32, az: 30, tick: 995 },
            { fall: 3, level: 16, az: 128, tick: 1008 }])])));
    sameView(v, view0, 'after the keyframe\'s whole state');
    assert.ok(Object.is(fx.fall_t0_s[6], fallStart[6]) && Object.is(fx.fall_t0_s[7], fallStart[7]), 'the falls under way keep their starts across the keyframe');
    assert.equal(sound.pending.length, 0, 'a keyframe sounds no fall again');
    checks += 3;
}

// A page that joins now: the keyframe's BUNDLE with the whole state, the DAMAGE (full, the
// branch) then the FOREST, at tick 1012: the same picture; the falls under 3 s old start
// at their ticks (tree 6 where the watching page's is), the old one lies.
const late = newFx(), ls = newSound(), ld = new Decoder();
const b = ld.decode(bundle([damageBytes(1012, true, [{ tree: 1, node: 5, kind: DAMAGE.BRANCH, value: 0, tick: 990 }]),
    forestBytes(1012, 3, [
        { fall: 0, level: 20 },
        { fall: 0, level: 32 },
        { fall: 3, level: 32, az: 77, tick: 100 },
        { fall: 2, level: 32, az: 30, tick: 995 },
        { fall: 3, level: 16, az: 128, tick: 1008 }])]));
assert.equal(b.types, (1 << MSG.DAMAGE) | (1 << MSG.FOREST));
onFrame(late, ls, b);
sameView(late.view, v, 'a late joiner');
assert.ok(Math.abs(late.fall_t0_s[6] - t0_6) <= 1e-6 && Number.isNaN(late.fall_t0_s[5]));
assert.ok(Math.abs(late.fall_t0_s[7] - fx.fall_t0_s[7]) <= 1e-6);
checks += 4;

// The whole state again after a heal with other falls (a FOREST that says tree 6 stands
// and tree 2 fell long ago): tree 6 stands, its fall start cleared, tree 2 lies at once.
onFrame(fx, sound, dec.decode(bundle([damageBytes(1020, true, [{ tree: 1, node: 5, kind: DAMAGE.BRANCH, value: 0, tick: 990 }]),
    forestBytes(1020, 2, [{ fall: 2, level: 32, az: 3, tick: 50 }])])));
assert.deepEqual([...v.fallen], [0, 0, DAMAGE.SNAP, 0, 0, 0, 0, 0]);
assert.deepEqual([...v.level], [32, 32, 32, 32, 32, 32, 32, 32]);
assert.ok(fx.fall_t0_s.every((x) => Number.isNaN(x)));
assert.equal(fx.fallAngle(2, 1e9), TIP_FALL.LYING_RAD, "tree 2 lies at once");
assert.deepEqual(v.broken, [1 * 2 ** 32 + 5]);
checks += 5;

// healTrees alone: every tree up and whole, the branches kept (damage_view_heal_trees)
const hv = new DamageView(3);
hv.apply(false, [{ tree: 2, node: 4, kind: DAMAGE.BRANCH, value: 0, tick: 1 }, { tree: 0, node: W, kind: DAMAGE.SNAP, value: 9, tick: 2 },
    { tree: 1, node: W, kind: DAMAGE.STRIP, value: 3, tick: 2 }]);
const g0 = hv.generation;
hv.healTrees();
assert.deepEqual([[...hv.fallen], [...hv.fall_az], [...hv.fall_tick], [...hv.level], hv.broken], [[0, 0, 0], [0, 0, 0], [0, 0, 0], [32, 32, 32], [2 * 2 ** 32 + 4]]);
assert.equal(hv.generation, g0 + 1);
hv.heal();
assert.deepEqual(hv.broken, []);
checks += 3;

console.log(JSON.stringify({ checks, ok: true }));
