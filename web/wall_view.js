// A wall tile's view (client/wall/wall.c in JavaScript): the tile's corners from a wall file
// (configs/walls/README.md), the generalized perspective projection of its glass from the
// wall's eye (Kooima 2008, eqs. 1-10) and the wall's tour camera at a frame's instant.
// tests/web/test_wall_js.mjs holds these to gale-client's own (tests/web/wall_table.c)
// for every wall file of configs/walls/.
import { mul } from './view_math.js';

// near and far planes of every tile (client/app/client_frame.c's render_camera)
export const WALL_Z_NEAR_M = 0.3;
export const WALL_Z_FAR_M = 4500;

const sub = (a, b) => a.map((x, k) => x - b[k]);
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const unit = (a) => {
    const n = Math.hypot(...a);
    return n > 0 ? a.map((x) => x / n) : a;
};

// wall_offaxis: corners pa (bottom left), pb (bottom right), pc (top left) of the glass
// seen from pe; rot = M^T T (the wall frame into the screen's, translated by -pe), proj
// the frustum of the extents at the near plane (both column-major)
export function offaxis(pa, pb, pc, pe, n, f) {
    const vr = unit(sub(pb, pa)), vu = unit(sub(pc, pa)), vn = unit(cross(vr, vu)); // eqs. 1-3
    const va = sub(pa, pe), vb = sub(pb, pe), vc = sub(pc, pe); // eq. 5
    const d = -dot(vn, va), s = n / d; // eq. 6
    const l = dot(vr, va) * s, r = dot(vr, vb) * s, b = dot(vu, va) * s, t = dot(vu, vc) * s; // eqs. 7-10
    const proj = new Float32Array(16);
    proj[0] = 2 * n / (r - l);
    proj[5] = 2 * n / (t - b);
    proj[8] = (r + l) / (r - l);
    proj[9] = (t + b) / (t - b);
    proj[10] = -(f + n) / (f - n);
    proj[11] = -1;
    proj[14] = -2 * f * n / (f - n);
    const rot = new Float32Array(16);
    for (let k = 0; k < 3; k++) {
        rot[k * 4] = vr[k];
        rot[k * 4 + 1] = vu[k];
        rot[k * 4 + 2] = vn[k];
    }
    rot[12] = -dot(vr, pe);
    rot[13] = -dot(vu, pe);
    rot[14] = -dot(vn, pe);
    rot[15] = 1;
    return { rot, proj };
}

// wall_tile_corners: lower left, lower right, upper left of the visible area; the file's
// normal and up taken as unit vectors, as wall_parse stores them
export function tileCorners(t) {
    const up = unit(t.up), normal = unit(t.normal);
    const right = cross(up, normal), hw = 0.5 * t.size_m[0], hh = 0.5 * t.size_m[1];
    const at = (a, b) => t.centre_m.map((c, k) => c + a * right[k] + b * up[k]);
    return [at(-hw, -hh), at(hw, -hh), at(-hw, hh)];
}

// wall_tile_matrices: the tile's view for a camera whose world-to-camera matrix is camView
// (the camera stands at the wall's eye: view = rot · T(eye) · camView) and its projection
export function tileMatrices(wall, tile, camView, n = WALL_Z_NEAR_M, f = WALL_Z_FAR_M) {
    const [pa, pb, pc] = tileCorners(tile);
    const { rot, proj } = offaxis(pa, pb, pc, wall.eye_m, n, f);
    const toWall = new Float32Array([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, ...wall.eye_m, 1]);
    return { view: mul(rot, mul(toWall, camView)), proj };
}

// wall_tour_at: the tour's orbit camera at server time t_s (looped over the last stop's
// time, linear between stops)
export function tourAt(wall, t_s) {
    const s = wall.tour, n = s.length, t = t_s % s[n - 1].t_s;
    let i = 0;
    while (i + 2 < n && t >= s[i + 1].t_s) i++;
    const u = (t - s[i].t_s) / (s[i + 1].t_s - s[i].t_s);
    const lerp = (a, b) => a + u * (b - a);
    return { target_m: s[i].target_m.map((x, k) => lerp(x, s[i + 1].target_m[k])), distance_m: lerp(s[i].distance_m, s[i + 1].distance_m),
        yaw_deg: lerp(s[i].yaw_deg, s[i + 1].yaw_deg), pitch_deg: lerp(s[i].pitch_deg, s[i + 1].pitch_deg) };
}
