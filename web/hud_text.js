// What the HUD says of the server's WEATHER, line for line what gale-client's HUD says in
// the same language (client/hud/hud_format.c hud_format_weather, hud_units.c;
// tests/web/test_hud_js.mjs holds the two together in every language): wind in the
// language's units with its gust, the Saffir-Simpson class (or the Beaufort force below
// tropical storm, where "tropical depression" would mislabel a breeze), where it comes
// from, a replay's storm or a steady scenario's name, and the expert line (knots, m/s).
import { t, scenarioTitle, kmhFirst } from './lang.js';

const SS_TS = 1;
const SS_COUNT = 7;
const W_STORM = 1, W_DIAL = 2, W_FINISHED = 4, W_CLOCK = 8;

// ---- units (hud_units.c) ----------------------------------------------------------------
export const UNIT = { MPH: 0, KMH: 1, KT: 2, MS: 3 };
const MS_PER_MPH = 0.44704;
const MS_PER_KT = 0.514444; // protocol/wind_scale.h WIND_SCALE_MS_PER_KT
export const UNIT_NO_TOP = 1000000;
// NHC's Saffir-Simpson table: lowest whole value of each class (TD .. Cat 5) per unit,
// and m/s's tops, where NHC's rounding shares 58 and 70 between classes
const CLASS_LO = [
    [0, 39, 74, 96, 111, 130, 157],
    [0, 63, 119, 154, 178, 209, 252],
    [0, 34, 64, 83, 96, 113, 137],
    [0, 18, 33, 43, 50, 58, 70],
];
const MS_HI = [17, 32, 42, 49, 58, 70, UNIT_NO_TOP];

export function unitValue(ms, unit) {
    return unit === UNIT.MPH ? ms / MS_PER_MPH : unit === UNIT.KMH ? ms * 3.6 : unit === UNIT.KT ? ms / MS_PER_KT : ms;
}

export function unitRound(ms, unit) {
    const v = unitValue(ms, unit);
    return Number.isFinite(v) && v > 0 ? Math.floor(v + 0.5) : 0;
}

export function unitRange(ssClass, unit) {
    if (!(ssClass >= 0 && ssClass < SS_COUNT) || !(unit >= 0 && unit < 4)) return null;
    const lo = CLASS_LO[unit][ssClass];
    const hi = unit === UNIT.MS ? MS_HI[ssClass] : ssClass + 1 < SS_COUNT ? CLASS_LO[unit][ssClass + 1] - 1 : UNIT_NO_TOP;
    return [lo, hi];
}

// the whole number shown for a sustained wind of a class: rounded, then kept in its range
export function unitSustained(ms, unit, ssClass) {
    const v = unitRound(ms, unit), r = unitRange(ssClass, unit);
    return r ? Math.min(Math.max(v, r[0]), r[1]) : v;
}

// "120 mph · 193 km/h" in the language's order, each kept in the class's range
export function formatSpeed(lang, ms, ssClass) {
    const mph = ssClass >= 0 ? unitSustained(ms, UNIT.MPH, ssClass) : unitRound(ms, UNIT.MPH);
    const kmh = ssClass >= 0 ? unitSustained(ms, UNIT.KMH, ssClass) : unitRound(ms, UNIT.KMH);
    return kmhFirst(lang) ? `${t(lang, 'unit.kmh', kmh)} · ${t(lang, 'unit.mph', mph)}`
        : `${t(lang, 'unit.mph', mph)} · ${t(lang, 'unit.kmh', kmh)}`;
}

export function formatSpeedFirst(lang, ms) {
    return kmhFirst(lang) ? t(lang, 'unit.kmh', unitRound(ms, UNIT.KMH)) : t(lang, 'unit.mph', unitRound(ms, UNIT.MPH));
}

// ---- lines ------------------------------------------------------------------------------

// hud_compass_index: 16 points from north clockwise, -1 for a bearing that is not a number
export function compassIndex(deg) {
    if (!Number.isFinite(deg)) return -1;
    let b = deg % 360;
    if (b < 0) b += 360;
    return Math.floor(b / 22.5 + 0.5) % 16;
}

export function compassText(lang, deg) {
    const i = compassIndex(deg);
    return i < 0 ? '?' : t(lang, `compass.${i}`);
}

const whole = (x) => (Number.isFinite(x) ? Math.floor(x + 0.5) : 0);
const pad2 = (n) => String(n).padStart(2, '0');

// minutes since 1970-01-01 00:00 UTC as [YYYY-MM-DD, HH:MM]
function civil(min) {
    const d = new Date(min * 60000);
    const y = d.getUTCFullYear();
    return [`${y < 0 ? '-' : ''}${String(Math.abs(y)).padStart(4, '0')}-${pad2(d.getUTCMonth() + 1)}-${pad2(d.getUTCDate())}`,
        `${pad2(d.getUTCHours())}:${pad2(d.getUTCMinutes())}`];
}

// the class line: Saffir-Simpson from tropical storm up, else the Beaufort force
function classLine(lang, ssClass, beaufort) {
    if (ssClass >= SS_TS && ssClass < SS_COUNT) return t(lang, `ss.${ssClass}`);
    const b = beaufort >= 0 && beaufort <= 12 ? beaufort : 0;
    return t(lang, 'hud.beaufort', t(lang, `bft.${b}`), b);
}

// The lines (an array) of a decoded WEATHER (web/wire.js) in a language ('en', 'es', 'ht').
export function weatherLines(w, lang = 'en') {
    const v = w.sustained_ms, cls = w.ss_class;
    const lines = [t(lang, 'hud.wind', formatSpeed(lang, v, cls), formatSpeedFirst(lang, w.gust_ms))];
    lines.push(classLine(lang, cls, w.beaufort));
    lines.push(t(lang, 'hud.from', compassText(lang, w.dir_from_deg), whole(w.dir_from_deg) % 360)
        + (w.flags & W_DIAL ? t(lang, 'hud.dialled') : ''));
    if (w.flags & W_STORM) {
        const name = w.name || t(lang, 'hud.storm_default');
        if (w.flags & W_CLOCK) {
            const [d, hm] = civil(w.utc_min), [, lhm] = civil(w.utc_min + w.utc_offset_min);
            lines.push(t(lang, 'hud.storm_clock', name, d, hm, lhm));
        } else {
            lines.push(name);
        }
        lines.push(t(lang, 'hud.eye', whole(w.distance_km), compassText(lang, w.bearing_deg), whole(w.central_hpa),
            w.storm_class < SS_COUNT ? t(lang, `ss_abbrev.${w.storm_class}`) : '?'));
        const pos = Math.trunc(w.replay_pos_s), len = Math.trunc(w.replay_len_s), x = whole(w.replay_speed);
        lines.push(len > 0 ? t(lang, 'hud.replay', Math.trunc(pos / 60), pos % 60, Math.trunc(len / 60), len % 60, x)
            + (w.flags & W_FINISHED ? t(lang, 'hud.replay_ended') : '')
            : t(lang, 'hud.replay_loop', Math.trunc(pos / 60), pos % 60, x));
    } else if (w.name && !(w.flags & W_DIAL)) {
        // a dial overrides a steady scenario: its title would contradict the wind above
        lines.push(scenarioTitle(lang, w.name));
    }
    // the expert line, the one place knots appear
    lines.push(t(lang, 'hud.expert', unitSustained(v, UNIT.KT, cls), unitSustained(v, UNIT.MS, cls),
        unitRound(w.gust_ms, UNIT.KT), unitRound(w.gust_ms, UNIT.MS)));
    return lines;
}
