/* gale-client --fall-shots against the real gale-server on a loopback port
 * (tests/data/fall_scene.json: two pines in calm): once the client draws, gale-ctl dials
 * 50 m/s, a pine uproots, and the headless client frames its fall and writes a PNG at each
 * chosen time after the stem gave way, named by the age its frame had; the picture changes
 * as the tree goes down. Bad times are refused before connecting. */
#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <stb_image.h>

#include "check.h"
#include "proc_fixture.h"
#include "mono.h"

#if !defined(GALE_SERVER_EXE) || !defined(GALE_CLIENT_EXE) || !defined(GALE_CTL_EXE)
#error "GALE_SERVER_EXE, GALE_CLIENT_EXE and GALE_CTL_EXE must be defined by the build"
#endif

static char tmp[256];
static int port;

/* The first line of log containing needle into line (cap bytes); false if none. */
static bool log_line(const char *log, const char *needle, int nth, char *line, size_t cap)
{
    FILE *f = fopen(log, "r");
    if (!f) {
        return false;
    }
    int n = 0;
    while (fgets(line, (int)cap, f)) {
        if (strstr(line, needle) && n++ == nth) {
            fclose(f);
            return true;
        }
    }
    fclose(f);
    return false;
}

static bool wait_log(const char *log, const char *needle, double timeout_s)
{
    char line[1024];
    double until = mono_s() + timeout_s;
    while (mono_s() < until) {
        if (log_line(log, needle, 0, line, sizeof line)) {
            return true;
        }
        usleep(100000);
    }
    return false;
}

/* The path and age of fall shot k from the client's log ("fall shot PATH (A s after"). */
static bool shot(const char *log, int k, char *path, size_t cap, double *age_s)
{
    char line[1024];
    if (!log_line(log, "fall shot ", k, line, sizeof line)) {
        return false;
    }
    const char *p = strstr(line, "fall shot ") + 10, *e = strstr(p, " (");
    if (!e || (size_t)(e - p) >= cap) {
        return false;
    }
    memcpy(path, p, (size_t)(e - p));
    path[e - p] = '\0';
    *age_s = atof(e + 2);
    return true;
}

static void test_bad_times(void)
{
    char log[300];
    snprintf(log, sizeof log, "%s/bad.log", tmp);
    char *argv[] = { GALE_CLIENT_EXE, "--url", "ws://127.0.0.1:1", "--headless", "--fall-shots",
                     "2,1", NULL };
    CHECK(proc_wait_exit(proc_spawn(argv, log), 20.0) == 2);
    char line[1024];
    CHECK(log_line(log, "--fall-shots: expected 1..8 ascending seconds", 0, line, sizeof line));
}

static void test_fall_live(void)
{
    char slog[300], clog[300], cache[300], ccache[300], url[64], png[300];
    snprintf(slog, sizeof slog, "%s/server.log", tmp);
    snprintf(clog, sizeof clog, "%s/client.log", tmp);
    snprintf(cache, sizeof cache, "%s/srvcache", tmp);
    snprintf(ccache, sizeof ccache, "%s/clicache", tmp);
    snprintf(png, sizeof png, "%s/live.png", tmp);
    char *sargv[] = { GALE_SERVER_EXE, "--config", GALE_SOURCE_DIR "/tests/data/fall_scene.json",
                      "--port", "0", "--cache", cache, NULL };
    pid_t server = proc_spawn(sargv, slog);
    char line[1024];
    CHECK(wait_log(slog, "listening on port ", 120.0));
    if (log_line(slog, "listening on port ", 0, line, sizeof line)) {
        port = atoi(strstr(line, "listening on port ") + 18);
    }
    CHECK(port > 0);
    snprintf(url, sizeof url, "ws://127.0.0.1:%d", port);
    char *cargv[] = { GALE_CLIENT_EXE, "--url", url, "--headless", "--size", "320x180",
                      "--storm-fx", "off", "--frames", "20000", "--wait", "60", "--cache", ccache,
                      "--fall-shots", "0.3,2,6", "--screenshot", png, NULL };
    pid_t client = proc_spawn(cargv, clog);
    CHECK(wait_log(clog, "receiving state", 90.0));
    sleep(2); /* frames drawn in calm */
    char ctl_log[300];
    snprintf(ctl_log, sizeof ctl_log, "%s/ctl.log", tmp);
    char *targv[] = { GALE_CTL_EXE, "--url", url, "--token", "test-token", "wind", "--speed",
                      "50", NULL };
    CHECK(proc_wait_exit(proc_spawn(targv, ctl_log), 30.0) == 0);
    const int rc = proc_wait_exit(client, 120.0);
    CHECK(rc == 0);
    CHECK(log_line(clog, "fall caught live: tree ", 0, line, sizeof line));
    if (rc != 0 || !strstr(line, "uprooted")) {
        proc_dump(clog);
    }
    /* three shots, each at or after its time, the frames' ages ascending */
    const double want[3] = { 0.3, 2.0, 6.0 };
    unsigned char *img[3] = { NULL, NULL, NULL };
    int w = 0, h = 0;
    for (int k = 0; k < 3; k++) {
        char path[300];
        double age = -1.0;
        CHECK(shot(clog, k, path, sizeof path, &age));
        CHECK(age >= want[k] && age < want[k] + 3.0);
        int c;
        img[k] = stbi_load(path, &w, &h, &c, 3);
        CHECK(img[k] != NULL && w == 320 && h == 180);
        fprintf(stderr, "shot %d: %s at %.2f s\n", k, path, age);
    }
    /* the tree goes down between the first and the last: a good part of the view changes */
    int changed = 0;
    for (int i = 0; img[0] && img[2] && i < w * h; i++) {
        int d = 0;
        for (int k = 0; k < 3; k++) {
            d += abs(img[0][3 * i + k] - img[2][3 * i + k]);
        }
        changed += d > 60;
    }
    fprintf(stderr, "first to last shot: %d of %d px changed\n", changed, w * h);
    CHECK(changed > w * h / 20);
    for (int k = 0; k < 3; k++) {
        stbi_image_free(img[k]);
    }
    kill(server, SIGTERM);
    proc_wait_exit(server, 20.0);
}

int main(void)
{
    if (!getenv("DISPLAY")) {
        fprintf(stderr, "test_fall_shots_live: no DISPLAY (run under xvfb-run); skipped\n");
        return 77;
    }
    snprintf(tmp, sizeof tmp, "%s/fall_shots_live_%ld", GALE_TEST_DIR, (long)getpid());
    mkdir(tmp, 0755);
    RUN(test_bad_times);
    RUN(test_fall_live);
    return check_report();
}
