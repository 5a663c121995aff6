// A broken branch as tumbling debris, client/motion/debris_path.c in the browser (PROTOCOL.md
// "DAMAGE" BRANCH): a rigid piece that leaves the tree where it broke, falls under gravity
// with quadratic drag relative to the streamed wind (a = g + k |u - v| (u - v)), spins about
// an axis of its own, lands, settles flat, lies, then sinks away. Everything random comes
// from a hash of (tree, node) and the motion is integrated in fixed steps from the moment
// it broke, as in the C; tests/web/test_damage_js.mjs holds it to the C
// (gale-web-damage-table). Matrices column-major 3×3, r[3 col + row].
import { hashMix32 } from './hash.js';

export const DEBRIS = { DT_S: 1 / 120, SETTLE_S: 0.6, LIE_S: 45, SINK_S: 6, MAX_FALL_S: 30 };

function hash01(tree, node, k) {
    const h = hashMix32((hashMix32((Math.imul(tree, 0x9E3779B1) + k) >>> 0) ^ ((Math.imul(node, 0x85EBCA77) + 0x165667B1) >>> 0)) >>> 0);
    return (h >>> 8) / 16777216;
}

function matMul(a, b) {
    const t = new Array(9);
    for (let c = 0; c < 3; c++) for (let r = 0; r < 3; r++) t[3 * c + r] = a[r] * b[3 * c] + a[3 + r] * b[3 * c + 1] + a[6 + r] * b[3 * c + 2];
    return t;
}
function matVec(a, v) {
    return [0, 1, 2].map((r) => a[r] * v[0] + a[3 + r] * v[1] + a[6 + r] * v[2]);
}
// rotation by angle about unit axis k (Rodrigues)
function axisAngle(k, angle) {
    const c = Math.cos(angle), s = Math.sin(angle), t = 1 - c;
    return [c + t * k[0] * k[0], t * k[0] * k[1] + s * k[2], t * k[0] * k[2] - s * k[1],
        t * k[0] * k[1] - s * k[2], c + t * k[1] * k[1], t * k[1] * k[2] + s * k[0],
        t * k[0] * k[2] + s * k[1], t * k[1] * k[2] - s * k[0], c + t * k[2] * k[2]];
}

// shaders/common.glsl tree_frame: yaw about z, then tipped by fall towards azimuth az.
export function debrisFrameMatrix(yaw, fall, az) {
    const rz = [Math.cos(yaw), Math.sin(yaw), 0, -Math.sin(yaw), Math.cos(yaw), 0, 0, 0, 1];
    return matMul(axisAngle([-Math.sin(az), Math.cos(az), 0], fall), rz);
}

// Its inverse: { yaw, fall (0..π), az } of a rotation r.
export function debrisFrameAngles(r) {
    const z = [r[6], r[7], r[8]];
    const fall = Math.acos(Math.min(Math.max(z[2], -1), 1));
    const az = Math.hypot(z[0], z[1]) > 1e-6 ? Math.atan2(z[1], z[0]) : 0;
    const tip = axisAngle([-Math.sin(az), Math.cos(az), 0], fall);
    const x = [tip[0] * r[0] + tip[1] * r[1] + tip[2] * r[2], tip[3] * r[0] + tip[4] * r[1] + tip[5] * r[2]];
    return { yaw: Math.atan2(x[1], x[0]), fall, az };
}

export class DebrisPath {
    // The piece of (tree, node) from t0_s: centre c0 [m, world], orientation r0 (the tree's
    // frame then), restAxis its main axis in the tree frame, extent_m from its centre to its
    // farthest node [m, world].
    constructor(tree, node, t0_s, c0, r0, restAxis, extent_m) {
        this.tree = tree;
        this.node = node;
        this.t0_s = this.t_s = this.sim_s = t0_s;
        this.c = c0.slice();
        this.v = [0, 0, 0];
        this.r0 = r0.slice();
        const u = 2 * hash01(tree, node, 1) - 1, ph = 6.2831853 * hash01(tree, node, 2);
        const s = Math.sqrt(Math.max(1 - u * u, 0));
        this.spin_axis = [s * Math.cos(ph), s * Math.sin(ph), u];
        this.spin_rad_s = 1.2 + 2.3 * hash01(tree, node, 3);
        const vt = 9 + 6 * hash01(tree, node, 4); // terminal speed [m/s]: k = g / v_t²
        this.k_per_m = 9.81 / (vt * vt);
        const n = Math.hypot(...restAxis);
        this.rest_axis = n > 1e-9 ? restAxis.map((x) => x / n) : [1, 0, 0];
        this.lie_z_m = Math.min(Math.max(0.3 * extent_m, 0.15), 1.2);
        this.landed = false;
    }

    rotationFalling(t_s) {
        return matMul(axisAngle(this.spin_axis, this.spin_rad_s * (t_s - this.t0_s)), this.r0);
    }

    land() {
        this.landed = true;
        this.land_s = this.sim_s;
        this.v = [0, 0, 0];
        this.r_land = this.rotationFalling(this.sim_s);
        // lay the main axis flat: the shortest turn to its horizontal direction
        const a = matVec(this.r_land, this.rest_axis);
        let hn = Math.hypot(a[0], a[1]);
        const h = [a[0], a[1], 0];
        if (hn < 1e-4) {
            h[0] = 1;
            hn = 1;
        }
        h[0] /= hn;
        h[1] /= hn;
        const k = [a[1] * h[2] - a[2] * h[1], a[2] * h[0] - a[0] * h[2], a[0] * h[1] - a[1] * h[0]];
        const kn = Math.hypot(...k), d = a[0] * h[0] + a[1] * h[1] + a[2] * h[2];
        this.settle_rad = Math.atan2(kn, d);
        this.settle_axis = kn > 1e-6 ? k.map((x) => x / kn) : [0, 0, 1];
    }

    // Integrates up to t_s (never backwards); wind(p) the streamed wind [m/s] at p.
    advance(t_s, wind) {
        while (!this.landed && this.sim_s + DEBRIS.DT_S <= t_s) {
            const dt = DEBRIS.DT_S, u = wind ? wind(this.c) : [0, 0, 0];
            const rel = [u[0] - this.v[0], u[1] - this.v[1], u[2] - this.v[2]], rs = Math.hypot(...rel);
            for (let k = 0; k < 3; k++) {
                this.v[k] += dt * (this.k_per_m * rs * rel[k] - (k === 2 ? 9.81 : 0));
                this.c[k] += dt * this.v[k];
            }
            this.sim_s += DEBRIS.DT_S;
            if (this.c[2] <= this.lie_z_m || this.sim_s - this.t0_s >= DEBRIS.MAX_FALL_S) {
                this.c[2] = this.lie_z_m;
                this.land();
            }
        }
        if (t_s > this.t_s) this.t_s = t_s;
    }

    rotation() {
        if (!this.landed || this.t_s < this.land_s) return this.rotationFalling(this.landed ? this.land_s : this.t_s);
        let f = Math.min(Math.max((this.t_s - this.land_s) / DEBRIS.SETTLE_S, 0), 1);
        f = f * f * (3 - 2 * f);
        return matMul(axisAngle(this.settle_axis, f * this.settle_rad), this.r_land);
    }

    sink_m() {
        if (!this.landed) return 0;
        const s = (this.t_s - this.land_s - DEBRIS.LIE_S) / DEBRIS.SINK_S;
        return s > 0 ? s * (2 * this.lie_z_m + 2) : 0;
    }

    done() {
        return this.landed && this.t_s - this.land_s >= DEBRIS.LIE_S + DEBRIS.SINK_S;
    }
}
