// The clients' sound policy: every number the wind's sound is made of and the laws that
// turn the wind at the listener, what grows near it and the storm's damage into levels,
// frequencies and densities; the same as gale-client's (client/audio/sound_policy.h,
// sound_caption.c), held to it by tests/web/test_sound_policy_js.mjs. Levels are dBFS
// before the operator's volume. Sources: aeolian tones at f = St·U/d, St ≈ 0.2 for a
// cylinder (a 1 mm needle at 20 m/s near 4 kHz, a 1 cm twig near 400 Hz); procedural
// wind as band-passed noise following the speed, with leaf crackle whose density grows
// with it and lags the gusts (A. Farnell, Designing Sound, ch. 41).
import { t } from './lang.js';

export const SOUND_RATE_HZ = 48000;
export const SOUND_CHANNELS = 2;

// aeolian tones: diameter classes [m], a factor √10 apart
export const SOUND_STROUHAL = 0.2;
export const SOUND_CLASSES = 6;
export const SOUND_CLASS_D_M = [0.001, 0.00316, 0.01, 0.0316, 0.1, 0.316];
export const SOUND_NEEDLE_D_M = 0.001;
export const SOUND_NEEDLES_PER_TUFT = 12;
export const SOUND_AEOL_F_MIN_HZ = 40;
export const SOUND_AEOL_F_MAX_HZ = 12000;
export const SOUND_AEOL_Q = 12;
export const SOUND_AEOL_DB_REF = -30;
export const SOUND_AEOL_LEN_REF_M = 100;
export const SOUND_AEOL_DB_PER_DECADE = 40;
export const SOUND_AEOL_DB_MAX = -14;

// what is near the listener
export const SOUND_NEAR_M = 120;
export const SOUND_REF_M = 10;
export const SOUND_LISTEN_Z_M = 10;
export const SOUND_U_REF_MS = 20;

// the wind bed: rumble, body, howl
export const SOUND_BED_DB_REF = -22;
export const SOUND_BED_DB_PER_DECADE = 24;
export const SOUND_BED_DB_MAX = -8;
export const SOUND_BED_U_MIN_MS = 0.5;
export const SOUND_BAND = { RUMBLE: 0, BODY: 1, HOWL: 2 };
export const SOUND_BANDS = 3;
export const SOUND_BAND_DB = [-2, -4, -8];
export const SOUND_RUMBLE_HZ = 110;
export const SOUND_RUMBLE_Q = 0.707;
export const SOUND_BODY_HZ0 = 180;
export const SOUND_BODY_HZ_PER_MS = 22;
export const SOUND_BODY_Q = 0.9;
export const SOUND_HOWL_MULT = 2.2;
export const SOUND_HOWL_Q = 7;
export const SOUND_HOWL_WANDER = 0.12;
export const SOUND_HOWL_WANDER_HZ = 0.23;
export const SOUND_HOWL_U0_MS = 18;
export const SOUND_HOWL_U1_MS = 40;
export const SOUND_GUST_DEPTH = 0.6;
export const SOUND_GUST_HZ = 0.25;

// leaf rustle
export const SOUND_RUSTLE_HZ_PER = 8;
export const SOUND_RUSTLE_U0_MS = 1.5;
export const SOUND_RUSTLE_EXP = 1.5;
export const SOUND_RUSTLE_MAX_HZ = 400;
export const SOUND_RUSTLE_LEAVES_HALF = 2000;
export const SOUND_RUSTLE_LAG_S = 0.6;
export const SOUND_RUSTLE_HP_HZ = 2500;
export const SOUND_RUSTLE_DECAY_MS = 6;
export const SOUND_RUSTLE_DB_REF = -22;
export const SOUND_RUSTLE_DB_PER_DECADE = 20;

// one-shots: crack (a branch), snap (a stem), uproot
export const SOUND_EV = { CRACK: 0, SNAP: 1, UPROOT: 2 };
export const SOUND_EVENTS = 3;
export const SOUND_EVENT_DB = [-6, 0, -2];
export const SOUND_EVENT_S = [0.18, 0.9, 1.4];
export const SOUND_EVENT_REF_M = 20;
export const SOUND_EVENT_MAX_M = 600;
export const SOUND_VOICES = 16;

// loudness the operator sets
export const SOUND_VOLUME_DB = -6;
export const SOUND_CEILING_DBFS = -1;
export const SOUND_QUIET_VOLUME_DB = -20;
export const SOUND_QUIET_CEILING_DBFS = -14;
export const SOUND_QUIET_EVENT_DB = -6;
export const SOUND_VISITOR_STEP_DB = 3;
export const SOUND_VISITOR_MAX_DB = 9;
export const SOUND_VISITOR_MIN_DB = -30;
export const SOUND_LIMIT_LOOKAHEAD_MS = 2;
export const SOUND_LIMIT_RELEASE_MS = 80;

// captions
export const SOUND_CAPTION_EVENT_S = 3;
export const SOUND_CAPTION_WHISPER_MS = 8;
export const SOUND_CAPTION_ROAR_MS = 20;
export const SOUND_CAPTION_HOWL_MS = 33;
export const SOUND_CAPTION_RUSTLE_HZ = 30;
export const SOUND_CAPTION_WHISTLE_DB = -40;

// The captions: the keys of their texts in configs/lang (web/lang.js), in the C table's order.
export const SOUND_CAPTIONS = [
    'sound.wind_whispering', 'sound.wind_blowing', 'sound.wind_roaring', 'sound.wind_howling',
    'sound.leaves_rustling', 'sound.twigs_whistling', 'sound.branch_cracks', 'sound.tree_snaps',
    'sound.tree_uprooted',
];
export const SOUND_CAP = { WIND_WHISPERING: 0, WIND_BLOWING: 1, WIND_ROARING: 2, WIND_HOWLING: 3, LEAVES_RUSTLING: 4, TWIGS_WHISTLING: 5, BRANCH_CRACKS: 6, TREE_SNAPS: 7, TREE_UPROOTED: 8 };

export const dbToGain = (db) => Math.pow(10, db / 20);

export function strouhalHz(u_ms, d_m) {
    return SOUND_STROUHAL * u_ms / d_m;
}

// the bed's level [dBFS] at u_ms before each band's offset; -Infinity when silent
export function bedDb(u_ms) {
    if (!(u_ms >= SOUND_BED_U_MIN_MS)) return -Infinity;
    return Math.min(SOUND_BED_DB_REF + SOUND_BED_DB_PER_DECADE * Math.log10(u_ms / SOUND_U_REF_MS), SOUND_BED_DB_MAX);
}

export function bodyHz(u_ms) {
    return SOUND_BODY_HZ0 + SOUND_BODY_HZ_PER_MS * Math.max(u_ms, 0);
}

export function howlShare(u_ms) {
    const x = Math.min(Math.max((u_ms - SOUND_HOWL_U0_MS) / (SOUND_HOWL_U1_MS - SOUND_HOWL_U0_MS), 0), 1);
    return x * x * (3 - 2 * x);
}

// each band's centre [Hz] (the howl's without its wander) and RMS gain (client/audio/wind_bed.c)
export function bandHz(k, u_ms) {
    return k === SOUND_BAND.RUMBLE ? SOUND_RUMBLE_HZ : k === SOUND_BAND.BODY ? bodyHz(u_ms) : SOUND_HOWL_MULT * bodyHz(u_ms);
}
export function bandGain(k, u_ms) {
    const db = bedDb(u_ms);
    if (!Number.isFinite(db)) return 0;
    const g = dbToGain(db + SOUND_BAND_DB[k]);
    return k === SOUND_BAND.HOWL ? g * howlShare(u_ms) : g;
}

// a class with len_m metres near (weighted) at u_ms: its level [dBFS], -Infinity when silent
export function aeolDb(len_m, u_ms, d_m) {
    const f = strouhalHz(u_ms, d_m);
    if (!(len_m > 0) || !(u_ms >= SOUND_BED_U_MIN_MS) || f < SOUND_AEOL_F_MIN_HZ || f > SOUND_AEOL_F_MAX_HZ) return -Infinity;
    const db = SOUND_AEOL_DB_REF + 10 * Math.log10(len_m / SOUND_AEOL_LEN_REF_M) + SOUND_AEOL_DB_PER_DECADE * Math.log10(u_ms / SOUND_U_REF_MS);
    return Math.min(db, SOUND_AEOL_DB_MAX);
}

export function nearWeight(d_m) {
    if (!(d_m <= SOUND_NEAR_M)) return 0;
    const r = Math.max(d_m, SOUND_REF_M) / SOUND_REF_M;
    return 1 / (r * r);
}

export function rustleHz(u_ms, leaves_w, kept) {
    const x = Math.max(u_ms - SOUND_RUSTLE_U0_MS, 0);
    const hz = Math.min(SOUND_RUSTLE_HZ_PER * Math.pow(x, SOUND_RUSTLE_EXP), SOUND_RUSTLE_MAX_HZ);
    const near = leaves_w > 0 ? leaves_w / (leaves_w + SOUND_RUSTLE_LEAVES_HALF) : 0;
    return hz * near * Math.min(Math.max(kept, 0), 1);
}

export function rustleDb(u_ms) {
    return SOUND_RUSTLE_DB_REF + SOUND_RUSTLE_DB_PER_DECADE * Math.log10(Math.max(u_ms, 0.1) / SOUND_U_REF_MS);
}

export function eventLevelDb(k, dist_m) {
    if (!(k >= 0 && k < SOUND_EVENTS) || !(dist_m <= SOUND_EVENT_MAX_M)) return -Infinity;
    return SOUND_EVENT_DB[k] - 20 * Math.log10(Math.max(dist_m, SOUND_EVENT_REF_M) / SOUND_EVENT_REF_M);
}

// pan (−1 left .. +1 right) of a source at bearing rel_rad from the view, counter-clockwise
// positive; equal-power gains [left, right]
export function soundPan(rel_rad) {
    return -Math.sin(rel_rad);
}
export function panGains(pan) {
    const a = (Math.min(Math.max(pan, -1), 1) + 1) * 0.78539816;
    return [Math.cos(a), Math.sin(a)];
}

// the class of diameter d_m: the nearest on a log scale
export function classOf(d_m) {
    let best = 0, bd = Infinity;
    const ld = Math.log(Math.max(d_m, 1e-6));
    for (let k = 0; k < SOUND_CLASSES; k++) {
        const e = Math.abs(ld - Math.log(SOUND_CLASS_D_M[k]));
        if (e < bd) { bd = e; best = k; }
    }
    return best;
}

// the operator's volume and ceiling after the quiet preset (sound_mix_resolve)
export function resolveLoudness(volume_db, ceiling_dbfs, quiet) {
    return {
        volume_db: quiet ? Math.min(volume_db, SOUND_QUIET_VOLUME_DB) : volume_db,
        ceiling_dbfs: Math.min(quiet ? Math.min(ceiling_dbfs, SOUND_QUIET_CEILING_DBFS) : ceiling_dbfs, 0),
    };
}

// what is heard now, most telling first (sound_caption_pick): caption indices
export function captionPick(u_ms, rustle_hz, loudest_tone_db, event) {
    const out = [];
    if (event === SOUND_EV.CRACK) out.push(SOUND_CAP.BRANCH_CRACKS);
    else if (event === SOUND_EV.SNAP) out.push(SOUND_CAP.TREE_SNAPS);
    else if (event === SOUND_EV.UPROOT) out.push(SOUND_CAP.TREE_UPROOTED);
    if (u_ms >= SOUND_BED_U_MIN_MS) {
        out.push(u_ms >= SOUND_CAPTION_HOWL_MS ? SOUND_CAP.WIND_HOWLING : u_ms >= SOUND_CAPTION_ROAR_MS ? SOUND_CAP.WIND_ROARING
            : u_ms < SOUND_CAPTION_WHISPER_MS ? SOUND_CAP.WIND_WHISPERING : SOUND_CAP.WIND_BLOWING);
    }
    if (rustle_hz >= SOUND_CAPTION_RUSTLE_HZ) out.push(SOUND_CAP.LEAVES_RUSTLING);
    if (loudest_tone_db >= SOUND_CAPTION_WHISTLE_DB) out.push(SOUND_CAP.TWIGS_WHISTLING);
    return out;
}

export function captionLine(keys, lang = 'en') {
    return keys.map((k) => t(lang, SOUND_CAPTIONS[k])).join(' ');
}

// A species' diameter classes and leaves from its asset (web/asset.js; sound_species_profile).
export function speciesProfile(a) {
    const len = new Array(SOUND_CLASSES).fill(0);
    let leaves = 0;
    for (let i = 0; i < a.n_nodes; i++) {
        const p = a.parent[i];
        if (p < 0) continue;
        const dx = a.rest[3 * i] - a.rest[3 * p], dy = a.rest[3 * i + 1] - a.rest[3 * p + 1], dz = a.rest[3 * i + 2] - a.rest[3 * p + 2];
        len[classOf(2 * a.radius[i])] += Math.hypot(dx, dy, dz);
    }
    for (let j = 0; j < a.n_leaves; j++) {
        if (a.leaf_shape === 2) len[classOf(SOUND_NEEDLE_D_M)] += SOUND_NEEDLES_PER_TUFT * a.leaf_size[j];
        else leaves += 1;
    }
    return { class_len_m: len, leaves };
}

// The trees near eye_xy (rows [species, x, y, z, yaw, scale]) summed (sound_listen):
// { class_len_m, leaves_w, kept }; prof[species] or null; fallen(t), level(t) from the damage.
export function listen(eye_xy, rows, prof, fallen, level) {
    const len = new Array(SOUND_CLASSES).fill(0);
    let leaves = 0, leavesAll = 0;
    for (let t = 0; t < rows.length; t++) {
        const r = rows[t], p = prof[r[0]];
        if (!p) continue;
        const w = nearWeight(Math.hypot(r[1] - eye_xy[0], r[2] - eye_xy[1]));
        if (w === 0) continue;
        const down = fallen ? fallen(t) : 0, kept = down ? 0 : level ? level(t) / 32 : 1, sc = r[5] > 0 ? r[5] : 1;
        for (let k = 0; k < SOUND_CLASSES; k++) len[k] += w * sc * p.class_len_m[k] * (down ? 0 : 1) * (k === 0 ? kept : 1);
        leavesAll += w * p.leaves;
        leaves += w * p.leaves * kept;
    }
    return { class_len_m: len, leaves_w: leavesAll, kept: leavesAll > 0 ? leaves / leavesAll : 1 };
}
