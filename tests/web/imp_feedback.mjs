// The impostor's vertex stage (web/imp_shader.js) in a page against web/imp_sway.js: the
// quad's six corners of the `count` impostors of the last frame whose trees' q is largest,
// read back by transform feedback, beside the same corners on the CPU (the tree's q the
// blend of the frame shown, formed on the CPU). For test_web_large, on a frozen page
// (App.still).
export async function impostorSwayCheck(page, count = 5) {
    return page.evaluate(async (count) => {
        const g = window.gale, r = g.r, gl = r.gl;
        const { IMP_VERT } = await import('/web/imp_shader.js');
        const { PREAMBLE } = await import('/web/shaders.js');
        const { swayOffset } = await import('/web/imp_sway.js');
        const { RU } = await import('/web/render_data.js');
        const common = await (await fetch('/shaders/common.glsl')).text();
        // the frame's blend once more, uploaded, and each tree's q from it on the CPU as the
        // GPU forms it (snapshots that came since the frame may have taken a slot of the
        // ring); from here on nothing awaits, so no snapshot arrives to take a slot of the
        // ring between this blend and the draws that read it (under load one did, while
        // the imports above were awaited: corners 6-12 mm off a 12 cm sway)
        r.setMix(g.jitter.weights(g.shown_s));
        const mix = r.mix && { n: r.mix.n, snaps: r.mix.snaps.slice(), c: Float64Array.from(r.mix.c) };
        const qOf = (t) => {
            const w = mix, sp = r.species[r.inst[t][0]];
            if (!w || t >= r.q_trees) return [0, 0];
            return [0, 1].map((m) => {
                let v = 0;
                for (let k = 0; k < w.n; k++) v += sp.qw[4 * m + k] * w.snaps[k].q[t * r.q_stride + m];
                return v;
            });
        };
        const sh = (stage, src) => { const s = gl.createShader(stage); gl.shaderSource(s, src); gl.compileShader(s); if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s)); return s; };
        const p = gl.createProgram();
        gl.attachShader(p, sh(gl.VERTEX_SHADER, PREAMBLE + '#define GALE_VERT 1\n#define GALE_Q_RING 1\n' + common + '\n' + IMP_VERT));
        gl.attachShader(p, sh(gl.FRAGMENT_SHADER, PREAMBLE + 'out vec4 o; void main() { o = vec4(1.0); }'));
        gl.transformFeedbackVaryings(p, ['v_wpos'], gl.INTERLEAVED_ATTRIBS);
        gl.linkProgram(p);
        if (!gl.getProgramParameter(p, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(p));
        const u = {};
        for (let i = 0; i < gl.getProgramParameter(p, gl.ACTIVE_UNIFORMS); i++) { const info = gl.getActiveUniform(p, i); u[info.name.replace(/\[0\]$/, '')] = gl.getUniformLocation(p, info.name); }
        const prog = { id: p, u };
        r.bindSamplers(prog);
        // the impostors of the last frame with the largest q
        const out = [];
        const ni = r.stats.impostors, cand = [];
        for (let e = 0; e < ni; e += Math.max(1, Math.floor(ni / 400))) {
            const t = r.impData[4 * e], q = qOf(t);
            cand.push([Math.hypot(q[0], q[1]), t, q]);
        }
        cand.sort((a, b) => b[0] - a[0]);
        const tfb = gl.createTransformFeedback(), buf = gl.createBuffer();
        for (const [, t, q] of cand.slice(0, count)) {
            const row = r.inst[t], sp = r.species[row[0]], sc = row[5] > 0 ? row[5] : 1;
            r.setCommon(prog, 0);
            const list = r.dataTex(4, 1, new Float32Array([t, 1, 0, 1]));
            r.bindTex(RU.LIST, gl.TEXTURE_2D, list.tex);
            r.bindTex(RU.TREES, gl.TEXTURE_2D, r.trees.tex);
            r.bindTex(RU.Q, gl.TEXTURE_2D_ARRAY, r.qring.tex);
            gl.uniform4iv(u.u_qlayer, r.mix ? r.qlayer : [0, 0, 0, 0]);
            gl.uniform1i(u.u_qstride, r.q_stride);
            gl.uniform1i(u.u_qtrees, Math.min(r.n_trees, r.q_trees));
            gl.uniform3fv(u.u_bsize, sp.bsize);
            gl.uniform3fv(u.u_sway, sp.sway.c);
            gl.uniform1f(u.u_zc, sp.sway.z_c_m);
            gl.uniform2fv(u.u_imp_ab, sp.sway.ab);
            gl.uniform4fv(u.u_qw, sp.qw.subarray(0, 8));
            gl.uniform1i(u.u_base, 0);
            gl.bindBuffer(gl.TRANSFORM_FEEDBACK_BUFFER, buf);
            gl.bufferData(gl.TRANSFORM_FEEDBACK_BUFFER, 6 * 12, gl.STREAM_READ);
            gl.bindTransformFeedback(gl.TRANSFORM_FEEDBACK, tfb);
            gl.bindBufferBase(gl.TRANSFORM_FEEDBACK_BUFFER, 0, buf);
            gl.enable(gl.RASTERIZER_DISCARD);
            gl.bindVertexArray(r.vaoEmpty);
            gl.beginTransformFeedback(gl.TRIANGLES);
            gl.drawArraysInstanced(gl.TRIANGLES, 0, 6, 1);
            gl.endTransformFeedback();
            gl.disable(gl.RASTERIZER_DISCARD);
            gl.bindBufferBase(gl.TRANSFORM_FEEDBACK_BUFFER, 0, null);
            gl.bindTransformFeedback(gl.TRANSFORM_FEEDBACK, null);
            const got = new Float32Array(18);
            gl.bindBuffer(gl.TRANSFORM_FEEDBACK_BUFFER, buf);
            gl.getBufferSubData(gl.TRANSFORM_FEEDBACK_BUFFER, 0, got);
            // the CPU's
            const eye = r.eye, fx0 = eye[0] - row[1] + 1e-6, fy0 = eye[1] - row[2], fl = Math.hypot(fx0, fy0), right = [-fy0 / fl, fx0 / fl];
            let maxErr = 0, maxSway = 0;
            for (let id = 0; id < 6; id++) {
                const s = (id === 1 || id === 2 || id === 4) ? 1 : 0, tt = (id === 2 || id === 4 || id === 5) ? 1 : 0;
                const z = sp.bsize[2] + tt * sp.bsize[1], o = swayOffset(sp.sway, q, z), c = Math.cos(row[4]), sn = Math.sin(row[4]);
                const ow = [c * o[0] - sn * o[1], sn * o[0] + c * o[1], o[2]];
                const want = [row[1] + sc * (right[0] * (2 * s - 1) * sp.bsize[0] + ow[0]), row[2] + sc * (right[1] * (2 * s - 1) * sp.bsize[0] + ow[1]), row[3] + sc * (z + ow[2])];
                for (let k = 0; k < 3; k++) maxErr = Math.max(maxErr, Math.abs(got[3 * id + k] - want[k]));
                maxSway = Math.max(maxSway, sc * Math.hypot(...o));
            }
            out.push({ tree: t, q, max_err_m: maxErr, max_sway_m: maxSway });
        }
        return out;
    }, count);
}
