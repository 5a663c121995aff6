/* The host's steal time from /proc/stat: see host_steal.h. */
#include "host_steal.h"

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
