// The page's frame-time governor (web/governor.js) in headless chromium with SwiftShader on
// the clearing: a software renderer starts 3 steps down; with a target no frame can meet
// (?governor=1) it steps down to the last step, the canvas drawn at half its size and the
// HUD saying "detail −6"; with one every frame meets (?governor=100000) it steps back up
// to full detail, the canvas at its full size and the HUD without the step; without the
// parameter, under automation, it is off.
import assert from 'node:assert/strict';
import path from 'node:path';
import { args, startServer, startBrowser, waitFor } from './harness.mjs';

const [server, work, config] = args('usage: node test_web_governor.mjs GALE_SERVER WORK_DIR SCENE.json');
const srv = await startServer(server, ['--cache', path.join(work, '..', 'cache'), '--config', config]);
const ctx = await startBrowser(work, { width: 640, height: 480 });
const gov = () => {
    const s = window.gale.lodStats().governor, c = document.querySelector('canvas');
    return { ...s, width: c.width, client: c.clientWidth, hud: document.getElementById('hud').textContent };
};
try {
    const page = await ctx.newPage();
    await page.goto(`${srv.url}/?governor=1`);
    await waitFor(page, () => window.gale && window.gale.framesDrawn >= 1, null, 120, 'a frame drawn');
    const first = await page.evaluate(gov);
    assert.match(first.renderer, /SwiftShader|llvmpipe/, 'a software renderer');
    assert.ok(first.step >= 3, `a software renderer starts at step 3, got ${first.step}`);
    await waitFor(page, () => window.gale.lodStats().governor.step === 6, null, 120, 'the last step');
    const low = await page.evaluate(gov);
    assert.equal(low.res_scale, 0.5);
    assert.ok(Math.abs(low.width - 0.5 * low.client) <= 1, `canvas ${low.width} px for ${low.client} px`);
    assert.ok(Math.abs(low.lod_scale - Math.pow(0.75, 6)) < 1e-6);
    assert.match(low.hud, /detail \u22126/);
    await page.screenshot({ path: path.join(work, 'governor-low.png') });

    await page.goto(`${srv.url}/?governor=100000`);
    await waitFor(page, () => window.gale && window.gale.framesDrawn >= 1, null, 120, 'a frame drawn');
    await waitFor(page, () => window.gale.lodStats().governor.step === 0, null, 120, 'back to full detail');
    const up = await page.evaluate(gov);
    assert.equal(up.res_scale, 1);
    assert.ok(Math.abs(up.width - up.client) <= 1, `canvas ${up.width} px for ${up.client} px`);
    assert.doesNotMatch(up.hud, /detail/);

    await page.goto(`${srv.url}/`);
    await waitFor(page, () => window.gale && window.gale.framesDrawn >= 1, null, 120, 'a frame drawn');
    const off = await page.evaluate(gov);
    assert.equal(off.target_ms, 0, 'off under automation');
    assert.equal(off.step, 0);
    console.log(`governor: started at step ${first.step}, down to 6 (canvas ${low.width}/${low.client} px), up to 0, off by default under automation`);
} finally {
    await ctx.close();
    await srv.stop();
}
