/* The table of texts (lang.h) over gale-lang-gen's arrays. */
#include "lang.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

extern const char *const lang_gen_codes[LANG_GEN_COUNT];
extern const char *const lang_gen_keys[L_KEY_COUNT];
extern const char *const lang_gen_texts[LANG_GEN_COUNT][L_KEY_COUNT];

/* client/lang/CMakeLists.txt lists en, es, ht in this order (lang_find checks the codes at run time);
 * numbered families are read as the first key plus an index, so they must stay
 * contiguous and complete in en.po */
_Static_assert(LANG_COUNT == LANG_GEN_COUNT, "one .po file per language of enum lang_id");
_Static_assert(L_SS_6 - L_SS_0 == 6, "ss.0..ss.6 contiguous");
_Static_assert(L_SS_ABBREV_6 - L_SS_ABBREV_0 == 6, "ss_abbrev.0..6 contiguous");
_Static_assert(L_BFT_12 - L_BFT_0 == 12, "bft.0..bft.12 contiguous");
_Static_assert(L_COMPASS_15 - L_COMPASS_0 == 15, "compass.0..15 contiguous");
_Static_assert(L_CAPTION_BFT_12 - L_CAPTION_BFT_0 == 12, "caption.bft.0..12 contiguous");
_Static_assert(L_CAPTION_CAT_5 - L_CAPTION_CAT_1 == 4, "caption.cat.1..5 contiguous");

static const char *const lang_codes[LANG_COUNT] = { "en", "es", "ht" };

int lang_find(const char *code)
{
    for (int l = 0; code && l < LANG_COUNT; l++) {
        if (!strcmp(code, lang_codes[l]) && !strcmp(code, lang_gen_codes[l])) {
            return l;
        }
    }
    return -1;
}

const char *lang_code(int lang)
{
    return lang >= 0 && lang < LANG_COUNT ? lang_codes[lang] : lang_codes[LANG_EN];
}

const char *lang_text(int lang, int key)
{
    if (key < 0 || key >= L_KEY_COUNT) {
        return "?";
    }
    return lang_gen_texts[lang >= 0 && lang < LANG_COUNT ? lang : LANG_EN][key];
}

int lang_key_find(const char *name)
{
    for (int k = 0; name && k < L_KEY_COUNT; k++) {
        if (!strcmp(name, lang_gen_keys[k])) {
            return k;
        }
    }
    return -1;
}

const char *lang_scenario_title(int lang, const char *english_title)
{
    if (!english_title) {
        return "";
    }
    for (int k = 0; k < L_KEY_COUNT; k++) {
        if (!strncmp(lang_gen_keys[k], "scenario.", 9) &&
            !strcmp(lang_gen_texts[LANG_EN][k], english_title)) {
            return lang_text(lang, k);
        }
    }
    return english_title;
}

bool lang_kmh_first(int lang)
{
    return !strncmp(lang_text(lang, L_UNITS_ORDER), "kmh", 3);
}

/* The one printf of a text that is not a literal: gale-lang-gen refused any translation
 * whose conversions differ from the English text's, and each caller passes the English
 * text's arguments (lang.h names them per key in configs/lang/en.po's comments). */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wformat-nonliteral"
int lang_format(char *out, size_t cap, int lang, int key, ...)
{
    va_list ap;
    va_start(ap, key);
    int n = vsnprintf(out, cap, lang_text(lang, key), ap);
    va_end(ap);
    return n;
}
#pragma GCC diagnostic pop
