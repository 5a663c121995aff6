// The modal state and the skeleton pass (shaders/skel.frag): the ring of snapshots' quantised
// values the pass blends (or q as floats, the native client's way, for tests), and the two
// passes that pose every drawn tree's nodes into float textures. Renderer
// (web/render_gl.js) takes these methods as its own.
import { loadProgram } from './shaders.js';
import { blendWeights } from './jitter.js';
import { WebGL2Missing, DATA_W, RU } from './render_data.js';

export class RendererSkel {
    // The skeleton pass from q uploaded as floats (uploadQ), the native client's way, in
    // place of the blend of snapshots: for tests that hold the one to the other.
    async useFloatQ(on) {
        if (on && !this.p.skelF) {
            this.p.skelF = await loadProgram(this.gl, 'skel', this.base);
            this.bindSamplers(this.p.skelF);
        }
        this.floatQ = on;
    }

    // The modal state's store: a ring of `layers` snapshots, each one's quantised values Q
    // [q_trees × stride] (int16, as decoded) in a layer of an R16I texture array, DATA_W
    // texels a row, uploaded once, by the first frame that blends it (setMix): a page that
    // draws slower than snapshots come uploads only those it draws. The skeleton pass
    // blends the layers setMix names (shaders/skel.frag GALE_Q_RING).
    setStride(stride, layers = 32) {
        // the trees whose motion the page holds (App: q_trees), all of them unless a
        // scene is past the page's memory
        const gl = this.gl, n = Math.max(1, Math.min(this.n_trees, this.q_trees) * stride), w = Math.min(DATA_W, n), h = Math.ceil(n / w);
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
        // grown by doubling, never past the frame's budget of trees nor the GPU's largest
        // texture (web/render_list.js)
        w = Math.max(w, this.skel_w);
        rows = Math.min(Math.max(rows, 2 * this.skel_h, 16), Math.max(rows, Math.min(this.max_rows, this.maxSkelRows())));
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

    // The skeleton rows of the draw list's groups posed: pass 0 writes the posed segments,
    // pass 1 their sums, the nodes' places that the tree and leaf draws read (u_skel).
    poseSkeletons(groups) {
        const gl = this.gl;
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
    }
}
