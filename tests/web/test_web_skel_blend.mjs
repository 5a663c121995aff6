// The browser's skeleton pass, which blends up to four snapshots' quantised values itself
// (shaders/skel.frag GALE_Q_RING, web/render_skel.js setMix), against the same pass fed q the
// native client's way (dequantised per snapshot, blended on the CPU in double, uploaded as
// floats: client/app/client_stream.c, client/playout/jitter.c), on a real gale-server's gusty clearing:
// at a time between two snapshots with a neighbour on each side, every drawn node stands
// within 1e-5 m of where the float path puts it (f32 weights and sums over positions of a
// few metres: a few units in the last place). The check can fail: the same nodes differ by
// more than 30 times that between the blend and its nearest snapshot held alone.
import assert from 'node:assert/strict';
import path from 'node:path';
import { args, startServer, startBrowser, waitFor } from './harness.mjs';

const [server, work, config, scenario] = args('usage: node test_web_skel_blend.mjs GALE_SERVER WORK_DIR SCENE.json SCENARIO.json');
const TOL_M = 1e-5;
const srv = await startServer(server, ['--cache', path.join(work, '..', 'cache'), '--config', config, '--scenario', scenario]);
const ctx = await startBrowser(work, { width: 320, height: 240 });
try {
    const page = await ctx.newPage();
    await page.goto(`${srv.url}/`);
    await waitFor(page, () => window.gale && window.gale.framesDrawn >= 3 && window.gale.jitter.snaps.length >= 6, null, 120, 'three frames drawn, six snapshots held');
    const res = await page.evaluate(async () => {
        const g = window.gale, r = g.r, gl = r.gl;
        g.frozen = true;
        await r.useFloatQ(true); // compiled before the snapshots are picked
        r.floatQ = false;
        // the newest four snapshots about evenly spaced (spacings within a factor 2: the
        // weights stay near Catmull-Rom's, where f32 sums are well conditioned)
        const snaps = g.jitter.snaps, even = (i) => {
            const d = [1, 2, 3].map((k) => snaps[i + k].t - snaps[i + k - 1].t);
            return Math.max(...d) <= 2 * Math.min(...d);
        };
        let i = snaps.length - 4;
        while (i > 0 && !even(i - 1)) i--;
        if (i <= 0) return { times: snaps.map((s) => s.t), errors: ['no four evenly spaced snapshots'] };
        const t = 0.5 * (snaps[i].t + snaps[i + 1].t);
        const w = g.jitter.weightsAt(t);
        const mix = { n: w.n, snaps: [...w.snaps], c: Float64Array.from(w.c) };
        const cam = g.camera();
        const read = () => {
            gl.bindFramebuffer(gl.FRAMEBUFFER, r.skelFbo[0]);
            const px = new Float32Array(r.skel_w * r.skel_h * 4);
            gl.readPixels(0, 0, r.skel_w, r.skel_h, gl.RGBA, gl.FLOAT, px);
            gl.bindFramebuffer(gl.FRAMEBUFFER, null);
            return px;
        };
        r.setMix(mix);
        r.draw(cam, 0, g.modes, t);
        const ring = read();
        // q the native client's way: each snapshot dequantised in f32, blended in double
        const inst = g.welcome.instances, S = g.stride, n = g.jitter.n_values;
        const cpu = (k0, k1) => {
            const q = new Float32Array(n);
            for (let v = 0; v < n; v++) {
                const m = v % S;
                let x = 0;
                for (let k = k0; k < k1; k++) {
                    const st = mix.snaps[k].meta.step[inst[(v / S) | 0][0]];
                    x += (k1 - k0 === 1 ? 1 : mix.c[k]) * Math.fround(mix.snaps[k].q[v] * (st[m] || 0));
                }
                q[v] = x;
            }
            return q;
        };
        r.floatQ = true;
        r.uploadQ(cpu(0, mix.n));
        r.draw(cam, 0, g.modes, t);
        const flt = read();
        r.uploadQ(cpu(0, 1)); // the nearest earlier snapshot alone
        r.draw(cam, 0, g.modes, t);
        const near = read();
        r.floatQ = false;
        let err = 0, sens = 0, nodes = 0;
        for (const grp of r.groups) {
            const nn = r.species[grp.s].n_nodes;
            for (let row = grp.base; row < grp.base + grp.n; row++) {
                for (let x = 0; x < nn; x++) {
                    const o = 4 * (row * r.skel_w + x);
                    for (let c = 0; c < 3; c++) {
                        err = Math.max(err, Math.abs(ring[o + c] - flt[o + c]));
                        sens = Math.max(sens, Math.abs(near[o + c] - flt[o + c]));
                    }
                    nodes++;
                }
            }
        }
        return { times: snaps.slice(i - 1, i + 3).map((s) => s.t), terms: mix.n, weights: [...mix.c].slice(0, mix.n), nodes, trees: r.stats.trees_drawn, max_err_m: err, blend_vs_nearest_m: sens,
            finite: ring.every(Number.isFinite), errors: g.errors };
    });
    console.log(JSON.stringify(res));
    assert.deepEqual(res.errors, []);
    assert.equal(res.terms, 4, 'a time with a neighbour on each side blends four snapshots');
    assert.ok(res.trees >= 5 && res.nodes > 100, `trees drawn (${res.trees}, ${res.nodes} nodes)`);
    assert.ok(res.finite, 'the skeleton is finite');
    assert.ok(res.max_err_m <= TOL_M, `the GPU's blend is ${res.max_err_m} m from the CPU's (tolerance ${TOL_M} m)`);
    assert.ok(res.blend_vs_nearest_m >= 30 * TOL_M, `the trees move between snapshots (${res.blend_vs_nearest_m} m): the check can fail`);
    console.log(JSON.stringify({ ok: true }));
} finally {
    await ctx.close();
    await srv.stop();
}
