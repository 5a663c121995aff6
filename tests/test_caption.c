/* Caption tables (client/kiosk/caption.c): the shipped English file equals the built-in table;
 * the caption of a wind follows its class (hurricane categories) or Beaufort force; a
 * broken table names file, line and key and leaves the table as it was. */
#include <stdio.h>
#include <string.h>

#include "caption.h"
#include "check.h"
#include "wind_scale.h"

static void test_english_file(void)
{
    caption_table builtin, file;
    caption_table_english(&builtin);
    memset(&file, 0, sizeof file);
    gale_err e = { 0 };
    CHECK(caption_table_load(GALE_SOURCE_DIR "/configs/captions/en.txt", &file, &e) == 0);
    for (int i = 0; i < CAPTION_BFT; i++) {
        CHECK(strcmp(builtin.bft[i], file.bft[i]) == 0);
    }
    for (int i = 0; i < CAPTION_CAT; i++) {
        CHECK(strcmp(builtin.cat[i], file.cat[i]) == 0);
    }
    CHECK_STR_HAS(caption_for(&builtin, WIND_SCALE_CAT4, 12), "Category 4: catastrophic");
    CHECK_STR_HAS(caption_for(&builtin, WIND_SCALE_TS, 9), "Strong gale");
    CHECK_STR_HAS(caption_for(&builtin, WIND_SCALE_TD, 3), "Gentle breeze");
    CHECK_STR_HAS(caption_for(&builtin, WIND_SCALE_TD, 99), "Hurricane force");
}

static void write(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    fputs(text, f);
    fclose(f);
}

static void test_errors(void)
{
    caption_table t;
    memset(&t, 0, sizeof t);
    caption_table_english(&t);
    caption_table before = t;
    gale_err e = { 0 };
    write("captions_bad.txt", "# x\nbft0 = Calma\nbft13 = no\n");
    CHECK(caption_table_load("captions_bad.txt", &t, &e) == GALE_E_PARSE);
    CHECK_STR_HAS(e.msg, "captions_bad.txt:3: key: expected bft0..bft12 or cat1..cat5, got \"bft13\"");
    write("captions_bad.txt", "bft0 = Calma\nbft0 = otra\n");
    CHECK(caption_table_load("captions_bad.txt", &t, &e) == GALE_E_PARSE);
    CHECK_STR_HAS(e.msg, "captions_bad.txt:2: bft0: given twice");
    write("captions_bad.txt", "bft0 = Calma\n");
    CHECK(caption_table_load("captions_bad.txt", &t, &e) == GALE_E_PARSE);
    CHECK_STR_HAS(e.msg, "bft1: required key missing");
    write("captions_bad.txt", "just words\n");
    CHECK(caption_table_load("captions_bad.txt", &t, &e) == GALE_E_PARSE);
    CHECK_STR_HAS(e.msg, "captions_bad.txt:1: expected KEY = TEXT");
    CHECK(caption_table_load("no/such/file.txt", &t, &e) == GALE_E_IO);
    CHECK(memcmp(&t, &before, sizeof t) == 0);
}

int main(void)
{
    RUN(test_english_file);
    RUN(test_errors);
    return check_report();
}
