// One WebSocket connection to gale-server as PROTOCOL.md describes it: hello, welcome,
// state frames through web/wire.js (resync after a gap), ping/pong for the clock, and
// every close code turned into what the page says and does: retry with a doubling backoff
// (0.25 s to 5 s, ±20 %, as gale-client), except a refused kiosk token, which waits for a
// new one.
import { Decoder, WireError } from './wire.js';

export const PROTOCOL = 1;
export const CLOSE = {
    NORMAL: 1000, GOING_AWAY: 1001, ABNORMAL: 1006, BAD_JSON: 4000, UNKNOWN_TYPE: 4001,
    BAD_FIELD: 4002, VERSION: 4003, TOO_BIG: 4004, BINARY: 4005, FORBIDDEN: 4006,
    BAD_TOKEN: 4007, SLOW: 4008, ORDER: 4009, FULL: 4010, BAD_FRAME: 4011, RATE: 4012,
};

// What a person reads for a close, and whether retrying can help.
export function describeClose(code, message, host, everConnected) {
    const why = message ? ` (${message})` : '';
    switch (code) {
    case CLOSE.BAD_TOKEN:
        return { retry: false, text: `The kiosk token was refused${why}. Type the token set on the server (gale-server --kiosk-token-file).` };
    case CLOSE.VERSION:
        return { retry: true, text: `Version mismatch: this page speaks gale protocol ${PROTOCOL} and the server at ${host} refused it${why}. Reload the page once the server and page match.` };
    case CLOSE.FULL:
        return { retry: true, text: `The server at ${host} is full${why}. Retrying.` };
    case CLOSE.GOING_AWAY:
        return { retry: true, text: `The server at ${host} is restarting. Reconnecting.` };
    case CLOSE.SLOW:
        return { retry: true, text: `This screen fell too far behind the server${why}. Reconnecting.` };
    case CLOSE.BAD_FRAME:
        return { retry: true, text: `A frame from ${host} could not be decoded${why}. Reconnecting.` };
    case CLOSE.ABNORMAL: case 1005:
        return { retry: true, text: everConnected ? `Lost the connection to ${host}. Reconnecting.` : `Cannot reach the gale server at ${host}: is gale-server running and the address right? Retrying.` };
    case CLOSE.NORMAL:
        return { retry: true, text: `The server at ${host} closed the connection. Reconnecting.` };
    default:
        return { retry: true, text: `The server at ${host} closed the connection with ${code}${why}. Retrying.` };
    }
}

export class Connection {
    // opts: { url, role, token?, view?, extraHello?, onWelcome(w), onFrame(f, bytes),
    // onText(msg), onStatus(status), onLive() }
    constructor(opts) {
        this.o = opts;
        this.decoder = new Decoder();
        this.backoff_s = 0.25;
        this.attempt = 0;
        this.everConnected = false;
        this.stats = { frames: 0, bytes: 0, errors: 0, resyncs: 0, lastError: '' };
        this.status = { state: 'idle' };
        this.pingId = 0;
        this.pings = new Map();
        this.stopped = false;
    }

    host() { return new URL(this.o.url).host; }

    setStatus(s) {
        this.status = s;
        if (this.o.onStatus) this.o.onStatus(s);
    }

    start() {
        this.stopped = false;
        clearTimeout(this.retryTimer);
        this.open();
    }

    stop() {
        this.stopped = true;
        clearTimeout(this.retryTimer);
        clearInterval(this.pingTimer);
        if (this.ws) this.ws.close(CLOSE.NORMAL);
    }

    open() {
        this.setStatus({ state: 'connecting', attempt: this.attempt });
        this.decoder.reset();
        this.serverError = null;
        let ws;
        try {
            ws = new WebSocket(this.o.url);
        } catch (e) {
            this.lost(CLOSE.ABNORMAL, e.message);
            return;
        }
        this.ws = ws;
        ws.binaryType = 'arraybuffer';
        ws.onopen = () => {
            const hello = { type: 'hello', protocol: PROTOCOL, role: this.o.role, ...(this.o.extraHello || {}) };
            if (this.o.view) hello.view = this.o.view;
            if (this.o.token) hello.token = this.o.token;
            ws.send(JSON.stringify(hello));
        };
        ws.onmessage = (ev) => (typeof ev.data === 'string' ? this.text(ev.data) : this.binary(ev.data));
        ws.onclose = (ev) => {
            if (ws !== this.ws) return;
            this.ws = null;
            clearInterval(this.pingTimer);
            const err = this.serverError;
            this.lost(err && [CLOSE.NORMAL, 1005, CLOSE.ABNORMAL].includes(ev.code) ? err.code : ev.code, (err && err.message) || ev.reason);
        };
    }

    lost(code, message) {
        const d = describeClose(code, message, this.host(), this.everConnected);
        this.stats.lastClose = code;
        if (this.stopped) return;
        if (!d.retry) {
            this.setStatus({ state: 'refused', code, text: d.text });
            return;
        }
        this.attempt++;
        const wait = this.backoff_s * (0.8 + 0.4 * Math.random());
        this.backoff_s = Math.min(this.backoff_s * 2, 5);
        this.setStatus({ state: 'backoff', code, text: d.text, attempt: this.attempt, retry_in_s: wait });
        this.retryTimer = setTimeout(() => this.open(), wait * 1000);
    }

    send(msg) {
        if (this.ws && this.ws.readyState === WebSocket.OPEN) {
            this.ws.send(JSON.stringify(msg));
            return true;
        }
        return false;
    }

    text(data) {
        let m;
        try {
            m = JSON.parse(data);
        } catch (e) {
            this.stats.errors++;
            this.stats.lastError = `control message dropped: ${e.message}`;
            return;
        }
        if (m.type === 'welcome') {
            if (m.protocol !== PROTOCOL) {
                this.serverError = { code: CLOSE.VERSION, message: `welcome.protocol: expected ${PROTOCOL}, got ${m.protocol}` };
                this.ws.close(CLOSE.NORMAL);
                return;
            }
            this.everConnected = true;
            this.attempt = 0;
            this.backoff_s = 0.25;
            this.setStatus({ state: 'live', role: m.role });
            this.pingTimer = setInterval(() => this.ping(), 1000);
            this.ping();
            if (this.o.onWelcome) this.o.onWelcome(m);
        } else if (m.type === 'pong') {
            const sent = this.pings.get(m.id);
            this.pings.delete(m.id);
            if (sent !== undefined && this.o.onPong) this.o.onPong(sent, m.server_us * 1e-6, performance.now() * 1e-3);
        } else if (m.type === 'error') {
            this.serverError = { code: m.code, message: m.message };
        } else if (this.o.onText) {
            this.o.onText(m);
        }
    }

    ping() {
        const id = ++this.pingId >>> 0;
        const now = performance.now();
        this.pings.set(id, now * 1e-3);
        if (this.pings.size > 32) this.pings.delete(this.pings.keys().next().value);
        this.send({ type: 'ping', id, client_us: Math.round(now * 1000) });
    }

    binary(buf) {
        const bytes = new Uint8Array(buf);
        this.stats.bytes += bytes.length;
        let f;
        const t0 = performance.now();
        try {
            f = this.decoder.decode(bytes);
            this.lastDecode_ms = performance.now() - t0;
        } catch (e) {
            if (!(e instanceof WireError)) throw e;
            if (e.state) {
                // a gap: keep drawing the last state, ask for a keyframe (PROTOCOL.md)
                this.stats.resyncs++;
                this.send({ type: 'resync', seq: this.decoder.last ? this.decoder.last.seq : 0 });
                return;
            }
            this.stats.errors++;
            this.stats.lastError = e.message;
            this.serverError = { code: CLOSE.BAD_FRAME, message: e.message };
            this.ws.close(CLOSE.NORMAL);
            return;
        }
        this.stats.frames++;
        if (this.o.onFrame) this.o.onFrame(f, bytes.length);
    }
}
