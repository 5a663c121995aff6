/* The visitor's texts (client/lang): the table gale-lang-gen built holds English, Spanish
 * and Haitian Creole in that order, every key translated; texts format with the English's
 * arguments in every language; a shipped scenario's title is translated and a storm's name
 * is not; and gale-lang-gen refuses a translation file that lacks a key, has one twice,
 * leaves one empty or changes a text's printf conversions, naming file and line. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "lang.h"

static void test_table(void)
{
    CHECK(lang_find("en") == LANG_EN && lang_find("es") == LANG_ES && lang_find("ht") == LANG_HT);
    CHECK(lang_find("fr") == -1 && lang_find(NULL) == -1 && lang_find("") == -1);
    CHECK(strcmp(lang_code(LANG_HT), "ht") == 0 && strcmp(lang_code(99), "en") == 0);
    CHECK(strcmp(lang_text(LANG_EN, L_LANG_NAME), "English") == 0);
    CHECK(strcmp(lang_text(LANG_ES, L_LANG_NAME), "Espa\xC3\xB1ol") == 0);
    CHECK(strcmp(lang_text(LANG_HT, L_LANG_NAME), "Krey\xC3\xB2l") == 0);
    CHECK(strcmp(lang_text(LANG_EN, -1), "?") == 0);
    CHECK(lang_key_find("hud.wind") == L_HUD_WIND && lang_key_find("no.such") == -1);
    CHECK(!lang_kmh_first(LANG_EN) && lang_kmh_first(LANG_ES) && lang_kmh_first(LANG_HT));
    int same = 0;
    for (int k = 0; k < L_KEY_COUNT; k++) {
        CHECK(lang_text(LANG_ES, k)[0] && lang_text(LANG_HT, k)[0]);
        same += strcmp(lang_text(LANG_EN, k), lang_text(LANG_ES, k)) == 0;
    }
    /* units, compass letters and "Beaufort %d" read the same; most texts do not */
    CHECK(same < L_KEY_COUNT / 4);
}

static void test_format_and_titles(void)
{
    char buf[256];
    lang_format(buf, sizeof buf, LANG_ES, L_HUD_REPLAY, 2, 5, 6, 40, 50);
    CHECK(strcmp(buf, "Repetici\xC3\xB3n 2:05 / 6:40 \xC2\xB7 \xC3\x97" "50") == 0);
    lang_format(buf, sizeof buf, LANG_HT, L_HUD_LOST, 3u, 1.5);
    CHECK_STR_HAS(buf, "3 ankò nan 1.5 s");
    CHECK(strcmp(lang_scenario_title(LANG_ES, "Gusty afternoon"), "Tarde con rachas") == 0);
    CHECK(strcmp(lang_scenario_title(LANG_HT, "Andrew 1992"), "Andrew 1992") == 0);
    CHECK(strcmp(lang_scenario_title(LANG_EN, "Gusty afternoon"), "Gusty afternoon") == 0);
    CHECK(strcmp(lang_scenario_title(LANG_ES, NULL), "") == 0);
}

static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    CHECK(f != NULL);
    if (f) {
        fputs(text, f);
        fclose(f);
    }
}

/* gale-lang-gen on en.po and a broken es.po: its exit status and first error line */
static int run_gen(const char *es_text, char *msg, size_t cap)
{
    write_file("lang_test/en.po", "msgid \"a.b\"\nmsgstr \"Wind %d mph\"\n\n"
                                  "msgid \"c.d\"\nmsgstr \"Hello \"\n\"there\"\n");
    write_file("lang_test/es.po", es_text);
    int rc = system(GALE_LANG_GEN " --out-c lang_test/t.c --out-h lang_test/t.h --out-js "
                                  "lang_test/t.js lang_test/en.po lang_test/es.po "
                                  "2> lang_test/err.txt");
    msg[0] = '\0';
    FILE *f = fopen("lang_test/err.txt", "r");
    if (f) {
        if (!fgets(msg, (int)cap, f)) {
            msg[0] = '\0';
        }
        fclose(f);
    }
    return rc;
}

static void test_generator_refuses(void)
{
    CHECK(system("mkdir -p lang_test") == 0);
    char msg[512];
    CHECK(run_gen("msgid \"a.b\"\nmsgstr \"Viento %d mph\"\nmsgid \"c.d\"\nmsgstr \"Hola\"\n",
                  msg, sizeof msg) == 0);
    CHECK(msg[0] == '\0');
    /* the generated module holds both languages, the continued line joined */
    FILE *f = fopen("lang_test/t.js", "r");
    char js[2048] = "";
    if (f) {
        size_t n = fread(js, 1, sizeof js - 1, f);
        js[n] = '\0';
        fclose(f);
    }
    CHECK_STR_HAS(js, "'c.d': 'Hello there'");
    CHECK_STR_HAS(js, "'a.b': 'Viento %d mph'");
    CHECK(run_gen("msgid \"a.b\"\nmsgstr \"Viento %s mph\"\nmsgid \"c.d\"\nmsgstr \"Hola\"\n",
                  msg, sizeof msg) != 0);
    CHECK_STR_HAS(msg, "lang_test/es.po:1: a.b: expected the conversions \"d \"");
    CHECK(run_gen("msgid \"a.b\"\nmsgstr \"Viento %d mph\"\n", msg, sizeof msg) != 0);
    CHECK_STR_HAS(msg, "lang_test/es.po: c.d: missing");
    CHECK(run_gen("msgid \"a.b\"\nmsgstr \"x %d\"\nmsgid \"c.d\"\nmsgstr \"y\"\n"
                  "msgid \"a.b\"\nmsgstr \"z %d\"\n",
                  msg, sizeof msg) != 0);
    CHECK_STR_HAS(msg, "lang_test/es.po:5: a.b: given twice (first at line 1)");
    CHECK(run_gen("msgid \"a.b\"\nmsgstr \"\"\nmsgid \"c.d\"\nmsgstr \"y\"\n", msg,
                  sizeof msg) != 0);
    CHECK_STR_HAS(msg, "lang_test/es.po:1: a.b: empty msgstr");
    CHECK(run_gen("msgid \"a.b\"\nmsgstr \"x %d\"\nmsgid \"c.d\"\nmsgstr \"y\"\n"
                  "msgid \"e.f\"\nmsgstr \"z\"\n",
                  msg, sizeof msg) != 0);
    CHECK_STR_HAS(msg, "lang_test/es.po:5: e.f: not a key of lang_test/en.po");
    CHECK(run_gen("msgid \"a.b\"\nmsgstr \"x %d\nmsgid \"c.d\"\nmsgstr \"y\"\n", msg,
                  sizeof msg) != 0);
    CHECK_STR_HAS(msg, "lang_test/es.po:2: unterminated string");
}

int main(void)
{
    test_table();
    test_format_and_titles();
    test_generator_refuses();
    return check_report();
}
