// The closed card in the kiosk page and the staff's status page against a real gale-server
// whose opening hours (TZ=UTC, to the second) open a window a few seconds after the page
// loads and close it again: closed, the page shows "Closed — opens at HH:MM" over
// everything and the server reports the kiosk's language and audio (kiosk_state); open,
// the card goes and frames are drawn; closed again, the card is back. /status.html says
// Open and Closed in turn. Screenshots of each in WORK_DIR.
import assert from 'node:assert/strict';
import { writeFileSync, mkdirSync } from 'node:fs';
import path from 'node:path';
import { args, startServer, startBrowser, waitFor, until } from './harness.mjs';

const [server, work, config] = args('usage: node test_web_closed.mjs GALE_SERVER WORK_DIR SCENE.json');
const TOKEN = 'web-closed-test-51c2';
mkdirSync(work, { recursive: true });
const tokenFile = path.join(work, 'token');
writeFileSync(tokenFile, `${TOKEN}\n`, { mode: 0o600 });
const hhmmss = (t) => new Date(t).toISOString().slice(11, 19);
// a window may not span midnight: a run that starts in the day's last 45 s waits for the
// next day (UTC, as the server's TZ)
const DAY_MS = 86400000, left_ms = DAY_MS - (Date.now() % DAY_MS);
if (left_ms < 45000) await new Promise((r) => setTimeout(r, left_ms + 1000));
const t0 = Date.now();
const opens = t0 + 15000, closes = t0 + 30000;
const srv = await startServer(server, ['--cache', path.join(work, '..', 'cache'), '--config', config,
    '--kiosk-token-file', tokenFile, '--hours', `${hhmmss(opens)}-${hhmmss(closes)}`], { env: { TZ: 'UTC' } });
const status = async () => (await fetch(`${srv.url}/status`)).json();
const ctx = await startBrowser(work, { width: 800, height: 600 });
const out = {};
try {
    const page = await ctx.newPage();
    await page.goto(`${srv.url}/kiosk?attract=3600#token=${TOKEN}`);
    const card = () => page.evaluate(() => { const c = document.getElementById('closed'); return c && !c.hidden ? c.textContent : null; });
    await waitFor(page, () => { const c = document.getElementById('closed'); return c && !c.hidden; }, null, 30, 'the closed card');
    out.closed_card = await card();
    assert.equal(out.closed_card, `Closed \u2014 opens at ${hhmmss(opens).slice(0, 5)}`);
    // the card covers the panel: a touch at the panel's place lands on the card
    const hit = await page.evaluate(() => { const r = document.getElementById('panel').getBoundingClientRect(); const e = document.elementFromPoint(r.x + r.width / 2, r.y + r.height / 2); return e && e.closest('#closed') && 'closed'; });
    assert.equal(hit, 'closed', 'the closed card takes the touches');
    // the audio the page reports: its sound's output ('null' until Web Audio runs, which
    // chromium here may start unasked: the page tells the server again when it does)
    const audio = () => page.evaluate(() => window.gale.sound.deviceName());
    await until(async () => { const s = await status(); return s.languages.length === 1 && s.audio[0] === await audio(); }, 20, 'the kiosk reported its state');
    const s1 = await status();
    assert.deepEqual([s1.state, s1.languages, s1.audio, s1.clients.kiosk], ['closed', ['en'], [await audio()], 1]);
    await page.screenshot({ path: path.join(work, 'kiosk-closed.png') });
    const staff = await ctx.newPage();
    await staff.goto(`${srv.url}/status.html`);
    await waitFor(staff, () => document.getElementById('state').textContent === 'Closed', null, 20, 'status page: Closed');
    out.status_next = await staff.textContent('#next');
    assert.ok(out.status_next.startsWith(`opens at ${hhmmss(opens)}`), `status page next change: ${out.status_next}`);
    await staff.screenshot({ path: path.join(work, 'status-closed.png') });
    // the opening: the card goes, the page draws
    await waitFor(page, () => document.getElementById('closed').hidden && window.gale && window.gale.framesDrawn >= 3, null, 60, 'open: card hidden and frames drawn');
    await waitFor(staff, () => document.getElementById('state').textContent === 'Open', null, 20, 'status page: Open');
    await page.screenshot({ path: path.join(work, 'kiosk-open.png') });
    await staff.screenshot({ path: path.join(work, 'status-open.png') });
    // the closing: the card is back, the connection stays
    await waitFor(page, () => !document.getElementById('closed').hidden, null, 60, 'closed again: the card is back');
    out.closed_again = await card();
    assert.ok(/^Closed \u2014 opens at \d\d:\d\d$/.test(out.closed_again), out.closed_again);
    const s2 = await status();
    assert.equal(s2.state, 'closed');
    assert.equal(s2.clients.kiosk, 1, 'the kiosk stayed connected');
    assert.deepEqual(ctx.errors, [], `page errors: ${ctx.errors.join('; ')}`);
    console.log(JSON.stringify({ ...out, ok: true }));
} finally {
    await ctx.close();
    await srv.stop();
}
