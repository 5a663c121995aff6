// The kiosk page's words by the keys its code and kiosk.html use, read from the visitor's
// texts of configs/lang (web/lang.js, the table gale-client is built with): each page key
// names the shared key it shows, so the page and the native panel say the same words in
// every language. The page's language is set here (setKioskLang); kt(key, ...args) formats
// with C's printf rules, as the shared texts are written.
import { t, scenarioTitle } from './lang.js';

let lang = 'en';

// page key -> configs/lang key
const MAP = {
    'page.title': 'page.title', 'view.label': 'page.view_label',
    'setup.title': 'page.setup_title', 'setup.token': 'page.setup_token', 'setup.start': 'page.setup_start',
    'panel.label': 'page.panel_label', 'lang.label': 'kiosk.language',
    'hide': 'kiosk.hide', 'show': 'kiosk.show', 'reset': 'kiosk.reset',
    'dial.title': 'kiosk.wind_speed', 'dial.letgo': 'kiosk.let_go', 'dial.held': 'kiosk.set_here', 'dial.drag': 'kiosk.drag',
    'dial.ms': 'unit.ms', 'dial.kmh': 'unit.kmh', 'dial.mph': 'unit.mph', 'dial.value': 'page.dial_value',
    'band.calm': 'kiosk.band_calm', 'band.breeze': 'kiosk.band_breeze', 'band.strong': 'kiosk.band_strong',
    'band.ts': 'ss.1', 'band.cat1': 'ss_abbrev.2', 'band.cat2': 'ss_abbrev.3', 'band.cat3': 'ss_abbrev.4',
    'band.cat4': 'ss_abbrev.5', 'band.cat5': 'ss_abbrev.6',
    'compass.title': 'kiosk.wind_from', 'compass.label': 'page.compass_label', 'compass.value': 'page.compass_value',
    'group.steady': 'kiosk.steady_winds', 'group.replay': 'kiosk.storm_replays',
    'page.prev': 'kiosk.previous', 'page.next': 'kiosk.next', 'page.of': 'page.of',
    'replay.title': 'kiosk.storm_replay', 'replay.pause': 'kiosk.pause', 'replay.play': 'kiosk.play',
    'replay.landfall': 'kiosk.landfall', 'replay.speed': 'kiosk.replay_speed', 'replay.x': 'page.times',
    'replay.at': 'page.at_landfall', 'replay.before': 'page.before_landfall', 'replay.after': 'page.after_landfall',
    'replay.hm': 'page.hours_minutes', 'replay.min': 'page.minutes', 'replay.pos': 'page.replay_pos',
    'replay.loop': 'page.replay_loop', 'replay.ended': 'page.replay_ended', 'replay.paused': 'page.replay_paused',
    'attract.touch': 'kiosk.touch', 'attract.water': 'attract.water',
    'idle.title': 'page.idle_title', 'idle.body': 'page.idle_body', 'idle.keep': 'page.idle_keep',
};
const COMPASS = ['N', 'NNE', 'NE', 'ENE', 'E', 'ESE', 'SE', 'SSE', 'S', 'SSW', 'SW', 'WSW', 'W', 'WNW', 'NW', 'NNW'];
COMPASS.forEach((p, i) => { MAP[`compass.${p}`] = `compass.${i}`; });
for (let b = 0; b <= 12; b++) MAP[`caption.bft${b}`] = `caption.bft.${b}`;
for (let c = 1; c <= 5; c++) MAP[`caption.cat${c}`] = `caption.cat.${c}`;
// signs, the same in every language
const SIGNS = { 'compass.?': '?', 'dial.unknown': '\u2013' };

// The page keys and the shared keys they show (tests/web/test_kiosk_js.mjs checks each
// exists in every language).
export const KIOSK_KEYS = Object.freeze({ ...MAP });

export function setKioskLang(code) {
    lang = code;
}

export function kioskLang() {
    return lang;
}

// The text of a page key in the page's language, formatted with args; a key the table
// lacks reads as itself, so a missing word shows where it is.
export function kt(key, ...args) {
    if (Object.prototype.hasOwnProperty.call(SIGNS, key)) return SIGNS[key];
    if (!Object.prototype.hasOwnProperty.call(MAP, key)) return key;
    return t(lang, MAP[key], ...args);
}

// A scenario's title in the page's language (the shipped steady winds'; a storm keeps its name).
export function scenarioText(title) {
    return scenarioTitle(lang, title);
}

// The caption's key of a wind class (WEATHER ss_class 0..6, beaufort 0..12): a hurricane's
// category (cat1..cat5, ss_class 2..6), else its Beaufort force (client/kiosk/caption.c
// caption_for).
export function captionKey(ssClass, beaufort) {
    if (ssClass >= 2 && ssClass <= 6) return `cat${ssClass - 1}`;
    const b = beaufort < 0 ? 0 : beaufort > 12 ? 12 : beaufort | 0;
    return `bft${b}`;
}

// The caption of a key (bft0..bft12, cat1..cat5).
export function caption(key) {
    return kt(`caption.${key}`);
}
