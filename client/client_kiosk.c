/* gale-client kiosk dialling: the + / - keys of a kiosk move a wind-speed dial and send it
 * as a wind command with the kiosk token (protocol/PROTOCOL.md "Control messages"). */
#include <math.h>
#include <stdio.h>

#include "client.h"

void client_kiosk_dial(client *c, float delta_ms)
{
    if (c->a.role != CTL_ROLE_KIOSK) {
        return;
    }
    if (c->kiosk_speed_ms == 0.0f && c->have_wind) {
        c->kiosk_speed_ms = c->wind_ms;
    }
    c->kiosk_speed_ms = fminf(fmaxf(c->kiosk_speed_ms + delta_ms, 0.0f), 100.0f);
    ctl_wind w = { .has_speed = true, .speed_ms = c->kiosk_speed_ms };
    snprintf(w.token, sizeof w.token, "%s", c->a.token ? c->a.token : "");
    gale_err err = { 0 };
    if (cli_net_send_wind(c->net, &w, &err) != 0) {
        fprintf(stderr, "gale-client: wind: %s\n", err.msg);
    } else {
        fprintf(stderr, "gale-client: wind dialled to %.0f m/s\n", (double)c->kiosk_speed_ms);
    }
}

void client_kiosk_release(client *c)
{
    if (c->a.role != CTL_ROLE_KIOSK) {
        return;
    }
    ctl_wind w = { .release = true };
    snprintf(w.token, sizeof w.token, "%s", c->a.token ? c->a.token : "");
    gale_err err = { 0 };
    if (cli_net_send_wind(c->net, &w, &err) != 0) {
        fprintf(stderr, "gale-client: release: %s\n", err.msg);
    } else {
        fprintf(stderr, "gale-client: attract mode: dial released, touring the cameras\n");
    }
    c->kiosk_speed_ms = 0.0f;
}
