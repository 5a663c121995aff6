/* What each of the kiosk panel's actions sends the server (kiosk_ui.h, PROTOCOL.md
 * "wind" and "reset"). */
#include "kiosk_ui.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "ctl.h"

void kiosk_ui_forget_dial(kiosk_ui *ui)
{
    ui->set_speed = false;
    ui->set_dir = false;
}

/* ctl wind.dir_deg is where the wind blows towards, counter-clockwise from +x (east); the
 * panel's is where it comes from, clockwise from north: from = 270° − toward (as the
 * server converts it, server/serve/srv_control.c). */
static float toward_deg(float from_deg)
{
    float d = fmodf(270.0f - from_deg + 720.0f, 360.0f);
    return d >= 360.0f ? 0.0f : d;
}

int kiosk_ui_message(kiosk_ui *ui, const kiosk_ui_action *a, const char *token, ctl_msg *m)
{
    memset(m, 0, sizeof *m);
    m->type = CTL_WIND;
    ctl_wind *w = &m->u.wind;
    snprintf(w->token, sizeof w->token, "%s", token ? token : "");
    switch (a->act) {
    case KIOSK_UI_ACT_SPEED:
        ui->set_speed = true;
        ui->set_speed_ms = fminf(fmaxf(a->value, 0.0f), KIOSK_UI_DIAL_MAX_MS);
        w->has_speed = true;
        w->speed_ms = ui->set_speed_ms;
        /* without a scenario the server takes a missing direction as the scene's */
        if (ui->set_dir) {
            w->has_dir = true;
            w->dir_deg = toward_deg(ui->set_from_deg);
        }
        return 0;
    case KIOSK_UI_ACT_DIR:
        ui->set_dir = true;
        ui->set_from_deg = a->value;
        w->has_dir = true;
        w->dir_deg = toward_deg(a->value);
        if (ui->set_speed) {
            w->has_speed = true;
            w->speed_ms = ui->set_speed_ms;
        }
        return 0;
    case KIOSK_UI_ACT_SCENARIO:
        if (a->index < 0 || a->index >= ui->n_scen) {
            return 1;
        }
        kiosk_ui_forget_dial(ui); /* the server drops the dial for a scenario */
        w->has_scenario = true;
        snprintf(w->scenario, sizeof w->scenario, "%s", ui->scen[a->index].name);
        return 0;
    case KIOSK_UI_ACT_PAUSE:
        w->has_replay_paused = true;
        w->replay_paused = a->value != 0.0f;
        return 0;
    case KIOSK_UI_ACT_SEEK:
        w->has_replay_at = true;
        w->replay_at_min = a->value;
        return 0;
    case KIOSK_UI_ACT_REPLAY_SPEED:
        w->has_replay_speed = true;
        w->replay_speed = a->value;
        return 0;
    case KIOSK_UI_ACT_RESET:
        kiosk_ui_forget_dial(ui);
        memset(m, 0, sizeof *m);
        m->type = CTL_RESET;
        snprintf(m->u.reset.token, sizeof m->u.reset.token, "%s", token ? token : "");
        return 0;
    default:
        return 1;
    }
}
