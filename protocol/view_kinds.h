/* Camera views of three kinds, as a landscape's visitors take them, for the benchmarks
 * and load clients that ask the server for many views (gale-bench views, gale-load
 * --views): a street (eye 1.75 m up, 2 degrees up, far 300 m), a roof (12 m, 8 degrees down,
 * 600 m) and an aerial camera (150 m, 30 degrees down, 2,000 m), each 60 degrees wide
 * with the given lod_m. Header-only. */
#ifndef GALE_VIEW_KINDS_H
#define GALE_VIEW_KINDS_H

#include <math.h>
#include <stdint.h>

#include "ctl.h"

enum { VIEW_KIND_STREET, VIEW_KIND_ROOF, VIEW_KIND_AERIAL, VIEW_KINDS };

static inline const char *view_kind_name(int kind)
{
    static const char *const names[VIEW_KINDS] = { "street", "roof", "aerial" };
    return kind >= 0 && kind < VIEW_KINDS ? names[kind] : "?";
}

/* Uniform in [0, 1) from the state *s (xorshift64*; *s nonzero). */
static inline double view_kinds_rand(uint64_t *s)
{
    *s ^= *s >> 12;
    *s ^= *s << 25;
    *s ^= *s >> 27;
    return (double)((*s * 0x2545f4914f6cdd1dull) >> 11) * 0x1.0p-53;
}

/* A view of `kind` with its eye at a random place within half_m of (0, 0) on both axes,
 * a random heading, from the state *rng. */
static inline ctl_view view_kind_make(int kind, uint64_t *rng, double half_m, float lod_m)
{
    static const float eye_z_m[VIEW_KINDS] = { 1.75f, 12.0f, 150.0f };
    static const float pitch_deg[VIEW_KINDS] = { 2.0f, -8.0f, -30.0f };
    static const float far_m[VIEW_KINDS] = { 300.0f, 600.0f, 2000.0f };
    kind = kind >= 0 && kind < VIEW_KINDS ? kind : VIEW_KIND_STREET;
    const double yaw = 2.0 * 3.14159265358979 * view_kinds_rand(rng);
    const double pitch = (double)pitch_deg[kind] * 0.017453292519943295;
    ctl_view v = { .kind = CTL_VIEW_FRUSTUM, .fov_deg = 60.0f, .far_m = far_m[kind],
                   .lod_m = lod_m };
    v.eye[0] = (float)((2.0 * view_kinds_rand(rng) - 1.0) * half_m);
    v.eye[1] = (float)((2.0 * view_kinds_rand(rng) - 1.0) * half_m);
    v.eye[2] = eye_z_m[kind];
    v.dir[0] = (float)(cos(yaw) * cos(pitch));
    v.dir[1] = (float)(sin(yaw) * cos(pitch));
    v.dir[2] = (float)sin(pitch);
    return v;
}

#endif
