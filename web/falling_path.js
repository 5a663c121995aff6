// The one shared falling-leaf path of client/motion/falling_path.c (Vazquez 2008 sections
// 3.2-4.2) in the browser: the same falling-plate simulation in float32 arithmetic, every
// operation rounded as C rounds it (Math.fround of a double result is the correctly
// rounded float of +, -, ×, ÷ and sqrt), so the page draws the path gale-client draws;
// tests/web/test_damage_js.mjs holds it to the C (gale-web-damage-table) sample by sample.
// Then a leaf's variation from its seed, the evaluation with path reuse, and the landing
// time, as falling_path.c and shaders/fall.vert compute them.
import { hashMix32 } from './hash.js';

const f = Math.fround;
export const FALL_MAX_POINTS = 8;
export const FALL_MAX_JUMPS = 64;
const RHO_AIR = f(1.2), GRAV = f(9.81);

function hash01(x) {
    return f((hashMix32(x) >>> 8) * f(1 / 16777216));
}
function cross3(a, b) {
    return [f(f(a[1] * b[2]) - f(a[2] * b[1])), f(f(a[2] * b[0]) - f(a[0] * b[2])), f(f(a[0] * b[1]) - f(a[1] * b[0]))];
}
function dot3(a, b) {
    return f(f(f(a[0] * b[0]) + f(a[1] * b[1])) + f(a[2] * b[2]));
}
// v' = q v q* for a unit quaternion (x, y, z, w)
function quatRotate(q, v) {
    const u = [q[0], q[1], q[2]];
    const t = cross3(u, v).map((x) => f(x * 2));
    const c = cross3(u, t);
    return [0, 1, 2].map((k) => f(f(v[k] + f(q[3] * t[k])) + c[k]));
}
function quatMul(a, b) {
    return [
        f(f(f(f(a[3] * b[0]) + f(a[0] * b[3])) + f(a[1] * b[2])) - f(a[2] * b[1])),
        f(f(f(f(a[3] * b[1]) - f(a[0] * b[2])) + f(a[1] * b[3])) + f(a[2] * b[0])),
        f(f(f(f(a[3] * b[2]) + f(a[0] * b[1])) - f(a[1] * b[0])) + f(a[2] * b[3])),
        f(f(f(f(a[3] * b[3]) - f(a[0] * b[0])) - f(a[1] * b[1])) - f(a[2] * b[2])),
    ];
}
function quatNormalize(q) {
    const n = f(Math.sqrt(f(f(f(f(q[0] * q[0]) + f(q[1] * q[1])) + f(q[2] * q[2])) + f(q[3] * q[3]))));
    for (let k = 0; k < 4; k++) q[k] = f(q[k] / n);
}

// falling_path_build with the default desc (8 s, 8 cm, 0.6 g, seed 1), as gale-client
// builds it: { n, dt, pos: Float32Array(3n), quat: Float32Array(4n), start[], cont[],
// fall_speed }.
export function fallingPathBuild({ duration_s = 8, leaf_size_m = 0.08, leaf_mass_kg = 6e-4, seed = 1 } = {}) {
    const dur = f(duration_s), L = f(leaf_size_m), m = f(leaf_mass_kg);
    const sample_dt = f(1 / 60);
    const A = f(L * L), cn = f(1.2), ct = f(0.08);
    const r = f(0.5 * L);
    const i_add = f(f(f(f(f(f(f(8 / 3) * RHO_AIR) * r) * r) * r) * r) * r);
    const ip = f(f(f(m * L) * L) / 12), inertia = [f(ip + i_add), f(ip + i_add), f(f(f(m * L) * L) / 6)];
    const m_eff = f(m + f(f(f(f(f(f(8 / 3) * RHO_AIR) * r) * r) * r) * f(0.3)));
    let x = [0, 0, 0], v = [0, 0, 0], w = [0, 0, 0];
    const tilt = f(f(0.25) + f(f(0.2) * hash01(seed))), az = f(f(6.2831853) * hash01((Math.imul(seed, 7) + 3) >>> 0));
    const ht = f(f(0.5) * tilt);
    let q = [f(f(Math.sin(ht)) * f(Math.cos(az))), f(f(Math.sin(ht)) * f(Math.sin(az))), 0, f(Math.cos(ht))];
    const sub = 40, h = f(sample_dt / sub);
    const n = Math.trunc(f(dur / sample_dt)) + 1;
    const pos = new Float32Array(3 * n), quat = new Float32Array(4 * n);
    const ez = [0, 0, 1];
    const kn = f(f(f(f(-0.5) * RHO_AIR) * A) * cn), kt = f(f(f(0.5) * RHO_AIR) * A);
    const L5 = f(f(f(f(f(f(0.3) * RHO_AIR) * L) * L) * L) * L);
    for (let s = 0; s < n; s++) {
        pos.set(x, 3 * s);
        quat.set(q, 4 * s);
        for (let k = 0; k < sub; k++) {
            const nrm = quatRotate(q, ez);
            const speed = f(Math.sqrt(dot3(v, v)));
            const vn = dot3(v, nrm);
            const vt = [], fo = [], fn = [];
            for (let c = 0; c < 3; c++) {
                vt[c] = f(v[c] - f(vn * nrm[c]));
                fn[c] = f(f(f(kn * speed) * vn) * nrm[c]);
                fo[c] = f(fn[c] - f(f(f(f(kt * ct) * speed)) * vt[c]));
            }
            fo[2] = f(fo[2] - f(m * GRAV));
            const vtl = f(Math.sqrt(dot3(vt, vt)));
            let torque = [0, 0, 0];
            if (vtl > f(1e-6) && speed > f(1e-6)) {
                const sin_a = f(Math.abs(vn) / speed);
                const e = f(f(f(0.25) * L) * f(1 - sin_a));
                const rcp = [f(f(e * vt[0]) / vtl), f(f(e * vt[1]) / vtl), f(f(e * vt[2]) / vtl)];
                torque = cross3(rcp, fn);
            }
            const wl = f(Math.sqrt(dot3(w, w)));
            for (let c = 0; c < 3; c++) {
                // C's `a -= b + c`: a - (b + c)
                torque[c] = f(torque[c] - f(f(f(f(L5 * L) * wl) * w[c]) + f(f(2e-8) * w[c])));
            }
            const qi = [-q[0], -q[1], -q[2], q[3]];
            const tb = quatRotate(qi, torque);
            let wb = quatRotate(qi, w);
            const iw = [0, 1, 2].map((c) => f(inertia[c] * wb[c]));
            const gyro = cross3(wb, iw);
            wb = wb.map((wc, c) => f(wc + f(f(h * f(tb[c] - gyro[c])) / inertia[c])));
            w = quatRotate(q, wb);
            for (let c = 0; c < 3; c++) {
                v[c] = f(v[c] + f(f(h * fo[c]) / m_eff));
                x[c] = f(x[c] + f(h * v[c]));
            }
            const dq = quatMul([w[0], w[1], w[2], 0], q);
            for (let c = 0; c < 4; c++) q[c] = f(q[c] + f(f(f(0.5) * h) * dq[c]));
            quatNormalize(q);
        }
        if (!Number.isFinite(x[0] + x[1] + x[2] + q[3])) throw new Error(`falling_path: simulation diverged at ${(s * sample_dt).toFixed(2)} s`);
    }
    const P = (s) => pos.subarray(3 * s, 3 * s + 3), Q = (s) => quat.subarray(4 * s, 4 * s + 4);
    for (let s = 1; s < n; s++) {
        const a = Q(s), b = Q(s - 1);
        if (f(dot3(a, b) + f(a[3] * b[3])) < 0) for (let c = 0; c < 4; c++) a[c] = -a[c];
    }
    const fall_speed = f(-pos[3 * (n - 1) + 2] / f((n - 1) * sample_dt));
    if (!(fall_speed > f(0.05))) throw new Error(`falling_path: plate does not fall (${fall_speed} m/s)`);
    const start = [0];
    for (let s = 8; s < Math.trunc(n / 2) && start.length < FALL_MAX_POINTS; s++) {
        const up = quatRotate(Q(s), ez);
        const dv = [0, 1, 2].map((c) => f(f(pos[3 * (s + 1) + c] - pos[3 * s + c]) / sample_dt));
        const sp = f(Math.sqrt(dot3(dv, dv)));
        if (Math.abs(up[2]) > f(0.9) && sp < f(f(f(0.8) * fall_speed) + f(0.3)) && s - start[start.length - 1] >= 12) start.push(s);
    }
    const score = new Float64Array(n);
    const ve = [0, 1, 2].map((c) => f(pos[3 * (n - 1) + c] - pos[3 * (n - 2) + c]));
    const vel = f(f(Math.sqrt(dot3(ve, ve))) + f(1e-6));
    for (let s = 0; s < n; s++) {
        score[s] = Infinity;
        if (s < Math.trunc(n / 6) || s > Math.trunc((n * 3) / 4)) continue;
        const dv = [0, 1, 2].map((c) => f(f(pos[3 * s + c] - pos[3 * (s - 1) + c]) - ve[c]));
        const a = Q(s), b = Q(n - 1);
        const qd = Math.abs(f(dot3(a, b) + f(a[3] * b[3])));
        score[s] = f(f(f(Math.sqrt(dot3(dv, dv))) / vel) + f(2 * f(1 - qd)));
    }
    const cont = [];
    while (cont.length < 4) {
        let best = 0, bs = Infinity;
        for (let s = 0; s < n; s++) if (score[s] < bs) { bs = score[s]; best = s; }
        if (!Number.isFinite(bs)) break;
        cont.push(best);
        for (let s = best > 10 ? best - 10 : 0; s < n && s <= best + 10; s++) score[s] = Infinity;
    }
    if (!cont.length) throw new Error('falling_path: no continuity point');
    return { n, dt: sample_dt, pos, quat, start, cont, fall_speed };
}

// falling_var_from_seed: a leaf's variation of the shared path (section 4.1).
export function fallingVar(p, seed) {
    const h = hashMix32((seed ^ 0x9e3779b9) >>> 0);
    return { start: p.start[h % p.start.length], yaw: f(f(6.2831853) * hash01((h + 1) >>> 0)),
        sx: f(1 + f(2 * hash01((h + 2) >>> 0))), sy: f(1 + f(2 * hash01((h + 3) >>> 0))), seed: h };
}

// falling_path_eval: displacement [m] from the release point at tau [s] after release.
export function fallingPathEval(p, v, tau) {
    let fi = f(v.start + f((tau > 0 ? f(tau) : 0) / p.dt));
    const P = (i, k) => p.pos[3 * i + k];
    const off = [-P(v.start, 0), -P(v.start, 1), -P(v.start, 2)];
    const last = p.n - 1;
    for (let j = 0; fi >= last && j < FALL_MAX_JUMPS; j++) {
        const c = p.cont[hashMix32((v.seed + j) >>> 0) % p.cont.length];
        for (let k = 0; k < 3; k++) off[k] = f(off[k] + f(P(p.n - 1, k) - P(c - 1, k)));
        fi = f(f(fi - last) + (c - 1));
    }
    if (fi > last) fi = last;
    const i0 = Math.trunc(fi), i1 = i0 + 1 < p.n ? i0 + 1 : i0, t = f(fi - i0);
    const d = [0, 1, 2].map((k) => f(f(off[k] + P(i0, k)) + f(t * f(P(i1, k) - P(i0, k)))));
    const cy = f(Math.cos(v.yaw)), sy = f(Math.sin(v.yaw));
    const hx = f(d[0] * v.sx), hy = f(d[1] * v.sy);
    return [f(f(cy * hx) - f(sy * hy)), f(f(sy * hx) + f(cy * hy)), d[2]];
}

// falling_path_land_time: when a leaf released h0 [m] above the ground reaches it.
export function fallingPathLandTime(p, v, h0, max_s) {
    let prev_t = 0, prev_z = f(h0);
    const step = f(2 * p.dt);
    for (let t = step; t <= max_s; t = f(t + step)) {
        const z = f(f(h0) + fallingPathEval(p, v, t)[2]);
        if (z <= 0) return f(prev_t + f(f(step * prev_z) / f(prev_z - z)));
        prev_t = t;
        prev_z = z;
    }
    return f(max_s);
}
