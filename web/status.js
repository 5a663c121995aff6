// The staff's status page (/status.html): reads /status every few seconds and writes it
// out in plain words (server/SERVER.md "Status"). No framework; English only.
'use strict';

const POLL_MS = 3000;
const CLASS_NAMES = { td: 'Below storm', ts: 'Tropical storm', cat1: 'Cat 1', cat2: 'Cat 2',
    cat3: 'Cat 3', cat4: 'Cat 4', cat5: 'Cat 5' };

function $(id) {
    return document.getElementById(id);
}

function duration(s) {
    s = Math.max(0, Math.round(s));
    if (s < 60) return `${s} s`;
    if (s < 3600) return `${Math.floor(s / 60)} min ${s % 60} s`;
    if (s < 86400) return `${Math.floor(s / 3600)} h ${Math.floor(s / 60) % 60} min`;
    return `${Math.floor(s / 86400)} d ${Math.floor(s / 3600) % 24} h`;
}

function counts(o, names) {
    const rows = Object.entries(o || {}).filter(([, n]) => n > 0);
    if (!rows.length) return 'none yet';
    return rows.map(([k, n]) => `${names ? names[k] || k : k}: ${n}`).join(', ');
}

function show(s) {
    const st = $('state');
    st.textContent = s.state === 'open' ? 'Open' : 'Closed';
    st.className = `state ${s.state === 'open' ? 'open' : 'closed'}`;
    const sc = s.schedule;
    $('today').textContent = sc.today === 'always' ? 'always open' : sc.today;
    $('next').textContent = sc.next_change
        ? `${s.state === 'open' ? 'closes' : 'opens'} at ${sc.next_change} (in ${duration(sc.next_in_s)})`
        : 'none';
    const c = s.clients;
    $('kiosks').textContent = String(c.kiosk);
    $('others').textContent = `${c.viewer} viewers, ${c['wall-tile']} wall tiles`;
    $('last').textContent = s.last_interaction
        ? `${duration(s.last_interaction.ago_s)} ago (${new Date(s.last_interaction.utc).toLocaleTimeString()})`
        : 'none since the server started';
    $('lang').textContent = s.languages.length ? s.languages.join(', ') : 'no kiosk reported';
    $('audio').textContent = s.audio.length ? s.audio.join(', ') : 'no kiosk reported';
    $('uptime').textContent = duration(s.uptime_s);
    const u = s.usage;
    $('sessions').textContent = `${u.sessions}${u.session_under_way ? ' (one under way)' : ''}`;
    $('dwell').textContent = duration(u.dwell_s);
    $('dials').textContent = counts(u.categories, CLASS_NAMES);
    $('replays').textContent = counts(u.replays);
    $('langs').textContent = counts(u.languages);
    $('updated').textContent = `Updated ${new Date().toLocaleTimeString()}`;
}

async function poll() {
    try {
        const r = await fetch('/status', { cache: 'no-store' });
        if (!r.ok) throw new Error(`HTTP ${r.status}`);
        show(await r.json());
    } catch (e) {
        const st = $('state');
        st.textContent = 'Not answering';
        st.className = 'state down';
        $('updated').textContent = `The server did not answer (${e.message}); trying again…`;
    }
    setTimeout(poll, POLL_MS);
}

poll();
