/* The host's steal time from /proc/stat: see host_steal.h. */
#include "host_steal.h"

#include <stdbool.h>
#include <stdio.h>
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

int host_steal_read(double *ms)
{
    FILE *f = fopen("/proc/stat", "r");
    if (!f) {
        return -1;
    }
    char buf[512];
    const size_t n = fread(buf, 1, sizeof buf, f);
    fclose(f);
    return host_steal_parse(buf, n, sysconf(_SC_CLK_TCK), ms);
}

int host_steal_start(host_steal_window *w, double now_s)
{
    double ms;
    const int rc = host_steal_read(&ms);
    *w = (host_steal_window){ .ms = { rc ? -1.0 : ms, rc ? -1.0 : ms },
                              .at_s = { now_s, now_s } };
    return rc;
}

void host_steal_advance(host_steal_window *w, double now_s)
{
    if (w->ms[1] < 0.0 || now_s - w->at_s[1] < 1.0) {
        return;
    }
    double ms;
    const bool ok = host_steal_read(&ms) == 0;
    w->ms[0] = ok ? w->ms[1] : -1.0;
    w->at_s[0] = w->at_s[1];
    w->ms[1] = ok ? ms : -1.0;
    w->at_s[1] = now_s;
}

int host_steal_recent(const host_steal_window *w, double now_s, double *ms, double *span_s)
{
    double now_ms;
    if (w->ms[0] < 0.0 || host_steal_read(&now_ms) != 0) {
        return -1;
    }
    *ms = now_ms - w->ms[0];
    *span_s = now_s - w->at_s[0];
    return 0;
}
