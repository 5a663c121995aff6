// Storm damage on the GPU (client/render/render_damage.c): the trees' damage codes, the broken
// branches' cut lists, the debris pieces in the slots after the trees, and the root
// plates and stumps drawn (plate.vert, stump.vert). Renderer (web/render_gl.js) takes
// these methods as its own.
import { MAX_DEBRIS, damageCutMask } from './damage.js';
import { RU } from './render_data.js';

const PLATE_SEG = 24, STUMP_SEG = 12; // shaders/plate.vert, stump.vert

export class RendererDamage {
    // Storm damage of every tree (web/damage.js DamageFx.update): u_trees slot 1 .z
    // (render_tree_code: fall angle + 4 x leaf levels lost + 256 when snapped) and .w (fall
    // azimuth), and which trees lie on their root plate; a tree tipping or lying (fallen,
    // uprooted, snapped) is drawn far away as an impostor laid along its fall (the cells'
    // rows, web/render_list.js placeDamage and impFall).
    setDamage(code, az, uprooted) {
        const t = this.treeData;
        for (let i = 0; i < this.n_trees; i++) {
            t[8 * i + 6] = code[i];
            t[8 * i + 7] = az[i];
        }
        this.uprooted.set(uprooted.subarray(0, this.n_trees));
        this.placeDamage(); // the cells' copies (web/render_list.js)
        this.trees = this.dataTex(4, (this.n_trees + MAX_DEBRIS) * 2, t, this.trees);
    }

    // The broken branches' cut lists (render_damage_upload): per tree (first, count,
    // keep-only, 0) and the cut nodes; the debris slots' lists follow.
    // Also each tree's share of its leaf slots whose node no broken branch takes, for its
    // impostor (client/render/render_damage.c leaf_attached_update): only trees with broken
    // branches cost anything.
    setCuts(head, nodes) {
        this.cutTrees = { head, nodes };
        this.leafAttached.fill(1);
        for (let t = 0; t < this.n_trees; t++) {
            const nc = head[4 * t + 1], first = head[4 * t], sp = this.species[this.inst[t][0]];
            if (!nc || !sp || !sp.n_leaves) continue;
            const m = damageCutMask(sp.a.parent, Array.from(nodes.subarray(first, first + nc)), false);
            let kept = 0;
            for (let l = 0; l < sp.n_leaves; l++) kept += m[sp.a.leaf_node[l]];
            this.leafAttached[t] = kept / sp.n_leaves;
        }
        this.placeDamage();
        this.uploadCuts();
    }

    uploadCuts() {
        const n = this.n_trees, { head, nodes } = this.cutTrees, nd = this.debris.length;
        const h = new Float32Array((n + MAX_DEBRIS) * 4), nn = new Float32Array(nodes.length + nd);
        h.set(head.subarray(0, 4 * n));
        nn.set(nodes);
        this.debris.forEach((d, k) => {
            // keep only the sub-tree of the node that broke
            h.set([nodes.length + k, 1, 1, 0], 4 * (n + k));
            nn[nodes.length + k] = d.node;
        });
        this.cut = this.dataTex(4, n + MAX_DEBRIS, h, this.cut);
        this.cutn = this.dataTex(1, nn.length, nn, this.cutn);
    }

    // The pieces broken off and tumbling or lying (render_set_debris; web/damage.js
    // DamageFx.debrisAt): slot n_trees + k drawn at rest from its tree's species and scale,
    // its own place and turn, only the sub-tree of its node.
    setDebris(list) {
        const n = this.n_trees, t = this.treeData;
        const same = list.length === this.debris.length && list.every((d, k) => d.tree === this.debris[k].tree && d.node === this.debris[k].node);
        if (!list.length && !this.debris.length) return;
        list.forEach((d, k) => {
            const src = 8 * d.tree, z = t[src + 6];
            const lost = Math.floor((z - 256 * (z >= 256)) * 0.25);
            t.set([d.pos[0], d.pos[1], d.pos[2], d.yaw, t[src + 4], t[src + 5], Math.min(Math.max(d.fall, 0), 3.1415926) + 4 * lost, d.az], 8 * (n + k));
        });
        this.debris = list;
        this.subUpload(this.trees, t, 2 * n, 2 * (n + Math.max(list.length, 1)));
        if (!same) this.uploadCuts(); // the cut lists change only with the set of pieces
    }

    // Root plates of uprooted trees and stumps of snapped ones among the trees drawn
    // (client/render/render.c build_lists, render_damage.c render_plates_draw, render_stumps_draw).
    drawDamage(drawn, t) {
        const gl = this.gl, plates = [], stumps = [];
        for (const i of drawn) {
            if (i >= this.n_trees) continue; // a debris piece has no stump nor plate
            const z = this.treeData[8 * i + 6], fall = z - 4 * Math.floor(z * 0.25);
            if (this.uprooted[i] && fall > 0.02) plates.push(i);
            if (z >= 256) {
                const s = this.species[this.inst[i][0]];
                stumps.push(i, s.stem_r_m, s.stem_taper, 0, s.bark[0], s.bark[1], s.bark[2], 0);
            }
        }
        this.stats.plates = plates.length;
        this.stats.stumps = stumps.length / 8;
        this.bindTex(RU.TREES, gl.TEXTURE_2D, this.trees.tex);
        gl.bindVertexArray(this.vaoEmpty);
        if (plates.length) {
            this.plateBuf = this.dataTex(1, plates.length, Float32Array.from(plates), this.plateBuf);
            this.setCommon(this.p.plate, t);
            this.bindTex(RU.PLATE, gl.TEXTURE_2D, this.plateBuf.tex);
            gl.drawArraysInstanced(gl.TRIANGLES, 0, 12 * PLATE_SEG, plates.length);
        }
        if (stumps.length) {
            this.stumpBuf = this.dataTex(4, stumps.length / 4, Float32Array.from(stumps), this.stumpBuf);
            this.setCommon(this.p.stump, t);
            this.bindTex(RU.STUMP, gl.TEXTURE_2D, this.stumpBuf.tex);
            gl.drawArraysInstanced(gl.TRIANGLES, 0, 21 * STUMP_SEG, stumps.length / 8);
        }
    }
}
