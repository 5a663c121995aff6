// gale's binary frames in the browser (protocol/PROTOCOL.md "Binary frames"): the same
// checks and the same error texts as protocol/msg_*.c, so a frame the C decoder rejects is
// rejected here too. Pure: no DOM, runs under Node for the spec-vector test.

export const MSG = { KEYFRAME: 1, DELTA: 2, LEAVES: 3, WIND: 4, WEATHER: 5, DAMAGE: 6, BUNDLE: 7, FOREST: 8 };
const NAMES = ['?', 'KEYFRAME', 'DELTA', 'LEAVES', 'WIND', 'WEATHER', 'DAMAGE', 'BUNDLE', 'FOREST'];
export const LIMITS = {
    MAX_TREES: 262144, MAX_MODES: 64, MAX_SPECIES: 64, MAX_LEAVES: 4096, MAX_WIND_SIDE: 256,
    MAX_DAMAGE: 4096, MAX_BUNDLE: 16, MAX_FRAME_BYTES: 16 << 20, QMAX: 32767, MAX_STEP: 1e30,
};
const HEADER_BYTES = 20;
const GROUP = 8;
const MAX_WIDTH = 18;

// A rejected frame; state says the decoder lacks the base (send resync, wait for a KEYFRAME).
export class WireError extends Error {
    constructor(msg, state = false) {
        super(msg);
        this.state = state;
    }
}

class Reader {
    constructor(bytes, where) {
        this.b = bytes;
        this.v = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
        this.p = 0;
        this.where = where;
    }
    left() { return this.b.length - this.p; }
    need(n, what) {
        if (this.left() < n) {
            throw new WireError(`${this.where}: ${what} at byte ${this.p}: truncated`);
        }
    }
    u8(what) { this.need(1, what); return this.b[this.p++]; }
    u16(what) { this.need(2, what); const x = this.v.getUint16(this.p, true); this.p += 2; return x; }
    i16(what) { this.need(2, what); const x = this.v.getInt16(this.p, true); this.p += 2; return x; }
    u32(what) { this.need(4, what); const x = this.v.getUint32(this.p, true); this.p += 4; return x; }
    f32(what) {
        this.need(4, what);
        const x = this.v.getFloat32(this.p, true);
        this.p += 4;
        if (!Number.isFinite(x)) {
            throw new WireError(`${this.where}: ${what} at byte ${this.p - 4}: not finite`);
        }
        return x;
    }
    // LEB128, at most 5 bytes, no overlong forms (wire_get_varint)
    varint(what) {
        const at = this.p;
        let v = 0;
        for (let i = 0; i < 5; i++) {
            if (this.p >= this.b.length) break;
            const b = this.b[this.p++];
            if (i === 4 && b > 0x0f) break;
            v += (b & 0x7f) * 2 ** (7 * i);
            if (!(b & 0x80)) {
                if (i > 0 && b === 0) break;
                return v;
            }
        }
        throw new WireError(`${this.where}: ${what} at byte ${at}: truncated or bad varint`);
    }
    end() {
        if (this.left() !== 0) {
            throw new WireError(`${this.where}: length: expected ${this.p} bytes, got ${this.b.length} (trailing bytes)`);
        }
    }
}

export function typeName(t) { return NAMES[t] || `type ${t}`; }

// The 20-byte header (PROTOCOL.md "Frame header").
export function decodeHeader(bytes) {
    if (bytes.length > LIMITS.MAX_FRAME_BYTES) {
        throw new WireError(`wire: frame of ${bytes.length} bytes: expected <= ${LIMITS.MAX_FRAME_BYTES}`);
    }
    if (bytes.length < HEADER_BYTES) {
        throw new WireError(`wire: header: expected ${HEADER_BYTES} bytes, got ${bytes.length}`);
    }
    const v = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    if (v.getUint32(0, true) !== 0x454c4147) {
        throw new WireError('wire: magic at byte 0: expected "GALE"');
    }
    const version = v.getUint16(4, true);
    if (version !== 1) throw new WireError(`wire: version at byte 4: expected 1, got ${version}`);
    const type = bytes[6], flags = bytes[7];
    if (type < 1 || type > 8) throw new WireError(`wire: type at byte 6: expected 1..8, got ${type}`);
    if (flags !== 0) throw new WireError(`wire: flags at byte 7: expected 0, got ${flags}`);
    const tick = v.getUint32(8, true);
    const lo = v.getUint32(12, true), hi = v.getUint32(16, true);
    return { type, tick, server_time_us: hi * 4294967296 + lo };
}

// The decoder of one connection: the scene of the last KEYFRAME and the two newest
// snapshots (wire_decoder.c). decode() returns a frame object or throws a WireError; a
// rejected frame leaves the state as it was.
export class Decoder {
    constructor() { this.reset(); }

    reset() {
        this.scene = null;   // { n_trees, n_species, n_modes[], step[][], species Uint8Array, stride }
        this.last = null;    // { seq, n_modes Uint8Array, q Int16Array (n_trees × stride) }
        this.before = null;  // seq − 1 of last, only after a DELTA
        this.spare = [];     // snapshots no longer held, reused: no garbage per frame
    }

    // A snapshot's storage for n trees of `stride` modes, reused when one is spare.
    take(n, stride) {
        const s = this.spare.pop();
        if (s && s.q.length === n * stride && s.n_modes.length === n) return s;
        return { seq: 0, n_modes: new Uint8Array(n), q: new Int16Array(n * stride) };
    }

    give(s) {
        if (s && this.spare.length < 2) this.spare.push(s);
    }

    decode(bytes) {
        const h = decodeHeader(bytes);
        const r = new Reader(bytes, `wire: ${typeName(h.type)} tick ${h.tick}`);
        r.p = HEADER_BYTES;
        const f = { hdr: h, types: 1 << h.type };
        if (h.type === MSG.BUNDLE) return this.bundle(bytes, h, r);
        this.body(h, r, f, true);
        return f;
    }

    body(h, r, f, commit) {
        switch (h.type) {
        case MSG.KEYFRAME: case MSG.DELTA: f.state = this.state(h, r, commit); break;
        case MSG.LEAVES: f.leaves = leaves(r); break;
        case MSG.WIND: f.wind = wind(r); break;
        case MSG.WEATHER: f.weather = weather(r); break;
        case MSG.DAMAGE: f.damage = damage(r); break;
        case MSG.FOREST: f.forest = forest(r, h); break;
        default: throw new WireError(`${r.where}: type: a BUNDLE inside a BUNDLE`);
        }
        r.end();
    }

    // PROTOCOL.md "BUNDLE": the container checked whole, inner frames decoded, the state last.
    bundle(bytes, h, r) {
        const count = r.u8('count');
        if (count < 1 || count > LIMITS.MAX_BUNDLE) {
            throw new WireError(`${r.where}: count at byte 20: expected 1..${LIMITS.MAX_BUNDLE}, got ${count}`);
        }
        const inner = [];
        let seen = 0, states = 0;
        for (let i = 0; i < count; i++) {
            const len = r.u32(`frame ${i + 1} length`);
            if (len < HEADER_BYTES || len > r.left()) {
                throw new WireError(`${r.where}: frame ${i + 1} of ${count} at byte ${r.p - 4}: expected length ${HEADER_BYTES}..${r.left()}, got ${len}`);
            }
            const fb = bytes.subarray(r.p, r.p + len);
            r.p += len;
            const ih = decodeHeader(fb);
            if (ih.type === MSG.BUNDLE) throw new WireError(`${r.where}: frame ${i + 1} of ${count}: a BUNDLE inside a BUNDLE`);
            if (seen & (1 << ih.type)) throw new WireError(`${r.where}: frame ${i + 1} of ${count}: a second ${typeName(ih.type)}`);
            seen |= 1 << ih.type;
            if (ih.type === MSG.KEYFRAME || ih.type === MSG.DELTA) states++;
            inner.push([fb, ih, i]);
        }
        r.end();
        if (states > 1) throw new WireError(`${r.where}: more than one state frame`);
        // the state frame last, so a failing extra leaves the snapshots unchanged
        inner.sort((a, b) => isState(a[1].type) - isState(b[1].type));
        // the header reported: the state frame's, else the first inner frame's (msg_bundle.c)
        const f = { hdr: inner[0][1], types: seen };
        for (const [fb, ih, i] of inner) {
            const ir = new Reader(fb, `wire: ${typeName(ih.type)} tick ${ih.tick}`);
            ir.p = HEADER_BYTES;
            try {
                this.body(ih, ir, f, true);
            } catch (e) {
                if (!(e instanceof WireError)) throw e;
                throw new WireError(`${r.where}: frame ${i + 1} of ${count}: ${e.message}`, e.state);
            }
            if (isState(ih.type)) f.hdr = ih;
        }
        return f;
    }

    // KEYFRAME / DELTA (PROTOCOL.md; wire_decode_state in protocol/msg_state_dec.c).
    state(h, r, commit) {
        const key = h.type === MSG.KEYFRAME;
        const where = r.where;
        const seq = r.u32('seq');
        let sc = this.scene, hist = 0;
        if (key) {
            const n_trees = r.u32('n_trees');
            if (n_trees === 0 || n_trees > LIMITS.MAX_TREES) {
                throw new WireError(`${where}: n_trees at byte 24: expected 1..${LIMITS.MAX_TREES}, got ${n_trees}`);
            }
            const n_species = r.u8('n_species');
            if (n_species === 0 || n_species > LIMITS.MAX_SPECIES) {
                throw new WireError(`${where}: n_species at byte 28: expected 1..${LIMITS.MAX_SPECIES}, got ${n_species}`);
            }
            const n_modes = [], step = [];
            for (let s = 0; s < n_species; s++) {
                const nm = r.u8(`species ${s} n_modes`);
                if (nm === 0 || nm > LIMITS.MAX_MODES) {
                    throw new WireError(`${where}: species ${s} n_modes at byte ${r.p - 1}: expected 1..${LIMITS.MAX_MODES}, got ${nm}`);
                }
                const st = new Float32Array(nm);
                for (let m = 0; m < nm; m++) {
                    const x = r.v.getFloat32((r.need(4, `species ${s} step ${m}`), r.p), true);
                    if (!(x > 0 && x <= LIMITS.MAX_STEP)) {
                        throw new WireError(`${where}: species ${s} step ${m} at byte ${r.p}: expected in (0, 1e+30], got ${x}`);
                    }
                    r.p += 4;
                    st[m] = x;
                }
                n_modes.push(nm);
                step.push(st);
            }
            if (r.left() < n_trees) {
                throw new WireError(`${where}: species of trees at byte ${r.p}: truncated: expected ${n_trees} bytes, got ${r.left()}`);
            }
            const species = bytes8(r, n_trees);
            for (let t = 0; t < n_trees; t++) {
                if (species[t] >= n_species) {
                    throw new WireError(`${where}: species of tree ${t} at byte ${r.p - n_trees + t}: expected < ${n_species}, got ${species[t]}`);
                }
            }
            sc = { n_trees, n_species, n_modes, step, species, stride: Math.max(...n_modes) };
        } else {
            if (!this.last) throw new WireError(`${where}: seq ${seq}: no keyframe yet: waiting for a keyframe`, true);
            if (seq !== ((this.last.seq + 1) >>> 0)) {
                throw new WireError(`${where}: seq ${seq}: gap: expected seq ${this.last.seq + 1} (holding ${this.last.seq}): waiting for a keyframe`, true);
            }
            hist = r.u8('history');
            if (hist < 1 || hist > 2) throw new WireError(`${where}: history at byte ${r.p - 1}: expected 1 or 2, got ${hist}`);
            if (hist === 2 && !this.before) {
                throw new WireError(`${where}: seq ${seq}: predicts from seq ${seq - 2} which this decoder does not hold: waiting for a keyframe`, true);
            }
        }
        const snap = this.take(sc.n_trees, sc.stride);
        try {
            this.treeSet(r, sc, key, snap.n_modes);
            this.values(r, sc, snap.n_modes, key ? null : this.last, hist === 2 ? this.before : null, hist, snap.q);
            r.end();
        } catch (e) {
            this.give(snap);
            throw e;
        }
        snap.seq = seq;
        if (commit) {
            if (key) {
                this.scene = sc;
                this.give(this.before);
                this.before = null;
                this.give(this.last);
            } else {
                this.give(this.before);
                this.before = this.last;
            }
            this.last = snap;
        }
        // n_modes and q are the decoder's own until the frame after next: read them now
        return { seq, scene: sc, n_modes: snap.n_modes, q: snap.q, keyframe: key };
    }

    treeSet(r, sc, key, n_modes) {
        const where = r.where;
        const at = r.p;
        const kind = r.u8('tree set');
        if (kind === 0 && !key) {
            n_modes.set(this.last.n_modes);
            return n_modes;
        }
        n_modes.fill(0);
        if (kind !== 1) {
            throw new WireError(`${where}: tree set kind at byte ${at}: expected ${key ? '1 (runs)' : '0 (same) or 1 (runs)'}, got ${kind}`);
        }
        const n_runs = r.varint('run count');
        if (n_runs > sc.n_trees) throw new WireError(`${where}: run count: expected <= ${sc.n_trees} trees, got ${n_runs}`);
        let pos = 0, n_present = 0;
        for (let i = 0; i < n_runs; i++) {
            const rat = r.p;
            const gap = r.varint(`run ${i}`), len = r.varint(`run ${i}`);
            if (len === 0 || (i > 0 && gap === 0)) {
                throw new WireError(`${where}: run ${i} at byte ${rat}: expected gap >= ${i > 0 ? 1 : 0} and length >= 1, got ${gap}, ${len}`);
            }
            if (gap > sc.n_trees - pos || len > sc.n_trees - pos - gap) {
                throw new WireError(`${where}: run ${i} at byte ${rat}: expected to end <= ${sc.n_trees} trees, got ${pos} + ${gap} + ${len}`);
            }
            pos += gap;
            n_modes.fill(1, pos, pos + len);
            pos += len;
            n_present += len;
        }
        const mat = r.p;
        const mk = r.u8('mode list kind');
        if (mk > 1) throw new WireError(`${where}: mode list kind at byte ${mat}: expected 0 (full) or 1 (list), got ${mk}`);
        if (mk === 1 && r.left() < n_present) {
            throw new WireError(`${where}: mode list at byte ${r.p}: truncated: expected ${n_present} bytes, got ${r.left()}`);
        }
        for (let t = 0; t < sc.n_trees; t++) {
            if (!n_modes[t]) continue;
            const full = sc.n_modes[sc.species[t]];
            let n = full;
            if (mk === 1) {
                n = r.b[r.p++];
                if (n === 0 || n > full) throw new WireError(`${where}: modes of tree ${t} at byte ${r.p - 1}: expected 1..${full}, got ${n}`);
            }
            n_modes[t] = n;
        }
        return n_modes;
    }

    values(r, sc, n_modes, prev, prev2, hist, q) {
        r.p = unpackValues(r.b, r.p, r.where, sc.n_trees, sc.stride, n_modes, q,
            prev ? prev.q : q, prev2 ? prev2.q : q, hist);
        return q;
    }
}

// The values section (PROTOCOL.md "Values"; get_values in protocol/msg_state_dec.c) from byte
// p of b into q [n_trees × stride]; returns the byte after it. One pass over flat typed
// arrays with the position in a local: this loop is most of a frame's decode. pq, pq2:
// the snapshots a predictor 1 or 2 reads (any array when the history lacks them: a
// predictor above hist is refused before either is read).
function unpackValues(b, p, where, n_trees, stride, n_modes, q, pq, pq2, hist) {
    const len = b.length, QMAX = LIMITS.QMAX;
    for (let t = 0; t < n_trees; t++) {
        const n = n_modes[t], base = t * stride;
        // short runs zeroed in loops: fill() costs a call each, per tree and group
        for (let ix = base + n; ix < base + stride; ix++) q[ix] = 0;
        for (let g0 = 0; g0 < n; g0 += GROUP) {
            const k = n - g0 < GROUP ? n - g0 : GROUP;
            const at = p;
            if (p >= len) throw new WireError(`${where}: tree ${t} group ${g0 / GROUP} at byte ${at}: truncated`);
            const gh = b[p++];
            const width = gh & 0x1f, pred = gh >> 5;
            if (width > MAX_WIDTH || pred > hist) {
                throw new WireError(`${where}: tree ${t} group ${g0 / GROUP} at byte ${at}: expected width <= ${MAX_WIDTH} and predictor <= ${hist}, got ${width}, ${pred}`);
            }
            if (len - p < (k * width + 7) >> 3) throw new WireError(`${where}: tree ${t} group ${g0 / GROUP} at byte ${at}: truncated or nonzero padding`);
            const ix0 = base + g0, ix1 = ix0 + k;
            if (width === 0 && pred < 2) {
                // a quiet group: no bytes, the prediction itself (always in range)
                if (pred === 0) for (let ix = ix0; ix < ix1; ix++) q[ix] = 0;
                else for (let ix = ix0; ix < ix1; ix++) q[ix] = pq[ix];
                continue;
            }
            const mask = (1 << width) - 1;
            if (k === GROUP && width <= 16 && len - p >= width + 2) {
                // a full group is exactly `width` bytes, no padding to check
                if (pred === 0 && width <= 8) {
                    // the group's <= 64 bits as two words; |v| <= 128: in range unchecked
                    let lo = 0, hi = 0;
                    for (let j = 0; j < width; j++) {
                        if (j < 4) lo |= b[p + j] << (8 * j);
                        else hi |= b[p + j] << (8 * j - 32);
                    }
                    if (width <= 4) {
                        for (let ix = ix0; ix < ix0 + GROUP; ix++) {
                            const z = lo & mask;
                            lo >>>= width;
                            q[ix] = (z >>> 1) ^ -(z & 1);
                        }
                    } else {
                        for (let i = 0, o = 0; i < GROUP; i++, o += width) {
                            const z = (o + width <= 32 ? lo >>> o : o >= 32 ? hi >>> (o - 32) : (lo >>> o) | (hi << (32 - o))) & mask;
                            q[ix0 + i] = (z >>> 1) ^ -(z & 1);
                        }
                    }
                    p += width;
                    continue;
                }
                if (width <= 4) {
                    // a predicted group in <= 32 bits: one word, as above, each value added
                    // to its prediction and checked (most delta groups are this narrow)
                    let lo = 0;
                    for (let j = 0; j < width; j++) lo |= b[p + j] << (8 * j);
                    if (pred === 1) {
                        for (let ix = ix0; ix < ix0 + GROUP; ix++) {
                            const z = lo & mask;
                            lo >>>= width;
                            const v = ((z >>> 1) ^ -(z & 1)) + pq[ix];
                            if (v < -QMAX || v > QMAX) throw new WireError(`${where}: tree ${t} mode ${ix - base} at byte ${at}: expected |q| <= ${QMAX}, got ${v}`);
                            q[ix] = v;
                        }
                    } else {
                        for (let ix = ix0; ix < ix0 + GROUP; ix++) {
                            const z = lo & mask;
                            lo >>>= width;
                            const v = ((z >>> 1) ^ -(z & 1)) + 2 * pq[ix] - pq2[ix];
                            if (v < -QMAX || v > QMAX) throw new WireError(`${where}: tree ${t} mode ${ix - base} at byte ${at}: expected |q| <= ${QMAX}, got ${v}`);
                            q[ix] = v;
                        }
                    }
                    p += width;
                    continue;
                }
                // value i from the 3 bytes at bit i·width (its bits and the shift fit in 24;
                // the 2 bytes read past a group are masked off)
                for (let i = 0, o = 0; i < GROUP; i++, o += width) {
                    const j = p + (o >> 3);
                    const z = ((b[j] | (b[j + 1] << 8) | (b[j + 2] << 16)) >> (o & 7)) & mask;
                    const ix = ix0 + i;
                    let v = (z >>> 1) ^ -(z & 1);
                    if (pred === 1) v += pq[ix];
                    else if (pred === 2) v += 2 * pq[ix] - pq2[ix];
                    if (v < -QMAX || v > QMAX) {
                        throw new WireError(`${where}: tree ${t} mode ${ix - base} at byte ${at}: expected |q| <= ${QMAX}, got ${v}`);
                    }
                    q[ix] = v;
                }
                p += width;
                continue;
            }
            let acc = 0, nacc = 0; // acc holds < width + 8 <= 26 bits
            for (let ix = ix0; ix < ix1; ix++) {
                while (nacc < width) {
                    acc |= b[p++] << nacc;
                    nacc += 8;
                }
                const z = acc & mask;
                acc >>>= width;
                nacc -= width;
                let v = (z >>> 1) ^ -(z & 1);
                if (pred === 1) v += pq[ix];
                else if (pred === 2) v += 2 * pq[ix] - pq2[ix];
                if (v < -QMAX || v > QMAX) {
                    throw new WireError(`${where}: tree ${t} mode ${ix - base} at byte ${at}: expected |q| <= ${QMAX}, got ${v}`);
                }
                q[ix] = v;
            }
            if (acc !== 0) throw new WireError(`${where}: tree ${t} group ${g0 / GROUP} at byte ${at}: truncated or nonzero padding`);
        }
    }
    return p;
}

function isState(type) { return type === MSG.KEYFRAME || type === MSG.DELTA ? 1 : 0; }

function bytes8(r, n) {
    const a = r.b.slice(r.p, r.p + n);
    r.p += n;
    return a;
}

function leaves(r) {
    const n = r.u16('count');
    if (n > LIMITS.MAX_LEAVES) throw new WireError(`${r.where}: count at byte 20: expected <= ${LIMITS.MAX_LEAVES}, got ${n}`);
    const out = [];
    for (let i = 0; i < n; i++) {
        out.push({ instance: r.u32('instance'), slot: r.u16('slot'), spawn_tick: r.u32('spawn_tick'), seed: r.u32('seed') });
    }
    return out;
}

function wind(r) {
    const w = { x0_m: r.f32('x0_m'), y0_m: r.f32('y0_m'), z_m: r.f32('z_m'), cell_m: r.f32('cell_m'), scale_ms: r.f32('scale_ms') };
    if (!(w.cell_m > 0)) throw new WireError(`${r.where}: cell_m at byte 32: expected > 0, got ${w.cell_m}`);
    if (!(w.scale_ms > 0)) throw new WireError(`${r.where}: scale_ms at byte 36: expected > 0, got ${w.scale_ms}`);
    w.nx = r.u16('nx');
    w.ny = r.u16('ny');
    for (const k of ['nx', 'ny']) {
        if (w[k] < 1 || w[k] > LIMITS.MAX_WIND_SIDE) throw new WireError(`${r.where}: ${k}: expected 1..${LIMITS.MAX_WIND_SIDE}, got ${w[k]}`);
    }
    const n = 3 * w.nx * w.ny;
    r.need(n, 'cells');
    w.cells = new Int8Array(r.b.buffer, r.b.byteOffset + r.p, n).slice();
    r.p += n;
    return w;
}

// WEATHER (PROTOCOL.md "WEATHER (type 5)"): every field range-checked as msg_weather.c
// does (weather_bad_field); a field its flags leave unset holds its "none" value exactly.
function weather(r) {
    const w = {};
    w.sustained_ms = r.f32('sustained_ms');
    w.gust_ms = r.f32('gust_ms');
    w.dir_from_deg = r.f32('dir_from_deg');
    w.ss_class = r.u8('ss_class');
    w.beaufort = r.u8('beaufort');
    w.flags = r.u8('flags');
    w.storm_class = r.u8('storm_class');
    w.pressure_hpa = r.f32('pressure_hpa');
    w.central_hpa = r.f32('central_hpa');
    w.distance_km = r.f32('distance_km');
    w.bearing_deg = r.f32('bearing_deg');
    w.utc_min = r.u32('utc_min');
    w.utc_offset_min = r.i16('utc_offset_min');
    w.storm_min = r.f32('storm_min');
    w.replay_pos_s = r.f32('replay_pos_s');
    w.replay_len_s = r.f32('replay_len_s');
    w.replay_speed = r.f32('replay_speed');
    const bad = weatherBadField(w);
    if (bad) throw new WireError(`${r.where}: ${bad}: out of range (PROTOCOL.md "WEATHER")`);
    const n = r.u8('name_len');
    if (n > 63 || n !== r.left()) throw new WireError(`${r.where}: name_len: expected ${Math.min(63, r.left())} (the bytes left), got ${n}`);
    const nb = r.b.subarray(r.p, r.p + n);
    for (const c of nb) {
        if (c < 0x20 || c === 0x7f) throw new WireError(`${r.where}: name: byte ${c} below 0x20 or 0x7f`);
    }
    try {
        w.name = UTF8.decode(nb);
    } catch (e) {
        throw new WireError(`${r.where}: name (not UTF-8): out of range (PROTOCOL.md "WEATHER")`);
    }
    r.p += n;
    return w;
}

const UTF8 = new TextDecoder('utf-8', { fatal: true });
const W_STORM = 1, W_FINISHED = 4, W_CLOCK = 8, W_PAUSED = 16, W_FLAGS_ALL = 0x1f;

function weatherBadField(w) {
    const inr = (x, lo, hi) => x >= lo && x <= hi;
    const storm = (w.flags & W_STORM) !== 0, clock = (w.flags & W_CLOCK) !== 0;
    if (!inr(w.sustained_ms, 0, 200)) return 'sustained_ms';
    if (!inr(w.gust_ms, 0, 300)) return 'gust_ms';
    if (!(w.dir_from_deg >= 0 && w.dir_from_deg < 360)) return 'dir_from_deg';
    if (w.ss_class >= 7) return 'ss_class';
    if (w.beaufort > 12) return 'beaufort';
    // FINISHED, PAUSED and CLOCK describe a replay: only with STORM
    if ((w.flags & ~W_FLAGS_ALL) || (!storm && (w.flags & (W_FINISHED | W_PAUSED | W_CLOCK)))) return 'flags';
    if (storm ? w.storm_class >= 7 : w.storm_class !== 255) return 'storm_class';
    if (!inr(w.pressure_hpa, 800, 1100)) return 'pressure_hpa';
    if (storm ? !inr(w.central_hpa, 800, 1100) : w.central_hpa !== 0) return 'central_hpa';
    if (storm ? !inr(w.distance_km, 0, 20000) : w.distance_km !== -1) return 'distance_km';
    if (storm ? !(w.bearing_deg >= 0 && w.bearing_deg < 360) : w.bearing_deg !== 0) return 'bearing_deg';
    if (!clock && w.utc_min !== 0) return 'utc_min';
    if (clock ? w.utc_offset_min < -840 || w.utc_offset_min > 840 : w.utc_offset_min !== 0) return 'utc_offset_min';
    if (storm ? !inr(w.storm_min, -1e6, Math.fround(1e6)) : w.storm_min !== 0) return 'storm_min';
    if (storm ? !inr(w.replay_pos_s, 0, Math.fround(1e9)) : w.replay_pos_s !== 0) return 'replay_pos_s';
    if (storm ? !inr(w.replay_len_s, 0, Math.fround(1e9)) : w.replay_len_s !== 0) return 'replay_len_s';
    if (storm ? !inr(w.replay_speed, 0, Math.fround(1e5)) : w.replay_speed !== 0) return 'replay_speed';
    return null;
}

const DAMAGE_KINDS = ['', 'BRANCH', 'SNAP', 'UPROOT', 'STRIP'];

function damage(r) {
    const full = r.u8('full');
    if (full > 1) throw new WireError(`${r.where}: full at byte 20: expected 0 or 1, got ${full}`);
    const n = r.u16('count');
    if (n > LIMITS.MAX_DAMAGE) throw new WireError(`${r.where}: count at byte 21: expected <= ${LIMITS.MAX_DAMAGE}, got ${n}`);
    const events = [];
    for (let i = 0; i < n; i++) {
        const at = r.p;
        const e = { tree: r.u32('tree'), node: r.u32('node'), kind: r.u8('kind'), value: r.u8('value'), tick: r.u32('tick') };
        if (e.kind < 1 || e.kind > 4) throw new WireError(`${r.where}: event ${i} at byte ${at}: kind: expected 1..4, got ${e.kind}`);
        // BRANCH names a node; the others the whole tree (ff ff ff ff), which is no node
        if ((e.kind !== 1) !== (e.node === 0xffffffff)) throw new WireError(`${r.where}: event ${i} at byte ${at}: node: expected ${e.kind === 1 ? 'a node index' : 'ff ff ff ff'} for ${DAMAGE_KINDS[e.kind]}, got ${e.node}`);
        if (e.kind === 4 && e.value > 32) throw new WireError(`${r.where}: event ${i} at byte ${at}: value: expected <= 32 for STRIP, got ${e.value}`);
        if (e.kind === 1 && e.value !== 0) throw new WireError(`${r.where}: event ${i} at byte ${at}: value: expected 0 for BRANCH, got ${e.value}`);
        e.kindName = DAMAGE_KINDS[e.kind];
        events.push(e);
    }
    return { full: full === 1, events };
}

// FOREST (PROTOCOL.md "FOREST (type 8)"; wire_decode_forest in protocol/msg_forest.c): trees
// [first, first + count) as a state byte each, fall << 6 | level, then the fallen ones'
// azimuth and tick in tree order. The checks and texts are the C's (which also refuses a
// count over its decoder's trees; this decoder has no such bound).
const FOREST_FIXED = HEADER_BYTES + 8, FOREST_FALL = 5, FOREST_LEVEL_MASK = 0x3f, FOREST_FALL_SHIFT = 6;
const forestStateValid = (s) => (s & FOREST_LEVEL_MASK) <= 32 && (s >> FOREST_FALL_SHIFT) !== 1;

function forest(r, h) {
    if (r.left() < 8) throw new WireError(`${r.where}: first, count at byte ${HEADER_BYTES}: truncated`);
    const first = r.u32('first'), count = r.u32('count');
    if (count > LIMITS.MAX_TREES || first > LIMITS.MAX_TREES - count) {
        throw new WireError(`${r.where}: count at byte ${HEADER_BYTES + 4}: expected first + count <= ${LIMITS.MAX_TREES}, got ${first} + ${count}`);
    }
    if (r.left() < count) {
        throw new WireError(`${r.where}: length: expected >= ${FOREST_FIXED + count} bytes for ${count} trees, got ${FOREST_FIXED + r.left()}`);
    }
    const state = r.b.slice(r.p, r.p + count);
    let fallen = 0;
    for (let i = 0; i < count; i++) {
        const s = state[i];
        if (!forestStateValid(s)) {
            throw new WireError(`${r.where}: tree ${first + i} at byte ${FOREST_FIXED + i}: expected level <= 32 and fall 0, 2 or 3, got 0x${s.toString(16).padStart(2, '0')}`);
        }
        fallen += s >> FOREST_FALL_SHIFT ? 1 : 0;
    }
    r.p += count;
    if (r.left() !== fallen * FOREST_FALL) {
        throw new WireError(`${r.where}: length: expected ${FOREST_FIXED + count + fallen * FOREST_FALL} bytes for ${count} trees, ${fallen} fallen, got ${FOREST_FIXED + count + r.left()}`);
    }
    const falls = [];
    for (let i = 0; i < fallen; i++) falls.push({ az: r.u8('azimuth'), tick: r.u32('tick') });
    return { first, count, state, falls };
}

// A decoded frame's FOREST (f.forest, f.hdr) as the DAMAGE events it stands for
// (wire_forest_events): in tree order a SNAP or UPROOT for each fallen tree (its azimuth
// and tick) and a STRIP for each crown below 32 (the frame's tick); [] without a FOREST.
// Applied after healing every tree's fall and level (not its branches), they give the
// state the frame holds (DamageView.healTrees, web/damage.js).
export function forestEvents(f) {
    const fo = f.forest, out = [];
    if (!fo) return out;
    for (let i = 0, k = 0; i < fo.count; i++) {
        const s = fo.state[i], tree = fo.first + i, fall = s >> FOREST_FALL_SHIFT, level = s & FOREST_LEVEL_MASK;
        if (fall && k < fo.falls.length) {
            const fl = fo.falls[k++];
            out.push({ tree, node: 0xffffffff, kind: fall, value: fl.az, tick: fl.tick, kindName: DAMAGE_KINDS[fall] });
        }
        if (level < 32) out.push({ tree, node: 0xffffffff, kind: 4, value: level, tick: f.hdr.tick, kindName: DAMAGE_KINDS[4] });
    }
    return out;
}

// Each value's step [n_trees × stride]: step_m of the tree's species, 0 past its modes;
// built once per keyframe scene. q_i = Q_i step_i is then one multiply per value.
export function sceneSteps(sc) {
    if (sc.steps) return sc.steps;
    const stride = sc.stride, out = new Float32Array(sc.n_trees * stride);
    for (let t = 0; t < sc.n_trees; t++) out.set(sc.step[sc.species[t]], t * stride);
    sc.steps = out;
    return out;
}

// q of every tree as floats: q_i = Q_i step_i (PROTOCOL.md "Quantisation of q") into
// out[n_trees × stride] (0 where a mode was not sent: the decoder keeps Q 0 there).
export function dequantise(st, out) {
    const steps = sceneSteps(st.scene), q = st.q;
    for (let i = 0; i < steps.length; i++) out[i] = q[i] * steps[i];
    return out;
}
