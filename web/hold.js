// Which trees the page holds of a scene past what it can hold (web/WEB.md "Reduced view"):
// the ones nearest a point of the ground plane, as many as fit, and the circle about that
// point that holds exactly them, which the page asks the server to stream (PROTOCOL.md
// `view`, kind circle). The rule of gale-client's client/playout/hold.c, held to it by
// tests/web/test_hold_js.mjs: positions as the float32 gale-client reads from the welcome,
// the arithmetic in double in the same order, so both pick the same trees.

const VIEW_RADIUS_MIN_M = 0.001; // PROTOCOL.md: radius_m in [0.001, 1e6]
const VIEW_RADIUS_MAX_M = 1e6;

// The mean x and y of the welcome's rows [species, x, y, z, yaw, scale] (the scene's
// centre, where the default camera looks), summed in row order; [0, 0] for none.
export function holdCentre(rows) {
    let sx = 0, sy = 0;
    for (const r of rows) {
        sx += Math.fround(r[1]);
        sy += Math.fround(r[2]);
    }
    return rows.length ? [sx / rows.length, sy / rows.length] : [0, 0];
}

// The min(limit, rows) trees nearest (cx, cy) in 2D, a tie going to the lower index:
// { held (Uint32Array, ascending), cx, cy, n_held, radius_m (the farthest held), edge_m
// (midway to the nearest not held; radius_m when all are held) }.
export function holdNearest(rows, cx, cy, limit) {
    const n = rows.length, k = Math.max(0, Math.min(limit, n));
    const out = { held: new Uint32Array(k), cx, cy, n_held: k, radius_m: 0, edge_m: 0 };
    if (k === 0) return out;
    const d2 = new Float64Array(n), order = new Uint32Array(n);
    for (let t = 0; t < n; t++) {
        const dx = Math.fround(rows[t][1]) - cx, dy = Math.fround(rows[t][2]) - cy;
        d2[t] = dx * dx + dy * dy;
        order[t] = t;
    }
    order.sort((a, b) => d2[a] - d2[b] || a - b);
    out.held.set(order.subarray(0, k));
    out.held.sort();
    out.radius_m = Math.sqrt(d2[order[k - 1]]);
    out.edge_m = k < n ? 0.5 * (out.radius_m + Math.sqrt(d2[order[k]])) : out.radius_m;
    return out;
}

// The radius a circle view asks for so that the server, which widens a circle by the
// height of the scene's tallest tree (margin_m), streams the trees held and no others.
export function holdViewRadius(h, margin_m) {
    const r = h.edge_m - margin_m;
    return r > VIEW_RADIUS_MAX_M ? VIEW_RADIUS_MAX_M : r > VIEW_RADIUS_MIN_M ? r : VIEW_RADIUS_MIN_M;
}

// The view message's object for held circle h: a circle of holdViewRadius about its point
// (no lod_m: the trees held stream with all their modes; the limit bounds the stream).
export function holdView(h, margin_m) {
    return { kind: 'circle', x: h.cx, y: h.cy, radius_m: holdViewRadius(h, margin_m) };
}
