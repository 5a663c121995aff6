/* The kiosk's touch panel (issue "touch-friendly kiosk UI"): a wind dial from calm to
 * Category 5 with its bands (protocol/wind_scale.h), a compass ring for the direction the
 * wind comes from, a button per scenario of the welcome, replay controls while a storm
 * replays, a reset button and a tab that hides the panel. Layout, hit-testing and the touch
 * state machine only, no GL (kiosk_ui_draw.c draws it): every size is a fraction of the
 * framebuffer height, so the panel covers the same share of a 720p, 1080p and 4K screen,
 * and it keeps to the bottom edge so the trees stay in view. A touch under GLFW is the
 * left mouse button. */
#ifndef GALE_KIOSK_UI_H
#define GALE_KIOSK_UI_H

#include <stdbool.h>

#include "lang.h"
#include "wire.h"

#define KIOSK_UI_MAX_SCENARIOS ((int)WIRE_MAX_SCENARIOS) /* a welcome lists at most these */
#define KIOSK_UI_NAME_CHARS    64
#define KIOSK_UI_MAX_CONTROLS  (KIOSK_UI_MAX_SCENARIOS + 14)
/* Scenario buttons are laid out in the rows these many take (at least 2): a longer list (a
 * storm library) is shown a page at a time, steady winds first, then the replays oldest
 * first, with Previous / Next buttons, so the panel never grows taller. */
#define KIOSK_UI_SCEN_UNPAGED 12
#define KIOSK_UI_MAX_PAGES KIOSK_UI_MAX_SCENARIOS

/* The dial's scale: from calm to a strong Category 5 (the strongest Atlantic landfalls,
 * e.g. Allen 1980, 165 kt = 85 m/s). */
#define KIOSK_UI_DIAL_MAX_MS 85.0f
#define KIOSK_UI_BANDS       9 /* calm, breeze, strong wind, tropical storm, Cat 1..5 */

/* Replay speeds of the ×1, ×10, ×50 buttons: ×N is N storm seconds per second (×1 is real
 * time), the server's replay_speed as PROTOCOL.md "wind" defines it; the shipped replays
 * run at their time_scale, ×30 to ×120. */
#define KIOSK_UI_SPEEDS 3

/* Sizes [fraction of the framebuffer height]. 9 mm on a 24" 1080p panel is 33 px, 0.03. */
#define KIOSK_UI_MIN_TARGET_FRAC 0.03f
#define KIOSK_UI_BUTTON_H_FRAC   0.062f /* 67 px at 1080p: 18 mm on that panel */
#define KIOSK_UI_PANEL_H_FRAC    0.31f  /* the panel's least height */

enum kiosk_ui_kind {
    KIOSK_UI_DIAL = 0,  /* drag: wind speed */
    KIOSK_UI_COMPASS,   /* drag: where the wind comes from */
    KIOSK_UI_SCENARIO,  /* index: scenario */
    KIOSK_UI_PLAY,      /* pause / resume the replay */
    KIOSK_UI_LANDFALL,  /* jump to the replay's minute 0 */
    KIOSK_UI_SPEED,     /* index: 0..KIOSK_UI_SPEEDS-1 */
    KIOSK_UI_RESET,     /* heal the forest, back to the first scenario */
    KIOSK_UI_COLLAPSE,  /* hide / show the panel */
    KIOSK_UI_LANG,      /* index: the language (lang.h) the kiosk speaks */
    KIOSK_UI_PAGE,      /* index: 0 the previous page of scenarios, 1 the next */
    KIOSK_UI_KIND_COUNT
};

typedef struct kiosk_ui_rect {
    float x0, y0, x1, y1; /* framebuffer pixels, y down, x1 and y1 exclusive */
} kiosk_ui_rect;

typedef struct kiosk_ui_control {
    int kind;  /* enum kiosk_ui_kind */
    int index; /* the scenario or speed; 0 otherwise */
    kiosk_ui_rect r; /* its touch target (the dial's and compass's: their bounding box) */
} kiosk_ui_control;

typedef struct kiosk_ui_scenario {
    char name[KIOSK_UI_NAME_CHARS];  /* what wind.scenario names */
    char title[KIOSK_UI_NAME_CHARS]; /* the button's face */
    bool replay;                     /* a storm replay (else steady) */
} kiosk_ui_scenario;

/* What a touch asks for (kiosk_ui_touch); client_kiosk.c sends it. */
enum kiosk_ui_act {
    KIOSK_UI_ACT_NONE = 0,
    KIOSK_UI_ACT_SPEED,    /* value: wind speed [m/s] */
    KIOSK_UI_ACT_DIR,      /* value: where the wind comes from [deg, clockwise from north] */
    KIOSK_UI_ACT_SCENARIO, /* index: kiosk_ui.scen[index] */
    KIOSK_UI_ACT_PAUSE,    /* value: 1 pause, 0 resume */
    KIOSK_UI_ACT_SEEK,     /* value: storm minute (0 = landfall) */
    KIOSK_UI_ACT_REPLAY_SPEED, /* value: storm seconds per second */
    KIOSK_UI_ACT_RESET,
    KIOSK_UI_ACT_COLLAPSE, /* value: 1 hidden, 0 shown (applied by kiosk_ui_touch) */
    KIOSK_UI_ACT_LANG,     /* index: the language chosen (applied by kiosk_ui_touch) */
    KIOSK_UI_ACT_PAGE,     /* index: the page of scenarios now shown (applied by
                              kiosk_ui_touch; sends nothing) */
};

typedef struct kiosk_ui_action {
    int act;      /* enum kiosk_ui_act */
    int index;
    float value;
    bool dragging; /* SPEED / DIR while the finger is still down (the caller may throttle) */
} kiosk_ui_action;

enum kiosk_ui_phase { KIOSK_UI_DOWN = 0, KIOSK_UI_MOVE, KIOSK_UI_UP };

typedef struct kiosk_ui {
    /* what the server said (kiosk_ui_set_scenarios, kiosk_ui_set_weather) */
    kiosk_ui_scenario scen[KIOSK_UI_MAX_SCENARIOS];
    int n_scen;
    unsigned scen_gen; /* counts changes of the list (what the drawing keeps depends on it) */
    bool have_wx;
    float wind_ms;      /* sustained wind [m/s] of the last WEATHER */
    float dir_from_deg; /* where it comes from [deg, clockwise from north] */
    bool dial_held;     /* a kiosk's dial holds the wind (WIRE_WEATHER_DIAL) */
    bool replay;        /* a storm replays (WIRE_WEATHER_STORM): replay controls shown */
    bool paused;        /* the replay is held (WIRE_WEATHER_PAUSED) */
    float replay_speed; /* storm seconds per second */
    int running;        /* index of the scenario WEATHER names, -1 none */
    /* the panel */
    int lang;           /* the language its words are in (lang.h), as the client shows */
    bool collapsed;
    int page;           /* the page of scenario buttons shown (kiosk_ui_layout clamps it) */
    int n_pages;        /* pages of the last layout; 1 when every button fits */
    int page_start[KIOSK_UI_MAX_PAGES], page_len[KIOSK_UI_MAX_PAGES]; /* into order[] */
    int order[KIOSK_UI_MAX_SCENARIOS]; /* paged: scen[] indices, steady first, then the
                                          replays by the year their title ends with */
    int pressed;        /* control under the finger, -1 none (drawn pressed) */
    float drag_ms;      /* the dial's value while dragged */
    float drag_from_deg;
    char last[KIOSK_UI_NAME_CHARS]; /* face of the last control that acted ("" none) */
    /* what this kiosk dialled (kiosk_ui_message), so a speed keeps the chosen direction
     * and a direction the dialled speed; forgotten on release, scenario and reset */
    bool set_speed, set_dir;
    float set_speed_ms, set_from_deg;
    /* layout for fb_w × fb_h (kiosk_ui_layout) */
    int fb_w, fb_h;
    kiosk_ui_control c[KIOSK_UI_MAX_CONTROLS];
    int n;
    float panel_y0;           /* the panel's top edge [px] (fb_h when collapsed) */
    float dial_cx, dial_cy, dial_r0, dial_r1; /* centre, inner and outer ring radius [px] */
    float comp_cx, comp_cy, comp_r;           /* the compass ring's centre and radius */
} kiosk_ui;

/* No scenarios, no weather, shown, nothing pressed. */
void kiosk_ui_init(kiosk_ui *ui);
/* The scenario buttons (at most KIOSK_UI_MAX_SCENARIOS; names and titles cut to fit). */
void kiosk_ui_set_scenario(kiosk_ui *ui, int i, const char *name, const char *title, bool replay);
void kiosk_ui_set_scenario_count(kiosk_ui *ui, int n);
/* The state the panel shows: wind, direction, running scenario, replay. */
void kiosk_ui_set_weather(kiosk_ui *ui, const wire_weather *w);

/* The controls for a fb_w × fb_h framebuffer into ui->c (those hidden now are left out:
 * the replay row without a replay, everything but the tab when collapsed). */
void kiosk_ui_layout(kiosk_ui *ui, int fb_w, int fb_h);
/* Index in ui->c of the control at framebuffer pixel (x, y), -1 none. The dial answers on
 * its ring (and a little beyond), the compass on its disc. */
int kiosk_ui_hit(const kiosk_ui *ui, float x, float y);
/* A touch at framebuffer pixel (x, y): the pressed state follows the finger; a button acts
 * on release inside it, the dial and compass while dragged and on release. True with *a
 * when it asks for something; a touch that is not on the panel returns false with
 * a->act NONE and leaves the panel as it was (the caller may orbit the camera). */
bool kiosk_ui_touch(kiosk_ui *ui, int phase, float x, float y, kiosk_ui_action *a);
/* Whether a touch is held on a control (so the camera must not take it). */
bool kiosk_ui_busy(const kiosk_ui *ui);

/* The dial's scale: angle [rad, clockwise from straight up] of a speed, and back (angles
 * beyond the sweep clamp to its ends). Each band gets the same share of the sweep. */
float kiosk_ui_dial_angle(float speed_ms);
float kiosk_ui_dial_speed(float angle_rad);
#define KIOSK_UI_DIAL_SWEEP_RAD 4.712389f /* 270°: from lower left over the top to lower right */
/* Band b's lowest speed [m/s] (from wind_scale.h; b == KIOSK_UI_BANDS: the dial's top)
 * and its label ("Calm" ... "Tropical storm", "Cat 1" ... "Cat 5"); -1 / "?" outside. */
float kiosk_ui_band_lower_ms(int b);
const char *kiosk_ui_band_label(int b);
/* Band b's label in a language (lang.h). */
const char *kiosk_ui_band_name(int lang, int b);
/* The band of a speed, 0..KIOSK_UI_BANDS-1. */
int kiosk_ui_band(float speed_ms);
/* The framebuffer pixel on the dial's ring at speed_ms, and the compass ring's pixel for a
 * wind from from_deg (for tests and scripts that touch them). */
void kiosk_ui_dial_point(const kiosk_ui *ui, float speed_ms, float *x, float *y);
void kiosk_ui_compass_point(const kiosk_ui *ui, float from_deg, float *x, float *y);
/* Index in ui->c of the first control of kind (and index), -1 none. */
int kiosk_ui_find(const kiosk_ui *ui, int kind, int index);

/* The speed of speed button i (storm seconds per second), 0 outside. */
float kiosk_ui_speed_x(int i);
/* A button's face into buf (cap bytes): a scenario's title, "Pause" / "Play", ... */
void kiosk_ui_label(const kiosk_ui *ui, const kiosk_ui_control *k, char *buf, unsigned cap);
/* The heading over the scenario buttons ("Choose the weather", paged: "Storm replays 2/3"). */
void kiosk_ui_scen_heading(const kiosk_ui *ui, char *buf, unsigned cap);
/* The panel's state as one line for the headless HUD text ("Panel: wind 45 m/s ..."). */
void kiosk_ui_describe(const kiosk_ui *ui, char *buf, unsigned cap);

/* ---- the control message of an action (kiosk_ui_msg.c; PROTOCOL.md "wind", "reset") -- */

struct ctl_msg;
/* The message a touch's action asks the server for, with the kiosk token, into *m: wind
 * speed (with the direction this kiosk chose, if any), direction (with the speed it
 * dialled, if a dial holds), scenario by name, replay_paused, replay_at_min 0,
 * replay_speed, reset. 0 with *m, or 1 when the action sends nothing (collapse, none).
 * Remembers the dialled speed and direction in ui. */
int kiosk_ui_message(kiosk_ui *ui, const kiosk_ui_action *a, const char *token,
                     struct ctl_msg *m);
/* Forgets what this kiosk dialled (its dial was released). */
void kiosk_ui_forget_dial(kiosk_ui *ui);

#endif
