// Every program of shaders/ compiles and links as GLSL ES 3.00 in headless Chromium
// (WebGL2, SwiftShader), from the files gale-server serves: one copy of the shaders.
import assert from 'node:assert/strict';
import path from 'node:path';
import { args, startServer, startBrowser } from './harness.mjs';

const [server, work] = args('usage: node test_web_shaders.mjs GALE_SERVER WORK_DIR');
const srv = await startServer(server, ['--cache', path.join(work, 'cache')]);
const ctx = await startBrowser(work);
try {
    const page = await ctx.newPage();
    await page.goto(`${srv.url}/`);
    const res = await page.evaluate(async () => {
        const { loadProgram, PROGRAMS } = await import('/web/shaders.js');
        const gl = document.createElement('canvas').getContext('webgl2');
        const out = {};
        for (const name of PROGRAMS) {
            try {
                const p = await loadProgram(gl, name);
                out[name] = Object.keys(p.u).length;
            } catch (e) {
                out[name] = e.message;
            }
        }
        return out;
    });
    for (const [name, r] of Object.entries(res)) {
        assert.equal(typeof r, 'number', `${name}: ${r}`);
    }
    console.log(JSON.stringify({ programs: res, ok: true }));
} finally {
    await ctx.close();
    await srv.stop();
}
