// The kiosk panel's numbers, as gale-client's (client/kiosk/kiosk_ui.c, kiosk_ui_draw.c,
// kiosk_ui_msg.c): the wind dial's bands and their colours, the dial's angle of a speed and
// back, the replay speeds, what a bearing sends and which scenario WEATHER names.
// tests/web/test_kiosk_js.mjs holds every number and rule here to the C (gale-web-kiosk-table)
// and the colours to kiosk_ui_draw.c's table.

// The dial runs from calm to a strong Category 5 (the strongest Atlantic landfalls, e.g.
// Allen 1980, 165 kt = 85 m/s), 270° from lower left over the top to lower right.
export const DIAL_MAX_MS = 85;
export const DIAL_SWEEP_RAD = Math.fround(4.712389);
export const BANDS = 9; // calm, breeze, strong wind, tropical storm, Cat 1..5
// Band b's lowest speed [m/s] (BANDS: the dial's top), kiosk_ui_band_lower_ms as float32:
// breeze from Beaufort 2, strong wind from Beaufort 6 (half a tenth above the force below's
// WMO limit), tropical storm and Cat 1..5 half a knot below their first whole knot
// (protocol/wind_scale.c: 34, 64, 83, 96, 113, 137 kt).
const KT = 0.514444;
export const BAND_LOWER_MS = [0, 1.55, 10.75, 33.5 * KT, 63.5 * KT, 82.5 * KT, 95.5 * KT, 112.5 * KT,
    136.5 * KT, DIAL_MAX_MS].map(Math.fround);
// The band's label key in web/kiosk_text.js ("Calm" ... "Tropical storm", "Cat 1" ... "Cat 5").
export const BAND_KEYS = ['band.calm', 'band.breeze', 'band.strong', 'band.ts', 'band.cat1', 'band.cat2',
    'band.cat3', 'band.cat4', 'band.cat5'];
// kiosk_ui_draw.c's colours (0..1): the usual warm ramp of Saffir-Simpson charts above the
// cool Beaufort bands; a band not holding the wind is drawn at BAND_DIM_ALPHA.
export const BAND_RGB = [
    [0.62, 0.82, 0.95], // calm
    [0.45, 0.80, 0.60], // breeze
    [0.72, 0.85, 0.38], // strong wind
    [0.98, 0.86, 0.30], // tropical storm
    [1.00, 0.68, 0.25], // Cat 1
    [1.00, 0.50, 0.20], // Cat 2
    [0.94, 0.30, 0.20], // Cat 3
    [0.84, 0.16, 0.36], // Cat 4
    [0.68, 0.18, 0.68], // Cat 5
];
export const BAND_DIM_ALPHA = 0.62;
export const INK = [0.97, 0.97, 0.93];
export const DIM_INK = [0.80, 0.82, 0.84];
export const ACCENT = [1.0, 0.80, 0.30];
export const DARK_INK = [0.08, 0.08, 0.10];
export const PANEL_RGBA = [0.04, 0.06, 0.09, 0.62];
export const BUTTON_RGBA = [0.10, 0.13, 0.18, 1.0];
export const PRESSED_RGBA = [0.35, 0.42, 0.52, 1.0];

// storm seconds per second of the ×1, ×10, ×50 buttons (×1 is real time)
export const REPLAY_SPEEDS = [1, 10, 50];

// a CSS colour of an rgb triple in 0..1 (and an alpha)
// protocol/wind_scale.c wind_scale_ss_class: the Saffir-Simpson class (0 depression .. 6
// Category 5) of a sustained wind, its knots rounded to the nearest whole knot
const SS_LOWER_KT = [0, 34, 64, 83, 96, 113, 137];
export function ssClass(speedMs) {
    if (!(speedMs > 0)) return 0;
    const kt = Math.floor(speedMs / KT + 0.5);
    let c = 0;
    for (let i = 1; i < SS_LOWER_KT.length; i++) if (kt >= SS_LOWER_KT[i]) c = i;
    return c;
}

export function css(rgb, a = 1) {
    const c = rgb.slice(0, 3).map((v) => Math.round(v * 255));
    return a >= 1 ? `rgb(${c.join(' ')})` : `rgb(${c.join(' ')} / ${a})`;
}

const f32 = Math.fround;

// The band of a speed, 0..BANDS-1 (kiosk_ui_band).
export function bandOf(speedMs) {
    let b = 0;
    for (let i = 1; i < BANDS; i++) if (speedMs >= BAND_LOWER_MS[i]) b = i;
    return b;
}

// Angle [rad, clockwise from straight up] of a speed on the dial (kiosk_ui_dial_angle): each
// band the same share of the sweep, linear within it; float32 as the C.
export function dialAngle(speedMs) {
    const v = f32(Math.min(Math.max(Number.isFinite(speedMs) ? f32(speedMs) : 0, 0), DIAL_MAX_MS));
    const b = bandOf(v);
    const lo = BAND_LOWER_MS[b], hi = BAND_LOWER_MS[b + 1];
    const f = hi > lo ? Math.min(f32(f32(v - lo) / f32(hi - lo)), 1) : 0;
    return f32(f32(-0.5 * DIAL_SWEEP_RAD) + f32(f32(f32(b + f) * DIAL_SWEEP_RAD) / BANDS));
}

// The speed at an angle of the dial (kiosk_ui_dial_speed); beyond the sweep, its ends.
export function dialSpeed(angleRad) {
    let u = f32(f32(f32(f32(angleRad) + f32(0.5 * DIAL_SWEEP_RAD)) / DIAL_SWEEP_RAD) * BANDS);
    u = Math.min(Math.max(Number.isFinite(u) ? u : 0, 0), BANDS);
    const b = Math.floor(u);
    if (b >= BANDS) return DIAL_MAX_MS;
    const lo = BAND_LOWER_MS[b], hi = BAND_LOWER_MS[b + 1];
    return f32(lo + f32(f32(u - b) * f32(hi - lo)));
}

// The wire's wind.dir_deg (where the wind blows towards, counter-clockwise from +x) of a
// bearing the wind comes from (clockwise from north): 270° − bearing, in [0, 360)
// (kiosk_ui_msg.c toward_deg, as the server converts it back).
export function towardDeg(fromDeg) {
    const d = f32(((270 - f32(fromDeg) + 720) % 360));
    return d >= 360 ? 0 : d;
}

// Letters and digits only, lower case: how the server matches scenario names, so
// "Andrew 1992" names andrew1992 (kiosk_ui.c squash; ASCII as the C's isalnum).
export function squash(s) {
    return (s || '').toLowerCase().replace(/[^a-z0-9]/g, '');
}

const W_DIAL = 2;

// Index of the scenario (welcome rows { name, title }) a WEATHER runs, -1 none: its name
// against each title or name, squashed (kiosk_ui_set_weather). A dialled wind (the DIAL
// flag) runs none: the name WEATHER still carries is the scenario the dial holds back.
export function runningIndex(weather, scenarios) {
    if (!weather || (weather.flags & W_DIAL)) return -1;
    const want = squash(weather.name);
    if (!want) return -1;
    return scenarios.findIndex((s) => squash(s.title || s.name) === want || squash(s.name) === want);
}

// What each touch of the panel sends (kiosk_ui_message), without the token: a speed keeps
// the direction this kiosk chose, a direction the speed it dialled; a scenario and a reset
// forget both (the server drops the dial for them).
export class DialMessages {
    constructor() { this.forget(); }

    forget() {
        this.setSpeed = false;
        this.setDir = false;
        this.speedMs = 0;
        this.fromDeg = 0;
    }

    speed(v) {
        this.setSpeed = true;
        this.speedMs = f32(Math.min(Math.max(v, 0), DIAL_MAX_MS));
        const m = { type: 'wind', speed_ms: this.speedMs };
        // without a scenario the server takes a missing direction as the scene's
        if (this.setDir) m.dir_deg = towardDeg(this.fromDeg);
        return m;
    }

    dir(fromDeg) {
        this.setDir = true;
        this.fromDeg = f32(fromDeg);
        const m = { type: 'wind', dir_deg: towardDeg(fromDeg) };
        if (this.setSpeed) m.speed_ms = this.speedMs;
        return m;
    }

    scenario(name) {
        this.forget();
        return { type: 'wind', scenario: name };
    }

    reset() {
        this.forget();
        return { type: 'reset' };
    }
}

// 16 compass points of a bearing, as the HUD names them (hud_compass_point); the key of
// its name in web/kiosk_text.js, 'compass.?' for a bearing that is not a number.
const POINTS = ['N', 'NNE', 'NE', 'ENE', 'E', 'ESE', 'SE', 'SSE', 'S', 'SSW', 'SW', 'WSW', 'W', 'WNW', 'NW', 'NNW'];
export function compassKey(deg) {
    if (!Number.isFinite(deg)) return 'compass.?';
    let b = deg % 360;
    if (b < 0) b += 360;
    return `compass.${POINTS[Math.floor(b / 22.5 + 0.5) % 16]}`;
}
