/* Camera presets and the attract tour (camera_preset.h). */
#include "camera_preset.h"

#include <math.h>
#include <stdbool.h>
#include <string.h>

static const char *const preset_names[CAMERA_PRESET_COUNT] = { "street", "garden", "roof",
                                                               "aerial", "tour" };

int camera_preset_find(const char *name)
{
    for (int i = 0; i < CAMERA_PRESET_COUNT; i++) {
        if (name && !strcmp(name, preset_names[i])) {
            return i;
        }
    }
    return -1;
}

const char *camera_preset_name(int preset)
{
    return preset >= 0 && preset < CAMERA_PRESET_COUNT ? preset_names[preset] : "?";
}

const char *camera_preset_names(void)
{
    return "street|garden|roof|aerial|tour";
}

/* Centre and radius of the instances in the xy plane. */
static void spread(const ctl_instance *inst, uint32_t n, float c[2], float *radius)
{
    c[0] = c[1] = 0.0f;
    for (uint32_t i = 0; i < n; i++) {
        c[0] += inst[i].pos[0] / (float)n;
        c[1] += inst[i].pos[1] / (float)n;
    }
    *radius = 10.0f;
    for (uint32_t i = 0; i < n; i++) {
        *radius = fmaxf(*radius, hypotf(inst[i].pos[0] - c[0], inst[i].pos[1] - c[1]));
    }
}

/* The instance of a species whose name contains word nearest to c; -1 when none is
 * (any species then). */
static int nearest(const ctl_instance *inst, uint32_t n, const ctl_species *sp, uint32_t n_sp,
                   const char *word, const float c[2])
{
    int best = -1;
    float bd = INFINITY;
    for (int pass = 0; pass < 2 && best < 0; pass++) {
        for (uint32_t i = 0; i < n; i++) {
            uint32_t s = inst[i].species;
            if (pass == 0 && (s >= n_sp || !strstr(sp[s].name, word))) {
                continue;
            }
            float d = hypotf(inst[i].pos[0] - c[0], inst[i].pos[1] - c[1]);
            if (d < bd) {
                bd = d;
                best = (int)i;
            }
        }
    }
    return best;
}

/* Bounds of the instances in y. */
static void y_bounds(const ctl_instance *inst, uint32_t n, float *lo, float *hi)
{
    *lo = INFINITY;
    *hi = -INFINITY;
    for (uint32_t i = 0; i < n; i++) {
        *lo = fminf(*lo, inst[i].pos[1]);
        *hi = fmaxf(*hi, inst[i].pos[1]);
    }
    if (!(*lo <= *hi)) {
        *lo = *hi = 0.0f;
    }
}

void camera_preset_apply(camera *c, int preset, const ctl_instance *inst, uint32_t n_inst,
                         const ctl_species *species, uint32_t n_species)
{
    float ctr[2], radius, ylo, yhi;
    spread(inst, n_inst, ctr, &radius);
    y_bounds(inst, n_inst, &ylo, &yhi);
    float target[3] = { ctr[0], ctr[1], 4.0f };
    float dist = fminf(1.6f * radius + 22.0f, 1500.0f), pitch = -0.52f, yaw = 0.0f;
    bool set_yaw = false;
    if (preset == CAMERA_PRESET_STREET || preset == CAMERA_PRESET_GARDEN) {
        /* from outside the planting, so no other crown stands between eye and tree: the
         * palm nearest the south edge seen from the south, the oak nearest the north
         * edge from the north */
        bool street = preset == CAMERA_PRESET_STREET;
        const float edge[2] = { ctr[0], street ? ylo : yhi };
        int t = nearest(inst, n_inst, species, n_species, street ? "palm" : "oak", edge);
        if (t >= 0) {
            target[0] = inst[t].pos[0];
            target[1] = inst[t].pos[1];
            target[2] = inst[t].pos[2];
        }
        float eye_z = street ? 1.7f : 3.0f, aim_z = street ? 4.5f : 5.5f;
        float off = street ? (target[1] - ylo) + 10.0f : (yhi - target[1]) + 9.0f;
        target[2] += aim_z;
        dist = hypotf(off, aim_z - eye_z);
        pitch = atan2f(aim_z - eye_z, off); /* looking up a little at the crown */
        yaw = street ? 1.5707963f : -1.5707963f; /* looking north / south */
        set_yaw = true;
    } else if (preset == CAMERA_PRESET_ROOF) {
        /* eye about 12 m up, over the roofs (6-9 m), half the block away */
        dist = fminf(0.7f * radius + 20.0f, 200.0f);
        pitch = -asinf(fminf((12.0f - target[2]) / dist, 0.9f));
    } else if (preset == CAMERA_PRESET_AERIAL) {
        pitch = -1.0f;
        dist = fminf(1.9f * radius + 30.0f, 2000.0f);
        target[2] = 0.0f;
    }
    camera_init(c, target, dist);
    c->pitch = pitch;
    if (set_yaw) {
        c->yaw = yaw;
    }
    camera_eye(c, c->eye);
}

void camera_preset_tour(camera *c, double t_s, const ctl_instance *inst, uint32_t n_inst,
                        const ctl_species *species, uint32_t n_species)
{
    double t = t_s > 0.0 ? t_s : 0.0;
    int stop = (int)fmod(floor(t / CAMERA_TOUR_STOP_S), (double)CAMERA_PRESET_TOUR);
    camera_preset_apply(c, stop, inst, n_inst, species, n_species);
    c->yaw += (float)(fmod(t, CAMERA_TOUR_STOP_S) * 0.017453292519943295);
    camera_eye(c, c->eye);
}

/* Trees of inst[] (other than `skip`) standing within 4 m of the sight line from eye to
 * target, in the plane: crowns in the way. */
static uint32_t trees_in_view(const ctl_instance *inst, uint32_t n_inst, uint32_t skip,
                              const float eye[3], const float target[3])
{
    const float dx = target[0] - eye[0], dy = target[1] - eye[1];
    const float len2 = dx * dx + dy * dy;
    uint32_t n = 0;
    for (uint32_t i = 0; i < n_inst && len2 > 0.0f; i++) {
        const float px = inst[i].pos[0] - eye[0], py = inst[i].pos[1] - eye[1];
        const float u = (px * dx + py * dy) / len2;
        if (i == skip || u < 0.0f || u > 0.85f) {
            continue; /* behind the eye, or at the tree itself */
        }
        const float ex = px - u * dx, ey = py - u * dy;
        n += ex * ex + ey * ey < 16.0f;
    }
    return n;
}

uint32_t camera_preset_fall(camera *c, const ctl_instance *inst, uint32_t n_inst,
                            uint32_t tree, float height_m, float fall_az_rad)
{
    if (tree >= n_inst) {
        return UINT32_MAX;
    }
    const float *p = inst[tree].pos, h = height_m > 1.0f ? height_m : 1.0f;
    const float dir[2] = { cosf(fall_az_rad), sinf(fall_az_rad) };
    /* the middle of the arc the stem sweeps, a little above the ground */
    const float target[3] = { p[0] + 0.45f * h * dir[0], p[1] + 0.45f * h * dir[1],
                              p[2] + 0.3f * h };
    /* far enough that the standing tree and the fallen one both fit a 50° view */
    const float dist = 1.1f * h + 5.0f, pitch = -0.2f;
    float best_yaw = 0.0f;
    uint32_t best = UINT32_MAX;
    for (int side = 0; side < 2; side++) {
        const float yaw = fall_az_rad + (side ? -1.5707963f : 1.5707963f);
        const float f[3] = { cosf(pitch) * cosf(yaw), cosf(pitch) * sinf(yaw), sinf(pitch) };
        const float eye[3] = { target[0] - dist * f[0], target[1] - dist * f[1],
                               target[2] - dist * f[2] };
        const uint32_t n = trees_in_view(inst, n_inst, tree, eye, target);
        if (n < best) {
            best = n;
            best_yaw = yaw;
        }
    }
    camera_init(c, target, dist);
    c->pitch = pitch;
    c->yaw = best_yaw;
    return best;
}
