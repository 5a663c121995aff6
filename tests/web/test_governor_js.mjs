// web/governor.js against gale-client's governor (gale-web-governor-table, built from
// client/render/governor.c by tests/web/CMakeLists.txt): over the same frame times and
// clock, the same steps at the same frames and the same distance and resolution scales.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { Governor, softwareRenderer } from '../../web/governor.js';

const a = process.argv.slice(2);
if (a.includes('--help') || a.length !== 1) {
    console.log('usage: node test_governor_js.mjs GALE_WEB_GOVERNOR_TABLE');
    process.exit(a.includes('--help') ? 0 : 2);
}
const lines = execFileSync(a[0], { encoding: 'utf8' }).trim().split('\n').map((l) => JSON.parse(l));
let g = null, seq = '', frames = 0, changes = 0;
for (const l of lines) {
    if (l.seq) {
        g = new Governor(l.target_ms, l.software, 0);
        seq = l.seq;
        continue;
    }
    const changed = g.frame(l.ms, l.t_s);
    const where = `${seq}: frame at ${l.t_s.toFixed(3)} s`;
    assert.equal(changed, l.changed, `${where}: changed`);
    assert.equal(g.step, l.step, `${where}: step`);
    assert.equal(Math.fround(g.lodScale()), Math.fround(l.lod), `${where}: distance scale`);
    assert.equal(Math.fround(g.resScale()), Math.fround(l.res), `${where}: resolution scale`);
    frames++;
    changes += changed;
}
assert.ok(changes >= 6, `the sequences change steps (${changes})`);
assert.ok(softwareRenderer('Google SwiftShader') && softwareRenderer('llvmpipe (LLVM 15.0.6, 256 bits)') && !softwareRenderer('ANGLE (NVIDIA)'));
console.log(`governor: ${frames} frames, ${changes} step changes agree`);
