// A species on the GPU (client/render/render_species.c): its extent, stump and crown from the
// asset, its correction fields, nodes and leaves as data textures, and its bark mesh with
// its LODs. Renderer (web/render_gl.js) takes these methods as its own.

export const LEAF_ASPECT = [0.55, 0.16, 1.0]; // render_leaf_aspect, client/render/render_species.c

export class RendererSpecies {
    // One species (web/asset.js decodeAsset), at index i of the welcome's list.
    addSpecies(i, a) {
        const gl = this.gl, nn = a.n_nodes, nm = a.n_modes;
        if (nn < 2 || nn > 16384) throw new Error(`${a.name}: n_nodes ${nn} (2..16384)`);
        if (nm > 64) throw new Error(`${a.name}: n_modes ${nm} (0..64)`);
        const s = { n_nodes: nn, n_modes: nm, n_leaves: a.n_leaves, n_lods: a.n_lods, lod_first: a.lod_first,
            lod_count: a.lod_count, bark: a.bark_rgb, leaf_rgb: a.leaf_rgb, leaf_shape: a.leaf_shape };
        let h = 0, cr = 0;
        for (let k = 0; k < nn; k++) {
            h = Math.max(h, a.rest[3 * k + 2]);
            cr = Math.max(cr, Math.hypot(a.rest[3 * k], a.rest[3 * k + 1]) + a.radius[k]);
        }
        for (let l = 0; l < a.n_leaves; l++) {
            const j = a.leaf_node[l];
            const x = a.rest[3 * j] + a.leaf_offset[3 * l], y = a.rest[3 * j + 1] + a.leaf_offset[3 * l + 1];
            h = Math.max(h, a.rest[3 * j + 2] + a.leaf_offset[3 * l + 2] + a.leaf_size[l]);
            cr = Math.max(cr, Math.hypot(x, y) + a.leaf_size[l]);
        }
        s.height = h;
        s.crown_r = cr;
        // the stem at the base, for a snapped tree's stump: the root's radius, tapering as
        // towards its thickest child (client/render/render_species.c)
        s.stem_r_m = a.radius[0];
        s.stem_taper = 0;
        for (let k = 1, best = 0; k < nn; k++) {
            const dz = Math.fround(a.rest[3 * k + 2] - a.rest[2]);
            if (a.parent[k] === 0 && dz > 0.05 && (best === 0 || a.radius[k] > a.radius[best])) {
                best = k;
                s.stem_taper = Math.min(Math.fround(Math.fround(a.radius[k] - a.radius[0]) / dz), 0);
            }
        }
        s.a = a; // rest pose, pose fields and leaf slots for releasing a leaf (addFallingLeaf)
        // the leaves' centroid at rest [m, tree frame]: where the crown stands
        const c = [0, 0, 0];
        for (let l = 0; l < a.n_leaves; l++) {
            for (let k = 0; k < 3; k++) c[k] += (a.rest[3 * a.leaf_node[l] + k] + a.leaf_offset[3 * l + k]) / a.n_leaves;
        }
        s.crown_c = a.n_leaves ? c : [0, 0, 0.62 * h];
        s.ab = new Float32Array(128);
        s.qw = new Float32Array(256); // setMix: per mode, the weights of the blended snapshots
        for (let m = 0; m < nm; m++) {
            s.ab[2 * m] = a.corr_a[m];
            s.ab[2 * m + 1] = a.corr_b[m];
        }
        const vw = new Float32Array(nm * nn * 8);
        for (let m = 0; m < nm; m++) for (let k = 0; k < nn; k++) {
            const o = (m * nn + k) * 8, src = (m * nn + k) * 3;
            vw.set(a.corr_v.subarray(src, src + 3), o);
            vw.set(a.corr_w.subarray(src, src + 3), o + 4);
        }
        s.vw = this.dataTex(4, nm * nn * 2, vw);
        const node = new Float32Array(nn * 4);
        for (let k = 0; k < nn; k++) {
            node.set(a.rest.subarray(3 * k, 3 * k + 3), 4 * k);
            node[4 * k + 3] = a.parent[k];
        }
        s.node = this.dataTex(4, nn, node);
        const leaf = new Float32Array(Math.max(1, a.n_leaves) * 8);
        for (let l = 0; l < a.n_leaves; l++) {
            leaf.set(a.leaf_offset.subarray(3 * l, 3 * l + 3), 8 * l);
            leaf[8 * l + 3] = a.leaf_node[l];
            leaf.set(a.leaf_normal.subarray(3 * l, 3 * l + 3), 8 * l + 4);
            leaf[8 * l + 7] = a.leaf_size[l];
        }
        s.leaf = this.dataTex(4, Math.max(1, a.n_leaves) * 2, leaf);
        s.vao = gl.createVertexArray();
        gl.bindVertexArray(s.vao);
        const nv = a.n_verts;
        const vbo = gl.createBuffer();
        gl.bindBuffer(gl.ARRAY_BUFFER, vbo);
        gl.bufferData(gl.ARRAY_BUFFER, nv * 36 || 16, gl.STATIC_DRAW);
        gl.bufferSubData(gl.ARRAY_BUFFER, 0, a.mesh_pos);
        gl.bufferSubData(gl.ARRAY_BUFFER, nv * 12, a.mesh_normal);
        gl.bufferSubData(gl.ARRAY_BUFFER, nv * 24, a.mesh_bone);
        gl.bufferSubData(gl.ARRAY_BUFFER, nv * 32, a.mesh_weight);
        gl.enableVertexAttribArray(0);
        gl.vertexAttribPointer(0, 3, gl.FLOAT, false, 0, 0);
        gl.enableVertexAttribArray(1);
        gl.vertexAttribPointer(1, 3, gl.FLOAT, false, 0, nv * 12);
        gl.enableVertexAttribArray(2);
        // tree.vert reads ivec2: WebGL wants the signed type (bones < 16384: the same bits)
        gl.vertexAttribIPointer(2, 2, gl.INT, 0, nv * 24);
        gl.enableVertexAttribArray(3);
        gl.vertexAttribPointer(3, 1, gl.FLOAT, false, 0, nv * 32);
        const ibo = gl.createBuffer();
        gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, ibo);
        gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, a.mesh_index, gl.STATIC_DRAW);
        gl.bindVertexArray(null);
        // a species replaced (a new welcome's) gives back its impostors (web/render_imp.js);
        // the new one's are drawn at the next frame
        const old = this.species[i];
        if (old && old.imp) {
            gl.deleteTexture(old.imp);
            gl.deleteTexture(old.impWood);
        }
        this.species[i] = s;
    }
}
