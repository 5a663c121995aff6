/* gale_render's coarse wind: a 3D texture for the shaders and a CPU copy that falling
 * leaves sample for their drift when they are released. */
#include "render_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int render_set_wind(render *r, const render_wind *w, gale_err *err)
{
    if (!isfinite(w->uniform[0] + w->uniform[1] + w->uniform[2])) {
        return gale_errf(err, GALE_E_RANGE, "render_set_wind: uniform wind not finite");
    }
    memcpy(r->wind_uniform, w->uniform, sizeof r->wind_uniform);
    if (w->nx == 0) {
        memset(r->wind_extent, 0, sizeof r->wind_extent);
        r->wind_n[0] = 0;
        return 0;
    }
    uint64_t cells = (uint64_t)w->nx * w->ny * w->nz;
    if (w->ny == 0 || w->nz == 0 || w->nx > 1024 || w->ny > 1024 || w->nz > 256 || !w->v ||
        !(w->cell[0] > 0.0f) || !(w->cell[1] > 0.0f) || !(w->cell[2] > 0.0f)) {
        return gale_errf(err, GALE_E_RANGE,
                         "render_set_wind: grid %ux%ux%u (<= 1024x1024x256) "
                         "with cell sizes > 0 and data",
                         w->nx, w->ny, w->nz);
    }
    if (r->wind_n[0] != w->nx || r->wind_n[1] != w->ny || r->wind_n[2] != w->nz) {
        float *nv = realloc(r->wind_v, cells * 4 * sizeof(float));
        if (!nv) {
            return gale_errf(err, GALE_E_NOMEM, "render_set_wind: out of memory");
        }
        r->wind_v = nv;
    }
    for (uint64_t c = 0; c < cells; c++) {
        r->wind_v[4 * c] = w->v[3 * c];
        r->wind_v[4 * c + 1] = w->v[3 * c + 1];
        r->wind_v[4 * c + 2] = w->v[3 * c + 2];
        r->wind_v[4 * c + 3] = 0.0f;
    }
    glBindTexture(GL_TEXTURE_3D, r->wind_tex);
    if (r->wind_n[0] != w->nx || r->wind_n[1] != w->ny || r->wind_n[2] != w->nz) {
        glTexImage3D(GL_TEXTURE_3D, 0, GL_RGBA32F, (GLsizei)w->nx, (GLsizei)w->ny, (GLsizei)w->nz,
                     0, GL_RGBA, GL_FLOAT, r->wind_v);
    } else {
        glTexSubImage3D(GL_TEXTURE_3D, 0, 0, 0, 0, (GLsizei)w->nx, (GLsizei)w->ny, (GLsizei)w->nz,
                        GL_RGBA, GL_FLOAT, r->wind_v);
    }
    r->wind_n[0] = w->nx;
    r->wind_n[1] = w->ny;
    r->wind_n[2] = w->nz;
    for (int k = 0; k < 3; k++) {
        r->wind_origin[k] = w->origin[k];
        r->wind_cell[k] = w->cell[k];
        r->wind_extent[k] = w->cell[k] * (float)r->wind_n[k];
    }
    return 0;
}

void render_wind_at(const render *r, const float p[3], float out[3])
{
    memcpy(out, r->wind_uniform, 3 * sizeof(float));
    if (r->wind_n[0] == 0) {
        return;
    }
    uint32_t ijk[3];
    for (int k = 0; k < 3; k++) {
        float c = (p[k] - r->wind_origin[k]) / r->wind_cell[k];
        if (k == 2) {
            /* a slice or a low grid applies at every height: clamp vertically */
            c = fminf(fmaxf(c, 0.0f), (float)r->wind_n[2] - 0.5f);
        }
        if (!(c >= 0.0f) || c >= (float)r->wind_n[k]) {
            return;
        }
        ijk[k] = (uint32_t)c;
    }
    size_t c = ijk[0] + r->wind_n[0] * ((size_t)ijk[1] + r->wind_n[1] * ijk[2]);
    memcpy(out, &r->wind_v[4 * c], 3 * sizeof(float));
}

void render_wind_sample(const render *r, const float p[3], float out[3])
{
    render_wind_at(r, p, out);
}
