/* The exhibit's operation on the real gale-server (server/SERVER.md "Status", "Opening
 * hours", "Usage counters"):
 * - a window of the opening hours a few seconds ahead (second resolution, TZ=UTC): a
 *   kiosk that joins while closed is told so (schedule open false, next_change the
 *   opening), the tick stays where it is and the process uses next to no CPU; at the
 *   opening every client is told (open true) and the tick runs; at the closing it holds
 *   again, and the connections stay;
 * - kiosk_state, dials and a pick show in /status and /metrics (a session counts the
 *   language of the kiosk it began at, and a change of language in it); a viewer's
 *   kiosk_state is refused (4006), a bad language 4002 with its message;
 * - the counters after a restart equal those before (the state file);
 * - a corrupt state file stops the server with the file and key named, and is left as
 *   it was. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "check.h"
#include "kiosk_fixture.h"

static char state[300];

/* The next text message containing needle within timeout_s (binary frames skipped);
 * malloc'd, NULL when none came. */
static char *next_text(wsraw *c, const char *needle, double timeout_s)
{
    const double until = mono_s() + timeout_s;
    while (mono_s() < until) {
        uint8_t *m;
        size_t n;
        int op = wsraw_recv(c, &m, &n, 200);
        if (op == 1 && m && strstr((const char *)m, needle)) {
            return (char *)m;
        }
        free(m);
        if (op == 8) {
            return NULL;
        }
    }
    return NULL;
}

static unsigned tick_now(void)
{
    char *b = NULL;
    unsigned t = 0;
    if (wsraw_http_get(kf_port, "/healthz", &b) == 200 && b) {
        sscanf(b, "ok tick %u", &t);
    }
    free(b);
    return t;
}

/* user + system CPU seconds of the server so far (/proc/PID/stat). */
static double cpu_s(void)
{
    char p[64], line[1024];
    snprintf(p, sizeof p, "/proc/%d/stat", (int)kf_server);
    FILE *f = fopen(p, "r");
    unsigned long ut = 0, st = 0;
    if (f && fgets(line, sizeof line, f)) {
        const char *q = strrchr(line, ')');
        /* fields after the name: state ppid pgrp session tty tpgid flags minflt cminflt
         * majflt cmajflt utime stime */
        if (q) {
            sscanf(q + 2, "%*c %*d %*d %*d %*d %*d %*u %*u %*u %*u %*u %lu %lu", &ut, &st);
        }
    }
    if (f) {
        fclose(f);
    }
    return (double)(ut + st) / (double)sysconf(_SC_CLK_TCK);
}

static void clock_at(time_t t, char *out, size_t cap)
{
    struct tm tm;
    gmtime_r(&t, &tm);
    strftime(out, cap, "%H:%M:%S", &tm);
}

/* t as the schedule's next_change writes it: HH:MM on a whole minute, else HH:MM:SS. */
static void change_at(time_t t, char *out, size_t cap)
{
    struct tm tm;
    gmtime_r(&t, &tm);
    strftime(out, cap, tm.tm_sec ? "%H:%M:%S" : "%H:%M", &tm);
}

static char *get(const char *path)
{
    char *b = NULL;
    if (wsraw_http_get(kf_port, path, &b) != 200) {
        free(b);
        return NULL;
    }
    return b;
}

/* The lines of /metrics that start with gale_usage_. */
static void usage_rows(char *out, size_t cap)
{
    char *m = get("/metrics");
    out[0] = 0;
    size_t n = 0;
    for (char *l = m ? strtok(m, "\n") : NULL; l; l = strtok(NULL, "\n")) {
        if (!strncmp(l, "gale_usage_", 11) && n + strlen(l) + 2 < cap) {
            n += (size_t)snprintf(out + n, cap - n, "%s\n", l);
        }
    }
    free(m);
}

static char rows_before[4096];
static char usage_before[2048];

/* "usage":{...} of /status. */
static void usage_json(char *out, size_t cap)
{
    char *s = get("/status");
    const char *u = s ? strstr(s, "\"usage\":") : NULL;
    snprintf(out, cap, "%s", u ? u : "(none)");
    free(s);
}

static void test_closed_then_open(void)
{
    setenv("TZ", "UTC", 1);
    /* a window may not span midnight: a run in the day's last 30 s waits for the next day */
    const time_t left_s = 86400 - time(NULL) % 86400;
    if (left_s < 30) {
        sleep((unsigned)left_s + 1);
    }
    const time_t now = time(NULL);
    char o[16], c[16], hours[40];
    /* opens 10 s from now (the server takes a moment to start, more on a loaded machine),
     * closes 14 s after */
    clock_at(now + 10, o, sizeof o);
    clock_at(now + 24, c, sizeof c);
    snprintf(hours, sizeof hours, "%s-%s", o, c);
    snprintf(state, sizeof state, "%s/usage.json", kf_dir);
    unlink(state);
    const char *extra[] = { "--hours", hours, "--state-file", state, "--kiosk-idle", "2", NULL };
    CHECK(kf_start_server(NULL, extra) == 0);
    if (time(NULL) >= now + 7) {
        fprintf(stderr, "  the server took too long to start for this window\n");
        CHECK(0);
        return;
    }
    wsraw k = { .fd = -1 }, v = { .fd = -1 };
    CHECK(kf_hello(&k, "kiosk", KIOSK_TOKEN) == 0);
    char *m = next_text(&k, "\"schedule\"", 3);
    char want[80], o_change[16], c_change[16];
    change_at(now + 10, o_change, sizeof o_change);
    change_at(now + 24, c_change, sizeof c_change);
    snprintf(want, sizeof want, "\"open\":false,\"next_change\":\"%s\"", o_change);
    CHECK(m && strstr(m, want));
    free(m);
    CHECK(kf_hello(&v, "viewer", NULL) == 0);
    m = next_text(&v, "\"schedule\"", 3);
    CHECK(m && strstr(m, "\"open\":false"));
    free(m);
    /* closed: the tick holds and the process idles */
    const unsigned t0 = tick_now();
    const double c0 = cpu_s();
    usleep(1500000);
    const unsigned t1 = tick_now();
    const double c1 = cpu_s();
    CHECK(t1 == t0);
    fprintf(stderr, "  closed: tick %u -> %u, %.3f s of CPU in 1.5 s\n", t0, t1, c1 - c0);
    CHECK(c1 - c0 < 0.15); /* a ticking server here takes ~0.5 s of CPU per second */
    char *st = get("/status");
    CHECK(st && strstr(st, "\"state\":\"closed\""));
    free(st);
    /* the opening: both told, the tick runs */
    m = next_text(&k, "\"open\":true", 14);
    snprintf(want, sizeof want, "\"next_change\":\"%s\"", c_change);
    CHECK(m && strstr(m, want));
    free(m);
    m = next_text(&v, "\"open\":true", 3);
    CHECK(m != NULL);
    free(m);
    usleep(500000);
    CHECK(tick_now() > t1 + 10);
    /* a kiosk's state, two dials and a pick */
    wsraw_text(&k, "{\"type\":\"kiosk_state\",\"token\":\"" KIOSK_TOKEN "\",\"lang\":\"en\","
                   "\"audio\":\"none\"}");
    wsraw_text(&k, "{\"type\":\"wind\",\"token\":\"" KIOSK_TOKEN "\",\"speed_ms\":45}");
    wsraw_text(&k, "{\"type\":\"wind\",\"token\":\"" KIOSK_TOKEN "\",\"speed_ms\":46}");
    wsraw_text(&k, "{\"type\":\"wind\",\"token\":\"" KIOSK_TOKEN "\",\"scenario\":\"andrew1992\"}");
    usleep(300000);
    st = get("/status");
    CHECK(st && strstr(st, "\"state\":\"open\""));
    CHECK(st && strstr(st, "\"kiosk\":1,"));
    CHECK(st && strstr(st, "\"viewer\":1,"));
    CHECK(st && strstr(st, "\"languages\":[\"en\"]"));
    CHECK(st && strstr(st, "\"audio\":[\"none\"]"));
    CHECK(st && strstr(st, "\"last_interaction\":{\"utc\":\""));
    CHECK(st && strstr(st, "\"sessions\":1,"));
    CHECK(st && strstr(st, "\"cat2\":1,")); /* 45 and 46 m/s: 87 and 89 kt, one class */
    CHECK(st && strstr(st, "\"replays\":{\"andrew1992\":1}"));
    if (st) {
        fprintf(stderr, "  /status: %s\n", st);
    }
    free(st);
    char *mt = get("/metrics");
    CHECK(mt && strstr(mt, "gale_usage_dials_total{class=\"cat2\"} 1\n"));
    CHECK(mt && strstr(mt, "gale_usage_languages_total{lang=\"en\"} 1\n"));
    CHECK(mt && strstr(mt, "gale_usage_scenarios_total{scenario=\"andrew1992\"} 1\n"));
    CHECK(mt && strstr(mt, "gale_open 1\n"));
    free(mt);
    /* the visitor switches the kiosk to German: counted in the session under way; the
     * kiosk's first report (above) was its own, not counted */
    wsraw_text(&k, "{\"type\":\"kiosk_state\",\"token\":\"" KIOSK_TOKEN "\",\"lang\":\"de\","
                   "\"audio\":\"none\"}");
    usleep(300000);
    st = get("/status");
    CHECK(st && strstr(st, "\"languages\":{\"en\":1,\"de\":1}"));
    CHECK(st && strstr(st, "\"sessions\":1,"));
    free(st);
    /* a native kiosk drawing through the closing: its last frame carries the card */
    char clog[300], cout[300], url[64], cache[300], shot[300], tok[300];
    snprintf(clog, sizeof clog, "%s/client.log", kf_dir);
    snprintf(cout, sizeof cout, "%s/client.out", kf_dir);
    snprintf(url, sizeof url, "ws://127.0.0.1:%d", kf_port);
    snprintf(cache, sizeof cache, "%s/cache", kf_dir);
    snprintf(shot, sizeof shot, "%s/closed.png", kf_dir);
    snprintf(tok, sizeof tok, "%s/token", kf_dir);
    FILE *tf = fopen(tok, "w");
    if (tf) {
        fputs(KIOSK_TOKEN "\n", tf);
        fclose(tf);
    }
    char *cargv[] = { GALE_CLIENT_EXE, "--url", url, "--role", "kiosk", "--token-file", tok,
                      "--headless", "--frames", "300", "--max-fps", "20", "--size", "640x360",
                      "--wait", "60", "--cache", cache, "--screenshot", shot, NULL };
    pid_t cl = kf_spawn(cargv, clog, cout);
    /* the closing: told, the tick holds, the connections stay */
    m = next_text(&k, "\"open\":false", 20);
    CHECK(m != NULL);
    free(m);
    /* the tick in flight when the message went out ends (a sanitizer's tick on a loaded
       machine takes a while), then none follows */
    unsigned t2 = tick_now();
    for (int i = 0; i < 50; i++) {
        usleep(200000);
        const unsigned t = tick_now();
        if (t == t2) {
            break;
        }
        t2 = t;
    }
    usleep(1000000);
    CHECK(tick_now() == t2);
    /* the client saw open then closed, and drew the card */
    CHECK(proc_wait_exit(cl, 90.0) == 0);
    char card[80];
    snprintf(card, sizeof card, "gale-client: exhibit closed, opens at %s", o);
    CHECK(proc_log_count(clog, "gale-client: exhibit open until") >= 1);
    CHECK(proc_log_count(clog, card) == 1);
    snprintf(card, sizeof card, "hud: Closed \xE2\x80\x94 opens at %.5s", o);
    CHECK(proc_log_count(cout, card) >= 1);
    if (proc_log_count(cout, card) < 1) {
        proc_dump(clog);
        proc_dump(cout);
    }
    st = get("/status"); /* the client gone, the two raw connections stay while closed */
    CHECK(st && strstr(st, "\"state\":\"closed\"") && strstr(st, "\"total\":2"));
    free(st);
    /* refusals */
    wsraw_text(&v, "{\"type\":\"kiosk_state\",\"token\":\"x\",\"lang\":\"en\",\"audio\":\"none\"}");
    CHECK(wsraw_wait_close(&v, 3000) == 4006);
    CHECK_STR_HAS(v.close_reason, "kiosk_state: only a kiosk reports its state");
    wsraw_text(&k, "{\"type\":\"kiosk_state\",\"token\":\"" KIOSK_TOKEN "\",\"lang\":\"e n\","
                   "\"audio\":\"none\"}");
    CHECK(wsraw_wait_close(&k, 3000) == 4002);
    CHECK_STR_HAS(k.close_reason, "kiosk_state.lang: expected a language tag");
    wsraw_close(&k);
    wsraw_close(&v);
    usleep(2500000); /* --kiosk-idle 2: the session ends */
    usage_rows(rows_before, sizeof rows_before);
    usage_json(usage_before, sizeof usage_before);
    CHECK(strstr(usage_before, "\"session_under_way\":false") != NULL);
    kf_stop_server();
}

static void test_restart(void)
{
    const char *extra[] = { "--state-file", state, NULL };
    CHECK(kf_start_server(NULL, extra) == 0);
    char rows[4096], usage[2048];
    usage_rows(rows, sizeof rows);
    usage_json(usage, sizeof usage);
    CHECK(rows[0] && !strcmp(rows, rows_before));
    CHECK(!strcmp(usage, usage_before));
    if (strcmp(rows, rows_before)) {
        fprintf(stderr, "  before:\n%s  after:\n%s", rows_before, rows);
    }
    CHECK(strstr(rows, "gale_usage_sessions_total 1\n") != NULL);
    kf_stop_server();
}

static void test_corrupt(void)
{
    FILE *f = fopen(state, "w");
    static const char bad[] = "{\"format\":\"gale-usage\",\"version\":1,\"sessions\":\"many\"}\n";
    if (f) {
        fputs(bad, f);
        fclose(f);
    }
    char log[300];
    snprintf(log, sizeof log, "%s/corrupt.log", kf_dir);
    const char *argv[] = { GALE_SERVER_EXE, "--config", GALE_SOURCE_DIR "/tests/data/clientnet_scene.json",
                           "--port", "0", "--state-file", state, NULL };
    pid_t p = kf_spawn((char *const *)argv, log, NULL);
    CHECK(proc_wait_exit(p, 120) == 1);
    CHECK(proc_log_count(log, "usage.json") >= 1);
    CHECK(proc_log_count(log, "sessions") >= 1);
    CHECK(proc_log_count(log, "left as it is") == 1);
    proc_dump(log);
    f = fopen(state, "r");
    char back[256] = "";
    if (f) {
        size_t n = fread(back, 1, sizeof back - 1, f);
        back[n] = 0;
        fclose(f);
    }
    CHECK(!strcmp(back, bad));
}

int main(void)
{
    kf_init("test_server_ops");
    RUN(test_closed_then_open);
    RUN(test_restart);
    RUN(test_corrupt);
    kf_stop_server();
    return check_report();
}
