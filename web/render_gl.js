// The trees in WebGL2 as gale-client draws them (client/render*.c): the skeleton of every
// drawn tree rebuilt on the GPU from q in the length-true form (shaders/skel.frag, two
// passes into float textures; q blended there from the snapshots' quantised values, each
// uploaded once into a texture ring, where gale-client blends on the CPU), the bark tubes
// skinned on it (tree.vert/.frag), the leaves
// on their nodes (leaf.vert/.frag), sky and ground (sky.frag), and in a storm the sky,
// light, fog and wet crowns of web/storm_fx.js, the welcome's houses (web/house.js,
// house.vert/.frag) with rain streaks over the frame
// (rain.vert/.frag, client/render_rain.c), storm damage (trees tipped over or lying, their
// stumps and root plates, crowns stripped, branches gone: web/damage.js gives the trees'
// codes and cut lists, client/render_damage.c draws the same) and falling leaves on the
// shared path (web/falling_path.js, fall.vert/.frag, client/render_fall.c). The shaders are the files
// of shaders/ (web/shaders.js). Data the native client keeps in buffer textures lives here
// in 2D textures read by buf_fetch (common.glsl), row-major, DATA_W texels a row.
import { loadProgram } from './shaders.js';
import { blendWeights } from './jitter.js';
import { stormFxCalm, rainUniforms } from './storm_fx.js';
import { housesMesh, HOUSE_FLOATS } from './house.js';
import { hashMix32, MAX_DEBRIS } from './damage.js';
import { fallingPathBuild, fallingVar, fallingPathLandTime } from './falling_path.js';

export class WebGL2Missing extends Error {}

const DATA_W = 2048;
// texture units: the native client's (client/render_internal.h)
const RU = { SKEL: 0, NODE: 1, LIST: 2, TREES: 3, VW: 4, Q: 5, LEAF: 6, WIND: 7, PATH: 8, CUT: 10, CUTN: 11, PLATE: 12, STUMP: 13, SCRATCH: 15 }; // SCRATCH: uploads
const SAMPLERS = { u_skel: RU.SKEL, u_node: RU.NODE, u_list: RU.LIST, u_trees: RU.TREES, u_vw: RU.VW,
    u_q: RU.Q, u_qring: RU.Q, u_leaf: RU.LEAF, u_wind: RU.WIND, u_path: RU.PATH, u_cut: RU.CUT, u_cutn: RU.CUTN, u_plates: RU.PLATE, u_stumps: RU.STUMP };
const MAX_FALLING = 16384; // render_desc max_falling's default (client/render.c)
const FALL_FLOATS = 21;    // rs_fall: start, var, drift, q0, look (4 each), shape
const PLATE_SEG = 24, STUMP_SEG = 12; // shaders/plate.vert, stump.vert
const LEAF_ASPECT = [0.55, 0.16, 1.0]; // render_leaf_aspect, client/render_species.c
const FOG_DIST_M = 450; // the native renderer's default fog distance (client/render.c)

// ---- small column-major matrix helpers (the layout of cglm and GLSL) ----
export function perspective(fovy_rad, aspect, near, far) {
    const f = 1 / Math.tan(fovy_rad / 2), nf = 1 / (near - far);
    return new Float32Array([f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, (far + near) * nf, -1, 0, 0, 2 * far * near * nf, 0]);
}
export function lookAt(eye, target, up) {
    const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    const norm = (a) => { const l = Math.hypot(...a); return a.map((x) => x / l); };
    const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
    const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    const f = norm(sub(target, eye)), s = norm(cross(f, up)), u = cross(s, f);
    return new Float32Array([s[0], u[0], -f[0], 0, s[1], u[1], -f[1], 0, s[2], u[2], -f[2], 0,
        -dot(s, eye), -dot(u, eye), dot(f, eye), 1]);
}
export function mul(a, b) {
    const o = new Float32Array(16);
    for (let c = 0; c < 4; c++) for (let r = 0; r < 4; r++) {
        let s = 0;
        for (let k = 0; k < 4; k++) s += a[k * 4 + r] * b[c * 4 + k];
        o[c * 4 + r] = s;
    }
    return o;
}
export function invert(m) {
    const inv = new Float64Array(16);
    inv[0] = m[5] * m[10] * m[15] - m[5] * m[11] * m[14] - m[9] * m[6] * m[15] + m[9] * m[7] * m[14] + m[13] * m[6] * m[11] - m[13] * m[7] * m[10];
    inv[4] = -m[4] * m[10] * m[15] + m[4] * m[11] * m[14] + m[8] * m[6] * m[15] - m[8] * m[7] * m[14] - m[12] * m[6] * m[11] + m[12] * m[7] * m[10];
    inv[8] = m[4] * m[9] * m[15] - m[4] * m[11] * m[13] - m[8] * m[5] * m[15] + m[8] * m[7] * m[13] + m[12] * m[5] * m[11] - m[12] * m[7] * m[9];
    inv[12] = -m[4] * m[9] * m[14] + m[4] * m[10] * m[13] + m[8] * m[5] * m[14] - m[8] * m[6] * m[13] - m[12] * m[5] * m[10] + m[12] * m[6] * m[9];
    inv[1] = -m[1] * m[10] * m[15] + m[1] * m[11] * m[14] + m[9] * m[2] * m[15] - m[9] * m[3] * m[14] - m[13] * m[2] * m[11] + m[13] * m[3] * m[10];
    inv[5] = m[0] * m[10] * m[15] - m[0] * m[11] * m[14] - m[8] * m[2] * m[15] + m[8] * m[3] * m[14] + m[12] * m[2] * m[11] - m[12] * m[3] * m[10];
    inv[9] = -m[0] * m[9] * m[15] + m[0] * m[11] * m[13] + m[8] * m[1] * m[15] - m[8] * m[3] * m[13] - m[12] * m[1] * m[11] + m[12] * m[3] * m[9];
    inv[13] = m[0] * m[9] * m[14] - m[0] * m[10] * m[13] - m[8] * m[1] * m[14] + m[8] * m[2] * m[13] + m[12] * m[1] * m[10] - m[12] * m[2] * m[9];
    inv[2] = m[1] * m[6] * m[15] - m[1] * m[7] * m[14] - m[5] * m[2] * m[15] + m[5] * m[3] * m[14] + m[13] * m[2] * m[7] - m[13] * m[3] * m[6];
    inv[6] = -m[0] * m[6] * m[15] + m[0] * m[7] * m[14] + m[4] * m[2] * m[15] - m[4] * m[3] * m[14] - m[12] * m[2] * m[7] + m[12] * m[3] * m[6];
    inv[10] = m[0] * m[5] * m[15] - m[0] * m[7] * m[13] - m[4] * m[1] * m[15] + m[4] * m[3] * m[13] + m[12] * m[1] * m[7] - m[12] * m[3] * m[5];
    inv[14] = -m[0] * m[5] * m[14] + m[0] * m[6] * m[13] + m[4] * m[1] * m[14] - m[4] * m[2] * m[13] - m[12] * m[1] * m[6] + m[12] * m[2] * m[5];
    inv[3] = -m[1] * m[6] * m[11] + m[1] * m[7] * m[10] + m[5] * m[2] * m[11] - m[5] * m[3] * m[10] - m[9] * m[2] * m[7] + m[9] * m[3] * m[6];
    inv[7] = m[0] * m[6] * m[11] - m[0] * m[7] * m[10] - m[4] * m[2] * m[11] + m[4] * m[3] * m[10] + m[8] * m[2] * m[7] - m[8] * m[3] * m[6];
    inv[11] = -m[0] * m[5] * m[11] + m[0] * m[7] * m[9] + m[4] * m[1] * m[11] - m[4] * m[3] * m[9] - m[8] * m[1] * m[7] + m[8] * m[3] * m[5];
    inv[15] = m[0] * m[5] * m[10] - m[0] * m[6] * m[9] - m[4] * m[1] * m[10] + m[4] * m[2] * m[9] + m[8] * m[1] * m[6] - m[8] * m[2] * m[5];
    const det = m[0] * inv[0] + m[1] * inv[4] + m[2] * inv[8] + m[3] * inv[12];
    return Float32Array.from(inv, (x) => x / det);
}

// quaternion (x, y, z, w) of an orthonormal basis given as columns (client/render_fall.c)
function quatFromBasis(x, y, z) {
    const tr = x[0] + y[1] + z[2];
    if (tr > 0) {
        const s = Math.sqrt(tr + 1) * 2;
        return [(y[2] - z[1]) / s, (z[0] - x[2]) / s, (x[1] - y[0]) / s, 0.25 * s];
    }
    if (x[0] > y[1] && x[0] > z[2]) {
        const s = Math.sqrt(1 + x[0] - y[1] - z[2]) * 2;
        return [0.25 * s, (y[0] + x[1]) / s, (z[0] + x[2]) / s, (y[2] - z[1]) / s];
    }
    if (y[1] > z[2]) {
        const s = Math.sqrt(1 + y[1] - x[0] - z[2]) * 2;
        return [(y[0] + x[1]) / s, 0.25 * s, (z[1] + y[2]) / s, (z[0] - x[2]) / s];
    }
    const s = Math.sqrt(1 + z[2] - x[0] - y[1]) * 2;
    return [(z[0] + x[2]) / s, (z[1] + y[2]) / s, 0.25 * s, (x[1] - y[0]) / s];
}

// The orbit camera of client/camera.c: yaw from +x, pitch up, looking at target.
export function orbitEye(target, distance, yaw, pitch) {
    const cp = Math.cos(pitch);
    const f = [cp * Math.cos(yaw), cp * Math.sin(yaw), Math.sin(pitch)];
    return target.map((t, k) => t - f[k] * distance);
}

export class Renderer {
    constructor(canvas) {
        const gl = canvas.getContext('webgl2', { antialias: false, preserveDrawingBuffer: true });
        if (!gl) throw new WebGL2Missing('This browser has no WebGL2: gale draws its trees with WebGL2. Use a current Chrome, Firefox, Edge or Safari with hardware acceleration on.');
        if (!gl.getExtension('EXT_color_buffer_float')) {
            throw new WebGL2Missing('This browser\'s WebGL2 cannot render to float textures (EXT_color_buffer_float), which gale needs to pose the trees.');
        }
        this.gl = gl;
        this.canvas = canvas;
        this.species = [];
        this.n_trees = 0;
        this.skel_w = 0;
        this.skel_h = 0;
        this.max_rows = 4096;
        this.stats = { frames: 0, trees_drawn: 0, upload_ms: 0 };
        this.fx = stormFxCalm(); // web/storm_fx.js; the page sets it from WEATHER
        this.subject_m = 0;
    }

    async init(base = '') {
        const gl = this.gl;
        const names = ['skel', 'tree', 'leaf', 'sky', 'rain', 'house', 'plate', 'stump', 'fall'];
        this.base = base;
        // the skeleton pass blends the snapshots itself (setMix)
        const progs = await Promise.all(names.map((n) => loadProgram(gl, n, base, n === 'skel' ? '#define GALE_Q_RING 1\n' : '')));
        this.p = Object.fromEntries(names.map((n, i) => [n, progs[i]]));
        for (const p of progs) this.bindSamplers(p);
        this.vaoEmpty = gl.createVertexArray();
        this.wind = gl.createTexture();
        gl.bindTexture(gl.TEXTURE_3D, this.wind);
        gl.texImage3D(gl.TEXTURE_3D, 0, gl.RGBA8, 1, 1, 1, 0, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
        this.list = this.dataTex(4, 1);
        this.cutn = this.dataTex(1, 1);
        this.plateBuf = this.dataTex(1, 1);
        this.stumpBuf = this.dataTex(4, 2);
        this.fallInit();
    }

    bindSamplers(p) {
        const gl = this.gl;
        gl.useProgram(p.id);
        for (const [name, unit] of Object.entries(SAMPLERS)) if (p.u[name]) gl.uniform1i(p.u[name], unit);
    }

    // The skeleton pass from q uploaded as floats (uploadQ), the native client's way, in
    // place of the blend of snapshots: for tests that hold the one to the other.
    async useFloatQ(on) {
        if (on && !this.p.skelF) {
            this.p.skelF = await loadProgram(this.gl, 'skel', this.base);
            this.bindSamplers(this.p.skelF);
        }
        this.floatQ = on;
    }

    // The shared falling-leaf path as a 2-row texture (positions, orientations) and the
    // ring of released leaves in an instanced vertex buffer (client/render_fall.c).
    fallInit() {
        const gl = this.gl, p = this.path = fallingPathBuild();
        const px = new Float32Array(8 * p.n);
        for (let i = 0; i < p.n; i++) {
            px.set(p.pos.subarray(3 * i, 3 * i + 3), 4 * i);
            px.set(p.quat.subarray(4 * i, 4 * i + 4), 4 * (p.n + i));
        }
        this.pathTex = gl.createTexture();
        gl.activeTexture(gl.TEXTURE0 + RU.SCRATCH);
        gl.bindTexture(gl.TEXTURE_2D, this.pathTex);
        gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, p.n, 2, 0, gl.RGBA, gl.FLOAT, px);
        for (const k of [gl.TEXTURE_MIN_FILTER, gl.TEXTURE_MAG_FILTER]) gl.texParameteri(gl.TEXTURE_2D, k, gl.NEAREST);
        this.ring = new Float32Array(MAX_FALLING * FALL_FLOATS);
        this.ringU32 = new Uint32Array(this.ring.buffer);
        this.ringHead = 0;
        this.ringCount = 0;
        this.dirtyLo = Infinity;
        this.dirtyHi = 0;
        this.fallVao = gl.createVertexArray();
        gl.bindVertexArray(this.fallVao);
        this.fallVbo = gl.createBuffer();
        gl.bindBuffer(gl.ARRAY_BUFFER, this.fallVbo);
        gl.bufferData(gl.ARRAY_BUFFER, this.ring.byteLength, gl.DYNAMIC_DRAW);
        for (let a = 0; a < 6; a++) {
            gl.enableVertexAttribArray(a);
            gl.vertexAttribPointer(a, a < 5 ? 4 : 1, gl.FLOAT, false, FALL_FLOATS * 4, a * 16);
            gl.vertexAttribDivisor(a, 1);
        }
        gl.bindVertexArray(null);
    }

    // A data texture of n texels of `channels` floats (1 or 4), uploaded from data.
    dataTex(channels, n, data = null, old = null) {
        const gl = this.gl;
        const w = Math.min(DATA_W, Math.max(n, 1)), h = Math.max(1, Math.ceil(n / w));
        const t = old && old.w === w && old.h >= h && old.channels === channels ? old : { tex: gl.createTexture(), w, h, channels, fresh: true };
        if (old && t !== old) gl.deleteTexture(old.tex);
        gl.activeTexture(gl.TEXTURE0 + RU.SCRATCH); // the units a draw binds stay as they are
        gl.bindTexture(gl.TEXTURE_2D, t.tex);
        const fmt = channels === 1 ? gl.RED : gl.RGBA, ifmt = channels === 1 ? gl.R32F : gl.RGBA32F;
        if (t.fresh) {
            gl.texImage2D(gl.TEXTURE_2D, 0, ifmt, w, t.h, 0, fmt, gl.FLOAT, null);
            for (const k of [gl.TEXTURE_MIN_FILTER, gl.TEXTURE_MAG_FILTER]) gl.texParameteri(gl.TEXTURE_2D, k, gl.NEAREST);
            t.fresh = false;
        }
        if (data) {
            const rows = Math.ceil(data.length / channels / w);
            let src = data;
            if (src.length < rows * w * channels) {
                src = new Float32Array(rows * w * channels);
                src.set(data);
            }
            gl.texSubImage2D(gl.TEXTURE_2D, 0, 0, 0, w, rows, fmt, gl.FLOAT, src.subarray(0, rows * w * channels));
        }
        return t;
    }

    // Texels [a, b) of data (laid out as texture t, whole rows) into t: the rows they span.
    subUpload(t, data, a, b) {
        const gl = this.gl, r0 = Math.floor(a / t.w), r1 = Math.ceil(b / t.w);
        gl.activeTexture(gl.TEXTURE0 + RU.SCRATCH);
        gl.bindTexture(gl.TEXTURE_2D, t.tex);
        gl.texSubImage2D(gl.TEXTURE_2D, 0, 0, r0, t.w, r1 - r0, t.channels === 1 ? gl.RED : gl.RGBA, gl.FLOAT, data, r0 * t.w * t.channels);
    }

    bindTex(unit, target, tex) {
        const gl = this.gl;
        gl.activeTexture(gl.TEXTURE0 + unit);
        gl.bindTexture(target, tex);
    }

    // One species (web/asset.js decodeAsset), at index i of the welcome's list.
    addSpecies(i, a) {
        const gl = this.gl, nn = a.n_nodes, nm = a.n_modes;
        if (nn < 2 || nn > 16384) throw new Error(`${a.name}: n_nodes ${nn} (2..16384)`);
        if (nm > 64) throw new Error(`${a.name}: n_modes ${nm} (0..64)`);
        const s = { n_nodes: nn, n_modes: nm, n_leaves: a.n_leaves, n_lods: a.n_lods, lod_first: a.lod_first,
            lod_count: a.lod_count, bark: a.bark_rgb, leaf_rgb: a.leaf_rgb, leaf_shape: a.leaf_shape };
        let h = 0, cr = 0;
        for (let k = 0; k < nn; k++) {
            h = Math.max(h, a.rest[3 * k + 2]);
            cr = Math.max(cr, Math.hypot(a.rest[3 * k], a.rest[3 * k + 1]) + a.radius[k]);
        }
        for (let l = 0; l < a.n_leaves; l++) {
            const j = a.leaf_node[l];
            const x = a.rest[3 * j] + a.leaf_offset[3 * l], y = a.rest[3 * j + 1] + a.leaf_offset[3 * l + 1];
            h = Math.max(h, a.rest[3 * j + 2] + a.leaf_offset[3 * l + 2] + a.leaf_size[l]);
            cr = Math.max(cr, Math.hypot(x, y) + a.leaf_size[l]);
        }
        s.height = h;
        s.crown_r = cr;
        // the stem at the base, for a snapped tree's stump: the root's radius, tapering as
        // towards its thickest child (client/render_species.c)
        s.stem_r_m = a.radius[0];
        s.stem_taper = 0;
        for (let k = 1, best = 0; k < nn; k++) {
            const dz = Math.fround(a.rest[3 * k + 2] - a.rest[2]);
            if (a.parent[k] === 0 && dz > 0.05 && (best === 0 || a.radius[k] > a.radius[best])) {
                best = k;
                s.stem_taper = Math.min(Math.fround(Math.fround(a.radius[k] - a.radius[0]) / dz), 0);
            }
        }
        s.a = a; // rest pose, pose fields and leaf slots for releasing a leaf (addFallingLeaf)
        // the leaves' centroid at rest [m, tree frame]: where the crown stands
        const c = [0, 0, 0];
        for (let l = 0; l < a.n_leaves; l++) {
            for (let k = 0; k < 3; k++) c[k] += (a.rest[3 * a.leaf_node[l] + k] + a.leaf_offset[3 * l + k]) / a.n_leaves;
        }
        s.crown_c = a.n_leaves ? c : [0, 0, 0.62 * h];
        s.ab = new Float32Array(128);
        s.qw = new Float32Array(256); // setMix: per mode, the weights of the blended snapshots
        for (let m = 0; m < nm; m++) {
            s.ab[2 * m] = a.corr_a[m];
            s.ab[2 * m + 1] = a.corr_b[m];
        }
        const vw = new Float32Array(nm * nn * 8);
        for (let m = 0; m < nm; m++) for (let k = 0; k < nn; k++) {
            const o = (m * nn + k) * 8, src = (m * nn + k) * 3;
            vw.set(a.corr_v.subarray(src, src + 3), o);
            vw.set(a.corr_w.subarray(src, src + 3), o + 4);
        }
        s.vw = this.dataTex(4, nm * nn * 2, vw);
        const node = new Float32Array(nn * 4);
        for (let k = 0; k < nn; k++) {
            node.set(a.rest.subarray(3 * k, 3 * k + 3), 4 * k);
            node[4 * k + 3] = a.parent[k];
        }
        s.node = this.dataTex(4, nn, node);
        const leaf = new Float32Array(Math.max(1, a.n_leaves) * 8);
        for (let l = 0; l < a.n_leaves; l++) {
            leaf.set(a.leaf_offset.subarray(3 * l, 3 * l + 3), 8 * l);
            leaf[8 * l + 3] = a.leaf_node[l];
            leaf.set(a.leaf_normal.subarray(3 * l, 3 * l + 3), 8 * l + 4);
            leaf[8 * l + 7] = a.leaf_size[l];
        }
        s.leaf = this.dataTex(4, Math.max(1, a.n_leaves) * 2, leaf);
        s.vao = gl.createVertexArray();
        gl.bindVertexArray(s.vao);
        const nv = a.n_verts;
        const vbo = gl.createBuffer();
        gl.bindBuffer(gl.ARRAY_BUFFER, vbo);
        gl.bufferData(gl.ARRAY_BUFFER, nv * 36 || 16, gl.STATIC_DRAW);
        gl.bufferSubData(gl.ARRAY_BUFFER, 0, a.mesh_pos);
        gl.bufferSubData(gl.ARRAY_BUFFER, nv * 12, a.mesh_normal);
        gl.bufferSubData(gl.ARRAY_BUFFER, nv * 24, a.mesh_bone);
        gl.bufferSubData(gl.ARRAY_BUFFER, nv * 32, a.mesh_weight);
        gl.enableVertexAttribArray(0);
        gl.vertexAttribPointer(0, 3, gl.FLOAT, false, 0, 0);
        gl.enableVertexAttribArray(1);
        gl.vertexAttribPointer(1, 3, gl.FLOAT, false, 0, nv * 12);
        gl.enableVertexAttribArray(2);
        // tree.vert reads ivec2: WebGL wants the signed type (bones < 16384: the same bits)
        gl.vertexAttribIPointer(2, 2, gl.INT, 0, nv * 24);
        gl.enableVertexAttribArray(3);
        gl.vertexAttribPointer(3, 1, gl.FLOAT, false, 0, nv * 32);
        const ibo = gl.createBuffer();
        gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, ibo);
        gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, a.mesh_index, gl.STATIC_DRAW);
        gl.bindVertexArray(null);
        this.species[i] = s;
    }

    // The welcome's obstacles, rows [min x, y, z, max x, y, z] (PROTOCOL.md checks them on
    // the server's side; a row that is not 6 finite numbers with min <= max is an error).
    setObstacles(rows) {
        const gl = this.gl;
        rows.forEach((b, i) => {
            if (!Array.isArray(b) || b.length !== 6 || !b.every(Number.isFinite) || b[0] > b[3] || b[1] > b[4] || b[2] > b[5]) {
                throw new Error(`welcome.obstacles[${i}]: expected [min x, y, z, max x, y, z] with min <= max, got ${JSON.stringify(b)}`);
            }
        });
        const v = housesMesh(rows);
        this.houseVerts = v.length / HOUSE_FLOATS;
        if (!this.houseVao) {
            this.houseVao = gl.createVertexArray();
            this.houseVbo = gl.createBuffer();
            gl.bindVertexArray(this.houseVao);
            gl.bindBuffer(gl.ARRAY_BUFFER, this.houseVbo);
            const stride = HOUSE_FLOATS * 4;
            [[3, 0], [3, 3], [4, 6], [1, 10]].forEach(([size, off], a) => {
                gl.enableVertexAttribArray(a);
                gl.vertexAttribPointer(a, size, gl.FLOAT, false, stride, off * 4);
            });
            gl.bindVertexArray(null);
        }
        gl.bindBuffer(gl.ARRAY_BUFFER, this.houseVbo);
        gl.bufferData(gl.ARRAY_BUFFER, v.length ? v : new Float32Array(HOUSE_FLOATS), gl.STATIC_DRAW);
    }

    // The welcome's instances: rows [species, x, y, z, yaw, scale]; after them MAX_DEBRIS
    // slots for broken-off pieces (setDebris).
    setInstances(rows, stride) {
        this.n_trees = rows.length;
        this.inst = rows;
        this.debris = [];
        // whole rows of the texture, so that a range of slots uploads without a copy
        const texels = (rows.length + MAX_DEBRIS) * 2, tw = Math.min(DATA_W, texels);
        const t = new Float32Array(Math.ceil(texels / tw) * tw * 4);
        rows.forEach((r, i) => {
            t.set([r[1], r[2], r[3], r[4], r[5] > 0 ? r[5] : 1, r[0], 0, 0], 8 * i);
        });
        this.treeData = t;
        this.trees = this.dataTex(4, (rows.length + MAX_DEBRIS) * 2, t, this.trees);
        this.uprooted = new Uint8Array(rows.length);
        this.setCuts(new Float32Array(rows.length * 4), new Float32Array(1));
        this.setStride(stride);
        this.clearFalling();
    }

    // Storm damage of every tree (web/damage.js DamageFx.update): u_trees slot 1 .z
    // (render_tree_code: fall angle + 4 x leaf levels lost + 256 when snapped) and .w (fall
    // azimuth), and which trees lie on their root plate.
    setDamage(code, az, uprooted) {
        const t = this.treeData;
        for (let i = 0; i < this.n_trees; i++) {
            t[8 * i + 6] = code[i];
            t[8 * i + 7] = az[i];
        }
        this.uprooted.set(uprooted.subarray(0, this.n_trees));
        this.trees = this.dataTex(4, (this.n_trees + MAX_DEBRIS) * 2, t, this.trees);
    }

    // The broken branches' cut lists (render_damage_upload): per tree (first, count,
    // keep-only, 0) and the cut nodes; the debris slots' lists follow.
    setCuts(head, nodes) {
        this.cutTrees = { head, nodes };
        this.uploadCuts();
    }

    uploadCuts() {
        const n = this.n_trees, { head, nodes } = this.cutTrees, nd = this.debris.length;
        const h = new Float32Array((n + MAX_DEBRIS) * 4), nn = new Float32Array(nodes.length + nd);
        h.set(head.subarray(0, 4 * n));
        nn.set(nodes);
        this.debris.forEach((d, k) => {
            // keep only the sub-tree of the node that broke
            h.set([nodes.length + k, 1, 1, 0], 4 * (n + k));
            nn[nodes.length + k] = d.node;
        });
        this.cut = this.dataTex(4, n + MAX_DEBRIS, h, this.cut);
        this.cutn = this.dataTex(1, nn.length, nn, this.cutn);
    }

    // The pieces broken off and tumbling or lying (render_set_debris; web/damage.js
    // DamageFx.debrisAt): slot n_trees + k drawn at rest from its tree's species and scale,
    // its own place and turn, only the sub-tree of its node.
    setDebris(list) {
        const n = this.n_trees, t = this.treeData;
        const same = list.length === this.debris.length && list.every((d, k) => d.tree === this.debris[k].tree && d.node === this.debris[k].node);
        if (!list.length && !this.debris.length) return;
        list.forEach((d, k) => {
            const src = 8 * d.tree, z = t[src + 6];
            const lost = Math.floor((z - 256 * (z >= 256)) * 0.25);
            t.set([d.pos[0], d.pos[1], d.pos[2], d.yaw, t[src + 4], t[src + 5], Math.min(Math.max(d.fall, 0), 3.1415926) + 4 * lost, d.az], 8 * (n + k));
        });
        this.debris = list;
        this.subUpload(this.trees, t, 2 * n, 2 * (n + Math.max(list.length, 1)));
        if (!same) this.uploadCuts(); // the cut lists change only with the set of pieces
    }

    // The last WIND slice (PROTOCOL.md "WIND"), as gale-client keeps it for a leaf's drift
    // (client/client_stream.c take_wind, client/render_wind.c render_wind_at): the mean as
    // the uniform wind, the cells on a grid one layer high.
    setWind(w) {
        const n = w.nx * w.ny, v = new Float32Array(3 * n), mean = [0, 0, 0];
        for (let i = 0; i < 3 * n; i++) {
            v[i] = Math.fround(w.cells[i] * w.scale_ms);
            mean[i % 3] += v[i];
        }
        this.windGrid = { nx: w.nx, ny: w.ny, origin: [w.x0_m, w.y0_m, 0],
            cell: [w.cell_m, w.cell_m, 2 * w.z_m > 1 ? 2 * w.z_m : 1], v };
        this.windMean = mean.map((x) => x / n);
    }

    windAt(p) {
        const g = this.windGrid;
        if (!g) return [0, 0, 0];
        const ijk = [];
        const nk = [g.nx, g.ny, 1];
        for (let k = 0; k < 3; k++) {
            let c = (p[k] - g.origin[k]) / g.cell[k];
            if (k === 2) c = Math.min(Math.max(c, 0), nk[2] - 0.5); // a slice applies at every height
            if (!(c >= 0) || c >= nk[k]) return this.windMean;
            ijk.push(Math.trunc(c));
        }
        const c = ijk[0] + g.nx * ijk[1];
        return [g.v[3 * c], g.v[3 * c + 1], g.v[3 * c + 2]];
    }

    clearFalling() {
        this.ringHead = 0;
        this.ringCount = 0;
        this.dirtyLo = Infinity;
        this.dirtyHi = 0;
    }

    // One leaf torn from its tree (render_add_falling_leaf): released from its slot in the
    // tree's pose of q (the length-true form, protocol/asset_pose.c, for that node only) at
    // server time spawn_s, its variation from its seed, its landing time and the wind's
    // drift at release; q: the tree's modal state [modes] (null: at rest). Returns false for
    // a tree or slot outside the scene.
    addFallingLeaf(tree, slot, seed, spawn_s, q) {
        if (!(tree < this.n_trees) || !Number.isFinite(spawn_s)) return false;
        const r = this.inst[tree], s = this.species[r[0]];
        if (!s || !(slot < s.n_leaves)) return false;
        const a = s.a, nn = a.n_nodes, f = Math.fround;
        const j = a.leaf_node[slot];
        const acc = [0, 0, 0];
        let i = j;
        for (let guard = 0; guard < nn && a.parent[i] >= 0; guard++) {
            const p = a.parent[i], th = [0, 0, 0], sg = [0, 1, 2].map((k) => a.rest[3 * i + k] - a.rest[3 * p + k]);
            for (let m = 0; m < s.n_modes; m++) {
                const qm = (q && q[m]) || 0, b = a.corr_b[m];
                const qt = b !== 0 ? f(a.corr_a[m] * f(Math.atan(f(b * qm)))) : qm;
                const o = (m * nn + i) * 3;
                for (let k = 0; k < 3; k++) {
                    th[k] += qt * a.corr_v[o + k];
                    sg[k] += qt * a.corr_w[o + k];
                }
            }
            const t2 = th[0] * th[0] + th[1] * th[1] + th[2] * th[2];
            let sa, ca;
            if (t2 < 1e-8) {
                sa = 1 - t2 / 6;
                ca = 0.5 - t2 / 24;
            } else {
                const tt = Math.sqrt(t2);
                sa = Math.sin(tt) / tt;
                ca = (1 - Math.cos(tt)) / t2;
            }
            const c = [th[1] * sg[2] - th[2] * sg[1], th[2] * sg[0] - th[0] * sg[2], th[0] * sg[1] - th[1] * sg[0]];
            const cc = [th[1] * c[2] - th[2] * c[1], th[2] * c[0] - th[0] * c[2], th[0] * c[1] - th[1] * c[0]];
            for (let k = 0; k < 3; k++) acc[k] += sg[k] + sa * c[k] + ca * cc[k];
            i = p;
        }
        const x = [0, 1, 2].map((k) => f(a.rest[3 * i + k] + acc[k]));
        const sc = r[5] > 0 ? r[5] : 1, cy = f(Math.cos(r[4])), sy = f(Math.sin(r[4]));
        const off = a.leaf_offset.subarray(3 * slot, 3 * slot + 3);
        const lp = [0, 1, 2].map((k) => f(f(x[k] + off[k]) * sc));
        const wp = [f(f(r[1] + f(cy * lp[0])) - f(sy * lp[1])), f(f(r[2] + f(sy * lp[0])) + f(cy * lp[1])), f(r[3] + lp[2])];
        const h = hashMix32((seed ^ Math.imul(tree, 2654435761) ^ Math.imul(slot, 40503)) >>> 0);
        const v = fallingVar(this.path, h);
        const t_land = fallingPathLandTime(this.path, v, wp[2], 600);
        const wind = this.windAt(wp);
        if (this.t_base === undefined) this.t_base = Math.floor(spawn_s);
        const e = this.ringHead * FALL_FLOATS, o = this.ring;
        o.fill(0, e, e + FALL_FLOATS);
        o.set([wp[0], wp[1], wp[2], spawn_s - this.t_base, v.yaw, v.sx, v.sy, v.start, 0.8 * wind[0], 0.8 * wind[1], t_land], e);
        this.ringU32[e + 11] = v.seed; // fall.vert reads its bits (floatBitsToUint)
        // orientation on the tree: blade axis x, normal z (rest pose, instance yaw)
        const n0 = a.leaf_normal.subarray(3 * slot, 3 * slot + 3);
        const nz = [cy * n0[0] - sy * n0[1], sy * n0[0] + cy * n0[1], n0[2]];
        let ax = Math.abs(nz[0]) > 0.9 ? [0, 1, 0] : [1, 0, 0];
        const d = ax[0] * nz[0] + ax[1] * nz[1] + ax[2] * nz[2];
        ax = ax.map((c, k) => c - d * nz[k]);
        const al = Math.hypot(...ax);
        ax = ax.map((c) => c / al);
        const ay = [nz[1] * ax[2] - nz[2] * ax[1], nz[2] * ax[0] - nz[0] * ax[2], nz[0] * ax[1] - nz[1] * ax[0]];
        o.set(quatFromBasis(ax, ay, nz), e + 12);
        // torn leaves: the species colour, some turned yellow-brown
        const yel = 0.35 * (hashMix32((h + 5) >>> 0) >>> 8) / 16777216, brown = [0.62, 0.48, 0.16];
        for (let k = 0; k < 3; k++) o[e + 16 + k] = s.leaf_rgb[k] * (1 - yel) + brown[k] * yel;
        o[e + 19] = a.leaf_size[slot] * sc;
        o[e + 20] = s.leaf_shape;
        this.dirtyLo = Math.min(this.dirtyLo, this.ringHead);
        this.dirtyHi = Math.max(this.dirtyHi, this.ringHead + 1);
        this.ringHead = (this.ringHead + 1) % MAX_FALLING;
        if (this.ringCount < MAX_FALLING) this.ringCount++;
        return true;
    }

    // The falling and landed leaves (render_fall_draw) at server time server_s.
    drawFalling(server_s) {
        const gl = this.gl;
        this.stats.falling = this.ringCount;
        if (this.ringCount === 0 || this.hideFalling || this.t_base === undefined || !Number.isFinite(server_s)) return;
        gl.bindBuffer(gl.ARRAY_BUFFER, this.fallVbo);
        if (this.dirtyLo < this.dirtyHi) {
            gl.bufferSubData(gl.ARRAY_BUFFER, this.dirtyLo * FALL_FLOATS * 4, this.ring, this.dirtyLo * FALL_FLOATS, (this.dirtyHi - this.dirtyLo) * FALL_FLOATS);
        }
        this.dirtyLo = Infinity;
        this.dirtyHi = 0;
        const p = this.p.fall, path = this.path;
        this.setCommon(p, server_s - this.t_base);
        gl.uniform1i(p.u.u_npath, path.n);
        gl.uniform1f(p.u.u_pdt, path.dt);
        gl.uniform1i(p.u.u_ncont, path.cont.length);
        const cont = new Int32Array(8);
        cont.set(path.cont);
        gl.uniform1iv(p.u.u_cont, cont);
        gl.uniform1fv(p.u.u_aspects, LEAF_ASPECT);
        this.bindTex(RU.PATH, gl.TEXTURE_2D, this.pathTex);
        gl.bindVertexArray(this.fallVao);
        gl.drawArraysInstanced(gl.TRIANGLES, 0, 6, this.ringCount);
    }

    // Root plates of uprooted trees and stumps of snapped ones among the trees drawn
    // (client/render.c build_lists, render_damage.c render_plates_draw, render_stumps_draw).
    drawDamage(drawn, t) {
        const gl = this.gl, plates = [], stumps = [];
        for (const i of drawn) {
            if (i >= this.n_trees) continue; // a debris piece has no stump nor plate
            const z = this.treeData[8 * i + 6], fall = z - 4 * Math.floor(z * 0.25);
            if (this.uprooted[i] && fall > 0.02) plates.push(i);
            if (z >= 256) {
                const s = this.species[this.inst[i][0]];
                stumps.push(i, s.stem_r_m, s.stem_taper, 0, s.bark[0], s.bark[1], s.bark[2], 0);
            }
        }
        this.stats.plates = plates.length;
        this.stats.stumps = stumps.length / 8;
        this.bindTex(RU.TREES, gl.TEXTURE_2D, this.trees.tex);
        gl.bindVertexArray(this.vaoEmpty);
        if (plates.length) {
            this.plateBuf = this.dataTex(1, plates.length, Float32Array.from(plates), this.plateBuf);
            this.setCommon(this.p.plate, t);
            this.bindTex(RU.PLATE, gl.TEXTURE_2D, this.plateBuf.tex);
            gl.drawArraysInstanced(gl.TRIANGLES, 0, 12 * PLATE_SEG, plates.length);
        }
        if (stumps.length) {
            this.stumpBuf = this.dataTex(4, stumps.length / 4, Float32Array.from(stumps), this.stumpBuf);
            this.setCommon(this.p.stump, t);
            this.bindTex(RU.STUMP, gl.TEXTURE_2D, this.stumpBuf.tex);
            gl.drawArraysInstanced(gl.TRIANGLES, 0, 21 * STUMP_SEG, stumps.length / 8);
        }
    }

    // The modal state's store: a ring of `layers` snapshots, each one's quantised values Q
    // [n_trees × stride] (int16, as decoded) in a layer of an R16I texture array, DATA_W
    // texels a row, uploaded once, by the first frame that blends it (setMix): a page that
    // draws slower than snapshots come uploads only those it draws. The skeleton pass
    // blends the layers setMix names (shaders/skel.frag GALE_Q_RING).
    setStride(stride, layers = 32) {
        const gl = this.gl, n = Math.max(1, this.n_trees * stride), w = Math.min(DATA_W, n), h = Math.ceil(n / w);
        this.q_stride = stride;
        this.mix = null;
        if (this.qring && this.qring.w === w && this.qring.h === h && this.qring.layers === layers) {
            this.qring.n = n;
            this.qring.held.fill(null);
            return;
        }
        if (this.qring) gl.deleteTexture(this.qring.tex);
        const tex = gl.createTexture();
        gl.activeTexture(gl.TEXTURE0 + RU.SCRATCH);
        gl.bindTexture(gl.TEXTURE_2D_ARRAY, tex);
        gl.texStorage3D(gl.TEXTURE_2D_ARRAY, 1, gl.R16I, w, h, layers);
        // an integer texture is complete only unfiltered
        for (const k of [gl.TEXTURE_MIN_FILTER, gl.TEXTURE_MAG_FILTER]) gl.texParameteri(gl.TEXTURE_2D_ARRAY, k, gl.NEAREST);
        this.qring = { tex, w, h, layers, n, held: new Array(layers).fill(null) }; // held: the snapshot in each layer
    }

    // One snapshot's Q [n_trees × stride] (Int16Array) into layer `layer` of the ring.
    uploadSnapshot(layer, q) {
        const gl = this.gl, { tex, w, n } = this.qring, full = Math.floor(n / w);
        if (!(layer >= 0 && layer < this.qring.layers) || q.length < n) throw new Error(`snapshot of ${q.length} values into layer ${layer}: expected ${n} values, layer < ${this.qring.layers}`);
        gl.activeTexture(gl.TEXTURE0 + RU.SCRATCH);
        gl.bindTexture(gl.TEXTURE_2D_ARRAY, tex);
        if (full) gl.texSubImage3D(gl.TEXTURE_2D_ARRAY, 0, 0, 0, layer, w, full, 1, gl.RED_INTEGER, gl.SHORT, q, 0);
        if (n > full * w) gl.texSubImage3D(gl.TEXTURE_2D_ARRAY, 0, 0, full, layer, n - full * w, 1, 1, gl.RED_INTEGER, gl.SHORT, q, full * w);
    }

    // The snapshots the next frames blend (web/jitter.js weights: snaps[k].slot its layer,
    // c[k] its Hermite weight, snaps[k].meta the keyframe scene whose steps dequantise it;
    // null: none, drawn at rest), and per species the shader's weights (blendWeights): one
    // multiply-add per value and snapshot there.
    // Snapshots not yet in their layer are uploaded first (stats.upload_ms, stats.uploads).
    setMix(w) {
        this.mix = w && w.n ? w : null;
        this.stats.upload_ms = 0;
        if (!this.mix) return;
        const t0 = performance.now();
        let ups = 0;
        for (let k = 0; k < w.n; k++) {
            const snap = w.snaps[k];
            if (this.qring.held[snap.slot] === snap) continue;
            this.uploadSnapshot(snap.slot, snap.q);
            this.qring.held[snap.slot] = snap;
            ups++;
        }
        if (ups) this.stats.upload_ms = performance.now() - t0;
        this.stats.uploads = (this.stats.uploads || 0) + ups;
        this.qlayer = this.qlayer || new Int32Array(4);
        for (let k = 0; k < 4; k++) this.qlayer[k] = w.snaps[k < w.n ? k : 0].slot;
        this.species.forEach((sp, s) => { if (sp) blendWeights(w, s, sp.qw); });
    }

    // q of every tree [n_trees × q_stride] (floats) for the float path (useFloatQ).
    uploadQ(q) {
        const gl = this.gl;
        this.q = this.dataTex(1, Math.max(1, this.n_trees * this.q_stride), null, this.q);
        const n = this.n_trees * this.q_stride, w = this.q.w, rows = Math.ceil(n / w);
        gl.activeTexture(gl.TEXTURE0 + RU.SCRATCH);
        gl.bindTexture(gl.TEXTURE_2D, this.q.tex);
        if (q.length >= rows * w) {
            gl.texSubImage2D(gl.TEXTURE_2D, 0, 0, 0, w, rows, gl.RED, gl.FLOAT, q, 0);
        } else {
            if (rows > 1) gl.texSubImage2D(gl.TEXTURE_2D, 0, 0, 0, w, rows - 1, gl.RED, gl.FLOAT, q, 0);
            const last = n - (rows - 1) * w;
            gl.texSubImage2D(gl.TEXTURE_2D, 0, 0, rows - 1, last, 1, gl.RED, gl.FLOAT, q, (rows - 1) * w);
        }
    }

    ensureSkel(w, rows) {
        const gl = this.gl;
        if (w <= this.skel_w && rows <= this.skel_h) return;
        w = Math.max(w, this.skel_w);
        rows = Math.max(rows, 2 * this.skel_h, 16);
        this.skelTex = this.skelTex || [gl.createTexture(), gl.createTexture()];
        this.skelFbo = this.skelFbo || [gl.createFramebuffer(), gl.createFramebuffer()];
        for (let k = 0; k < 2; k++) {
            gl.bindTexture(gl.TEXTURE_2D, this.skelTex[k]);
            gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, w, rows, 0, gl.RGBA, gl.FLOAT, null);
            for (const p of [gl.TEXTURE_MIN_FILTER, gl.TEXTURE_MAG_FILTER]) gl.texParameteri(gl.TEXTURE_2D, p, gl.NEAREST);
            gl.bindFramebuffer(gl.FRAMEBUFFER, this.skelFbo[k]);
            gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, this.skelTex[k], 0);
            if (gl.checkFramebufferStatus(gl.FRAMEBUFFER) !== gl.FRAMEBUFFER_COMPLETE) {
                throw new WebGL2Missing(`skeleton texture ${w}×${rows} (RGBA32F) is not renderable here`);
            }
        }
        this.skel_w = w;
        this.skel_h = rows;
    }

    setCommon(p, t) {
        const gl = this.gl, u = p.u, fx = this.fx;
        gl.useProgram(p.id);
        gl.uniformMatrix4fv(u.u_viewproj, false, this.viewproj);
        gl.uniform3fv(u.u_eye, this.eye);
        const sun = [0.45, -0.35, 0.62], l = Math.hypot(...sun);
        gl.uniform3fv(u.u_sun_dir, sun.map((x) => x / l));
        gl.uniform3fv(u.u_sun_col, fx.sun_col);
        gl.uniform3fv(u.u_sky_zenith, fx.sky_zenith);
        gl.uniform3fv(u.u_sky_horizon, fx.sky_horizon);
        gl.uniform3fv(u.u_ground_col, fx.ground_col);
        gl.uniform1f(u.u_fog_dist, FOG_DIST_M * fx.fog_scale);
        // the storm fog is the calm one times fog_scale; up to the subject it is thinned
        // towards the calm fog (common.glsl fog_apply)
        if (u.u_storm) gl.uniform4f(u.u_storm, fx.wet, this.subject_m, FOG_DIST_M, fx.subject_clear);
        gl.uniform1f(u.u_time, t);
        gl.uniform3fv(u.u_wind_origin, [0, 0, 0]);
        gl.uniform3fv(u.u_wind_extent, [0, 0, 0]);
        gl.uniform3fv(u.u_wind_uniform, this.windUniform || [0, 0, 0]);
        this.bindTex(RU.WIND, gl.TEXTURE_3D, this.wind);
    }

    // Rain streaks and spray over the frame (client/render_rain.c): one full-screen
    // triangle of rain.frag, blended, after the scene.
    drawRain(t) {
        const gl = this.gl, fx = this.fx, p = this.p.rain;
        if (fx.rain_layers <= 0 || !(fx.rain > 0)) return;
        const v = this.view || new Float32Array(16); // no view matrix: streaks fall straight
        let subject = null;
        if (this.subject_m > 0) {
            // the subject lies subject_m along the view axis: -(row 2 of the view matrix)
            subject = [0, 1, 2].map((k) => this.eye[k] - this.subject_m * v[4 * k + 2]);
        }
        const ru = rainUniforms(fx, v, this.viewproj, subject, this.canvas.width, this.canvas.height);
        this.setCommon(p, t);
        gl.uniform4fv(p.u.u_rain, ru.rain);
        gl.uniform2fv(p.u.u_spray, ru.spray);
        gl.uniform4fv(p.u.u_rain_clear, ru.clear);
        gl.uniformMatrix4fv(p.u.u_inv_viewproj, false, invert(this.viewproj));
        gl.disable(gl.DEPTH_TEST);
        gl.depthMask(false);
        gl.enable(gl.BLEND);
        gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA);
        gl.bindVertexArray(this.vaoEmpty);
        gl.drawArrays(gl.TRIANGLES, 0, 3);
        gl.disable(gl.BLEND);
        gl.depthMask(true);
        gl.enable(gl.DEPTH_TEST);
    }

    // The picture draw() renders into while this.offscreen is set (colour and depth of the
    // canvas's size), so that a frame can be drawn ahead and shown later: present() copies
    // it to the canvas, which the browser composites at its next display refresh.
    target() {
        const gl = this.gl, w = this.canvas.width, h = this.canvas.height;
        if (this.off && this.off.w === w && this.off.h === h) return this.off.fbo;
        if (this.off) {
            gl.deleteFramebuffer(this.off.fbo);
            for (const rb of this.off.rb) gl.deleteRenderbuffer(rb);
        }
        const fbo = gl.createFramebuffer(), rb = [gl.createRenderbuffer(), gl.createRenderbuffer()];
        gl.bindFramebuffer(gl.FRAMEBUFFER, fbo);
        [[gl.RGBA8, gl.COLOR_ATTACHMENT0], [gl.DEPTH_COMPONENT24, gl.DEPTH_ATTACHMENT]].forEach(([fmt, at], k) => {
            gl.bindRenderbuffer(gl.RENDERBUFFER, rb[k]);
            gl.renderbufferStorage(gl.RENDERBUFFER, fmt, w, h);
            gl.framebufferRenderbuffer(gl.FRAMEBUFFER, at, gl.RENDERBUFFER, rb[k]);
        });
        if (gl.checkFramebufferStatus(gl.FRAMEBUFFER) !== gl.FRAMEBUFFER_COMPLETE) {
            throw new WebGL2Missing(`an offscreen picture of ${w}×${h} (RGBA8, depth 24) is not renderable here`);
        }
        this.off = { fbo, rb, w, h };
        return fbo;
    }

    // The offscreen picture onto the canvas (false when there is none of the canvas's size).
    present() {
        const gl = this.gl, o = this.off;
        if (!o || o.w !== this.canvas.width || o.h !== this.canvas.height) return false;
        gl.bindFramebuffer(gl.READ_FRAMEBUFFER, o.fbo);
        gl.bindFramebuffer(gl.DRAW_FRAMEBUFFER, null);
        gl.blitFramebuffer(0, 0, o.w, o.h, 0, 0, o.w, o.h, gl.COLOR_BUFFER_BIT, gl.NEAREST);
        gl.bindFramebuffer(gl.FRAMEBUFFER, null);
        return true;
    }

    // cam: { eye, target, fov_y_deg, near, far, subject_m? } or { viewproj, eye } for a
    // wall tile (subject_m: how far along the view the camera's subject lies, 0 none);
    // modes: per tree mode count (0: not sent: drawn at rest with none); server_s: the
    // server time shown (falling leaves follow it), undefined: none drawn.
    draw(cam, t, modes, server_s) {
        const gl = this.gl, W = this.canvas.width, H = this.canvas.height;
        if (cam.viewproj) {
            this.viewproj = cam.viewproj;
            this.view = cam.view || null;
        } else {
            const proj = perspective(cam.fov_y_deg * Math.PI / 180, W / H, cam.near || 0.3, cam.far || 3000);
            this.view = lookAt(cam.eye, cam.target, [0, 0, 1]);
            this.viewproj = mul(proj, this.view);
        }
        this.eye = cam.eye;
        if (this.t_base === undefined && Number.isFinite(server_s)) this.t_base = Math.floor(server_s);
        this.subject_m = cam.subject_m > 0 && Number.isFinite(cam.subject_m) && this.view ? cam.subject_m : 0;
        // the draw list: per species, its trees nearest first, up to max_rows in all
        const per = this.species.map(() => []);
        const order = [];
        for (let i = 0; i < this.n_trees; i++) {
            const r = this.inst[i];
            if (!this.species[r[0]]) continue;
            order.push([Math.hypot(r[1] - cam.eye[0], r[2] - cam.eye[1], r[3] - cam.eye[2]), i]);
        }
        // the debris pieces in slots after the trees
        const spOf = (i) => (i < this.n_trees ? this.inst[i][0] : this.debris[i - this.n_trees].species);
        this.debris.forEach((d, k) => {
            if (this.species[d.species]) order.push([Math.hypot(d.pos[0] - cam.eye[0], d.pos[1] - cam.eye[1], d.pos[2] - cam.eye[2]), this.n_trees + k]);
        });
        order.sort((a, b) => a[0] - b[0]);
        const drawn = order.slice(0, this.max_rows).map(([, i]) => i);
        for (const [d, i] of order.slice(0, this.max_rows)) per[spOf(i)].push([i, d]);
        const list = new Float32Array(Math.max(1, order.length) * 4);
        const groups = [];
        let row = 0, maxw = 1;
        per.forEach((trees, s) => {
            const sp = this.species[s];
            if (!sp || !trees.length) return;
            maxw = Math.max(maxw, sp.n_nodes);
            // nearer trees get the finer mesh LOD: one group per LOD, 30 m apart
            const byLod = Array.from({ length: sp.n_lods }, () => []);
            for (const [i, d] of trees) byLod[Math.min(sp.n_lods - 1, Math.floor(d / 30))].push(i);
            const g = { s, base: row, lods: [] };
            for (let l = 0; l < sp.n_lods; l++) {
                g.lods.push([row, byLod[l].length]);
                for (const i of byLod[l]) {
                    // a debris piece: its rest pose needs no modes
                    const nm = i >= this.n_trees ? 0 : modes ? Math.min(modes[i], sp.n_modes) : sp.n_modes;
                    list.set([i, row, nm, 1], 4 * row);
                    row++;
                }
            }
            g.n = row - g.base;
            groups.push(g);
        });
        this.stats.trees_drawn = row;
        this.groups = groups; // the skeleton rows drawn: for tests
        this.list = this.dataTex(4, Math.max(1, row), list.subarray(0, Math.max(1, row) * 4), this.list);
        this.ensureSkel(maxw, row);

        gl.disable(gl.DEPTH_TEST);
        gl.disable(gl.BLEND);
        const ring = !this.floatQ, ps = ring ? this.p.skel : this.p.skelF;
        gl.useProgram(ps.id);
        gl.uniform2f(ps.u.u_target, this.skel_w, this.skel_h);
        gl.uniform1i(ps.u.u_qstride, this.q_stride);
        gl.bindVertexArray(this.vaoEmpty);
        this.bindTex(RU.LIST, gl.TEXTURE_2D, this.list.tex);
        if (ring) {
            this.bindTex(RU.Q, gl.TEXTURE_2D_ARRAY, this.qring.tex);
            gl.uniform4iv(ps.u.u_qlayer, this.mix ? this.qlayer : [0, 0, 0, 0]);
        } else {
            this.bindTex(RU.Q, gl.TEXTURE_2D, this.q.tex);
        }
        this.bindTex(RU.CUT, gl.TEXTURE_2D, this.cut.tex);
        this.bindTex(RU.CUTN, gl.TEXTURE_2D, this.cutn.tex);
        for (const g of groups) {
            const sp = this.species[g.s];
            gl.uniform1i(ps.u.u_base, g.base);
            gl.uniform1i(ps.u.u_nodes, sp.n_nodes);
            gl.uniform2fv(ps.u.u_ab, sp.ab);
            if (ring) {
                if (!this.mix) sp.qw.fill(0); // at rest
                gl.uniform4fv(ps.u.u_qw, sp.qw);
            }
            this.bindTex(RU.VW, gl.TEXTURE_2D, sp.vw.tex);
            this.bindTex(RU.NODE, gl.TEXTURE_2D, sp.node.tex);
            // pass 0: posed segments into skelTex[1]; pass 1: their sums into skelTex[0]
            gl.bindFramebuffer(gl.FRAMEBUFFER, this.skelFbo[1]);
            gl.viewport(0, 0, this.skel_w, this.skel_h);
            this.bindTex(RU.SKEL, gl.TEXTURE_2D, this.skelTex[0]);
            gl.uniform1i(ps.u.u_pass, 0);
            gl.drawArraysInstanced(gl.TRIANGLES, 0, 6, g.n);
            gl.bindFramebuffer(gl.FRAMEBUFFER, this.skelFbo[0]);
            this.bindTex(RU.SKEL, gl.TEXTURE_2D, this.skelTex[1]);
            gl.uniform1i(ps.u.u_pass, 1);
            gl.drawArraysInstanced(gl.TRIANGLES, 0, 6, g.n);
        }

        gl.bindFramebuffer(gl.FRAMEBUFFER, this.offscreen ? this.target() : null);
        gl.viewport(0, 0, W, H);
        gl.enable(gl.DEPTH_TEST);
        gl.depthMask(true);
        gl.clear(gl.DEPTH_BUFFER_BIT);
        gl.depthFunc(gl.ALWAYS);
        this.setCommon(this.p.sky, t);
        gl.uniformMatrix4fv(this.p.sky.u.u_inv_viewproj, false, invert(this.viewproj));
        gl.bindVertexArray(this.vaoEmpty);
        gl.drawArrays(gl.TRIANGLES, 0, 3);
        gl.depthFunc(gl.LESS);

        // houses (both faces drawn: the mesh is closed, and thin boxes stay visible);
        // gale-client's colours (client/render.c)
        if (this.houseVerts > 0 && !this.hideHouses) {
            const ph = this.p.house;
            this.setCommon(ph, t);
            gl.uniform3f(ph.u.u_wall, 0.92, 0.82, 0.64);
            gl.uniform3f(ph.u.u_roof, 0.52, 0.22, 0.15);
            gl.uniform3f(ph.u.u_window, 0.14, 0.18, 0.24);
            gl.bindVertexArray(this.houseVao);
            gl.drawArrays(gl.TRIANGLES, 0, this.houseVerts);
        }

        if (this.hideTrees) {
            this.stats.frames++;
            return;
        }
        this.bindTex(RU.SKEL, gl.TEXTURE_2D, this.skelTex[0]);
        this.bindTex(RU.LIST, gl.TEXTURE_2D, this.list.tex);
        this.bindTex(RU.TREES, gl.TEXTURE_2D, this.trees.tex);
        gl.enable(gl.CULL_FACE);
        gl.cullFace(gl.BACK);
        const pt = this.p.tree;
        this.setCommon(pt, t);
        for (const g of groups) {
            const sp = this.species[g.s];
            gl.uniform3fv(pt.u.u_bark, sp.bark);
            this.bindTex(RU.NODE, gl.TEXTURE_2D, sp.node.tex);
            gl.bindVertexArray(sp.vao);
            g.lods.forEach(([base, n], l) => {
                if (!n || !sp.lod_count[l]) return;
                gl.uniform1i(pt.u.u_base, base);
                gl.drawElementsInstanced(gl.TRIANGLES, sp.lod_count[l], gl.UNSIGNED_INT, sp.lod_first[l] * 4, n);
            });
        }
        gl.disable(gl.CULL_FACE);
        this.drawDamage(drawn, t);
        const pl = this.p.leaf;
        this.setCommon(pl, t);
        gl.bindVertexArray(this.vaoEmpty);
        for (const g of groups) {
            const sp = this.species[g.s];
            if (!sp.n_leaves) continue;
            gl.uniform1i(pl.u.u_base, g.base);
            gl.uniform1i(pl.u.u_nleaves, sp.n_leaves);
            gl.uniform1f(pl.u.u_aspect, LEAF_ASPECT[sp.leaf_shape]);
            gl.uniform2f(pl.u.u_crown, sp.crown_r, sp.height);
            gl.uniform3fv(pl.u.u_leafcol, sp.leaf_rgb);
            gl.uniform1i(pl.u.u_shape, sp.leaf_shape);
            this.bindTex(RU.NODE, gl.TEXTURE_2D, sp.node.tex);
            this.bindTex(RU.LEAF, gl.TEXTURE_2D, sp.leaf.tex);
            gl.drawArraysInstanced(gl.TRIANGLES, 0, 6, g.n * sp.n_leaves);
        }
        this.drawFalling(server_s);
        this.drawRain(t);
        // the first frames are checked (a check each frame would stall the pipeline)
        if (this.stats.frames++ < 3) {
            const e = gl.getError();
            if (e) throw new Error(`WebGL error 0x${e.toString(16)} in frame ${this.stats.frames}`);
        }
    }
}
