// web/hud_text.js against gale-client's HUD (gale-web-hud-table, built from
// client/hud/hud_format.c by tests/web/CMakeLists.txt): for each WEATHER frame of the table,
// decoded by web/wire.js, the browser's HUD lines equal gale-client's, character for
// character, in every language (one wording of the weather on every screen of an exhibit),
// with the texts the page is served (the generated lang_texts.js).
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { pathToFileURL } from 'node:url';
import { Decoder } from '../../web/wire.js';
import { weatherLines } from '../../web/hud_text.js';
import { setTexts } from '../../web/lang.js';

const a = process.argv.slice(2);
if (a.includes('--help') || a.length !== 2) {
    console.log('usage: node test_hud_js.mjs GALE_WEB_HUD_TABLE LANG_TEXTS_JS');
    process.exit(a.includes('--help') ? 0 : 2);
}
const { LANG_CODES, TEXTS } = await import(pathToFileURL(a[1]).href);
setTexts(LANG_CODES, TEXTS);
const rows = execFileSync(a[0], { encoding: 'utf8' }).trim().split('\n').map((l) => JSON.parse(l));
assert.ok(rows.length >= 20, `the table has ${rows.length} cases`);
const seen = { classes: new Set(), forces: new Set(), storm: 0, clock: 0, names: 0 };
for (const r of rows) {
    const f = new Decoder().decode(Uint8Array.from(Buffer.from(r.hex, 'hex')));
    const w = f.weather;
    assert.ok(w, `a WEATHER frame: ${r.hex}`);
    seen.classes.add(w.ss_class);
    seen.forces.add(w.beaufort);
    seen.storm += (w.flags & 1) !== 0;
    seen.clock += (w.flags & 8) !== 0;
    seen.names += w.name !== '';
    assert.deepEqual(Object.keys(r.lines), LANG_CODES, 'a case per language');
    for (const lang of LANG_CODES) {
        assert.deepEqual(weatherLines(w, lang), r.lines[lang], `the HUD in ${lang} of ${JSON.stringify(w)}`);
    }
}
assert.equal(seen.classes.size, 7, 'every Saffir-Simpson class');
assert.ok(seen.forces.size >= 12, `Beaufort forces: ${[...seen.forces]}`);
assert.ok(seen.storm >= 3 && seen.clock >= 2 && seen.names >= 10, JSON.stringify(seen));
assert.ok(rows.some((r) => r.lines.es[0] !== r.lines.en[0]), 'the languages differ');
console.log(JSON.stringify({ cases: rows.length, languages: LANG_CODES.length, classes: seen.classes.size, forces: seen.forces.size, ok: true }));
