// The renderer's GPU data and its setup: the texture units (the native client's), the
// samplers bound to them, and data textures: what the native client keeps in buffer
// textures lives here in 2D textures read by buf_fetch (shaders/common.glsl), row-major,
// DATA_W texels a row. Renderer (web/render_gl.js) takes these methods as its own.

export class WebGL2Missing extends Error {}

export const DATA_W = 2048;
// texture units: the native client's (client/render/render_internal.h)
export const RU = { SKEL: 0, NODE: 1, LIST: 2, TREES: 3, VW: 4, Q: 5, LEAF: 6, WIND: 7, PATH: 8, CUT: 10, CUTN: 11, PLATE: 12, STUMP: 13, SCRATCH: 15,
    IMP: 9, IMP_WOOD: 14 }; // SCRATCH: uploads; IMP, IMP_WOOD: the impostors' textures (web/render_imp.js)
const SAMPLERS = { u_skel: RU.SKEL, u_node: RU.NODE, u_list: RU.LIST, u_trees: RU.TREES, u_vw: RU.VW,
    u_q: RU.Q, u_qring: RU.Q, u_leaf: RU.LEAF, u_wind: RU.WIND, u_path: RU.PATH, u_cut: RU.CUT, u_cutn: RU.CUTN, u_plates: RU.PLATE, u_stumps: RU.STUMP,
    u_imp: RU.IMP, u_imp_wood: RU.IMP_WOOD };

export class RendererData {
    bindSamplers(p) {
        const gl = this.gl;
        gl.useProgram(p.id);
        for (const [name, unit] of Object.entries(SAMPLERS)) if (p.u[name]) gl.uniform1i(p.u[name], unit);
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
            // the whole rows, then the last row's texels alone: no padded copy (from the air
            // the impostors' list is 1.5 MB a frame); texels past the data are never read
            const texels = Math.floor(data.length / channels), full = Math.floor(texels / w), rest = texels - full * w;
            if (full) gl.texSubImage2D(gl.TEXTURE_2D, 0, 0, 0, w, full, fmt, gl.FLOAT, data.subarray(0, full * w * channels));
            if (rest) gl.texSubImage2D(gl.TEXTURE_2D, 0, 0, full, rest, 1, fmt, gl.FLOAT, data.subarray(full * w * channels, texels * channels));
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
}
