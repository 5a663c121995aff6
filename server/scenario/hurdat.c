/* HURDAT2 best-track reader: see hurdat.h. The format is the NHC's "hurdat2-format"
 * description: comma-separated, fixed field order, −999 for missing values. */
#include "hurdat.h"

#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define MAX_FIELDS         24
#define MAX_LINE           512
#define MAX_ROWS_PER_STORM 2000 /* the longest-lived Atlantic storms have ~150 rows */
#define MAX_STORMS         4000 /* the whole 1851– Atlantic file has ~1,950 */

static const char *const field_names[21] = {
    "date",     "time",     "record id", "status",   "latitude", "longitude", "max wind",
    "pressure", "34-kt NE", "34-kt SE",  "34-kt SW", "34-kt NW", "50-kt NE",  "50-kt SE",
    "50-kt SW", "50-kt NW", "64-kt NE",  "64-kt SE", "64-kt SW", "64-kt NW",  "radius of max wind",
};

long long hurdat_civil_minutes(int year, int month, int day, int hour, int minute)
{
    /* days from civil (H. Hinnant's algorithm), 1970-01-01 = day 0 */
    long long y = (long long)year - (month <= 2);
    long long era = (y >= 0 ? y : y - 399) / 400;
    long long yoe = y - era * 400;
    long long mp = (month + 9) % 12;
    long long doy = (153 * mp + 2) / 5 + day - 1;
    long long doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    long long days = era * 146097 + doe - 719468;
    return (days * 24 + hour) * 60 + minute;
}

void hurdat_civil_from_minutes(long long minutes, int *year, int *month, int *day, int *hour,
                               int *minute)
{
    long long days = minutes >= 0 ? minutes / 1440 : -((-minutes + 1439) / 1440);
    long long rem = minutes - days * 1440;
    *hour = (int)(rem / 60);
    *minute = (int)(rem % 60);
    long long z = days + 719468;
    long long era = (z >= 0 ? z : z - 146096) / 146097;
    long long doe = z - era * 146097;
    long long yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
    long long doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    long long mp = (5 * doy + 2) / 153;
    *day = (int)(doy - (153 * mp + 2) / 5 + 1);
    *month = (int)(mp < 10 ? mp + 3 : mp - 9);
    *year = (int)(yoe + era * 400 + (*month <= 2));
}

long long hurdat_minutes(const hurdat_row *r)
{
    return hurdat_civil_minutes(r->year, r->month, r->day, r->hour, r->minute);
}

/* Splits line (modified in place) at commas into trimmed fields; returns the count, or
 * MAX_FIELDS + 1 when there are more. */
static int split(char *line, char **fields)
{
    int n = 0;
    char *p = line;
    for (;;) {
        char *c = strchr(p, ',');
        if (c) {
            *c = '\0';
        }
        while (isspace((unsigned char)*p)) {
            p++;
        }
        char *e = p + strlen(p);
        while (e > p && isspace((unsigned char)e[-1])) {
            *--e = '\0';
        }
        if (n == MAX_FIELDS) {
            return MAX_FIELDS + 1;
        }
        fields[n++] = p;
        if (!c) {
            break;
        }
        p = c + 1;
    }
    /* a trailing comma leaves one empty last field: drop it */
    if (n > 0 && fields[n - 1][0] == '\0') {
        n--;
    }
    return n;
}

/* A whole field as a decimal integer; 0 ok. */
static int parse_int(const char *s, long *out)
{
    if (!s[0]) {
        return -1;
    }
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (*end || errno) {
        return -1;
    }
    *out = v;
    return 0;
}

/* "25.5N" / "80.3W" → signed degrees; hemisphere letters pos/neg; 0 ok. */
static int parse_coord(const char *s, char pos, char neg, double limit, double *out)
{
    size_t n = strlen(s);
    if (n < 2) {
        return -1;
    }
    char h = (char)toupper((unsigned char)s[n - 1]);
    if (h != pos && h != neg) {
        return -1;
    }
    char num[32];
    if (n - 1 >= sizeof num) {
        return -1;
    }
    memcpy(num, s, n - 1);
    num[n - 1] = '\0';
    char *end;
    errno = 0;
    double v = strtod(num, &end);
    if (*end || errno || end == num || !(v >= 0.0 && v <= limit)) {
        return -1;
    }
    *out = h == pos ? v : -v;
    return 0;
}

static int field_err(gale_err *err, const char *name, int line, int field, const char *want,
                     const char *got)
{
    return gale_errf(err, GALE_E_PARSE, "%s:%d: field %d (%s): expected %s, got '%.40s'", name,
                     line, field + 1, field_names[field], want, got);
}

static int parse_row(hurdat_row *r, char **f, int nf, const char *name, int line, gale_err *err)
{
    memset(r, 0, sizeof *r);
    r->line = line;
    if (nf != 20 && nf != 21) {
        return gale_errf(err, GALE_E_PARSE,
                         "%s:%d: data row: expected 20 or 21 comma-separated fields, got %d", name,
                         line, nf > MAX_FIELDS ? MAX_FIELDS + 1 : nf);
    }
    long date, hhmm, v;
    if (strlen(f[0]) != 8 || parse_int(f[0], &date) != 0) {
        return field_err(err, name, line, 0, "YYYYMMDD", f[0]);
    }
    r->year = (int)(date / 10000);
    r->month = (int)(date / 100 % 100);
    r->day = (int)(date % 100);
    if (r->year < 1800 || r->year > 2200 || r->month < 1 || r->month > 12 || r->day < 1 ||
        r->day > 31) {
        return field_err(err, name, line, 0, "a date YYYYMMDD", f[0]);
    }
    if (strlen(f[1]) != 4 || parse_int(f[1], &hhmm) != 0 || hhmm / 100 > 23 || hhmm % 100 > 59) {
        return field_err(err, name, line, 1, "hhmm UTC", f[1]);
    }
    r->hour = (int)(hhmm / 100);
    r->minute = (int)(hhmm % 100);
    if (strlen(f[2]) > 1 || (f[2][0] && !isalpha((unsigned char)f[2][0]))) {
        return field_err(err, name, line, 2, "one letter or nothing", f[2]);
    }
    r->record = f[2][0] ? f[2][0] : ' ';
    if (strlen(f[3]) != 2 || !isalpha((unsigned char)f[3][0]) || !isalpha((unsigned char)f[3][1])) {
        return field_err(err, name, line, 3, "a two-letter status (TD, TS, HU...)", f[3]);
    }
    memcpy(r->status, f[3], 3);
    if (parse_coord(f[4], 'N', 'S', 90.0, &r->lat_deg) != 0) {
        return field_err(err, name, line, 4, "degrees with N or S, like 25.5N", f[4]);
    }
    if (parse_coord(f[5], 'E', 'W', 360.0, &r->lon_deg) != 0) {
        return field_err(err, name, line, 5, "degrees with E or W, like 80.3W", f[5]);
    }
    if (parse_int(f[6], &v) != 0 || (v != HURDAT_MISSING && (v < 0 || v > 250))) {
        return field_err(err, name, line, 6, "knots in [0, 250] or -999", f[6]);
    }
    r->vmax_kt = (int)v;
    if (parse_int(f[7], &v) != 0 || (v != HURDAT_MISSING && (v < 800 || v > 1100))) {
        return field_err(err, name, line, 7, "millibars in [800, 1100] or -999", f[7]);
    }
    r->pmin_mb = (int)v;
    for (int i = 8; i < 20; i++) {
        if (parse_int(f[i], &v) != 0 || (v != HURDAT_MISSING && (v < 0 || v > 2000))) {
            return field_err(err, name, line, i, "nautical miles in [0, 2000] or -999", f[i]);
        }
    }
    r->rmw_nm = HURDAT_MISSING;
    if (nf == 21) {
        if (parse_int(f[20], &v) != 0 || (v != HURDAT_MISSING && (v < 1 || v > 500))) {
            return field_err(err, name, line, 20, "nautical miles in [1, 500] or -999", f[20]);
        }
        r->rmw_nm = (int)v;
    }
    return GALE_OK;
}

void hurdat_fini(hurdat_file *f)
{
    if (!f) {
        return;
    }
    for (int i = 0; i < f->n_storms; i++) {
        free(f->storms[i].rows);
    }
    free(f->storms);
    f->storms = NULL;
    f->n_storms = 0;
}

int hurdat_parse(hurdat_file *f, const char *name, const char *text, size_t len, gale_err *err)
{
    memset(f, 0, sizeof *f);
    snprintf(f->name, sizeof f->name, "%s", name ? name : "<hurdat>");
    name = f->name;
    int cap = 0, rc = GALE_OK;
    hurdat_storm *cur = NULL;
    int expect = 0, header_line = 0;
    size_t pos = 0;
    int line = 0;
    char buf[MAX_LINE + 2];
    char *fields[MAX_FIELDS + 1];
    while (pos < len) {
        line++;
        size_t start = pos;
        while (pos < len && text[pos] != '\n') {
            pos++;
        }
        size_t n = pos - start;
        if (pos < len) {
            pos++; /* the '\n' */
        }
        if (n > 0 && text[start + n - 1] == '\r') {
            n--;
        }
        if (n > MAX_LINE) {
            rc = gale_errf(err, GALE_E_PARSE, "%s:%d: line longer than %d bytes", name, line,
                           MAX_LINE);
            goto fail;
        }
        memcpy(buf, text + start, n);
        buf[n] = '\0';
        if (memchr(buf, '\0', n)) {
            rc = gale_errf(err, GALE_E_PARSE, "%s:%d: NUL byte in a text line", name, line);
            goto fail;
        }
        char shown[64];
        snprintf(shown, sizeof shown, "%.60s", buf);
        int nf = split(buf, fields);
        if (nf == 0) {
            continue; /* blank line */
        }
        if (expect == 0) {
            /* a header: id (2 letters + 6 digits), name, row count */
            long count;
            if (nf != 3 || strlen(fields[0]) != 8 || !isalpha((unsigned char)fields[0][0]) ||
                !isalpha((unsigned char)fields[0][1]) || parse_int(fields[2], &count) != 0) {
                rc = gale_errf(err, GALE_E_PARSE,
                               "%s:%d: expected a storm header like 'AL041992, ANDREW, 52,', "
                               "got '%.60s'",
                               name, line, shown);
                goto fail;
            }
            for (int i = 2; i < 8; i++) {
                if (!isdigit((unsigned char)fields[0][i])) {
                    rc = gale_errf(err, GALE_E_PARSE,
                                   "%s:%d: storm id: expected 2 letters and 6 digits, got "
                                   "'%.20s'",
                                   name, line, fields[0]);
                    goto fail;
                }
            }
            if (count < 1 || count > MAX_ROWS_PER_STORM) {
                rc = gale_errf(err, GALE_E_RANGE,
                               "%s:%d: row count: expected an integer in [1, %d], got %ld", name,
                               line, MAX_ROWS_PER_STORM, count);
                goto fail;
            }
            if (f->n_storms == cap) {
                if (cap >= MAX_STORMS) {
                    rc = gale_errf(err, GALE_E_RANGE, "%s:%d: more than %d storms", name, line,
                                   MAX_STORMS);
                    goto fail;
                }
                int ncap = cap ? cap * 2 : 4;
                hurdat_storm *ns = realloc(f->storms, (size_t)ncap * sizeof *ns);
                if (!ns) {
                    rc = gale_errf(err, GALE_E_NOMEM, "%s:%d: out of memory", name, line);
                    goto fail;
                }
                f->storms = ns;
                cap = ncap;
            }
            cur = &f->storms[f->n_storms];
            memset(cur, 0, sizeof *cur);
            cur->rows = calloc((size_t)count, sizeof *cur->rows);
            if (!cur->rows) {
                rc = gale_errf(err, GALE_E_NOMEM, "%s:%d: out of memory", name, line);
                goto fail;
            }
            f->n_storms++;
            snprintf(cur->id, sizeof cur->id, "%s", fields[0]);
            snprintf(cur->name, sizeof cur->name, "%s", fields[1]);
            expect = (int)count;
            header_line = line;
            continue;
        }
        if (nf == 3 && strlen(fields[0]) == 8 && isalpha((unsigned char)fields[0][0])) {
            rc = gale_errf(err, GALE_E_PARSE,
                           "%s:%d: storm header, but %s (line %d) declared %d more rows", name,
                           line, cur->id, header_line, expect);
            goto fail;
        }
        hurdat_row *r = &cur->rows[cur->n_rows];
        rc = parse_row(r, fields, nf, name, line, err);
        if (rc < 0) {
            goto fail;
        }
        if (cur->n_rows > 0 && hurdat_minutes(r) < hurdat_minutes(&cur->rows[cur->n_rows - 1])) {
            rc = gale_errf(err, GALE_E_PARSE, "%s:%d: time goes backwards (previous row %d)", name,
                           line, cur->rows[cur->n_rows - 1].line);
            goto fail;
        }
        cur->n_rows++;
        expect--;
    }
    if (expect > 0) {
        rc = gale_errf(err, GALE_E_PARSE,
                       "%s:%d: end of file, but %s (line %d) declared %d more rows", name, line,
                       cur->id, header_line, expect);
        goto fail;
    }
    if (f->n_storms == 0) {
        rc = gale_errf(err, GALE_E_PARSE, "%s: no storms", name);
        goto fail;
    }
    return GALE_OK;
fail:
    hurdat_fini(f);
    return rc;
}

int hurdat_load(hurdat_file *f, const char *path, gale_err *err)
{
    memset(f, 0, sizeof *f);
    FILE *fp = fopen(path, "rb");
    if (!fp) {
        return gale_errf(err, GALE_E_IO, "%s: cannot open: %s", path, strerror(errno));
    }
    size_t cap = 1 << 16, len = 0;
    char *buf = malloc(cap);
    if (!buf) {
        fclose(fp);
        return gale_errf(err, GALE_E_NOMEM, "%s: out of memory", path);
    }
    for (;;) {
        if (len == cap) {
            if (cap >= (64u << 20)) {
                free(buf);
                fclose(fp);
                return gale_errf(err, GALE_E_RANGE, "%s: larger than 64 MiB", path);
            }
            char *nb = realloc(buf, cap * 2);
            if (!nb) {
                free(buf);
                fclose(fp);
                return gale_errf(err, GALE_E_NOMEM, "%s: out of memory", path);
            }
            buf = nb;
            cap *= 2;
        }
        size_t got = fread(buf + len, 1, cap - len, fp);
        len += got;
        if (got == 0) {
            break;
        }
    }
    int bad = ferror(fp);
    fclose(fp);
    if (bad) {
        free(buf);
        return gale_errf(err, GALE_E_IO, "%s: read error", path);
    }
    int rc = hurdat_parse(f, path, buf, len, err);
    free(buf);
    return rc;
}

const hurdat_storm *hurdat_find(const hurdat_file *f, const char *id_or_name)
{
    for (int i = 0; i < f->n_storms; i++) {
        if (strcasecmp(f->storms[i].id, id_or_name) == 0 ||
            strcasecmp(f->storms[i].name, id_or_name) == 0) {
            return &f->storms[i];
        }
    }
    return NULL;
}

int hurdat_pressure_at(const hurdat_storm *st, int i, double ambient_hpa, double *p_hpa)
{
    const hurdat_row *r = &st->rows[i];
    if (r->pmin_mb != HURDAT_MISSING) {
        *p_hpa = r->pmin_mb;
        return 0;
    }
    if (r->vmax_kt == HURDAT_MISSING) {
        return -1;
    }
    const hurdat_row *best = NULL;
    long long best_dt = 0;
    for (int j = 0; j < st->n_rows; j++) {
        const hurdat_row *q = &st->rows[j];
        if (q->pmin_mb == HURDAT_MISSING || q->vmax_kt == HURDAT_MISSING || q->vmax_kt <= 0) {
            continue;
        }
        long long dt = llabs(hurdat_minutes(q) - hurdat_minutes(r));
        if (!best || dt < best_dt) {
            best = q;
            best_dt = dt;
        }
    }
    if (!best) {
        return -1;
    }
    double k = (double)r->vmax_kt / (double)best->vmax_kt;
    *p_hpa = ambient_hpa - (ambient_hpa - (double)best->pmin_mb) * k * k;
    return 1;
}
