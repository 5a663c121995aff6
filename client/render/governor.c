/* The frame-time governor (governor.h). */
#include "governor.h"

#include <math.h>
#include <string.h>

void governor_init(governor *g, double target_ms, bool software, double now_s)
{
    *g = (governor){ .target_ms = target_ms > 0.0 ? target_ms : 0.0,
                     .step = target_ms > 0.0 && software ? GOVERNOR_SOFTWARE_STEP : 0,
                     .hold_until_s = now_s + GOVERNOR_DOWN_HOLD_S };
}

bool governor_frame(governor *g, double frame_ms, double now_s)
{
    if (!(g->target_ms > 0.0) || !(frame_ms >= 0.0) || !isfinite(frame_ms)) {
        return false;
    }
    g->smooth_ms = g->smooth_ms > 0.0
                       ? (1.0 - GOVERNOR_SMOOTH) * g->smooth_ms + GOVERNOR_SMOOTH * frame_ms
                       : frame_ms;
    g->frames++;
    if (now_s < g->hold_until_s || g->frames < GOVERNOR_MIN_FRAMES) {
        return false;
    }
    if (g->smooth_ms > GOVERNOR_DOWN_OVER * g->target_ms && g->step < GOVERNOR_MAX_STEP) {
        g->step++;
        g->hold_until_s = now_s + GOVERNOR_DOWN_HOLD_S;
    } else if (g->smooth_ms < GOVERNOR_UP_UNDER * g->target_ms && g->step > 0) {
        g->step--;
        g->hold_until_s = now_s + GOVERNOR_UP_HOLD_S;
    } else {
        return false;
    }
    /* the frames before the change say nothing of the new step's cost */
    g->smooth_ms = 0.0;
    g->frames = 0;
    g->changes++;
    return true;
}

float governor_lod_scale(const governor *g)
{
    return powf(GOVERNOR_LOD_FACTOR, (float)g->step);
}

float governor_res_scale(const governor *g)
{
    return fmaxf(GOVERNOR_RES_MIN, 1.0f - GOVERNOR_RES_STEP * (float)g->step);
}

bool governor_software_renderer(const char *gl_renderer)
{
    return gl_renderer && (strstr(gl_renderer, "llvmpipe") || strstr(gl_renderer, "softpipe") ||
                           strstr(gl_renderer, "SwiftShader"));
}
