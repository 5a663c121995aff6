// The jitter buffer and server clock of client/jitter.c, in JavaScript: decoded q
// snapshots held by server time and played out a fixed delay behind it, q interpolated by
// cubic Hermite with tangents from the parabola through neighbouring snapshots (C1, exact
// for quadratic motion); the clock offset from the pong of least round trip.

export class Jitter {
    constructor(n_values, capacity = 32, playout_delay_s = 0.1) {
        this.n_values = n_values;
        this.capacity = capacity;
        this.delay_s = playout_delay_s;
        this.snaps = []; // { tick, t, q: Float32Array }, sorted by tick
        this.spare = [];
        this.passed_t = -Infinity;
        this.stats = { inserted: 0, duplicates: 0, late: 0, out_of_order: 0, evicted: 0, underruns: 0 };
    }

    reset() {
        for (const s of this.snaps) this.spare.push(s.q);
        this.snaps = [];
        this.passed_t = -Infinity;
    }

    // 'inserted' | 'duplicate' | 'late'; throws on a time out of tick order. With scale,
    // the snapshot held is q[i] * scale[i] (web/wire.js sceneSteps: dequantised in the
    // copy, one pass).
    insert(tick, t_s, q, scale = null) {
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
            this.spare.push(s.shift().q);
            pos--;
            this.stats.evicted++;
        }
        if (pos < s.length) this.stats.out_of_order++;
        let buf = this.spare.pop();
        if (!buf || buf.length !== this.n_values) buf = new Float32Array(this.n_values);
        if (scale) {
            for (let i = 0; i < buf.length; i++) buf[i] = q[i] * scale[i];
        } else {
            buf.set(q);
        }
        s.splice(pos, 0, { tick, t: t_s, q: buf });
        this.stats.inserted++;
        return 'inserted';
    }

    // q at server time t into out; false when empty (out untouched).
    sample(t, out) {
        const s = this.snaps, n = s.length, nv = this.n_values;
        if (!n) return false;
        if (t > this.passed_t) this.passed_t = t;
        if (n === 1 || t <= s[0].t || t >= s[n - 1].t) {
            out.set(t <= s[0].t ? s[0].q : s[n - 1].q);
            if (t > s[n - 1].t) this.stats.underruns++;
            return true;
        }
        let i = 0;
        while (i + 2 < n && s[i + 1].t <= t) i++;
        const t1 = s[i].t, t2 = s[i + 1].t, h = t2 - t1, u = (t - t1) / h;
        let a0 = 0, a1 = -1 / h, a2 = 1 / h, b1 = -1 / h, b2 = 1 / h, b3 = 0;
        let q0 = null, q3 = null;
        if (i > 0) {
            [a0, a1, a2] = parabolaSlope(s[i - 1].t, t1, t2);
            q0 = s[i - 1].q;
        }
        if (i + 2 < n) {
            [b1, b2, b3] = parabolaSlope(t1, t2, s[i + 2].t);
            q3 = s[i + 2].q;
        }
        const u2 = u * u, u3 = u2 * u;
        const h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2, h11 = u3 - u2;
        const c0 = h10 * h * a0, c1 = h00 + h10 * h * a1 + h11 * h * b1;
        const c2 = h01 + h10 * h * a2 + h11 * h * b2, c3 = h11 * h * b3;
        const q1 = s[i].q, q2 = s[i + 1].q;
        if (q0 && q3) {
            for (let k = 0; k < nv; k++) out[k] = c0 * q0[k] + c1 * q1[k] + c2 * q2[k] + c3 * q3[k];
        } else {
            for (let k = 0; k < nv; k++) {
                out[k] = c1 * q1[k] + c2 * q2[k] + (q0 ? c0 * q0[k] : 0) + (q3 ? c3 * q3[k] : 0);
            }
        }
        return true;
    }

    renderTime(server_now_s) { return server_now_s - this.delay_s; }
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
