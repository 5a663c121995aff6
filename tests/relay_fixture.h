/* Test helper: a real nats-server, gale-server --nats and gale-relays as child processes
 * on loopback (server/SERVER.md "Relays"), each on a port of its own; the including test
 * defines GALE_SERVER_EXE, GALE_RELAY_EXE and NATS_SERVER_EXE and sets fx_prefix, which
 * names its files in the build tree. */
#ifndef GALE_TEST_RELAY_FIXTURE_H
#define GALE_TEST_RELAY_FIXTURE_H

#include <errno.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include "server_wsraw.h"

typedef struct proc {
    pid_t pid;
    int port;
} proc;

static char nats_url[64];
static int nats_port;
/* Names the files of one test: <prefix>_scene.json, _token, _cache, and the logs. */
static const char *fx_prefix = "relay";

static int free_port(void)
{
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    struct sockaddr_in a = { .sin_family = AF_INET, .sin_addr.s_addr = htonl(INADDR_LOOPBACK) };
    socklen_t n = sizeof a;
    int port = -1;
    if (fd >= 0 && bind(fd, (struct sockaddr *)&a, sizeof a) == 0 &&
        getsockname(fd, (struct sockaddr *)&a, &n) == 0) {
        port = ntohs(a.sin_port);
    }
    if (fd >= 0) {
        close(fd);
    }
    return port;
}

/* Runs argv (NULL ended), stderr to log; when want_line is set, waits for a stdout line
 * "<want_line> %d" and stores the port. 0 ok. */
static int spawn(proc *p, const char *const *argv, const char *log, const char *want_line)
{
    int po[2];
    if (pipe(po)) {
        return -1;
    }
    p->pid = fork();
    if (p->pid == 0) {
        int lf = open(log, O_WRONLY | O_CREAT | O_APPEND, 0644);
        dup2(po[1], 1);
        dup2(lf, 2);
        if (!want_line) {
            dup2(lf, 1);
        }
        close(po[0]);
        close(po[1]);
        close(lf);
        execv(argv[0], (char *const *)argv);
        _exit(127);
    }
    close(po[1]);
    if (!want_line) {
        close(po[0]);
        return 0;
    }
    char line[256];
    size_t got = 0;
    struct pollfd pf = { .fd = po[0], .events = POLLIN };
    while (got + 1 < sizeof line && !memchr(line, '\n', got) && poll(&pf, 1, 90000) > 0) {
        ssize_t k = read(po[0], line + got, sizeof line - 1 - got); /* the first run bakes */
        if (k <= 0) {
            break;
        }
        got += (size_t)k;
    }
    line[got] = 0;
    close(po[0]);
    size_t wl = strlen(want_line);
    p->port = !strncmp(line, want_line, wl) ? atoi(line + wl) : 0;
    if (p->port <= 0) {
        fprintf(stderr, "  %s did not start: \"%s\" (log %s)\n", argv[0], line, log);
        kill(p->pid, SIGKILL);
        waitpid(p->pid, NULL, 0);
        p->pid = 0;
        return -1;
    }
    return 0;
}

static void end(proc *p, int sig)
{
    if (p->pid > 0) {
        kill(p->pid, sig);
        waitpid(p->pid, NULL, 0);
        p->pid = 0;
    }
}

static int start_nats(proc *p)
{
    char port[16];
    snprintf(port, sizeof port, "%d", nats_port);
    const char *argv[] = { NATS_SERVER_EXE, "-a", "127.0.0.1", "-p", port, NULL };
    char log[96];
    snprintf(log, sizeof log, "%s_nats.log", fx_prefix);
    if (spawn(p, argv, log, NULL)) {
        return -1;
    }
    for (int i = 0; i < 750; i++) { /* until it accepts: up to 15 s on a loaded machine */
        int fd = wsraw_tcp(nats_port, 0);
        if (fd >= 0) {
            close(fd);
            return 0;
        }
        if (waitpid(p->pid, NULL, WNOHANG) == p->pid) {
            p->pid = 0; /* it exited: the port was taken between free_port and its bind */
            return -1;
        }
        usleep(20000);
    }
    end(p, SIGKILL);
    return -1;
}

/* nats-server on a free port; a port another test took first gets a second try. */
static int start_nats_fresh(proc *p)
{
    for (int attempt = 0; attempt < 3; attempt++) {
        nats_port = free_port();
        if (start_nats(p) == 0) {
            return 0;
        }
    }
    return -1;
}

/* gale-server on <prefix>_scene.json, publishing on nats_url. */
static int start_server(proc *p)
{
    char scene[96], cache[96], token[96], log[96];
    snprintf(scene, sizeof scene, "%s_scene.json", fx_prefix);
    snprintf(cache, sizeof cache, "%s_cache", fx_prefix);
    snprintf(token, sizeof token, "%s_token", fx_prefix);
    snprintf(log, sizeof log, "%s_server.log", fx_prefix);
    const char *argv[] = { GALE_SERVER_EXE, "--config", scene, "--port", "0", "--cache", cache,
                           "--kiosk-token-file", token, "--nats", nats_url, NULL };
    return spawn(p, argv, log, "gale-server: listening on port");
}

static int start_relay(proc *p)
{
    char log[96];
    snprintf(log, sizeof log, "%s_relay.log", fx_prefix);
    const char *argv[] = { GALE_RELAY_EXE, "--nats", nats_url, "--port", "0", NULL };
    return spawn(p, argv, log, "gale-relay: listening on port");
}

#endif
