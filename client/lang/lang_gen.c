/* gale-lang-gen: turns the translation files (the configs/lang .po files, one per language, the
 * first the reference) into the one table both clients read: a C table and header for
 * gale-client (client/lang/lang.h) and a JavaScript module the page imports
 * (web/lang.js). Runs at build time, so the two clients cannot drift apart.
 *
 * The .po files are gettext's format with the message id as a stable key
 * ("hud.wind"), msgstr its text. Checked, each an error naming file:line: every key of
 * the reference in every language and no other, no key twice, no empty text, and every
 * text's printf conversions (%s %d %u %.1f %02d ...) the same, in the same order, as
 * the reference's: a translation cannot make a printf read the wrong argument. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_LANGS 8
#define MAX_KEYS  512
#define MAX_TEXT  1024

typedef struct po_entry {
    char key[96];
    char text[MAX_TEXT];
    int line;
} po_entry;

typedef struct po_file {
    char path[512];
    char code[16]; /* the file's stem: "en", "es", "ht" */
    po_entry *e;
    int n;
} po_file;

static int fail(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "gale-lang-gen: ");
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    return -1;
}

/* Appends the C string literal at s ("...", escapes \" \\ \n \t) to out. */
static int append_quoted(const char *path, int ln, const char *s, char *out, size_t cap)
{
    while (*s == ' ' || *s == '\t') {
        s++;
    }
    if (*s != '"') {
        return fail("%s:%d: expected a quoted string, got '%s'", path, ln, s);
    }
    size_t n = strlen(out);
    for (s++; *s && *s != '"'; s++) {
        char c = *s;
        if (c == '\\') {
            s++;
            c = *s == 'n' ? '\n' : *s == 't' ? '\t' : *s;
            if (!c) {
                break;
            }
        }
        if (n + 1 >= cap) {
            return fail("%s:%d: text longer than %d bytes", path, ln, MAX_TEXT - 1);
        }
        out[n++] = c;
    }
    out[n] = '\0';
    if (*s != '"') {
        return fail("%s:%d: unterminated string", path, ln);
    }
    for (s++; *s == ' ' || *s == '\t' || *s == '\r' || *s == '\n'; s++) {
    }
    if (*s) {
        return fail("%s:%d: unexpected '%s' after the string", path, ln, s);
    }
    return 0;
}

static int po_load(const char *path, po_file *po)
{
    FILE *f = fopen(path, "r");
    if (!f) {
        return fail("%s: cannot open", path);
    }
    snprintf(po->path, sizeof po->path, "%s", path);
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    size_t stem = strcspn(base, ".");
    if (stem == 0 || stem >= sizeof po->code) {
        fclose(f);
        return fail("%s: the file name must be the language code, e.g. es.po", path);
    }
    memcpy(po->code, base, stem);
    po->code[stem] = '\0';
    po->e = calloc(MAX_KEYS, sizeof *po->e);
    char line[4096];
    int ln = 0, rc = 0;
    char *into = NULL; /* the field continuation lines append to */
    size_t into_cap = 0;
    po_entry *cur = NULL;
    while (!rc && fgets(line, sizeof line, f)) {
        ln++;
        char *s = line;
        while (*s == ' ' || *s == '\t') {
            s++;
        }
        if (*s == '#' || *s == '\n' || *s == '\r' || !*s) {
            into = NULL;
            continue;
        }
        if (!strncmp(s, "msgid ", 6)) {
            if (po->n == MAX_KEYS) {
                rc = fail("%s:%d: more than %d messages", path, ln, MAX_KEYS);
                break;
            }
            cur = &po->e[po->n++];
            cur->line = ln;
            into = cur->key;
            into_cap = sizeof cur->key;
            rc = append_quoted(path, ln, s + 6, into, into_cap);
        } else if (!strncmp(s, "msgstr ", 7)) {
            if (!cur || into != cur->key) {
                rc = fail("%s:%d: msgstr without its msgid", path, ln);
                break;
            }
            into = cur->text;
            into_cap = sizeof cur->text;
            rc = append_quoted(path, ln, s + 7, into, into_cap);
        } else if (*s == '"' && into) {
            rc = append_quoted(path, ln, s, into, into_cap);
        } else {
            rc = fail("%s:%d: expected msgid, msgstr, a string or a comment, got '%.40s'", path,
                      ln, s);
        }
    }
    fclose(f);
    if (rc) {
        return rc;
    }
    /* gettext's header entry (empty msgid) carries metadata, not a message */
    if (po->n && !po->e[0].key[0]) {
        memmove(po->e, po->e + 1, (size_t)(po->n - 1) * sizeof *po->e);
        po->n--;
    }
    for (int i = 0; i < po->n; i++) {
        if (!po->e[i].key[0]) {
            return fail("%s:%d: empty msgid", path, po->e[i].line);
        }
        if (!po->e[i].text[0]) {
            return fail("%s:%d: %s: empty msgstr (untranslated)", path, po->e[i].line,
                        po->e[i].key);
        }
        for (int j = 0; j < i; j++) {
            if (!strcmp(po->e[i].key, po->e[j].key)) {
                return fail("%s:%d: %s: given twice (first at line %d)", path, po->e[i].line,
                            po->e[i].key, po->e[j].line);
            }
        }
    }
    return 0;
}

/* The printf conversions of s as one string, e.g. "%s %02d %.0f" -> "s d f". */
static void conversions(const char *s, char *out, size_t cap)
{
    size_t n = 0;
    out[0] = '\0';
    for (; *s; s++) {
        if (*s != '%') {
            continue;
        }
        s++;
        if (*s == '%') {
            continue;
        }
        while (*s && strchr("0123456789.-+ #l", *s)) {
            s++;
        }
        if (!*s) {
            break;
        }
        if (n + 2 < cap) {
            out[n++] = *s;
            out[n++] = ' ';
            out[n] = '\0';
        }
    }
}

static const po_entry *po_find(const po_file *po, const char *key)
{
    for (int i = 0; i < po->n; i++) {
        if (!strcmp(po->e[i].key, key)) {
            return &po->e[i];
        }
    }
    return NULL;
}

static void c_string(FILE *o, const char *s)
{
    fputc('"', o);
    for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
        if (*p == '"' || *p == '\\') {
            fprintf(o, "\\%c", *p);
        } else if (*p == '\n') {
            fputs("\\n", o);
        } else if (*p < 0x20 || *p >= 0x7f) {
            /* octal, so the next character cannot extend the escape */
            fprintf(o, "\\%03o", *p);
        } else {
            fputc(*p, o);
        }
    }
    fputc('"', o);
}

static void js_string(FILE *o, const char *s)
{
    fputc('\'', o);
    for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
        if (*p == '\'' || *p == '\\') {
            fprintf(o, "\\%c", *p);
        } else if (*p == '\n') {
            fputs("\\n", o);
        } else {
            fputc(*p, o); /* UTF-8 passes through: the module is served as utf-8 */
        }
    }
    fputc('\'', o);
}

/* "hud.wind_line" -> "L_HUD_WIND_LINE" */
static void c_name(FILE *o, const char *key)
{
    fputs("L_", o);
    for (const char *p = key; *p; p++) {
        char c = *p;
        fputc(c >= 'a' && c <= 'z' ? c - 'a' + 'A' : (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ? c : '_', o);
    }
}

static void usage(FILE *o)
{
    fprintf(o, "usage: gale-lang-gen --out-c FILE.c --out-h FILE.h --out-js FILE.js REF.po [LANG.po ...]\n"
               "Checks the translation files against the first (the reference: every key, no\n"
               "other, the same printf conversions) and writes the C table, its header and the\n"
               "page's module. Exit 0 when written, 1 on any error (named file:line).\n");
}

int main(int argc, char **argv)
{
    const char *out_c = NULL, *out_h = NULL, *out_js = NULL;
    const char *in[MAX_LANGS];
    int n_in = 0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(argv[i], "--out-c") && i + 1 < argc) {
            out_c = argv[++i];
        } else if (!strcmp(argv[i], "--out-h") && i + 1 < argc) {
            out_h = argv[++i];
        } else if (!strcmp(argv[i], "--out-js") && i + 1 < argc) {
            out_js = argv[++i];
        } else if (argv[i][0] == '-') {
            usage(stderr);
            return 1;
        } else if (n_in < MAX_LANGS) {
            in[n_in++] = argv[i];
        } else {
            fail("more than %d languages", MAX_LANGS);
            return 1;
        }
    }
    if (!out_c || !out_h || !out_js || n_in == 0) {
        usage(stderr);
        return 1;
    }
    static po_file po[MAX_LANGS];
    for (int l = 0; l < n_in; l++) {
        if (po_load(in[l], &po[l]) != 0) {
            return 1;
        }
    }
    const po_file *ref = &po[0];
    for (int l = 1; l < n_in; l++) {
        for (int i = 0; i < po[l].n; i++) {
            if (!po_find(ref, po[l].e[i].key)) {
                fail("%s:%d: %s: not a key of %s", po[l].path, po[l].e[i].line, po[l].e[i].key,
                     ref->path);
                return 1;
            }
        }
        for (int i = 0; i < ref->n; i++) {
            const po_entry *t = po_find(&po[l], ref->e[i].key);
            if (!t) {
                fail("%s: %s: missing (%s:%d has it)", po[l].path, ref->e[i].key, ref->path,
                     ref->e[i].line);
                return 1;
            }
            char a[128], b[128];
            conversions(ref->e[i].text, a, sizeof a);
            conversions(t->text, b, sizeof b);
            if (strcmp(a, b)) {
                fail("%s:%d: %s: expected the conversions \"%s\" of %s:%d, got \"%s\"",
                     po[l].path, t->line, t->key, a, ref->path, ref->e[i].line, b);
                return 1;
            }
        }
    }

    FILE *h = fopen(out_h, "w");
    FILE *c = fopen(out_c, "w");
    FILE *js = fopen(out_js, "w");
    if (!h || !c || !js) {
        fail("cannot write the outputs");
        return 1;
    }
    fprintf(h, "/* The translation keys of configs/lang/%s.po, written by gale-lang-gen. */\n"
               "#ifndef GALE_LANG_KEYS_H\n#define GALE_LANG_KEYS_H\n\n"
               "#define LANG_GEN_COUNT %d\n\nenum lang_key {\n",
            ref->code, n_in);
    for (int i = 0; i < ref->n; i++) {
        fputs("    ", h);
        c_name(h, ref->e[i].key);
        fprintf(h, ",\n");
    }
    fprintf(h, "    L_KEY_COUNT\n};\n\n#endif\n");

    fprintf(c, "/* The texts of the configs/lang files, written by gale-lang-gen. */\n"
               "#include \"lang_keys.h\"\n\n"
               "const char *const lang_gen_codes[LANG_GEN_COUNT] = {");
    for (int l = 0; l < n_in; l++) {
        fprintf(c, "%s\"%s\"", l ? ", " : " ", po[l].code);
    }
    fprintf(c, " };\n\nconst char *const lang_gen_keys[L_KEY_COUNT] = {\n");
    for (int i = 0; i < ref->n; i++) {
        fputs("    ", c);
        c_string(c, ref->e[i].key);
        fputs(",\n", c);
    }
    fprintf(c, "};\n\nconst char *const lang_gen_texts[LANG_GEN_COUNT][L_KEY_COUNT] = {\n");
    for (int l = 0; l < n_in; l++) {
        fprintf(c, "    { /* %s */\n", po[l].code);
        for (int i = 0; i < ref->n; i++) {
            fputs("        ", c);
            c_string(c, po_find(&po[l], ref->e[i].key)->text);
            fputs(",\n", c);
        }
        fprintf(c, "    },\n");
    }
    fprintf(c, "};\n");

    fprintf(js, "// The texts of configs/lang/*.po, written by gale-lang-gen (client/lang/lang_gen.c)\n"
                "// for web/lang.js: the same table gale-client is built with.\n"
                "export const LANG_CODES = [");
    for (int l = 0; l < n_in; l++) {
        fprintf(js, "%s'%s'", l ? ", " : "", po[l].code);
    }
    fprintf(js, "];\nexport const TEXTS = {\n");
    for (int l = 0; l < n_in; l++) {
        fprintf(js, "    %s: {\n", po[l].code);
        for (int i = 0; i < ref->n; i++) {
            fputs("        ", js);
            js_string(js, ref->e[i].key);
            fputs(": ", js);
            js_string(js, po_find(&po[l], ref->e[i].key)->text);
            fputs(",\n", js);
        }
        fprintf(js, "    },\n");
    }
    fprintf(js, "};\n");
    int bad = ferror(h) | ferror(c) | ferror(js);
    bad |= fclose(h) | fclose(c) | fclose(js);
    for (int l = 0; l < n_in; l++) {
        free(po[l].e);
    }
    if (bad) {
        fail("write error");
        return 1;
    }
    return 0;
}
