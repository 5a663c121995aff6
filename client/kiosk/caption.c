/* Caption tables (caption.h). */
#include "caption.h"

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "wind_scale.h"

/* The English texts, as in configs/captions/en.txt (Met Office Beaufort land
 * descriptions; NHC Saffir-Simpson Hurricane Wind Scale). */
static const char *const en_bft[CAPTION_BFT] = {
    "Calm: smoke rises straight up.",
    "Light air: smoke drifts; leaves are still.",
    "Light breeze: you feel the wind on your face; leaves rustle.",
    "Gentle breeze: leaves and small twigs move all the time; flags fly.",
    "Moderate breeze: dust and paper blow about; small branches move.",
    "Fresh breeze: small trees in leaf begin to sway.",
    "Strong breeze: large branches move; umbrellas are hard to hold.",
    "Near gale: whole trees move; walking into the wind is hard.",
    "Gale: twigs break off trees; walking is difficult.",
    "Strong gale: branches break; slight damage to roofs.",
    "Storm: trees are uprooted; houses are damaged.",
    "Violent storm: widespread damage to trees and buildings.",
    "Hurricane force: devastation.",
};
static const char *const en_cat[CAPTION_CAT] = {
    "Category 1: very dangerous winds; roofs and siding are damaged, large branches snap and "
    "shallow-rooted trees topple.",
    "Category 2: extremely dangerous winds; major roof damage, many trees snapped or uprooted, "
    "roads blocked.",
    "Category 3: devastating damage; roofs torn off well-built homes, many trees snapped or "
    "uprooted.",
    "Category 4: catastrophic damage; most of a roof and some walls lost, most trees snapped or "
    "uprooted.",
    "Category 5: catastrophic damage; many homes destroyed, fallen trees cut off whole "
    "neighbourhoods.",
};

void caption_table_english(caption_table *t)
{
    for (int i = 0; i < CAPTION_BFT; i++) {
        snprintf(t->bft[i], CAPTION_CHARS, "%s", en_bft[i]);
    }
    for (int i = 0; i < CAPTION_CAT; i++) {
        snprintf(t->cat[i], CAPTION_CHARS, "%s", en_cat[i]);
    }
}

static char *trim(char *s)
{
    while (*s == ' ' || *s == '\t') {
        s++;
    }
    size_t n = strlen(s);
    while (n && (s[n - 1] == ' ' || s[n - 1] == '\t' || s[n - 1] == '\n' || s[n - 1] == '\r')) {
        s[--n] = '\0';
    }
    return s;
}

int caption_table_load(const char *path, caption_table *out, gale_err *err)
{
    FILE *f = fopen(path, "r");
    if (!f) {
        return gale_errf(err, GALE_E_IO, "%s: cannot open the caption table", path);
    }
    caption_table *t = calloc(1, sizeof *t);
    bool seen[CAPTION_BFT + CAPTION_CAT] = { false };
    char line[1024];
    int ln = 0, rc = 0;
    while (!rc && t && fgets(line, sizeof line, f)) {
        ln++;
        char *s = trim(line);
        if (!*s || *s == '#') {
            continue;
        }
        char *eq = strchr(s, '=');
        if (!eq) {
            rc = gale_errf(err, GALE_E_PARSE, "%s:%d: expected KEY = TEXT, got \"%.40s\"", path, ln, s);
            break;
        }
        *eq = '\0';
        char *key = trim(s), *text = trim(eq + 1);
        int k = -1, idx;
        char tail;
        if (sscanf(key, "bft%d%c", &idx, &tail) == 1 && idx >= 0 && idx < CAPTION_BFT) {
            k = idx;
        } else if (sscanf(key, "cat%d%c", &idx, &tail) == 1 && idx >= 1 && idx <= CAPTION_CAT) {
            k = CAPTION_BFT + idx - 1;
        }
        if (k < 0) {
            rc = gale_errf(err, GALE_E_PARSE,
                           "%s:%d: key: expected bft0..bft12 or cat1..cat5, got \"%.40s\"", path,
                           ln, key);
        } else if (seen[k]) {
            rc = gale_errf(err, GALE_E_PARSE, "%s:%d: %s: given twice", path, ln, key);
        } else if (!*text || strlen(text) >= CAPTION_CHARS) {
            rc = gale_errf(err, GALE_E_PARSE, "%s:%d: %s: expected 1..%d bytes of text, got %zu",
                           path, ln, key, CAPTION_CHARS - 1, strlen(text));
        } else {
            seen[k] = true;
            snprintf(k < CAPTION_BFT ? t->bft[k] : t->cat[k - CAPTION_BFT], CAPTION_CHARS, "%s",
                     text);
        }
    }
    fclose(f);
    if (!t) {
        return gale_errf(err, GALE_E_NOMEM, "%s: no memory", path);
    }
    for (int k = 0; !rc && k < CAPTION_BFT + CAPTION_CAT; k++) {
        if (!seen[k]) {
            rc = gale_errf(err, GALE_E_PARSE, "%s: %s%d: required key missing", path,
                           k < CAPTION_BFT ? "bft" : "cat",
                           k < CAPTION_BFT ? k : k - CAPTION_BFT + 1);
        }
    }
    if (!rc) {
        *out = *t;
    }
    free(t);
    return rc;
}

const char *caption_for(const caption_table *t, int ss_class, int beaufort)
{
    if (ss_class >= WIND_SCALE_CAT1 && ss_class <= WIND_SCALE_CAT5) {
        return t->cat[ss_class - WIND_SCALE_CAT1];
    }
    return t->bft[beaufort < 0 ? 0 : beaufort > 12 ? 12 : beaufort];
}
