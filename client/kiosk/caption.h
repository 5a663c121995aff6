/* Plain-language captions per wind class for the kiosk: what that wind does to
 * trees and houses, from the public Beaufort land descriptions and the NHC's Saffir-Simpson
 * descriptions (sources in configs/captions/en.txt). A language is a table file of
 * KEY = TEXT lines (bft0..bft12, cat1..cat5); English is built in. */
#ifndef GALE_CAPTION_H
#define GALE_CAPTION_H

#include "err.h"

#define CAPTION_BFT 13 /* Beaufort forces 0..12 */
#define CAPTION_CAT 5  /* hurricane categories 1..5 */
#define CAPTION_CHARS 200

typedef struct caption_table {
    char bft[CAPTION_BFT][CAPTION_CHARS];
    char cat[CAPTION_CAT][CAPTION_CHARS];
} caption_table;

/* The built-in English table (the texts of configs/captions/en.txt). */
void caption_table_english(caption_table *t);
/* Reads a table file; every key once, no other key. Errors name file:line and the key
 * (GALE_E_IO, GALE_E_PARSE). *t is unchanged on failure. */
int caption_table_load(const char *path, caption_table *t, gale_err *err);
/* The caption of a wind: its hurricane category's when ss_class (wind_scale.h numbering)
 * is a hurricane, else its Beaufort force's (a tropical storm is Beaufort 8-11). */
const char *caption_for(const caption_table *t, int ss_class, int beaufort);

#endif
