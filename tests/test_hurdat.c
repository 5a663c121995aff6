/* HURDAT2 reader: the shipped Andrew and Charley rows, landfall values from PHYSICS.md,
 * calendar arithmetic, and bad input with exact messages naming the line. gale-hurdat:
 * configs/scenarios/README.md's commands rebuild the shipped replays byte for byte, the
 * site's local time (--utc-offset-min) included, and the scenario reads it. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "check.h"
#include "hurdat.h"
#include "scenario.h"

#ifndef GALE_HURDAT_EXE
#error "GALE_HURDAT_EXE (path of gale-hurdat) must be defined by the build"
#endif

static void test_shipped_rows(void)
{
    hurdat_file f;
    gale_err err = { 0 };
    int rc =
        hurdat_load(&f, GALE_SOURCE_DIR "/tests/data/hurdat2-andrew1992-charley2004.txt", &err);
    CHECK(rc == 0);
    if (rc < 0) {
        fprintf(stderr, "%s\n", err.msg);
        return;
    }
    CHECK(f.n_storms == 2);
    const hurdat_storm *a = hurdat_find(&f, "andrew");
    const hurdat_storm *c = hurdat_find(&f, "AL032004");
    CHECK(a && c);
    if (!a || !c) {
        hurdat_fini(&f);
        return;
    }
    CHECK(a->n_rows == 52);
    CHECK(c->n_rows == 30);
    CHECK_STR_HAS(c->name, "CHARLEY");
    /* Andrew's mainland landfall: 1992-08-24 09:05 UTC, 25.5N 80.3W, 145 kt, 922 mb, RMW 10 */
    const hurdat_row *l = NULL;
    for (int i = 0; i < a->n_rows; i++) {
        if (a->rows[i].day == 24 && a->rows[i].hour == 9 && a->rows[i].minute == 5) {
            l = &a->rows[i];
        }
    }
    CHECK(l != NULL);
    if (l) {
        CHECK(l->record == 'L');
        CHECK_STR_HAS(l->status, "HU");
        CHECK_NEAR(l->lat_deg, 25.5, 1e-12);
        CHECK_NEAR(l->lon_deg, -80.3, 1e-12);
        CHECK(l->vmax_kt == 145);
        CHECK(l->pmin_mb == 922);
        CHECK(l->rmw_nm == 10);
        CHECK(l[-1].rmw_nm == HURDAT_MISSING);
    }
    hurdat_fini(&f);
}

/* A row without a central pressure: the nearest row's that has one, its deficit scaled by
 * the winds squared. Camille 1969-08-18 06:00Z (115 kt, no pressure): the nearest is the
 * landfall at 04:00Z (150 kt, 900 hPa) → 1013 − 113 (115/150)² = 946.58 hPa; 00:00Z (140
 * kt) is 4 h from 04:00Z and 6 h from 1969-08-17 18:00Z (919 hPa): 1013 − 113 (140/150)². */
static void test_pressure_fill(void)
{
    hurdat_file f;
    gale_err err = { 0 };
    CHECK(hurdat_load(&f, GALE_SOURCE_DIR "/tests/data/hurdat2-landfalls.txt", &err) == 0);
    CHECK(f.n_storms == 13);
    const hurdat_storm *c = hurdat_find(&f, "AL091969");
    CHECK(c != NULL);
    int n_rows = 0;
    for (int i = 0; i < f.n_storms; i++) {
        n_rows += f.storms[i].n_rows;
    }
    CHECK(n_rows == 665);
    for (int i = 0; c && i < c->n_rows; i++) {
        const hurdat_row *r = &c->rows[i];
        double p = 0.0;
        if (r->day == 18 && r->hour == 6) {
            CHECK(r->pmin_mb == HURDAT_MISSING && r->vmax_kt == 115);
            CHECK(hurdat_pressure_at(c, i, 1013.0, &p) == 1);
            CHECK_NEAR(p, 1013.0 - 113.0 * (115.0 / 150.0) * (115.0 / 150.0), 1e-9);
            CHECK_NEAR(p, 946.58, 0.005);
        } else if (r->day == 18 && r->hour == 0) {
            CHECK(hurdat_pressure_at(c, i, 1013.0, &p) == 1);
            CHECK_NEAR(p, 1013.0 - 113.0 * (140.0 / 150.0) * (140.0 / 150.0), 1e-9);
        } else if (r->day == 18 && r->hour == 4) {
            CHECK(hurdat_pressure_at(c, i, 1013.0, &p) == 0 && p == 900.0);
        }
    }
    hurdat_fini(&f);
    /* no row with a pressure: none to fill from */
    const char *t = "AL011999, X, 2,\n"
                    "19990801, 0000,  , HU, 25.0N,  80.0W, 100, -999, -999, -999, -999, -999, "
                    "-999, -999, -999, -999, -999, -999, -999, -999, -999\n"
                    "19990801, 0600,  , HU, 25.5N,  80.5W, -999, -999, -999, -999, -999, -999, "
                    "-999, -999, -999, -999, -999, -999, -999, -999, -999\n";
    CHECK(hurdat_parse(&f, "t.txt", t, strlen(t), &err) == 0);
    double p = 0.0;
    CHECK(f.n_storms == 1 && hurdat_pressure_at(&f.storms[0], 0, 1013.0, &p) == -1);
    CHECK(f.n_storms == 1 && hurdat_pressure_at(&f.storms[0], 1, 1013.0, &p) == -1);
    hurdat_fini(&f);
}

static void test_calendar(void)
{
    CHECK(hurdat_civil_minutes(1970, 1, 1, 0, 0) == 0);
    CHECK(hurdat_civil_minutes(1970, 1, 2, 0, 1) == 1441);
    /* 2004 is a leap year: Feb 29 exists */
    CHECK(hurdat_civil_minutes(2004, 3, 1, 0, 0) - hurdat_civil_minutes(2004, 2, 28, 0, 0) ==
          2 * 1440);
    long long m = hurdat_civil_minutes(1992, 8, 24, 9, 5);
    int y, mo, d, h, mi;
    hurdat_civil_from_minutes(m + 19, &y, &mo, &d, &h, &mi);
    CHECK(y == 1992 && mo == 8 && d == 24 && h == 9 && mi == 24);
    hurdat_civil_from_minutes(m + 15 * 60, &y, &mo, &d, &h, &mi);
    CHECK(y == 1992 && mo == 8 && d == 25 && h == 0 && mi == 5);
}

static void expect_error(const char *text, const char *msg)
{
    hurdat_file f;
    gale_err err = { 0 };
    int rc = hurdat_parse(&f, "t.txt", text, strlen(text), &err);
    CHECK(rc < 0);
    CHECK(f.n_storms == 0 && f.storms == NULL);
    if (rc < 0 && !strstr(err.msg, msg)) {
        fprintf(stderr, "got: %s\n", err.msg);
    }
    CHECK_STR_HAS(err.msg, msg);
}

#define HDR "AL041992,             ANDREW,      2,\n"
#define ROW1                                                                          \
    "19920824, 0600,  , HU, 25.4N,  79.3W, 130,  937, -999, -999, -999, -999, -999, " \
    "-999, -999, -999, -999, -999, -999, -999, -999\n"
#define ROW2                                                                          \
    "19920824, 0905, L, HU, 25.5N,  80.3W, 145,  922, -999, -999, -999, -999, -999, " \
    "-999, -999, -999, -999, -999, -999, -999,   10\n"

static void test_errors(void)
{
    hurdat_file f;
    gale_err err = { 0 };
    const char *ok = HDR ROW1 ROW2;
    CHECK(hurdat_parse(&f, "t.txt", ok, strlen(ok), &err) == 0);
    CHECK(f.n_storms == 1 && f.storms[0].n_rows == 2);
    hurdat_fini(&f);

    expect_error("", "t.txt: no storms");
    expect_error("hello\n", "t.txt:1: expected a storm header like 'AL041992, ANDREW, 52,', "
                            "got 'hello'");
    expect_error("AL04199X, ANDREW, 2,\n", "t.txt:1: storm id: expected 2 letters and 6 "
                                           "digits, got 'AL04199X'");
    expect_error("AL041992, ANDREW, 0,\n", "t.txt:1: row count: expected an integer in "
                                           "[1, 2000], got 0");
    expect_error(HDR ROW1, "t.txt:2: end of file, but AL041992 (line 1) declared 1 more rows");
    expect_error(HDR ROW1 HDR, "t.txt:3: storm header, but AL041992 (line 1) declared 1 more "
                               "rows");
    expect_error(HDR ROW2 ROW1, "t.txt:3: time goes backwards (previous row 2)");
    expect_error(HDR ROW1 "19920824, 0905, L, HU, 25.5N,  80.3W, 145\n",
                 "t.txt:3: data row: expected 20 or 21 comma-separated fields, got 7");
    expect_error(HDR ROW1 "19920824, 0905, L, HU, 25.5Q,  80.3W, 145,  922, -999, -999, -999, "
                          "-999, -999, -999, -999, -999, -999, -999, -999, -999,   10\n",
                 "t.txt:3: field 5 (latitude): expected degrees with N or S, like 25.5N, got "
                 "'25.5Q'");
    expect_error(HDR ROW1 "19920824, 0905, L, HU, 25.5N,  80.3W, 145,  999x, -999, -999, -999, "
                          "-999, -999, -999, -999, -999, -999, -999, -999, -999,   10\n",
                 "t.txt:3: field 8 (pressure): expected millibars in [800, 1100] or -999, got "
                 "'999x'");
    expect_error(HDR ROW1 "19920824, 2505, L, HU, 25.5N,  80.3W, 145,  922, -999, -999, -999, "
                          "-999, -999, -999, -999, -999, -999, -999, -999, -999,   10\n",
                 "t.txt:3: field 2 (time): expected hhmm UTC, got '2505'");
    expect_error(HDR ROW1 "19921324, 0905, L, HU, 25.5N,  80.3W, 145,  922, -999, -999, -999, "
                          "-999, -999, -999, -999, -999, -999, -999, -999, -999,   10\n",
                 "t.txt:3: field 1 (date): expected a date YYYYMMDD, got '19921324'");
    expect_error(HDR ROW1 "19920824, 0905, L, HU, 25.5N,  80.3W, 300,  922, -999, -999, -999, "
                          "-999, -999, -999, -999, -999, -999, -999, -999, -999,   10\n",
                 "t.txt:3: field 7 (max wind): expected knots in [0, 250] or -999, got '300'");
    expect_error(HDR ROW1 "19920824, 0905, L, HU, 25.5N,  80.3W, 145,  922, -999, -999, -999, "
                          "-999, -999, -999, -999, -999, -999, -999, -999, -999,    0\n",
                 "t.txt:3: field 21 (radius of max wind): expected nautical miles in [1, 500] "
                 "or -999, got '0'");
}

/* The whole file at path into a malloc'd string (NULL when unreadable). */
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

/* gale-hurdat with Andrew's arguments from configs/scenarios/README.md and `extra`, into
 * out; its exit status. */
static int andrew(const char *extra, const char *out)
{
    /* from the source tree, as the README runs it: the file's "source" names that path */
    char cwd[512], cmd[2200];
    if (!getcwd(cwd, sizeof cwd)) {
        return -1;
    }
    snprintf(cmd, sizeof cmd,
             "cd '" GALE_SOURCE_DIR "' && '%s' --in tests/data/hurdat2-andrew1992-charley2004.txt "
             "--storm ANDREW --name Andrew --ref 1992-08-24T09:05Z --from 1992-08-24T06:00Z "
             "--to 1992-08-24T12:00Z --site-lat 25.52 --site-lon -80.40 --site-label "
             "\"south Miami-Dade County, Florida, in the eye's path\" --time-scale 50 "
             "--start-min -160 --end-min 175 --seed 1992 %s --out '%s/%s' 2>'%s/test_hurdat.d/log'",
             GALE_HURDAT_EXE, extra, cwd, out, cwd);
    int st = system(cmd);
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

static int offset_of(const char *path)
{
    scenario *s = scenario_load(path, NULL);
    scenario_state st = { 0 };
    if (s) {
        scenario_eval(s, 1.0, &st);
    }
    scenario_destroy(s);
    return s && st.has_clock ? st.utc_offset_min : 99999;
}

static void test_tool_offset(void)
{
    mkdir("test_hurdat.d", 0755);
    CHECK(andrew("--utc-offset-min -240", "test_hurdat.d/andrew.json") == 0);
    char *made = slurp("test_hurdat.d/andrew.json");
    char *shipped = slurp(GALE_SOURCE_DIR "/configs/scenarios/andrew1992.json");
    CHECK(made && shipped && strcmp(made, shipped) == 0);
    CHECK(made && strstr(made, "\"utc_offset_min\": -240 }"));
    free(made);
    free(shipped);
    CHECK(offset_of("test_hurdat.d/andrew.json") == -240); /* EDT, as the kiosk shows it */
    /* without it: the longitude's 15-degree zone, -80.4 deg -> UTC-5 */
    CHECK(andrew("", "test_hurdat.d/andrew-zone.json") == 0);
    made = slurp("test_hurdat.d/andrew-zone.json");
    CHECK(made && !strstr(made, "utc_offset_min"));
    free(made);
    CHECK(offset_of("test_hurdat.d/andrew-zone.json") == -300);
    CHECK(andrew("--utc-offset-min 900", "test_hurdat.d/bad.json") == 2);
    char *log = slurp("test_hurdat.d/log");
    CHECK_STR_HAS(log ? log : "", "--utc-offset-min: expected whole minutes in [-840, 840], got 900");
    free(log);
}

int main(void)
{
    RUN(test_tool_offset);
    RUN(test_shipped_rows);
    RUN(test_pressure_fill);
    RUN(test_calendar);
    RUN(test_errors);
    return check_report();
}
