// A far tree's impostor (web/render_imp.js): its quad's extent in the tree frame and how
// it sways. The impostor is the species at rest; it moves as its crown does in the tree's
// lowest modes (Diener 2008 eq. 1: a node's displacement is Σ_k φ_k q_k), the crown taken
// as the leaves' mean node, and the quad bent by height below and above it. The native
// client draws the same formula, so the two pictures of a far tree agree.
import { LOD_IMPOSTOR_MODES } from './lod_policy.js';

// A cap on the height factor (z / z_c)²: the quad's top stands up to twice the crown's
// height, where the crown's own sway would overshoot what its branches do.
export const IMP_SWAY_MAX = 4;

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
// z_c_m }.
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
    return { c, z_c_m: z / total };
}

// The offset [m, tree frame, before the tree's yaw and scale] of the quad's point at height
// z_m of a tree whose modes stand at q (q[k], k < LOD_IMPOSTOR_MODES): min((max(z, 0) /
// z_c)², IMP_SWAY_MAX) Σ_k q_k c_k. The GLSL twin is web/imp_shader.js imp_sway.
export function swayOffset(sway, q, z_m, out = [0, 0, 0]) {
    const r = Math.max(z_m, 0) / Math.max(sway.z_c_m, 1e-3), f = Math.min(r * r, IMP_SWAY_MAX);
    for (let d = 0; d < 3; d++) {
        let s = 0;
        for (let k = 0; k < LOD_IMPOSTOR_MODES; k++) s += (q[k] || 0) * sway.c[3 * k + d];
        out[d] = f * s;
    }
    return out;
}
