/* The exhibit's operation: opening hours, kiosk reports, usage counters and /status
 * (srv_ops.h). One mutex guards everything but the open flag, which the simulation
 * thread reads on every tick. */
#include "srv_ops.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <cjson/cJSON.h>

#include "ctl.h"
#include "pi_mutex.h"
#include "json.h"
#include "mono.h"
#include "ops_usage.h"

typedef struct ops_kiosk {
    uint32_t conn;              /* 0: free */
    char lang[CTL_MAX_LANG];
    char audio[CTL_MAX_NAME];
} ops_kiosk;

struct srv_ops {
    srv_ops_desc d;
    pthread_mutex_t lock;
    ops_usage u;
    ops_kiosk kiosks[SRV_OPS_MAX_KIOSKS];
    bool any;                   /* an interaction since start */
    time_t last_wall;           /* the last interaction, wall clock */
    double last_mono_s;
    time_t start_wall;
    double start_mono_s;
    atomic_int open;
    time_t next;                /* the next change (0: none) */
    double next_save_s;
    net_server *net;            /* borrowed while running */
    const atomic_uint *tick;
    pthread_t thread;
    bool running;
    atomic_int stop;
};

srv_ops *srv_ops_create(const srv_ops_desc *d, gale_err *err)
{
    srv_ops *o = calloc(1, sizeof *o);
    if (!o) {
        gale_errf(err, GALE_E_NOMEM, "srv_ops_create: no memory");
        return NULL;
    }
    o->d = *d;
    pi_mutex_init(&o->lock);
    ops_usage_init(&o->u);
    if (d->state_file) {
        bool found = false;
        gale_err e;
        if (ops_usage_load(&o->u, d->state_file, &found, &e)) {
            gale_errf(err, e.code, "state file: %s (left as it is; fix or move it away to "
                      "start counting from zero)", e.msg);
            srv_ops_destroy(o);
            return NULL;
        }
        if (!d->quiet) {
            fprintf(stderr, "gale-server: usage counters %s %s (%llu sessions)\n",
                    found ? "loaded from" : "start at zero; they will be kept in",
                    d->state_file, o->u.sessions);
        }
    }
    o->start_wall = time(NULL);
    o->start_mono_s = mono_s();
    time_t next;
    atomic_store(&o->open, ops_hours_eval(&d->hours, o->start_wall, &next));
    o->next = next;
    return o;
}

/* The schedule notice as it stands (clients' closed card; PROTOCOL.md "schedule"). */
static void send_schedule(srv_ops *o, time_t now)
{
    if (!o->d.hours.set) {
        return; /* always open: nothing to tell, and the wire stays as it was */
    }
    ctl_msg m = { .type = CTL_SCHEDULE };
    m.u.schedule.open = atomic_load(&o->open);
    if (o->next > now) {
        ops_hours_clock(o->next, m.u.schedule.next_change, sizeof m.u.schedule.next_change);
        const double in = difftime(o->next, now);
        m.u.schedule.next_in_s = in > 604800 ? 604800u : (uint32_t)in;
    }
    char *text = NULL;
    size_t len = 0;
    gale_err e;
    if (ctl_encode(&m, &text, &len, &e)) {
        fprintf(stderr, "gale-server: schedule notice: %s\n", e.msg);
        return;
    }
    net_set_notice(o->net, text, len);
    free(text);
}

/* Writes a copy of the counters (taken under the lock) with the lock released: an fsync
 * may take a while, and the control handler on the network thread must not wait for it. */
static void save(const ops_usage *u, const char *path)
{
    gale_err e;
    if (path && ops_usage_save(u, path, &e)) {
        fprintf(stderr, "gale-server: usage counters not saved: %s\n", e.msg);
    }
}

static void *poll_thread(void *arg)
{
    srv_ops *o = arg;
    while (!atomic_load(&o->stop)) {
        const struct timespec nap = { 0, SRV_OPS_POLL_MS * 1000000L };
        nanosleep(&nap, NULL);
        const time_t now = time(NULL);
        const double now_s = mono_s();
        pthread_mutex_lock(&o->lock);
        ops_usage_poll(&o->u, now_s, o->d.idle_s);
        time_t next;
        const bool open = ops_hours_eval(&o->d.hours, now, &next);
        if (open != atomic_load(&o->open) || next != o->next) {
            const bool changed = open != atomic_load(&o->open);
            atomic_store(&o->open, open);
            o->next = next;
            char at[12] = "";
            if (next) {
                ops_hours_clock(next, at, sizeof at);
            }
            if (changed && !o->d.quiet) {
                fprintf(stderr, "gale-server: %s by the opening hours%s%s%s; tick %u\n",
                        open ? "open" : "closed", next ? " until " : "", at,
                        open ? "" : " (the simulation idles)",
                        o->tick ? atomic_load(o->tick) : 0u);
            }
            send_schedule(o, now);
        }
        const bool due = now_s >= o->next_save_s;
        ops_usage copy;
        if (due) {
            copy = o->u;
        }
        pthread_mutex_unlock(&o->lock);
        if (due) {
            o->next_save_s = now_s + SRV_OPS_SAVE_S;
            save(&copy, o->d.state_file);
        }
    }
    return NULL;
}

int srv_ops_start(srv_ops *o, net_server *net, const atomic_uint *tick, gale_err *err)
{
    o->net = net;
    o->tick = tick;
    o->next_save_s = mono_s() + SRV_OPS_SAVE_S;
    pthread_mutex_lock(&o->lock);
    send_schedule(o, time(NULL));
    pthread_mutex_unlock(&o->lock);
    if (pthread_create(&o->thread, NULL, poll_thread, o)) {
        return gale_errf(err, GALE_E_STATE, "gale-server: cannot start the schedule thread");
    }
    o->running = true;
    return 0;
}

void srv_ops_stop(srv_ops *o)
{
    if (!o) {
        return;
    }
    if (o->running) {
        atomic_store(&o->stop, 1);
        pthread_join(o->thread, NULL);
        o->running = false;
    }
    pthread_mutex_lock(&o->lock);
    ops_usage_end(&o->u);
    ops_usage copy = o->u;
    pthread_mutex_unlock(&o->lock);
    save(&copy, o->d.state_file);
}

void srv_ops_destroy(srv_ops *o)
{
    if (!o) {
        return;
    }
    pthread_mutex_destroy(&o->lock);
    free(o);
}

bool srv_ops_open(const srv_ops *o)
{
    return !o || atomic_load(&o->open);
}

static ops_kiosk *kiosk_of(srv_ops *o, uint32_t conn)
{
    for (int i = 0; i < SRV_OPS_MAX_KIOSKS; i++) {
        if (o->kiosks[i].conn == conn) {
            return &o->kiosks[i];
        }
    }
    return NULL;
}

/* Lock held. */
static void interaction_locked(srv_ops *o, uint32_t conn)
{
    o->any = true;
    o->last_wall = time(NULL);
    o->last_mono_s = mono_s();
    if (ops_usage_interaction(&o->u, o->last_mono_s, o->d.idle_s)) {
        /* a visitor begins at a kiosk showing this language */
        const ops_kiosk *k = kiosk_of(o, conn);
        if (k) {
            ops_usage_count(o->u.langs, &o->u.n_langs, k->lang);
        }
    }
}

void srv_ops_interaction(srv_ops *o, uint32_t conn)
{
    pthread_mutex_lock(&o->lock);
    interaction_locked(o, conn);
    pthread_mutex_unlock(&o->lock);
}

void srv_ops_dial(srv_ops *o, double speed_ms)
{
    pthread_mutex_lock(&o->lock);
    ops_usage_dial(&o->u, speed_ms);
    pthread_mutex_unlock(&o->lock);
}

void srv_ops_pick(srv_ops *o, const char *scenario)
{
    pthread_mutex_lock(&o->lock);
    ops_usage_count(o->u.replays, &o->u.n_replays, scenario);
    pthread_mutex_unlock(&o->lock);
}

void srv_ops_kiosk_state(srv_ops *o, uint32_t conn, const char *lang, const char *audio)
{
    pthread_mutex_lock(&o->lock);
    ops_kiosk *k = kiosk_of(o, conn);
    if (k && strcmp(k->lang, lang)) {
        /* a visitor chose another language: counted in (or as the start of) the session */
        snprintf(k->lang, sizeof k->lang, "%s", lang);
        const unsigned long long before = o->u.sessions;
        interaction_locked(o, conn);
        if (o->u.sessions == before) {
            ops_usage_count(o->u.langs, &o->u.n_langs, lang); /* else counted as it began */
        }
    }
    if (!k && (k = kiosk_of(o, 0))) { /* the kiosk's first report: a free row */
        k->conn = conn;
    }
    if (k) {
        snprintf(k->lang, sizeof k->lang, "%s", lang);
        snprintf(k->audio, sizeof k->audio, "%s", audio);
    }
    pthread_mutex_unlock(&o->lock);
}

void srv_ops_conn_closed(srv_ops *o, uint32_t conn)
{
    pthread_mutex_lock(&o->lock);
    for (int i = 0; i < SRV_OPS_MAX_KIOSKS; i++) {
        if (o->kiosks[i].conn == conn) {
            memset(&o->kiosks[i], 0, sizeof o->kiosks[i]);
        }
    }
    pthread_mutex_unlock(&o->lock);
}

static void iso_utc(time_t t, char *out, size_t cap)
{
    struct tm tm;
    gmtime_r(&t, &tm);
    strftime(out, cap, "%Y-%m-%dT%H:%M:%SZ", &tm);
}

/* Adds the distinct values of field f (lang or audio) of the reporting kiosks. */
static cJSON *distinct(const srv_ops *o, bool audio)
{
    cJSON *a = cJSON_CreateArray();
    for (int i = 0; a && i < SRV_OPS_MAX_KIOSKS; i++) {
        const ops_kiosk *k = &o->kiosks[i];
        if (!k->conn) {
            continue;
        }
        const char *v = audio ? k->audio : k->lang;
        bool seen = false;
        for (int j = 0; j < i && !seen; j++) {
            seen = o->kiosks[j].conn && !strcmp(v, audio ? o->kiosks[j].audio : o->kiosks[j].lang);
        }
        if (!seen) {
            cJSON_AddItemToArray(a, cJSON_CreateString(v));
        }
    }
    return a;
}

char *srv_ops_status(void *user, size_t *len)
{
    srv_ops *o = user;
    static const char *const roles[NET_ROLE_COUNT] = { "connecting", "viewer", "kiosk",
                                                       "wall-tile", "load" };
    const time_t now = time(NULL);
    const double now_s = mono_s();
    cJSON *j = cJSON_CreateObject();
    if (!j) {
        return NULL;
    }
    pthread_mutex_lock(&o->lock);
    const bool open = atomic_load(&o->open);
    cJSON_AddStringToObject(j, "state", open ? "open" : "closed");
    cJSON *cl = cJSON_AddObjectToObject(j, "clients");
    const net_metrics *m = net_get_metrics(o->net);
    int total = 0;
    for (int r = 0; cl && r < NET_ROLE_COUNT; r++) {
        const int n = atomic_load(&m->clients[r]);
        json_add_number(cl, roles[r], n);
        total += n;
    }
    json_add_number(cl, "total", total);
    json_add_number(j, "uptime_s", (double)(long long)(now_s - o->start_mono_s));
    char t[32];
    iso_utc(o->start_wall, t, sizeof t);
    cJSON_AddStringToObject(j, "started_utc", t);
    json_add_number(j, "tick", o->tick ? atomic_load(o->tick) : 0);
    if (o->any) {
        cJSON *li = cJSON_AddObjectToObject(j, "last_interaction");
        iso_utc(o->last_wall, t, sizeof t);
        cJSON_AddStringToObject(li, "utc", t);
        json_add_number(li, "ago_s", (double)(long long)(now_s - o->last_mono_s));
    } else {
        cJSON_AddNullToObject(j, "last_interaction");
    }
    cJSON_AddItemToObject(j, "languages", distinct(o, false));
    cJSON_AddItemToObject(j, "audio", distinct(o, true));
    cJSON *ks = cJSON_AddArrayToObject(j, "kiosks");
    for (int i = 0; ks && i < SRV_OPS_MAX_KIOSKS; i++) {
        if (o->kiosks[i].conn) {
            cJSON *k = cJSON_CreateObject();
            cJSON_AddStringToObject(k, "lang", o->kiosks[i].lang);
            cJSON_AddStringToObject(k, "audio", o->kiosks[i].audio);
            cJSON_AddItemToArray(ks, k);
        }
    }
    cJSON *sc = cJSON_AddObjectToObject(j, "schedule");
    char today[32], at[12] = "";
    ops_hours_today(&o->d.hours, now, today, sizeof today);
    cJSON_AddStringToObject(sc, "today", today);
    cJSON_AddBoolToObject(sc, "open", open);
    if (o->next > now) {
        ops_hours_clock(o->next, at, sizeof at);
        cJSON_AddStringToObject(sc, "next_change", at);
        iso_utc(o->next, t, sizeof t);
        cJSON_AddStringToObject(sc, "next_change_utc", t);
        json_add_number(sc, "next_in_s", (double)(long long)difftime(o->next, now));
    } else {
        cJSON_AddNullToObject(sc, "next_change");
    }
    struct tm tm;
    localtime_r(&now, &tm);
    strftime(t, sizeof t, "%H:%M:%S %Z", &tm);
    cJSON_AddStringToObject(sc, "local_time", t);
    ops_usage v = o->u;
    ops_usage_end(&v); /* the session under way counts what it has so far */
    const bool in_session = o->u.in_session;
    pthread_mutex_unlock(&o->lock);
    char *ut = ops_usage_json(&v);
    cJSON *u = ut ? cJSON_Parse(ut) : NULL;
    free(ut);
    if (u) {
        cJSON_DeleteItemFromObjectCaseSensitive(u, "format");
        cJSON_DeleteItemFromObjectCaseSensitive(u, "version");
        cJSON_AddBoolToObject(u, "session_under_way", in_session);
        cJSON_AddItemToObject(j, "usage", u);
    }
    char *text = cJSON_PrintUnformatted(j);
    cJSON_Delete(j);
    *len = text ? strlen(text) : 0;
    return text;
}

char *srv_ops_metrics(void *user, size_t *len)
{
    srv_ops *o = user;
    const size_t cap = 16384;
    char *t = malloc(cap);
    *len = 0;
    if (!t) {
        return NULL;
    }
    pthread_mutex_lock(&o->lock);
    size_t n = 0;
    bool ok = ops_usage_prom(&o->u, t, cap, &n);
    const bool open = atomic_load(&o->open);
    pthread_mutex_unlock(&o->lock);
    int k = ok ? snprintf(t + n, cap - n,
                          "# HELP gale_open 1 while the opening hours hold the exhibit open, 0 "
                          "while it is closed (the simulation idles)\n"
                          "# TYPE gale_open gauge\ngale_open %d\n", open)
               : -1;
    if (k < 0 || (size_t)k >= cap - n) {
        free(t);
        return NULL;
    }
    *len = n + (size_t)k;
    return t;
}
