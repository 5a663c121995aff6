// What the three pages share: the connection (web/conn.js), the species assets checked
// against the welcome's hashes (web/asset.js), snapshots through the jitter buffer
// (web/jitter.js) into the renderer (web/render_gl.js), the HUD from WEATHER, and the
// messages a person can act on, the storm look from WEATHER (web/storm_fx.js; the page's
// ?storm_fx=off|low|high, default low as gale-client's --storm-fx), a scene past what the
// page holds as a reduced view (web/hold.js; ?hold_trees=N holds at most N trees).
// window.gale exposes the state for tests and benchmarks.
import { showSchedule } from './closed.js';
import { Connection } from './conn.js';
import { fetchAsset } from './asset.js';
import { Jitter, Clock, blendWeights } from './jitter.js';
import { Renderer } from './render_gl.js';
import { WebGL2Missing } from './render_data.js';
import { orbitEye } from './view_math.js';
import { stormFxFromWeather, stormFxQualityParse, STORM_FX_LOW } from './storm_fx.js';
import { DamageFx, DAMAGE, frameDamage } from './damage.js';
import { weatherLines } from './hud_text.js';
import { setTexts, langFind, t } from './lang.js';
import { LANG_CODES, TEXTS } from './lang_texts.js';
import { Governor, softwareRenderer } from './governor.js';
import { DATA_W } from './render_data.js';
import { frustumCone, frustumView, ViewSender } from './view_stream.js';
import { VIEW_FAR_M, VIEW_LOD_M } from './lod_policy.js';
import { holdCentre, holdNearest, holdView } from './hold.js';
import { Sound, soundOptions } from './audio.js';

// the visitor's texts, built from configs/lang/*.po with gale-client's (client/lang)
setTexts(LANG_CODES, TEXTS);

const LEAVES_PER_FRAME = 4096; // CLIENT_LEAVES_PER_FRAME (client/app/client.h): more are thinned
// The modal state the page holds: every snapshot's quantised values (n_trees × stride
// int16) once in the jitter buffer and once in the GPU's ring, up to Q_LAYERS_MAX
// snapshots, as many as fit this many bytes (?hold_mb=N lowers it), never fewer than
// Q_LAYERS_MIN (the blend takes up to four); a scene past that is a reduced view, its trees
// nearest one point as many as fit (web/hold.js).
const Q_HOLD_BYTES = 192 * 1048576;
const Q_LAYERS_MAX = 32;
const Q_LAYERS_MIN = 5;

// How much of a scene of n trees × stride modes the page holds: { trees, layers, why },
// within hold_bytes and the GPU's texture height and array layers; why says what holds
// fewer trees than n (null when none does).
export function qHold(n, stride, hold_bytes, max_rows, max_layers) {
    const snap = Math.max(1, n * stride * 2), rows = Math.floor(max_rows * DATA_W / stride);
    let layers = Math.min(Q_LAYERS_MAX, max_layers, Math.floor(hold_bytes / snap));
    let trees = Math.min(n, rows), why = rows < n ? `the GPU's ${max_rows} texture rows take ${rows} trees of ${stride} modes` : null;
    if (layers < Q_LAYERS_MIN) {
        layers = Math.min(Q_LAYERS_MIN, max_layers);
        const fit = Math.floor(hold_bytes / (layers * stride * 2));
        if (fit < trees) {
            trees = fit;
            why = `${(hold_bytes / 1048576).toFixed(0)} MB hold ${layers} snapshots of ${fit} trees of ${stride} modes`;
        }
    }
    return { trees, layers, why };
}

// Whether two welcomes' rows are the same trees (a reconnection to the same scene).
function sameTrees(a, b) {
    if (a.length !== b.length) return false;
    for (let t = 0; t < a.length; t++) {
        for (let k = 0; k < 6; k++) if (a[t][k] !== b[t][k]) return false;
    }
    return true;
}

function percentile(a, p) {
    if (!a.length) return null;
    const s = [...a].sort((x, y) => x - y);
    return s[Math.min(s.length - 1, Math.floor(p * (s.length - 1) + 0.5))];
}

export class App {
    // opts: { role, token?, extraHello?, onWelcome?, onWeather?, onStatus?, camera? (fn),
    // and a wall tile's offscreen (true), beforeDraw(app, server_s), renderTime(app,
    // server_s) (null: draw nothing now), shaderTime(shown_s), afterFrame(app) }
    constructor(opts) {
        this.o = opts;
        this.statusEl = document.getElementById('status');
        this.hudEl = document.getElementById('hud');
        this.hudSaysEl = document.getElementById('hud-says');
        this.canvas = document.getElementById('view');
        // JS CPU per stage: decode and insert (the copy into the jitter buffer) per
        // snapshot; interp (the blend's weights) and upload (of the snapshots a frame is
        // first to blend, into the GPU's ring) per drawn frame
        this.perf = { decode: [], insert: [], interp: [], upload: [], draw: [], cull: [] };
        this.bytesAssets = 0;
        this.t_load = performance.now();
        this.firstFrame_ms = null;
        this.weather = null;
        this.errors = [];
        this.framesDrawn = 0;
        const sq = new URLSearchParams(location.search).get('storm_fx');
        this.stormQuality = sq === null ? STORM_FX_LOW : stormFxQualityParse(sq);
        if (this.stormQuality === null) {
            this.stormQuality = STORM_FX_LOW;
            this.errors.push(`storm_fx=${sq}: expected off, low or high; low is used`);
        }
        this.cam = { yaw: 1.5707963 - 0.6108652, pitch: -0.5235988, distance: 60, target: [0, 0, 4], fov_y_deg: 50 };
        const q = new URLSearchParams(location.search), mb = Number(q.get('hold_mb'));
        // the frame-time governor (web/governor.js): ?governor=MS|off; by default 33 ms, off in
        // a browser driven by automation (as gale-client's headless runs: their pictures compare)
        const gq = q.get('governor');
        this.governorMs = gq === 'off' ? 0 : Number(gq) > 0 ? Number(gq) : navigator.webdriver ? 0 : 33;
        this.resScale = 1;
        this.hudLines = [];
        // the visitor's language: ?lang=en|es|ht (gale-client's --lang), English by default;
        // a kiosk visitor may choose another (setLang), and idle returns to this one
        const lq = q.get('lang');
        this.langDefault = langFind(lq) || 'en';
        if (lq !== null && !langFind(lq)) this.errors.push(`lang=${lq}: expected ${LANG_CODES.join(', ')}; en is used`);
        this.lang = this.langDefault;
        // ?view=all: no view sent, the whole scene streamed (a reference for the stream's size)
        this.followCamera = q.get('view') !== 'all';
        this.holdBytes = mb > 0 ? Math.min(mb * 1048576, Q_HOLD_BYTES) : Q_HOLD_BYTES;
        // ?hold_trees=N: at most N trees held (gale-client's --max-trees), a reduced view past it
        const ht = q.get('hold_trees');
        this.holdTrees = ht !== null && /^[1-9][0-9]*$/.test(ht) ? Number(ht) : 0;
        if (ht !== null && !this.holdTrees) this.errors.push(`hold_trees=${ht}: expected a whole number of trees above 0; no limit is used`);
        this.held = null; // a reduced view: web/hold.js's circle, held (scene index of each tree held), slot, why
        // the stream's view follows the camera (web/view_stream.js)
        this.views = new ViewSender((m) => this.conn && this.conn.send(m));
        this.bytesSeen = []; // [page time s, stream bytes] about every half second
        this.treesSent = 0; // trees the last state frame carried
        // the wind's sound (web/audio.js): ?sound=off, ?volume=DB, ?volume_max=DBFS, ?quiet=1
        const so = soundOptions(location.search);
        this.errors.push(...so.errors);
        this.sound = new Sound(this, so);
        window.gale = this;
    }

    say(text) {
        if (!this.statusEl) return;
        this.statusEl.hidden = !text;
        this.statusEl.textContent = text || '';
    }

    status() {
        return { conn: this.conn && this.conn.status, frames: this.conn && this.conn.stats, drawn: this.framesDrawn,
            species: this.r ? this.r.species.filter(Boolean).length : 0, errors: this.errors, message: this.statusEl && !this.statusEl.hidden ? this.statusEl.textContent : '' };
    }

    async start() {
        this.resize();
        window.addEventListener('resize', () => this.resize());
        try {
            this.r = new Renderer(this.canvas);
            if (this.o.maxTrees > 0) this.r.max_rows = this.o.maxTrees;
            this.r.offscreen = !!this.o.offscreen; // a wall tile draws ahead, presents later
            await this.r.init();
            const gl = this.r.gl, info = gl.getExtension('WEBGL_debug_renderer_info');
            this.rendererName = info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER);
            this.gov = new Governor(this.governorMs, softwareRenderer(this.rendererName), performance.now() * 1e-3);
            this.applyGovernor();
        } catch (e) {
            this.fatal = e;
            this.say(e instanceof WebGL2Missing ? e.message : `The page could not start its renderer: ${e.message}`);
            this.errors.push(e.message);
            return;
        }
        const proto = location.protocol === 'https:' ? 'wss:' : 'ws:';
        this.conn = new Connection({
            url: `${proto}//${location.host}/`, role: this.o.role, token: this.o.token, extraHello: this.o.extraHello,
            onStatus: (s) => this.onStatus(s),
            onWelcome: (w) => this.onWelcome(w),
            onFrame: (f) => this.onFrame(f),
            onPong: (sent, server, recv) => this.clock.pong(sent, server, recv),
            // the schedule is every page's (the closed card, closed.js)
            onText: (m) => (m.type === 'schedule' ? this.schedule(m) : this.o.onText && this.o.onText(m)),
        });
        this.clock = new Clock();
        this.conn.start();
        this.attachControls();
        this.sound.attach();
        requestAnimationFrame((t) => this.frame(t));
    }

    resize() {
        const dpr = Math.min(window.devicePixelRatio || 1, 2) * this.resScale;
        this.canvas.width = Math.max(1, Math.round(this.canvas.clientWidth * dpr));
        this.canvas.height = Math.max(1, Math.round(this.canvas.clientHeight * dpr));
    }

    onStatus(s) {
        if (s.state === 'live') this.say('');
        else if (s.text) this.say(s.text);
        if (this.o.onStatus) this.o.onStatus(s);
    }

    // The trees of welcome w this page holds (client/app/client_hold.c's rule): all of them
    // within its limit (?hold_trees, the GPU's texture rows, the bytes of Q_LAYERS_MIN
    // snapshots), else as many as that nearest one point (the one held about before on
    // this scene, else a fitted camera's target, else the scene's centre): this.held, and
    // the welcome the rest of the page sees, with those trees alone.
    holdScene(w, stride) {
        const rows = w.instances, n = rows.length, gl = this.r.gl;
        const whole = qHold(n, stride, this.holdBytes, gl.getParameter(gl.MAX_TEXTURE_SIZE), gl.getParameter(gl.MAX_ARRAY_TEXTURE_LAYERS));
        let limit = Math.max(1, whole.trees), why = whole.why;
        if (this.holdTrees > 0 && this.holdTrees < limit) {
            limit = this.holdTrees;
            why = `?hold_trees=${this.holdTrees}`;
        }
        if (!(this.sceneWelcome && sameTrees(this.sceneWelcome.instances, rows))) {
            this.holdPoint = null; // another scene: its own point, said anew
            this.heldSaid = false;
        }
        this.sceneWelcome = w;
        this.held = null;
        if (limit >= n) return w;
        if (!this.holdPoint) this.holdPoint = this.camSet ? [this.cam.target[0], this.cam.target[1]] : holdCentre(rows);
        const h = holdNearest(rows, this.holdPoint[0], this.holdPoint[1], limit), slot = new Int32Array(n).fill(-1);
        h.held.forEach((t, k) => { slot[t] = k; });
        this.held = { circle: h, held: h.held, slot, why, view: null };
        return { ...w, instances: Array.from(h.held, (t) => rows[t]) };
    }

    // The reduced view's circle once the species' heights are known (the server widens a
    // circle by the tallest tree's), said once a scene on the console.
    holdCircle() {
        const h = this.held, rows = this.sceneWelcome.instances;
        let margin = 0; // the asset's height_m, the server's (not the leaves' reach the culling takes)
        for (const r of rows) {
            const sp = this.r.species[r[0]];
            if (sp) margin = Math.max(margin, sp.a.height_m * (r[5] > 0 ? r[5] : 1));
        }
        h.view = holdView(h.circle, margin);
        if (this.heldSaid) return;
        this.heldSaid = true;
        const c = h.circle;
        console.info(`gale: ${location.host}: the scene has ${rows.length} trees, more than this page holds (${h.why}): holding the ${c.n_held} nearest (${c.cx.toFixed(2)}, ${c.cy.toFixed(2)}), within ${c.radius_m.toFixed(2)} m; the others are not drawn, and the server is asked for these alone (a circle view of ${h.view.radius_m.toFixed(1)} m)`);
    }

    async onWelcome(w) {
        this.ready = false;
        this.sceneChecked = null;
        const stride = Math.max(...w.species.map((s) => s.n_modes));
        this.stride = stride;
        this.clock.reset();
        // the trees held: every one, or a reduced view's (this.welcome has those alone;
        // the stream's tree indices are the scene's, this.sceneWelcome's)
        w = this.holdScene(w, stride);
        this.welcome = w;
        // the held trees' centre and extent: the camera of client/app/client_scene.c
        const n = w.instances.length;
        const c = [0, 0, 0];
        for (const r of w.instances) for (let k = 0; k < 3; k++) c[k] += r[1 + k] / n;
        let rad = 10;
        for (const r of w.instances) rad = Math.max(rad, Math.hypot(r[1] - c[0], r[2] - c[1]));
        if (!this.camSet) {
            this.cam.target = [c[0], c[1], c[2] + 4];
            this.cam.distance = Math.min(1.6 * rad + 22, 1500);
            this.camSet = true;
        }
        this.qTree = new Float32Array(stride);
        this.qwTree = new Float32Array(4 * stride);
        this.modes = new Uint8Array(n);
        this.qGather = null;
        // the modal state of the trees held, from their count (the GPU's limits, the page's bytes)
        const gl = this.r.gl, hold = qHold(n, stride, this.holdBytes, gl.getParameter(gl.MAX_TEXTURE_SIZE), gl.getParameter(gl.MAX_ARRAY_TEXTURE_LAYERS));
        this.qTrees = hold.trees;
        this.jitter = new Jitter(hold.trees * stride, hold.layers);
        this.r.q_trees = hold.trees;
        this.views.reset(this.conn.o.view);
        // storm damage: a new picture per welcome; the keyframe's full DAMAGE fills it
        // (a reconnect heals what the server no longer holds)
        this.damage = new DamageFx(n, w.tick_hz, (t) => {
            const sp = this.r.species[w.instances[t][0]];
            return sp ? sp.height * (w.instances[t][5] > 0 ? w.instances[t][5] : 1) : 0;
        }, (t) => (w.instances[t][5] > 0 ? w.instances[t][5] : 1));
        this.damage.scene = { row: (t) => w.instances[t], asset: (t) => (this.ready && this.r.species[w.instances[t][0]] ? this.r.species[w.instances[t][0]].a : null) };
        this.damageGen = -1;
        this.leavesFrame = 0;
        try {
            for (let i = 0; i < w.species.length; i++) {
                if (this.speciesHash && this.speciesHash[i] === w.species[i].hash && this.r.species[i]) continue;
                const sp = w.species[i];
                const { asset, bytes } = await this.fetchWithRetry(sp);
                this.bytesAssets += bytes;
                if (asset.n_modes !== sp.n_modes) throw new Error(`${sp.name}: the asset has ${asset.n_modes} modes, the welcome says ${sp.n_modes}`);
                this.r.addSpecies(i, asset);
                this.sound.addSpecies(i, asset);
            }
        } catch (e) {
            this.errors.push(e.message);
            this.say(e.message);
            return;
        }
        this.speciesHash = w.species.map((s) => s.hash);
        this.r.setInstances(w.instances, stride);
        this.r.setStride(stride, this.jitter.capacity);
        if (this.held) this.holdCircle();
        this.showHud();
        try {
            this.r.setObstacles(w.obstacles || []);
        } catch (e) {
            this.errors.push(e.message); // the trees are still drawn
            this.say(`The scene's houses cannot be drawn: ${e.message}`);
        }
        this.ready = true;
        if (this.o.onWelcome) this.o.onWelcome(w);
        // the view at once, before the first frame: the whole scene's stream would
        // otherwise fill the queue a large scene's first frame waits behind
        this.r.look(this.camera());
        this.followView(performance.now() * 1e-3);
    }

    // An asset whose bytes do not hash to the welcome's hash is refused and fetched again
    // with a backoff (a server that rebakes serves the right bytes later).
    async fetchWithRetry(sp) {
        for (let wait = 0.5; ; wait = Math.min(wait * 2, 10)) {
            try {
                return await fetchAsset(sp.url, sp.hash, sp.name);
            } catch (e) {
                this.errors.push(e.message);
                this.say(e.hashMismatch ? `Asset hash mismatch: ${e.message}. The tree species cannot be drawn; retrying in ${wait} s.` : `Could not load the ${sp.name} asset: ${e.message}. Retrying in ${wait} s.`);
                await new Promise((res) => setTimeout(res, wait * 1000));
                this.say('');
            }
        }
    }

    onFrame(f) {
        const now = performance.now();
        if (this.conn.lastDecode_ms !== undefined) this.perf.decode.push(this.conn.lastDecode_ms);
        if (f.state && this.jitter) {
            const st = f.state;
            const scene = this.sceneWelcome.instances;
            if (st.scene.stride !== this.stride || st.scene.n_trees !== scene.length) {
                this.errors.push(`keyframe of ${st.scene.n_trees} trees × ${st.scene.stride} modes, welcome ${scene.length} × ${this.stride}`);
                return;
            }
            // the skeleton pass dequantises with the steps of the scene's species, which
            // PROTOCOL.md makes the welcome's instance species
            if (st.scene !== this.sceneChecked) {
                const inst = scene, t = inst.findIndex((r, i) => r[0] !== st.scene.species[i]);
                if (t >= 0) {
                    this.errors.push(`keyframe: tree ${t} of species ${st.scene.species[t]}, welcome ${inst[t][0]}`);
                    return;
                }
                this.sceneChecked = st.scene;
            }
            // a tree the server stops sending (out of its view) has 0 modes: the decoder
            // zeroes its values, so it is drawn at rest, never with stale ones
            let sent = 0;
            for (let t = 0; t < st.n_modes.length; t++) sent += st.n_modes[t] > 0;
            this.treesSent = sent;
            const q = this.held ? this.gatherHeld(st) : st.q;
            if (!this.held) this.modes.set(st.n_modes);
            const t_s = f.hdr.server_time_us * 1e-6;
            this.clock.arrival(t_s, now * 1e-3);
            // Q as decoded into the jitter buffer's copy, later once into the GPU's ring
            // (web/jitter.js, render_skel.js setMix), dequantised and blended there per frame
            const t0 = performance.now();
            try {
                this.jitter.insert(f.hdr.tick, t_s, q, st.scene);
            } catch (e) {
                this.errors.push(e.message);
                this.jitter.reset();
            }
            this.perf.insert.push(performance.now() - t0);
        }
        if (f.weather) {
            this.weather = f.weather;
            if (this.r) this.r.fx = stormFxFromWeather(f.weather.sustained_ms, f.weather.dir_from_deg, this.stormQuality);
            const lines = weatherLines(f.weather, this.lang);
            this.hudLines = lines;
            this.showHud();
            // a screen reader is told the class when it changes, not every replay second
            if (this.hudSaysEl && this.hudSaysEl.textContent !== lines[1]) this.hudSaysEl.textContent = lines[1];
            if (this.o.onWeather) this.o.onWeather(f.weather);
        }
        if (f.wind) {
            this.lastWind = f.wind;
            if (this.r) this.r.setWind(f.wind);
        }
        if (f.damage) this.damageEvents = (this.damageEvents || 0) + f.damage.events.length;
        const fd = frameDamage(f); // a FOREST with its DAMAGE as one (web/damage.js)
        if (fd) {
            const d = this.heldDamage(fd);
            if (this.damage) this.sound.onDamage(f.hdr, d, this.damage.view, this.welcome.tick_hz);
            if (this.damage) this.damage.take(f.hdr, d);
        }
        if (f.leaves) {
            this.leavesShed = (this.leavesShed || 0) + f.leaves.length;
            if (this.ready) this.takeLeaves(f);
        }
    }

    // A reduced view's modes and Q of the trees held, in their order, from a state frame
    // of the scene's (this.modes, and a scratch the jitter buffer copies).
    gatherHeld(st) {
        const held = this.held.held, s = this.stride, src = st.q;
        if (!this.qGather || this.qGather.constructor !== src.constructor) this.qGather = new src.constructor(held.length * s);
        const g = this.qGather;
        for (let k = 0; k < held.length; k++) {
            const b = held[k] * s, o = k * s;
            this.modes[k] = st.n_modes[held[k]];
            for (let m = 0; m < s; m++) g[o + m] = src[b + m];
        }
        return g;
    }

    // A tree of the stream as the page's: its index among the trees held, -1 for one not
    // held (a tree past the scene stays past the trees held).
    heldTree(t) {
        if (!this.held) return t;
        return t < this.held.slot.length ? this.held.slot[t] : t;
    }

    // A DAMAGE frame's events of the trees held, their indices the page's.
    heldDamage(d) {
        if (!this.held) return d;
        const events = [];
        for (const e of d.events) {
            const k = this.heldTree(e.tree);
            if (k >= 0) events.push(k === e.tree ? e : { ...e, tree: k });
        }
        return { ...d, events };
    }

    // LEAVES seeds released from the trees' pose now on screen, at their spawn time on the
    // server clock (client/app/client_stream.c take_leaves).
    takeLeaves(f) {
        const hz = this.welcome.tick_hz > 0 ? this.welcome.tick_hz : 60, t_hdr = f.hdr.server_time_us * 1e-6;
        for (let i = 0; i < f.leaves.length; i++) {
            const l = f.leaves[i], tree = this.heldTree(l.instance);
            if (tree < 0) continue; // a tree not held sheds no leaf here
            if (this.leavesFrame >= LEAVES_PER_FRAME) {
                this.leavesThinned = (this.leavesThinned || 0) + f.leaves.length - i;
                return;
            }
            this.leavesFrame++;
            const spawn = t_hdr - (f.hdr.tick - l.spawn_tick) / hz;
            if (!this.r.addFallingLeaf(tree, l.slot, l.seed, spawn, this.treeQ(tree))) this.leavesBad = (this.leavesBad || 0) + 1;
        }
    }

    // One tree's q at the time shown last, the blend the skeleton pass forms (null before
    // the first frame: at rest).
    treeQ(tree) {
        const w = this.shown_s === undefined ? null : this.jitter.weightsAt(this.shown_s);
        if (!w || !(tree < this.qTrees)) return null;
        const qw = blendWeights(w, this.welcome.instances[tree][0], this.qwTree), b = tree * this.stride, out = this.qTree;
        for (let m = 0; m < out.length; m++) {
            let v = 0;
            for (let k = 0; k < w.n; k++) v += qw[4 * m + k] * w.snaps[k].q[b + m];
            out[m] = v;
        }
        return out;
    }

    // The damage at server time shown_s into the renderer (client_damage_draw): the trees'
    // codes while a fall is under way or the picture changed, the cut lists when the
    // broken branches changed.
    applyDamage(shown_s) {
        const d = this.damage;
        if (!d) return;
        if (d.update(shown_s)) {
            const up = new Uint8Array(d.view.n_trees);
            for (let t = 0; t < up.length; t++) up[t] = d.view.fallen[t] === DAMAGE.UPROOT;
            this.r.setDamage(d.code, d.az, up);
        }
        if (d.view.generation !== this.damageGen) {
            const inst = this.welcome.instances;
            const cl = d.cutLists((t) => (this.r.species[inst[t][0]] ? this.r.species[inst[t][0]].n_nodes : 0));
            this.r.setCuts(cl.head, cl.nodes);
            this.damageGen = d.view.generation;
        }
        this.r.setDebris(d.debrisAt(shown_s, (p) => this.r.windAt(p)));
    }

    camera() {
        if (this.o.camera) return this.o.camera(this);
        const c = this.cam;
        // the orbit's subject: the point it turns about (client/app/client_frame.c)
        return { eye: orbitEye(c.target, c.distance, c.yaw, c.pitch), target: c.target, fov_y_deg: c.fov_y_deg, subject_m: c.distance };
    }

    // The governor's step into the frame: the LOD cap, the canvas's resolution, the HUD.
    applyGovernor() {
        if (!this.gov) return;
        this.resScale = this.gov.resScale();
        this.resize();
        if (this.r && this.r.lod) this.r.lod.cap = this.gov.lodScale();
        this.showHud();
    }

    // The HUD: the weather's lines, the governor's step when it draws less detail (as
    // gale-client's status line: "detail −2") and a reduced view's trees held.
    showHud() {
        if (!this.hudEl) return;
        const step = this.gov ? this.gov.step : 0;
        const detail = step > 0 ? [t(this.lang, 'hud.detail', step).replace(/^ · /, '')] : [];
        const reduced = this.reducedText();
        this.hudEl.textContent = this.hudLines.concat(detail, reduced ? [reduced] : []).join('\n');
    }

    // A reduced view's HUD line in the page's language (hud.reduced), '' for none.
    reducedText() {
        return this.held ? t(this.lang, 'hud.reduced', this.held.held.length, this.sceneWelcome.instances.length) : '';
    }

    // The server's schedule: the closed card (web/closed.js), kept to say it again in
    // another language.
    schedule(m) {
        this.lastSchedule = m;
        showSchedule(m, this.lang);
    }

    // The language the page speaks from the next line drawn (a code of lang_texts.js).
    setLang(code) {
        const l = langFind(code);
        if (!l) return false;
        this.lang = l;
        document.documentElement.lang = l;
        if (this.weather) this.hudLines = weatherLines(this.weather, l);
        if (this.lastSchedule) showSchedule(this.lastSchedule, l);
        this.showHud();
        if (this.o.onLang) this.o.onLang(l);
        return true;
    }

    frame(t_ms) {
        requestAnimationFrame((t) => this.frame(t));
        // the governor takes the time between frames the browser gave (the whole frame's)
        if (this.gov && this.lastFrame_ms !== undefined && this.ready && this.gov.frame(t_ms - this.lastFrame_ms, t_ms * 1e-3)) this.applyGovernor();
        this.lastFrame_ms = t_ms;
        if (this.r && this.r.lod && this.gov) this.r.lod.cap = this.gov.lodScale();
        if (this.frozen || !this.ready || !this.jitter || !this.jitter.snaps.length) return;
        const server = this.clock.serverTime(performance.now() * 1e-3);
        if (server === null) return;
        // a wall tile first presents the group frame it drew ahead, when its time has come
        if (this.o.beforeDraw) this.o.beforeDraw(this, server);
        // a wall tile shows its group's frame instant; others a fixed delay behind the server
        const shown = this.o.renderTime ? this.o.renderTime(this, server) : this.jitter.renderTime(server);
        if (shown === null) return;
        const t0 = performance.now();
        this.r.setMix(this.jitter.weights(shown));
        const t2 = performance.now();
        this.leavesFrame = 0;
        this.shown_s = shown;
        try {
            this.applyDamage(shown);
            // the shaders' clock (leaves, rain): a wall tile's is its frame's instant
            this.r.draw(this.camera(), this.o.shaderTime ? this.o.shaderTime(shown) : (t_ms * 1e-3) % 3600, this.modes, shown);
        } catch (e) {
            this.errors.push(e.message);
            this.say(`Drawing failed: ${e.message}`);
            this.ready = false;
            return;
        }
        const t3 = performance.now();
        this.sound.frame(shown, this.camera()); // the sound of what this frame shows
        this.followView(t3 * 1e-3);
        this.perf.cull.push(this.r.stats.cull_ms);
        this.perf.interp.push(t2 - t0 - this.r.stats.upload_ms);
        this.perf.upload.push(this.r.stats.upload_ms);
        this.perf.draw.push(t3 - t2);
        for (const k of Object.keys(this.perf)) if (this.perf[k].length > 2000) this.perf[k].splice(0, 1000);
        this.framesDrawn++;
        if (this.firstFrame_ms === null) this.firstFrame_ms = performance.now(); // since navigation start
        if (this.o.afterFrame) this.o.afterFrame(this);
    }

    // The stream's view after each frame: the frustum drawn, its far and LOD distances the
    // policy's as the frame's budget scaled them (web/lod_policy.js); the next hello carries
    // the last one sent.
    followView(now_s) {
        const r = this.r;
        if (!r.view || !this.conn) return;
        const sc = r.stats.lod_scale || 1, sf = r.stats.lod_scale_far || 1;
        if (this.held && this.held.view) {
            // a reduced view asks for the circle of its trees, whatever the camera does and
            // with ?view=all too: no tree past it can be drawn (client/app/client_view.c)
            const v = this.held.view;
            if (JSON.stringify(this.views.sent) !== JSON.stringify(v) && this.conn.send({ type: 'view', view: v })) {
                this.views.sent = v;
                this.views.count++;
            }
        } else if (this.followCamera) this.views.update(frustumView(frustumCone(r.view, r.viewproj), VIEW_FAR_M * sf, VIEW_LOD_M * sc), now_s);
        this.conn.o.view = this.views.sent;
        const b = this.bytesSeen;
        if (!b.length || now_s - b[b.length - 1][0] >= 0.5) {
            b.push([now_s, this.conn.stats.bytes]);
            if (b.length > 8) b.shift();
        }
    }

    // What the frames cost and what the stream carries, for tests and the benchmark: the
    // last frame's draw calls, triangles and vertices, trees drawn per level (a tree fading
    // into its impostor in both THIN and impostor), impostors drawn, the cull's CPU
    // time, views sent, the stream's bytes a second over the last few seconds (page
    // time: frames and views only advance while the page draws) and trees a snapshot.
    lodStats() {
        const s = this.r.stats, b = this.bytesSeen, now = performance.now() * 1e-3;
        const bytes = this.conn ? this.conn.stats.bytes : 0;
        return { draws: s.draws, triangles: s.triangles, vertices: s.vertices, trees_drawn: s.trees_drawn,
            trees_per_level: { full: (s.levels || [])[0] || 0, thin: (s.levels || [])[1] || 0, impostor: (s.levels || [])[2] || 0 },
            impostors: s.impostors || 0, lod_worst: s.lod_worst,
            cull_ms: s.cull_ms, lod_scale: s.lod_scale, lod_scale_far: s.lod_scale_far, cells_in_view: s.cells_in_view, views_sent: this.views.count, view: this.views.sent,
            stream_bytes_per_s: b.length && now > b[0][0] ? (bytes - b[0][1]) / (now - b[0][0]) : null,
            governor: this.gov ? { target_ms: this.gov.target_ms, step: this.gov.step, lod_scale: this.gov.lodScale(), res_scale: this.resScale, renderer: this.rendererName } : null,
            trees_per_snapshot: this.treesSent, trees_held: this.qTrees, scene_trees: this.sceneWelcome ? this.sceneWelcome.instances.length : 0,
            reduced: this.held ? { text: this.reducedText(), why: this.held.why, cx: this.held.circle.cx, cy: this.held.circle.cy, radius_m: this.held.circle.radius_m,
                edge_m: this.held.circle.edge_m, view: this.held.view } : null };
    }

    // Holds the newest n snapshots from now on (the jitter buffer and the GPU's ring grow;
    // at most the GPU's texture layers), for tests that draw an instant long past with
    // still(); returns the count held. Throws when the GPU refuses a ring that large
    // (SwiftShader refuses 240 snapshots of 100,000 trees × 32 modes, 1.5 GB): the ring
    // would read q = 0 and every tree be drawn at rest, which no picture shows as an error.
    holdSnapshots(n) {
        const gl = this.r.gl, layers = Math.min(n, gl.getParameter(gl.MAX_ARRAY_TEXTURE_LAYERS));
        for (let k = 0; k < 8 && gl.getError() !== gl.NO_ERROR; k++); // (earlier calls' errors are not its)
        this.jitter.grow(layers);
        this.r.setStride(this.stride, this.jitter.capacity);
        const e = gl.getError();
        if (e !== gl.NO_ERROR) {
            const mb = (this.qTrees * this.stride * 2 * this.jitter.capacity) / 1048576;
            throw new Error(`holdSnapshots(${n}): the GPU's ring of ${this.jitter.capacity} snapshots (${mb.toFixed(0)} MB) failed: GL error ${e}`);
        }
        return this.jitter.capacity;
    }

    // One frame of the state drawn last (or of the state at server time at_s), with or
    // without the trees, at shader time t_s, its pixels read back (RGBA rows bottom first,
    // base64) with the camera it was drawn with: for tests.
    still(showTrees, at_s = null, t_s = 0) {
        this.frozen = true;
        const cam = this.camera();
        this.r.hideTrees = !showTrees;
        if (at_s !== null) {
            this.r.setMix(this.jitter.weights(at_s));
            this.shown_s = at_s;
            this.applyDamage(at_s);
        }
        const off = this.r.offscreen;
        this.r.offscreen = false; // onto the canvas, read back below
        this.r.draw(cam, t_s, this.modes, this.shown_s);
        this.r.offscreen = off;
        this.r.hideTrees = false;
        const gl = this.r.gl, w = this.canvas.width, h = this.canvas.height;
        const px = new Uint8Array(w * h * 4);
        gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
        let bin = '';
        for (let i = 0; i < px.length; i += 0x8000) bin += String.fromCharCode.apply(null, px.subarray(i, i + 0x8000));
        return { w, h, cam, pixels: btoa(bin) };
    }

    perfSummary() {
        const out = {};
        // performance.now() is coarsened (0.1 ms here): the mean over many is finer than a median
        for (const [k, a] of Object.entries(this.perf)) {
            out[k] = { n: a.length, median_ms: percentile(a, 0.5), p95_ms: percentile(a, 0.95), mean_ms: a.length ? a.reduce((x, y) => x + y, 0) / a.length : null };
        }
        return out;
    }

    // drag to orbit, wheel to zoom (gale-client's orbit camera); no hover-only control
    attachControls() {
        if (this.o.camera) return;
        let last = null;
        this.canvas.addEventListener('pointerdown', (e) => { last = [e.clientX, e.clientY]; this.canvas.setPointerCapture(e.pointerId); });
        this.canvas.addEventListener('pointerup', () => { last = null; });
        this.canvas.addEventListener('pointermove', (e) => {
            if (!last) return;
            this.cam.yaw -= (e.clientX - last[0]) * 0.005;
            this.cam.pitch = Math.max(-1.5, Math.min(1.5, this.cam.pitch - (e.clientY - last[1]) * 0.005));
            last = [e.clientX, e.clientY];
        });
        this.canvas.addEventListener('wheel', (e) => {
            e.preventDefault();
            this.cam.distance = Math.max(2, Math.min(5000, this.cam.distance * Math.exp(e.deltaY * 0.001)));
        }, { passive: false });
    }
}
