// Attract mode of the kiosk page, as gale-client's (client/kiosk/attract.c, camera_preset.c):
// after idle_s without a touch the page lets go of its dial (the scene's own scenarios
// and playlist come back) and the camera tours the presets (street, garden, roof, aerial,
// CAMERA_TOUR_STOP_S each, turning a degree a second); the next touch wakes it and is not
// taken as a control. Time is the caller's clock [s]. tests/web/test_attract_js.mjs holds
// the tour to the C function's cameras.
// The page adds two things for its visitors: a warning before the tour takes the screen
// (WCAG 2.2.1: at least 20 s to say "still here", which a touch does), and, for a browser
// that asks for less motion (prefers-reduced-motion), a tour that turns five times slower.

export const ATTRACT_DEFAULT_IDLE_S = 90;
export const CAMERA_TOUR_STOP_S = 20;
// the warning comes this long before the tour (half the idle time when that is shorter)
export const ATTRACT_WARN_S = 20;
// the tour turns a degree a second (camera_preset_tour); with less motion asked for, 0.2
export const CAMERA_TOUR_TURN_DEG_S = 1;
export const CAMERA_TOUR_TURN_REDUCED_DEG_S = 0.2;
export const CAMERA_PRESETS = ['street', 'garden', 'roof', 'aerial', 'tour'];
const CAMERA_MIN_DIST = 0.5, CAMERA_MAX_DIST = 5000;

// attract.h ATTRACT_CARD_S, ATTRACT_CARDS: its cards in turn, the invitation to touch (0)
// and the water card (1), each this long
export const ATTRACT_CARD_S = 8;
const ATTRACT_CARDS = 2;

export class Attract {
    // awake, idle from now_s; idle_s 0 (or not > 0) → ATTRACT_DEFAULT_IDLE_S
    constructor(idle_s, now_s) {
        this.idle_s = idle_s > 0 ? idle_s : ATTRACT_DEFAULT_IDLE_S;
        this.warn_s = Math.min(ATTRACT_WARN_S, 0.5 * this.idle_s);
        this.last_input_s = now_s;
        this.active = false;
    }

    // seconds left before the tour at now_s (0 once it runs)
    left_s(now_s) {
        return this.active ? 0 : Math.max(0, this.idle_s - (now_s - this.last_input_s));
    }

    // whether the visitor is being warned at now_s: awake, within warn_s of the tour
    warning(now_s) {
        return !this.active && this.left_s(now_s) <= this.warn_s;
    }

    // true exactly once, when attract mode begins at now_s
    tick(now_s) {
        if (this.active || now_s - this.last_input_s < this.idle_s) return false;
        this.active = true;
        return true;
    }

    // the card shown at now_s, counted from when attract mode began; -1 awake (attract_card)
    card(now_s) {
        if (!this.active) return -1;
        const shown_s = Math.max(now_s - this.last_input_s - this.idle_s, 0);
        return Math.floor(shown_s / ATTRACT_CARD_S) % ATTRACT_CARDS;
    }

    // a touch at now_s: true when it woke the kiosk (the caller drops that touch)
    input(now_s) {
        this.last_input_s = now_s;
        if (!this.active) return false;
        this.active = false;
        return true;
    }
}

// Centre and radius of the instances (rows [species, x, y, z, ...]) in the xy plane.
function spread(inst) {
    const n = inst.length, c = [0, 0];
    for (const r of inst) {
        c[0] += r[1] / n;
        c[1] += r[2] / n;
    }
    let radius = 10;
    for (const r of inst) radius = Math.max(radius, Math.hypot(r[1] - c[0], r[2] - c[1]));
    return { c, radius };
}

// The instance of a species whose name contains word nearest to c; any species when none.
function nearest(inst, names, word, c) {
    let best = -1, bd = Infinity;
    for (let pass = 0; pass < 2 && best < 0; pass++) {
        inst.forEach((r, i) => {
            if (pass === 0 && !(names[r[0]] || '').includes(word)) return;
            const d = Math.hypot(r[1] - c[0], r[2] - c[1]);
            if (d < bd) {
                bd = d;
                best = i;
            }
        });
    }
    return best;
}

// The orbit camera { target, distance, yaw, pitch } of a preset over the scene
// (camera_preset_apply): instances as the welcome's rows, names the species' names.
export function cameraPreset(preset, inst, names) {
    const { c: ctr, radius } = spread(inst);
    let ylo = Infinity, yhi = -Infinity;
    for (const r of inst) {
        ylo = Math.min(ylo, r[2]);
        yhi = Math.max(yhi, r[2]);
    }
    if (!(ylo <= yhi)) ylo = yhi = 0;
    const target = [ctr[0], ctr[1], 4];
    let dist = Math.min(1.6 * radius + 22, 1500), pitch = -0.52, yaw = 1.5707963 - 0.6108652;
    if (preset === 0 || preset === 1) {
        // from outside the planting, so no other crown stands between eye and tree: the
        // palm nearest the south edge seen from the south, the oak nearest the north edge
        // from the north
        const street = preset === 0;
        const t = nearest(inst, names, street ? 'palm' : 'oak', [ctr[0], street ? ylo : yhi]);
        if (t >= 0) [target[0], target[1], target[2]] = inst[t].slice(1, 4);
        const eye_z = street ? 1.7 : 3.0, aim_z = street ? 4.5 : 5.5;
        const off = street ? target[1] - ylo + 10 : yhi - target[1] + 9;
        target[2] += aim_z;
        dist = Math.hypot(off, aim_z - eye_z);
        pitch = Math.atan2(aim_z - eye_z, off); // looking up a little at the crown
        yaw = street ? 1.5707963 : -1.5707963; // looking north / south
    } else if (preset === 2) {
        // eye about 12 m up, over the roofs (6-9 m), half the block away
        dist = Math.min(0.7 * radius + 20, 200);
        pitch = -Math.asin(Math.min((12 - target[2]) / dist, 0.9));
    } else if (preset === 3) {
        pitch = -1.0;
        dist = Math.min(1.9 * radius + 30, 2000);
        target[2] = 0;
    }
    dist = Math.min(Math.max(dist, CAMERA_MIN_DIST), CAMERA_MAX_DIST);
    return { target, distance: dist, yaw, pitch };
}

// The tour t_s [s] after it began (camera_preset_tour): that time's stop, turning slowly
// (turn_deg_s degrees a second, CAMERA_TOUR_TURN_DEG_S as the C's unless less motion is asked).
export function cameraTour(t_s, inst, names, turn_deg_s = CAMERA_TOUR_TURN_DEG_S) {
    const t = t_s > 0 ? t_s : 0;
    const stop = Math.floor(t / CAMERA_TOUR_STOP_S) % 4;
    const cam = cameraPreset(stop, inst, names);
    cam.yaw += (t % CAMERA_TOUR_STOP_S) * turn_deg_s * 0.017453292519943295;
    cam.stop = stop;
    return cam;
}
