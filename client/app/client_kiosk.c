/* gale-client kiosk dialling: the touch panel (kiosk_ui.h) and the + / - keys of a kiosk
 * send wind, scenario, replay and reset commands with the kiosk token (protocol/PROTOCOL.md
 * "Control messages"); the camera button (camera_button.h) and the C key step through the
 * camera presets. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "camera_button.h"
#include "client.h"
#include "kiosk_ui_draw.h"
#include "mono.h"

/* Sends the message of a panel action (kiosk_ui_message) and logs it as sent. */
static void send_action(client *c, const kiosk_ui_action *a)
{
    ctl_msg m;
    if (kiosk_ui_message(&c->kiosk, a, c->a.token, &m) != 0) {
        return;
    }
    char text[CTL_MAX_CLIENT_BYTES];
    gale_err err = { 0 };
    if (cli_net_send_ctl(c->net, &m, text, sizeof text, &err) != 0) {
        fprintf(stderr, "gale-client: kiosk: %s\n", err.msg);
    } else {
        fprintf(stderr, "gale-client: kiosk sent %s\n", text);
    }
}

void client_kiosk_dial(client *c, float delta_ms)
{
    if (c->a.role != CTL_ROLE_KIOSK) {
        return;
    }
    if (c->kiosk_speed_ms == 0.0f && c->have_wx) {
        c->kiosk_speed_ms = c->wx.sustained_ms;
    } else if (c->kiosk_speed_ms == 0.0f && c->have_wind) {
        c->kiosk_speed_ms = c->wind_ms;
    }
    c->kiosk_speed_ms =
        fminf(fmaxf(c->kiosk_speed_ms + delta_ms, 0.0f), KIOSK_UI_DIAL_MAX_MS);
    /* the same message as the panel's dial (it keeps a chosen direction) */
    kiosk_ui_action a = { .act = KIOSK_UI_ACT_SPEED, .value = c->kiosk_speed_ms };
    send_action(c, &a);
}

void client_kiosk_release(client *c)
{
    if (c->a.role != CTL_ROLE_KIOSK) {
        return;
    }
    /* the dial dropped and the scene's own scenario or playlist back (scenario ""): a
     * visitor's pick ends with the visitor, not at the server's idle time */
    ctl_msg m = { .type = CTL_WIND };
    m.u.wind.release = true;
    m.u.wind.has_scenario = true;
    snprintf(m.u.wind.token, sizeof m.u.wind.token, "%s", c->a.token ? c->a.token : "");
    char text[CTL_MAX_CLIENT_BYTES];
    gale_err err = { 0 };
    if (cli_net_send_ctl(c->net, &m, text, sizeof text, &err) != 0) {
        fprintf(stderr, "gale-client: release: %s\n", err.msg);
    } else {
        fprintf(stderr, "gale-client: kiosk sent %s\n", text);
        fprintf(stderr, "gale-client: attract mode: dial released, back to the scene's "
                        "scenarios, touring the cameras\n");
    }
    c->kiosk_speed_ms = 0.0f;
    kiosk_ui_forget_dial(&c->kiosk);
}

void client_kiosk_camera_next(client *c)
{
    if (c->a.role == CTL_ROLE_WALL_TILE) {
        return; /* every tile shows the wall's one camera */
    }
    c->a.camera_preset = camera_button_next(c->a.camera_preset);
    if (c->scene_ready) {
        client_scene_reset_camera(c); /* the tour moves on from there in the main loop */
    }
    fprintf(stderr, "gale-client: camera %s\n", camera_preset_name(c->a.camera_preset));
}

void client_kiosk_draw_camera_button(client *c, int fb_w, int fb_h)
{
    if (c->a.role != CTL_ROLE_KIOSK) {
        return;
    }
    camera_button_rect r = camera_button_layout(fb_w, fb_h);
    char label[32];
    camera_button_label(c->lang, c->a.camera_preset, label, sizeof label);
    hud_draw_button(c->hud, label, r.x0, r.y0, r.x1, r.y1, fb_w, fb_h);
}

void client_kiosk_on_welcome(client *c, const ctl_welcome *w)
{
    int n = (int)w->n_scenarios;
    for (int i = 0; i < n && i < KIOSK_UI_MAX_SCENARIOS; i++) {
        const ctl_scenario_info *s = &w->scenarios[i];
        kiosk_ui_set_scenario(&c->kiosk, i, s->name, s->title, s->kind == CTL_SCENARIO_REPLAY);
    }
    kiosk_ui_set_scenario_count(&c->kiosk, n);
    if (c->have_wx) {
        kiosk_ui_set_weather(&c->kiosk, &c->wx);
    }
    client_kiosk_send_state(c);
}

void client_kiosk_send_state(client *c)
{
    if (c->a.role != CTL_ROLE_KIOSK) {
        return;
    }
    /* the language shown and the audio output, for the staff's /status and the counters */
    ctl_msg m = { .type = CTL_KIOSK_STATE };
    snprintf(m.u.kiosk_state.token, sizeof m.u.kiosk_state.token, "%s", c->a.token ? c->a.token : "");
    snprintf(m.u.kiosk_state.lang, sizeof m.u.kiosk_state.lang, "%s", lang_code(c->lang));
    snprintf(m.u.kiosk_state.audio, sizeof m.u.kiosk_state.audio, "%s", client_audio_device_name(c));
    char text[CTL_MAX_CLIENT_BYTES];
    gale_err err = { 0 };
    if (cli_net_send_ctl(c->net, &m, text, sizeof text, &err) != 0) {
        fprintf(stderr, "gale-client: kiosk_state: %s\n", err.msg);
    }
}

bool client_kiosk_touch(client *c, int phase, float x, float y)
{
    if (c->a.role != CTL_ROLE_KIOSK || !c->hud_on || c->closed) {
        return false; /* closed: the panel is not shown */
    }
    kiosk_ui_action a;
    bool busy = kiosk_ui_busy(&c->kiosk);
    bool acted = kiosk_ui_touch(&c->kiosk, phase, x, y, &a);
    bool took = busy || kiosk_ui_busy(&c->kiosk) || acted;
    if (!acted) {
        return took;
    }
    double now = mono_s();
    if (a.dragging && now - c->kiosk_drag_sent_s < CLIENT_KIOSK_DRAG_S) {
        return took; /* a drag sends a few values a second, and the last on release */
    }
    if (a.dragging) {
        c->kiosk_drag_sent_s = now;
    }
    if (a.act == KIOSK_UI_ACT_LANG) {
        /* the visitor's language: the next frame speaks it, until idle returns the
         * operator's (main.c) */
        c->lang = a.index;
        fprintf(stderr, "gale-client: kiosk: language %s\n", lang_code(c->lang));
        client_kiosk_send_state(c);
        return took;
    }
    if (a.act == KIOSK_UI_ACT_SPEED) {
        c->kiosk_speed_ms = a.value; /* the + / - keys go on from here */
    } else if (a.act == KIOSK_UI_ACT_SCENARIO || a.act == KIOSK_UI_ACT_RESET) {
        c->kiosk_speed_ms = 0.0f;
    }
    send_action(c, &a);
    return took;
}

void client_kiosk_draw_panel(client *c, int fb_w, int fb_h)
{
    if (c->a.role != CTL_ROLE_KIOSK || !c->hud_on) {
        return;
    }
    if (c->have_wx) {
        kiosk_ui_set_weather(&c->kiosk, &c->wx);
    }
    c->kiosk.lang = c->lang;
    kiosk_ui_layout(&c->kiosk, fb_w, fb_h);
    kiosk_ui_draw(c->hud, &c->kiosk);
}

static int push_touch(client *c, int phase, float x, float y)
{
    if (c->n_touches >= CLIENT_MAX_TOUCHES) {
        fprintf(stderr, "gale-client: --touch: more than %d events\n", CLIENT_MAX_TOUCHES);
        return -1;
    }
    c->touches[c->n_touches++] = (client_touch){ phase, x, y };
    return 0;
}

int client_kiosk_touch_script(client *c, const char *spec)
{
    const char *p = spec;
    int k = 0;
    while (*p) {
        k++;
        while (*p == ' ' || *p == ';') {
            p++;
        }
        if (!*p) {
            break;
        }
        char verb[8] = "";
        float x = 0.0f, y = 0.0f;
        int used = 0;
        if (strncmp(p, "wait", 4) == 0) {
            p += 4;
            if (push_touch(c, -1, 0.0f, 0.0f) != 0) {
                return -1;
            }
        } else if (sscanf(p, "%7[a-z] %f,%f%n", verb, &x, &y, &used) == 3 &&
                   isfinite(x) && isfinite(y)) {
            p += used;
            int rc = 0;
            if (strcmp(verb, "down") == 0) {
                rc = push_touch(c, KIOSK_UI_DOWN, x, y);
            } else if (strcmp(verb, "move") == 0) {
                rc = push_touch(c, KIOSK_UI_MOVE, x, y);
            } else if (strcmp(verb, "up") == 0) {
                rc = push_touch(c, KIOSK_UI_UP, x, y);
            } else if (strcmp(verb, "tap") == 0) {
                rc = push_touch(c, KIOSK_UI_DOWN, x, y);
                rc = rc ? rc : push_touch(c, KIOSK_UI_UP, x, y);
            } else {
                rc = 1;
            }
            if (rc < 0) {
                return -1;
            }
            if (rc > 0) {
                fprintf(stderr, "gale-client: --touch: event %d: expected down, move, up or tap, "
                                "got \"%s\"\n", k, verb);
                return -1;
            }
        } else {
            fprintf(stderr, "gale-client: --touch: event %d: expected \"down|move|up|tap X,Y\" "
                            "or \"wait\", got \"%.20s\"\n", k, p);
            return -1;
        }
        while (*p == ' ') {
            p++;
        }
        if (*p && *p != ';') {
            fprintf(stderr, "gale-client: --touch: event %d: expected ';' before \"%.20s\"\n", k,
                    p);
            return -1;
        }
    }
    return 0;
}

void client_kiosk_touch_step(client *c)
{
    if (c->next_touch >= c->n_touches) {
        return;
    }
    const client_touch *t = &c->touches[c->next_touch++];
    /* as a window's touch: one that wakes the kiosk is no control */
    if (t->phase == KIOSK_UI_DOWN && client_input_woke(c)) {
        c->touch_woke = true;
        return;
    }
    if (t->phase == KIOSK_UI_UP && c->touch_woke) {
        c->touch_woke = false; /* the lift of the waking touch */
        return;
    }
    if (t->phase >= 0) {
        client_kiosk_touch(c, t->phase, t->x, t->y);
    }
}
