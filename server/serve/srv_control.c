/* The control protocol on the lws thread (ctl.h, protocol/PROTOCOL.md): hello and the
 * welcome it gets (srv_welcome.c; a kiosk's through the token gate, kiosk_gate.h), the
 * view a connection follows (one snapshot stream per distinct view), kiosk wind commands
 * into the scenario, resync and ping, and display walls' groups (wall_group.h). */
#include "srv_int.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Moves a connection from stream `old` to the stream of view v (lws thread): an equal view
 * already encoded is shared, else a free slot takes it. Returns the new stream, 0 for the
 * shared whole-scene stream (v covers everything, or all SRV_MAX_VIEWS slots are taken). */
static uint32_t view_join(srv *s, uint32_t old, const ctl_view *v)
{
    uint32_t stream = 0;
    pthread_mutex_lock(&s->view_lock);
    for (int k = 0; k < SRV_MAX_VIEWS && old; k++) {
        srv_view *w = &s->views[k];
        if (w->stream == old && --w->users <= 0) {
            w->stream = 0;
            w->users = 0;
        }
    }
    if (v && v->kind != CTL_VIEW_ALL) {
        int free_slot = -1;
        for (int k = 0; k < SRV_MAX_VIEWS && !stream; k++) {
            srv_view *w = &s->views[k];
            if (w->stream && !memcmp(&w->v, v, sizeof *v)) {
                w->users++;
                stream = w->stream;
            } else if (!w->stream && free_slot < 0) {
                free_slot = k;
            }
        }
        if (!stream && free_slot >= 0) {
            s->views[free_slot] = (srv_view){ .v = *v, .stream = ++s->next_stream, .users = 1 };
            stream = s->views[free_slot].stream;
        }
    }
    pthread_mutex_unlock(&s->view_lock);
    return stream;
}

/* A kiosk hello's token through the gate (server/SERVER.md "Kiosk tokens"): 0 to let it
 * in, else WIRE_CLOSE_BAD_TOKEN with the reason in why. */
static int kiosk_hello(srv *s, const net_peer *p, const char *token, char *why, size_t why_cap)
{
    const char *want = s->d.sc->kiosk_token;
    uint64_t wait_us = 0;
    kiosk_gate_verdict v = kiosk_gate_check(&s->kgate, p->addr, token, want, mono_us(), &wait_us);
    if (v == KIOSK_GATE_PASS) {
        return 0;
    }
    if (v == KIOSK_GATE_WAIT) {
        snprintf(why, why_cap, "hello.token: not checked: wrong kiosk tokens from this address; "
                               "retry in %.2f s", (double)wait_us * 1e-6);
    } else if (!want[0]) {
        snprintf(why, why_cap, "hello.token: kiosks are disabled (the server has no kiosk "
                               "token)");
    } else {
        snprintf(why, why_cap, "hello.token: wrong kiosk token");
    }
    return WIRE_CLOSE_BAD_TOKEN;
}

void srv_release_dial_locked(srv *s, const char *why)
{
    if (s->dial_owner) {
        fprintf(stderr, "gale-server: conn %u: kiosk dial released (%s)\n", s->dial_owner, why);
    }
    s->dial_owner = 0;
    if (s->scen) {
        scenario_clear_override(s->scen);
    } else {
        const scene *sc = s->d.sc;
        s->man_inflow = (wind_inflow){ .dir_rad = sc->wind_dir_deg * 0.017453292f,
                                       .u10_ms = sc->wind_u10_ms };
        tick_set_inflow(s->tick, &s->man_inflow);
    }
}

void srv_on_closed(void *user, const net_peer *p)
{
    srv *s = user;
    if (p->stream) {
        view_join(s, p->stream, NULL);
    }
    wall_groups_leave(s->walls, p->id, mono_us());
    if (p->role == NET_ROLE_KIOSK) {
        srv_ops_conn_closed(s->ops, p->id);
    }
    pthread_mutex_lock(&s->scen_lock);
    if (s->dial_owner && s->dial_owner == p->id) {
        /* nobody is left at that kiosk's setting */
        srv_release_dial_locked(s, "its kiosk disconnected");
    }
    pthread_mutex_unlock(&s->scen_lock);
}

void srv_wall_send(void *user, uint32_t conn, const char *text, size_t len)
{
    srv *s = user;
    net_send_text(s->net, conn, text, len);
}

/* The wall messages (wall_group.h): joins and frame reports from wall tiles, the camera
 * from a kiosk. 0 or a close code with why. */
static int wall_control(srv *s, const net_peer *p, const ctl_msg *m, char **reply,
                        size_t *reply_len, char *why, size_t why_cap)
{
    const uint64_t now = mono_us();
    wall_groups_poll(s->walls, now);
    if (m->type == CTL_WALL_CAMERA) {
        if (p->role != NET_ROLE_KIOSK) {
            snprintf(why, why_cap, "wall_camera: only a kiosk may steer a wall (this is a %s)",
                     ctl_role_name(p->role - 1));
            return WIRE_CLOSE_FORBIDDEN;
        }
        return wall_groups_camera(s->walls, &m->u.wall_camera, now, why, why_cap);
    }
    if (p->role != NET_ROLE_WALL) {
        snprintf(why, why_cap, "%s: only for wall tiles (this is a %s)", ctl_type_name(m->type),
                 ctl_role_name(p->role - 1));
        return WIRE_CLOSE_FORBIDDEN;
    }
    if (m->type == CTL_WALL_DRAWN) {
        return wall_groups_drawn(s->walls, p->id, m->u.wall_frame.frame, now, why, why_cap);
    }
    ctl_msg sync = { .type = CTL_WALL_SYNC };
    int rc = wall_groups_join(s->walls, p->id, &m->u.wall_join, now, &sync.u.wall_sync, why,
                              why_cap);
    gale_err e;
    if (!rc && ctl_encode(&sync, reply, reply_len, &e)) {
        snprintf(why, why_cap, "wall_sync: %s", e.msg);
        rc = WIRE_CLOSE_BAD_FIELD;
    }
    return rc;
}

/* A kiosk's (or gale-ctl's) wind command, token checked: dial, direction, release,
 * scenario pick (any of the library, "" back to the playlist), replay seek and speed.
 * 0 or a close code with why. */
static int kiosk_wind(srv *s, const net_peer *p, const ctl_wind *w, char *why, size_t why_cap)
{
    const double t_s = atomic_load(&s->simm.current_tick) / s->d.sc->tick_hz;
    int rc = 0;
    pthread_mutex_lock(&s->scen_lock);
    const bool replay_fields = w->has_replay_at || w->has_replay_speed || w->has_replay_paused;
    if (w->has_scenario && w->scenario[0] && replay_fields) {
        /* replay fields steer the picked scenario: refuse them before a pick of a steady
         * one is made, so a refused command changes nothing */
        const int k = s->d.lib ? scen_lib_find(s->d.lib, w->scenario) : -1;
        if (k >= 0 && scenario_get_kind(s->d.lib->e[k].scen) != SCENARIO_HURRICANE) {
            snprintf(why, why_cap, "wind.replay: \"%.40s\" replays no storm", w->scenario);
            rc = WIRE_CLOSE_BAD_FIELD;
        }
    }
    if (!rc && w->has_scenario && w->scenario[0]) {
        /* a pick is checked and made first: replay fields then steer the new scenario */
        rc = srv_scen_pick_locked(s, w->scenario, t_s, why, why_cap);
        if (!rc) {
            /* counted by the library's name, else the running file's (never the text the
             * kiosk sent) */
            const int k = s->d.lib ? scen_lib_find(s->d.lib, w->scenario) : -1;
            srv_ops_pick(s->ops, k >= 0 ? s->d.lib->e[k].name : scenario_name(s->scen));
        }
    }
    if (!rc && replay_fields &&
        (!s->scen || scenario_get_kind(s->scen) != SCENARIO_HURRICANE)) {
        snprintf(why, why_cap, "wind.replay: this server replays no storm (it runs \"%s\")",
                 s->scen ? scenario_name(s->scen) : "no scenario");
        rc = WIRE_CLOSE_BAD_FIELD;
    }
    if (rc) {
        pthread_mutex_unlock(&s->scen_lock);
        return rc;
    }
    s->dial_last_s = mono_s(); /* any command: the kiosk is in use (attract waits) */
    if (w->release || (w->has_scenario && !w->scenario[0])) {
        srv_release_dial_locked(s, "released by its kiosk");
    }
    if (w->has_scenario && !w->scenario[0]) {
        srv_playlist_resume_locked(s, t_s);
    }
    if (w->has_replay_at || w->has_replay_speed) {
        gale_err e;
        if (scenario_replay_set(s->scen, t_s, w->has_replay_at, w->replay_at_min,
                                w->has_replay_speed, w->replay_speed, &e)) {
            snprintf(why, why_cap, "wind.replay: %s", e.msg);
            rc = WIRE_CLOSE_BAD_FIELD;
        } else if (w->has_replay_at) {
            srv_weather_jumped_locked(s); /* the peak before the jump is another minute's */
        }
    }
    if (!rc && w->has_replay_paused) {
        gale_err e;
        if (scenario_replay_pause(s->scen, t_s, w->replay_paused, &e)) {
            snprintf(why, why_cap, "wind.replay_paused: %s", e.msg);
            rc = WIRE_CLOSE_BAD_FIELD;
        }
    }
    if (w->has_speed) {
        srv_ops_dial(s->ops, w->speed_ms);
    }
    if (w->has_speed || w->has_dir) {
        /* a kept dial (a script's) is no connection's: only a release or the idle time
         * drops it */
        s->dial_owner = w->keep ? SRV_DIAL_KEPT : p->id;
        s->dial_last_s = mono_s();
    }
    if (s->scen) {
        if (w->has_speed) {
            /* the scenario's dial holds a sustained wind in [0, 90] m/s */
            scenario_set_dial(s->scen, w->speed_ms > 90.0f ? 90.0 : (double)w->speed_ms, NULL);
        }
        if (w->has_dir) {
            /* ctl: toward, from +x counter-clockwise; scenario: from, clockwise from
             * north. Coming from θ + 180° (math) is bearing 90° − (θ + 180°). */
            double from = fmod(270.0 - (double)w->dir_deg + 720.0, 360.0);
            scenario_set_direction(s->scen, from, NULL);
        }
    } else if (w->has_speed || w->has_dir) {
        const scene *sc = s->d.sc;
        wind_inflow in = { .dir_rad = (w->has_dir ? w->dir_deg : sc->wind_dir_deg) * 0.017453292f,
                           .u10_ms = w->has_speed ? w->speed_ms : sc->wind_u10_ms };
        tick_set_inflow(s->tick, &in);
        s->man_inflow = in; /* what the weather reports (srv_weather.c) */
    }
    pthread_mutex_unlock(&s->scen_lock);
    return rc;
}

int srv_on_control(void *user, net_peer *p, const char *text, size_t len, char **reply,
                   size_t *reply_len, char *why, size_t why_cap)
{
    srv *s = user;
    ctl_msg m;
    int code = WIRE_CLOSE_BAD_JSON;
    gale_err e;
    if (ctl_decode(text, len, CTL_MAX_CLIENT_BYTES, &m, &code, &e)) {
        snprintf(why, why_cap, "%s", e.msg);
        return code ? code : WIRE_CLOSE_BAD_JSON;
    }
    int rc = 0;
    if (!ctl_from_client(m.type)) {
        /* a known type in the wrong direction is out of order, not unknown (PROTOCOL.md) */
        snprintf(why, why_cap, "type: %s is a server message", ctl_type_name(m.type));
        rc = WIRE_CLOSE_ORDER;
    } else if (m.type == CTL_HELLO) {
        const ctl_hello *h = &m.u.hello;
        if (p->role != NET_ROLE_NONE) {
            snprintf(why, why_cap, "hello: a second hello on one connection");
            rc = WIRE_CLOSE_ORDER;
        } else if (h->protocol != WIRE_PROTOCOL_VERSION) {
            snprintf(why, why_cap, "hello.protocol: expected %d, got %d", WIRE_PROTOCOL_VERSION,
                     h->protocol);
            rc = WIRE_CLOSE_VERSION;
        } else if (h->role == CTL_ROLE_KIOSK && (rc = kiosk_hello(s, p, h->token, why, why_cap))) {
            /* refused: rc and why are set */
        } else {
            rc = srv_welcome(s, p, h->role, reply, reply_len, &p->reply_shared, why, why_cap);
            if (!rc) {
                p->role = h->role + 1; /* NET_ROLE_* follows ctl_role, shifted by NONE */
                p->resync = true;
                p->stream = view_join(s, p->stream, &h->view);
            }
        }
    } else if (p->role == NET_ROLE_NONE) {
        snprintf(why, why_cap, "%s before hello", ctl_type_name(m.type));
        rc = WIRE_CLOSE_ORDER;
    } else if (m.type == CTL_WIND) {
        const ctl_wind *w = &m.u.wind;
        if (p->role != NET_ROLE_KIOSK) {
            snprintf(why, why_cap, "wind: only a kiosk may steer the wind (this is a %s)",
                     ctl_role_name(p->role - 1));
            rc = WIRE_CLOSE_FORBIDDEN;
        } else if (!kiosk_gate_token_eq(w->token, s->d.sc->kiosk_token)) {
            kiosk_gate_count_failure(&s->kgate);
            snprintf(why, why_cap, "wind.token: wrong kiosk token");
            rc = WIRE_CLOSE_BAD_TOKEN;
        } else if (w->has_gust) {
            /* The scenario's gust process has no override (scenario.h dials hold the
             * sustained wind and its direction only): say so rather than ignore it. */
            snprintf(why, why_cap, "wind.gust: not supported (the scenario sets the "
                                   "turbulence); send speed_ms and dir_deg only");
            rc = WIRE_CLOSE_BAD_FIELD;
        } else {
            srv_ops_interaction(s->ops, p->id); /* first: a dial in it counts in its session */
            rc = kiosk_wind(s, p, w, why, why_cap);
        }
    } else if (m.type == CTL_RESET) {
        /* a kiosk's reset: the forest healed, the dial dropped, the playlist's head from
         * its configured start (SERVER.md "Scenarios"); refused to others as wind is */
        if (p->role != NET_ROLE_KIOSK) {
            snprintf(why, why_cap, "reset: only a kiosk may reset the exhibit (this is a %s)",
                     ctl_role_name(p->role - 1));
            rc = WIRE_CLOSE_FORBIDDEN;
        } else if (!kiosk_gate_token_eq(m.u.reset.token, s->d.sc->kiosk_token)) {
            kiosk_gate_count_failure(&s->kgate);
            snprintf(why, why_cap, "reset.token: wrong kiosk token");
            rc = WIRE_CLOSE_BAD_TOKEN;
        } else {
            srv_ops_interaction(s->ops, p->id);
            pthread_mutex_lock(&s->scen_lock);
            srv_reset_locked(s, atomic_load(&s->simm.current_tick) / s->d.sc->tick_hz);
            pthread_mutex_unlock(&s->scen_lock);
        }
    } else if (m.type == CTL_KIOSK_STATE) {
        /* what a kiosk shows and plays through, for /status and the language counts */
        const ctl_kiosk_state *k = &m.u.kiosk_state;
        if (p->role != NET_ROLE_KIOSK) {
            snprintf(why, why_cap, "kiosk_state: only a kiosk reports its state (this is a %s)",
                     ctl_role_name(p->role - 1));
            rc = WIRE_CLOSE_FORBIDDEN;
        } else if (!kiosk_gate_token_eq(k->token, s->d.sc->kiosk_token)) {
            kiosk_gate_count_failure(&s->kgate);
            snprintf(why, why_cap, "kiosk_state.token: wrong kiosk token");
            rc = WIRE_CLOSE_BAD_TOKEN;
        } else {
            srv_ops_kiosk_state(s->ops, p->id, k->lang, k->audio);
        }
    } else if (m.type >= CTL_WALL_JOIN && m.type <= CTL_WALL_CAMERA) {
        rc = wall_control(s, p, &m, reply, reply_len, why, why_cap);
    } else if (m.type == CTL_RESYNC) {
        p->resync = true;
    } else if (m.type == CTL_VIEW) {
        /* the new stream's first frame is a keyframe (net.c: a stream change breaks the
         * delta chain) */
        p->stream = view_join(s, p->stream, &m.u.view);
    } else if (m.type == CTL_PING) {
        ctl_msg pong = { .type = CTL_PONG };
        pong.u.pong.id = m.u.ping.id;
        pong.u.pong.client_us = m.u.ping.client_us;
        pong.u.pong.server_us = mono_us();
        pong.u.pong.tick = atomic_load(&s->simm.current_tick);
        if (ctl_encode(&pong, reply, reply_len, &e)) {
            snprintf(why, why_cap, "pong: %s", e.msg);
            rc = WIRE_CLOSE_BAD_FIELD;
        }
    }
    ctl_msg_fini(&m);
    return rc;
}
