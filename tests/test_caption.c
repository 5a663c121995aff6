/* Captions (client/kiosk/caption.c): the caption of a wind follows its class (hurricane
 * categories) or Beaufort force in every language; the categories quote the NHC's
 * sentence on trees, the forces the NWS land table; and none speaks of what the scene
 * cannot show (its houses stand through any storm, it has no power poles or wires). */
#include <stdio.h>
#include <string.h>

#include "caption.h"
#include "check.h"
#include "lang.h"
#include "wind_scale.h"

static void test_classes(void)
{
    CHECK_STR_HAS(caption_for(LANG_EN, WIND_SCALE_CAT4, 12), "Most trees will be snapped or uprooted");
    CHECK_STR_HAS(caption_for(LANG_EN, WIND_SCALE_CAT1, 12), "Large branches of trees will snap");
    CHECK_STR_HAS(caption_for(LANG_EN, WIND_SCALE_TS, 9), "Strong gale");
    CHECK_STR_HAS(caption_for(LANG_EN, WIND_SCALE_TD, 3), "Gentle breeze");
    CHECK_STR_HAS(caption_for(LANG_EN, WIND_SCALE_TD, 99), "Hurricane force");
    CHECK_STR_HAS(caption_for(LANG_EN, WIND_SCALE_TD, -4), "Calm");
    CHECK_STR_HAS(caption_for(LANG_ES, WIND_SCALE_CAT3, 12), "Categoría 3");
    CHECK_STR_HAS(caption_for(LANG_HT, WIND_SCALE_CAT5, 12), "Kategori 5");
    CHECK_STR_HAS(caption_for(LANG_ES, WIND_SCALE_TD, 10), "arrancados de raíz");
}

/* every category's caption in every language names the NHC; every text differs by
 * language, so a language cannot silently fall back to English */
static void test_sources_and_languages(void)
{
    for (int c = WIND_SCALE_CAT1; c <= WIND_SCALE_CAT5; c++) {
        for (int l = 0; l < LANG_COUNT; l++) {
            CHECK_STR_HAS(caption_for(l, c, 12), "NHC");
        }
        CHECK(strcmp(caption_for(LANG_EN, c, 12), caption_for(LANG_ES, c, 12)) != 0);
        CHECK(strcmp(caption_for(LANG_EN, c, 12), caption_for(LANG_HT, c, 12)) != 0);
    }
    for (int b = 0; b <= 12; b++) {
        CHECK(strcmp(caption_for(LANG_EN, WIND_SCALE_TD, b), caption_for(LANG_ES, WIND_SCALE_TD, b)) != 0);
        CHECK(strcmp(caption_for(LANG_EN, WIND_SCALE_TD, b), caption_for(LANG_HT, WIND_SCALE_TD, b)) != 0);
    }
}

/* what the scene contradicts: its houses are never damaged, it has no poles or wires */
static void test_nothing_the_scene_contradicts(void)
{
    static const char *const never[] = { "roof", "home", "house", "building", "wall", "pole",
                                         "wire", "techo", "casa", "edific", "poste", "kay ",
                                         "twati", "poto", "structural" };
    int checked = 0;
    for (int l = 0; l < LANG_COUNT; l++) {
        for (int c = WIND_SCALE_TD; c < WIND_SCALE_SS_COUNT; c++) {
            for (int b = 0; b <= 12; b++) {
                const char *cap = caption_for(l, c, b);
                for (size_t i = 0; i < sizeof never / sizeof never[0]; i++) {
                    if (strstr(cap, never[i])) {
                        fprintf(stderr, "caption %s class %d force %d says \"%s\": %s\n",
                                lang_code(l), c, b, never[i], cap);
                        CHECK(0);
                    }
                }
                checked++;
            }
        }
    }
    CHECK(checked == LANG_COUNT * WIND_SCALE_SS_COUNT * 13);
}

int main(void)
{
    test_classes();
    test_sources_and_languages();
    test_nothing_the_scene_contradicts();
    return check_report();
}
