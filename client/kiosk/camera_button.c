/* The kiosk's camera button: layout, hit-testing and the preset cycle (camera_button.h). */
#include "camera_button.h"

#include <stdio.h>

#include "camera_preset.h"
#include "lang.h"

camera_button_rect camera_button_layout(int fb_w, int fb_h)
{
    camera_button_rect r = { 0 };
    if (fb_w <= 0 || fb_h <= 0) {
        return r;
    }
    const float h = CAMERA_BUTTON_H_FRAC * (float)fb_h;
    const float w = CAMERA_BUTTON_ASPECT * h;
    r.x1 = (float)fb_w - CAMERA_BUTTON_MARGIN_FRAC * (float)fb_h;
    r.x0 = r.x1 - w;
    r.y0 = CAMERA_BUTTON_TOP_FRAC * (float)fb_h;
    r.y1 = r.y0 + h;
    if (r.x0 < 0.0f) { /* a screen narrower than the button: keep it on screen */
        r.x0 = 0.0f;
    }
    return r;
}

bool camera_button_hit(int fb_w, int fb_h, int win_w, int win_h, double x, double y)
{
    if (win_w <= 0 || win_h <= 0) {
        return false;
    }
    camera_button_rect r = camera_button_layout(fb_w, fb_h);
    /* window coordinates to framebuffer pixels (a HiDPI framebuffer is larger) */
    double fx = x * (double)fb_w / (double)win_w, fy = y * (double)fb_h / (double)win_h;
    return fx >= (double)r.x0 && fx < (double)r.x1 && fy >= (double)r.y0 && fy < (double)r.y1;
}

int camera_button_next(int preset)
{
    if (preset < 0 || preset >= CAMERA_PRESET_COUNT - 1) {
        return CAMERA_PRESET_STREET;
    }
    return preset + 1;
}

void camera_button_label(int lang, int preset, char *buf, unsigned cap)
{
    if (preset < 0 || preset >= CAMERA_PRESET_COUNT) {
        snprintf(buf, cap, "%s", lang_text(lang, L_KIOSK_CAMERA));
    } else {
        /* the preset's word in the language: configs/lang's camera.<name> */
        char key[48];
        snprintf(key, sizeof key, "camera.%s", camera_preset_name(preset));
        int k = lang_key_find(key);
        lang_format(buf, cap, lang, L_KIOSK_CAMERA_IS,
                    k >= 0 ? lang_text(lang, k) : camera_preset_name(preset));
    }
}
