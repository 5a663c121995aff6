/* The exhibit's operating messages (PROTOCOL.md "Control messages"): kiosk_state, what a
 * kiosk shows and plays through (its language and audio output), and schedule, the
 * server's opening hours as they stand (open or closed, and the next change). */
#include "ctl_int.h"

#include <string.h>

/* A language tag as a kiosk names its language: a letter, then letters, digits or '-'
 * (BCP 47's alphabet: "en", "de-CH", "zh-Hant"); the server counts by it, so it must be
 * short and plain. */
static bool lang_ok(const char *s)
{
    if (!((s[0] >= 'a' && s[0] <= 'z') || (s[0] >= 'A' && s[0] <= 'Z'))) {
        return false;
    }
    for (const char *p = s + 1; *p; p++) {
        const char ch = *p;
        if (!((ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') ||
              ch == '-')) {
            return false;
        }
    }
    return true;
}

/* An audio device name: non-empty, no byte below 0x20 nor 0x7f (it is shown to staff). */
static bool audio_ok(const char *s)
{
    if (!s[0]) {
        return false;
    }
    for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
        if (*p < 0x20 || *p == 0x7f) {
            return false;
        }
    }
    return true;
}

/* "HH:MM" or "HH:MM:SS" of a 24-hour clock, or "" (no change ahead). */
static bool clock_ok(const char *s)
{
    size_t n = strlen(s);
    if (n == 0) {
        return true;
    }
    if (n != 5 && n != 8) {
        return false;
    }
    for (size_t i = 0; i < n; i++) {
        const bool colon = i == 2 || i == 5;
        if (colon ? s[i] != ':' : !(s[i] >= '0' && s[i] <= '9')) {
            return false;
        }
    }
    const int h = (s[0] - '0') * 10 + (s[1] - '0'), m = (s[3] - '0') * 10 + (s[4] - '0');
    const int sec = n == 8 ? (s[6] - '0') * 10 + (s[7] - '0') : 0;
    return h < 24 && m < 60 && sec < 60;
}

static int check_state(ctl_rd *c, const ctl_kiosk_state *k)
{
    if (!lang_ok(k->lang)) {
        return ctl_fail(c, 0, GALE_E_RANGE,
                        "kiosk_state.lang: expected a language tag (a letter, then letters, "
                        "digits or '-'), got \"%.20s\"", k->lang);
    }
    if (!audio_ok(k->audio)) {
        return ctl_fail(c, 0, GALE_E_RANGE,
                        "kiosk_state.audio: expected a device name (\"none\" for no output; no "
                        "control characters), got \"%.40s\"", k->audio);
    }
    return 0;
}

int ctl_kiosk_state_parse(ctl_rd *c, const cJSON *o, ctl_kiosk_state *k)
{
    static const char *const keys[] = { "type", "token", "lang", "audio", NULL };
    const json_rd *r = &c->j;
    int rc = json_check_keys(r, o, "kiosk_state", keys);
    if (!rc) {
        rc = json_string(r, o, "kiosk_state", "token", true, NULL, k->token, sizeof k->token,
                         NULL);
    }
    if (!rc) {
        rc = json_string(r, o, "kiosk_state", "lang", true, NULL, k->lang, sizeof k->lang, NULL);
    }
    if (!rc) {
        rc = json_string(r, o, "kiosk_state", "audio", true, NULL, k->audio, sizeof k->audio,
                         NULL);
    }
    return rc ? rc : check_state(c, k);
}

int ctl_kiosk_state_encode(ctl_rd *c, const ctl_kiosk_state *k, cJSON *o)
{
    const json_rd *r = &c->j;
    int rc = json_check_string(r, "kiosk_state", "token", k->token, sizeof k->token);
    if (!rc) {
        rc = json_check_string(r, "kiosk_state", "lang", k->lang, sizeof k->lang);
    }
    if (!rc) {
        rc = json_check_string(r, "kiosk_state", "audio", k->audio, sizeof k->audio);
    }
    if (!rc) {
        rc = check_state(c, k);
    }
    if (rc) {
        return rc;
    }
    return cJSON_AddStringToObject(o, "token", k->token) &&
                   cJSON_AddStringToObject(o, "lang", k->lang) &&
                   cJSON_AddStringToObject(o, "audio", k->audio)
               ? 0
               : ctl_fail(c, 0, GALE_E_NOMEM, "kiosk_state: out of memory");
}

/* Longest wait a schedule reports: a week, the period of a weekly timetable. */
#define NEXT_IN_MAX_S 604800

static int check_schedule(ctl_rd *c, const ctl_schedule *m)
{
    if (!clock_ok(m->next_change)) {
        return ctl_fail(c, 0, GALE_E_RANGE,
                        "schedule.next_change: expected \"HH:MM\", \"HH:MM:SS\" or \"\", got "
                        "\"%.12s\"", m->next_change);
    }
    if (!m->next_change[0] != !m->next_in_s) {
        return ctl_fail(c, 0, GALE_E_RANGE,
                        "schedule.next_in_s: expected 0 exactly when next_change is \"\", got %u "
                        "with \"%s\"", m->next_in_s, m->next_change);
    }
    return 0;
}

int ctl_schedule_parse(ctl_rd *c, const cJSON *o, ctl_schedule *m)
{
    static const char *const keys[] = { "type", "open", "next_change", "next_in_s", NULL };
    const json_rd *r = &c->j;
    long long in_s = 0;
    int rc = json_check_keys(r, o, "schedule", keys);
    if (!rc) {
        rc = json_bool(r, o, "schedule", "open", true, &m->open, NULL);
    }
    if (!rc) {
        rc = json_string(r, o, "schedule", "next_change", true, NULL, m->next_change,
                         sizeof m->next_change, NULL);
    }
    if (!rc) {
        rc = json_int(r, o, "schedule", "next_in_s", true, 0, NEXT_IN_MAX_S, &in_s, NULL);
    }
    m->next_in_s = (uint32_t)in_s;
    return rc ? rc : check_schedule(c, m);
}

int ctl_schedule_encode(ctl_rd *c, const ctl_schedule *m, cJSON *o)
{
    const json_rd *r = &c->j;
    int rc = json_check_string(r, "schedule", "next_change", m->next_change,
                               sizeof m->next_change);
    if (!rc) {
        rc = json_check_int(r, "schedule", "next_in_s", 0, NEXT_IN_MAX_S, m->next_in_s);
    }
    if (!rc) {
        rc = check_schedule(c, m);
    }
    if (rc) {
        return rc;
    }
    return cJSON_AddBoolToObject(o, "open", m->open) &&
                   cJSON_AddStringToObject(o, "next_change", m->next_change) &&
                   ctl_add_num(o, "next_in_s", m->next_in_s)
               ? 0
               : ctl_fail(c, 0, GALE_E_NOMEM, "schedule: out of memory");
}
