// The test vectors of protocol/PROTOCOL.md, read from that file (the one copy) by the
// marker its "Test vectors" section defines: a fenced block opened by ```gale-hex NAME
// (a binary frame, offset-prefixed hex lines) or ```gale-json NAME (one line of JSON).
import { readFileSync } from 'node:fs';

const BLOCK = /^```gale-(hex|json) ([A-Z][A-Z0-9-]*)\n([\s\S]*?)\n```$/gm;
const DUMP = /^([0-9a-f]{2,}):((?: [0-9a-f]{2}){1,16})$/;

// Returns { hex: { NAME: Uint8Array }, json: { NAME: string } }; throws, naming the
// line, on a malformed dump, a gap in its offsets or a name used twice.
export function parseVectors(text) {
    const out = { hex: {}, json: {} };
    for (const m of text.matchAll(BLOCK)) {
        const [, kind, name, body] = m;
        const line = text.slice(0, m.index).split('\n').length;
        if (out.hex[name] || out.json[name]) throw new Error(`PROTOCOL.md line ${line}: ${name} used twice`);
        if (kind === 'json') {
            if (body.includes('\n')) throw new Error(`PROTOCOL.md line ${line}: ${name}: more than one line`);
            out.json[name] = body;
            continue;
        }
        const bytes = [];
        for (const [k, l] of body.split('\n').entries()) {
            const d = l.match(DUMP);
            if (!d) throw new Error(`PROTOCOL.md line ${line + 1 + k}: ${name}: not a dump line: ${l}`);
            if (parseInt(d[1], 16) !== bytes.length) {
                throw new Error(`PROTOCOL.md line ${line + 1 + k}: ${name}: offset ${d[1]} after ${bytes.length} bytes`);
            }
            for (const h of d[2].trim().split(' ')) bytes.push(parseInt(h, 16));
        }
        out.hex[name] = Uint8Array.from(bytes);
    }
    return out;
}

export function readVectors(path) {
    return parseVectors(readFileSync(path, 'utf8'));
}
