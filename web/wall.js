// A wall tile (/wall?file=NAME&tile=T): tile T of the wall file configs/walls/NAME.json
// (served at /walls/), its view the generalized perspective projection of its glass from
// the wall's eye (web/wall_view.js, as client/wall/wall.c), in the wall's group (PROTOCOL.md
// "Wall groups") as gale-client's client_wall_group.c: frame N shows server time epoch +
// N period − delay on every tile, the camera is the wall's tour at frame N's instant or
// the kiosk's wall_camera from its frame on.
//
// Presenting: frame N is drawn ahead into an offscreen picture (web/render_gl.js target)
// in one animation frame; once the GPU has finished it (a fence) the tile reports
// wall_drawn N (swap-lock), and in the first animation frame at or after N's instant on
// the server clock, and after wall_swap N (or budget_ms without one), the picture is
// copied onto the canvas: that animation frame is where N is "presented". The browser
// composites it at its next display refresh, which the page cannot see, so a browser tile
// shows N up to one refresh interval (16.7 ms at 60 Hz) after it became presentable, plus
// the compositor's own latency; a native tile swaps at once. The frame number is locked,
// the moment to within about a display refresh (PROTOCOL.md "Wall groups").
//
// The query may carry the group's clock for when this tile is the first to join:
// rate=HZ (60), swap_lock=1, budget=MS (8), delay=MS (100), as gale-client's --rate,
// --swap-lock, --budget and --delay; a later joiner takes the group's.
import { App } from './app.js';
import { lookAt, mul, orbitEye } from './view_math.js';
import { tileMatrices, tourAt } from './wall_view.js';

const q = new URLSearchParams(location.search);
const file = (q.get('file') || '').replace(/\.json$/, '');
const tileName = q.get('tile') || '';
const num = (k, dflt, lo, hi) => {
    const v = Number(q.get(k));
    return q.get(k) !== null && Number.isInteger(v) && v >= lo && v <= hi ? v : dflt;
};
const JOIN = { rate_hz: num('rate', 60, 1, 240), swap_lock: q.get('swap_lock') === '1', budget_ms: num('budget', 8, 1, 1000),
    delay_ms: num('delay', 100, 1, 10000) };
const LOG_MAX = 4000; // presented frames kept for tests (a minute at 60 Hz)

async function main() {
    const status = document.getElementById('status');
    const say = (t) => { status.hidden = !t; status.textContent = t; };
    if (!/^[A-Za-z0-9._-]+$/.test(file) || !tileName) {
        say('This page shows one tile of a display wall: open /wall?file=NAME&tile=T (a wall file of configs/walls/ and one of its tiles).');
        return;
    }
    const res = await fetch(`/walls/${file}.json`, { cache: 'no-store' });
    if (!res.ok) {
        say(`The server has no wall file "${file}" (configs/walls/${file}.json): HTTP ${res.status}.`);
        return;
    }
    const wall = await res.json();
    const tile = wall.tiles.find((t) => t.name === tileName);
    if (!tile) {
        say(`The wall "${wall.name}" has no tile "${tileName}"; its tiles: ${wall.tiles.map((t) => t.name).join(', ')}.`);
        return;
    }
    let sync = null, last = -1, swap = -1, pending = null, fromServer = null, t_base = null;
    // frames: presented; drawn; reports: wall_drawn sent; swapTimeouts: presented after
    // the budget without wall_swap; log: [frame, due_us, drawn_us, presented_us] on the
    // server clock; swaps: [frame, drawn, members, received_us]
    const g = { frames: 0, drawn: 0, skipped: 0, reports: 0, swapTimeouts: 0, frame: -1, held: null, log: [], swaps: [], join: JOIN };
    const keep = (a, row) => {
        a.push(row);
        if (a.length > LOG_MAX) a.splice(0, a.length - LOG_MAX);
    };
    const drop = (app) => {
        if (g.held && g.held.fence) app.r.gl.deleteSync(g.held.fence);
        g.held = null;
    };
    // Whether the GPU has finished held frame h (its fence signalled); the first time it
    // has, the time is kept and, in swap-lock, the frame reported drawn.
    const drawn = (a, h, now_s) => {
        if (h.drawn_s !== undefined) return true;
        const gl = a.r.gl;
        if (gl.getSyncParameter(h.fence, gl.SYNC_STATUS) !== gl.SIGNALED) return false;
        h.drawn_s = now_s;
        if (sync && sync.swap_lock && a.conn.send({ type: 'wall_drawn', frame: h.frame })) {
            h.reported = true;
            g.reports++;
        }
        return true;
    };
    // Between animation frames too, so that the report leaves as soon as the frame is
    // drawn: the group waits on it, not on this page's next animation frame.
    const poll = (a, h) => {
        if (g.held !== h || h.drawn_s !== undefined) return;
        const now_s = a.clock.serverTime(performance.now() * 1e-3);
        if (now_s === null || !drawn(a, h, now_s)) setTimeout(() => poll(a, h), 2);
    };
    const app = new App({
        role: 'wall-tile',
        offscreen: true,
        onWelcome: () => {
            // a new connection may be a new server: a new clock, frames from its numbering
            sync = null;
            last = swap = -1;
            pending = fromServer = null;
            drop(app);
            app.conn.send({ type: 'wall_join', wall: wall.name, tile: tileName, ...JOIN });
        },
        onText: (m) => {
            if (m.type === 'wall_sync') sync = m;
            else if (m.type === 'wall_swap') {
                swap = Math.max(swap, m.frame);
                const now = app.clock.serverTime(performance.now() * 1e-3);
                keep(g.swaps, [m.frame, m.drawn, m.members, now === null ? null : Math.round(now * 1e6)]);
            } else if (m.type === 'wall_camera' && m.wall === wall.name) pending = m;
        },
        beforeDraw: (a, now_s) => {
            const h = g.held;
            if (!h || !sync) return;
            if (!h.fence) { // its draw failed
                g.held = null;
                return;
            }
            if (!drawn(a, h, now_s)) return;
            if (now_s < h.due_s) return; // its instant has not come
            if (h.reported && swap < h.frame) {
                if (now_s < Math.max(h.due_s, h.drawn_s) + sync.budget_ms * 1e-3) return;
                g.swapTimeouts++;
            }
            // (a canvas resized since the draw shows nothing of it: the frame is passed)
            if (a.r.present()) {
                keep(g.log, [h.frame, Math.round(h.due_s * 1e6), Math.round(h.drawn_s * 1e6), Math.round(now_s * 1e6)]);
                g.frames++;
                g.frame = h.frame;
            }
            last = h.frame;
            drop(a);
        },
        renderTime: (a, now_s) => {
            if (!sync || g.held) return null;
            const epoch = sync.epoch_us * 1e-6, period = sync.period_us * 1e-6;
            // the next frame whose instant is still ahead, never one frame twice
            let n = Math.max(0, Math.floor((now_s - epoch) / period) + 1);
            if (last >= 0 && n <= last) n = last + 1;
            else if (last >= 0) g.skipped += n - last - 1;
            g.held = { frame: n, due_s: (sync.epoch_us + n * sync.period_us) * 1e-6, fence: null };
            g.instant_s = epoch + n * period;
            if (pending && n >= pending.frame) {
                fromServer = pending;
                pending = null;
            }
            return (sync.epoch_us + n * sync.period_us - sync.delay_us) * 1e-6;
        },
        // the shaders' time from the first frame's whole second, as gale-client's
        // render_rel_time
        shaderTime: (shown_s) => {
            if (t_base === null) t_base = Math.floor(shown_s);
            return shown_s - t_base;
        },
        afterFrame: (a) => {
            if (!g.held || g.held.fence) return;
            const gl = a.r.gl;
            g.held.fence = gl.fenceSync(gl.SYNC_GPU_COMMANDS_COMPLETE, 0);
            gl.flush();
            g.drawn++;
            setTimeout(() => poll(a, g.held), 0);
        },
        camera: () => {
            const c = fromServer || (wall.tour && wall.tour.length >= 2 ? tourAt(wall, g.instant_s || 0) : { target_m: [0, 0, 4], distance_m: 40, yaw_deg: 55, pitch_deg: -25 });
            const eye = orbitEye(c.target_m, c.distance_m, c.yaw_deg * Math.PI / 180, c.pitch_deg * Math.PI / 180);
            const { view, proj } = tileMatrices(wall, tile, lookAt(eye, c.target_m, [0, 0, 1]));
            // the tile's view as gale-client's: the storm's rain slants across it and its
            // fog and streaks thin about the subject along its normal (web/storm_fx.js)
            return { eye, target: c.target_m, viewproj: mul(proj, view), view, subject_m: c.distance_m };
        },
    });
    app.wallGroup = g;
    app.wallTile = tile;
    await app.start();
}

main();
