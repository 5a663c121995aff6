// What the HUD says of the server's WEATHER, line for line what gale-client's HUD says
// (client/hud/hud_format.c hud_format_weather; tests/web/test_hud_js.mjs holds the two
// together): wind with its gust, the Saffir-Simpson class (or the Beaufort force below
// tropical storm, where "tropical depression" would mislabel a breeze), where it comes
// from, and a replay's storm or a steady scenario's name.

// protocol/wind_scale.c's titles, the classes and forces WEATHER carries
export const SS_TITLE = ['Tropical depression', 'Tropical storm', 'Category 1 hurricane', 'Category 2 hurricane',
    'Category 3 hurricane', 'Category 4 hurricane', 'Category 5 hurricane'];
const SS_ABBREV = ['TD', 'TS', 'Cat 1', 'Cat 2', 'Cat 3', 'Cat 4', 'Cat 5'];
const BEAUFORT_TITLE = ['Calm', 'Light air', 'Light breeze', 'Gentle breeze', 'Moderate breeze', 'Fresh breeze',
    'Strong breeze', 'Near gale', 'Gale', 'Strong gale', 'Storm', 'Violent storm', 'Hurricane force'];
const COMPASS = ['N', 'NNE', 'NE', 'ENE', 'E', 'ESE', 'SE', 'SSE', 'S', 'SSW', 'SW', 'WSW', 'W', 'WNW', 'NW', 'NNW'];
const SS_TS = 1;
const W_STORM = 1, W_DIAL = 2, W_FINISHED = 4, W_CLOCK = 8;

// printf's "%.Nf": the exact binary value rounded half to even, where toFixed rounds a
// tie up (2.5 is "2" in C, "3" by toFixed)
function fixed(x, digits) {
    const m = 10 ** digits, y = x * m;
    if (Number.isFinite(y) && Math.abs(y - Math.trunc(y)) === 0.5 && y / m === x) {
        const f = Math.floor(y);
        return ((f % 2 === 0 ? f : f + 1) / m).toFixed(digits);
    }
    return x.toFixed(digits);
}

// hud_compass_point: 16 points, "?" for a bearing that is not a number
function compassPoint(deg) {
    if (!Number.isFinite(deg)) return '?';
    let b = deg % 360;
    if (b < 0) b += 360;
    return COMPASS[Math.floor(b / 22.5 + 0.5) % 16];
}

const pad2 = (n) => String(n).padStart(2, '0');

// minutes since 1970-01-01 00:00 UTC as [YYYY-MM-DD, HH:MM]
function civil(min) {
    const d = new Date(min * 60000);
    const y = d.getUTCFullYear();
    return [`${y < 0 ? '-' : ''}${String(Math.abs(y)).padStart(4, '0')}-${pad2(d.getUTCMonth() + 1)}-${pad2(d.getUTCDate())}`,
        `${pad2(d.getUTCHours())}:${pad2(d.getUTCMinutes())}`];
}

// The lines (an array) of a decoded WEATHER (web/wire.js).
export function weatherLines(w) {
    const v = w.sustained_ms;
    const lines = [`Wind ${fixed(v, 1)} m/s · ${fixed(v * 3.6, 0)} km/h · ${fixed(v / 0.44704, 0)} mph · gusts ${fixed(w.gust_ms, 0)} m/s`];
    lines.push(w.ss_class >= SS_TS ? SS_TITLE[w.ss_class] : `${BEAUFORT_TITLE[w.beaufort]} · Beaufort ${w.beaufort}`);
    lines.push(`From the ${compassPoint(w.dir_from_deg)} (${fixed(w.dir_from_deg, 0)}°)${w.flags & W_DIAL ? ' · dialled at the kiosk' : ''}`);
    if (w.flags & W_STORM) {
        let clock = '';
        if (w.flags & W_CLOCK) {
            const [d, hm] = civil(w.utc_min), [, lhm] = civil(w.utc_min + w.utc_offset_min);
            clock = ` · ${d} ${hm} UTC (${lhm} local)`;
        }
        lines.push(`${w.name || 'Storm'}${clock}`);
        lines.push(`Eye ${fixed(w.distance_km, 0)} km ${compassPoint(w.bearing_deg)} · ${fixed(w.central_hpa, 0)} hPa · storm ${SS_ABBREV[w.storm_class] || '?'}`);
        const pos = Math.trunc(w.replay_pos_s), len = Math.trunc(w.replay_len_s);
        const mmss = (s) => `${Math.trunc(s / 60)}:${pad2(s % 60)}`;
        lines.push(len > 0 ? `Replay ${mmss(pos)} / ${mmss(len)} · ×${fixed(w.replay_speed, 0)}${w.flags & W_FINISHED ? ' · ended' : ''}`
            : `Replay ${mmss(pos)} · ×${fixed(w.replay_speed, 0)} (looping)`);
    } else if (w.name && !(w.flags & W_DIAL)) {
        // a dial overrides a steady scenario: its title would contradict the wind above
        lines.push(w.name);
    }
    return lines;
}
