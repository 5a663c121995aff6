// The viewer page against a real gale-server (the 7-tree clearing): snapshots decoded with
// zero errors and drawn; then one still with the trees and one without, and each tree's
// crown (the centroid of its leaves at rest) must change the picture where an independent
// projection of the scene (the welcome's instances, the page's camera, a pinhole model
// written here) puts it, and nothing may
// change away from every tree.
import assert from 'node:assert/strict';
import { writeFileSync } from 'node:fs';
import path from 'node:path';
import { args, startServer, startBrowser, waitFor, projector } from './harness.mjs';

const [server, work, config] = args('usage: node test_web_viewer.mjs GALE_SERVER WORK_DIR SCENE.json');
const srv = await startServer(server, ['--cache', path.join(work, '..', 'cache'), '--config', config]);
const ctx = await startBrowser(work, { width: 640, height: 480 });
try {
    const page = await ctx.newPage();
    await page.goto(`${srv.url}/`);
    await waitFor(page, () => window.gale && window.gale.framesDrawn >= 5 && window.gale.conn.stats.frames >= 30, null, 120, 'five frames drawn');
    const st = await page.evaluate(() => ({ stats: window.gale.conn.stats, errors: window.gale.errors, inst: window.gale.welcome.instances,
        heights: window.gale.r.species.map((s) => [s.height, s.crown_r, s.crown_c]) }));
    assert.equal(st.stats.errors, 0, `decode errors: ${st.stats.lastError}`);
    assert.deepEqual(st.errors, []);
    assert.ok(st.stats.frames >= 30);
    await page.screenshot({ path: path.join(work, 'viewer.png') });
    const bare = await page.evaluate(() => window.gale.still(false));
    const full = await page.evaluate(() => window.gale.still(true));
    const a = Buffer.from(bare.pixels, 'base64'), b = Buffer.from(full.pixels, 'base64');
    const { w, h, cam } = full;
    const project = projector(cam, w, h), fy = project.fy;
    const changed = (x, y) => {
        const i = 4 * (y * w + x);
        return Math.abs(a[i] - b[i]) + Math.abs(a[i + 1] - b[i + 1]) + Math.abs(a[i + 2] - b[i + 2]) > 24;
    };
    const boxes = [];
    const crowns = [];
    for (const [sp, x, y, z, yaw, scale] of st.inst) {
        const [hgt, cr, cc] = st.heights[sp];
        const base = project([x, y, z]), top = project([x, y, z + hgt * scale]);
        // the crown's centroid (its leaves at rest, tree frame) turned by yaw, scaled, placed
        const cy = Math.cos(yaw), sy = Math.sin(yaw);
        const centre = project([x + scale * (cy * cc[0] - sy * cc[1]), y + scale * (sy * cc[0] + cy * cc[1]), z + scale * cc[2]]);
        const rpx = (cr * scale * fy * h / 2) / centre[2];
        boxes.push([Math.min(base[0], top[0]) - rpx, Math.max(base[0], top[0]) + rpx, base[1] - 4, top[1] + 4]);
        if (centre[0] < 8 || centre[0] > w - 8 || centre[1] < 8 || centre[1] > h - 8) continue;
        // the crown: a window a third of its radius across about its centre
        const k = Math.max(2, Math.round(rpx / 3));
        let n = 0, c = 0;
        for (let dy = -k; dy <= k; dy++) for (let dx = -k; dx <= k; dx++) {
            const px = Math.round(centre[0] + dx), py = Math.round(centre[1] + dy);
            if (px < 0 || py < 0 || px >= w || py >= h) continue;
            n++;
            c += changed(px, py);
        }
        crowns.push({ at: centre.slice(0, 2).map(Math.round), radius_px: Math.round(rpx), changed: +(c / n).toFixed(2) });
    }
    let outside = 0, total = 0;
    for (let y = 0; y < h; y++) for (let x = 0; x < w; x++) {
        if (boxes.some(([x0, x1, y0, y1]) => x >= x0 && x <= x1 && y >= y0 && y <= y1)) continue;
        total++;
        outside += changed(x, y);
    }
    writeFileSync(path.join(work, 'crowns.json'), JSON.stringify({ crowns, outside, total }, null, 1));
    assert.ok(crowns.length >= 4, `expected at least 4 crowns in the picture, got ${crowns.length}`);
    for (const c of crowns) assert.ok(c.changed >= 0.25, `crown at ${c.at}: ${c.changed} of its window changed (expected >= 0.25)`);
    assert.ok(outside <= 0.002 * total, `${outside} of ${total} pixels away from every tree changed`);
    assert.deepEqual(ctx.errors, []);
    console.log(JSON.stringify({ frames: st.stats.frames, bytes: st.stats.bytes, crowns, outside_changed: outside, outside_px: total, ok: true }));
} finally {
    await ctx.close();
    await srv.stop();
}
