// Differential fuzzer of the browser's decoders: the same inputs go to protocol/'s C
// decoders (through gale-web-decode-dump, tests/web/decode_dump.c) and to web/wire.js and
// web/asset.js, each printing one canonical line per frame (per asset: its hash64 and
// CRC-32, then its decode), and the lines must be equal: the same accept or reject (and a
// rejected DELTA the same "wait for a keyframe" or not) and the same decoded values, floats
// compared bit for bit. Inputs: the C fuzzers' seed corpus (tests/fuzz/corpus/wire,
// tests/fuzz/corpus/asset), PROTOCOL.md's test vectors and ASSET.md's example, then
// mutations of them from a fixed seed: bit flips, bytes set to edge values, truncations,
// splices, inserted and deleted runs, count and length fields rewritten, BUNDLEs of seeds;
// a frame goes alone, after the corpus keyframe, or after that keyframe and a DELTA (so
// predictors 1 and 2 are reached); an asset goes as it is or with its header and CRCs
// repaired (so a mutation reaches the sections, as tests/fuzz/fuzz_asset.c does). Besides
// the seeds, KEYFRAMEs and DELTAs are built from parts (random trees, runs, mode lists,
// and groups of every width and predictor) so every path of the value decoders is reached,
// and FOREST frames (random states and falls, alone or in a KEYFRAME's BUNDLE after a
// DAMAGE), whose lines hold the DAMAGE events each side makes of them as well.
// The browser's asset reader draws with a subset of the file: it skips MODE's arrays (the
// server's), params_json and the optional sections, and checks no range of a value it
// only draws with; an asset asset_decode refuses for one of those alone (RELAXED below)
// may pass it, every other refusal must be its too. It refuses by design an asset with
// modes and no CORR (the browser draws the length-true pose only).
//   node fuzz_web_decoders.mjs DECODE_DUMP WORK_DIR [--cases N] [--seconds S] [--seed K]
// Exits 1 at the first disagreement, the input written to WORK_DIR/disagree-*.bin.
import { spawnSync } from 'node:child_process';
import { mkdirSync, readdirSync, readFileSync, writeFileSync } from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { Decoder, WireError, forestEvents } from '../../web/wire.js';
import { decodeAsset, AssetError, hash64, crc32 } from '../../web/asset.js';
import { readVectors } from './spec_vectors.mjs';

const argv = process.argv.slice(2);
if (argv.includes('--help') || argv.length < 2) {
    console.log('usage: node fuzz_web_decoders.mjs DECODE_DUMP WORK_DIR [--cases N] [--seconds S] [--seed K]\n' +
        '  compares web/wire.js and web/asset.js with protocol/ on seeds and N mutations (default 3000),\n' +
        '  or as many as fit in S seconds; prints a JSON summary, exits 1 at a disagreement');
    process.exit(argv.includes('--help') ? 0 : 2);
}
const [dump, work] = argv;
const opt = (k, d) => (argv.includes(k) ? Number(argv[argv.indexOf(k) + 1]) : d);
const seconds = opt('--seconds', 0), cases = opt('--cases', seconds ? Infinity : 3000), seed0 = opt('--seed', 1);
const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
mkdirSync(work, { recursive: true });

// asset_decode refusals the browser's reader may pass, by the field asset_decode names:
// what it does not read (params, MODE's arrays, the optional sections' content), and
// ranges of values it only draws with (a normal's length, a weight, a radius, a size)
const RELAXED = new Set(['params_json', 'params_json length', 'source_hash', 'species', 'omega', 'gamma',
    'wind_basis', 'phi', 'phi_rot', 'MODE', 'n_modes', 'META', 'SRID', 'SRES', 'source_id', 'n_source_ids',
    'source_origin', 'static_res', 'n_static_cols', 'mesh_normal', 'mesh_weight', 'leaf_normal', 'leaf_size',
    'radius', 'bark_rgb', 'leaf_rgb']);
const relaxed = (cline) => { const m = cline.match(/^E bad fuzz: (.+?) at byte \d+/); return m && RELAXED.has(m[1]); };

// ---- deterministic randomness (mulberry32) ----
let rs = seed0 >>> 0;
function rnd() {
    rs = (rs + 0x6d2b79f5) >>> 0;
    let t = rs;
    t = Math.imul(t ^ (t >>> 15), t | 1);
    t ^= t + Math.imul(t ^ (t >>> 7), t | 61);
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
}
const ri = (n) => Math.floor(rnd() * n);
const pick = (a) => a[ri(a.length)];

// ---- seeds ----
const readDir = (d) => readdirSync(d).sort().map((n) => new Uint8Array(readFileSync(path.join(d, n))));
const wireSeeds = readDir(path.join(root, 'tests/fuzz/corpus/wire'));
const vec = readVectors(path.join(root, 'protocol/PROTOCOL.md')).hex;
wireSeeds.push(...Object.values(vec));
const keyframe = new Uint8Array(readFileSync(path.join(root, 'tests/fuzz/corpus/wire/keyframe')));
const deltaSame = new Uint8Array(readFileSync(path.join(root, 'tests/fuzz/corpus/wire/delta_same')));
const assetSeeds = readDir(path.join(root, 'tests/fuzz/corpus/asset'));
const assetMd = readFileSync(path.join(root, 'protocol/ASSET.md'), 'utf8');
const ex = assetMd.match(/## Example: the smallest asset[\s\S]*?```\n([\s\S]*?)\n```/);
if (ex) {
    const hex = ex[1].split('\n').map((l) => l.replace(/^[0-9a-f]+:/, '').trim()).join(' ').split(/\s+/).filter((h) => /^[0-9a-f]{2}$/.test(h));
    if (hex.length > 24) assetSeeds.push(Uint8Array.from(hex.map((h) => parseInt(h, 16))));
}

// ---- mutations ----
const EDGE = [0, 1, 2, 7, 8, 0x10, 0x1f, 0x20, 0x3f, 0x40, 0x7f, 0x80, 0xfe, 0xff];
function put(b, at, v, n) {
    for (let i = 0; i < n && at + i < b.length; i++) b[at + i] = (v / 2 ** (8 * i)) & 0xff;
}
function mutateOnce(b, others, fields) {
    const n = b.length;
    switch (ri(9)) {
    case 0: { // bit flips
        if (!n) return b;
        const c = b.slice();
        for (let k = 1 + ri(3); k > 0; k--) c[ri(n)] ^= 1 << ri(8);
        return c;
    }
    case 1: { // a byte set to an edge value
        if (!n) return b;
        const c = b.slice();
        c[ri(n)] = pick(EDGE);
        return c;
    }
    case 2: return b.slice(0, ri(n + 1)); // truncation
    case 3: { // splice: a head of this, a tail of another
        const o = pick(others);
        return Uint8Array.from([...b.subarray(0, ri(n + 1)), ...o.subarray(ri(o.length + 1))]);
    }
    case 4: { // a run inserted
        const at = ri(n + 1), k = 1 + ri(8), c = new Uint8Array(n + k);
        c.set(b.subarray(0, at));
        for (let i = 0; i < k; i++) c[at + i] = rnd() < 0.5 ? pick(EDGE) : ri(256);
        c.set(b.subarray(at), at + k);
        return c;
    }
    case 5: { // a run deleted
        const at = ri(n + 1), k = 1 + ri(8);
        return Uint8Array.from([...b.subarray(0, at), ...b.subarray(at + k)]);
    }
    case 6: { // a run duplicated
        const at = ri(n + 1), k = 1 + ri(16);
        return Uint8Array.from([...b.subarray(0, at + k), ...b.subarray(at, at + k), ...b.subarray(at + k)]);
    }
    default: { // a count or length field rewritten: at a known field, or anywhere
        const c = b.slice();
        const f = fields.length && rnd() < 0.7 ? pick(fields) : [ri(Math.max(n, 1)), pick([1, 2, 4, 8])];
        const [at, w] = f;
        const old = at + w <= n ? c.subarray(at, at + w).reduce((s, x, i) => s + x * 2 ** (8 * i), 0) : 0;
        const v = pick([0, 1, 2, 3, old + 1, old - 1, old + 2, old + 3, old - 3, old * 2, n, n - at, 2 ** (8 * Math.min(w, 4)) - 1, 2 ** 31, 0x80, 64, 65, 262144, 262145]);
        put(c, at, Math.max(0, v), Math.min(w, 4));
        if (w === 8) put(c, at + 4, rnd() < 0.8 ? 0 : ri(4), 4);
        return c;
    }
    }
}
// Count and length fields of a frame: the body's first bytes (counts of every type), a
// BUNDLE's inner lengths, and any byte that may start a varint.
function wireFields(b) {
    const f = [[20, 1], [20, 2], [20, 4], [21, 1], [21, 2], [24, 4], [28, 1], [29, 1]];
    if (b[6] === 7 && b.length > 21) {
        for (let p = 21, i = 0; i < b[20] && p + 4 <= b.length; i++) {
            f.push([p, 4]);
            p += 4 + (b[p] | (b[p + 1] << 8) | (b[p + 2] << 16));
        }
    }
    for (let k = 0; k < 4; k++) f.push([20 + ri(Math.max(1, b.length - 20)), 1]);
    return f;
}
// An asset's header fields and every section's length.
function assetFields(b) {
    const f = [[4, 4], [8, 8]];
    for (let p = 24; p + 12 <= b.length; p++) {
        const tag = String.fromCharCode(b[p], b[p + 1], b[p + 2], b[p + 3]);
        if (!/^(META|SKEL|MODE|CORR|MESH|LEAF|LOOK|SRID|SRES)$/.test(tag)) continue;
        f.push([p + 4, 8], [p + 12, 4], [p, 4]);
        // words of the body: counts, flags, indices, LOD ranges
        const len = b[p + 4] | (b[p + 5] << 8);
        for (let k = 0; k < 6; k++) f.push([p + 12 + 4 * ri(Math.max(1, len >> 2)), 4]);
    }
    return f;
}
function mutate(b, others, fields) {
    for (let k = rnd() < 0.5 ? 1 : 1 + ri(3); k > 0; k--) b = mutateOnce(b, others, fields(b));
    return b;
}
function bundleOf(frames) {
    const n = frames.reduce((s, f) => s + 4 + f.length, 21);
    const b = new Uint8Array(n);
    b.set(frames[0].subarray(0, 20));
    b[6] = 7;
    b[20] = frames.length;
    let p = 21;
    for (const f of frames) {
        put(b, p, f.length, 4);
        b.set(f, p + 4);
        p += 4 + f.length;
    }
    return b;
}
function repairAsset(b) {
    if (b.length < 24) return b;
    const c = b.slice();
    c.set([0x47, 0x41, 0x53, 0x54], 0);
    put(c, 4, rnd() < 0.5 ? 2 : 1, 4);
    put(c, 8, c.length - 24, 4);
    put(c, 12, 0, 4);
    put(c, 16, crc32(c.subarray(24)), 4);
    put(c, 20, crc32(c.subarray(0, 20)), 4);
    return c;
}

// ---- the JavaScript side's canonical lines (decode_dump.c's format) ----
const f32 = new Float32Array(1), u32 = new Uint32Array(f32.buffer);
const bitsOf = (x) => { f32[0] = x; return u32[0]; };
const fbits = (tag, a) => ` ${tag}${Array.from(a, bitsOf).join(',')}`;
const ubits = (tag, a) => ` ${tag}${Array.from(a).join(',')}`;
const hex = (tag, bytes) => ` ${tag}${Array.from(bytes, (x) => x.toString(16).padStart(2, '0')).join('')}`;
const utf8 = new TextEncoder();

function frameLine(f) {
    let s = `T${f.types} H${f.hdr.type},${f.hdr.tick},${BigInt(f.hdr.server_time_us)}`;
    if (f.state) {
        const st = f.state, sc = st.scene;
        s += ` S${st.seq} C${sc.n_trees},${sc.n_species}:${sc.n_modes.join(',')}`;
        for (const step of sc.step) s += fbits(':', step);
        s += ` T${sc.species.join(',')} M${st.n_modes.join(',')} Q`;
        const q = [];
        for (let t = 0; t < sc.n_trees; t++) for (let m = 0; m < st.n_modes[t]; m++) q.push(st.q[t * sc.stride + m]);
        s += q.join(',');
    }
    if (f.leaves) s += ` L${f.leaves.map((l) => `${l.instance},${l.slot},${l.spawn_tick},${l.seed}`).join(';')}`;
    if (f.wind) {
        const w = f.wind;
        s += `${fbits('W', [w.x0_m, w.y0_m, w.z_m, w.cell_m, w.scale_ms])},${w.nx},${w.ny}:${w.cells.join(',')}`;
    }
    if (f.weather) {
        const w = f.weather;
        s += fbits('X', [w.sustained_ms, w.gust_ms, w.dir_from_deg, w.pressure_hpa, w.central_hpa]);
        s += fbits('', [w.distance_km, w.bearing_deg, w.storm_min, w.replay_pos_s, w.replay_len_s, w.replay_speed]);
        s += ` ${w.ss_class},${w.beaufort},${w.flags},${w.storm_class},${w.utc_min},${w.utc_offset_min}`;
        s += hex('N', utf8.encode(w.name));
    }
    if (f.damage) s += ` D${f.damage.full ? 1 : 0}:${f.damage.events.map((e) => `${e.tree},${e.node},${e.kind},${e.value},${e.tick}`).join(';')}`;
    if (f.forest) {
        const fo = f.forest, ev = forestEvents(f);
        s += ` F${fo.first},${fo.count}:${hex('', fo.state)} :${fo.falls.map((x) => `${x.az},${x.tick}`).join(';')}`;
        s += ` G${ev.length}:${ev.map((e) => `${e.tree},${e.node},${e.kind},${e.value},${e.tick}`).join(';')}`;
    }
    return s;
}

function wireLines(frames) {
    const d = new Decoder(), out = [];
    for (const b of frames) {
        try {
            out.push(frameLine(d.decode(b)));
        } catch (e) {
            out.push(e instanceof WireError ? `${e.state ? 'E state' : 'E bad'} ${e.message}` : `THROWN ${e.constructor.name}: ${e.message}`);
        }
    }
    return out;
}

function assetLines(b) {
    const out = [`H${hash64(b)},${crc32(b).toString(16).padStart(8, '0')}`];
    let a;
    try {
        a = decodeAsset(b, 'fuzz');
    } catch (e) {
        out.push(e instanceof AssetError ? `E bad ${e.message}` : `THROWN ${e.constructor.name}: ${e.message}`);
        return out;
    }
    let s = hex('ok', utf8.encode(a.species)) + ` ${a.n_nodes}` + fbits('h', [a.height_m]) + ubits('p', a.parent);
    s += fbits('r', a.rest) + fbits('R', a.radius) + ` m${a.n_modes}`;
    if (a.n_modes && a.corr_v) s += fbits('v', a.corr_v) + fbits('w', a.corr_w) + fbits('a', a.corr_a) + fbits('b', a.corr_b);
    else if (a.n_modes) s += ' nocorr';
    s += fbits('P', a.mesh_pos) + fbits('n', a.mesh_normal) + ubits('B', a.mesh_bone) + fbits('g', a.mesh_weight);
    s += ubits('I', a.mesh_index) + ` l${a.n_lods}` + ubits(':', a.lod_first.slice(0, a.n_lods)) + ubits(':', a.lod_count.slice(0, a.n_lods));
    s += ubits('L', a.leaf_node) + fbits('o', a.leaf_offset) + fbits('N', a.leaf_normal) + fbits('s', a.leaf_size);
    s += fbits('k', a.bark_rgb) + fbits('K', a.leaf_rgb) + ` S${a.leaf_shape}`;
    out.push(s);
    return out;
}

// ---- state frames built from parts (every width 0..18, predictor, group length, tree
// set and mode list kind), so the value decoders' paths are reached, not only the seeds'
function header(type, tick) {
    const b = new Uint8Array(20);
    b.set([0x47, 0x41, 0x4c, 0x45, 1, 0, type, 0]);
    put(b, 8, tick, 4);
    put(b, 12, tick * 33333, 4);
    return b;
}
function varint(out, v) {
    do {
        out.push((v & 0x7f) | (v > 0x7f ? 0x80 : 0));
        v = Math.floor(v / 128);
    } while (v > 0);
}
function values(out, n_trees, counts, hist) {
    for (let t = 0; t < n_trees; t++) {
        for (let g0 = 0; g0 < counts[t]; g0 += 8) {
            const k = Math.min(8, counts[t] - g0);
            const width = rnd() < 0.6 ? ri(6) : ri(19), pred = ri(hist + 1);
            out.push((pred << 5) | width);
            let acc = 0, nacc = 0;
            for (let i = 0; i < k; i++) {
                const z = width ? ri(2 ** width) : 0;
                acc += z * 2 ** nacc;
                nacc += width;
                while (nacc >= 8) {
                    out.push(acc % 256);
                    acc = Math.floor(acc / 256);
                    nacc -= 8;
                }
            }
            if (nacc > 0) out.push(acc);
        }
    }
}
function treeSet(out, n_trees, full, key) {
    const counts = new Array(n_trees).fill(0);
    if (!key && rnd() < 0.3) {
        out.push(0);
        return null; // SAME: the previous counts
    }
    out.push(1);
    const runs = [];
    for (let pos = 0; pos < n_trees;) {
        const gap = runs.length ? 1 + ri(3) : ri(3), len = 1 + ri(6);
        if (pos + gap + len > n_trees) break;
        runs.push([gap, len]);
        for (let t = pos + gap; t < pos + gap + len; t++) counts[t] = full[t];
        pos += gap + len;
    }
    varint(out, runs.length);
    for (const [gap, len] of runs) { varint(out, gap); varint(out, len); }
    const list = rnd() < 0.5;
    out.push(list ? 1 : 0);
    if (list) for (let t = 0; t < n_trees; t++) if (counts[t]) { counts[t] = 1 + ri(full[t]); out.push(counts[t]); }
    return counts;
}
function stateSequence() {
    const n_trees = 1 + ri(40), n_species = 1 + ri(3);
    const nm = Array.from({ length: n_species }, () => 1 + ri(20));
    const species = Array.from({ length: n_trees }, () => ri(n_species));
    const full = species.map((s) => nm[s]);
    const kf = [...header(1, 100)];
    const seq = 1 + ri(1000);
    const b4 = new Uint8Array(4);
    const u32 = (v) => { put(b4, 0, v, 4); return [...b4]; };
    kf.push(...u32(seq), ...u32(n_trees), n_species);
    for (let sp = 0; sp < n_species; sp++) {
        kf.push(nm[sp]);
        for (let m = 0; m < nm[sp]; m++) kf.push(...new Uint8Array(Float32Array.of(10 ** (-4 + 3 * rnd())).buffer));
    }
    kf.push(...species);
    let counts = treeSet(kf, n_trees, full, true);
    values(kf, n_trees, counts, 0);
    const frames = [Uint8Array.from(kf)];
    for (let d = 1, n = ri(4); d <= n; d++) {
        const hist = d === 1 ? 1 : 1 + ri(2);
        const df = [...header(2, 100 + d), ...u32(seq + d), hist];
        counts = treeSet(df, n_trees, full, false) || counts;
        values(df, n_trees, counts, hist);
        frames.push(Uint8Array.from(df));
    }
    return frames;
}

// A FOREST from parts: up to 40 trees from a random first (now and then against
// WIRE_MAX_TREES), standing, snapped or uprooted, crowns whole or stripped, now and then a
// state byte no FOREST has.
function forestFrame() {
    const count = rnd() < 0.2 ? 0 : 1 + ri(40), tick = 100 + ri(1000);
    const first = rnd() < 0.1 ? 262144 - count - 1 + ri(3) : ri(1000);
    const b = [...header(8, tick), 0, 0, 0, 0, 0, 0, 0, 0];
    put(b, 20, first, 4);
    put(b, 24, count, 4);
    const st = [];
    for (let i = 0; i < count; i++) st.push((pick([0, 0, 0, 2, 3]) << 6) | (rnd() < 0.5 ? 32 : ri(33)));
    if (count && rnd() < 0.1) st[ri(count)] = rnd() < 0.5 ? 0x40 | ri(64) : ri(256);
    b.push(...st);
    for (const x of st) {
        if (!(x >> 6)) continue;
        const fall = [ri(256), 0, 0, 0, 0];
        put(fall, 1, (tick - ri(400)) >>> 0, 4);
        b.push(...fall);
    }
    return Uint8Array.from(b);
}
// The spec's FOREST vector and the refusals PROTOCOL.md names, alone and in a BUNDLE with
// the keyframe's whole damage state, as seeds (the first few cases, then mutated).
{
    const fv = vec.FOREST, at = (k, v) => { const c = fv.slice(); c[k] = v; return c; };
    const grown = new Uint8Array(fv.length + 1);
    grown.set(fv);
    const far = fv.slice();
    put(far, 20, 262142, 4);
    wireSeeds.push(at(0x1c, 0x54), at(0x1e, 0xe1), fv.subarray(0, 40), grown, far,
        bundleOf([keyframe, vec['DAMAGE-FULL'], fv]), bundleOf([vec['DAMAGE-FULL'], fv]));
}

// ---- cases ----
function wireCase(i) {
    if (i >= wireSeeds.length && rnd() < 0.1) {
        // a built FOREST, alone or in a KEYFRAME's BUNDLE after its DAMAGE, mutated now and then
        let fo = forestFrame();
        if (rnd() < 0.3) fo = mutate(fo, wireSeeds, wireFields);
        const prefix = rnd() < 0.5 ? [] : [keyframe];
        return { kind: 'W', frames: [...prefix, rnd() < 0.3 ? bundleOf([keyframe, vec['DAMAGE-FULL'], fo]) : fo] };
    }
    if (i >= wireSeeds.length && rnd() < 0.3) {
        // a built keyframe and deltas, one of them mutated now and then
        const frames = stateSequence();
        if (rnd() < 0.5) {
            const k = ri(frames.length);
            frames[k] = mutate(frames[k], wireSeeds, wireFields);
        }
        return { kind: 'W', frames };
    }
    const r = rnd();
    const prefix = r < 0.25 ? [] : r < 0.75 ? [keyframe] : [keyframe, deltaSame];
    if (i < wireSeeds.length) return { kind: 'W', frames: [...prefix, wireSeeds[i]] };
    const src = rnd() < 0.15 ? bundleOf(Array.from({ length: 1 + ri(3) }, () => pick(wireSeeds))) : pick(wireSeeds);
    const x = mutate(src, wireSeeds, wireFields);
    // half the time the magic, version, type and flags kept, so the body is reached
    if (rnd() < 0.5) x.set(src.subarray(0, Math.min(8, x.length)));
    return { kind: 'W', frames: [...prefix, x] };
}
function assetCase(i) {
    if (i < assetSeeds.length) return { kind: 'A', bytes: assetSeeds[i] };
    let b = mutate(pick(assetSeeds), assetSeeds, assetFields);
    if (rnd() < 0.7) b = repairAsset(b);
    return { kind: 'A', bytes: b };
}
function record(c) {
    const parts = [];
    const u32le = (v) => { const h = new Uint8Array(4); put(h, 0, v, 4); return h; };
    if (c.kind === 'W') {
        parts.push(Uint8Array.of(0x57), u32le(c.frames.length));
        for (const f of c.frames) parts.push(u32le(f.length), f);
    } else {
        parts.push(Uint8Array.of(0x41), u32le(c.bytes.length), c.bytes);
    }
    return parts;
}

// A sweep before the random cases: the 32-bit word at every byte of the first asset
// seed's payload (sections are not aligned) set to old ± 1 and 2, header and CRCs
// repaired: each count, flag, index and LOD range of a whole asset, one at a time.
const sweep = [];
for (let at = 24, a = assetSeeds[0]; at + 4 <= a.length; at++) {
    const old = a[at] | (a[at + 1] << 8) | (a[at + 2] << 16) | (a[at + 3] << 24);
    for (const v of [old + 1, old - 1, 2]) {
        const c = a.slice();
        put(c, at, v >>> 0, 4);
        sweep.push({ kind: 'A', bytes: repairAsset(c) });
    }
}
const t_end = seconds ? Date.now() + seconds * 1000 : Infinity;
const stats = { cases: 0, wire_frames: 0, wire_accepted: 0, wire_state_refusals: 0, forest_accepted: 0, assets: 0, assets_accepted: 0,
    assets_relaxed: 0, assets_nocorr: 0, batches: 0 };
let n = 0;
for (let batch = 0; n < cases && Date.now() < t_end; batch++) {
    const list = [];
    if (batch === 0) list.push(...sweep);
    for (let k = 0; k < 500 && n < cases; k++, n++) list.push(rnd() < 0.75 ? wireCase(n) : assetCase(n));
    const file = path.join(work, 'batch.bin');
    writeFileSync(file, Buffer.concat(list.flatMap(record)));
    const res = spawnSync(dump, [file], { maxBuffer: 1 << 30, encoding: 'utf8' });
    if (res.status !== 0) {
        console.error(`${dump} exited ${res.status} (${res.signal || ''}): ${res.stderr}`);
        writeFileSync(path.join(work, 'disagree-batch.bin'), readFileSync(file));
        process.exit(1);
    }
    // the species name as text (ASSET.md: bytes to the first NUL): C's bytes as the browser
    // shows them, invalid UTF-8 replaced
    const cl = res.stdout.split('\n').map((l) => l.replace(/^ ok([0-9a-f]*)/, (m, h) =>
        ` ok${Array.from(utf8.encode(new TextDecoder().decode(Uint8Array.from(h.match(/../g) || [], (x) => parseInt(x, 16)))), (x) => x.toString(16).padStart(2, '0')).join('')}`));
    let li = 0;
    for (const c of list) {
        const js = c.kind === 'W' ? wireLines(c.frames) : assetLines(c.bytes);
        const cs = cl.slice(li, li + js.length);
        li += js.length;
        let bad = null;
        for (let k = 0; k < js.length && !bad; k++) {
            const [a, b] = [cs[k], js[k]];
            if (a === b) continue;
            const verdict = (l) => (l || '').split(' ', 2).join(' ');
            if (a.startsWith('E ') && verdict(a) === verdict(b)) continue;
            if (c.kind === 'A' && k === 1 && a.startsWith('E bad') && b.startsWith(' ok') && relaxed(a)) {
                stats.assets_relaxed++;
                continue;
            }
            if (c.kind === 'A' && k === 1 && a.includes(' nocorr') && /has_correction/.test(b)) {
                stats.assets_nocorr++;
                continue;
            }
            bad = k;
        }
        if (bad !== null) {
            const out = path.join(work, `disagree-${c.kind}-${stats.cases}.bin`);
            writeFileSync(out, Buffer.concat(record(c)));
            const clip = (s) => (s && s.length > 400 ? `${s.slice(0, 400)}...` : s);
            console.error(`disagreement in case ${stats.cases} (${c.kind === 'W' ? `frame ${bad + 1} of ${c.frames.length}` : 'asset'}), input ${out}:\n  C:  ${clip(cs[bad])}\n  JS: ${clip(js[bad])}`);
            process.exit(1);
        }
        stats.cases++;
        if (c.kind === 'W') {
            stats.wire_frames += js.length;
            stats.wire_accepted += js.filter((l) => l.startsWith('T')).length;
            stats.wire_state_refusals += js.filter((l) => l.startsWith('E state')).length;
            stats.forest_accepted += js.filter((l) => l.startsWith('T') && / G\d+:/.test(l)).length;
        } else {
            stats.assets++;
            if (js[1].startsWith(' ok')) stats.assets_accepted++;
        }
    }
    stats.batches++;
}
console.log(JSON.stringify({ seed: seed0, ...stats, ok: true }));
