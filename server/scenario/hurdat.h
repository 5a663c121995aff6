/* Reader for NHC HURDAT2 best-track text (Landsea & Franklin 2013 format): a header row
 * per storm ("AL041992, ANDREW, 52,") followed by that many data rows (date, time, record
 * id, status, lat, lon, max wind kt, min pressure mb, 12 wind radii, radius of max wind). */
#ifndef GALE_HURDAT_H
#define GALE_HURDAT_H

#include <stddef.h>

#include "err.h"

#define HURDAT_MISSING (-999)

typedef struct hurdat_row {
    int year, month, day; /* UTC date */
    int hour, minute;     /* UTC time */
    char record;          /* 'L' landfall, 'I' intensity peak, ... ' ' none */
    char status[3];       /* "TD", "TS", "HU", "EX", ... */
    double lat_deg;       /* north positive */
    double lon_deg;       /* east positive (HURDAT2 "80.3W" → −80.3) */
    int vmax_kt;          /* 1-minute sustained 10 m wind [kt]; HURDAT_MISSING if absent */
    int pmin_mb;          /* minimum central pressure [mb = hPa]; HURDAT_MISSING if absent */
    int rmw_nm;           /* radius of maximum wind [nmi]; HURDAT_MISSING if absent */
    int line;             /* 1-based line in the source, for messages */
} hurdat_row;

typedef struct hurdat_storm {
    char id[16];   /* "AL041992" */
    char name[32]; /* "ANDREW" */
    int n_rows;
    hurdat_row *rows; /* owned by the hurdat_file, in file order */
} hurdat_storm;

typedef struct hurdat_file {
    char name[160];
    int n_storms;
    hurdat_storm *storms; /* owned */
} hurdat_file;

/* Parses text (len bytes) named `name` into *f. Errors name "name:line: field N (what):
 * expected ..., got ...". On failure *f is left empty (nothing to free). */
int hurdat_parse(hurdat_file *f, const char *name, const char *text, size_t len, gale_err *err);
/* Reads and parses a file; I/O errors name the path. */
int hurdat_load(hurdat_file *f, const char *path, gale_err *err);
/* Frees what *f owns. NULL is a no-op. */
void hurdat_fini(hurdat_file *f);
/* The storm with this id ("AL041992") or name ("ANDREW", case-insensitive); NULL if none. */
const hurdat_storm *hurdat_find(const hurdat_file *f, const char *id_or_name);
/* Central pressure [hPa] of row i of st for a replay: the row's own when it has one
 * (returns 0); else the nearest row in time that has both a pressure and a max wind, its
 * deficit below ambient_hpa scaled by the square of the two rows' max winds (returns 1):
 * Holland's V_max² = B Δp / (ρ e) at an unchanged B (PHYSICS.md "Hurricanes"), so a storm
 * weakening over land fills as its wind falls. −1 when row i has no max wind or no row has
 * both. */
int hurdat_pressure_at(const hurdat_storm *st, int i, double ambient_hpa, double *p_hpa);
/* Minutes since 1970-01-01 00:00 UTC of a row (proleptic Gregorian). */
long long hurdat_minutes(const hurdat_row *r);
/* Minutes since 1970-01-01 00:00 UTC of a civil UTC date and time. */
long long hurdat_civil_minutes(int year, int month, int day, int hour, int minute);
/* The inverse: civil date and time of minutes since the epoch. */
void hurdat_civil_from_minutes(long long minutes, int *year, int *month, int *day, int *hour,
                               int *minute);

#endif
