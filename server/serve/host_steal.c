/* The host's steal time from /proc/stat: see host_steal.h. */
#include "host_steal.h"

#include <fcntl.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int host_steal_parse(const char *text, size_t len, long ticks_per_s, double *ms)
{
    if (len < 4 || memcmp(text, "cpu ", 4) != 0 || ticks_per_s <= 0) {
        return -1;
    }
    /* the line alone, terminated, so strtoull stops at its end */
    char line[512];
    const char *nl = memchr(text, '\n', len);
    const size_t n = nl ? (size_t)(nl - text) : len;
    if (n >= sizeof line) {
        return -1;
    }
    memcpy(line, text, n);
    line[n] = '\0';
    const char *p = line + 3;
    unsigned long long v = 0;
    for (int field = 0; field < 8; field++) { /* steal is the eighth */
        char *end;
        while (*p == ' ') {
            p++;
        }
        if (*p < '0' || *p > '9') {
            return -1;
        }
        v = strtoull(p, &end, 10);
        p = end;
    }
    *ms = (double)v * 1e3 / (double)ticks_per_s;
    return 0;
}

/* The steal from the descriptor fd of /proc/stat, read from its start. */
static int read_fd(int fd, double *ms)
{
    char buf[512];
    const ssize_t n = pread(fd, buf, sizeof buf, 0);
    return n > 0 ? host_steal_parse(buf, (size_t)n, sysconf(_SC_CLK_TCK), ms) : -1;
}

int host_steal_read(double *ms)
{
    const int fd = open("/proc/stat", O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
        return -1;
    }
    const int rc = read_fd(fd, ms);
    close(fd);
    return rc;
}

int host_steal_open(host_steal_window *w, double now_s)
{
    *w = (host_steal_window){ .fd = open("/proc/stat", O_RDONLY | O_CLOEXEC),
                              .ms = { -1.0, -1.0 }, .at_s = { now_s, now_s } };
    double ms;
    if (w->fd < 0 || read_fd(w->fd, &ms) != 0) {
        host_steal_close(w);
        return -1;
    }
    w->ms[0] = w->ms[1] = ms;
    return 0;
}

void host_steal_close(host_steal_window *w)
{
    if (w->fd >= 0) {
        close(w->fd);
    }
    w->fd = -1;
}

void host_steal_advance(host_steal_window *w, double now_s)
{
    if (w->fd < 0 || now_s - w->at_s[1] < 1.0) {
        return;
    }
    double ms;
    const bool ok = read_fd(w->fd, &ms) == 0;
    w->ms[0] = ok ? w->ms[1] : -1.0;
    w->at_s[0] = w->at_s[1];
    w->ms[1] = ok ? ms : -1.0;
    w->at_s[1] = now_s;
}

int host_steal_recent(const host_steal_window *w, double now_s, double *ms, double *span_s)
{
    double now_ms;
    if (w->fd < 0 || w->ms[0] < 0.0 || read_fd(w->fd, &now_ms) != 0) {
        return -1;
    }
    *ms = now_ms - w->ms[0];
    *span_s = now_s - w->at_s[0];
    return 0;
}
