/* The real gale-server process: a bad config is refused with its key path; a good one
 * serves a connected client, and SIGTERM tells that client (close 1001), closes the
 * sockets and exits 0. Small scene (palm, 12 trees, no wind grid), assets cached in the
 * build tree. */
#include "check.h"
#include "server_wsraw.h"
#include "wire.h"

#include <signal.h>
#include <sys/wait.h>
#include <time.h>

static const char *cfg_path = "sigterm_scene.json";

static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (f) {
        fputs(text, f);
        fclose(f);
    }
}

/* Starts gale-server with args; *out_fd reads its stdout. Returns the pid. */
static pid_t spawn(const char *const *args, int *out_fd, int *err_fd)
{
    int po[2], pe[2];
    if (pipe(po) || pipe(pe)) {
        return -1;
    }
    pid_t pid = fork();
    if (pid == 0) {
        dup2(po[1], 1);
        dup2(pe[1], 2);
        close(po[0]);
        close(pe[0]);
        execv(GALE_SERVER_EXE, (char *const *)args);
        _exit(127);
    }
    close(po[1]);
    close(pe[1]);
    *out_fd = po[0];
    *err_fd = pe[0];
    return pid;
}

static int wait_exit(pid_t pid, double timeout_s)
{
    for (int i = 0; i < (int)(timeout_s * 100); i++) {
        int st;
        if (waitpid(pid, &st, WNOHANG) == pid) {
            return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
        }
        usleep(10000);
    }
    kill(pid, SIGKILL);
    waitpid(pid, NULL, 0);
    return -1;
}

static size_t read_some(int fd, char *buf, size_t cap, int timeout_ms)
{
    size_t n = 0;
    struct pollfd p = { .fd = fd, .events = POLLIN };
    while (n + 1 < cap && poll(&p, 1, timeout_ms) > 0) {
        ssize_t k = read(fd, buf + n, cap - 1 - n);
        if (k <= 0) {
            break;
        }
        n += (size_t)k;
        buf[n] = 0;
        if (strchr(buf, '\n')) {
            break;
        }
    }
    buf[n] = 0;
    return n;
}

static void test_bad_config(void)
{
    write_file("bad_scene.json", "{\"species\": [{\"name\": \"palm\", \"file\": \"x.json\"}],\n"
                                 " \"trees\": [{\"species\": \"palm\", \"pos\": [0, 0], \"scale\": 99}]}");
    const char *args[] = { GALE_SERVER_EXE, "--config", "bad_scene.json", NULL };
    int o, e;
    pid_t pid = spawn(args, &o, &e);
    char buf[1024];
    read_some(e, buf, sizeof buf, 5000);
    CHECK(wait_exit(pid, 10) == 1);
    CHECK_STR_HAS(buf, "bad config: bad_scene.json: trees[0].scale: expected a number in [0.05, 20], got 99");
    close(o);
    close(e);
}

static void test_sigterm(void)
{
    char cfg[1024];
    snprintf(cfg, sizeof cfg,
             "{\"name\": \"sigterm\", \"species\": [{\"name\": \"palm\", \"file\": \"%s/configs/species/palm.json\", \"modes\": 8}],"
             " \"forest\": [{\"species\": \"palm\", \"count\": 12, \"area_min\": [-20, -20],"
             " \"area_max\": [20, 20], \"min_spacing_m\": 3}],"
             " \"wind\": {\"solver\": false, \"u10_ms\": 12}}",
             GALE_SOURCE_DIR);
    write_file(cfg_path, cfg);
    const char *args[] = { GALE_SERVER_EXE, "--config", cfg_path, "--port", "0", "--iface",
                           "127.0.0.1", "--cache", "sigterm_cache", NULL };
    int o, e;
    pid_t pid = spawn(args, &o, &e);
    char line[256];
    read_some(o, line, sizeof line, 60000); /* the first run bakes the palm */
    int port = 0;
    CHECK(sscanf(line, "gale-server: listening on port %d", &port) == 1);
    if (port <= 0) {
        kill(pid, SIGKILL);
        waitpid(pid, NULL, 0);
        return;
    }
    wsraw c;
    CHECK(wsraw_open(&c, port, 0) == 0);
    char h[128];
    snprintf(h, sizeof h, "{\"type\": \"hello\", \"protocol\": %d, \"role\": \"viewer\"}",
             WIRE_PROTOCOL_VERSION);
    wsraw_text(&c, h);
    int state = 0;
    for (int i = 0; i < 20 && state < 5; i++) {
        uint8_t *b;
        size_t n;
        int op = wsraw_recv(&c, &b, &n, 3000);
        free(b);
        state += op == 2;
    }
    CHECK(state >= 5);
    CHECK(kill(pid, SIGTERM) == 0);
    CHECK(wsraw_wait_close(&c, 5000) == WIRE_CLOSE_GOING_AWAY);
    CHECK_STR_HAS(c.close_reason, "shutting down");
    CHECK(wait_exit(pid, 10) == 0);
    /* the socket is closed: a new connection is refused */
    CHECK(wsraw_tcp(port, 0) < 0);
    char err[4096];
    read_some(e, err, sizeof err, 100);
    wsraw_close(&c);
    close(o);
    close(e);
}

int main(void)
{
    signal(SIGPIPE, SIG_IGN);
    RUN(test_bad_config);
    RUN(test_sigterm);
    return check_report();
}
