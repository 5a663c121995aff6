// What a visitor reads, in English, Spanish and Haitian Creole: the texts of configs/lang/
// (.po files) as gale-lang-gen writes them into /web/lang_texts.js at build time, the same
// table gale-client is built with (client/lang/lang.h), and the printf the C side formats
// them with. A page's entry module hands the table over once (setTexts); everything else
// asks t(lang, key, ...args). The language codes are 'en', 'es', 'ht'.

let texts = null;
let codes = ['en'];

export function setTexts(langCodes, table) {
    codes = langCodes.slice();
    texts = table;
}

export function langCodes() {
    return codes.slice();
}

// a code of the table, or null: what ?lang= and the language buttons accept
export function langFind(code) {
    return codes.includes(code) ? code : null;
}

// printf's "%.Nf": the exact binary value rounded half to even, where toFixed rounds a
// tie up (2.5 is "2" in C, "3" by toFixed)
export function fixed(x, digits) {
    const m = 10 ** digits, y = x * m;
    if (Number.isFinite(y) && Math.abs(y - Math.trunc(y)) === 0.5 && y / m === x) {
        const f = Math.floor(y);
        return ((f % 2 === 0 ? f : f + 1) / m).toFixed(digits);
    }
    return x.toFixed(digits);
}

// The printf conversions the texts use (gale-lang-gen checks each language has the
// English's): %s, %d, %u, %llu, %02d, %.1f, %%.
export function format(fmt, args) {
    let i = 0;
    return fmt.replace(/%(0?)(\d*)(?:\.(\d+))?(?:ll|l)?([sdufx%])/g, (m, zero, width, prec, conv) => {
        if (conv === '%') return '%';
        const a = args[i++];
        let s;
        if (conv === 's') s = String(a);
        else if (conv === 'f') s = fixed(Number(a), prec === undefined ? 6 : Number(prec));
        else s = String(Math.trunc(Number(a)));
        const w = Number(width || 0);
        if (s.length < w) {
            s = zero && conv !== 's' ? (s.startsWith('-') ? '-' + s.slice(1).padStart(w - 1, '0') : s.padStart(w, '0'))
                : s.padStart(w, ' ');
        }
        return s;
    });
}

// The text of key in lang (English for an unknown language), formatted with args.
export function t(lang, key, ...args) {
    if (!texts) throw new Error('lang.js: setTexts was not called (the page imports /web/lang_texts.js)');
    const table = texts[lang] || texts.en;
    const text = table[key];
    if (text === undefined) return '?';
    return args.length ? format(text, args) : text;
}

// A scenario's title in lang: the "scenario.*" text whose English is the title (the shipped
// scenarios), else the title itself (a museum's own, a storm's proper name); lang.c
// lang_scenario_title.
export function scenarioTitle(lang, title) {
    if (!texts || !title) return title || '';
    for (const [key, en] of Object.entries(texts.en)) {
        if (key.startsWith('scenario.') && en === title) return t(lang, key);
    }
    return title;
}

// km/h first (Spanish, Creole) or mph first (English): units.order
export function kmhFirst(lang) {
    return t(lang, 'units.order').startsWith('kmh');
}
