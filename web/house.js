// House meshes of the browser client, as gale-client's (client/render/render_house.c): an
// obstacle box of the welcome ([min x, y, z, max x, y, z], metres, z up) as walls up to
// the eaves, gable ends and a pitched roof whose ridge runs along the longer side, in the
// vertex layout of shaders/house.vert. tests/web/test_house_js.mjs holds it to the C mesh.

export const HOUSE_FLOATS = 11; // position, normal, (u, v, wall height, half width), material
export const HOUSE_VERTS = 42;  // 14 triangles: two long walls, two gabled ends, two roof planes

// The HOUSE_VERTS vertices of box b written at out[o...]; returns the offset after them.
export function houseMesh(b, out, o = 0) {
    const lo = b.slice(0, 3), hi = b.slice(3, 6);
    const ia = hi[0] - lo[0] >= hi[1] - lo[1] ? 0 : 1, ib = 1 - ia;
    const a0 = lo[ia], a1 = hi[ia], b0 = lo[ib], b1 = hi[ib], z0 = lo[2], z1 = hi[2];
    const ca = 0.5 * (a0 + a1), cb = 0.5 * (b0 + b1);
    const half_a = 0.5 * (a1 - a0), half_b = 0.5 * (b1 - b0);
    // the roof rises 40 % of the height, at most a 40° pitch (tan 40° ≈ 0.84)
    const rh = Math.min(0.4 * (z1 - z0), 0.84 * half_b);
    const zw = z1 - rh;
    const vert = (a, bb, z, na, nb, nz, u, v, half_w, mat) => {
        out[o + ia] = a;
        out[o + ib] = bb;
        out[o + 2] = z;
        out[o + 3 + ia] = na;
        out[o + 3 + ib] = nb;
        out[o + 5] = nz;
        out[o + 6] = u;
        out[o + 7] = v;
        out[o + 8] = zw - z0;
        out[o + 9] = half_w;
        out[o + 10] = mat;
        o += HOUSE_FLOATS;
    };
    // long walls (normal -b, +b): u along a
    for (const s of [-1, 1]) {
        const bb = s < 0 ? b0 : b1;
        const q = [[a0, z0], [a1, z0], [a1, zw], [a0, zw]];
        for (const k of [0, 1, 2, 0, 2, 3]) vert(q[k][0], bb, q[k][1], 0, s, 0, q[k][0] - ca, q[k][1] - z0, half_a, 0);
    }
    // end walls (normal -a, +a) with their gables: u along b
    for (const s of [-1, 1]) {
        const a = s < 0 ? a0 : a1;
        const q = [[b0, z0], [b1, z0], [b1, zw], [b0, zw], [cb, z1]];
        for (const k of [0, 1, 2, 0, 2, 3, 3, 2, 4]) vert(a, q[k][0], q[k][1], s, 0, 0, q[k][0] - cb, q[k][1] - z0, half_b, 0);
    }
    // roof planes: from the eave at b0 or b1 up to the ridge; v along the slope
    const slope = Math.hypot(half_b, rh);
    const nb = slope > 0 ? rh / slope : 0, nz = slope > 0 ? half_b / slope : 1;
    for (const s of [-1, 1]) {
        const bb = s < 0 ? b0 : b1;
        const q = [[a0, bb, 0], [a1, bb, 0], [a1, cb, slope], [a0, cb, slope]];
        for (const k of [0, 1, 2, 0, 2, 3]) {
            vert(q[k][0], q[k][1], q[k][2] > 0 ? z1 : zw, 0, s * nb, nz, q[k][0] - ca, q[k][2], half_a, 1);
        }
    }
    return o;
}

// Every box's mesh in one array (HOUSE_VERTS × HOUSE_FLOATS floats a box).
export function housesMesh(boxes) {
    const out = new Float32Array(boxes.length * HOUSE_VERTS * HOUSE_FLOATS);
    let o = 0;
    for (const b of boxes) o = houseMesh(b, out, o);
    return out;
}
