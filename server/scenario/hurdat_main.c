/* gale-hurdat: turns the HURDAT2 best-track rows of one storm around a landfall into a
 * hurricane scenario file (track times relative to a reference, pressure, Rmax, Vmax in
 * SI units), so configs/scenarios/andrew1992.json and charley2004.json can be rebuilt
 * from tests/data/hurdat2-andrew1992-charley2004.txt, and the storm library from
 * tests/data/hurdat2-landfalls.txt (deploy/storm-library.sh). See
 * configs/scenarios/README.md. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "hurdat.h"
#include "saffir.h"
#include "scenario.h"

#define KM_PER_NM 1.852

static void usage(FILE *o)
{
    fprintf(o, "usage: gale-hurdat --in HURDAT2.txt --storm ID|NAME --ref YYYY-MM-DDTHH:MMZ\n"
               "         --from YYYY-MM-DDTHH:MMZ --to YYYY-MM-DDTHH:MMZ\n"
               "         --site-lat DEG --site-lon DEG [--site-label TEXT] [--over-water]\n"
               "         [--utc-offset-min M]\n"
               "         [--time-scale K] [--start-min M] [--end-min M] [--ambient-hpa P]\n"
               "         [--rmax-km R] [--seed N] [--name TEXT] [--out FILE]\n"
               "Writes a hurricane scenario (JSON) with the storm's rows in [from, to]; rows\n"
               "without a radius of maximum wind take the nearest row's that has one (or\n"
               "--rmax-km). --utc-offset-min: the site's local time is UTC + M minutes\n"
               "(-840..840, e.g. -240 for EDT; the kiosk shows it); without it the scenario\n"
               "takes the longitude's 15-degree zone. A row without a central pressure takes\n"
               "the nearest row's that has one, its deficit below --ambient-hpa scaled by\n"
               "(Vmax / that row's Vmax)^2 (the count is noted in \"source\"). The file is\n"
               "validated by loading it back.\n");
}

static int parse_utc(const char *s, long long *out)
{
    int y, mo, d, h, mi;
    char z = 0;
    if (!s || sscanf(s, "%4d-%2d-%2dT%2d:%2d%c", &y, &mo, &d, &h, &mi, &z) != 6 || z != 'Z') {
        return -1;
    }
    *out = hurdat_civil_minutes(y, mo, d, h, mi);
    return 0;
}

static int parse_num(const char *s, double *out)
{
    char *end;
    if (!s) {
        return -1;
    }
    *out = strtod(s, &end);
    return (*end || end == s || !isfinite(*out)) ? -1 : 0;
}

/* A JSON string literal for s (escaped by cJSON). */
static void put_string(FILE *o, const char *s)
{
    cJSON *j = cJSON_CreateString(s);
    char *t = j ? cJSON_PrintUnformatted(j) : NULL;
    fputs(t ? t : "\"\"", o);
    cJSON_free(t);
    cJSON_Delete(j);
}

int main(int argc, char **argv)
{
    const char *in = NULL, *storm = NULL, *ref = NULL, *from = NULL, *to = NULL;
    const char *label = "", *name = NULL, *out_path = NULL;
    double site_lat = NAN, site_lon = NAN, time_scale = 1.0, start_min = NAN, end_min = NAN;
    double ambient = 1013.0, rmax_km = NAN, seed = 1.0, utc_offset_min = NAN;
    int over_land = 1;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        int num = 0;
        double *dst = NULL;
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            usage(stdout);
            return 0;
        } else if (strcmp(a, "--over-water") == 0) {
            over_land = 0;
            continue;
        } else if (strcmp(a, "--in") == 0) {
            in = v;
        } else if (strcmp(a, "--storm") == 0) {
            storm = v;
        } else if (strcmp(a, "--ref") == 0) {
            ref = v;
        } else if (strcmp(a, "--from") == 0) {
            from = v;
        } else if (strcmp(a, "--to") == 0) {
            to = v;
        } else if (strcmp(a, "--site-label") == 0) {
            label = v;
        } else if (strcmp(a, "--name") == 0) {
            name = v;
        } else if (strcmp(a, "--out") == 0) {
            out_path = v;
        } else if (strcmp(a, "--site-lat") == 0) {
            dst = &site_lat;
        } else if (strcmp(a, "--site-lon") == 0) {
            dst = &site_lon;
        } else if (strcmp(a, "--time-scale") == 0) {
            dst = &time_scale;
        } else if (strcmp(a, "--start-min") == 0) {
            dst = &start_min;
        } else if (strcmp(a, "--end-min") == 0) {
            dst = &end_min;
        } else if (strcmp(a, "--ambient-hpa") == 0) {
            dst = &ambient;
        } else if (strcmp(a, "--rmax-km") == 0) {
            dst = &rmax_km;
        } else if (strcmp(a, "--seed") == 0) {
            dst = &seed;
        } else if (strcmp(a, "--utc-offset-min") == 0) {
            dst = &utc_offset_min;
        } else {
            fprintf(stderr, "gale-hurdat: unknown argument '%s'\n", a);
            usage(stderr);
            return 2;
        }
        if (!v) {
            fprintf(stderr, "gale-hurdat: %s: missing value\n", a);
            return 2;
        }
        if (dst && (num = parse_num(v, dst)) != 0) {
            fprintf(stderr, "gale-hurdat: %s: expected a number, got '%s'\n", a, v);
            return 2;
        }
        i++;
    }
    if (!isnan(utc_offset_min) && !(utc_offset_min >= -840 && utc_offset_min <= 840 &&
                                     utc_offset_min == floor(utc_offset_min))) {
        fprintf(stderr, "gale-hurdat: --utc-offset-min: expected whole minutes in [-840, 840], "
                        "got %g\n",
                utc_offset_min);
        return 2;
    }
    long long ref_m, from_m, to_m;
    if (!in || !storm || isnan(site_lat) || isnan(site_lon)) {
        fprintf(stderr, "gale-hurdat: --in, --storm, --site-lat and --site-lon are required\n");
        usage(stderr);
        return 2;
    }
    if (parse_utc(ref, &ref_m) != 0 || parse_utc(from, &from_m) != 0 || parse_utc(to, &to_m) != 0) {
        fprintf(stderr, "gale-hurdat: --ref, --from, --to: expected YYYY-MM-DDTHH:MMZ\n");
        return 2;
    }
    hurdat_file hf;
    gale_err err = { 0 };
    if (hurdat_load(&hf, in, &err) < 0) {
        fprintf(stderr, "gale-hurdat: %s\n", err.msg);
        return 1;
    }
    const hurdat_storm *st = hurdat_find(&hf, storm);
    if (!st) {
        fprintf(stderr, "gale-hurdat: %s: no storm '%s'\n", in, storm);
        hurdat_fini(&hf);
        return 1;
    }
    int first = -1, last = -1;
    for (int i = 0; i < st->n_rows; i++) {
        long long m = hurdat_minutes(&st->rows[i]);
        if (m >= from_m && m <= to_m) {
            if (first < 0) {
                first = i;
            }
            last = i;
        }
    }
    if (first < 0 || last == first) {
        fprintf(stderr, "gale-hurdat: %s: fewer than 2 rows of %s between %s and %s\n", in, st->id,
                from, to);
        hurdat_fini(&hf);
        return 1;
    }
    FILE *o = out_path ? fopen(out_path, "w") : stdout;
    if (!o) {
        fprintf(stderr, "gale-hurdat: %s: cannot write\n", out_path);
        hurdat_fini(&hf);
        return 1;
    }
    char title[160];
    snprintf(title, sizeof title, "%s %d", name ? name : st->name, st->rows[first].year);
    /* rows without a central pressure: filled from the nearest that has one (hurdat.h) */
    int n_filled = 0;
    for (int i = first; i <= last; i++) {
        double p;
        n_filled += hurdat_pressure_at(st, i, ambient, &p) == 1;
    }
    char src[240], fill[64] = "";
    if (n_filled > 0) {
        snprintf(fill, sizeof fill, "; %d missing p from the nearest row's, x (V/V')^2",
                 n_filled);
    }
    snprintf(src, sizeof src,
             "NHC HURDAT2 %s (%s), rows %s..%s of %s; Vmax kt x 0.514444, RMW nm x 1.852%s",
             st->id, st->name, from, to, in, fill);
    fprintf(o, "{\n  \"name\": ");
    put_string(o, title);
    fprintf(o, ",\n  \"kind\": \"hurricane\",\n  \"seed\": %.0f,\n  \"z0_m\": 0.3,\n", seed);
    fprintf(o, "  \"hurricane\": {\n    \"source\": ");
    put_string(o, src);
    fprintf(o,
            ",\n    \"site\": { \"lat_deg\": %.4f, \"lon_deg\": %.4f, \"over_land\": %s, "
            "\"label\": ",
            site_lat, site_lon, over_land ? "true" : "false");
    put_string(o, label);
    if (!isnan(utc_offset_min)) {
        fprintf(o, ", \"utc_offset_min\": %d", (int)utc_offset_min);
    }
    fprintf(o, " },\n    \"ref_utc\": \"%s\",\n    \"ambient_hpa\": %g,\n", ref, ambient);
    fprintf(o, "    \"time_scale\": %g,\n", time_scale);
    if (!isnan(start_min)) {
        fprintf(o, "    \"start_min\": %g,\n", start_min);
    }
    if (!isnan(end_min)) {
        fprintf(o, "    \"end_min\": %g,\n", end_min);
    }
    fprintf(o, "    \"track\": [\n");
    int rc = 0;
    for (int i = first; i <= last; i++) {
        const hurdat_row *r = &st->rows[i];
        /* nearest row (in time) of this storm that carries a radius of maximum wind */
        double rkm = rmax_km;
        if (isnan(rkm) || r->rmw_nm != HURDAT_MISSING) {
            long long best = -1;
            for (int j = 0; j < st->n_rows; j++) {
                if (st->rows[j].rmw_nm == HURDAT_MISSING) {
                    continue;
                }
                long long dtm = llabs(hurdat_minutes(&st->rows[j]) - hurdat_minutes(r));
                if (best < 0 || dtm < best) {
                    best = dtm;
                    rkm = st->rows[j].rmw_nm * KM_PER_NM;
                }
            }
        }
        double p_hpa = 0.0;
        int filled = hurdat_pressure_at(st, i, ambient, &p_hpa);
        if (isnan(rkm) || r->vmax_kt == HURDAT_MISSING || filled < 0) {
            fprintf(stderr, "gale-hurdat: %s:%d: %s lacks %s\n", in, r->line, st->id,
                    isnan(rkm) ? "a radius of maximum wind (give --rmax-km)"
                               : "a max wind, or a pressure on any row");
            rc = 1;
            break;
        }
        if (filled == 1) {
            fprintf(stderr, "gale-hurdat: %s:%d: no pressure: %.0f hPa from the nearest row's\n",
                    in, r->line, p_hpa);
        }
        fprintf(o,
                "      { \"t_min\": %lld, \"lat_deg\": %.1f, \"lon_deg\": %.1f, "
                "\"p_hpa\": %.0f, \"rmax_km\": %.2f, \"vmax_ms\": %.2f }%s\n",
                hurdat_minutes(r) - ref_m, r->lat_deg, r->lon_deg, p_hpa, rkm,
                r->vmax_kt * SAFFIR_MS_PER_KT, i < last ? "," : "");
    }
    fprintf(o, "    ]\n  }\n}\n");
    hurdat_fini(&hf);
    if (out_path) {
        if (fclose(o) != 0) {
            fprintf(stderr, "gale-hurdat: %s: write error\n", out_path);
            return 1;
        }
        if (rc == 0) {
            scenario *s = scenario_load(out_path, &err);
            if (!s) {
                fprintf(stderr, "gale-hurdat: the written file does not load: %s\n", err.msg);
                return 1;
            }
            scenario_destroy(s);
        }
    }
    return rc;
}
