// The page's sound (web/audio.js) against a real gale-server: the kiosk page in a browser
// that starts Web Audio only after a gesture stays silent (its AudioContext suspended, no
// caption) until a click, then runs; the graph's parameters (read back from the AudioParams
// once held still) are web/sound_policy.js's laws at the wind the page has at its camera:
// the bed's bands' centres and gains, the operator's volume from ?volume= and the clamp
// at ?volume_max=; dialled from a breeze to 40 m/s the body's centre and the bed's gains
// rise with it and the caption says the wind howls; a visitor's ] adds 3 dB. A page in a
// browser that allows autoplay (a kiosk launched with
// --autoplay-policy=no-user-gesture-required) runs its sound without a gesture.
//
// Headless chromium lets some pages start Web Audio without a gesture whatever its
// --autoplay-policy, so the first page runs under an init script that keeps a context
// suspended until the page has had a touch, click or key, as Chrome's policy does.
import assert from 'node:assert/strict';
import { writeFileSync, mkdirSync } from 'node:fs';
import path from 'node:path';
import { args, startServer, startBrowser, waitFor } from './harness.mjs';
import * as P from '../../web/sound_policy.js';

const [server, work, config, scenario] = args('usage: node test_web_sound.mjs GALE_SERVER WORK_DIR SCENE.json SCENARIO.json');
const TOKEN = 'web-sound-test-5d1e';
mkdirSync(work, { recursive: true });
const tokenFile = path.join(work, 'token');
writeFileSync(tokenFile, `${TOKEN}\n`, { mode: 0o600 });
const srv = await startServer(server, ['--cache', path.join(work, '..', 'cache'), '--config', config, '--kiosk-token-file', tokenFile, '--scenario', scenario]);
const ctx = await startBrowser(work, { width: 640, height: 480 });
const out = {};
const near = (got, want, rel, what) => assert.ok(Math.abs(got - want) <= rel * Math.max(Math.abs(want), 1e-9), `${what}: ${got}, expected ${want} (within ${rel * 100} %)`);
const unitRms = (k, hz, rate) => Math.sqrt(1.5 * rate / (Math.PI / 2 * hz / (k === 0 ? 1 : [P.SOUND_RUMBLE_Q, P.SOUND_BODY_Q, P.SOUND_HOWL_Q][k])));

// the targets the page set against the policy at the wind it used, then (held) the
// AudioParams against the targets; held when the wind at the camera is one WANT accepts
// (turbulence moves it about the sustained figure)
async function graphFollows(page, what, want = () => true) {
    let p;
    for (let tries = 0; ; tries++) {
        await page.evaluate(() => window.gale.sound.hold(true));
        await page.waitForTimeout(400); // the glides (20 ms time constant) settle
        p = await page.evaluate(() => window.gale.sound.params());
        if (want(p.targets.u_ms)) break;
        assert.ok(tries < 40, `${what}: the wind at the camera never ${want} (last ${p.targets.u_ms} m/s)`);
        await page.evaluate(() => window.gale.sound.hold(false));
        await page.waitForTimeout(250);
    }
    const t = p.targets, u = t.u_ms;
    for (let k = 0; k < P.SOUND_BANDS; k++) {
        const hz = t.bands[k].frequency;
        if (k !== P.SOUND_BAND.HOWL) near(hz, P.bandHz(k, u), 1e-9, `${what}: band ${k} centre`);
        near(t.bands[k].gain, P.bandGain(k, u) * unitRms(k, hz, p.sample_rate), 1e-9, `${what}: band ${k} gain`);
        near(p.bands[k].frequency, hz, 1e-3, `${what}: band ${k} frequency read back`);
        near(p.bands[k].gain, t.bands[k].gain, 1e-3, `${what}: band ${k} gain read back`);
    }
    assert.equal(p.bands[0].type, 'lowpass');
    near(p.bands[0].Q, 20 * Math.log10(P.SOUND_RUMBLE_Q), 1e-4, `${what}: rumble Q (dB)`);
    near(p.bands[1].Q, P.SOUND_BODY_Q, 1e-4, `${what}: body Q`);
    for (let k = 0; k < P.SOUND_CLASSES; k++) {
        near(t.tones[k].frequency, P.strouhalHz(u, P.SOUND_CLASS_D_M[k]), 1e-9, `${what}: tone ${k} at St U/d`);
        if (t.tones[k].gain > 0) near(p.tones[k].frequency, t.tones[k].frequency, 1e-3, `${what}: tone ${k} read back`);
        near(p.tones[k].gain, t.tones[k].gain, 1e-3, `${what}: tone ${k} gain read back`);
    }
    await page.evaluate(() => window.gale.sound.hold(false));
    return p;
}

try {
    // a browser that wants a gesture: silent until the click
    const page = await ctx.newPage();
    await page.addInitScript(() => {
        let gesture = false; // a trusted touch, click or key (navigator.userActivation is set by the driver's navigation here)
        for (const type of ['pointerdown', 'keydown']) window.addEventListener(type, (e) => { gesture = gesture || e.isTrusted; }, { capture: true });
        const AC = window.AudioContext;
        window.AudioContext = class extends AC {
            constructor(o) { super(o); super.suspend(); }
            resume() { return gesture ? super.resume() : new Promise(() => {}); }
        };
    });
    await page.goto(`${srv.url}/kiosk?volume=-12&volume_max=-3#token=${TOKEN}`);
    await waitFor(page, () => window.gale && window.gale.framesDrawn >= 3 && window.gale.weather && window.gale.lastWind, null, 120, 'kiosk live, drawn, wind known');
    await page.waitForTimeout(500);
    const before = await page.evaluate(() => ({ p: window.gale.sound.params(), caption_hidden: !document.getElementById('sound-caption') || document.getElementById('sound-caption').hidden }));
    assert.notEqual(before.p.state, 'running', 'the sound starts before any gesture');
    assert.equal(before.p.device, 'null');
    assert.ok(before.caption_hidden, 'no caption while the sound is off');
    out.before_click = before.p.state;
    await page.mouse.click(320, 120);
    await waitFor(page, () => window.gale.sound.params().state === 'running', null, 30, 'AudioContext running after the click');
    const breeze = await graphFollows(page, 'breeze', (u) => u > 0.5 && u < 15);
    near(breeze.master_gain, P.dbToGain(-12), 1e-3, 'master gain from ?volume=-12');
    near(breeze.clamp_max, P.dbToGain(-3), 1e-6, 'clamp at ?volume_max=-3');
    out.breeze = { u_ms: breeze.targets.u_ms, body_hz: breeze.bands[1].frequency, gains: breeze.bands.map((b) => b.gain), caption: breeze.caption, device: breeze.device };
    assert.ok(breeze.targets.u_ms > 0.5 && breeze.targets.u_ms < 15, `a breeze at the camera: ${breeze.targets.u_ms} m/s`);
    // the wind dialled up: the graph follows
    await page.evaluate((tok) => window.gale.conn.send({ type: 'wind', speed_ms: 40, token: tok }), TOKEN);
    await waitFor(page, () => window.gale.weather.sustained_ms >= 35 && window.gale.sound.params().targets.u_ms > 25, null, 60, 'the storm at the camera');
    await page.waitForTimeout(800);
    const storm = await graphFollows(page, 'storm', (u) => u > 25);
    out.storm = { u_ms: storm.targets.u_ms, body_hz: storm.bands[1].frequency, gains: storm.bands.map((b) => b.gain), caption: storm.caption };
    assert.ok(storm.bands[1].frequency > breeze.bands[1].frequency + 300, 'the body band rises with the wind');
    for (let k = 0; k < 2; k++) assert.ok(storm.bands[k].gain > 3 * breeze.bands[k].gain, `band ${k} louder with the wind`);
    assert.ok(storm.bands[2].gain > 0 && breeze.bands[2].gain === 0, 'the howl comes in');
    // the caption names the camera's own wind (no gust swing), which turbulence moves about
    // the sustained figure: wait for it past the roar, then hold the word to the wind read in
    // the same instant
    await waitFor(page, (roar) => window.gale.sound.params().scene.u_ms >= roar, P.SOUND_CAPTION_ROAR_MS, 60, 'the camera\'s own wind past the roar');
    const cap = await page.evaluate(() => { const el = document.getElementById('sound-caption'), p = window.gale.sound.params(); return { hidden: el.hidden, text: el.textContent, line: p.caption, u_ms: p.scene.u_ms }; });
    const word = cap.u_ms >= P.SOUND_CAPTION_HOWL_MS ? 'howling' : cap.u_ms >= P.SOUND_CAPTION_ROAR_MS ? 'roaring' : cap.u_ms < P.SOUND_CAPTION_WHISPER_MS ? 'whispering' : 'blowing';
    assert.ok(cap.line.includes(`[wind ${word}]`), `caption for ${cap.u_ms} m/s: ${JSON.stringify(cap)}`);
    assert.ok(!cap.hidden && cap.text === cap.line, `caption shown: ${JSON.stringify(cap)}`);
    out.caption = cap.text;
    // a visitor's step up, and back to the default on idle
    await page.keyboard.press(']');
    await page.waitForTimeout(300);
    near(await page.evaluate(() => window.gale.sound.params().master_gain), P.dbToGain(-9), 1e-3, 'visitor +3 dB');
    await page.evaluate(() => window.gale.sound.visitorReset());
    await page.waitForTimeout(300);
    near(await page.evaluate(() => window.gale.sound.params().master_gain), P.dbToGain(-12), 1e-3, 'reset to the default');
    await page.evaluate((tok) => window.gale.conn.send({ type: 'wind', release: true, token: tok }), TOKEN);
    await page.close();
    assert.deepEqual(ctx.errors, [], 'no page errors');
    // a browser that allows autoplay: running without a gesture (attract loop heard)
    const actx = await startBrowser(path.join(work, 'autoplay'), { width: 640, height: 480, extraArgs: ['--autoplay-policy=no-user-gesture-required'] });
    const auto = await actx.newPage();
    await auto.goto(`${srv.url}/?quiet=1`);
    await waitFor(auto, () => window.gale && window.gale.framesDrawn >= 3 && window.gale.sound.params().state === 'running', null, 120, 'sound without a gesture where autoplay is allowed');
    const q = await auto.evaluate(() => window.gale.sound.params());
    near(q.master_gain, P.dbToGain(P.SOUND_QUIET_VOLUME_DB), 1e-3, 'quiet volume');
    near(q.clamp_max, P.dbToGain(P.SOUND_QUIET_CEILING_DBFS), 1e-6, 'quiet ceiling');
    out.autoplay = q.state;
    assert.deepEqual(actx.errors, [], 'no page errors');
    await actx.close();
    writeFileSync(path.join(work, 'sound.json'), JSON.stringify(out, null, 1));
    console.log(JSON.stringify(out));
} finally {
    await ctx.close();
    srv.stop();
}
