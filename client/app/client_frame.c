/* gale-client frame: q sampled from the jitter buffer a playout delay behind the server
 * clock, the camera (or a wall tile's off-axis projection), the scene through gale_render
 * and the HUD over it. */
#include <math.h>
#include <stdio.h>

#include "client.h"

static int hud_conn(const client *c, const cli_net_stats *ns)
{
    switch (ns->state) {
    case CLI_NET_LIVE:
        return c->got_state ? HUD_CONN_LIVE : HUD_CONN_WAIT_KEY;
    case CLI_NET_HELLO:
        return HUD_CONN_WAIT_KEY;
    case CLI_NET_BACKOFF:
        return HUD_CONN_RECONNECTING;
    default:
        return HUD_CONN_CONNECTING;
    }
}

/* A text centred across the screen at y [px from the top], broken into lines that fit 90 %
 * of the width (a Spanish caption runs a third longer than the English). */
static void draw_centred(client *c, const char *text, float y, int accent_line, int fb_w,
                         int fb_h)
{
    const hud_font *f = hud_get_font(c->hud);
    char lines[3][HUD_LINE_CHARS];
    int n = hud_wrap(f, text, 0.9f * (float)fb_w, lines, 3);
    const char *ptr[3];
    float w = 0.0f, asc, desc, gap;
    for (int i = 0; i < n; i++) {
        ptr[i] = lines[i];
        w = fmaxf(w, hud_text_width(f, lines[i]));
    }
    hud_font_metrics(f, &asc, &desc, &gap);
    /* the block's last line where a single line stood */
    float y0 = y - (float)(n - 1) * (asc - desc + gap);
    hud_draw_lines(c->hud, ptr, n, accent_line, floorf(0.5f * ((float)fb_w - w) - 10.0f), y0,
                   fb_w, fb_h);
}

int client_frame_draw(client *c, double now, gale_err *err)
{
    double server_now = now;
    jitter_clock_server_time(cli_net_clock(c->net), now, &server_now);
    double render_t = server_now - c->a.delay_s;
    if (c->wg.have_frame) {
        render_t = c->wg.render_t; /* the wall group's instant (client_wall_group.c) */
    }
    c->wg.render_t = render_t;
    if (c->scene_ready && c->jit) {
        uint32_t stride = 0;
        float *staging = render_q_staging(c->r, &stride);
        if (staging && stride == c->stride) {
            /* empty buffer (reconnecting): the staging keeps the last q on screen */
            jitter_sample(c->jit, render_t, staging, NULL);
        }
    }
    int fb_w, fb_h;
    render_size(c->r, &fb_w, &fb_h);
    render_camera rc = { .fov_y_deg = c->cam.fov_y_deg, .z_near = 0.3f, .z_far = 4500.0f };
    camera_eye(&c->cam, rc.eye);
    float f[3];
    camera_forward(&c->cam, f);
    for (int k = 0; k < 3; k++) {
        rc.target[k] = rc.eye[k] + f[k];
    }
    rc.up[2] = 1.0f;
    /* an orbit camera looks at its target (a preset's tree) */
    rc.subject_m = c->cam.mode == CAMERA_ORBIT ? c->cam.distance : 0.0f;
    if (c->a.role == CTL_ROLE_WALL_TILE) {
        rc.matrices = true;
        client_wall_matrices(c, fb_w, fb_h, rc.z_near, rc.z_far, rc.view, rc.proj);
    }
    /* the storm look follows the server's sustained wind (storm_fx.h) */
    storm_fx fx;
    storm_fx_from_weather(c->have_wx ? c->wx.sustained_ms : 0.0f,
                          c->have_wx ? c->wx.dir_from_deg : 0.0f,
                          (storm_fx_quality)c->a.storm_fx, &fx);
    render_set_storm(c->r, &fx);
    client_damage_frame(c, render_t); /* falls and debris under way */
    int rc_frame = render_frame(c->r, &rc, render_t, err);
    if (rc_frame != 0) {
        return rc_frame;
    }
    c->last_stats = render_get_stats(c->r);
    if (c->n_cull < CLIENT_CULL_SAMPLES) {
        c->cull_ms[c->n_cull++] = (float)c->last_stats.cull_ms;
    }
    client_view_update(c, now); /* the stream follows what this frame saw */
    client_audio_frame(c, render_t, now); /* the sound of what this frame shows */
    cli_net_stats ns = cli_net_get_stats(c->net);
    double rtt = jitter_clock_rtt(cli_net_clock(c->net));
    hud_state hs = {
        .have_wind = c->have_wind,
        .wind_ms = c->wind_ms,
        .conn = hud_conn(c, &ns),
        .server = cli_net_server_name(c->net),
        .retry_in_s = fmax(ns.retry_at_s - now, 0.0),
        .detail_step = c->gov.step,
        .attempt = ns.attempt,
        .fps = (float)c->fps,
        .latency_ms = rtt >= 0.0 ? (float)(rtt * 500.0) : -1.0f,
        .delay_ms = (float)(c->a.delay_s * 1e3),
        .frames_bad = ns.frames_bad,
        .trees_held = c->hold.reduced ? c->w.n_instances : 0,
        .trees_scene = c->hold.reduced ? c->hold.n_scene : 0,
        .role = ctl_role_name(c->a.role),
        .lang = c->lang,
        .wx = c->have_wx ? &c->wx : NULL,
        /* camera yaw is counter-clockwise from +x (east); a heading clockwise from north */
        .view_heading_deg = 90.0f - c->cam.yaw * 57.29578f,
    };
    /* a kiosk's panel along the bottom edge: captions go above it */
    float cap_y = 0.92f * (float)fb_h - 24.0f;
    if (c->hud_on && c->a.role == CTL_ROLE_KIOSK && !c->attract.active && !c->closed) {
        /* (attract mode tours the trees with the whole screen; a touch brings it back) */
        client_kiosk_draw_panel(c, fb_w, fb_h);
        /* over the panel's tab (kiosk_ui.c: 0.05 of the height) with a line to spare */
        cap_y = fminf(cap_y, c->kiosk.panel_y0 - 0.055f * (float)fb_h - 2.4f * c->hud_px);
    }
    if (c->hud_on) {
        hud_draw(c->hud, &hs, fb_w, fb_h);
        c->hud_lines = hud_drawn_lines(c->hud, c->hud_text); /* what the visitor reads */
        if (c->have_wx && !c->closed) {
            /* what this wind does, in plain words, along the bottom of the screen */
            const char *cap = caption_for(c->lang, c->wx.ss_class, c->wx.beaufort);
            draw_centred(c, cap, cap_y, -1, fb_w, fb_h);
            if (c->hud_lines < HUD_MAX_LINES) {
                snprintf(c->hud_text[c->hud_lines++], HUD_LINE_CHARS, "%s", cap);
            }
        }
    }
    const char *heard = client_audio_caption(c);
    if (c->hud_on && heard) {
        /* what is heard, a line above what the wind does (client_audio.c) */
        float w = hud_text_width(hud_get_font(c->hud), heard);
        hud_draw_lines(c->hud, &heard, 1, -1, floorf(0.5f * ((float)fb_w - w) - 10.0f),
                       cap_y - 1.6f * c->hud_px, fb_w, fb_h);
        if (c->hud_lines < HUD_MAX_LINES) {
            snprintf(c->hud_text[c->hud_lines++], HUD_LINE_CHARS, "%s", heard);
        }
    }
    if (c->hud_on) {
        client_kiosk_draw_camera_button(c, fb_w, fb_h);
    }
    if (c->hud_on && c->a.role == CTL_ROLE_KIOSK && c->hud_lines < HUD_MAX_LINES) {
        /* the panel's state, for scripts reading the headless HUD text */
        kiosk_ui_describe(&c->kiosk, c->hud_text[c->hud_lines++], HUD_LINE_CHARS);
    }
    if (c->attract.active) {
        /* the attract loop's cards in turn: the invitation to touch, and that water, not
         * wind, takes most lives in a hurricane */
        int card = attract_card(&c->attract, now);
        const char *line =
            lang_text(c->lang, card == ATTRACT_CARD_WATER ? L_ATTRACT_WATER : L_KIOSK_TOUCH);
        draw_centred(c, line, cap_y - 0.12f * (float)fb_h, 0, fb_w, fb_h);
        if (c->hud_lines < HUD_MAX_LINES) {
            snprintf(c->hud_text[c->hud_lines++], HUD_LINE_CHARS, "%s", line);
        }
    }
    if (c->got_state && hs.conn != HUD_CONN_LIVE) {
        /* the last picture stays, dimmed, under a calm word: never a crash or a desktop */
        hud_draw_veil(c->hud, lang_text(c->lang, L_KIOSK_RECONNECTING), fb_w, fb_h);
    } else {
        client_closed_draw(c, fb_w, fb_h);
    }
    return 0;
}
