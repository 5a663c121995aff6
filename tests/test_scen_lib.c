/* The scenario library (server/serve/scen_lib.h): the shipped folder loads, sorted by stem;
 * names match by stem and by title, letters and digits in lower case; the name list cut to
 * a close reason's room; a missing folder is empty; a bad file fails naming it; the
 * playlist resolves, and an unknown entry fails naming it and the valid names. */
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "check.h"
#include "scen_lib.h"

static void test_shipped(void)
{
    scen_lib l;
    gale_err e = { 0 };
    CHECK(scen_lib_load(&l, GALE_SOURCE_DIR "/configs/scenarios", &e) == 0);
    CHECK(l.n == 25); /* 12 steady and replays, 13 of the storm library */
    CHECK(l.n > 0 && !strcmp(l.e[0].name, "andrew1992"));
    int a = scen_lib_find(&l, "andrew1992");
    CHECK(a >= 0 && a == scen_lib_find(&l, "Andrew 1992") && a == scen_lib_find(&l, "ANDREW-1992"));
    int c4 = scen_lib_find(&l, "cat4");
    CHECK(c4 >= 0 && c4 == scen_lib_find(&l, "Category 4 (steady)"));
    CHECK(scen_lib_find(&l, "storm") >= 0 && scen_lib_find(&l, "storm") == scen_lib_find(&l, "Tropical storm"));
    CHECK(scen_lib_find(&l, "andrew") < 0 && scen_lib_find(&l, "") < 0);
    char names[1024], cut[40];
    scen_lib_names(&l, names, sizeof names);
    CHECK(!strcmp(names, "andrew1992, breeze, calm, camille1969, cat1, cat2, cat3, "
                         "cat3-synthetic, cat4, cat5, charley2004, gusty, harvey2017, hugo1989, "
                         "ian2022, ida2021, ike2008, irma2017, katrina2005, laborday1935, "
                         "laura2020, maria2017, michael2018, storm, wilma2005"));
    scen_lib_names_cut(names, cut, sizeof cut);
    CHECK(!strcmp(cut, "andrew1992, breeze, calm, ..."));
    scen_lib_names_cut("a, b", cut, sizeof cut);
    CHECK(!strcmp(cut, "a, b"));
    /* the playlist of the default scene */
    scene sc;
    memset(&sc, 0, sizeof sc);
    snprintf(sc.name, sizeof sc.name, "t");
    sc.n_playlist = 2;
    snprintf(sc.playlist[0], sizeof sc.playlist[0], "gusty");
    snprintf(sc.playlist[1], sizeof sc.playlist[1], "Charley 2004");
    scenario *pl[SCENE_MAX_PLAYLIST];
    int n = 0;
    CHECK(scen_lib_playlist(&l, &sc, pl, &n, &e) == 0 && n == 2);
    CHECK(n == 2 && !strcmp(scenario_name(pl[1]), "Charley 2004"));
    snprintf(sc.playlist[1], sizeof sc.playlist[1], "hugo1990");
    CHECK(scen_lib_playlist(&l, &sc, pl, &n, &e) == GALE_E_RANGE);
    CHECK_STR_HAS(e.msg, "scene t: playlist[1]: \"hugo1990\": expected a scenario of ");
    CHECK_STR_HAS(e.msg, "configs/scenarios: andrew1992, breeze,");
    scen_lib_fini(&l);
    scen_lib_fini(&l); /* twice is a no-op */
}

static void test_folders(void)
{
    scen_lib l;
    gale_err e = { 0 };
    CHECK(scen_lib_load(&l, "test_scen_lib.d/none", &e) == 0 && l.n == 0);
    mkdir("test_scen_lib.d", 0755);
    mkdir("test_scen_lib.d/bad", 0755);
    FILE *f = fopen("test_scen_lib.d/bad/broken.json", "w");
    CHECK(f != NULL);
    if (f) {
        fputs("{\"kind\": \"steady\", \"steady\": {\"u10_ms\": 500}}\n", f);
        fclose(f);
    }
    CHECK(scen_lib_load(&l, "test_scen_lib.d/bad", &e) != 0 && l.n == 0);
    CHECK_STR_HAS(e.msg, "test_scen_lib.d/bad/broken.json");
    CHECK_STR_HAS(e.msg, "steady.u10_ms");
}

int main(void)
{
    RUN(test_shipped);
    RUN(test_folders);
    return check_report();
}
