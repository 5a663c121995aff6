// Far trees as impostors (Singh section 2, Oliapuram LOD; client/render/render_species.c
// species_impostor and shaders/bill.*): per species at load its picture at rest, seen from
// the side, orthographic, into a mipmapped texture (alpha its coverage), and a second of
// its wood alone; per frame one instanced draw a species of every tree past THIN, a quad
// turned toward the eye and swaying with the tree's lowest modes (web/imp_sway.js,
// web/imp_shader.js). A crown that lost leaves keeps that share of its leaf texels and
// shows its wood where they went (shaders/bill.frag). Renderer (web/render_gl.js) takes
// these methods as its own.
import { loadProgram } from './shaders.js';
import { RU } from './render_data.js';
import { LEAF_ASPECT } from './render_species.js';
import { impostorQuad, crownSway } from './imp_sway.js';
import { IMP_VERT, IMP_VERT_NAME } from './imp_shader.js';
import { lookAt, ortho, mul } from './view_math.js';

// The impostor texture's size [texels] (the native client's RENDER_IMP_W, RENDER_IMP_H).
export const IMP_W = 256, IMP_H = 512;

export class RendererImp {
    // The impostor's programs: the snapshot ring's blend, and the float path's q (useFloatQ).
    async impInit(base) {
        const vert = { name: IMP_VERT_NAME, source: IMP_VERT };
        const [ring, flt] = await Promise.all([loadProgram(this.gl, 'bill', base, '#define GALE_Q_RING 1\n', vert), loadProgram(this.gl, 'bill', base, '', vert)]);
        this.p.imp = ring;
        this.p.impF = flt;
        this.bindSamplers(ring);
        this.bindSamplers(flt);
    }

    // Every species' impostor not yet drawn (a species is drawn once, at the first frame
    // after it loaded): its quad, its crown's sway, and its two pictures at rest.
    ensureImpostors() {
        for (const sp of this.species) {
            if (!sp || sp.imp) continue;
            const q = impostorQuad(sp.height, sp.crown_r);
            sp.bsize = [q.hw_m, q.top_m - q.bottom_m, q.bottom_m];
            sp.sway = crownSway(sp.a);
            this.restPose(sp);
            sp.imp = this.impostorDraw(sp, q, true);
            sp.impWood = this.impostorDraw(sp, q, false);
        }
    }

    // Species sp at rest into row 0 of the skeleton texture: a tree of its own (at the
    // origin, unturned, unit scale, no damage) with no modes and no cuts.
    restPose(sp) {
        const s = this.species.indexOf(sp), keep = { list: this.list, cut: this.cut, mix: this.mix };
        this.impRest = this.impRest || {
            list: this.dataTex(4, 1, new Float32Array([0, 0, 0, 1])),
            cut: this.dataTex(4, 1, new Float32Array(4)),
        };
        this.impRest.trees = this.dataTex(4, 2, new Float32Array([0, 0, 0, 0, 1, s, 0, 0]), this.impRest.trees);
        this.ensureSkel(sp.n_nodes, 1);
        this.list = this.impRest.list;
        this.cut = this.impRest.cut;
        this.mix = null;
        const qw = sp.qw.slice(); // the pass zeroes the weights of a page at rest
        this.poseSkeletons([{ s, base: 0, n: 1 }]);
        sp.qw.set(qw);
        Object.assign(this, keep);
    }

    // One impostor texture of sp (posed at rest in row 0, restPose): its wood, and its
    // leaves too when withLeaves, from −y, orthographic over quad q, on a clear
    // transparent background, unfogged and unwet; mipmapped.
    impostorDraw(sp, q, withLeaves) {
        const gl = this.gl, h = sp.height, dist = 4 * (h + sp.crown_r) + 10;
        const tex = gl.createTexture(), fbo = gl.createFramebuffer(), depth = gl.createRenderbuffer();
        gl.activeTexture(gl.TEXTURE0 + RU.SCRATCH);
        gl.bindTexture(gl.TEXTURE_2D, tex);
        gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA8, IMP_W, IMP_H, 0, gl.RGBA, gl.UNSIGNED_BYTE, null);
        gl.bindRenderbuffer(gl.RENDERBUFFER, depth);
        gl.renderbufferStorage(gl.RENDERBUFFER, gl.DEPTH_COMPONENT24, IMP_W, IMP_H);
        gl.bindFramebuffer(gl.FRAMEBUFFER, fbo);
        gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, tex, 0);
        gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.DEPTH_ATTACHMENT, gl.RENDERBUFFER, depth);
        gl.viewport(0, 0, IMP_W, IMP_H);
        gl.clearColor(0, 0, 0, 0);
        gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
        gl.enable(gl.DEPTH_TEST);
        gl.depthFunc(gl.LESS);
        gl.depthMask(true);
        gl.disable(gl.BLEND);
        const keep = { viewproj: this.viewproj, eye: this.eye, subject_m: this.subject_m };
        this.eye = [0, -dist, 0.5 * h];
        this.viewproj = mul(ortho(-q.hw_m, q.hw_m, q.bottom_m - 0.5 * h, q.top_m - 0.5 * h, 0.1, 2 * dist), lookAt(this.eye, [0, 0, 0.5 * h], [0, 0, 1]));
        this.subject_m = 0;
        const calm = (p) => {
            this.setCommon(p, 0);
            gl.uniform1f(p.u.u_fog_dist, 1e9);
            if (p.u.u_storm) gl.uniform4f(p.u.u_storm, 0, 0, 0, 0);
            gl.uniform3f(p.u.u_wind_uniform, 0, 0, 0);
        };
        this.bindTex(RU.SKEL, gl.TEXTURE_2D, this.skelTex[0]);
        this.bindTex(RU.LIST, gl.TEXTURE_2D, this.impRest.list.tex);
        this.bindTex(RU.TREES, gl.TEXTURE_2D, this.impRest.trees.tex);
        this.bindTex(RU.NODE, gl.TEXTURE_2D, sp.node.tex);
        const pt = this.p.tree;
        calm(pt);
        gl.uniform3fv(pt.u.u_bark, sp.bark);
        gl.uniform1i(pt.u.u_base, 0);
        gl.bindVertexArray(sp.vao);
        if (sp.lod_count[0]) gl.drawElementsInstanced(gl.TRIANGLES, sp.lod_count[0], gl.UNSIGNED_INT, sp.lod_first[0] * 4, 1);
        if (withLeaves && sp.n_leaves) {
            const pl = this.p.leaf;
            calm(pl);
            gl.uniform1i(pl.u.u_base, 0);
            gl.uniform1i(pl.u.u_nleaves, sp.n_leaves);
            gl.uniform1i(pl.u.u_leaf_total, sp.n_leaves);
            gl.uniform1f(pl.u.u_leaf_grow, 1);
            gl.uniform1f(pl.u.u_aspect, LEAF_ASPECT[sp.leaf_shape]);
            gl.uniform2f(pl.u.u_crown, sp.crown_r, sp.height);
            gl.uniform3fv(pl.u.u_leafcol, sp.leaf_rgb);
            gl.uniform1i(pl.u.u_shape, sp.leaf_shape);
            this.bindTex(RU.LEAF, gl.TEXTURE_2D, sp.leaf.tex);
            gl.bindVertexArray(this.vaoEmpty);
            gl.drawArraysInstanced(gl.TRIANGLES, 0, 6, sp.n_leaves);
        }
        Object.assign(this, keep);
        gl.bindFramebuffer(gl.FRAMEBUFFER, null);
        gl.deleteFramebuffer(fbo);
        gl.deleteRenderbuffer(depth);
        gl.activeTexture(gl.TEXTURE0 + RU.SCRATCH);
        gl.bindTexture(gl.TEXTURE_2D, tex);
        gl.generateMipmap(gl.TEXTURE_2D);
        gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.LINEAR_MIPMAP_LINEAR);
        gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
        gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
        gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
        return tex;
    }

    // The frame's impostors (web/render_list.js drawList: imps, this.impList): one
    // instanced draw of two triangles a tree per species, q for the sway as the skeleton
    // pass reads it.
    drawImpostors(imps, t) {
        if (!imps.length) return;
        const gl = this.gl, ring = !this.floatQ, p = ring ? this.p.imp : this.p.impF;
        this.setCommon(p, t);
        this.bindTex(RU.LIST, gl.TEXTURE_2D, this.impList.tex);
        this.bindTex(RU.TREES, gl.TEXTURE_2D, this.trees.tex);
        gl.uniform1i(p.u.u_qstride, this.q_stride);
        gl.uniform1i(p.u.u_qtrees, Math.min(this.n_trees, this.q_trees));
        if (ring) {
            this.bindTex(RU.Q, gl.TEXTURE_2D_ARRAY, this.qring.tex);
            gl.uniform4iv(p.u.u_qlayer, this.mix ? this.qlayer : [0, 0, 0, 0]);
        } else {
            this.bindTex(RU.Q, gl.TEXTURE_2D, this.q.tex);
        }
        gl.bindVertexArray(this.vaoEmpty);
        for (const g of imps) {
            const sp = this.species[g.s];
            gl.uniform3fv(p.u.u_bsize, sp.bsize);
            gl.uniform3fv(p.u.u_sway, sp.sway.c);
            gl.uniform1f(p.u.u_zc, sp.sway.z_c_m);
            gl.uniform2fv(p.u.u_imp_ab, sp.sway.ab);
            if (ring) {
                if (!this.mix) sp.qw.fill(0); // at rest
                gl.uniform4fv(p.u.u_qw, sp.qw.subarray(0, 4 * sp.sway.c.length / 3));
            }
            gl.uniform1i(p.u.u_base, g.base);
            this.bindTex(RU.IMP, gl.TEXTURE_2D, sp.imp);
            this.bindTex(RU.IMP_WOOD, gl.TEXTURE_2D, sp.impWood);
            gl.drawArraysInstanced(gl.TRIANGLES, 0, 6, g.n);
        }
    }
}
