/* gale-client against the real gale-server on a loopback port (tests/data/clientnet_scene.json):
 * a headless client receives state and writes a PNG; no server means exit status 3; a client
 * killed mid-stream leaves the server serving others; a server restarted mid-stream is
 * reconnected to and the stream resumes from its next keyframe. */
#include <errno.h>
#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <stb_image.h>

#include "mono.h"
#include "check.h"

#ifndef GALE_SERVER_EXE
#error "GALE_SERVER_EXE (path of gale-server) must be defined by the build"
#endif
#ifndef GALE_CLIENT_EXE
#error "GALE_CLIENT_EXE (path of gale-client) must be defined by the build"
#endif

static char tmp[256];
static int port;
static pid_t server;

/* Starts argv with stderr (and stdout) into log. */
static pid_t spawn(char *const argv[], const char *log)
{
    pid_t pid = fork();
    if (pid == 0) {
        FILE *f = freopen(log, "w", stderr);
        if (!f || dup2(fileno(stderr), 1) < 0) {
            _exit(126);
        }
        execv(argv[0], argv);
        _exit(127);
    }
    return pid;
}

/* Count of lines of the log file containing needle. */
static int log_count(const char *log, const char *needle)
{
    FILE *f = fopen(log, "r");
    if (!f) {
        return 0;
    }
    char line[1024];
    int n = 0;
    while (fgets(line, sizeof line, f)) {
        n += strstr(line, needle) != NULL;
    }
    fclose(f);
    return n;
}

static bool wait_log(const char *log, const char *needle, int count, double timeout_s)
{
    double until = mono_s() + timeout_s;
    while (mono_s() < until) {
        if (log_count(log, needle) >= count) {
            return true;
        }
        usleep(100000);
    }
    return false;
}

/* Waits for pid; returns its exit status, or -1 on timeout (then kills it). */
static int wait_exit(pid_t pid, double timeout_s)
{
    double until = mono_s() + timeout_s;
    int st;
    while (mono_s() < until) {
        pid_t r = waitpid(pid, &st, WNOHANG);
        if (r == pid) {
            return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
        }
        usleep(50000);
    }
    kill(pid, SIGKILL);
    waitpid(pid, &st, 0);
    return -1;
}

static void dump(const char *log)
{
    char cmd[600];
    snprintf(cmd, sizeof cmd, "tail -n 15 '%s' >&2", log);
    if (system(cmd) != 0) {
        fprintf(stderr, "(no log %s)\n", log);
    }
}

static int start_server(int want_port)
{
    char log[300], ports[16];
    snprintf(log, sizeof log, "%s/server.log", tmp);
    snprintf(ports, sizeof ports, "%d", want_port);
    char cache[300];
    snprintf(cache, sizeof cache, "%s/srvcache", tmp);
    char *argv[] = { GALE_SERVER_EXE,
                     "--config",
                     GALE_SOURCE_DIR "/tests/data/clientnet_scene.json",
                     "--port",
                     ports,
                     "--iface",
                     "127.0.0.1",
                     "--cache",
                     cache,
                     NULL };
    unlink(log);
    server = spawn(argv, log);
    if (!wait_log(log, "listening on port", 1, 120.0)) {
        dump(log);
        return -1;
    }
    FILE *f = fopen(log, "r");
    char line[512];
    while (f && fgets(line, sizeof line, f)) {
        const char *p = strstr(line, "listening on port ");
        if (p) {
            port = atoi(p + 18);
        }
    }
    if (f) {
        fclose(f);
    }
    return port > 0 ? 0 : -1;
}

static pid_t start_client(const char *name, int frames, const char *png)
{
    char log[300], url[64], fr[16], cache[300];
    snprintf(log, sizeof log, "%s/%s.log", tmp, name);
    snprintf(url, sizeof url, "ws://127.0.0.1:%d", port);
    snprintf(fr, sizeof fr, "%d", frames);
    snprintf(cache, sizeof cache, "%s/cache-%s", tmp, name);
    char *argv[] = { GALE_CLIENT_EXE, "--url",     url,      "--headless", "--frames", fr,
                     "--size",        "320x180",   "--wait", "150",        "--cache",  cache,
                     "--screenshot",  (char *)png, NULL };
    return spawn(argv, log);
}

static void client_log(char *buf, size_t cap, const char *name)
{
    snprintf(buf, cap, "%s/%s.log", tmp, name);
}

/* A headless client receives state and writes a PNG that is not one flat colour. */
static void test_headless_png(void)
{
    char png[300], log[300];
    snprintf(png, sizeof png, "%s/a.png", tmp);
    client_log(log, sizeof log, "a");
    pid_t a = start_client("a", 5, png);
    int st = wait_exit(a, 200.0);
    CHECK(st == 0);
    CHECK(log_count(log, "receiving state from tick") >= 1);
    int w = 0, h = 0, ch = 0;
    unsigned char *img = stbi_load(png, &w, &h, &ch, 3);
    CHECK(img != NULL && w == 320 && h == 180);
    if (img) {
        double sum = 0, sum2 = 0;
        for (int i = 0; i < w * h * 3; i++) {
            sum += img[i];
            sum2 += (double)img[i] * img[i];
        }
        double n = (double)w * h * 3, var = sum2 / n - (sum / n) * (sum / n);
        CHECK(var > 100.0); /* sky, ground, trees and the HUD panel */
        stbi_image_free(img);
    }
    if (st != 0) {
        dump(log);
    }
}

/* Nothing listening: the client retries until --wait, then exits 3. */
static void test_no_server(void)
{
    char log[300];
    client_log(log, sizeof log, "none");
    char *argv[] = { GALE_CLIENT_EXE, "--url",  "ws://127.0.0.1:1",
                     "--headless",    "--wait", "2",
                     "--size",        "64x64",  NULL };
    pid_t p = spawn(argv, log);
    int st = wait_exit(p, 120.0);
    CHECK(st == 3);
    CHECK(log_count(log, "no state received") == 1);
    if (st != 3) {
        dump(log);
    }
}

/* A client killed mid-stream: the server keeps serving the other one and new ones. */
static void test_client_killed(void)
{
    char png[300], logk[300], logb[300];
    snprintf(png, sizeof png, "%s/b.png", tmp);
    client_log(logk, sizeof logk, "k");
    client_log(logb, sizeof logb, "b");
    pid_t k = start_client("k", 1000000, png);
    CHECK(wait_log(logk, "receiving state", 1, 200.0));
    kill(k, SIGKILL);
    CHECK(wait_exit(k, 10.0) == 128 + SIGKILL);
    pid_t b = start_client("b", 5, png);
    int st = wait_exit(b, 200.0);
    CHECK(st == 0);
    CHECK(waitpid(server, NULL, WNOHANG) == 0); /* the server lives */
    if (st != 0) {
        dump(logb);
    }
}

/* The server restarts on the same port mid-stream: the client shows the loss, reconnects
 * with backoff, and receives state again from the new server's keyframe. */
static void test_server_restart(void)
{
    char png[300], log[300];
    snprintf(png, sizeof png, "%s/r.png", tmp);
    client_log(log, sizeof log, "r");
    pid_t r = start_client("r", 1000000, png);
    CHECK(wait_log(log, "receiving state", 1, 200.0));
    kill(server, SIGTERM);
    CHECK(wait_exit(server, 30.0) >= 0);
    CHECK(wait_log(log, "connection lost", 1, 30.0));
    sleep(1);
    int old_port = port;
    CHECK(start_server(old_port) == 0);
    CHECK(port == old_port);
    CHECK(wait_log(log, "receiving state", 2, 200.0));
    kill(r, SIGTERM); /* ends its loop: writes the screenshot, exits 0 (it had state) */
    int st = wait_exit(r, 60.0);
    CHECK(st == 0);
    CHECK(log_count(log, "welcome as viewer") >= 2);
    struct stat sb;
    CHECK(stat(png, &sb) == 0 && sb.st_size > 1000);
    if (st != 0 || log_count(log, "receiving state") < 2) {
        dump(log);
    }
}

int main(void)
{
    if (!getenv("DISPLAY")) {
        fprintf(stderr, "test_client_live: no DISPLAY (run under xvfb-run); skipped\n");
        return 77;
    }
    snprintf(tmp, sizeof tmp, "/tmp/gale_client_live_%ld", (long)getpid());
    mkdir(tmp, 0755);
    signal(SIGPIPE, SIG_IGN);
    if (start_server(0) != 0) {
        fprintf(stderr, "gale-server did not start\n");
        return 1;
    }
    RUN(test_no_server);
    RUN(test_headless_png);
    RUN(test_client_killed);
    RUN(test_server_restart);
    if (waitpid(server, NULL, WNOHANG) == 0) {
        kill(server, SIGTERM);
        wait_exit(server, 30.0);
    }
    if (check_failures == 0) {
        char cmd[300];
        snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmp);
        CHECK(system(cmd) == 0);
    }
    return check_report();
}
