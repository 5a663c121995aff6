/* The storm library (configs/scenarios/README.md): every shipped replay made from HURDAT2
 * rows shows its landfall row's figures at minute 0.
 * - deploy/storm-library.sh, run into a folder of this test's, writes every replay equal,
 *   byte for byte, to the shipped file;
 * - for each shipped replay, its storm's rows are read here (not with hurdat.c) from the
 *   file its "source" names, and the row at "ref_utc" is a landfall (L) row; the scenario
 *   at minute 0 has the row's central pressure exactly and its max wind as kt x 0.514444
 *   within the file's 0.005 m/s;
 * - the real gale-server, asked by a kiosk for each replay at minute 0, paused, sends a
 *   WEATHER whose central_hpa is the row's pressure exactly, whose storm_class is the
 *   Saffir-Simpson class of the row's knots (the frame carries the storm's wind as its
 *   class, PROTOCOL.md "WEATHER"), whose clock is the row's date and time (none before
 *   1970: the frame's utc_min counts from 1970 unsigned); and the HUD's
 *   storm line formatted from it (hud_format_weather) reads "<row's pressure> hPa" and
 *   "storm <class>". */
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <cjson/cJSON.h>

#include "check.h"
#include "hud.h"
#include "lang.h"
#include "kiosk_fixture.h"
#include "scenario.h"
#include "scenario_int.h"

#define MAX_REPLAYS 32

typedef struct replay {
    char stem[64], title[64], id[16], data[160], ref[24];
    /* the landfall row, read here */
    char record;
    int kt, mb;
    long long utc_min;
} replay;

static replay lib[MAX_REPLAYS];
static int n_lib;

/* The whole file into a malloc'd string (NULL when unreadable). */
static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        return NULL;
    }
    char *b = calloc(1, 1 << 20);
    size_t n = b ? fread(b, 1, (1 << 20) - 1, f) : 0;
    (void)n;
    fclose(f);
    return b;
}

/* Minutes since the epoch of a UTC date and time (timegm: the C library's calendar). */
static long long epoch_min(int y, int mo, int d, int h, int mi)
{
    struct tm t = { .tm_year = y - 1900, .tm_mon = mo - 1, .tm_mday = d, .tm_hour = h,
                    .tm_min = mi };
    return (long long)timegm(&t) / 60;
}

/* The Saffir-Simpson class of a wind in whole knots (NHC's table; 0 TD, 1 TS, 2..6 Cat 1..5). */
static int class_of_kt(int kt)
{
    static const int lower[6] = { 34, 64, 83, 96, 113, 137 };
    int c = 0;
    for (int i = 0; i < 6; i++) {
        c += kt >= lower[i];
    }
    return c;
}

/* Field i (0-based) of a comma-separated HURDAT2 line, blanks trimmed, into out. */
static void field(const char *line, int i, char *out, size_t cap)
{
    const char *p = line;
    for (int k = 0; k < i && p; k++) {
        p = strchr(p, ',');
        p = p ? p + 1 : NULL;
    }
    size_t n = 0;
    while (p && *p == ' ') {
        p++;
    }
    while (p && *p && *p != ',' && *p != '\n' && *p != '\r' && n + 1 < cap) {
        out[n++] = *p++;
    }
    while (n > 0 && out[n - 1] == ' ') {
        n--;
    }
    out[n] = '\0';
}

/* The row of storm r->id at r->ref in r->data: its record id, wind and pressure; 0 or -1. */
static int read_row(replay *r)
{
    char path[400];
    snprintf(path, sizeof path, GALE_SOURCE_DIR "/%s", r->data);
    FILE *f = fopen(path, "r");
    if (!f) {
        fprintf(stderr, "%s: %s: cannot read\n", r->stem, path);
        return -1;
    }
    int y, mo, d, h, mi;
    if (sscanf(r->ref, "%4d-%2d-%2dT%2d:%2dZ", &y, &mo, &d, &h, &mi) != 5) {
        fclose(f);
        return -1;
    }
    char want_date[16], want_time[8], line[512], a[64];
    snprintf(want_date, sizeof want_date, "%04d%02d%02d", y, mo, d);
    snprintf(want_time, sizeof want_time, "%02d%02d", h, mi);
    int left = -1, found = -1;
    while (fgets(line, sizeof line, f)) {
        field(line, 0, a, sizeof a);
        if (a[0] == 'A' && a[1] == 'L') { /* a header: id, name, rows */
            char n[16];
            field(line, 2, n, sizeof n);
            left = strcmp(a, r->id) == 0 ? atoi(n) : -1;
            continue;
        }
        if (left <= 0) {
            continue;
        }
        left--;
        char t[16], rec[8], w[16], p[16];
        field(line, 1, t, sizeof t);
        if (strcmp(a, want_date) != 0 || strcmp(t, want_time) != 0) {
            continue;
        }
        field(line, 2, rec, sizeof rec);
        field(line, 6, w, sizeof w);
        field(line, 7, p, sizeof p);
        r->record = rec[0] ? rec[0] : ' ';
        r->kt = atoi(w);
        r->mb = atoi(p);
        r->utc_min = epoch_min(y, mo, d, h, mi);
        found = 0;
    }
    fclose(f);
    if (found != 0) {
        fprintf(stderr, "%s: no row %s %s of %s in %s\n", r->stem, want_date, want_time, r->id,
                r->data);
    }
    return found;
}

/* The shipped replays made from HURDAT2 (their "source" names the storm and the file). */
static void find_replays(void)
{
    DIR *dir = opendir(GALE_SOURCE_DIR "/configs/scenarios");
    CHECK(dir != NULL);
    struct dirent *e;
    while (dir && (e = readdir(dir)) && n_lib < MAX_REPLAYS) {
        size_t n = strlen(e->d_name);
        if (n < 6 || strcmp(e->d_name + n - 5, ".json") != 0) {
            continue;
        }
        char path[400];
        snprintf(path, sizeof path, GALE_SOURCE_DIR "/configs/scenarios/%s", e->d_name);
        char *text = slurp(path);
        cJSON *j = text ? cJSON_Parse(text) : NULL;
        free(text);
        const cJSON *h = cJSON_GetObjectItemCaseSensitive(j, "hurricane");
        const cJSON *src = cJSON_GetObjectItemCaseSensitive(h, "source");
        const cJSON *ref = cJSON_GetObjectItemCaseSensitive(h, "ref_utc");
        const cJSON *name = cJSON_GetObjectItemCaseSensitive(j, "name");
        replay *r = &lib[n_lib];
        memset(r, 0, sizeof *r);
        const char *of = cJSON_IsString(src) ? strstr(src->valuestring, " of ") : NULL;
        if (cJSON_IsString(src) && cJSON_IsString(ref) && cJSON_IsString(name) && of &&
            sscanf(src->valuestring, "NHC HURDAT2 %15[A-Z0-9]", r->id) == 1 &&
            sscanf(of + 4, "%159[^;]", r->data) == 1) {
            snprintf(r->stem, sizeof r->stem, "%.*s", (int)(n - 5), e->d_name);
            snprintf(r->title, sizeof r->title, "%s", name->valuestring);
            snprintf(r->ref, sizeof r->ref, "%s", ref->valuestring);
            n_lib++;
        }
        cJSON_Delete(j);
    }
    if (dir) {
        closedir(dir);
    }
}

/* deploy/storm-library.sh into test_storm_library.d/regen: each file equals the shipped. */
static void test_regenerate(void)
{
    char cwd[400], cmd[1400];
    CHECK(getcwd(cwd, sizeof cwd) != NULL);
    snprintf(cmd, sizeof cmd,
             "rm -rf test_storm_library.d/regen && GALE_HURDAT='%s' '" GALE_SOURCE_DIR
             "/deploy/storm-library.sh' '%s/test_storm_library.d/regen' "
             "2>test_storm_library.d/regen.log",
             GALE_HURDAT_EXE, cwd);
    CHECK(system(cmd) == 0);
    int same = 0;
    for (int i = 0; i < n_lib; i++) {
        char made[500], shipped[500];
        snprintf(made, sizeof made, "test_storm_library.d/regen/%.63s.json", lib[i].stem);
        snprintf(shipped, sizeof shipped, GALE_SOURCE_DIR "/configs/scenarios/%.63s.json",
                 lib[i].stem);
        char *a = slurp(made), *b = slurp(shipped);
        bool eq = a && b && strcmp(a, b) == 0;
        if (!eq) {
            fprintf(stderr, "  %s: the script's file differs from the shipped one\n",
                    lib[i].stem);
        }
        CHECK(eq);
        same += eq;
        free(a);
        free(b);
    }
    fprintf(stderr, "  %d of %d replays rebuilt byte for byte\n", same, n_lib);
}

/* The rows, read here, and the scenario evaluated at minute 0. */
static void test_rows_and_scenario(void)
{
    CHECK(n_lib == 15); /* Andrew, Charley and the library's 13 */
    for (int i = 0; i < n_lib; i++) {
        replay *r = &lib[i];
        CHECK(read_row(r) == 0);
        CHECK(r->record == 'L');
        CHECK(r->kt > 0 && r->mb > 0);
        char path[400];
        snprintf(path, sizeof path, GALE_SOURCE_DIR "/configs/scenarios/%s.json", r->stem);
        gale_err err = { 0 };
        scenario *s = scenario_load(path, &err);
        CHECK(s != NULL);
        if (!s) {
            fprintf(stderr, "%s\n", err.msg);
            continue;
        }
        CHECK(scenario_set_start(s, 0.0, true, 0.0, false, 0.0, &err) == 0);
        scenario_state st;
        scenario_eval(s, 0.0, &st);
        scenario_track_pt c;
        scenario_storm_at(s, 0.0, &c);
        fprintf(stderr, "  %-14s %s %c %3d kt %4d hPa | minute %.1f: %.2f m/s, %.1f hPa, %s\n",
                r->stem, r->ref, r->record, r->kt, r->mb, st.storm_min, c.vmax_ms,
                st.central_hpa, st.clock_utc);
        CHECK(st.storm_min == 0.0);
        CHECK(st.central_hpa == (double)r->mb);
        CHECK_NEAR(c.vmax_ms, r->kt * 0.514444, 0.005);
        CHECK(st.storm_category == class_of_kt(r->kt));
        CHECK(st.has_clock && st.utc_min == r->utc_min);
        scenario_destroy(s);
    }
}

static bool at_landfall(const wire_weather *w, double arg)
{
    const replay *r = &lib[(int)arg];
    return strcmp(w->name, r->title) == 0 && (w->flags & WIRE_WEATHER_PAUSED) &&
           w->storm_min == 0.0f;
}

/* The real server's WEATHER at each landfall, and the HUD line made from it. */
static void test_server_weather(void)
{
    kf_reader k;
    CHECK(kf_reader_start(&k, "kiosk", KIOSK_TOKEN) == 0);
    for (int i = 0; i < n_lib; i++) {
        const replay *r = &lib[i];
        char msg[300];
        snprintf(msg, sizeof msg,
                 "{\"type\": \"wind\", \"token\": \"" KIOSK_TOKEN "\", \"scenario\": \"%.63s\", "
                 "\"replay_at_min\": 0, \"replay_paused\": true}",
                 r->stem);
        wsraw_text(&k.c, msg);
        wire_weather w;
        bool got = kf_reader_wait(&k, 20.0, at_landfall, (double)i, &w);
        CHECK(got);
        if (!got) {
            fprintf(stderr, "  %s: no WEATHER at its landfall (last: \"%s\", minute %.1f)\n",
                    r->stem, w.name, (double)w.storm_min);
            continue;
        }
        CHECK(w.flags & WIRE_WEATHER_STORM);
        CHECK(w.central_hpa == (float)r->mb);
        CHECK(w.storm_class == class_of_kt(r->kt));
        if (r->utc_min >= 0) {
            CHECK((w.flags & WIRE_WEATHER_CLOCK) && (long long)w.utc_min == r->utc_min);
        } else {
            /* before 1970 (Labor Day 1935, Camille 1969): utc_min is a u32 of minutes since
               1970, so the frame carries no clock and the HUD shows no date */
            CHECK(!(w.flags & WIRE_WEATHER_CLOCK));
        }
        char lines[HUD_MAX_LINES][HUD_LINE_CHARS];
        int n = hud_format_weather(&w, LANG_EN, lines);
        char want_p[32], want_c[32];
        snprintf(want_p, sizeof want_p, " %d hPa ", r->mb);
        static const char *const abbrev[7] = { "TD",    "TS",    "Cat 1", "Cat 2",
                                               "Cat 3", "Cat 4", "Cat 5" };
        snprintf(want_c, sizeof want_c, "storm %s", abbrev[class_of_kt(r->kt)]);
        const char *eye = NULL;
        for (int l = 0; l < n; l++) {
            eye = strncmp(lines[l], "Eye ", 4) == 0 ? lines[l] : eye;
        }
        CHECK(eye != NULL);
        fprintf(stderr, "  %-14s HUD: %s\n", r->stem, eye ? eye : "(no Eye line)");
        CHECK_STR_HAS(eye ? eye : "", want_p);
        CHECK_STR_HAS(eye ? eye : "", want_c);
    }
    kf_reader_stop(&k);
}

int main(void)
{
    kf_init("test_storm_library");
    find_replays();
    RUN(test_rows_and_scenario);
    RUN(test_regenerate);
    if (kf_start_server(NULL, NULL) != 0) {
        fprintf(stderr, "gale-server did not start\n");
        return 1;
    }
    RUN(test_server_weather);
    kf_stop_server();
    return check_report();
}
