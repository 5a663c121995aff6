// web/asset.js: hash64 against the table of protocol/ASSET.md "Content hash" (read from
// that file), and a served asset decoded with its CRCs checked, against the same asset's
// hash. node test_asset_js.mjs ASSET.md [ASSET_FILE]
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { hash64, decodeAsset } from '../../web/asset.js';

const [spec, file] = process.argv.slice(2);
if (!spec || spec === '--help') {
    console.log('usage: node test_asset_js.mjs PATH/TO/ASSET.md [FILE.gasset]');
    process.exit(spec ? 0 : 2);
}
const rows = [...readFileSync(spec, 'utf8').matchAll(/^\| (empty|`[^`]*`) \| `([0-9a-f]{16})` \| `([0-9a-f]{16})` \|$/gm)];
assert.ok(rows.length >= 4, `expected the hash table's rows in ${spec}, got ${rows.length}`);
for (const [, input, , hash] of rows) {
    const text = input === 'empty' ? '' : input.slice(1, -1);
    assert.equal(hash64(new TextEncoder().encode(text)), hash, `hash64(${input})`);
}
let decoded = null;
if (file) {
    const bytes = new Uint8Array(readFileSync(file));
    const a = decodeAsset(bytes, file);
    assert.ok(a.n_nodes > 1 && a.n_modes > 0 && a.n_indices > 0, 'a tree with modes and a mesh');
    bytes[bytes.length - 1] ^= 1;
    assert.throws(() => decodeAsset(bytes, file), /payload_crc32/);
    decoded = { species: a.species, n_nodes: a.n_nodes, n_modes: a.n_modes };
}
console.log(JSON.stringify({ hash_rows: rows.length, decoded, ok: true }));
