// Storm look of the browser client: the streamed weather (sustained wind, its direction)
// mapped to the sky, light, fog and rain the shared shaders take (common.glsl, rain.frag),
// with the numbers of client/render/storm_fx.c (its header says what each field means);
// tests/web/test_storm_fx_js.mjs holds the two to the same values.

// quality: off keeps the calm look at any wind; low one layer of rain streaks; high three
export const STORM_FX_OFF = 0, STORM_FX_LOW = 1, STORM_FX_HIGH = 2;
// sky darkens from Beaufort 6 (10.8 m/s) to darkest at Saffir-Simpson Cat 5 (70 m/s)
// (as float32, the C constants' and the wire's type, so a wind on a threshold falls on
// the same side of it as in gale-client)
export const STORM_FX_DARK_FROM_MS = Math.fround(10.8);
export const STORM_FX_DARK_FULL_MS = 70.0;
// rain streaks from tropical-storm strength, spray from hurricane strength (Beaufort 12)
export const STORM_FX_RAIN_FROM_MS = 17.5;
export const STORM_FX_SPRAY_FROM_MS = Math.fround(32.7);
export const STORM_FX_SUBJECT_CLEAR = 0.8;

const CALM_SUN = [1.05, 0.97, 0.86];
const CALM_ZENITH = [0.30, 0.50, 0.82];
const CALM_HORIZON = [0.74, 0.82, 0.90];
const CALM_GROUND = [0.30, 0.40, 0.17];
// the darkest storm: a grey deck lighter overhead than wet foliage under it, a paler
// horizon in rain, light through thick cloud (client/render/storm_fx.c gives the reasons)
const STORM_SUN = [0.22, 0.23, 0.25];
const STORM_ZENITH = [0.30, 0.32, 0.35];
const STORM_HORIZON = [0.40, 0.42, 0.44];
const STORM_GROUND = [0.20, 0.25, 0.14];
// fog distance at full intensity, a share of the clear day's (heavy rain: a few hundred m)
const STORM_FOG_SCALE = 0.18;

// The calm look: the renderer's clear day.
export function stormFxCalm() {
    return { intensity: 0, sun_col: [...CALM_SUN], sky_zenith: [...CALM_ZENITH], sky_horizon: [...CALM_HORIZON],
        ground_col: [...CALM_GROUND], fog_scale: 1, rain: 0, rain_layers: 0, spray: 0, wind_to: [0, 0], wet: 0, subject_clear: 0 };
}

const clamp01 = (x) => (x < 0 ? 0 : x > 1 ? 1 : x);
const mix3 = (a, b, t) => a.map((v, k) => v + (b[k] - v) * t);

// The look at sustained wind sustainedMs coming from dirFromDeg (clockwise from north) at
// quality q; below STORM_FX_DARK_FROM_MS (or NaN), or with q off, the calm look.
export function stormFxFromWeather(sustainedMs, dirFromDeg, q) {
    const fx = stormFxCalm();
    if (q === STORM_FX_OFF || !(sustainedMs > STORM_FX_DARK_FROM_MS)) return fx;
    const x = clamp01((sustainedMs - STORM_FX_DARK_FROM_MS) / (STORM_FX_DARK_FULL_MS - STORM_FX_DARK_FROM_MS));
    // eased so a gale already reads grey and the major hurricanes keep getting darker
    const i = Math.sqrt(x);
    fx.intensity = i;
    fx.sun_col = mix3(CALM_SUN, STORM_SUN, i);
    fx.sky_zenith = mix3(CALM_ZENITH, STORM_ZENITH, i);
    fx.sky_horizon = mix3(CALM_HORIZON, STORM_HORIZON, i);
    fx.ground_col = mix3(CALM_GROUND, STORM_GROUND, i);
    fx.fog_scale = 1 + (STORM_FOG_SCALE - 1) * i;
    fx.wet = i;
    fx.subject_clear = STORM_FX_SUBJECT_CLEAR;
    // where the wind goes: opposite to where it comes from
    const to = (dirFromDeg + 180) * 0.017453293;
    const s = Math.min(sustainedMs, 200);
    fx.wind_to = [s * Math.sin(to), s * Math.cos(to)];
    if (sustainedMs >= STORM_FX_RAIN_FROM_MS) {
        fx.rain = 0.25 + 0.75 * clamp01((sustainedMs - STORM_FX_RAIN_FROM_MS) / (STORM_FX_DARK_FULL_MS - STORM_FX_RAIN_FROM_MS));
        fx.rain_layers = q === STORM_FX_HIGH ? 3 : 1;
    }
    if (sustainedMs >= STORM_FX_SPRAY_FROM_MS) {
        fx.spray = 0.3 + 0.7 * clamp01((sustainedMs - STORM_FX_SPRAY_FROM_MS) / (STORM_FX_DARK_FULL_MS - STORM_FX_SPRAY_FROM_MS));
    }
    return fx;
}

// "off", "low" or "high" to its quality; null for any other text.
export function stormFxQualityParse(s) {
    const k = ['off', 'low', 'high'].indexOf(s);
    return k < 0 ? null : k;
}

// Rain streaks lean along the wind across the view (client/render/render_rain.c): a drop falling
// at about 9 m/s (Gunn & Kinzer 1949) is carried sideways at the wind speed.
const RAIN_FALL_MS = 9.0;
const RAIN_SLANT_MAX = 3.0;

// rain.frag's uniforms for a frame: view is the column-major view matrix, subject the
// camera's subject in world (null: none), viewproj its view-projection, w × h pixels.
export function rainUniforms(fx, view, viewproj, subject, w, h) {
    const across = fx.wind_to[0] * view[0] + fx.wind_to[1] * view[4]; // camera's right axis
    const slant = Math.max(-RAIN_SLANT_MAX, Math.min(RAIN_SLANT_MAX, across / RAIN_FALL_MS));
    const layers = Math.min(3, fx.rain_layers);
    const px = h / 720;
    const rain = [fx.rain, slant, layers, px < 0.5 ? 0.5 : px];
    // spray drifts along the wind: its azimuth pattern turns at the wind across the view
    // over about 30 m
    const spray = [fx.spray, -across / 30];
    let clear = [0, 0, 0.5 * h, 0];
    if (subject) {
        const m = viewproj, s = subject;
        const cx = m[0] * s[0] + m[4] * s[1] + m[8] * s[2] + m[12];
        const cy = m[1] * s[0] + m[5] * s[1] + m[9] * s[2] + m[13];
        const cw = m[3] * s[0] + m[7] * s[1] + m[11] * s[2] + m[15];
        if (cw > 0 && fx.subject_clear > 0) {
            clear = [(cx / cw * 0.5 + 0.5) * w, (cy / cw * 0.5 + 0.5) * h, 0.5 * h, fx.subject_clear];
        }
    }
    return { rain, spray, clear };
}
