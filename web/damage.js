// Storm damage in the browser, as gale-client shows it (client/app/client_damage.c; PROTOCOL.md
// "DAMAGE"; server/PHYSICS.md "Storm damage"): the receiver's picture of the damage
// (protocol/damage_view.c: per tree standing, snapped or uprooted, its fall azimuth and
// leaf level, and the sorted set of broken branches), when an event happened on the server
// clock and whether it is recent enough to animate (client/motion/damage_clock.c), the stem tipping
// over as a rigid pole (client/motion/tip_fall.c) about the break of a snapped stem
// (tip_fall_break_m) or the base of an uprooted one, and what the renderer is given: per
// tree the code of u_trees slot 1 .z (render_tree_code, client/render/render_internal.h) and the
// azimuth, the broken branches' cut lists, and the pieces that broke off as tumbling debris
// (web/debris_path.js). The formulas are the C's;
// tests/web/test_damage_js.mjs holds them to the C (gale-web-damage-table).
import { hashMix32 } from './hash.js';
import { DebrisPath, debrisFrameMatrix, debrisFrameAngles } from './debris_path.js';
import { forestEvents } from './wire.js';

export const DAMAGE = { BRANCH: 1, SNAP: 2, UPROOT: 3, STRIP: 4, LEVELS: 32 }; // protocol/wire.h
export const DAMAGE_RECENT_S = 3.0;          // client/motion/damage_clock.h
export const MAX_DEBRIS = 64;                // RENDER_MAX_DEBRIS (client/render/render.h)
export const TIP_FALL = { G_MS2: 9.81, LEAN0_RAD: 0.05, LYING_RAD: 1.536, BREAK_MIN_M: 0.5, BREAK_SPAN_M: 1.0 }; // client/motion/tip_fall.h

// wire_damage_leaf_kept (protocol/wire.h): whether leaf slot `slot` of tree `tree` stays on a
// crown with `level` of 32 left.
export function leafKept(tree, slot, level) {
    const r = (hashMix32((Math.imul(slot, 0x9E3779B1) + 0x7F4A7C15) >>> 0) +
        hashMix32((Math.imul(tree, 0x85EBCA77) + 0x165667B1) >>> 0)) >>> 0;
    return r * DAMAGE.LEVELS < level * 2 ** 32;
}

// damage_event_start_s: the server time [s] of an event of tick eventTick carried by a
// frame of tick frameTick sent at frameTime_us; NaN when older than DAMAGE_RECENT_S.
// What a decoded frame f gives DamageFx.take (null: no damage): its DAMAGE, or its FOREST
// with its DAMAGE if it has one, as one (client/app/client_damage.c
// client_damage_take_forest): the trees' fall and level healed, then both frames' events,
// so a fall under way across a keyframe's whole state is one the picture holds, not new
// after the heal (PROTOCOL.md "FOREST").
export function frameDamage(f) {
    if (!f.forest) return f.damage || null;
    const ev = forestEvents(f);
    return { full: !!(f.damage && f.damage.full), healTrees: true, events: f.damage ? f.damage.events.concat(ev) : ev };
}

export function damageEventStart_s(frameTick, frameTime_us, eventTick, tick_hz) {
    const hz = tick_hz > 0 ? tick_hz : 60;
    // ticks wrap at 2^32: the signed difference is the age
    let age = ((frameTick - eventTick) | 0) / hz;
    age = age > 0 ? age : 0;
    return age <= DAMAGE_RECENT_S ? frameTime_us * 1e-6 - age : NaN;
}

// tip_fall_angle: θ [rad] t_s after the stem gave way, for a pole height_m tall:
// θ(t) = 4 atan(tan(θ0 / 4) e^(ω t)), ω² = 3g / 2L, then lying.
export function tipFallAngle(t_s, height_m) {
    if (!(t_s > 0)) return 0;
    const e = Math.sqrt(1.5 * TIP_FALL.G_MS2 / (height_m > 0.5 ? height_m : 0.5)) * t_s;
    if (e > 40) return TIP_FALL.LYING_RAD;
    const th = 4 * Math.atan(Math.tan(0.25 * TIP_FALL.LEAN0_RAD) * Math.exp(e));
    return th < TIP_FALL.LYING_RAD ? th : TIP_FALL.LYING_RAD;
}

// tip_fall_break_m: where tree `tree`'s stem breaks when it snaps [m, tree frame, unit
// scale], the float the C and shaders/common.glsl stump_break_m compute.
export function tipFallBreak_m(tree) {
    const u = Math.fround((hashMix32((Math.imul(tree, 2246822519) + 374761393) >>> 0) >>> 8) * (1 / 16777216));
    return Math.fround(TIP_FALL.BREAK_MIN_M + Math.fround(TIP_FALL.BREAK_SPAN_M * u));
}

// damage_cut_mask (client/motion/damage_cut.c): out[i] 1 when no node from i up to the root is one
// of cut (keepOnly: the inverse, only the sub-trees of cut); parents come first.
export function damageCutMask(parent, cut, keepOnly) {
    const n = parent.length, out = new Uint8Array(n);
    for (const c of cut) if (c < n) out[c] = 1;
    for (let i = 1; i < n; i++) if (!out[i] && parent[i] >= 0) out[i] = out[parent[i]];
    if (!keepOnly) for (let i = 0; i < n; i++) out[i] = out[i] ? 0 : 1;
    return out;
}

// render_piece_shape (client/render/render_damage.c): the piece from `node` of asset a at rest: its
// nodes' centroid, its axis from the break to the centroid, the farthest node's distance.
export function pieceShape(a, node) {
    const m = damageCutMask(a.parent, [node], true);
    const c = [0, 0, 0];
    let n = 0;
    for (let i = 0; i < a.n_nodes; i++) {
        if (!m[i]) continue;
        for (let k = 0; k < 3; k++) c[k] += a.rest[3 * i + k];
        n++;
    }
    const centre = c.map((x) => Math.fround(x / n)); // n >= 1: the node itself
    let axis = centre.map((x, k) => Math.fround(x - a.rest[3 * node + k])), ext = 0;
    for (let i = 0; i < a.n_nodes; i++) {
        if (m[i]) ext = Math.max(ext, Math.hypot(a.rest[3 * i] - centre[0], a.rest[3 * i + 1] - centre[1], a.rest[3 * i + 2] - centre[2]));
    }
    if (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2] < 1e-12) {
        const p = a.parent[node]; // a single node: its own segment's direction
        axis = [0, 1, 2].map((k) => (p >= 0 ? a.rest[3 * node + k] - a.rest[3 * p + k] : k === 2 ? 1 : 0));
    }
    return { centre, axis, extent_m: ext };
}

// protocol/damage_view.c: what a receiver holds after DAMAGE frames.
export class DamageView {
    constructor(n_trees) {
        this.n_trees = n_trees;
        this.fallen = new Uint8Array(n_trees);
        this.fall_az = new Uint8Array(n_trees);
        this.level = new Uint8Array(n_trees);
        this.fall_tick = new Uint32Array(n_trees);
        this.broken = []; // keys tree · 2^32 + node, ascending
        this.generation = 0;
        this.heal();
    }

    // Every tree intact.
    heal() {
        this.healTrees();
        this.broken.length = 0;
    }

    // Every tree standing with its full crown, the broken branches kept
    // (damage_view_heal_trees: a FOREST's state replaces the trees' fall and level only).
    healTrees() {
        this.fallen.fill(0);
        this.fall_az.fill(0);
        this.level.fill(DAMAGE.LEVELS);
        this.fall_tick.fill(0);
        this.generation++;
    }

    lower(k) {
        let lo = 0, hi = this.broken.length;
        while (lo < hi) {
            const mid = (lo + hi) >>> 1;
            if (this.broken[mid] < k) lo = mid + 1; else hi = mid;
        }
        return lo;
    }

    isBroken(t, node) {
        const k = t * 2 ** 32 + node, at = this.lower(k);
        return at < this.broken.length && this.broken[at] === k;
    }

    // A decoded DAMAGE ({ full, events }): full heals first; returns the events skipped
    // (trees outside the scene).
    apply(full, events) {
        let skipped = 0;
        if (full) this.heal();
        for (const e of events) {
            const t = e.tree;
            if (t >= this.n_trees) {
                skipped++;
                continue;
            }
            if (e.kind === DAMAGE.SNAP || e.kind === DAMAGE.UPROOT) {
                if (!this.fallen[t]) {
                    this.fallen[t] = e.kind;
                    this.fall_az[t] = e.value;
                    this.fall_tick[t] = e.tick;
                }
            } else if (e.kind === DAMAGE.STRIP) {
                this.level[t] = Math.min(this.level[t], e.value);
            } else {
                const k = t * 2 ** 32 + e.node, at = this.lower(k);
                if (at < this.broken.length && this.broken[at] === k) continue;
                this.broken.splice(at, 0, k);
            }
        }
        this.generation++;
        return skipped;
    }
}

// client_damage.c for the page: the view, each fall's start on the server clock, and per
// frame the trees' codes for the renderer. heights(t): the tree's height [m] at its scale;
// scale(t): its scale.
export class DamageFx {
    constructor(n_trees, tick_hz, heights, scales) {
        this.view = new DamageView(n_trees);
        this.tick_hz = tick_hz;
        this.height_m = heights;
        this.scale = scales;
        this.fall_t0_s = new Float64Array(n_trees).fill(NaN);
        this.code = new Float32Array(n_trees);
        this.az = new Float32Array(n_trees);
        this.bad = 0;
        this.tipping = 0;
        this.dirty = true;
        this.debris = []; // { path: DebrisPath, centre (tree frame, unit scale), species }
        this.scene = null; // { row(t): [species, x, y, z, yaw, scale], asset(t): asset or null }
        this.now_s = NaN;
    }

    // A piece of tree t from node leaves the tree where it broke, at t0_s (spawn_debris).
    spawnDebris(t, node, t0_s) {
        const a = this.scene && this.scene.asset(t);
        if (!a || node >= a.n_nodes) return;
        const row = this.scene.row(t), sc = row[5] > 0 ? row[5] : 1;
        const shape = pieceShape(a, node);
        if (this.debris.length === MAX_DEBRIS) { // full: the oldest piece goes
            let k = 0;
            for (let i = 1; i < this.debris.length; i++) if (this.debris[i].path.t0_s < this.debris[k].path.t0_s) k = i;
            this.debris.splice(k, 1);
        }
        const r0 = debrisFrameMatrix(row[4], this.fallAngle(t, t0_s), Math.fround(this.view.fall_az[t] * Math.fround(6.2831853 / 256)));
        // where the tree draws the piece's centre: turned about the fall's pivot
        const piv = this.pivot_m(t), d = [shape.centre[0], shape.centre[1], shape.centre[2] - piv];
        const c0 = [0, 1, 2].map((i) => row[1 + i] + sc * (r0[i] * d[0] + r0[3 + i] * d[1] + r0[6 + i] * d[2] + (i === 2 ? piv : 0)));
        this.debris.push({ path: new DebrisPath(t, node, t0_s, c0, r0, shape.axis, shape.extent_m * sc), centre: shape.centre, species: row[0] });
    }

    // The pieces at server time now_s (client_damage_frame): advanced in the wind, the
    // sunk ones dropped; per piece { tree, node, species, pos, yaw, fall, az }.
    debrisAt(now_s, wind) {
        this.now_s = now_s;
        const out = [];
        this.debris = this.debris.filter((dp) => {
            const p = dp.path;
            p.advance(now_s, wind);
            if (p.done() || !this.scene) return false;
            const r = p.rotation(), ce = dp.centre, row = this.scene.row(p.tree), s = row[5] > 0 ? row[5] : 1;
            const pos = [0, 1, 2].map((i) => p.c[i] - s * (r[i] * ce[0] + r[3 + i] * ce[1] + r[6 + i] * ce[2]));
            pos[2] -= p.sink_m();
            out.push({ tree: p.tree, node: p.node, species: dp.species, pos, ...debrisFrameAngles(r) });
            return true;
        });
        return out;
    }

    // A frame's DAMAGE (f.hdr, f.damage), or its FOREST as { full: false, healTrees: true,
    // events: forestEvents(f) } (web/wire.js): what is new to this picture, then applied.
    // A FOREST heals the trees' fall and level (not the branches) just before its events
    // are applied, so a tree it lists as fallen that this picture already holds fallen is
    // not new: it keeps its fall's start and goes on falling from where it is.
    take(hdr, d) {
        const v = this.view;
        for (const e of d.events) {
            if (e.tree >= v.n_trees) continue;
            const t0 = damageEventStart_s(hdr.tick, hdr.server_time_us, e.tick, this.tick_hz);
            if ((e.kind === DAMAGE.SNAP || e.kind === DAMAGE.UPROOT) && !v.fallen[e.tree]) {
                this.fall_t0_s[e.tree] = t0; // NaN: an old fall, lying at once
            } else if (e.kind === DAMAGE.BRANCH && !Number.isNaN(t0) && !v.isBroken(e.tree, e.node)) {
                this.spawnDebris(e.tree, e.node, t0);
            }
        }
        if (d.healTrees) v.healTrees();
        this.bad += v.apply(d.full, d.events);
        if (d.full || d.healTrees) {
            // a heal: what no longer stands broken stops moving (a FOREST keeps the branches)
            if (d.full) this.debris = this.debris.filter((dp) => v.isBroken(dp.path.tree, dp.path.node));
            for (let t = 0; t < v.n_trees; t++) if (!v.fallen[t]) this.fall_t0_s[t] = NaN;
        }
        this.dirty = true;
    }

    // The fall's pivot [m up the stem, unit scale]: the break of a snapped stem, else the base.
    pivot_m(t) {
        return this.view.fallen[t] === DAMAGE.SNAP ? tipFallBreak_m(t) : 0;
    }

    fallAngle(t, now_s) {
        if (!this.view.fallen[t]) return 0;
        const t0 = this.fall_t0_s[t];
        if (Number.isNaN(t0) || Number.isNaN(now_s)) return TIP_FALL.LYING_RAD;
        return Math.fround(tipFallAngle(now_s - t0, this.height_m(t) - this.scale(t) * this.pivot_m(t)));
    }

    // Per tree the u_trees slot 1 .z and .w at server time now_s (render_tree_code): true
    // when they changed since the last call.
    update(now_s) {
        if (!this.dirty && this.tipping === 0) return false;
        const v = this.view;
        let tipping = 0;
        for (let t = 0; t < v.n_trees; t++) {
            const fall = this.fallAngle(t, now_s);
            if (v.fallen[t] && fall < Math.fround(TIP_FALL.LYING_RAD)) tipping++;
            const snapped = fall > 0 && v.fallen[t] !== DAMAGE.UPROOT;
            this.code[t] = fall + 4 * (DAMAGE.LEVELS - v.level[t]) + (snapped ? 256 : 0);
            this.az[t] = Math.fround(v.fall_az[t] * Math.fround(6.2831853 / 256));
        }
        this.tipping = tipping;
        this.dirty = false;
        return true;
    }

    // The cut lists of render_damage_upload: per tree (first, count, keep-only 0, 0) and the
    // broken nodes in tree order, ascending; nodes(t): the node count of tree t's species
    // (a node outside it is left out).
    cutLists(nodesOf) {
        const n = this.view.n_trees, head = new Float32Array(4 * n), nodes = [];
        for (const k of this.view.broken) {
            const t = Math.floor(k / 2 ** 32), node = k % 2 ** 32;
            if (node >= nodesOf(t)) continue;
            if (head[4 * t + 1] === 0) head[4 * t] = nodes.length;
            head[4 * t + 1]++;
            nodes.push(node);
        }
        return { head, nodes: Float32Array.from(nodes.length ? nodes : [0]) };
    }
}
