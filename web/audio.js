// The wind's sound in the page, on Web Audio: gale-client's design (client/audio, the numbers
// and laws of web/sound_policy.js) driven by the state the page already decodes. A wind bed
// of three noise bands whose level and centres follow the wind at the camera (the WIND
// grid's sample there, else WEATHER's sustained wind, swung by its gusts), aeolian tones of
// the diameter classes near the camera at St·U/d, leaf rustle clicks whose density rises
// with the speed and falls as crowns are stripped, and one-shots (a branch's crack, a
// stem's snap, an uprooting) started at the frame that shows them, panned by their bearing
// from the view and softer with distance. The master gain is the operator's volume
// (?volume=DB, ?quiet=1) and a visitor's step (] and [; back to the default when a kiosk
// goes idle), through a compressor and a clamp at the ceiling (?volume_max=DBFS), so no
// sample passes it. Browsers start audio only after a gesture: the context is made at once
// (a kiosk launched with --autoplay-policy=no-user-gesture-required plays from the start,
// attract loop included) and resumed by the first touch, click or key. A caption line says
// what is heard while the sound is on. ?sound=off: none of it.
import * as P from './sound_policy.js';
import { DAMAGE, damageEventStart_s } from './damage.js';

const LISTEN_EVERY_S = 0.25; // the trees near are summed four times a second
const RUSTLE_AHEAD_S = 0.05; // clicks are scheduled this far ahead of the context's clock
const GLIDE_S = 0.02;        // parameters glide to a new value over this time constant

// ?sound=off|on, ?volume=DB (-60..0), ?volume_max=DBFS (-40..0), ?quiet=1: the operator's
// loudness (gale-client's --sound, --volume, --volume-max, --quiet); errors name the key.
export function soundOptions(search) {
    const q = new URLSearchParams(search), errors = [];
    const num = (key, lo, def) => {
        const v = q.get(key);
        if (v === null) return def;
        const x = Number(v);
        if (v !== '' && Number.isFinite(x) && x >= lo && x <= 0) return x;
        errors.push(`${key}=${v}: expected ${lo}..0; ${def} is used`);
        return def;
    };
    const o = {
        on: q.get('sound') !== 'off',
        volume_db: num('volume', -60, P.SOUND_VOLUME_DB),
        ceiling_dbfs: num('volume_max', -40, P.SOUND_CEILING_DBFS),
        quiet: q.get('quiet') === '1' || q.get('quiet') === 'true',
        errors,
    };
    return o;
}

// xorshift32, as client/audio/sound_dsp.h: uniform in [-1, 1)
function noiseGen(seed) {
    let s = seed >>> 0 || 1;
    return () => {
        s ^= s << 13; s >>>= 0;
        s ^= s >>> 17;
        s ^= s << 5; s >>>= 0;
        return (s | 0) / 2147483648;
    };
}

// RBJ biquad (client/audio/sound_dsp.h) for the one-shots' buffers
function biquad(kind, f_hz, q, rate) {
    const w = 2 * Math.PI * Math.min(Math.max(f_hz, 5), 0.45 * rate) / rate, cw = Math.cos(w), al = Math.sin(w) / (2 * q);
    const a0 = 1 + al;
    let b0, b1, b2;
    if (kind === 'lp') { b0 = b2 = 0.5 * (1 - cw); b1 = 1 - cw; } else if (kind === 'hp') { b0 = b2 = 0.5 * (1 + cw); b1 = -(1 + cw); } else { b0 = al; b1 = 0; b2 = -al; }
    const c = [b0 / a0, b1 / a0, b2 / a0, -2 * cw / a0, (1 - al) / a0];
    let x1 = 0, x2 = 0, y1 = 0, y2 = 0;
    return (x) => {
        const y = c[0] * x + c[1] * x1 + c[2] * x2 - c[3] * y1 - c[4] * y2;
        x2 = x1; x1 = x; y2 = y1; y1 = y;
        return y;
    };
}

// One one-shot of kind at rate (client/audio/oneshot.c's recipe), peak near 1.
function oneshotBuffer(ctx, kind, seed) {
    const rate = ctx.sampleRate, n = Math.round(P.SOUND_EVENT_S[kind] * rate), buf = ctx.createBuffer(1, n, rate), out = buf.getChannelData(0);
    const nz = noiseGen(seed), u = () => 0.5 * (nz() + 1);
    const f0 = kind === P.SOUND_EV.UPROOT ? biquad('lp', 300, 0.707, rate) : biquad('bp', kind === P.SOUND_EV.CRACK ? 2500 : 1800, 0.8, rate);
    const f1 = biquad('hp', kind === P.SOUND_EV.UPROOT ? 1500 : 2000, 0.707, rate);
    let env = 0, phase = 0;
    const crackle = (hz) => {
        if (u() < hz / rate) env += 0.4 + 0.6 * u();
        const x = f1(env * nz());
        env *= Math.exp(-1 / (0.004 * rate));
        return x;
    };
    for (let i = 0; i < n; i++) {
        const s = i / rate, x = nz(), click = s < 0.0015 ? x : 0;
        let y;
        if (kind === P.SOUND_EV.CRACK) {
            const e = s < 0.001 ? s / 0.001 : Math.exp(-(s - 0.001) / 0.03);
            y = click + e * 1.6 * f0(x);
        } else if (kind === P.SOUND_EV.SNAP) {
            const e = s < 0.001 ? s / 0.001 : Math.exp(-(s - 0.001) / 0.05);
            const w = Math.exp(-s / 0.12) * (0.35 * Math.sin(2 * Math.PI * 180 * s) + 0.25 * Math.sin(2 * Math.PI * 410 * s) + 0.15 * Math.sin(2 * Math.PI * 730 * s));
            y = click + 0.7 * e * 1.2 * f0(x) + w + 0.4 * crackle(220 * Math.exp(-s / 0.2));
        } else {
            phase += 2 * Math.PI * (38 + 32 * Math.exp(-s / 0.15)) / rate;
            const e = s < 0.015 ? s / 0.015 : Math.exp(-(s - 0.015) / 0.35);
            y = click + 0.7 * e * Math.sin(phase) + 1.2 * Math.exp(-s / 0.5) * f0(x) + 0.35 * crackle(140 * Math.exp(-s / 0.5));
        }
        out[i] = y;
    }
    return buf;
}

// Scale giving unit RMS out of a filter of centre f and q fed uniform noise (wind_bed.c).
function unitRms(lowpass, f_hz, q, rate) {
    return Math.sqrt(1.5 * rate / (Math.PI / 2 * f_hz / (lowpass ? 1 : q)));
}

// Web Audio's low- and high-pass Q is a resonance in dB; the policy's is the filter's Q.
const qDb = (q) => 20 * Math.log10(q);

export class Sound {
    // app: web/app.js's App (its weather, wind, camera, damage and assets); opts: soundOptions()
    constructor(app, opts) {
        this.app = app;
        this.o = opts;
        const l = P.resolveLoudness(opts.volume_db, opts.ceiling_dbfs, opts.quiet);
        this.volume_db = l.volume_db;
        this.ceiling_dbfs = l.ceiling_dbfs;
        this.visitor_db = 0;
        this.ctx = null;
        this.prof = [];            // species index → { class_len_m, leaves }
        this.pending = [];         // damage events new to the picture: { tree, kind, t0_s }
        this.log = [];             // one entry per event sounded: frame and sound times
        this.scene = { u_ms: 0, gust: 1, class_len_m: new Array(P.SOUND_CLASSES).fill(0), leaves_w: 0, kept: 1 };
        this.u_rustle = 0;
        this.listen_at_s = -Infinity;
        this.last_event = -1;
        this.last_event_s = -Infinity;
        this.held = false;
        this.targets = null;
        this.caption = '';
        this.gust = { a: 0, b: 0, t: 0 };
        this.rng = noiseGen(0x6a1e5eed);
    }

    // The gesture that starts the sound, the visitor's keys, and the autoplay attempt.
    attach() {
        if (!this.o.on) return;
        const go = () => this.start();
        for (const type of ['pointerdown', 'keydown', 'touchstart']) window.addEventListener(type, go, { capture: true, passive: true });
        window.addEventListener('keydown', (e) => {
            if (e.key === ']') this.visitorStep(1);
            else if (e.key === '[') this.visitorStep(-1);
        });
        // a kiosk whose browser allows autoplay plays from the start (attract loop included)
        try {
            this.start();
        } catch (e) {
            this.app.errors.push(`sound: ${e.message}`);
        }
    }

    running() {
        return !!this.ctx && this.ctx.state === 'running';
    }

    // The output device as the kiosk will report it: the context's sink ('' the default)
    // while it runs, 'null' otherwise.
    deviceName() {
        if (!this.running()) return 'null';
        return typeof this.ctx.sinkId === 'string' && this.ctx.sinkId ? this.ctx.sinkId : 'default';
    }

    start() {
        if (!this.o.on) return;
        if (!this.ctx) {
            const AC = window.AudioContext || window.webkitAudioContext;
            if (!AC) {
                this.o.on = false;
                this.app.errors.push('sound: this browser has no Web Audio');
                return;
            }
            this.ctx = new AC({ latencyHint: 'interactive' });
            // the kiosk reports its device again when it starts or stops (kiosk_state)
            this.ctx.addEventListener('statechange', () => this.app.o.onSoundState && this.app.o.onSoundState());
            this.build();
        }
        if (this.ctx.state !== 'running') this.ctx.resume().catch(() => {});
    }

    build() {
        const ctx = this.ctx, rate = ctx.sampleRate, n = 4 * rate;
        const noise = ctx.createBuffer(2, n, rate);
        for (let ch = 0; ch < 2; ch++) {
            const d = noise.getChannelData(ch), g = noiseGen(0x9e3779b9 + 7919 * ch);
            for (let i = 0; i < n; i++) d[i] = g();
        }
        const src = (offset) => {
            const s = ctx.createBufferSource();
            s.buffer = noise;
            s.loop = true;
            s.start(0, offset % 4);
            return s;
        };
        // master: volume, a compressor just under the ceiling, a clamp at it
        this.master = ctx.createGain();
        this.comp = ctx.createDynamicsCompressor();
        this.clamp = ctx.createWaveShaper();
        this.setCeiling(this.ceiling_dbfs);
        this.master.connect(this.comp).connect(this.clamp).connect(ctx.destination);
        this.master.gain.value = P.dbToGain(this.volume_db + this.visitor_db);
        this.bands = [];
        const types = ['lowpass', 'bandpass', 'bandpass'], qs = [P.SOUND_RUMBLE_Q, P.SOUND_BODY_Q, P.SOUND_HOWL_Q];
        for (let k = 0; k < P.SOUND_BANDS; k++) {
            const f = ctx.createBiquadFilter(), g = ctx.createGain();
            f.type = types[k];
            f.Q.value = k === 0 ? qDb(qs[k]) : qs[k];
            f.frequency.value = P.bandHz(k, 0);
            g.gain.value = 0;
            src(0.7 * k).connect(f).connect(g).connect(this.master);
            this.bands.push({ f, g });
        }
        this.tones = [];
        for (let k = 0; k < P.SOUND_CLASSES; k++) {
            const f = ctx.createBiquadFilter(), g = ctx.createGain();
            f.type = 'bandpass';
            f.Q.value = P.SOUND_AEOL_Q;
            f.frequency.value = 1000;
            g.gain.value = 0;
            src(2.1 + 0.3 * k).connect(f).connect(g).connect(this.master);
            this.tones.push({ f, g });
        }
        // rustle: clicks (noise decaying over SOUND_RUSTLE_DECAY_MS) through one high-pass
        this.rustleHp = ctx.createBiquadFilter();
        this.rustleHp.type = 'highpass';
        this.rustleHp.frequency.value = P.SOUND_RUSTLE_HP_HZ;
        this.rustleHp.Q.value = qDb(0.707);
        this.rustleHp.connect(this.master);
        const cn = Math.round(6 * P.SOUND_RUSTLE_DECAY_MS * 1e-3 * rate), click = ctx.createBuffer(1, cn, rate), cd = click.getChannelData(0), cg = noiseGen(0x85ebca6b);
        for (let i = 0; i < cn; i++) cd[i] = cg() * Math.exp(-i / (P.SOUND_RUSTLE_DECAY_MS * 1e-3 * rate));
        this.click = click;
        this.rustleAt = 0;
        this.shots = [0, 1, 2].map((k) => oneshotBuffer(ctx, k, 0x1234567 + 977 * k));
    }

    // The clamp at ceiling_dbfs (a WaveShaper whose curve is min(max(x, -c), c)) and the
    // compressor just under it.
    setCeiling(dbfs) {
        const c = P.dbToGain(dbfs), m = 4097, curve = new Float32Array(m);
        for (let i = 0; i < m; i++) curve[i] = Math.min(Math.max(-1 + 2 * i / (m - 1), -c), c);
        this.clamp.curve = curve;
        this.clamp.oversample = 'none';
        this.comp.threshold.value = dbfs - 3;
        this.comp.knee.value = 3;
        this.comp.ratio.value = 20;
        this.comp.attack.value = 0.001;
        this.comp.release.value = P.SOUND_LIMIT_RELEASE_MS * 1e-3;
    }

    visitorStep(dir) {
        this.visitor_db = Math.min(Math.max(this.visitor_db + (dir > 0 ? 1 : -1) * P.SOUND_VISITOR_STEP_DB, P.SOUND_VISITOR_MIN_DB), P.SOUND_VISITOR_MAX_DB);
        this.applyVolume();
    }

    // a kiosk gone idle: the next visitor starts at the operator's volume
    visitorReset() {
        this.visitor_db = 0;
        this.applyVolume();
    }

    applyVolume() {
        if (this.master) this.master.gain.setTargetAtTime(P.dbToGain(this.volume_db + this.visitor_db), this.ctx.currentTime, GLIDE_S);
    }

    // A species' asset (web/asset.js) by its welcome index.
    addSpecies(i, asset) {
        this.prof[i] = P.speciesProfile(asset);
    }

    // A frame's DAMAGE, before the page applies it (view: the damage before): the snaps,
    // uproots and broken branches new to the picture and recent, to sound when shown.
    onDamage(hdr, d, view, tick_hz) {
        if (!this.o.on) return;
        for (const e of d.events) {
            if (e.tree >= view.n_trees) continue;
            const t0 = damageEventStart_s(hdr.tick, hdr.server_time_us, e.tick, tick_hz);
            if (Number.isNaN(t0)) continue; // an old event shows its end, silently
            let kind = -1;
            if ((e.kind === DAMAGE.SNAP || e.kind === DAMAGE.UPROOT) && !view.fallen[e.tree]) kind = e.kind === DAMAGE.SNAP ? P.SOUND_EV.SNAP : P.SOUND_EV.UPROOT;
            else if (e.kind === DAMAGE.BRANCH && !view.isBroken(e.tree, e.node)) kind = P.SOUND_EV.CRACK;
            if (kind >= 0 && this.pending.length < 64) this.pending.push({ tree: e.tree, kind, t0_s: t0 });
        }
    }

    // The wind at the listener: the WIND grid at the camera's ground point, SOUND_LISTEN_Z_M
    // up, else WEATHER's sustained wind; WEATHER's gust factor.
    listenerWind(eye) {
        const a = this.app, wx = a.weather;
        let u = wx ? wx.sustained_ms : 0;
        if (a.lastWind && a.r && a.r.windAt) {
            const w = a.r.windAt([eye[0], eye[1], P.SOUND_LISTEN_Z_M]);
            if (w) u = Math.hypot(w[0], w[1], w[2]);
        }
        this.scene.u_ms = Number.isFinite(u) ? u : 0;
        this.scene.gust = wx && wx.sustained_ms > 0.5 ? Math.max(wx.gust_ms / wx.sustained_ms, 1) : 1;
    }

    // the gust curve (sound_mix.c gust_swing)
    gustSwing(dt) {
        const g = this.gust;
        g.t += dt * P.SOUND_GUST_HZ;
        while (g.t >= 1) { g.t -= 1; g.a = g.b; g.b = 0.5 * (this.rng() + 1); }
        return g.a + (g.b - g.a) * (0.5 - 0.5 * Math.cos(Math.PI * g.t));
    }

    // After the frame of server time shown_s is drawn from cam ({ eye, ... }).
    frame(shown_s, cam) {
        if (!this.o.on) return;
        const a = this.app, now_s = performance.now() * 1e-3, eye = cam.eye;
        this.listenerWind(eye);
        if (a.welcome && a.ready && now_s - this.listen_at_s >= LISTEN_EVERY_S) {
            const d = a.damage && a.damage.view;
            Object.assign(this.scene, P.listen(eye, a.welcome.instances, this.prof, d ? (t) => d.fallen[t] : null, d ? (t) => d.level[t] : null));
            this.listen_at_s = now_s;
        }
        const dt = this.last_s === undefined ? 0 : Math.min(now_s - this.last_s, 0.5);
        this.last_s = now_s;
        this.u_rustle = this.u_rustle + (this.scene.u_ms - this.u_rustle) * (1 - Math.exp(-dt / P.SOUND_RUSTLE_LAG_S));
        if (this.first === undefined) { this.first = true; this.u_rustle = this.scene.u_ms; }
        const swing = 1 + P.SOUND_GUST_DEPTH * Math.max(this.scene.gust - 1, 0) * this.gustSwing(dt);
        const u = this.scene.u_ms * swing, ur = this.u_rustle * swing, s = this.scene;
        const rate = this.ctx ? this.ctx.sampleRate : P.SOUND_RATE_HZ;
        const t = {
            u_ms: u,
            bands: [0, 1, 2].map((k) => {
                const hz = P.bandHz(k, u) * (k === P.SOUND_BAND.HOWL ? 1 + P.SOUND_HOWL_WANDER * Math.sin(2 * Math.PI * P.SOUND_HOWL_WANDER_HZ * now_s) : 1);
                return { frequency: hz, gain: P.bandGain(k, u) * unitRms(k === 0, hz, [P.SOUND_RUMBLE_Q, P.SOUND_BODY_Q, P.SOUND_HOWL_Q][k], rate) };
            }),
            tones: P.SOUND_CLASS_D_M.map((d, k) => {
                const db = P.aeolDb(s.class_len_m[k], u, d), hz = P.strouhalHz(u, d);
                return { frequency: hz, db, gain: Number.isFinite(db) ? P.dbToGain(db) * Math.sqrt(1.5 * rate / (Math.PI / 2 * hz / P.SOUND_AEOL_Q)) : 0 };
            }),
            rustle_hz: P.rustleHz(ur, s.leaves_w, s.kept),
            rustle_db: P.rustleDb(ur),
        };
        if (!this.held) this.targets = t;
        if (this.running() && !this.held) this.apply(t, dt);
        this.fireDue(shown_s, cam, now_s);
        // the caption line while the sound is on
        const ev = this.last_event >= 0 && now_s - this.last_event_s < P.SOUND_CAPTION_EVENT_S ? this.last_event : -1;
        const loud = Math.max(...t.tones.map((x) => x.db));
        this.caption = P.captionLine(P.captionPick(s.u_ms, P.rustleHz(s.u_ms, s.leaves_w, s.kept), loud, ev), this.app.lang);
        this.showCaption();
    }

    apply(t, dt) {
        const c = this.ctx, now = c.currentTime;
        t.bands.forEach((b, k) => {
            this.bands[k].f.frequency.setTargetAtTime(b.frequency, now, GLIDE_S);
            this.bands[k].g.gain.setTargetAtTime(b.gain, now, GLIDE_S);
        });
        t.tones.forEach((x, k) => {
            if (x.gain > 0) this.tones[k].f.frequency.setTargetAtTime(Math.min(x.frequency, 0.45 * c.sampleRate), now, GLIDE_S);
            this.tones[k].g.gain.setTargetAtTime(x.gain, now, GLIDE_S);
        });
        // rustle clicks for this frame's time, a Poisson process, scheduled just ahead
        const amp = P.dbToGain(t.rustle_db);
        let at = Math.max(this.rustleAt, now + RUSTLE_AHEAD_S);
        const until = now + RUSTLE_AHEAD_S + dt;
        for (let k = 0; t.rustle_hz > 0 && k < 64; k++) {
            at += -Math.log(1 - 0.5 * (this.rng() + 1) * 0.999999) / t.rustle_hz;
            if (at >= until) break;
            const s = c.createBufferSource(), p = c.createStereoPanner(), g = c.createGain();
            s.buffer = this.click;
            p.pan.value = 0.8 * this.rng();
            g.gain.value = amp * (0.3 + 0.7 * 0.5 * (this.rng() + 1));
            s.connect(g).connect(p).connect(this.rustleHp);
            s.start(at);
        }
        this.rustleAt = Math.min(at, until);
    }

    // The events the frame of shown_s shows, started now; each logged with the frame's time
    // and when its sound leaves the speakers (the context's output timestamp), both on the
    // page's clock (performance.now).
    fireDue(shown_s, cam, now_s) {
        const a = this.app, keep = [], look = Math.atan2(cam.target[1] - cam.eye[1], cam.target[0] - cam.eye[0]);
        for (const e of this.pending) {
            if (e.t0_s > shown_s) { keep.push(e); continue; }
            const r = a.welcome && a.welcome.instances[e.tree];
            if (!r) continue;
            const d = [r[1] - cam.eye[0], r[2] - cam.eye[1], r[3] + 5 - cam.eye[2]], dist = Math.hypot(d[0], d[1], d[2]);
            let rel = Math.atan2(d[1], d[0]) - look;
            rel = Math.atan2(Math.sin(rel), Math.cos(rel));
            const db = P.eventLevelDb(e.kind, dist);
            if (!Number.isFinite(db)) continue;
            this.last_event = e.kind;
            this.last_event_s = now_s;
            const entry = { kind: ['crack', 'snap', 'uproot'][e.kind], tree: e.tree, dist_m: dist, bearing_deg: rel * 180 / Math.PI, level_db: db, frame_s: now_s, sound_s: null, gap_ms: null };
            if (this.running()) {
                const c = this.ctx, s = c.createBufferSource(), p = c.createStereoPanner(), g = c.createGain(), start = c.currentTime;
                s.buffer = this.shots[e.kind];
                p.pan.value = P.soundPan(rel);
                g.gain.value = P.dbToGain(db + (this.o.quiet ? P.SOUND_QUIET_EVENT_DB : 0));
                s.connect(g).connect(p).connect(this.master);
                s.start(start);
                const ts = c.getOutputTimestamp ? c.getOutputTimestamp() : null;
                entry.sound_s = ts && ts.performanceTime ? (ts.performanceTime + 1e3 * (start - ts.contextTime)) * 1e-3 + (c.outputLatency || 0) : now_s + (c.baseLatency || 0) + (c.outputLatency || 0);
                entry.gap_ms = 1e3 * (entry.sound_s - entry.frame_s);
            }
            this.log.push(entry);
            if (this.log.length > 200) this.log.shift();
            console.log(`sound ${entry.kind} tree ${entry.tree} dist_m ${dist.toFixed(1)} bearing_deg ${entry.bearing_deg.toFixed(0)} level_db ${db.toFixed(1)} frame_s ${entry.frame_s.toFixed(4)} sound_s ${entry.sound_s === null ? 'none' : entry.sound_s.toFixed(4)} gap_ms ${entry.gap_ms === null ? 'none' : entry.gap_ms.toFixed(1)}`);
        }
        this.pending = keep;
    }

    // The caption line: an element of its own over the scene, shown while the sound is on.
    showCaption() {
        let el = document.getElementById('sound-caption');
        if (!el) {
            el = document.createElement('div');
            el.id = 'sound-caption';
            el.className = 'sound-caption';
            el.setAttribute('aria-hidden', 'true'); // the HUD's line tells screen readers the wind
            Object.assign(el.style, { textAlign: 'center', color: '#fff', textShadow: '0 0 4px #000', font: '600 1.2rem system-ui, sans-serif', pointerEvents: 'none' });
            // on the kiosk page just above the wind's caption, clear of its panel; elsewhere
            // over the lower scene
            const cap = document.getElementById('caption');
            if (cap && cap.parentNode) cap.parentNode.insertBefore(el, cap);
            else {
                Object.assign(el.style, { position: 'fixed', left: '0', right: '0', bottom: '22%' });
                document.body.append(el);
            }
        }
        const on = this.running() && this.caption !== '';
        el.hidden = !on;
        if (on && el.textContent !== this.caption) el.textContent = this.caption;
    }

    // Stop following the scene (the graph holds its values), or follow it again: for tests.
    hold(on) {
        if (on && !this.held && this.running() && this.targets) this.apply(this.targets, 0);
        this.held = !!on;
    }

    // The graph's parameters as the audio thread has them, and what they were set towards.
    params() {
        const c = this.ctx;
        return {
            state: c ? c.state : 'none', sample_rate: c ? c.sampleRate : null, device: this.deviceName(),
            volume_db: this.volume_db, visitor_db: this.visitor_db, ceiling_dbfs: this.ceiling_dbfs,
            master_gain: this.master ? this.master.gain.value : null,
            clamp_max: this.clamp ? Math.max(...this.clamp.curve) : null,
            bands: this.bands ? this.bands.map((b) => ({ type: b.f.type, frequency: b.f.frequency.value, Q: b.f.Q.value, gain: b.g.gain.value })) : [],
            tones: this.tones ? this.tones.map((x) => ({ frequency: x.f.frequency.value, gain: x.g.gain.value })) : [],
            scene: { ...this.scene, class_len_m: [...this.scene.class_len_m] },
            targets: this.targets, caption: this.caption, log: this.log.slice(),
        };
    }
}
