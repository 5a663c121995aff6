/* A client that draws a frame a second (gale-client --headless --max-fps 1, as a software
 * renderer on a modest kiosk) against the real gale-server on a loopback port, with a
 * stream of 300 trees × 16 modes (tests/data/slow_client_scene.json, 30 snapshots a
 * second): its network thread takes the snapshots as they come, so it stays on
 * its one connection, the server never closes it, it decodes most of the snapshots
 * published (a client that read only between its frames would be sent one a second or
 * so: server/SERVER.md "Slow readers"; the server may still lower its rate a while when
 * the machine starves the thread of CPU), and every frame decodes (no gap). */
#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "check.h"
#include "mono.h"
#include "proc_fixture.h"
#include "server_wsraw.h"

#ifndef GALE_SERVER_EXE
#error "GALE_SERVER_EXE (path of gale-server) must be defined by the build"
#endif
#ifndef GALE_CLIENT_EXE
#error "GALE_CLIENT_EXE (path of gale-client) must be defined by the build"
#endif

#define FRAMES 12

static char tmp[256];

/* A /metrics row's value, -1 when absent. */
static double metric(int port, const char *name)
{
    char *body = NULL;
    double v = -1;
    if (wsraw_http_get(port, "/metrics", &body) == 200 && body) {
        char key[96];
        snprintf(key, sizeof key, "\n%s ", name);
        const char *at = strstr(body, key);
        v = at ? atof(at + strlen(key)) : -1;
    }
    free(body);
    return v;
}

/* The whole of a log file (NUL-terminated into buf). */
static void read_log(const char *path, char *buf, size_t cap)
{
    buf[0] = 0;
    FILE *f = fopen(path, "r");
    if (f) {
        buf[fread(buf, 1, cap - 1, f)] = 0;
        fclose(f);
    }
}

static void test_one_frame_a_second(void)
{
    char slog[300], clog[300], cache[300], ccache[300], png[300];
    snprintf(slog, sizeof slog, "%s/server.log", tmp);
    snprintf(clog, sizeof clog, "%s/client.log", tmp);
    snprintf(cache, sizeof cache, "%s/srvcache", tmp);
    snprintf(ccache, sizeof ccache, "%s/clicache", tmp);
    snprintf(png, sizeof png, "%s/slow.png", tmp);
    char *sargv[] = { GALE_SERVER_EXE, "--config",
                      GALE_SOURCE_DIR "/tests/data/slow_client_scene.json",
                      "--port", "0", "--iface", "127.0.0.1", "--cache", cache, NULL };
    pid_t server = proc_spawn(sargv, slog);
    CHECK(proc_wait_log(slog, "listening on port", 1, 120.0));
    char log[16384];
    read_log(slog, log, sizeof log);
    const char *p = strstr(log, "listening on port ");
    const int port = p ? atoi(p + 18) : 0;
    CHECK(port > 0);
    if (port <= 0) {
        proc_dump(slog);
        kill(server, SIGTERM);
        proc_wait_exit(server, 30.0);
        return;
    }
    char url[64], frames[16];
    snprintf(url, sizeof url, "ws://127.0.0.1:%d", port);
    snprintf(frames, sizeof frames, "%d", FRAMES);
    char *cargv[] = { GALE_CLIENT_EXE, "--url", url, "--headless", "--max-fps", "1",
                      "--frames", frames, "--size", "320x180", "--wait", "150",
                      "--cache", ccache, "--screenshot", png, NULL };
    pid_t client = proc_spawn(cargv, clog);
    CHECK(proc_wait_log(clog, "receiving state", 1, 200.0));
    const double t0 = mono_s();
    /* llvmpipe under a sanitizer on a busy machine: 10 s a frame and more */
    int st = proc_wait_exit(client, 600.0);
    const double drew_s = mono_s() - t0;
    const double conns = metric(port, "gale_connections_total");
    const double decim = metric(port, "gale_decimations_total");
    const double snaps = metric(port, "gale_snapshots_total");
    const double closed = metric(port, "gale_laggards_closed_total");
    const double bytes = metric(port, "gale_bytes_sent_total");
    read_log(clog, log, sizeof log);
    const char *ok = strstr(log, "frames ok ");
    const double got = ok ? atof(ok + 10) : 0;
    fprintf(stderr,
            "  %d frames drawn in %.1f s; %.0f of the server's %.0f snapshots decoded; server: "
            "%.0f connections, %.0f decimations, %.0f closed as slow, %.0f bytes sent\n",
            FRAMES, drew_s, got, snaps, conns, decim, closed, bytes);
    CHECK(st == 0);
    CHECK(drew_s >= FRAMES - 2.0); /* paced: about a frame a second, or slower */
    CHECK(conns == 1);
    CHECK(closed == 0);
    /* The stream is no trickle: a reader lowered to the 1 Hz floor would decode about one
     * snapshot a drawn frame. Counted against what the server published, not against the
     * clock or the bytes: a starved server publishes fewer, and deltas of a calm moment
     * are a fraction of a keyframe. */
    CHECK(got >= 0.7 * snaps);
    CHECK(got >= 3.0 * FRAMES);
    CHECK_STR_HAS(log, "bad 0, gaps 0");
    CHECK_STR_HAS(log, "connects 1");
    CHECK_STR_HAS(log, "hud: Wind ");
    if (st != 0 || conns != 1) {
        proc_dump(clog);
        proc_dump(slog);
    }
    kill(server, SIGTERM);
    CHECK(proc_wait_exit(server, 30.0) == 0);
}

int main(void)
{
    if (!getenv("DISPLAY")) {
        if (getenv("CI")) {
            fprintf(stderr, "test_client_slow: CI is set but there is no DISPLAY (run under "
                            "xvfb-run)\n");
            return 1;
        }
        fprintf(stderr, "test_client_slow: no DISPLAY (run under xvfb-run); skipped\n");
        return 77;
    }
    snprintf(tmp, sizeof tmp, "%s/client_slow_%ld", GALE_TEST_DIR, (long)getpid());
    mkdir(tmp, 0755);
    signal(SIGPIPE, SIG_IGN);
    RUN(test_one_frame_a_second);
    return check_report();
}
