// The hex test vectors of protocol/PROTOCOL.md, read from that file (the one copy): every
// fenced block whose lines are all `OFFSET: HEX HEX ...` dump lines is one frame, whatever
// label or info string the block carries. Frames are told apart by their header's type
// byte, not by where they stand, so a relabelled or reordered section still reads.
import { readFileSync } from 'node:fs';

const DUMP = /^\s*([0-9a-fA-F]+)\s*:\s*((?:[0-9a-fA-F]{2}\s*)+)$/;

export function parseVectors(text) {
    const frames = [];
    const lines = text.split('\n');
    for (let i = 0; i < lines.length; i++) {
        if (!/^\s*```/.test(lines[i])) continue;
        let j = i + 1;
        const body = [];
        while (j < lines.length && !/^\s*```/.test(lines[j])) body.push(lines[j++]);
        const dump = body.filter((l) => l.trim() !== '');
        if (dump.length && dump.every((l) => DUMP.test(l))) {
            const bytes = [];
            for (const l of dump) {
                const [, off, hex] = l.match(DUMP);
                if (parseInt(off, 16) !== bytes.length) {
                    throw new Error(`PROTOCOL.md line ${i + 1}: offset ${off} after ${bytes.length} bytes`);
                }
                for (const h of hex.trim().split(/\s+/)) bytes.push(parseInt(h, 16));
            }
            frames.push({ line: i + 1, bytes: Uint8Array.from(bytes) });
        }
        i = j;
    }
    return frames;
}

export function readVectors(path) {
    return parseVectors(readFileSync(path, 'utf8'));
}
