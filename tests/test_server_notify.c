/* gale-server under systemd's notify protocol, with the socket played here (server/SERVER.md
 * "Debian service"): READY=1 with a STATUS once it listens, WATCHDOG=1 from the sim tick
 * several times per WATCHDOG_USEC, no pings while the process is stopped (SIGSTOP: what
 * makes systemd's watchdog restart it), pings again after SIGCONT, STOPPING=1 on SIGTERM. */
#include "check.h"
#include "mono.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

static int sock;

/* Counts datagrams containing what within secs; stops early at the first when stop_first. */
static int count(const char *what, double secs, bool stop_first, char *last, size_t cap)
{
    int n = 0;
    double until = mono_s() + secs;
    while (mono_s() < until) {
        struct pollfd p = { .fd = sock, .events = POLLIN };
        if (poll(&p, 1, 50) <= 0) {
            continue;
        }
        char b[512];
        ssize_t k = recv(sock, b, sizeof b - 1, 0);
        if (k <= 0) {
            continue;
        }
        b[k] = 0;
        if (strstr(b, what)) {
            n++;
            if (last) {
                snprintf(last, cap, "%s", b);
            }
            if (stop_first) {
                break;
            }
        }
    }
    return n;
}

int main(void)
{
    FILE *f = fopen("notify_scene.json", "w");
    if (f) {
        fprintf(f,
                "{\"name\": \"notify\", \"species\": [{\"name\": \"palm\", \"file\": "
                "\"%s/configs/species/palm.json\", \"modes\": 8}],"
                " \"forest\": [{\"species\": \"palm\", \"count\": 4, \"area_min\": [-20, -20],"
                " \"area_max\": [20, 20], \"min_spacing_m\": 3}],"
                " \"wind\": {\"solver\": false, \"u10_ms\": 12}}",
                GALE_SOURCE_DIR);
        fclose(f);
    }
    char path[108];
    snprintf(path, sizeof path, "%s/notify.sock", getcwd((char[256]){ 0 }, 256));
    unlink(path);
    sock = socket(AF_UNIX, SOCK_DGRAM, 0);
    struct sockaddr_un a = { .sun_family = AF_UNIX };
    snprintf(a.sun_path, sizeof a.sun_path, "%s", path);
    CHECK(sock >= 0 && bind(sock, (struct sockaddr *)&a, sizeof a) == 0);
    pid_t pid = fork();
    if (pid == 0) {
        setenv("NOTIFY_SOCKET", path, 1);
        setenv("WATCHDOG_USEC", "400000", 1);
        unsetenv("WATCHDOG_PID");
        int lf = open("notify_server.log", O_WRONLY | O_CREAT | O_TRUNC, 0644);
        dup2(lf, 1);
        dup2(lf, 2);
        execl(GALE_SERVER_EXE, GALE_SERVER_EXE, "--config", "notify_scene.json", "--port", "0",
              "--cache", "notify_cache", (char *)NULL);
        _exit(127);
    }
    char st[512] = "";
    CHECK(count("READY=1", 90, true, st, sizeof st) == 1); /* the first run bakes */
    CHECK(strstr(st, "STATUS=scene notify, 4 trees, port ") != NULL);
    int pings = count("WATCHDOG=1", 1.0, false, NULL, 0);
    fprintf(stderr, "  %d watchdog pings in 1 s (interval 0.4 s)\n", pings);
    CHECK(pings >= 6 && pings <= 12);
    kill(pid, SIGSTOP);
    count("WATCHDOG=1", 0.1, false, NULL, 0); /* what was in flight */
    int stopped = count("WATCHDOG=1", 1.0, false, NULL, 0);
    CHECK(stopped == 0);
    kill(pid, SIGCONT);
    CHECK(count("WATCHDOG=1", 1.0, false, NULL, 0) >= 4);
    kill(pid, SIGTERM);
    CHECK(count("STOPPING=1", 5, true, NULL, 0) == 1);
    int status = -1;
    waitpid(pid, &status, 0);
    CHECK(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    close(sock);
    unlink(path);
    return check_report();
}
