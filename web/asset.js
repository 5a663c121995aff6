// Species assets in the browser (protocol/ASSET.md): the content hash checked against the
// welcome's before anything is drawn, the CRCs, and the sections the renderer needs.
// Pure: no DOM.

// hash64 (ASSET.md "Content hash"): FNV-1a 64 then the splitmix64 finaliser. The byte
// loop runs on two 32-bit halves (a product by the prime 2^40 + 0x1b3 stays exact in a
// double); the finaliser, three steps, in BigInt.
export function hash64(bytes) {
    let lo = 0x84222325, hi = 0xcbf29ce4;
    for (let i = 0; i < bytes.length; i++) {
        lo ^= bytes[i];
        lo >>>= 0;
        const p = lo * 0x1b3;
        const plo = p % 4294967296;
        const carry = (p - plo) / 4294967296;
        hi = (hi * 0x1b3 + carry + ((lo << 8) >>> 0)) % 4294967296;
        lo = plo;
    }
    const M = (1n << 64n) - 1n;
    let h = (BigInt(hi) << 32n) | BigInt(lo);
    h = ((h ^ (h >> 30n)) * 0xbf58476d1ce4e5b9n) & M;
    h = ((h ^ (h >> 27n)) * 0x94d049bb133111ebn) & M;
    h ^= h >> 31n;
    return h.toString(16).padStart(16, '0');
}

let crcTable = null;
export function crc32(bytes) {
    if (!crcTable) {
        crcTable = new Uint32Array(256);
        for (let n = 0; n < 256; n++) {
            let c = n;
            for (let k = 0; k < 8; k++) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
            crcTable[n] = c >>> 0;
        }
    }
    let c = 0xffffffff;
    for (let i = 0; i < bytes.length; i++) c = crcTable[(c ^ bytes[i]) & 0xff] ^ (c >>> 8);
    return (c ^ 0xffffffff) >>> 0;
}

export class AssetError extends Error {}

// The fields of an asset file the browser draws with. name names the file in errors.
export function decodeAsset(bytes, name = 'asset') {
    const dv = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    const fail = (what, at, msg) => { throw new AssetError(`${name}: ${what} at byte ${at}: ${msg}`); };
    if (bytes.length < 24) fail('header', 0, `expected 24 bytes, got ${bytes.length}`);
    if (dv.getUint32(0, true) !== 0x54534147) fail('magic', 0, 'expected "GAST"');
    if (crc32(bytes.subarray(0, 20)) !== dv.getUint32(20, true)) fail('header_crc32', 20, 'mismatch');
    const version = dv.getUint32(4, true);
    if (version !== 1 && version !== 2) fail('version', 4, `expected 1 or 2, got ${version}`);
    const plen = dv.getUint32(8, true) + dv.getUint32(12, true) * 4294967296;
    if (plen !== bytes.length - 24) fail('payload_length', 8, plen < bytes.length - 24 ? 'trailing bytes' : 'truncated');
    if (crc32(bytes.subarray(24)) !== dv.getUint32(16, true)) fail('payload_crc32', 16, 'mismatch');
    let p = 24;
    const need = (n, what) => { if (p + n > bytes.length) fail(what, p, `truncated: expected ${n} bytes`); };
    const u32 = (what) => { need(4, what); const v = dv.getUint32(p, true); p += 4; return v; };
    // every float finite, as asset_decode reads them (a NaN would reach the GPU)
    const f32s = (n, what) => {
        need(4 * n, what);
        const a = new Float32Array(bytes.slice(p, p + 4 * n).buffer);
        for (let i = 0; i < n; i++) if (!Number.isFinite(a[i])) fail(what, p + 4 * i, 'not a finite number');
        p += 4 * n;
        return a;
    };
    const u32s = (n, what) => { need(4 * n, what); const a = new Uint32Array(bytes.slice(p, p + 4 * n).buffer); p += 4 * n; return a; };
    const i32s = (n, what) => { need(4 * n, what); const a = new Int32Array(bytes.slice(p, p + 4 * n).buffer); p += 4 * n; return a; };
    const section = (tag) => {
        need(12, `${tag} header`);
        const t = String.fromCharCode(bytes[p], bytes[p + 1], bytes[p + 2], bytes[p + 3]);
        if (t !== tag) fail('section', p, `expected ${tag}, got ${t}`);
        const len = dv.getUint32(p + 4, true) + dv.getUint32(p + 8, true) * 4294967296;
        p += 12;
        need(len, tag);
        return p + len;
    };
    // a section's content must end where its length says (ASSET.md "Sections")
    const close = (tag, end) => { if (p !== end) fail(tag, p, `section length disagrees with its content (ends at ${end})`); };
    const a = { name };
    let end = section('META');
    a.species = new TextDecoder().decode(bytes.subarray(p, p + 64)).replace(/\0.*$/s, '');
    p = end;
    end = section('SKEL');
    a.n_nodes = u32('n_nodes');
    if (a.n_nodes < 1 || a.n_nodes > 262144) fail('n_nodes', p - 4, `count ${a.n_nodes} outside 1..262144`);
    a.height_m = f32s(1, 'height_m')[0];
    a.parent = i32s(a.n_nodes, 'parent');
    a.rest = f32s(3 * a.n_nodes, 'rest');
    a.radius = f32s(a.n_nodes, 'radius');
    close('SKEL', end);
    for (let i = 0; i < a.n_nodes; i++) {
        if (i === 0 ? a.parent[i] !== -1 : a.parent[i] < 0 || a.parent[i] >= i) fail('parent', 0, `node ${i}: parent ${a.parent[i]}`);
    }
    end = section('MODE');
    a.n_modes = u32('n_modes');
    const nmn = a.n_modes * a.n_nodes;
    if (a.n_modes > 256 || nmn > (1 << 23)) fail('n_modes', p - 4, `count ${a.n_modes} over the limit`);
    // omega, gamma and the wind basis are the server's; the pose uses CORR, a far tree's
    // impostor phi (its crown's sway, web/imp_sway.js); phi_rot is the server's
    p += 4 * 5 * a.n_modes;
    a.phi = f32s(3 * nmn, 'phi');
    p = end;
    end = section('CORR');
    const has = u32('has_correction');
    if (has > 1) fail('has_correction', p - 4, `expected 0 or 1, got ${has}`);
    if (has) {
        a.corr_v = f32s(3 * nmn, 'corr_v');
        a.corr_w = f32s(3 * nmn, 'corr_w');
        a.corr_a = f32s(a.n_modes, 'corr_a');
        a.corr_b = f32s(a.n_modes, 'corr_b');
    } else if (a.n_modes) {
        fail('has_correction', p - 4, 'expected 1 for a species with modes (the length-true pose)');
    }
    close('CORR', end);
    end = section('MESH');
    a.n_verts = u32('n_verts');
    if (a.n_verts > 4194304) fail('n_verts', p - 4, 'over the limit');
    a.mesh_pos = f32s(3 * a.n_verts, 'mesh_pos');
    a.mesh_normal = f32s(3 * a.n_verts, 'mesh_normal');
    a.mesh_bone = u32s(2 * a.n_verts, 'mesh_bone');
    a.mesh_weight = f32s(a.n_verts, 'mesh_weight');
    a.n_indices = u32('n_indices');
    if (a.n_indices > 16777216) fail('n_indices', p - 4, 'over the limit');
    a.mesh_index = u32s(a.n_indices, 'mesh_index');
    a.n_lods = u32('n_lods');
    if (a.n_lods > 4 || (a.n_lods === 0 && a.n_indices > 0)) fail('n_lods', p - 4, `expected 1..4, got ${a.n_lods}`);
    const lod = u32s(8, 'lods');
    a.lod_first = [lod[0], lod[2], lod[4], lod[6]];
    a.lod_count = [lod[1], lod[3], lod[5], lod[7]];
    // each LOD whole triangles within the indices (the browser draws these ranges)
    for (let l = 0; l < 4; l++) {
        const first = a.lod_first[l], count = a.lod_count[l];
        if (first + count > a.n_indices || count % 3 !== 0 || (l >= a.n_lods && (first || count))) {
            fail('lod_first', p - 32 + 8 * l, `LOD ${l}: [${first}, +${count}) not whole triangles within ${a.n_indices} indices (or set past n_lods)`);
        }
    }
    for (let v = 0; v < 2 * a.n_verts; v++) if (a.mesh_bone[v] >= a.n_nodes) fail('mesh_bone', 0, `${v}: ${a.mesh_bone[v]} >= n_nodes`);
    for (let k = 0; k < a.n_indices; k++) if (a.mesh_index[k] >= a.n_verts) fail('mesh_index', 0, `${k}: ${a.mesh_index[k]} >= n_verts`);
    close('MESH', end);
    end = section('LEAF');
    a.n_leaves = u32('n_leaves');
    if (a.n_leaves > 1048576) fail('n_leaves', p - 4, 'over the limit');
    a.leaf_node = u32s(a.n_leaves, 'leaf_node');
    a.leaf_offset = f32s(3 * a.n_leaves, 'leaf_offset');
    a.leaf_normal = f32s(3 * a.n_leaves, 'leaf_normal');
    a.leaf_size = f32s(a.n_leaves, 'leaf_size');
    for (let l = 0; l < a.n_leaves; l++) if (a.leaf_node[l] >= a.n_nodes) fail('leaf_node', 0, `${l}: ${a.leaf_node[l]} >= n_nodes`);
    close('LEAF', end);
    end = section('LOOK');
    a.bark_rgb = f32s(3, 'bark_rgb');
    a.leaf_rgb = f32s(3, 'leaf_rgb');
    a.leaf_shape = u32('leaf_shape');
    if (a.leaf_shape > 2) fail('leaf_shape', p - 4, `expected 0..2, got ${a.leaf_shape}`);
    close('LOOK', end);
    // version 1 ends here; version 2 may add optional sections, SRID and SRES at most once
    // each (their content is the server's), any other tag skipped by its length
    if (version === 1 && p !== bytes.length) fail('end', p, `${bytes.length - p} bytes after the last section (version 1 has no optional sections)`);
    const seen = new Set();
    while (p < bytes.length) {
        const at = p;
        need(12, 'section tag');
        const t = String.fromCharCode(bytes[p], bytes[p + 1], bytes[p + 2], bytes[p + 3]);
        const len = dv.getUint32(p + 4, true) + dv.getUint32(p + 8, true) * 4294967296;
        p += 12;
        if (len > bytes.length - p) fail('section length', at + 4, `section length ${len}, only ${bytes.length - p} bytes left`);
        if ((t === 'SRID' || t === 'SRES') && seen.has(t)) fail(t, at, `second ${t} section (at most one)`);
        seen.add(t);
        p += len;
    }
    return a;
}

// The asset at url, refused unless its bytes hash to `hash` (PROTOCOL.md "Handshake"):
// the error names both hashes, as gale-client's does.
export async function fetchAsset(url, hash, name) {
    const res = await fetch(url, { cache: 'no-store' });
    if (!res.ok) throw new AssetError(`${name}: ${url}: HTTP ${res.status}`);
    const bytes = new Uint8Array(await res.arrayBuffer());
    const got = hash64(bytes);
    if (got !== hash) {
        const e = new AssetError(`${name}: asset hash mismatch: the server announced ${hash}, the bytes at ${url} hash to ${got}`);
        e.hashMismatch = true;
        throw e;
    }
    return { asset: decodeAsset(bytes, name), bytes: bytes.length };
}
