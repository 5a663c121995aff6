// Falling leaves (client/render/render_fall.c): the shared falling-leaf path as a texture, the
// ring of released leaves, each placed from its tree's pose and the streamed wind, and
// their draw (fall.vert/.frag). Renderer (web/render_gl.js) takes these methods as its own.
import { hashMix32 } from './hash.js';
import { fallingPathBuild, fallingVar, fallingPathLandTime } from './falling_path.js';
import { RU } from './render_data.js';
import { LEAF_ASPECT } from './render_species.js';

const MAX_FALLING = 16384; // render_desc max_falling's default (client/render/render.c)
const FALL_FLOATS = 21;    // rs_fall: start, var, drift, q0, look (4 each), shape

// quaternion (x, y, z, w) of an orthonormal basis given as columns (client/render/render_fall.c)
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

export class RendererFall {
    // The shared falling-leaf path as a 2-row texture (positions, orientations) and the
    // ring of released leaves in an instanced vertex buffer (client/render/render_fall.c).
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

    // The last WIND slice (PROTOCOL.md "WIND"), as gale-client keeps it for a leaf's drift
    // (client/app/client_stream.c take_wind, client/render/render_wind.c render_wind_at): the mean as
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
}
