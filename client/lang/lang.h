/* What a visitor reads, in English, Spanish and Haitian Creole: one table of texts built
 * from the .po files of configs/lang by gale-lang-gen (lang_gen.c) at build time, the same table the
 * page imports (web/lang.js), so gale-client and the page say the same words. A text is
 * looked up by its key (lang_keys.h, generated: L_HUD_WIND is "hud.wind"); texts with
 * printf conversions are formats whose conversions the generator checked against the
 * English, so any language's text takes the same arguments. */
#ifndef GALE_LANG_H
#define GALE_LANG_H

#include <stdbool.h>
#include <stddef.h>

#include "lang_keys.h"

enum lang_id { LANG_EN = 0, LANG_ES, LANG_HT, LANG_COUNT };

/* The language of a code ("en", "es", "ht"); -1 for any other. */
int lang_find(const char *code);
/* The code of a language; "en" outside [0, LANG_COUNT). */
const char *lang_code(int lang);
/* The text of key in lang (English outside [0, LANG_COUNT), "?" for a key out of range). */
const char *lang_text(int lang, int key);
/* snprintf of key's text in lang with the arguments that follow: its conversions are the
 * English text's (gale-lang-gen checked them), whichever language. Returns snprintf's. */
int lang_format(char *out, size_t cap, int lang, int key, ...);
/* The key named name ("hud.wind"); -1 when there is none. */
int lang_key_find(const char *name);
/* A scenario's title in lang: the text of the "scenario.*" key whose English text is the
 * title (the shipped scenarios' titles), else the title itself (a museum's own scenario,
 * a storm's proper name). */
const char *lang_scenario_title(int lang, const char *english_title);
/* True when lang reads km/h first (units.order "kmh,mph"), false for mph first. */
bool lang_kmh_first(int lang);

#endif
