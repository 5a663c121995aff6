// The browser client's module graph: every static import of a web/*.js module
// (import ... from './x.js', export ... from './x.js') names a file of web/, no module
// reaches itself through its imports (a cycle makes one module's top level run before
// the other's exports exist), and no source of web/ is over 900 lines.
// node test_web_imports.mjs WEB_DIR
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';

const MAX_LINES = 900;
// modules gale-server serves beside web/'s that the build writes: the visitor's texts
// (client/lang's gale-lang-gen, from configs/lang/*.po)
const GENERATED = new Set(['lang_texts.js']);
const dir = process.argv[2];
assert.ok(dir, 'usage: node test_web_imports.mjs WEB_DIR');

const sources = fs.readdirSync(dir).filter((f) => /\.(js|html|css)$/.test(f)).sort();
const modules = sources.filter((f) => f.endsWith('.js'));
assert.ok(modules.length > 0, `${dir}: no .js files`);
const failures = [];

for (const f of sources) {
    const text = fs.readFileSync(path.join(dir, f), 'utf8');
    const lines = text.split('\n').length - (text.endsWith('\n') ? 1 : 0);
    if (lines > MAX_LINES) failures.push(`${f}: ${lines} lines (at most ${MAX_LINES})`);
}

// static imports and re-exports, one statement possibly over several lines; comments
// are taken out first so that a module named in one is not an edge
const edges = new Map();
for (const f of modules) {
    const text = fs.readFileSync(path.join(dir, f), 'utf8')
        .replace(/\/\*[\s\S]*?\*\//g, '').replace(/^\s*\/\/.*$/gm, '');
    const to = new Set();
    const statements = [...text.matchAll(/^\s*import\s*(?:[\w$*{}\s,]+?\s*from\s*)?['"]([^'"]+)['"]/gm),
        ...text.matchAll(/^\s*export\s*(?:\*(?:\s*as\s+[\w$]+)?|\{[^}]*\})\s*from\s*['"]([^'"]+)['"]/gm)];
    for (const m of statements) {
        const spec = m[1];
        if (!spec.startsWith('./')) {
            failures.push(`${f}: imports '${spec}', not a module beside it ('./NAME.js')`);
            continue;
        }
        const target = spec.slice(2);
        if (GENERATED.has(target)) continue; // built, then served beside the others
        if (!modules.includes(target)) failures.push(`${f}: imports '${spec}', which web/ does not hold`);
        else to.add(target);
    }
    edges.set(f, [...to].sort());
}

// depth-first search; a module met again while still on the path closes a cycle
const state = new Map(); // undefined: not seen, 1: on the path, 2: done
const cycles = [];
function visit(f, trail) {
    state.set(f, 1);
    trail.push(f);
    for (const g of edges.get(f)) {
        if (state.get(g) === 1) cycles.push([...trail.slice(trail.indexOf(g)), g].join(' -> '));
        else if (!state.get(g)) visit(g, trail);
    }
    trail.pop();
    state.set(f, 2);
}
for (const f of modules) if (!state.get(f)) visit(f, []);
for (const c of cycles) failures.push(`import cycle: ${c}`);

const n_edges = [...edges.values()].reduce((s, e) => s + e.length, 0);
if (failures.length) {
    for (const line of failures) console.error(line);
    process.exit(1);
}
console.log(`${modules.length} modules, ${n_edges} imports, no cycle, none over ${MAX_LINES} lines`);
