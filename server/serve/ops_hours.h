/* The exhibit's opening hours (server/SERVER.md "Opening hours"): a weekly timetable of
 * one window a day, in the machine's local time (TZ), to the second. Outside it the
 * exhibit is closed: clients show the closed card and the simulation idles. */
#ifndef GALE_OPS_HOURS_H
#define GALE_OPS_HOURS_H

#include <stdbool.h>
#include <time.h>

#include "err.h"

/* One window per weekday (0 = Sunday, as struct tm counts), seconds since local midnight,
 * open_s < close_s <= 86400; open_s < 0: closed all that day. */
typedef struct ops_hours {
    bool set;          /* false: no hours given, always open */
    int open_s[7];
    int close_s[7];
} ops_hours;

/* Parses spec into *h: entries separated by ';', each "[DAYS ]RANGE" with RANGE
 * "HH:MM[:SS]-HH:MM[:SS]" or "closed" and DAYS a comma list of days or day spans
 * ("mon-fri", "sat,sun"; mon tue wed thu fri sat sun). An entry without days sets every
 * day; later entries override earlier ones; with only entries that name days, the days
 * not named are closed. "09:30-17:00" opens every day. GALE_E_PARSE naming the entry and
 * what was expected. */
int ops_hours_parse(const char *spec, ops_hours *h, gale_err *err);

/* At now: whether open, and *next the time of the next opening or closing (0 when none
 * comes: no hours set, or closed every day). Uses localtime_r and mktime, so the local
 * clock's shifts (daylight saving) are followed. */
bool ops_hours_eval(const ops_hours *h, time_t now, time_t *next);

/* Today's window as "HH:MM-HH:MM" (seconds shown when not 0) or "closed" into out[cap];
 * "always" when no hours are set. */
void ops_hours_today(const ops_hours *h, time_t now, char *out, size_t cap);

/* The local clock time of t as "HH:MM", or "HH:MM:SS" when its seconds are not 0. */
void ops_hours_clock(time_t t, char *out, size_t cap);

#endif
