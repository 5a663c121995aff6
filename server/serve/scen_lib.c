/* The scenario library of scen_lib.h. */
#include "scen_lib.h"

#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int by_name(const void *a, const void *b)
{
    return strcmp(((const scen_lib_entry *)a)->name, ((const scen_lib_entry *)b)->name);
}

int scen_lib_load(scen_lib *l, const char *dir, gale_err *err)
{
    memset(l, 0, sizeof *l);
    DIR *d = opendir(dir);
    if (!d) {
        return errno == ENOENT || errno == ENOTDIR
                   ? GALE_OK
                   : gale_errf(err, GALE_E_IO, "%s: cannot read the scenarios folder: %s", dir,
                               strerror(errno));
    }
    snprintf(l->dir, sizeof l->dir, "%s", dir);
    struct dirent *de;
    int rc = GALE_OK;
    while (!rc && (de = readdir(d))) {
        size_t len = strlen(de->d_name);
        if (len <= 5 || strcmp(de->d_name + len - 5, ".json") || de->d_name[0] == '.') {
            continue;
        }
        if (len - 5 >= SCEN_LIB_NAME_MAX) {
            rc = gale_errf(err, GALE_E_RANGE, "%s/%s: scenario name: expected a file stem of at "
                           "most %d bytes, got %zu", dir, de->d_name, SCEN_LIB_NAME_MAX - 1,
                           len - 5);
            break;
        }
        bool odd = false;
        for (size_t k = 0; k + 5 < len; k++) {
            odd = odd || (unsigned char)de->d_name[k] < 0x20 || de->d_name[k] == 0x7f;
        }
        if (odd) {
            rc = gale_errf(err, GALE_E_RANGE, "%s: a scenario file name with control bytes: "
                           "expected printable names (kiosks name scenarios by them)", dir);
            break;
        }
        if (l->n == SCEN_LIB_MAX) {
            rc = gale_errf(err, GALE_E_RANGE, "%s: expected at most %d scenario files (what a "
                           "welcome lists), got more", dir, SCEN_LIB_MAX);
            break;
        }
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", dir, de->d_name);
        scen_lib_entry *e = &l->e[l->n];
        snprintf(e->name, sizeof e->name, "%.*s", (int)(len - 5), de->d_name);
        if (!(e->scen = scenario_load(path, err))) {
            rc = err && err->code ? err->code : GALE_E_PARSE;
            break;
        }
        l->n++;
    }
    closedir(d);
    if (rc) {
        scen_lib_fini(l);
        return rc;
    }
    qsort(l->e, (size_t)l->n, sizeof l->e[0], by_name);
    return GALE_OK;
}

void scen_lib_fini(scen_lib *l)
{
    if (!l) {
        return;
    }
    for (int i = 0; i < l->n; i++) {
        scenario_destroy(l->e[i].scen);
    }
    memset(l, 0, sizeof *l);
}

bool scen_lib_same_name(const char *a, const char *b)
{
    for (;;) {
        while (*a && !isalnum((unsigned char)*a)) {
            a++;
        }
        while (*b && !isalnum((unsigned char)*b)) {
            b++;
        }
        if (!*a || !*b) {
            return !*a && !*b;
        }
        if (tolower((unsigned char)*a++) != tolower((unsigned char)*b++)) {
            return false;
        }
    }
}

int scen_lib_find(const scen_lib *l, const char *name)
{
    /* stems first: a title may match another file's stem */
    for (int i = 0; i < l->n; i++) {
        if (scen_lib_same_name(name, l->e[i].name)) {
            return i;
        }
    }
    for (int i = 0; i < l->n; i++) {
        if (scen_lib_same_name(name, scenario_name(l->e[i].scen))) {
            return i;
        }
    }
    return -1;
}

void scen_lib_names(const scen_lib *l, char *out, size_t cap)
{
    size_t at = 0;
    if (cap == 0) {
        return;
    }
    out[0] = '\0';
    for (int i = 0; i < l->n; i++) {
        int k = snprintf(out + at, cap - at, "%s%s", i ? ", " : "", l->e[i].name);
        if (k < 0 || (size_t)k >= cap - at) {
            if (cap >= 4) {
                snprintf(out + cap - 4, 4, "...");
            }
            return;
        }
        at += (size_t)k;
    }
}

int scen_lib_playlist(const scen_lib *l, const scene *sc, scenario **out, int *n, gale_err *err)
{
    *n = 0;
    for (int i = 0; i < sc->n_playlist; i++) {
        int k = scen_lib_find(l, sc->playlist[i]);
        if (k < 0) {
            char names[1024] = "";
            scen_lib_names(l, names, sizeof names);
            return gale_errf(err, GALE_E_RANGE,
                             "scene %s: playlist[%d]: \"%s\": expected a scenario of %s: %s",
                             sc->name, i, sc->playlist[i], l->dir[0] ? l->dir : "the scenarios "
                             "folder", l->n > 0 ? names : "none found");
        }
        out[(*n)++] = l->e[k].scen;
    }
    return GALE_OK;
}

void scen_lib_names_cut(const char *list, char *out, size_t cap)
{
    if (cap == 0) {
        return;
    }
    size_t n = strlen(list);
    if (n < cap) {
        memcpy(out, list, n + 1);
        return;
    }
    /* the names before the last ", " that leaves room for "..." */
    size_t keep = 0;
    for (size_t i = 0; i + 2 < n && i + 5 < cap; i++) {
        if (list[i] == ',' && list[i + 1] == ' ') {
            keep = i + 2;
        }
    }
    if (keep + 4 > cap) {
        out[0] = '\0';
        return;
    }
    memcpy(out, list, keep);
    memcpy(out + keep, "...", 4);
}
