// The jitter buffer and server clock of client/playout/jitter.c, in JavaScript: snapshots held by
// server time and played out a fixed delay behind it, q interpolated by cubic Hermite with
// tangents from the parabola through neighbouring snapshots (C1, exact for quadratic
// motion); the clock offset from the pong of least round trip. The page does not blend the
// values here: weights() gives the (up to four) snapshots and their weights at a time, and
// the skeleton pass blends the snapshots' quantised values on the GPU (shaders/skel.frag,
// GALE_Q_RING), each held once in a layer of a texture ring: its slot here.

export class Jitter {
    constructor(n_values, capacity = 32, playout_delay_s = 0.1) {
        this.n_values = n_values;
        this.capacity = capacity;
        this.delay_s = playout_delay_s;
        this.snaps = []; // { tick, t, q (a copy, of q's type), meta, slot }, sorted by tick
        this.spare = [];
        this.slots = Array.from({ length: capacity }, (_, k) => capacity - 1 - k); // free slots
        this.passed_t = -Infinity;
        this.last = null; // the snapshot the last insert took
        this.w = { n: 0, snaps: [null, null, null, null], c: new Float64Array(4) };
        this.stats = { inserted: 0, duplicates: 0, late: 0, out_of_order: 0, evicted: 0, underruns: 0 };
    }

    // Room for n snapshots (never less than now): new slots n_old..n-1.
    grow(n) {
        for (let k = this.capacity; k < n; k++) this.slots.unshift(k);
        this.capacity = Math.max(this.capacity, n);
    }

    release(s) {
        this.spare.push(s.q);
        this.slots.push(s.slot);
    }

    reset() {
        for (const s of this.snaps) this.release(s);
        this.snaps = [];
        this.passed_t = -Infinity;
    }

    // 'inserted' | 'duplicate' | 'late'; throws on a time out of tick order. q is copied
    // (the decoder reuses its arrays); meta rides along (the page's: the keyframe scene,
    // whose steps dequantise q). The snapshot taken is this.last, in slot this.last.slot.
    insert(tick, t_s, q, meta = null) {
        if (!Number.isFinite(t_s)) throw new Error(`snapshot tick ${tick}: server time not finite`);
        if (t_s < this.passed_t) { this.stats.late++; return 'late'; }
        const s = this.snaps;
        let pos = s.length;
        while (pos > 0 && s[pos - 1].tick >= tick) pos--;
        if (pos < s.length && s[pos].tick === tick) { this.stats.duplicates++; return 'duplicate'; }
        if ((pos > 0 && !(s[pos - 1].t < t_s)) || (pos < s.length && !(t_s < s[pos].t))) {
            throw new Error(`snapshot tick ${tick}: server time ${t_s.toFixed(6)} s out of tick order with its neighbours`);
        }
        if (s.length === this.capacity) {
            if (pos === 0) { this.stats.late++; return 'late'; }
            this.release(s.shift());
            pos--;
            this.stats.evicted++;
        }
        if (pos < s.length) this.stats.out_of_order++;
        let buf = this.spare.pop();
        if (!buf || buf.length !== this.n_values || buf.constructor !== q.constructor) buf = new q.constructor(this.n_values);
        buf.set(q.length > this.n_values ? q.subarray(0, this.n_values) : q);
        this.last = { tick, t: t_s, q: buf, meta, slot: this.slots.pop() };
        s.splice(pos, 0, this.last);
        this.stats.inserted++;
        return 'inserted';
    }

    // The snapshots and weights of server time t (jitter_sample's): q(t) = Σ_k<w.n c[k]
    // snaps[k].q; one snapshot of weight 1 when t is outside them (held). null when empty.
    // Counts the sample (playout passed t, or past the newest, an underrun, only the
    // newest's time: jitter_sample's). w is reused.
    weights(t) {
        const s = this.snaps, n = s.length;
        if (!n) return null;
        const played = Math.min(t, s[n - 1].t);
        if (played > this.passed_t) this.passed_t = played;
        if (t > s[n - 1].t) this.stats.underruns++;
        return this.weightsAt(t);
    }

    // weights(t) without counting it.
    weightsAt(t) {
        const s = this.snaps, n = s.length, w = this.w;
        if (!n) return null;
        if (n === 1 || t <= s[0].t || t >= s[n - 1].t) {
            w.n = 1;
            w.snaps[0] = t <= s[0].t ? s[0] : s[n - 1];
            w.c[0] = 1;
            return w;
        }
        let i = 0;
        while (i + 2 < n && s[i + 1].t <= t) i++;
        const t1 = s[i].t, t2 = s[i + 1].t, h = t2 - t1, u = (t - t1) / h;
        let a0 = 0, a1 = -1 / h, a2 = 1 / h, b1 = -1 / h, b2 = 1 / h, b3 = 0;
        if (i > 0) [a0, a1, a2] = parabolaSlope(s[i - 1].t, t1, t2);
        if (i + 2 < n) [b1, b2, b3] = parabolaSlope(t1, t2, s[i + 2].t);
        const u2 = u * u, u3 = u2 * u;
        const h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2, h11 = u3 - u2;
        w.n = 0;
        const put = (snap, c) => { w.snaps[w.n] = snap; w.c[w.n++] = c; };
        put(s[i], h00 + h10 * h * a1 + h11 * h * b1);
        put(s[i + 1], h01 + h10 * h * a2 + h11 * h * b2);
        if (i > 0) put(s[i - 1], h10 * h * a0);
        if (i + 2 < n) put(s[i + 2], h11 * h * b3);
        return w;
    }

    renderTime(server_now_s) { return server_now_s - this.delay_s; }
}

// The blend of weights w (Jitter.weights) as the skeleton pass forms it for the trees of
// species s (shaders/skel.frag u_qw): qw[4 m + k] = c_k step_k[s][m], the weight of the
// quantised value of mode m in snapshot k, step_k the steps of snapshot k's keyframe scene
// (its meta), 0 past that scene's modes of s and for k >= w.n; q_m = Σ_k qw[4 m + k] Q_k.
export function blendWeights(w, s, qw) {
    qw.fill(0);
    for (let k = 0; k < w.n; k++) {
        const c = w.c[k], st = w.snaps[k].meta.step[s];
        if (st) for (let m = 0; m < st.length && 4 * m < qw.length; m++) qw[4 * m + k] = c * st[m];
    }
    return qw;
}

function parabolaSlope(ta, tb, tc) {
    const dab = tb - ta, dbc = tc - tb, dac = tc - ta;
    return [-dbc / (dab * dac), dbc / (dab * dac) - dab / (dbc * dac), dab / (dbc * dac)];
}

// Server clock from ping/pong (NTP style): offset = t_server − (t_sent + t_recv) / 2 of the
// sample of least round trip among the last 16; before any pong, the largest
// t_server − t_recv of arriving snapshots.
export class Clock {
    constructor() { this.samples = []; this.arrival_max = -Infinity; }
    pong(t_sent, t_server, t_recv) {
        if (!(t_recv >= t_sent) || !Number.isFinite(t_server)) return;
        this.samples.push({ off: t_server - 0.5 * (t_sent + t_recv), rtt: t_recv - t_sent });
        if (this.samples.length > 16) this.samples.shift();
    }
    arrival(t_server, t_recv) { this.arrival_max = Math.max(this.arrival_max, t_server - t_recv); }
    serverTime(local) {
        if (this.samples.length) {
            let b = this.samples[0];
            for (const s of this.samples) if (s.rtt < b.rtt) b = s;
            return local + b.off;
        }
        return Number.isFinite(this.arrival_max) ? local + this.arrival_max : null;
    }
    reset() { this.samples = []; this.arrival_max = -Infinity; }
}
