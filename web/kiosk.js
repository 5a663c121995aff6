// The kiosk page (/kiosk): the scene with gale-client's touch panel (client/kiosk/kiosk_ui.c,
// kiosk_ui_draw.c; PROTOCOL.md "The kiosk's touch panel") along the bottom edge: the banded
// wind dial and the compass ring (web/kiosk_dial.js), the scenario buttons with the running
// one lit and the replay controls while a storm replays (web/kiosk_panel.js), reset, and
// above it the caption of the wind's class as gale-client shows it. Every word is
// web/kiosk_text.js's. The token is typed once on the setup screen (or given in the URL
// fragment, #token=..., which never reaches the server) and kept in this browser's
// localStorage: never in the query string or the page source. After ?attract=S seconds
// (default 90, as gale-client's --attract) without a touch the page lets go of its dial
// and tours the cameras (web/attract.js), having warned the visitor ATTRACT_WARN_S before
// (a touch keeps the controls); the next touch wakes it. A browser asking for less motion
// (prefers-reduced-motion) gets a slower tour and no rain streaks.
import { App } from './app.js';
import { Attract, cameraTour, CAMERA_TOUR_TURN_DEG_S, CAMERA_TOUR_TURN_REDUCED_DEG_S } from './attract.js';
import { DialMessages, runningIndex } from './kiosk_scale.js';
import { kt, caption, captionKey, setKioskLang, kioskLang } from './kiosk_text.js';
import { langCodes, t } from './lang.js';
import { WindDial, CompassRing } from './kiosk_dial.js';
import { ScenarioGroup, replayWhere, REPLAY_SPEEDS } from './kiosk_panel.js';

const KEY = 'gale.kiosk.token';
const W_STORM = 1, W_DIAL = 2, W_PAUSED = 16;
const $ = (id) => document.getElementById(id);
const reducedMotion = matchMedia('(prefers-reduced-motion: reduce)');

// the words of the page's own elements, by their data-kt and data-kt-label keys, and of
// everything drawn from state, in the page's language
function applyText() {
    document.documentElement.lang = kioskLang();
    for (const e of document.querySelectorAll('[data-kt]')) e.textContent = kt(e.dataset.kt);
    for (const e of document.querySelectorAll('[data-kt-label]')) e.setAttribute('aria-label', kt(e.dataset.ktLabel));
    for (const b of document.querySelectorAll('#speeds button')) b.textContent = kt('replay.x', Number(b.dataset.speed));
    for (const b of document.querySelectorAll('#lang button')) b.setAttribute('aria-pressed', String(b.dataset.lang === kioskLang()));
    if (app && app.welcome) {
        steady.relabel();
        replays.relabel();
        showPanel();
        if (app.weather) onWeather(app.weather);
    }
}

// The visitor's language (a button in each language's own name, or idle's return to the
// operator's ?lang=): the page, its HUD and sound captions from the next frame, and the
// server told (kiosk_state).
function setLanguage(code) {
    if (code === kioskLang()) return;
    setKioskLang(code);
    if (app) app.setLang(code);
    applyText();
    sendKioskState();
}

function tokenFromFragment() {
    const m = location.hash.match(/(?:^#|&)token=([^&]*)/);
    if (!m) return;
    localStorage.setItem(KEY, decodeURIComponent(m[1]));
    history.replaceState(null, '', location.pathname + location.search); // off the address bar
}

let app = null;
let attract = null;
let tourStart_s = 0;
let ownCam = null; // the kiosk's camera before the tour, restored on waking
let collapsed = false;
let scenarios = [];
const msgs = new DialMessages();
const now_s = () => performance.now() * 1e-3;

function send(msg) {
    return app && app.conn && app.conn.send({ ...msg, token: localStorage.getItem(KEY) });
}

const dial = new WindDial($('dial'), (v) => send(msgs.speed(v)));
const compass = new CompassRing($('compass'), (deg) => send(msgs.dir(deg)));
const pick = (sc) => send(msgs.scenario(sc.name));
const steady = new ScenarioGroup($('steady'), () => 2, pick);
// a replay library: one row of replays on a short screen, two on a tall one
const replays = new ScenarioGroup($('replays'), () => (innerHeight >= 900 ? 2 : 1), pick);

function showPanel() {
    const up = $('setup').hidden && !!app && !!app.welcome && !(attract && attract.active);
    $('panel').hidden = !up || collapsed;
    $('collapse').hidden = !up;
    $('collapse').textContent = kt(collapsed ? 'show' : 'hide');
    $('collapse').setAttribute('aria-expanded', String(!collapsed));
    if (up && !collapsed) {
        steady.layout();
        replays.layout();
    }
}

function showSetup(message) {
    $('panel').hidden = true;
    $('collapse').hidden = true;
    $('setup').hidden = false;
    $('setup-error').textContent = message || '';
    $('token').focus();
}

function onWeather(w) {
    dial.show(w.sustained_ms, (w.flags & W_DIAL) !== 0);
    compass.show(w.dir_from_deg);
    const run = runningIndex(w, scenarios);
    steady.light(run);
    replays.light(run);
    const cap = caption(captionKey(w.ss_class, w.beaufort));
    if ($('caption').textContent !== cap) $('caption').textContent = cap;
    $('caption').hidden = false;
    const storm = (w.flags & W_STORM) !== 0;
    $('replay').hidden = !storm;
    if (storm) {
        const paused = (w.flags & W_PAUSED) !== 0;
        $('pause-text').textContent = kt(paused ? 'replay.play' : 'replay.pause');
        $('pause').classList.toggle('paused', paused); // (its words say what it does: no pressed state)
        for (const b of document.querySelectorAll('[data-speed]')) {
            b.setAttribute('aria-pressed', String(Math.abs(Number(b.dataset.speed) - w.replay_speed) < 0.5));
        }
        const where = replayWhere(w);
        $('replay-at').textContent = where.at;
        $('replay-pos').textContent = paused ? kt('replay.paused', where.pos) : where.pos;
        $('replay-bar').style.width = where.share === null ? '100%' : `${(100 * where.share).toFixed(1)}%`;
    }
}

// What this kiosk shows and plays through, for the staff's status page (PROTOCOL.md
// "kiosk_state"): its language, and its sound's output once the first touch started it.
function sendKioskState() {
    send({ type: 'kiosk_state', lang: kioskLang(), audio: app && app.sound ? app.sound.deviceName() : 'null' });
}

function onWelcome(w) {
    sendKioskState();
    $('setup').hidden = true;
    scenarios = w.scenarios || [];
    const rows = scenarios.map((sc, index) => ({ sc, index }));
    steady.set(rows.filter((r) => r.sc.kind !== 'replay'));
    replays.set(rows.filter((r) => r.sc.kind === 'replay'));
    showPanel();
    if (app.weather) onWeather(app.weather);
}

// nobody at the kiosk: the scenario's wind back (the scene's own scenario or playlist:
// scenario ""), the panel away, the cameras toured
function attractBegin() {
    send({ type: 'wind', release: true, scenario: '' });
    app.sound.visitorReset(); // the next visitor starts at the operator's volume
    setLanguage(app.langDefault); // and reads the operator's language
    msgs.forget();
    document.activeElement && document.activeElement.blur && document.activeElement.blur();
    $('idle').hidden = true;
    $('attract').hidden = false;
    ownCam = { ...app.cam, target: [...app.cam.target] };
    tourStart_s = now_s();
    showPanel();
}

function attractFrame() {
    requestAnimationFrame(attractFrame);
    if (!app || !app.welcome || !app.ready || !attract) return;
    // less motion asked for: no rain streaks (the sky, fog and spray stay)
    if (reducedMotion.matches && app.r && app.r.fx && app.r.fx.rain_layers > 0) app.r.fx = { ...app.r.fx, rain_layers: 0 };
    const t = now_s();
    if (attract.tick(t)) attractBegin();
    if (attract.active) {
        // the cards in turn: the invitation to touch, and that water takes most lives
        const card = kt(attract.card(t) === 1 ? 'attract.water' : 'attract.touch');
        if ($('attract').textContent !== card) $('attract').textContent = card;
        const w = app.welcome, turn = reducedMotion.matches ? CAMERA_TOUR_TURN_REDUCED_DEG_S : CAMERA_TOUR_TURN_DEG_S;
        const c = cameraTour(t - tourStart_s, w.instances, w.species.map((s) => s.name), turn);
        Object.assign(app.cam, { target: c.target, distance: c.distance, yaw: c.yaw, pitch: c.pitch });
    }
    // the warning before the tour, counting down
    const warn = $('setup').hidden && attract.warning(t);
    if (warn) {
        const body = kt('idle.body', Math.ceil(attract.left_s(t)));
        if ($('idle-body').textContent !== body) $('idle-body').textContent = body;
    }
    if ($('idle').hidden === warn) $('idle').hidden = !warn;
}

// a touch, key or wheel: the idle clock restarts; the touch that wakes the kiosk, or that
// answers the warning, is not taken as a control
function onInput(e) {
    if (!attract) return;
    const warned = !$('idle').hidden;
    const woke = attract.input(now_s());
    if (!woke && !warned) return;
    e.preventDefault();
    e.stopImmediatePropagation();
    $('idle').hidden = true;
    if (woke) {
        if (ownCam) Object.assign(app.cam, ownCam);
        $('attract').hidden = true;
        showPanel();
    }
}
for (const type of ['pointerdown', 'keydown', 'wheel']) {
    window.addEventListener(type, onInput, { capture: true, passive: false });
}

function attractIdle_s() {
    const v = new URLSearchParams(location.search).get('attract');
    if (v === null) return 0;
    const s = Number(v);
    if (s >= 1 && s <= 86400) return s;
    console.warn(`attract=${v}: expected 1..86400 s; 90 s is used`);
    return 0;
}

function start(token) {
    if (app) {
        app.conn.o.token = token;
        app.conn.start();
        return;
    }
    app = new App({
        role: 'kiosk', token, onWelcome, onWeather, onSoundState: () => app && app.welcome && sendKioskState(),
        onStatus: (s) => {
            if (s.state === 'refused') {
                localStorage.removeItem(KEY);
                app.say('');
                showSetup(s.text);
            }
        },
    });
    app.kiosk = { dial, compass, steady, replays, msgs };
    app.start();
    attract = new Attract(attractIdle_s(), now_s());
    requestAnimationFrame(attractFrame);
}

// the language buttons, each in its own language's name
for (const code of langCodes()) {
    const b = document.createElement('button');
    b.type = 'button';
    b.dataset.lang = code;
    b.lang = code;
    b.textContent = t(code, 'lang.name');
    b.addEventListener('click', () => setLanguage(code));
    $('lang').append(b);
}
setKioskLang(new URLSearchParams(location.search).get('lang') && langCodes().includes(new URLSearchParams(location.search).get('lang'))
    ? new URLSearchParams(location.search).get('lang') : 'en');
applyText();
for (const x of REPLAY_SPEEDS) {
    const b = document.createElement('button');
    b.type = 'button';
    b.dataset.speed = String(x);
    b.textContent = kt('replay.x', x);
    b.setAttribute('aria-pressed', 'false');
    b.addEventListener('click', () => send({ type: 'wind', replay_speed: x }));
    $('speeds').append(b);
}
tokenFromFragment();
$('pause').addEventListener('click', () => send({ type: 'wind', replay_paused: !$('pause').classList.contains('paused') }));
$('landfall').addEventListener('click', () => send({ type: 'wind', replay_at_min: 0 }));
$('reset').addEventListener('click', () => send(msgs.reset()));
$('collapse').addEventListener('click', () => { collapsed = !collapsed; showPanel(); });
window.addEventListener('resize', () => { if (!$('panel').hidden) { steady.layout(); replays.layout(); } });
$('setup').addEventListener('submit', (e) => {
    e.preventDefault();
    const t = $('token').value;
    if (!t) return;
    localStorage.setItem(KEY, t);
    $('token').value = '';
    start(t);
});
// the dial is released when the visitor's page goes away
window.addEventListener('pagehide', () => send({ type: 'wind', release: true }));

const stored = localStorage.getItem(KEY);
if (stored) start(stored);
else showSetup('');
