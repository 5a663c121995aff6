// The trees in WebGL2 as gale-client draws them (client/render*.c): the skeleton of every
// drawn tree rebuilt on the GPU from q in the length-true form (shaders/skel.frag, two
// passes into float textures; q blended there from the snapshots' quantised values, each
// uploaded once into a texture ring, where gale-client blends on the CPU), the bark tubes
// skinned on it (tree.vert/.frag), the leaves
// on their nodes (leaf.vert/.frag), sky and ground (sky.frag), and in a storm the sky,
// light, fog and wet crowns of web/storm_fx.js, the welcome's houses (web/house.js,
// house.vert/.frag) with rain streaks over the frame
// (rain.vert/.frag, client/render/render_rain.c), storm damage (trees tipped over or lying, their
// stumps and root plates, crowns stripped, branches gone: web/damage.js gives the trees'
// codes and cut lists, client/render/render_damage.c draws the same) and falling leaves on the
// shared path (web/falling_path.js, fall.vert/.frag, client/render/render_fall.c). The shaders are the files
// of shaders/ (web/shaders.js). Here the Renderer with its scene, its offscreen picture and
// the frame; its other jobs, whose methods it takes as its own, in modules of their own:
// data textures and texture units (web/render_data.js), species (web/render_species.js),
// the modal state and the skeleton pass (web/render_skel.js), sky, fog and rain
// (web/render_sky.js), falling leaves (web/render_fall.js), storm damage
// (web/render_damage.js), the frame's draw list, the trees in view at their levels
// (web/render_list.js), and the far trees' impostors (web/render_imp.js); the matrices in
// web/view_math.js.
import { loadProgram } from './shaders.js';
import { stormFxCalm } from './storm_fx.js';
import { housesMesh, HOUSE_FLOATS } from './house.js';
import { MAX_DEBRIS } from './damage.js';
import { perspective, lookAt, mul } from './view_math.js';
import { WebGL2Missing, DATA_W, RU, RendererData } from './render_data.js';
import { RendererSpecies, LEAF_ASPECT } from './render_species.js';
import { RendererSkel } from './render_skel.js';
import { RendererSky, sceneFog_m } from './render_sky.js';
import { RendererFall } from './render_fall.js';
import { RendererDamage } from './render_damage.js';
import { RendererList } from './render_list.js';
import { RendererImp } from './render_imp.js';
import { LOD_BUDGET_TREES } from './lod_policy.js';

export class Renderer {
    constructor(canvas) {
        const gl = canvas.getContext('webgl2', { antialias: false, preserveDrawingBuffer: true });
        if (!gl) throw new WebGL2Missing('This browser has no WebGL2: gale draws its trees with WebGL2. Use a current Chrome, Firefox, Edge or Safari with hardware acceleration on.');
        if (!gl.getExtension('EXT_color_buffer_float')) {
            throw new WebGL2Missing('This browser\'s WebGL2 cannot render to float textures (EXT_color_buffer_float), which gale needs to pose the trees.');
        }
        this.gl = gl;
        this.canvas = canvas;
        this.species = [];
        this.n_trees = 0;
        this.skel_w = 0;
        this.skel_h = 0;
        this.max_rows = LOD_BUDGET_TREES; // trees posed a frame at most (the page's ?max_trees lowers it)
        this.q_trees = Infinity; // trees whose motion the page holds (App: a scene past its memory)
        this.stats = { frames: 0, trees_drawn: 0, impostors: 0, upload_ms: 0, draws: 0, triangles: 0, vertices: 0 };
        this.countDraws(gl);
        this.fx = stormFxCalm(); // web/storm_fx.js; the page sets it from WEATHER
        this.subject_m = 0;
    }

    async init(base = '') {
        const gl = this.gl;
        const names = ['skel', 'tree', 'leaf', 'sky', 'rain', 'house', 'plate', 'stump', 'fall'];
        this.base = base;
        // the skeleton pass blends the snapshots itself (setMix)
        const progs = await Promise.all(names.map((n) => loadProgram(gl, n, base, n === 'skel' ? '#define GALE_Q_RING 1\n' : '')));
        this.p = Object.fromEntries(names.map((n, i) => [n, progs[i]]));
        for (const p of progs) this.bindSamplers(p);
        await this.impInit(base);
        this.vaoEmpty = gl.createVertexArray();
        this.wind = gl.createTexture();
        gl.bindTexture(gl.TEXTURE_3D, this.wind);
        gl.texImage3D(gl.TEXTURE_3D, 0, gl.RGBA8, 1, 1, 1, 0, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
        this.list = this.dataTex(4, 1);
        this.cutn = this.dataTex(1, 1);
        this.plateBuf = this.dataTex(1, 1);
        this.stumpBuf = this.dataTex(4, 2);
        this.fallInit();
    }

    // The welcome's obstacles, rows [min x, y, z, max x, y, z] (PROTOCOL.md checks them on
    // the server's side; a row that is not 6 finite numbers with min <= max is an error).
    setObstacles(rows) {
        const gl = this.gl;
        rows.forEach((b, i) => {
            if (!Array.isArray(b) || b.length !== 6 || !b.every(Number.isFinite) || b[0] > b[3] || b[1] > b[4] || b[2] > b[5]) {
                throw new Error(`welcome.obstacles[${i}]: expected [min x, y, z, max x, y, z] with min <= max, got ${JSON.stringify(b)}`);
            }
        });
        const v = housesMesh(rows);
        this.houseVerts = v.length / HOUSE_FLOATS;
        if (!this.houseVao) {
            this.houseVao = gl.createVertexArray();
            this.houseVbo = gl.createBuffer();
            gl.bindVertexArray(this.houseVao);
            gl.bindBuffer(gl.ARRAY_BUFFER, this.houseVbo);
            const stride = HOUSE_FLOATS * 4;
            [[3, 0], [3, 3], [4, 6], [1, 10]].forEach(([size, off], a) => {
                gl.enableVertexAttribArray(a);
                gl.vertexAttribPointer(a, size, gl.FLOAT, false, stride, off * 4);
            });
            gl.bindVertexArray(null);
        }
        gl.bindBuffer(gl.ARRAY_BUFFER, this.houseVbo);
        gl.bufferData(gl.ARRAY_BUFFER, v.length ? v : new Float32Array(HOUSE_FLOATS), gl.STATIC_DRAW);
    }

    // The welcome's instances: rows [species, x, y, z, yaw, scale]; after them MAX_DEBRIS
    // slots for broken-off pieces (setDebris).
    setInstances(rows, stride) {
        this.n_trees = rows.length;
        this.inst = rows;
        this.debris = [];
        // whole rows of the texture, so that a range of slots uploads without a copy
        const texels = (rows.length + MAX_DEBRIS) * 2, tw = Math.min(DATA_W, texels);
        const t = new Float32Array(Math.ceil(texels / tw) * tw * 4);
        rows.forEach((r, i) => {
            t.set([r[1], r[2], r[3], r[4], r[5] > 0 ? r[5] : 1, r[0], 0, 0], 8 * i);
        });
        this.treeData = t;
        this.trees = this.dataTex(4, (rows.length + MAX_DEBRIS) * 2, t, this.trees);
        this.setupCulling(rows);
        this.fog_m = sceneFog_m(rows);
        this.uprooted = new Uint8Array(rows.length);
        this.setCuts(new Float32Array(rows.length * 4), new Float32Array(1));
        this.setStride(stride);
        this.clearFalling();
    }

    // The picture draw() renders into while this.offscreen is set (colour and depth of the
    // canvas's size), so that a frame can be drawn ahead and shown later: present() copies
    // it to the canvas, which the browser composites at its next display refresh.
    target() {
        const gl = this.gl, w = this.canvas.width, h = this.canvas.height;
        if (this.off && this.off.w === w && this.off.h === h) return this.off.fbo;
        if (this.off) {
            gl.deleteFramebuffer(this.off.fbo);
            for (const rb of this.off.rb) gl.deleteRenderbuffer(rb);
        }
        const fbo = gl.createFramebuffer(), rb = [gl.createRenderbuffer(), gl.createRenderbuffer()];
        gl.bindFramebuffer(gl.FRAMEBUFFER, fbo);
        [[gl.RGBA8, gl.COLOR_ATTACHMENT0], [gl.DEPTH_COMPONENT24, gl.DEPTH_ATTACHMENT]].forEach(([fmt, at], k) => {
            gl.bindRenderbuffer(gl.RENDERBUFFER, rb[k]);
            gl.renderbufferStorage(gl.RENDERBUFFER, fmt, w, h);
            gl.framebufferRenderbuffer(gl.FRAMEBUFFER, at, gl.RENDERBUFFER, rb[k]);
        });
        if (gl.checkFramebufferStatus(gl.FRAMEBUFFER) !== gl.FRAMEBUFFER_COMPLETE) {
            throw new WebGL2Missing(`an offscreen picture of ${w}×${h} (RGBA8, depth 24) is not renderable here`);
        }
        this.off = { fbo, rb, w, h };
        return fbo;
    }

    // Every draw call of gl counted (calls, vertices, and triangles of gl.TRIANGLES) into
    // this.drawCount, and a frame's into stats (frameCounted): for tests and the benchmark.
    countDraws(gl) {
        const c = this.drawCount = { calls: 0, vertices: 0, triangles: 0 };
        const wrap = (name, count) => {
            const f = gl[name].bind(gl);
            gl[name] = (...x) => {
                const v = count(x);
                c.calls++;
                c.vertices += v;
                if (x[0] === gl.TRIANGLES) c.triangles += v / 3;
                return f(...x);
            };
        };
        wrap('drawArrays', (x) => x[2]);
        wrap('drawElements', (x) => x[1]);
        wrap('drawArraysInstanced', (x) => x[2] * x[3]);
        wrap('drawElementsInstanced', (x) => x[1] * x[4]);
    }

    frameCounted() {
        this.stats.draws = this.drawCount.calls;
        this.stats.triangles = this.drawCount.triangles;
        this.stats.vertices = this.drawCount.vertices;
    }

    // The offscreen picture onto the canvas (false when there is none of the canvas's size).
    present() {
        const gl = this.gl, o = this.off;
        if (!o || o.w !== this.canvas.width || o.h !== this.canvas.height) return false;
        gl.bindFramebuffer(gl.READ_FRAMEBUFFER, o.fbo);
        gl.bindFramebuffer(gl.DRAW_FRAMEBUFFER, null);
        gl.blitFramebuffer(0, 0, o.w, o.h, 0, 0, o.w, o.h, gl.COLOR_BUFFER_BIT, gl.NEAREST);
        gl.bindFramebuffer(gl.FRAMEBUFFER, null);
        return true;
    }

    // The view and view-projection of cam (below) on this canvas: this.view, this.viewproj.
    look(cam) {
        if (cam.viewproj) {
            this.viewproj = cam.viewproj;
            this.view = cam.view || null;
        } else {
            const proj = perspective(cam.fov_y_deg * Math.PI / 180, this.canvas.width / this.canvas.height, cam.near || 0.3, cam.far || 4500);
            this.view = lookAt(cam.eye, cam.target, [0, 0, 1]);
            this.viewproj = mul(proj, this.view);
        }
        this.eye = cam.eye;
    }

    // cam: { eye, target, fov_y_deg, near, far, subject_m? } or { viewproj, eye } for a
    // wall tile (subject_m: how far along the view the camera's subject lies, 0 none);
    // modes: per tree mode count (0: not sent: drawn at rest with none); server_s: the
    // server time shown (falling leaves follow it), undefined: none drawn.
    draw(cam, t, modes, server_s) {
        const gl = this.gl, W = this.canvas.width, H = this.canvas.height;
        const c = this.drawCount;
        this.ensureImpostors(); // a species' pictures, once, before the frame's counts
        c.calls = c.vertices = c.triangles = 0;
        this.look(cam);
        if (this.t_base === undefined && Number.isFinite(server_s)) this.t_base = Math.floor(server_s);
        this.subject_m = cam.subject_m > 0 && Number.isFinite(cam.subject_m) && this.view ? cam.subject_m : 0;
        // the trees in view at their levels (web/render_list.js)
        const { groups, imps, drawn, rows } = this.drawList(cam, modes);
        this.groups = groups; // the skeleton rows drawn: for tests
        this.ensureSkel(Math.max(1, ...groups.map((g) => this.species[g.s].n_nodes)), rows);

        this.poseSkeletons(groups);

        gl.bindFramebuffer(gl.FRAMEBUFFER, this.offscreen ? this.target() : null);
        gl.viewport(0, 0, W, H);
        gl.enable(gl.DEPTH_TEST);
        gl.depthMask(true);
        gl.clear(gl.DEPTH_BUFFER_BIT);
        this.drawSky(t);

        // houses (both faces drawn: the mesh is closed, and thin boxes stay visible);
        // gale-client's colours (client/render/render.c)
        if (this.houseVerts > 0 && !this.hideHouses) {
            const ph = this.p.house;
            this.setCommon(ph, t);
            gl.uniform3f(ph.u.u_wall, 0.92, 0.82, 0.64);
            gl.uniform3f(ph.u.u_roof, 0.52, 0.22, 0.15);
            gl.uniform3f(ph.u.u_window, 0.14, 0.18, 0.24);
            gl.bindVertexArray(this.houseVao);
            gl.drawArrays(gl.TRIANGLES, 0, this.houseVerts);
        }

        if (this.hideTrees) {
            this.stats.frames++;
            this.frameCounted();
            return;
        }
        this.bindTex(RU.SKEL, gl.TEXTURE_2D, this.skelTex[0]);
        this.bindTex(RU.LIST, gl.TEXTURE_2D, this.list.tex);
        this.bindTex(RU.TREES, gl.TEXTURE_2D, this.trees.tex);
        gl.enable(gl.CULL_FACE);
        gl.cullFace(gl.BACK);
        const pt = this.p.tree;
        this.setCommon(pt, t);
        for (const g of groups) {
            const sp = this.species[g.s];
            gl.uniform3fv(pt.u.u_bark, sp.bark);
            this.bindTex(RU.NODE, gl.TEXTURE_2D, sp.node.tex);
            gl.bindVertexArray(sp.vao);
            for (const [base, n, l] of g.bark) {
                if (!sp.lod_count[l]) continue;
                gl.uniform1i(pt.u.u_base, base);
                gl.drawElementsInstanced(gl.TRIANGLES, sp.lod_count[l], gl.UNSIGNED_INT, sp.lod_first[l] * 4, n);
            }
        }
        gl.disable(gl.CULL_FACE);
        this.drawDamage(drawn, t);
        const pl = this.p.leaf;
        this.setCommon(pl, t);
        gl.bindVertexArray(this.vaoEmpty);
        for (const g of groups) {
            const sp = this.species[g.s];
            if (!sp.n_leaves) continue;
            gl.uniform1f(pl.u.u_aspect, LEAF_ASPECT[sp.leaf_shape]);
            gl.uniform2f(pl.u.u_crown, sp.crown_r, sp.height);
            gl.uniform3fv(pl.u.u_leafcol, sp.leaf_rgb);
            gl.uniform1i(pl.u.u_shape, sp.leaf_shape);
            this.bindTex(RU.NODE, gl.TEXTURE_2D, sp.node.tex);
            // each level its share of the leaves (web/render_list.js leafLevels)
            for (const [base, n, l] of g.leaves) {
                const lv = this.leafLevels(sp)[l];
                if (!lv.n) continue;
                gl.uniform1i(pl.u.u_base, base);
                gl.uniform1i(pl.u.u_nleaves, lv.n);
                // the level's own leaf texture holds its share, grown: every slot, as drawn
                gl.uniform1i(pl.u.u_leaf_total, lv.n);
                gl.uniform1f(pl.u.u_leaf_grow, 1);
                this.bindTex(RU.LEAF, gl.TEXTURE_2D, lv.tex.tex);
                gl.drawArraysInstanced(gl.TRIANGLES, 0, 6, n * lv.n);
            }
        }
        this.drawImpostors(imps, t);
        this.drawFalling(server_s);
        this.drawRain(t);
        this.frameCounted();
        // the first frames are checked (a check each frame would stall the pipeline)
        if (this.stats.frames++ < 3) {
            const e = gl.getError();
            if (e) throw new Error(`WebGL error 0x${e.toString(16)} in frame ${this.stats.frames}`);
        }
    }
}

// The methods of each job, kept in a module of its own, are Renderer's: copied as
// defined (not enumerable, as a class's own).
for (const part of [RendererData, RendererSpecies, RendererSkel, RendererSky, RendererFall, RendererDamage, RendererList, RendererImp]) {
    for (const [name, d] of Object.entries(Object.getOwnPropertyDescriptors(part.prototype))) {
        if (name !== 'constructor') Object.defineProperty(Renderer.prototype, name, d);
    }
}
