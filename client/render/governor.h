/* The frame-time governor: which level of detail a frame-time budget affords. Each step
 * down draws the scene's level-of-detail distances closer by GOVERNOR_LOD_FACTOR (more
 * trees thinned and as impostors, fewer modes and mesh detail) and its resolution lower by
 * GOVERNOR_RES_STEP (down to GOVERNOR_RES_MIN: the fill, a software renderer's cost), so
 * a step changes a frame's cost by a good fraction; the governor steps down while the smoothed frame time is well over its
 * target, back up while well under, and waits between steps longer when going up, so it
 * settles rather than flip-flops. A software renderer starts a few steps down. Plain CPU
 * code. */
#ifndef GALE_GOVERNOR_H
#define GALE_GOVERNOR_H

#include <stdbool.h>

#define GOVERNOR_MAX_STEP 6
#define GOVERNOR_SOFTWARE_STEP 3     /* where llvmpipe, softpipe or SwiftShader start */
#define GOVERNOR_LOD_FACTOR 0.75f    /* LOD distances × this per step */
#define GOVERNOR_RES_STEP 0.1f       /* the scene's resolution scale lower by this a step */
#define GOVERNOR_RES_MIN 0.5f
#define GOVERNOR_DOWN_OVER 1.15      /* step down past target × this */
#define GOVERNOR_UP_UNDER 0.6        /* step up under target × this (a step costs ~1/0.75²) */
#define GOVERNOR_DOWN_HOLD_S 1.0     /* after a step down, the next change waits this long */
#define GOVERNOR_UP_HOLD_S 4.0       /* after a step up */
#define GOVERNOR_SMOOTH 0.1          /* weight of a new frame in the smoothed frame time */
#define GOVERNOR_MIN_FRAMES 8u       /* frames of a step measured before it may change */

typedef struct governor {
    double target_ms; /* the frame time to keep under [ms]; 0 = no governing */
    int step;         /* 0 = full detail .. GOVERNOR_MAX_STEP */
    double smooth_ms; /* smoothed frame time; 0 = no frame yet */
    unsigned frames;  /* frames measured since the last change */
    double hold_until_s;
    unsigned changes; /* steps taken, either way */
} governor;

/* target_ms 0 turns it off (step stays 0). software: start at GOVERNOR_SOFTWARE_STEP. */
void governor_init(governor *g, double target_ms, bool software, double now_s);

/* Takes one frame's time; true when the step changed. */
bool governor_frame(governor *g, double frame_ms, double now_s);

/* The level-of-detail distance scale of the current step: GOVERNOR_LOD_FACTOR^step. */
float governor_lod_scale(const governor *g);

/* The scene's resolution scale of the current step: 1 - GOVERNOR_RES_STEP × step, at
 * least GOVERNOR_RES_MIN. */
float governor_res_scale(const governor *g);

/* Whether a GL_RENDERER string names a software renderer. */
bool governor_software_renderer(const char *gl_renderer);

#endif
