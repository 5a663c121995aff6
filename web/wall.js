// A wall tile (/wall?file=NAME&tile=T): tile T of the wall file configs/walls/NAME.json
// (served at /walls/), its view the generalized perspective projection of its glass from
// the wall's eye (Kooima 2008, as client/wall.c), in the wall's group (PROTOCOL.md "Wall
// groups"): frame N shows server time epoch + N period − delay on every tile, the camera
// is the wall's tour at frame N's instant or the kiosk's wall_camera from its frame on.
import { App } from './app.js';
import { lookAt, mul, orbitEye } from './render_gl.js';

const q = new URLSearchParams(location.search);
const file = (q.get('file') || '').replace(/\.json$/, '');
const tileName = q.get('tile') || '';
const RATE_HZ = 60; // gale-client's default --rate

const sub = (a, b) => a.map((x, k) => x - b[k]);
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const unit = (a) => a.map((x) => x / Math.hypot(...a));

// wall_offaxis (client/wall.c): corners pa (bottom left), pb (bottom right), pc (top left)
// of the glass, eye pe; returns proj · M^T T (Kooima eqs. 1-10)
export function offaxis(pa, pb, pc, pe, n, f) {
    const vr = unit(sub(pb, pa)), vu = unit(sub(pc, pa)), vn = unit(cross(vr, vu));
    const va = sub(pa, pe), vb = sub(pb, pe), vc = sub(pc, pe);
    const d = -dot(vn, va), s = n / d;
    const l = dot(vr, va) * s, r = dot(vr, vb) * s, b = dot(vu, va) * s, t = dot(vu, vc) * s;
    const proj = new Float32Array(16);
    proj[0] = 2 * n / (r - l);
    proj[5] = 2 * n / (t - b);
    proj[8] = (r + l) / (r - l);
    proj[9] = (t + b) / (t - b);
    proj[10] = -(f + n) / (f - n);
    proj[11] = -1;
    proj[14] = -2 * f * n / (f - n);
    const rot = new Float32Array(16);
    for (let k = 0; k < 3; k++) {
        rot[k * 4] = vr[k];
        rot[k * 4 + 1] = vu[k];
        rot[k * 4 + 2] = vn[k];
    }
    rot[12] = -dot(vr, pe);
    rot[13] = -dot(vu, pe);
    rot[14] = -dot(vn, pe);
    rot[15] = 1;
    return mul(proj, rot);
}

function corners(t) {
    const right = cross(t.up, t.normal), hw = 0.5 * t.size_m[0], hh = 0.5 * t.size_m[1];
    const at = (a, b) => t.centre_m.map((c, k) => c + a * right[k] + b * t.up[k]);
    return [at(-hw, -hh), at(hw, -hh), at(-hw, hh)];
}

function tourStop(w, t_s) {
    const s = w.tour, n = s.length, t = t_s % s[n - 1].t_s;
    let i = 0;
    while (i + 2 < n && t >= s[i + 1].t_s) i++;
    const u = (t - s[i].t_s) / (s[i + 1].t_s - s[i].t_s);
    const lerp = (a, b) => a + u * (b - a);
    return { target_m: s[i].target_m.map((x, k) => lerp(x, s[i + 1].target_m[k])), distance_m: lerp(s[i].distance_m, s[i + 1].distance_m),
        yaw_deg: lerp(s[i].yaw_deg, s[i + 1].yaw_deg), pitch_deg: lerp(s[i].pitch_deg, s[i + 1].pitch_deg) };
}

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
    const [pa, pb, pc] = corners(tile);
    const proj = offaxis(pa, pb, pc, wall.eye_m, 0.3, 3000);
    const toWall = new Float32Array([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, ...wall.eye_m, 1]);
    let sync = null, last = -1, pending = null, fromServer = null;
    const g = { frames: 0, skipped: 0 };
    const app = new App({
        role: 'wall-tile',
        onWelcome: () => {
            sync = null;
            last = -1;
            app.conn.send({ type: 'wall_join', wall: wall.name, tile: tileName, rate_hz: RATE_HZ });
        },
        onText: (m) => {
            if (m.type === 'wall_sync') sync = m;
            else if (m.type === 'wall_camera' && m.wall === wall.name) pending = m;
        },
        renderTime: (a, now_s) => {
            if (!sync) return null;
            const epoch = sync.epoch_us * 1e-6, period = sync.period_us * 1e-6;
            let n = Math.floor((now_s - epoch) / period) + 1;
            if (n <= last) return null; // never a frame twice
            if (last >= 0) g.skipped += n - last - 1;
            last = n;
            g.frames++;
            g.frame = n;
            g.instant_s = epoch + n * period;
            if (pending && n >= pending.frame) {
                fromServer = pending;
                pending = null;
            }
            return (sync.epoch_us + n * sync.period_us - sync.delay_us) * 1e-6;
        },
        camera: () => {
            const c = fromServer || (wall.tour && wall.tour.length >= 2 ? tourStop(wall, g.instant_s || 0) : { target_m: [0, 0, 4], distance_m: 40, yaw_deg: 55, pitch_deg: -25 });
            const eye = orbitEye(c.target_m, c.distance_m, c.yaw_deg * Math.PI / 180, c.pitch_deg * Math.PI / 180);
            const view = lookAt(eye, c.target_m, [0, 0, 1]);
            // view and subject as gale-client's orbit: the storm's rain slants across this
            // view and its fog and streaks thin about the subject (web/storm_fx.js)
            return { eye, target: c.target_m, viewproj: mul(proj, mul(toWall, view)), view, subject_m: c.distance_m };
        },
    });
    app.wallGroup = g;
    app.wallTile = tile;
    await app.start();
}

main();
