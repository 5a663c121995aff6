/* The exhibit's opening hours and usage counters (server/serve/ops_hours.c, ops_usage.c):
 * the --hours grammar and its refusals, open/closed and the next change against times
 * worked out by hand (UTC, and Europe/Berlin across the spring change when the zone
 * database is installed), sessions against the idle time, the dial classes against
 * wind_scale.h's boundaries, and the counters' file: a round trip, an atomic write that
 * leaves no temporary, and refusals of a corrupt file that name it and the key and leave
 * it as it was. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "check.h"
#include "ops_hours.h"
#include "ops_usage.h"

/* 2026-12-07 (a Monday) hh:mm:ss UTC. */
static time_t mon_utc(int hh, int mm, int ss)
{
    return (time_t)1796601600 + hh * 3600 + mm * 60 + ss; /* 2026-12-07T00:00:00Z */
}

static void test_hours_parse(void)
{
    ops_hours h;
    gale_err e;
    CHECK(ops_hours_parse("09:30-17:00", &h, &e) == 0);
    for (int d = 0; d < 7; d++) {
        CHECK(h.open_s[d] == 9 * 3600 + 1800 && h.close_s[d] == 17 * 3600);
    }
    CHECK(ops_hours_parse("mon-fri 09:30-17:00; sat,sun 10:00:15-18:00; tue closed", &h, &e) == 0);
    CHECK(h.open_s[1] == 34200 && h.open_s[2] == -1 && h.open_s[6] == 36015 &&
          h.open_s[0] == 36015 && h.close_s[5] == 61200);
    CHECK(ops_hours_parse("sat 10:00-12:00", &h, &e) == 0); /* the days not named: closed */
    CHECK(h.open_s[6] == 36000 && h.open_s[1] == -1 && h.open_s[0] == -1);
    CHECK(ops_hours_parse("fri-mon 08:00-24:00", &h, &e) == 0); /* wraps over Sunday */
    CHECK(h.open_s[5] == 28800 && h.open_s[0] == 28800 && h.open_s[1] == 28800 &&
          h.open_s[2] == -1 && h.close_s[0] == 86400);
    CHECK(ops_hours_parse("17:00-09:30", &h, &e) == GALE_E_PARSE);
    CHECK_STR_HAS(e.msg, "hours: \"17:00-09:30\": expected the closing time after the opening "
                         "time (a window may not span midnight)");
    CHECK(ops_hours_parse("9:30-17:00", &h, &e) == GALE_E_PARSE);
    CHECK_STR_HAS(e.msg, "hours: \"9:30-17:00\": expected HH:MM-HH:MM");
    CHECK(ops_hours_parse("mon-fry 09:30-17:00", &h, &e) == GALE_E_PARSE);
    CHECK_STR_HAS(e.msg, "expected a day after '-'");
    CHECK(ops_hours_parse("09:60-17:00", &h, &e) == GALE_E_PARSE);
    CHECK(ops_hours_parse("09:30-24:01", &h, &e) == GALE_E_PARSE);
    CHECK(ops_hours_parse(" ; ", &h, &e) == GALE_E_PARSE);
    CHECK_STR_HAS(e.msg, "expected HH:MM-HH:MM, or entries like");
}

static void test_hours_eval(void)
{
    setenv("TZ", "UTC", 1);
    tzset();
    ops_hours h;
    gale_err e;
    time_t next;
    CHECK(ops_hours_parse("mon-fri 09:30-17:00; sat 10:00-12:00", &h, &e) == 0);
    /* Monday 08:00: closed, opens 09:30 the same day */
    CHECK(!ops_hours_eval(&h, mon_utc(8, 0, 0), &next));
    CHECK(next == mon_utc(9, 30, 0));
    /* the opening second itself is open; the closing second is closed */
    CHECK(ops_hours_eval(&h, mon_utc(9, 30, 0), &next) && next == mon_utc(17, 0, 0));
    CHECK(!ops_hours_eval(&h, mon_utc(17, 0, 0), &next) && next == mon_utc(24 + 9, 30, 0));
    /* Friday 18:00: Saturday 10:00; Saturday 12:00: Monday 09:30 */
    CHECK(!ops_hours_eval(&h, mon_utc(4 * 24 + 18, 0, 0), &next));
    CHECK(next == mon_utc(5 * 24 + 10, 0, 0));
    CHECK(!ops_hours_eval(&h, mon_utc(5 * 24 + 12, 0, 0), &next));
    CHECK(next == mon_utc(7 * 24 + 9, 30, 0));
    char b[32];
    ops_hours_today(&h, mon_utc(12, 0, 0), b, sizeof b);
    CHECK(!strcmp(b, "09:30-17:00"));
    ops_hours_today(&h, mon_utc(6 * 24 + 12, 0, 0), b, sizeof b);
    CHECK(!strcmp(b, "closed"));
    ops_hours_clock(mon_utc(9, 30, 0), b, sizeof b);
    CHECK(!strcmp(b, "09:30"));
    ops_hours_clock(mon_utc(9, 30, 5), b, sizeof b);
    CHECK(!strcmp(b, "09:30:05"));
    /* no hours: always open, no change; closed every day: no change ahead */
    ops_hours none = { 0 };
    CHECK(ops_hours_eval(&none, mon_utc(3, 0, 0), &next) && next == 0);
    CHECK(ops_hours_parse("closed", &h, &e) == 0);
    CHECK(!ops_hours_eval(&h, mon_utc(3, 0, 0), &next) && next == 0);
    /* daylight saving: Berlin springs from 02:00 CET to 03:00 CEST on 2027-03-28 (a
     * Sunday): Saturday 20:00 CET (19:00Z) closed, Sunday 09:30 CEST is 07:30Z */
    setenv("TZ", "Europe/Berlin", 1);
    tzset();
    struct stat st;
    if (stat("/usr/share/zoneinfo/Europe/Berlin", &st) == 0) {
        CHECK(ops_hours_parse("09:30-17:00", &h, &e) == 0);
        const time_t sat = (time_t)1806105600 + 19 * 3600; /* 2027-03-27T19:00:00Z */
        CHECK(!ops_hours_eval(&h, sat, &next));
        CHECK(next == (time_t)1806105600 + 86400 + 7 * 3600 + 1800);
    } else {
        fprintf(stderr, "  (no zone database: the daylight-saving case is not checked)\n");
    }
    setenv("TZ", "UTC", 1);
    tzset();
}

static void test_sessions(void)
{
    ops_usage u;
    ops_usage_init(&u);
    ops_usage_interaction(&u, 100.0, 300.0);
    ops_usage_interaction(&u, 250.0, 300.0);
    ops_usage_interaction(&u, 550.0, 300.0); /* 300 s after: the same session */
    CHECK(u.sessions == 1 && u.in_session);
    CHECK(!ops_usage_poll(&u, 850.0, 300.0));
    CHECK(ops_usage_poll(&u, 850.5, 300.0)); /* more than 300 s idle: it ended */
    CHECK(u.sessions == 1 && !u.in_session);
    CHECK_NEAR(u.dwell_s, 450.0, 1e-9);
    ops_usage_interaction(&u, 1000.0, 300.0);
    ops_usage_interaction(&u, 1400.0, 300.0); /* a gap of 400 s: a new session */
    CHECK(u.sessions == 3);
    CHECK_NEAR(u.dwell_s, 450.0, 1e-9);
    ops_usage_interaction(&u, 1410.0, 300.0);
    ops_usage_end(&u);
    CHECK_NEAR(u.dwell_s, 460.0, 1e-9);
}

static void test_dials(void)
{
    ops_usage u;
    ops_usage_init(&u);
    ops_usage_interaction(&u, 0, 300);
    /* a drag from calm to Category 2 and back through Category 1: TD, TS, Cat1, Cat2, Cat1
     * each once; the repeats within a class are not counted */
    const double drag[] = { 5, 10, 17.2, 20, 33, 35, 42.7, 44, 42, 38 };
    for (size_t i = 0; i < sizeof drag / sizeof drag[0]; i++) {
        ops_usage_dial(&u, drag[i]);
    }
    /* 17.2 m/s = 33.4 kt → 33 kt: TD; 17.7 m/s would be TS. 42.7 m/s = 83.0 kt: Cat 2 */
    CHECK(u.categories[WIND_SCALE_TD] == 1);
    CHECK(u.categories[WIND_SCALE_TS] == 1);
    CHECK(u.categories[WIND_SCALE_CAT1] == 2);
    CHECK(u.categories[WIND_SCALE_CAT2] == 1);
    ops_usage_interaction(&u, 1000, 300); /* a new session: the same class counts again */
    ops_usage_dial(&u, 38);
    CHECK(u.categories[WIND_SCALE_CAT1] == 3);
    /* names: a full table counts the rest as "other" */
    for (int i = 0; i < 40; i++) {
        char n[16];
        snprintf(n, sizeof n, "s%d", i);
        ops_usage_count(u.replays, &u.n_replays, n);
    }
    ops_usage_count(u.replays, &u.n_replays, "s3");
    CHECK(u.n_replays == OPS_USAGE_MAX_NAMES);
    CHECK(u.replays[3].n == 2);
    CHECK(!strcmp(u.replays[OPS_USAGE_MAX_NAMES - 1].name, OPS_USAGE_OTHER));
    CHECK(u.replays[OPS_USAGE_MAX_NAMES - 1].n == 40 - (OPS_USAGE_MAX_NAMES - 1));
}

static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        return NULL;
    }
    static char b[8192];
    size_t n = fread(b, 1, sizeof b - 1, f);
    fclose(f);
    b[n] = 0;
    return strdup(b);
}

static void put(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    if (f) {
        fputs(text, f);
        fclose(f);
    }
}

static void test_file(void)
{
    const char *path = "test_ops.d/usage.json";
    mkdir("test_ops.d", 0755);
    unlink(path);
    ops_usage u, v;
    gale_err e;
    bool found = true;
    CHECK(ops_usage_load(&v, path, &found, &e) == 0 && !found && v.sessions == 0);
    ops_usage_init(&u);
    ops_usage_interaction(&u, 10, 300);
    ops_usage_dial(&u, 71); /* 138 kt: Category 5 */
    ops_usage_count(u.replays, &u.n_replays, "andrew1992");
    ops_usage_count(u.replays, &u.n_replays, "andrew1992");
    ops_usage_count(u.langs, &u.n_langs, "en");
    ops_usage_interaction(&u, 22.5, 300);
    CHECK(ops_usage_save(&u, path, &e) == 0);
    CHECK(access("test_ops.d/usage.json.tmp", F_OK) != 0); /* renamed away */
    CHECK(ops_usage_load(&v, path, &found, &e) == 0 && found);
    CHECK(v.sessions == 1 && v.categories[WIND_SCALE_CAT5] == 1 && v.n_replays == 1 &&
          v.replays[0].n == 2 && !strcmp(v.langs[0].name, "en"));
    CHECK_NEAR(v.dwell_s, 12.5, 1e-9); /* the session under way counts what it had */
    CHECK(!v.in_session);

    /* corrupt files: refused with the file, place and key; the file stays as it was */
    static const struct {
        const char *text, *msg;
    } bad[] = {
        { "{\"format\":\"gale-usage\",\"version\":1,", "usage.json:1:35: invalid JSON" },
        { "{\"format\":\"gale-usage\",\"version\":1,\"sessions\":-1,\"dwell_s\":0,"
          "\"categories\":{},\"replays\":{},\"languages\":{}}", "sessions" },
        { "{\"format\":\"gale-usage\",\"version\":2,\"sessions\":1,\"dwell_s\":0,"
          "\"categories\":{},\"replays\":{},\"languages\":{}}", "version" },
        { "{\"format\":\"gale-usage\",\"version\":1,\"sessions\":1,\"dwell_s\":0,"
          "\"categories\":{\"td\":0,\"ts\":0,\"cat1\":0,\"cat2\":0,\"cat3\":0,\"cat4\":0,"
          "\"cat5\":\"x\"},\"replays\":{},\"languages\":{}}", "cat5" },
        { "{\"format\":\"gale-usage\",\"version\":1,\"sessions\":1,\"dwell_s\":0,"
          "\"categories\":{\"td\":0,\"ts\":0,\"cat1\":0,\"cat2\":0,\"cat3\":0,\"cat4\":0,"
          "\"cat5\":0},\"replays\":{\"a\":1.5},\"languages\":{}}", "a" },
        { "{\"format\":\"other\"}", "format: expected \"gale-usage\"" },
        { "{\"format\":\"gale-usage\",\"version\":1,\"sessions\":1,\"dwell_s\":0,"
          "\"categories\":{\"td\":0,\"ts\":0,\"cat1\":0,\"cat2\":0,\"cat3\":0,\"cat4\":0,"
          "\"cat5\":0},\"replays\":{\"a\":1,\"a\":2},\"languages\":{}}", "replays.a: duplicate key" },
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        put(path, bad[i].text);
        gale_err be = { 0 };
        CHECK(ops_usage_load(&v, path, &found, &be) != 0 && !found && v.sessions == 0);
        CHECK_STR_HAS(be.msg, "test_ops.d/usage.json");
        CHECK_STR_HAS(be.msg, bad[i].msg);
        char *after = slurp(path);
        CHECK(after && !strcmp(after, bad[i].text));
        free(after);
    }
    /* unreadable: a folder where the file should be */
    gale_err de;
    CHECK(ops_usage_load(&v, "test_ops.d", &found, &de) != 0);
    CHECK_STR_HAS(de.msg, "test_ops.d");
}

static void test_prom(void)
{
    ops_usage u;
    ops_usage_init(&u);
    ops_usage_count(u.replays, &u.n_replays, "odd\"name");
    char b[8192];
    size_t n = 0;
    CHECK(ops_usage_prom(&u, b, sizeof b, &n) && n == strlen(b));
    CHECK_STR_HAS(b, "gale_usage_scenarios_total{scenario=\"odd\\\"name\"} 1\n");
    CHECK_STR_HAS(b, "gale_usage_dials_total{class=\"cat5\"} 0\n");
    n = 0;
    CHECK(!ops_usage_prom(&u, b, 64, &n)); /* too small: false, never past the buffer */
}

int main(void)
{
    RUN(test_hours_parse);
    RUN(test_hours_eval);
    RUN(test_sessions);
    RUN(test_dials);
    RUN(test_file);
    RUN(test_prom);
    return check_report();
}
