// The kiosk page (/kiosk): the scene with the touch panel of client/kiosk/kiosk_ui.c as HTML
// (PROTOCOL.md "The kiosk's touch panel"). The token is typed once on the setup screen
// (or given in the URL fragment, #token=..., which never reaches the server) and kept in
// this browser's localStorage: never in the query string or the page source. After
// ?attract=S seconds (default 90, as gale-client's --attract) without a touch the page
// lets go of its dial and tours the cameras (web/attract.js); the next touch wakes it.
import { App } from './app.js';
import { Attract, cameraTour } from './attract.js';

const KEY = 'gale.kiosk.token';
const $ = (id) => document.getElementById(id);

function tokenFromFragment() {
    const m = location.hash.match(/(?:^#|&)token=([^&]*)/);
    if (!m) return;
    localStorage.setItem(KEY, decodeURIComponent(m[1]));
    history.replaceState(null, '', location.pathname + location.search); // off the address bar
}

function showSetup(message) {
    $('panel').hidden = true;
    $('setup').hidden = false;
    $('setup-error').textContent = message || '';
    $('token').focus();
}

let app = null;
let dialSent = 0;
let dialTimer = null;
let chosenDir = false;
let attract = null;
let tourStart_s = 0;
let ownCam = null; // the kiosk's camera before the tour, restored on waking
const now_s = () => performance.now() * 1e-3;

function send(msg) {
    return app && app.conn && app.conn.send({ ...msg, token: localStorage.getItem(KEY) });
}

// the dial sends a few values a second while dragged and the last on release
function sendDial(final) {
    const speed = Number($('dial').value);
    const msg = { type: 'wind', speed_ms: speed };
    if (chosenDir) msg.dir_deg = dirDeg();
    const now = performance.now();
    clearTimeout(dialTimer);
    if (final || now - dialSent > 250) {
        dialSent = now;
        send(msg);
    } else {
        dialTimer = setTimeout(() => sendDial(true), 250);
    }
}

// compass: where the wind comes from, clockwise from north; the wire wants where it blows
// towards, counter-clockwise from +x: 270° − bearing
function dirDeg() {
    return (((270 - Number($('compass').value)) % 360) + 360) % 360;
}

function letters(s) { return (s || '').toLowerCase().replace(/[^a-z0-9]/g, ''); }

function onWeather(w) {
    if (document.activeElement !== $('dial')) {
        $('dial').value = Math.round(w.sustained_ms);
        $('dial-out').textContent = Math.round(w.sustained_ms);
    }
    if (document.activeElement !== $('compass')) {
        $('compass').value = Math.round(w.dir_from_deg) % 360;
        $('compass-out').textContent = Math.round(w.dir_from_deg) % 360;
    }
    for (const b of document.querySelectorAll('#scenarios button')) {
        b.setAttribute('aria-pressed', String(letters(w.name) !== '' && (letters(w.name) === letters(b.dataset.title) || letters(w.name) === letters(b.dataset.name))));
    }
    const paused = (w.flags & 16) !== 0;
    $('pause').textContent = paused ? 'Play' : 'Pause';
    $('pause').setAttribute('aria-pressed', String(paused));
    for (const b of document.querySelectorAll('[data-speed]')) {
        b.setAttribute('aria-pressed', String(Math.abs(Number(b.dataset.speed) - w.replay_speed) < 0.5));
    }
}

// What this kiosk shows and plays through, for the staff's status page (PROTOCOL.md
// "kiosk_state"): English and no audio until the page has others to choose from.
function sendKioskState() {
    send({ type: 'kiosk_state', lang: 'en', audio: 'none' });
}

function onWelcome(w) {
    sendKioskState();
    $('setup').hidden = true;
    $('panel').hidden = false;
    const box = $('scenarios');
    box.textContent = '';
    for (const sc of w.scenarios || []) {
        const b = document.createElement('button');
        b.type = 'button';
        b.textContent = sc.title || sc.name;
        b.dataset.name = sc.name;
        b.dataset.title = sc.title;
        b.addEventListener('click', () => send({ type: 'wind', scenario: sc.name }));
        box.append(b);
    }
}

// nobody at the kiosk: the scenario's wind back (the scene's own scenario or playlist:
// scenario ""), the panel away, the cameras toured
function attractBegin() {
    send({ type: 'wind', release: true, scenario: '' });
    app.sound.visitorReset(); // the next visitor starts at the operator's volume
    $('dial').blur();
    $('compass').blur();
    chosenDir = false;
    $('panel').hidden = true;
    $('attract').hidden = false;
    ownCam = { ...app.cam, target: [...app.cam.target] };
    tourStart_s = now_s();
}

function attractFrame() {
    requestAnimationFrame(attractFrame);
    if (!app || !app.welcome || !app.ready || !attract) return;
    if (attract.tick(now_s())) attractBegin();
    if (attract.active) {
        const w = app.welcome, c = cameraTour(now_s() - tourStart_s, w.instances, w.species.map((s) => s.name));
        Object.assign(app.cam, { target: c.target, distance: c.distance, yaw: c.yaw, pitch: c.pitch });
    }
}

// a touch, key, wheel or control change: the idle clock restarts; the touch that wakes
// the kiosk is not taken as a control
function onInput(e) {
    if (!attract || !attract.input(now_s())) return;
    e.preventDefault();
    e.stopImmediatePropagation();
    if (ownCam) Object.assign(app.cam, ownCam);
    $('attract').hidden = true;
    $('panel').hidden = !$('setup').hidden;
}
for (const type of ['pointerdown', 'keydown', 'wheel', 'input', 'change']) {
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
        role: 'kiosk', token, onWelcome, onWeather,
        onStatus: (s) => {
            if (s.state === 'refused') {
                localStorage.removeItem(KEY);
                app.say('');
                showSetup(s.text);
            }
        },
    });
    app.start();
    attract = new Attract(attractIdle_s(), now_s());
    requestAnimationFrame(attractFrame);
}

tokenFromFragment();
$('dial').addEventListener('input', () => { $('dial-out').textContent = $('dial').value; sendDial(false); });
$('dial').addEventListener('change', () => sendDial(true));
$('compass').addEventListener('input', () => { $('compass-out').textContent = $('compass').value; chosenDir = true; });
$('compass').addEventListener('change', () => {
    chosenDir = true;
    const msg = { type: 'wind', dir_deg: dirDeg() };
    if (app && app.weather && app.weather.flags & 2) msg.speed_ms = Number($('dial').value);
    send(msg);
});
$('pause').addEventListener('click', () => send({ type: 'wind', replay_paused: $('pause').getAttribute('aria-pressed') !== 'true' }));
$('landfall').addEventListener('click', () => send({ type: 'wind', replay_at_min: 0 }));
for (const b of document.querySelectorAll('[data-speed]')) {
    b.addEventListener('click', () => send({ type: 'wind', replay_speed: Number(b.dataset.speed) }));
}
$('reset').addEventListener('click', () => send({ type: 'reset' }));
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
