// Benchmark of the browser client's culling, levels and draw list (prints JSON; not a
// test): RendererList.drawList (web/render_list.js) under Node on the 2 km landscape of
// 100,000 trees (tests/web/landscape_scene.mjs), from each of its cameras, the camera
// moving a little each frame (0.4 m, 0.3 m sideways) so that the hysteresis and the
// budget's scale run as they do in a page. Per camera: trees in view (the first frame's),
// trees drawn, impostors, skeleton rows, triangles of the passes, draws, and the frames'
// stats.cull_ms: the first frame's, then median and p95 of --frames frames (100) after
// --warmup frames (30: a page's first half second, while V8 compiles the loops); the load
// average at the start and end (2 shared cores: compare runs at like loads).
// --tree-by-tree: no cell listed whole (RendererList.listWhole false), every tree in view
// through the gather, levels and draw list one by one.
//   node tests/web/bench_cull.mjs [--frames N] [--warmup N] [--tree-by-tree]
import os from 'node:os';
import { landscape, CAMERAS, viewProj } from './landscape_scene.mjs';
import { IMP_TRIANGLES } from '../../web/render_list.js';

const a = process.argv.slice(2);
const opt = (k, d) => (a.includes(k) ? Number(a[a.indexOf(k) + 1]) : d);
const frames = opt('--frames', 100), warmup = opt('--warmup', 30);
const load0 = os.loadavg();
const { r, species } = landscape();
if (a.includes('--tree-by-tree')) r.listWhole = false;
const out = { frames, warmup, tree_by_tree: r.listWhole === false, load_start: load0.map((v) => +v.toFixed(2)), cameras: [] };
const pct = (s, p) => s[Math.min(s.length - 1, Math.floor(p * s.length))];
for (const [name, eye0, target0] of CAMERAS) {
    const ms = [];
    let first = null;
    for (let k = 0; k < warmup + frames; k++) {
        const off = [0.4 * k, 0.3 * k, 0], eye = eye0.map((v, j) => v + off[j]);
        r.viewproj = viewProj(eye, target0.map((v, j) => v + off[j]));
        const list = r.drawList({ eye }, null);
        ms.push(r.stats.cull_ms);
        if (k) continue;
        let tris = 0, draws = 8;
        for (const g of list.groups) {
            const sp = species[g.s], lvl = r.leafLevels(sp);
            draws += 2 + g.bark.length + g.leaves.length;
            for (const [, n, m] of g.bark) tris += n * sp.lod_count[m] / 3;
            for (const [, n, l] of g.leaves) tris += n * 2 * lvl[l].n;
        }
        for (const g of list.imps) {
            draws++;
            tris += IMP_TRIANGLES * g.n;
        }
        const st = r.stats;
        const whole = r.grid.out.whole || { n: 0, trees: 0 };
        first = { camera: name, in_view: r.grid.out.n + whole.trees, listed_whole: whole.trees, cells_whole: whole.n, drawn: st.trees_drawn, impostors: st.impostors,
            rows: list.rows, levels: st.levels, triangles: tris, draws, scale: +st.lod_scale.toFixed(4) };
    }
    const rest = ms.slice(warmup).sort((x, y) => x - y);
    out.cameras.push({ ...first, cull_ms: { first: +ms[0].toFixed(3), median: +pct(rest, 0.5).toFixed(3), p95: +pct(rest, 0.95).toFixed(3) } });
}
out.load_end = os.loadavg().map((v) => +v.toFixed(2));
console.log(JSON.stringify(out));
