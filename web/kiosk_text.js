// Every word the kiosk page (/kiosk) shows a visitor, by key, in one table: the page never
// writes a visible string of its own, so another language is another table of the same
// keys. The captions (caption.bft0 .. caption.bft12, caption.cat1 .. caption.cat5) are
// configs/captions/en.txt's, the texts gale-client shows (client/kiosk/caption.c);
// tests/web/test_kiosk_js.mjs holds them, the band labels and the compass points to the C.
// {0}, {1}, ... in a text are kt()'s arguments.

export const KIOSK_LANG = 'en';

export const KIOSK_TEXT = {
    'page.title': 'gale kiosk',
    'view.label': 'Trees in the wind',
    'setup.title': 'Kiosk setup',
    'setup.token': 'Kiosk token',
    'setup.start': 'Start',
    'panel.label': 'Wind controls',
    'lang.label': 'Language',
    'hide': 'Hide controls',
    'show': 'Show controls',
    'reset': 'Reset',
    // the wind dial (client/kiosk/kiosk_ui_draw.c draw_dial)
    'dial.title': 'Wind speed',
    'dial.letgo': 'Let go to set',
    'dial.ms': '{0} m/s',
    'dial.kmh': '{0} km/h',
    'dial.mph': '{0} mph',
    'dial.unknown': '–',
    'dial.held': 'Set here',
    'dial.drag': 'Drag the dial',
    'dial.value': '{0} m/s, {1}',
    'band.calm': 'Calm',
    'band.breeze': 'Breeze',
    'band.strong': 'Strong wind',
    'band.ts': 'Tropical storm',
    'band.cat1': 'Cat 1',
    'band.cat2': 'Cat 2',
    'band.cat3': 'Cat 3',
    'band.cat4': 'Cat 4',
    'band.cat5': 'Cat 5',
    // the compass ring (draw_compass): where the wind comes from
    'compass.title': 'Wind from {0}',
    'compass.label': 'Where the wind comes from',
    'compass.value': '{0}, {1}°',
    'compass.N': 'N', 'compass.NNE': 'NNE', 'compass.NE': 'NE', 'compass.ENE': 'ENE',
    'compass.E': 'E', 'compass.ESE': 'ESE', 'compass.SE': 'SE', 'compass.SSE': 'SSE',
    'compass.S': 'S', 'compass.SSW': 'SSW', 'compass.SW': 'SW', 'compass.WSW': 'WSW',
    'compass.W': 'W', 'compass.WNW': 'WNW', 'compass.NW': 'NW', 'compass.NNW': 'NNW',
    'compass.?': '?',
    // the scenarios
    'group.steady': 'Steady winds',
    'group.replay': 'Storm replays',
    'page.prev': 'Previous page',
    'page.next': 'Next page',
    'page.of': '{0} / {1}',
    // a storm replay's controls
    'replay.title': 'Storm replay',
    'replay.pause': 'Pause',
    'replay.play': 'Play',
    'replay.landfall': 'Go to landfall',
    'replay.speed': 'Replay speed (×1 = real time)',
    'replay.x': '×{0}',
    'replay.at': 'At landfall',
    'replay.before': '{0} before landfall',
    'replay.after': '{0} after landfall',
    'replay.hm': '{0} h {1} min',
    'replay.min': '{0} min',
    'replay.pos': 'Replay {0} of {1}',
    'replay.loop': 'Replay {0}, looping',
    'replay.ended': 'Replay ended',
    'replay.paused': '{0} · Paused',
    // nobody at the kiosk (client/app/client_frame.c), and the warning before
    'attract.touch': 'Touch the screen to control the wind',
    'idle.title': 'Still there?',
    'idle.body': 'The exhibit starts its own tour in {0} s.',
    'idle.keep': 'Touch the screen to keep the controls.',
    // what the wind does (configs/captions/en.txt)
    'caption.bft0': 'Calm: smoke rises straight up.',
    'caption.bft1': 'Light air: smoke drifts; leaves are still.',
    'caption.bft2': 'Light breeze: you feel the wind on your face; leaves rustle.',
    'caption.bft3': 'Gentle breeze: leaves and small twigs move all the time; flags fly.',
    'caption.bft4': 'Moderate breeze: dust and paper blow about; small branches move.',
    'caption.bft5': 'Fresh breeze: small trees in leaf begin to sway.',
    'caption.bft6': 'Strong breeze: large branches move; umbrellas are hard to hold.',
    'caption.bft7': 'Near gale: whole trees move; walking into the wind is hard.',
    'caption.bft8': 'Gale: twigs break off trees; walking is difficult.',
    'caption.bft9': 'Strong gale: branches break; slight damage to roofs.',
    'caption.bft10': 'Storm: trees are uprooted; houses are damaged.',
    'caption.bft11': 'Violent storm: widespread damage to trees and buildings.',
    'caption.bft12': 'Hurricane force: devastation.',
    'caption.cat1': 'Category 1: very dangerous winds; roofs and siding are damaged, large branches snap and shallow-rooted trees topple.',
    'caption.cat2': 'Category 2: extremely dangerous winds; major roof damage, many trees snapped or uprooted, roads blocked.',
    'caption.cat3': 'Category 3: devastating damage; roofs torn off well-built homes, many trees snapped or uprooted.',
    'caption.cat4': 'Category 4: catastrophic damage; most of a roof and some walls lost, most trees snapped or uprooted.',
    'caption.cat5': 'Category 5: catastrophic damage; many homes destroyed, fallen trees cut off whole neighbourhoods.',
};

// The text of key with {0}, {1}, ... replaced by args; a key the table lacks reads as
// itself, so a missing translation shows where it is.
export function kt(key, ...args) {
    const t = Object.prototype.hasOwnProperty.call(KIOSK_TEXT, key) ? KIOSK_TEXT[key] : key;
    return t.replace(/\{(\d+)\}/g, (m, i) => (Number(i) < args.length ? String(args[Number(i)]) : m));
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
