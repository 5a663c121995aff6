/* The running scenario and what changes it (server/SERVER.md "Scenarios"): the scene's
 * playlist played in turn and looping, a kiosk's pick of any scenario of the library, the
 * way back to the playlist (a kiosk's "", its idle time, a reset). Every start of a
 * scenario is a fresh one: its timeline restarted, the forest healed (the storm acts on
 * a whole forest, as after a restart), the dial dropped, and the weather's 3-s gust
 * window started over (a gust of the scenario before is not this one's). The lws thread
 * (kiosk commands) and the sim thread (the playlist's turns) both call these under
 * scen_lock; the sim thread takes the new scenario's force balls at its next tick. */
#include "srv_int.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void srv_weather_jumped_locked(srv *s)
{
    s->wx_reset_due = true;
}

/* Starts `to` (NULL: the scene's steady inflow) at server time t_s. */
static void start_locked(srv *s, scenario *to, double t_s, const char *why)
{
    s->scen = to;
    if (to) {
        scenario_restart(to, t_s);
    }
    s->entry_t_s = t_s;
    srv_heal(s);
    srv_release_dial_locked(s, why);
    srv_weather_jumped_locked(s);
}

int srv_scen_pick_locked(srv *s, const char *name, double t_s, char *why, size_t why_cap)
{
    const scen_lib *l = s->d.lib;
    int k = l ? scen_lib_find(l, name) : -1;
    scenario *to = k >= 0 ? l->e[k].scen : NULL;
    if (!to && s->scen && scen_lib_same_name(name, scenario_name(s->scen))) {
        to = s->scen; /* a --scenario file outside the library restarts */
    }
    if (!to) {
        /* the reason holds what fits of the names (a close reason is short); the log and
         * gale-ctl scenarios give them all */
        char names[1024];
        if (l && l->n > 0) {
            scen_lib_names(l, names, sizeof names);
        } else {
            snprintf(names, sizeof names, "none (no scenarios folder)");
        }
        int at = snprintf(why, why_cap, "wind.scenario: \"%.40s\": unknown; one of: ", name);
        if (at > 0 && (size_t)at < why_cap) {
            scen_lib_names_cut(names, why + at, why_cap - (size_t)at);
        }
        fprintf(stderr, "gale-server: wind.scenario \"%.63s\" refused: the scenarios are %s\n",
                name, names);
        return WIRE_CLOSE_BAD_FIELD;
    }
    s->picked = true;
    start_locked(s, to, t_s, "scenario picked");
    fprintf(stderr, "gale-server: scenario %s (picked by a kiosk)\n", scenario_name(to));
    return 0;
}

void srv_playlist_resume_locked(srv *s, double t_s)
{
    if (!s->picked) {
        return;
    }
    s->picked = false;
    scenario *to = s->n_playlist > 0 ? s->playlist[s->pl_at] : s->head;
    start_locked(s, to, t_s, "back to the playlist");
    fprintf(stderr, "gale-server: scenario %s (the playlist)\n",
            to ? scenario_name(to) : "none");
}

void srv_reset_locked(srv *s, double t_s)
{
    s->picked = false;
    s->pl_at = 0;
    start_locked(s, s->head, t_s, "reset");
    fprintf(stderr, "gale-server: reset: the forest healed, scenario %s from its start\n",
            s->head ? scenario_name(s->head) : "none");
}

bool srv_playlist_poll_locked(srv *s, double t_s, const scenario_state *st)
{
    /* a visitor's dial holds the exhibit where they set it: the playlist waits */
    if (s->picked || s->n_playlist == 0 || !s->scen || s->dial_owner) {
        return false;
    }
    bool steady = scenario_get_kind(s->scen) == SCENARIO_STEADY;
    bool done = steady ? s->n_playlist > 1 && t_s - s->entry_t_s >= SRV_PLAYLIST_STEADY_S
                       : st->finished;
    if (!done) {
        return false;
    }
    s->pl_at = (s->pl_at + 1) % s->n_playlist;
    start_locked(s, s->playlist[s->pl_at], t_s, "the playlist's next scenario");
    fprintf(stderr, "gale-server: scenario %s (playlist entry %d of %d)\n",
            scenario_name(s->scen), s->pl_at + 1, s->n_playlist);
    return true;
}

int srv_scenarios_init(srv *s, gale_err *err)
{
    static const scen_lib none;
    const scen_lib *l = s->d.lib ? s->d.lib : &none;
    if (!s->d.scen && scen_lib_playlist(l, s->d.sc, s->playlist, &s->n_playlist, err)) {
        return err && err->code ? err->code : GALE_E_RANGE;
    }
    /* the welcome's list: every scenario of the library */
    _Static_assert(SCEN_LIB_MAX <= WIRE_MAX_SCENARIOS, "the library exceeds the welcome");
    if (l->n > 0 && !(s->wscen = calloc((size_t)l->n, sizeof *s->wscen))) {
        return gale_errf(err, GALE_E_NOMEM, "srv_create: no memory for the scenario list");
    }
    for (int i = 0; i < l->n; i++) {
        ctl_scenario_info *w = &s->wscen[i];
        const scenario *sc = l->e[i].scen;
        snprintf(w->name, sizeof w->name, "%s", l->e[i].name);
        /* the title: whole when it fits, else cut at a UTF-8 character boundary;
         * control bytes read as spaces */
        const char *title = scenario_name(sc);
        size_t n = strlen(title);
        if (n >= sizeof w->title) {
            n = sizeof w->title - 1;
            while (n > 0 && ((unsigned char)title[n] & 0xC0u) == 0x80u) {
                n--;
            }
        }
        for (size_t k = 0; k < n; k++) {
            unsigned char ch = (unsigned char)title[k];
            w->title[k] = ch < 0x20 || ch == 0x7f ? ' ' : (char)ch;
        }
        w->kind = scenario_get_kind(sc) == SCENARIO_HURRICANE ? CTL_SCENARIO_REPLAY
                                                              : CTL_SCENARIO_STEADY;
        double u = scenario_steady_ms(sc);
        w->sustained_ms = u > 100.0 ? 100.0f : (float)u;
    }
    s->n_wscen = (uint32_t)l->n;
    s->head = s->n_playlist > 0 ? s->playlist[0] : s->d.scen;
    s->scen = s->head;
    s->entry_t_s = 0.0;
    return GALE_OK;
}
