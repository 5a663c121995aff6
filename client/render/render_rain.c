/* Rain streaks and spray of the storm look (storm_fx.h) over the frame: one full-screen
 * pass of shaders/rain.frag, blended, after the scene. Streaks lean along the wind across the view:
 * a drop falling at about 9 m/s (large drops' terminal speed, Gunn & Kinzer 1949) is
 * carried sideways at the wind speed, so the slant dx/dy is wind / 9. */
#include "render_internal.h"

#include <cglm/cglm.h>
#include <string.h>

#define RAIN_FALL_MS   9.0f
#define RAIN_SLANT_MAX 3.0f

void render_rain_draw(render *r, float time_rel)
{
    if (r->fx.rain_layers <= 0 || !(r->fx.rain > 0.0f) || !r->p_rain.id) {
        return;
    }
    /* the camera's right axis in world: row 0 of the view matrix (column-major) */
    float across = r->fx.wind_to[0] * r->view[0] + r->fx.wind_to[1] * r->view[4];
    float slant = across / RAIN_FALL_MS;
    slant = slant > RAIN_SLANT_MAX    ? RAIN_SLANT_MAX
            : slant < -RAIN_SLANT_MAX ? -RAIN_SLANT_MAX
                                      : slant;
    render_set_common(r, &r->p_rain, time_rel, r->desc.fog_dist);
    int layers = r->fx.rain_layers > 3 ? 3 : r->fx.rain_layers;
    float px = (float)r->h / 720.0f;
    glUniform4f(r->p_rain.u_rain, r->fx.rain, slant, (float)layers, px < 0.5f ? 0.5f : px);
    /* spray drifts along the wind: its azimuth pattern turns at the wind across the view
     * over a distance of about 30 m */
    glUniform2f(r->p_rain.u_spray, r->fx.spray, -across / 30.0f);
    mat4 vp, inv;
    memcpy(vp, r->viewproj, sizeof vp);
    /* the subject on screen: the streaks thin within half the frame's height of it */
    vec4 s = { r->subject[0], r->subject[1], r->subject[2], 1.0f }, c;
    glm_mat4_mulv(vp, s, c);
    float clear = r->subject_m > 0.0f && c[3] > 0.0f ? r->fx.subject_clear : 0.0f;
    float sx = clear > 0.0f ? (c[0] / c[3] * 0.5f + 0.5f) * (float)r->w : 0.0f;
    float sy = clear > 0.0f ? (c[1] / c[3] * 0.5f + 0.5f) * (float)r->h : 0.0f;
    glUniform4f(r->p_rain.u_rain_clear, sx, sy, 0.5f * (float)r->h, clear);
    glm_mat4_inv(vp, inv);
    glUniformMatrix4fv(r->p_rain.u_inv_viewproj, 1, GL_FALSE, (float *)inv);
    glDisable(GL_DEPTH_TEST);
    glDepthMask(GL_FALSE);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glBindVertexArray(r->vao_empty);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    r->stats.draw_calls++;
    glDisable(GL_BLEND);
    glDepthMask(GL_TRUE);
    glEnable(GL_DEPTH_TEST);
}
