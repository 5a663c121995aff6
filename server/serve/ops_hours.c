/* Opening hours: the parser of --hours and the clock arithmetic (ops_hours.h). */
#include "ops_hours.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const day_names[7] = { "sun", "mon", "tue", "wed", "thu", "fri", "sat" };

/* A day name at *p (three letters) into *d, advancing *p; false if none. */
static bool read_day(const char **p, int *d)
{
    for (int i = 0; i < 7; i++) {
        if (!strncmp(*p, day_names[i], 3)) {
            *d = i;
            *p += 3;
            return true;
        }
    }
    return false;
}

/* "HH:MM[:SS]" at *p into seconds since midnight, advancing *p; -1 if malformed. 24:00
 * is the end of the day. */
static int read_clock(const char **p)
{
    const char *s = *p;
    int v[3] = { 0, 0, 0 }, n = 0;
    while (n < 3) {
        if (!(s[0] >= '0' && s[0] <= '9' && s[1] >= '0' && s[1] <= '9')) {
            return -1;
        }
        v[n++] = (s[0] - '0') * 10 + (s[1] - '0');
        s += 2;
        if (*s != ':' || n == 3) {
            break;
        }
        s++;
    }
    if (n < 2 || v[1] > 59 || v[2] > 59 || v[0] > 24 || (v[0] == 24 && (v[1] || v[2]))) {
        return -1;
    }
    *p = s;
    return v[0] * 3600 + v[1] * 60 + v[2];
}

static int fail(gale_err *err, const char *entry, size_t n, const char *what)
{
    return gale_errf(err, GALE_E_PARSE, "hours: \"%.*s\": %s", (int)n, entry, what);
}

/* One entry of n bytes at e. */
static int parse_entry(const char *e, size_t n, ops_hours *h, gale_err *err)
{
    char buf[96];
    if (n >= sizeof buf) {
        return fail(err, e, 40, "expected an entry of at most 95 characters");
    }
    memcpy(buf, e, n);
    buf[n] = 0;
    const char *p = buf;
    bool days[7] = { false };
    bool any_day = false;
    int d0;
    const char *q = p;
    if (read_day(&q, &d0)) {
        p = q;
        for (;;) {
            int d1 = d0;
            if (*p == '-') {
                p++;
                if (!read_day(&p, &d1)) {
                    return fail(err, e, n, "expected a day after '-' (mon tue wed thu fri sat sun)");
                }
            }
            for (int d = d0;; d = (d + 1) % 7) { /* "fri-mon" wraps over the week's end */
                days[d] = true;
                if (d == d1) {
                    break;
                }
            }
            if (*p != ',') {
                break;
            }
            p++;
            if (!read_day(&p, &d0)) {
                return fail(err, e, n, "expected a day after ',' (mon tue wed thu fri sat sun)");
            }
        }
        if (*p != ' ') {
            return fail(err, e, n, "expected a space between the days and the hours");
        }
        while (*p == ' ') {
            p++;
        }
        any_day = true;
    }
    int open_s = -1, close_s = -1;
    if (!strcmp(p, "closed")) {
        /* closed all day */
    } else {
        open_s = read_clock(&p);
        if (open_s < 0 || *p != '-') {
            return fail(err, e, n, "expected HH:MM-HH:MM (seconds optional: HH:MM:SS) or "
                                   "\"closed\"");
        }
        p++;
        close_s = read_clock(&p);
        if (close_s < 0 || *p) {
            return fail(err, e, n, "expected HH:MM-HH:MM (seconds optional: HH:MM:SS) or "
                                   "\"closed\"");
        }
        if (close_s <= open_s) {
            return fail(err, e, n, "expected the closing time after the opening time (a window "
                                   "may not span midnight)");
        }
    }
    for (int d = 0; d < 7; d++) {
        if (days[d] || !any_day) {
            h->open_s[d] = open_s;
            h->close_s[d] = close_s;
        }
    }
    return 0;
}

int ops_hours_parse(const char *spec, ops_hours *h, gale_err *err)
{
    memset(h, 0, sizeof *h);
    for (int d = 0; d < 7; d++) {
        h->open_s[d] = h->close_s[d] = -1;
    }
    bool any = false;
    const char *p = spec;
    while (*p) {
        while (*p == ' ' || *p == ';') {
            p++;
        }
        size_t n = strcspn(p, ";");
        while (n && p[n - 1] == ' ') {
            n--;
        }
        if (n) {
            int rc = parse_entry(p, n, h, err);
            if (rc) {
                return rc;
            }
            any = true;
        }
        p += n;
    }
    if (!any) {
        return gale_errf(err, GALE_E_PARSE, "hours: \"%s\": expected HH:MM-HH:MM, or entries "
                         "like \"mon-fri 09:30-17:00; sat,sun 10:00-18:00\"", spec);
    }
    h->set = true;
    return 0;
}

/* Local midnight of the day `days` after now's, plus sec seconds, as the local clock
 * reads it (mktime normalises the fields and follows daylight saving). */
static time_t at_local(const struct tm *now, int days, int sec)
{
    struct tm t = *now;
    t.tm_mday += days;
    /* hours, minutes and seconds apart: as elapsed seconds from midnight, mktime would
     * count across a daylight-saving change and land an hour off the clock time */
    t.tm_hour = sec / 3600;
    t.tm_min = sec / 60 % 60;
    t.tm_sec = sec % 60;
    t.tm_isdst = -1;
    return mktime(&t);
}

bool ops_hours_eval(const ops_hours *h, time_t now, time_t *next)
{
    *next = 0;
    if (!h->set) {
        return true;
    }
    struct tm tm;
    localtime_r(&now, &tm);
    const int sec = tm.tm_hour * 3600 + tm.tm_min * 60 + tm.tm_sec;
    const int d = tm.tm_wday;
    if (h->open_s[d] >= 0 && sec >= h->open_s[d] && sec < h->close_s[d]) {
        *next = at_local(&tm, 0, h->close_s[d]);
        return true;
    }
    if (h->open_s[d] >= 0 && sec < h->open_s[d]) {
        *next = at_local(&tm, 0, h->open_s[d]);
        return false;
    }
    for (int k = 1; k <= 7; k++) {
        const int dk = (d + k) % 7;
        if (h->open_s[dk] >= 0) {
            *next = at_local(&tm, k, h->open_s[dk]);
            return false;
        }
    }
    return false; /* closed every day */
}

static void put_clock(int sec, char *out, size_t cap)
{
    if (sec % 60) {
        snprintf(out, cap, "%02d:%02d:%02d", sec / 3600, sec / 60 % 60, sec % 60);
    } else {
        snprintf(out, cap, "%02d:%02d", sec / 3600, sec / 60 % 60);
    }
}

void ops_hours_today(const ops_hours *h, time_t now, char *out, size_t cap)
{
    if (!h->set) {
        snprintf(out, cap, "always");
        return;
    }
    struct tm tm;
    localtime_r(&now, &tm);
    const int d = tm.tm_wday;
    if (h->open_s[d] < 0) {
        snprintf(out, cap, "closed");
        return;
    }
    char a[12], b[12];
    put_clock(h->open_s[d], a, sizeof a);
    put_clock(h->close_s[d], b, sizeof b);
    snprintf(out, cap, "%s-%s", a, b);
}

void ops_hours_clock(time_t t, char *out, size_t cap)
{
    struct tm tm;
    localtime_r(&t, &tm);
    put_clock(tm.tm_hour * 3600 + tm.tm_min * 60 + tm.tm_sec, out, cap);
}
