/* The welcome (protocol/PROTOCOL.md "Control messages", SERVER.md "The welcome") in two
 * parts. The scene part (species, instances, obstacles, scenarios: megabytes of JSON at
 * 100,000 trees, the same for every connection and every role) is encoded once per scene
 * and shared by every connection that gets it (net_shared); the head (protocol,
 * client_id, role, rates, server_us, tick) is encoded at each hello, a few hundred bytes.
 * The encoder writes the head's fields first, so head + scene part is, byte for byte,
 * what ctl_encode makes of the whole welcome. Everything here runs under s->ctl_lock. */
#include "srv_int.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Where the scene part starts in an encoded welcome: the first member after the head. */
static const char SCENE_KEY[] = ",\"species\":";

/* A welcome with the scene's parts; the head's fields are filled by the caller. */
static ctl_welcome welcome_of(const srv *s, ctl_obstacle *obstacles)
{
    ctl_welcome w = { .protocol = WIRE_PROTOCOL_VERSION,
                      .role = CTL_ROLE_VIEWER,
                      .tick_hz = (float)s->d.sc->tick_hz,
                      .snapshot_hz = (float)(s->d.sc->tick_hz / s->ticks_per_snap),
                      .n_species = (uint32_t)s->d.sc->n_species,
                      .species = s->wspecies,
                      .n_instances = (uint32_t)s->d.sc->n_trees,
                      .instances = s->winst,
                      .n_obstacles = (uint32_t)s->d.sc->n_obstacles,
                      .obstacles = obstacles,
                      .n_scenarios = s->n_wscen,
                      .scenarios = s->wscen };
    return w;
}

/* The offset of the scene part in an encoded welcome text[len], or 0 when it has none. */
static size_t scene_at(const char *text, size_t len)
{
    const size_t k = sizeof SCENE_KEY - 1;
    for (size_t i = 0; i + k <= len; i++) {
        if (text[i] == ',' && !memcmp(text + i, SCENE_KEY, k)) {
            return i;
        }
    }
    return 0;
}

int srv_welcome_build(srv *s, gale_err *err)
{
    const uint64_t t0 = mono_ns();
    /* The houses: every scene obstacle fits the wire. */
    _Static_assert(SCENE_MAX_OBSTACLES <= WIRE_MAX_OBSTACLES, "scene obstacles exceed the wire");
    const scene *sc = s->d.sc;
    ctl_obstacle *ob = sc->n_obstacles > 0 ? calloc((size_t)sc->n_obstacles, sizeof *ob) : NULL;
    if (sc->n_obstacles > 0 && !ob) {
        return gale_errf(err, GALE_E_NOMEM, "welcome: out of memory");
    }
    for (int i = 0; i < sc->n_obstacles; i++) {
        memcpy(ob[i].min, sc->obstacles[i].min, sizeof ob[i].min);
        memcpy(ob[i].max, sc->obstacles[i].max, sizeof ob[i].max);
    }
    ctl_msg m = { .type = CTL_WELCOME };
    m.u.welcome = welcome_of(s, ob);
    char *text = NULL;
    size_t len = 0;
    gale_err e;
    int rc = ctl_encode(&m, &text, &len, &e);
    free(ob);
    if (rc) {
        return gale_errf(err, rc, "welcome: %s", e.msg);
    }
    const size_t at = scene_at(text, len);
    net_shared *body = at ? net_shared_create(text + at, len - at) : NULL;
    free(text);
    if (!body) {
        return gale_errf(err, at ? GALE_E_NOMEM : GALE_E_STATE,
                         "welcome: %s", at ? "out of memory" : "no species in the encoded text");
    }
    net_shared_unref(s->wbody); /* connections still sending the last one keep it */
    s->wbody = body;
    s->wstale = false;
    s->wbuilds++;
    s->wbuild_ms = (double)(mono_ns() - t0) * 1e-6;
    return 0;
}

void srv_welcome_stale(srv *s)
{
    s->wstale = true;
}

int srv_welcome(srv *s, const net_peer *p, int ctl_role, char **reply, size_t *len,
                net_shared **tail, char *why, size_t why_cap)
{
    *tail = NULL;
    gale_err e;
    if ((s->wstale || !s->wbody) && srv_welcome_build(s, &e)) {
        snprintf(why, why_cap, "cannot encode the welcome: %s", e.msg);
        return WIRE_CLOSE_BAD_FIELD;
    }
    /* The head: a welcome of one species and nothing else, encoded and cut before its
     * species, so its fields are checked and written as the whole welcome's are. */
    ctl_msg m = { .type = CTL_WELCOME };
    ctl_welcome *w = &m.u.welcome;
    *w = welcome_of(s, NULL);
    w->n_species = 1;
    w->n_instances = 0;
    w->n_obstacles = 0;
    w->n_scenarios = 0;
    w->client_id = p->id;
    w->role = ctl_role;
    w->server_us = mono_us();
    w->tick = atomic_load(&s->simm.current_tick);
    char *head = NULL;
    size_t n = 0;
    if (ctl_encode(&m, &head, &n, &e)) {
        snprintf(why, why_cap, "cannot encode the welcome: %s", e.msg);
        return WIRE_CLOSE_BAD_FIELD;
    }
    n = scene_at(head, n);
    const size_t body_len = net_shared_len(s->wbody);
    if (!n || n + body_len > CTL_MAX_SERVER_BYTES) {
        free(head);
        snprintf(why, why_cap, "cannot encode the welcome: %zu bytes, expected <= %u",
                 n + body_len, CTL_MAX_SERVER_BYTES);
        return WIRE_CLOSE_BAD_FIELD;
    }
    if (p->shared_ok) {
        *reply = head;
        *len = n;
        *tail = net_shared_ref(s->wbody);
        return 0;
    }
    /* a relayed connection's reply travels whole */
    char *whole = realloc(head, n + body_len + 1);
    if (!whole) {
        free(head);
        snprintf(why, why_cap, "cannot encode the welcome: out of memory");
        return WIRE_CLOSE_BAD_FIELD;
    }
    net_shared_copy(s->wbody, whole + n);
    whole[n + body_len] = 0;
    *reply = whole;
    *len = n + body_len;
    return 0;
}

void srv_welcome_fini(srv *s)
{
    net_shared_unref(s->wbody);
    s->wbody = NULL;
}
