// The welcome's houses in the browser (web/house.js, shaders/house.*) against a real
// gale-server (the clearing's one house): the viewer's orbit turned on the house, one still
// with the houses and one without (the same trees, the same instant); the house must change
// at least half the pixels inside the rectangle an independent pinhole projection of its
// box (roof included) gives, nothing beyond 3 px outside it, and what it draws is warm
// (plaster and tiles: red over blue) with both a roof and walls (tiles red well over green
// on 15-60 % of it: 35 % from this camera), as gale-client's colours.
import assert from 'node:assert/strict';
import path from 'node:path';
import { args, startServer, startBrowser, waitFor, projector } from './harness.mjs';

const [server, work, config] = args('usage: node test_web_houses.mjs GALE_SERVER WORK_DIR SCENE.json');
const srv = await startServer(server, ['--cache', path.join(work, '..', 'cache'), '--config', config]);
const ctx = await startBrowser(work, { width: 640, height: 480 });
try {
    const page = await ctx.newPage();
    await page.goto(`${srv.url}/`);
    await waitFor(page, () => window.gale && window.gale.framesDrawn >= 3, null, 120, 'three frames drawn');
    const boxes = await page.evaluate(() => window.gale.welcome.obstacles || []);
    assert.ok(boxes.length >= 1, 'the scene has a house');
    const b = boxes[0];
    const centre = [(b[0] + b[3]) / 2, (b[1] + b[4]) / 2, (b[2] + b[5]) / 2];
    const shots = await page.evaluate((c) => {
        const g = window.gale;
        Object.assign(g.cam, { target: c, distance: 38, yaw: 0.9, pitch: -0.25 });
        const full = g.still(true);
        g.r.hideHouses = true;
        const bare = g.still(true);
        g.r.hideHouses = false;
        g.frozen = false;
        return { full, bare };
    }, centre);
    await page.screenshot({ path: path.join(work, 'house.png') });
    const { w, h, cam } = shots.full;
    const a = Buffer.from(shots.bare.pixels, 'base64'), p = Buffer.from(shots.full.pixels, 'base64');
    const project = projector(cam, w, h);
    const pts = [];
    for (const x of [b[0], b[3]]) for (const y of [b[1], b[4]]) for (const z of [b[2], b[5]]) pts.push(project([x, y, z]));
    const [x0, x1] = [Math.min(...pts.map((q) => q[0])), Math.max(...pts.map((q) => q[0]))];
    const [y0, y1] = [Math.min(...pts.map((q) => q[1])), Math.max(...pts.map((q) => q[1]))];
    assert.ok(x0 > 0 && x1 < w && y0 > 0 && y1 < h, `the house lies inside the frame: ${[x0, x1, y0, y1]}`);
    let inside = 0, inN = 0, outside = 0, outN = 0, roof = 0;
    const warm = [0, 0, 0];
    for (let y = 0; y < h; y++) for (let x = 0; x < w; x++) {
        const i = 4 * (y * w + x);
        const ch = Math.abs(a[i] - p[i]) + Math.abs(a[i + 1] - p[i + 1]) + Math.abs(a[i + 2] - p[i + 2]) > 24;
        if (x >= x0 && x <= x1 && y >= y0 && y <= y1) {
            inN++;
            inside += ch;
            if (ch) {
                for (let k = 0; k < 3; k++) warm[k] += p[i + k];
                // tiles (0.52, 0.22, 0.15): red well over green; plaster (0.92, 0.82, 0.64) not
                if (p[i] > 1.5 * p[i + 1]) roof++;
            }
        } else if (x < x0 - 3 || x > x1 + 3 || y < y0 - 3 || y > y1 + 3) {
            outN++;
            outside += ch;
        }
    }
    const out = { rect_px: [x0, x1, y0, y1].map(Math.round), inside_changed: +(inside / inN).toFixed(3), outside_changed: outside,
        outside_px: outN, roof_share: +(roof / Math.max(1, inside)).toFixed(3), mean_rgb: warm.map((v) => Math.round(v / Math.max(1, inside))) };
    assert.ok(inside >= 0.5 * inN, `the house changed ${out.inside_changed} of its rectangle (expected >= 0.5)`);
    assert.ok(outside <= 0.001 * outN, `${outside} of ${outN} pixels away from the house changed`);
    assert.ok(out.mean_rgb[0] > out.mean_rgb[2] + 20, `the house's pixels are not warm: ${out.mean_rgb}`);
    assert.ok(out.roof_share >= 0.15 && out.roof_share <= 0.6, `roof ${out.roof_share} of the house's pixels: expected walls and a roof`);
    assert.deepEqual(ctx.errors, []);
    console.log(JSON.stringify({ ...out, ok: true }));
} finally {
    await ctx.close();
    await srv.stop();
}
