/* gale-client kiosk dialling: the + / - keys of a kiosk move a wind-speed dial and send it
 * as a wind command with the kiosk token (protocol/PROTOCOL.md "Control messages"); the
 * camera button (camera_button.h) and the C key step through the camera presets. */
#include <math.h>
#include <stdio.h>

#include "camera_button.h"
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
    camera_button_label(c->a.camera_preset, label, sizeof label);
    hud_draw_button(c->hud, label, r.x0, r.y0, r.x1, r.y1, fb_w, fb_h);
}
