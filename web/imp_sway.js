// A far tree's impostor (web/render_imp.js): its quad's extent in the tree frame and how
// it sways. The impostor is the species at rest; it moves as its crown does in the tree's
// lowest modes (Diener 2008 eq. 1: a node's displacement is Σ_k φ_k q_k), the crown taken
// as the leaves' mean node, q saturated as the pose's (q̃ = a atan(b q), eq. 16), and the
// quad leaning by height: its two rows can only shear, so the lean that puts the crown's
// middle where the modes put it. The native client (shaders/bill.vert, client/render/
// render_species.c impostor_sway) draws the same formula, so the two pictures agree.
import { LOD_IMPOSTOR_MODES } from './lod_policy.js';

// A cap on the height factor z / z_c (the quad's top stands above the crown's middle).
export const IMP_SWAY_MAX = 3;

// The impostor's quad [m, tree frame, z up, before the tree's scale] of a species height_m
// tall whose crown reaches crown_r_m from its stem (client/render/render_species.c
// species_impostor): half width, bottom, top.
export function impostorQuad(height_m, crown_r_m) {
    return { hw_m: crown_r_m * 1.05 + 0.2, bottom_m: -0.05 * height_m, top_m: 1.06 * height_m + 0.2 };
}

// The crown's sway of asset a (web/asset.js: rest, phi [mode][node][3], leaf_node): with
// w_j the leaves on node j, per mode k < LOD_IMPOSTOR_MODES the leaf-weighted mean of φ_k,
// c_k = Σ_j w_j φ_k(j) / Σ_j w_j [m per unit q], and the crown's height z_c = Σ_j w_j z_j
// / Σ_j w_j [m] (z_j the rest height of node j). A species without leaves takes its highest
// node alone. Returns { c: Float32Array(3 LOD_IMPOSTOR_MODES) (0 past the asset's modes),
// z_c_m, ab: Float32Array(2 LOD_IMPOSTOR_MODES) (a_k, b_k of q̃; b = 0: q̃ = q) }.
export function crownSway(a) {
    const nn = a.n_nodes, w = new Float64Array(nn);
    let total = 0;
    for (let l = 0; l < a.n_leaves; l++) {
        w[a.leaf_node[l]]++;
        total++;
    }
    if (!total) {
        let top = 0;
        for (let j = 1; j < nn; j++) if (a.rest[3 * j + 2] > a.rest[3 * top + 2]) top = j;
        w[top] = 1;
        total = 1;
    }
    let z = 0;
    for (let j = 0; j < nn; j++) z += w[j] * a.rest[3 * j + 2];
    const c = new Float32Array(3 * LOD_IMPOSTOR_MODES);
    for (let k = 0; k < Math.min(LOD_IMPOSTOR_MODES, a.n_modes); k++) {
        const acc = [0, 0, 0];
        for (let j = 0; j < nn; j++) {
            if (!w[j]) continue;
            for (let d = 0; d < 3; d++) acc[d] += w[j] * a.phi[(k * nn + j) * 3 + d];
        }
        for (let d = 0; d < 3; d++) c[3 * k + d] = acc[d] / total;
    }
    const ab = new Float32Array(2 * LOD_IMPOSTOR_MODES);
    for (let k = 0; k < Math.min(LOD_IMPOSTOR_MODES, a.n_modes); k++) {
        ab[2 * k] = a.corr_a ? a.corr_a[k] : 0;
        ab[2 * k + 1] = a.corr_b ? a.corr_b[k] : 0;
    }
    return { c, z_c_m: z / total, ab };
}

// The saturated coordinate q̃ = a atan(b q) of the pose (b = 0: q̃ = q).
export function saturated(a, b, q) {
    return b !== 0 ? a * Math.atan(b * q) : q;
}

// The offset [m, tree frame, before the tree's yaw and scale] of the quad's point at height
// z_m of a tree whose modes stand at q (q[k], k < LOD_IMPOSTOR_MODES): min(max(z, 0) / z_c,
// IMP_SWAY_MAX) Σ_k q̃_k c_k. The GLSL twin is web/imp_shader.js.
export function swayOffset(sway, q, z_m, out = [0, 0, 0]) {
    const f = Math.min(Math.max(z_m, 0) / Math.max(sway.z_c_m, 1e-3), IMP_SWAY_MAX);
    const ab = sway.ab || new Float32Array(2 * LOD_IMPOSTOR_MODES);
    for (let d = 0; d < 3; d++) {
        let s = 0;
        for (let k = 0; k < LOD_IMPOSTOR_MODES; k++) s += saturated(ab[2 * k], ab[2 * k + 1], q[k] || 0) * sway.c[3 * k + d];
        out[d] = f * s;
    }
    return out;
}
