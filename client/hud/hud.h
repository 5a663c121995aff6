/* Client HUD (server/PHYSICS.md "Hurricane scenario": the HUD shows speed and the
 * Saffir–Simpson category): a TrueType font baked into a glyph atlas with stb_truetype, text layout,
 * the HUD's lines (wind in m/s, km/h, mph; category; connection; fps; latency) and one
 * small OpenGL 3.3 pass that draws them over the rendered frame. Its files, one job each:
 * hud_font.c (atlas and layout), hud_format.c (the lines' text), hud_gl.c (program and
 * vertex batch), hud_layer.c (batches kept as pictures), hud_draw.c (the HUD's panels). */
#ifndef GALE_HUD_H
#define GALE_HUD_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "err.h"
#include "wire.h"

#define HUD_DEFAULT_FONT "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"
#define HUD_MAX_GLYPHS   2048 /* glyph quads per frame: the HUD uses ~200 */
#define HUD_MAX_LINES    12
#define HUD_LINE_CHARS   208 /* a caption line (caption.h) fits */

/* ---- font and layout (no GL) -------------------------------------------------------- */

typedef struct hud_font hud_font;

/* Reads a TrueType file and bakes printable ASCII plus ° · – — ± … × − “ ” ’ and the letters of
 * Spanish and Haitian Creole (á é í ó ú ñ ü à è ò ç ¡ ¿ and capitals) at px pixels (em height)
 * into a one-channel atlas. NULL with err on a missing or unreadable font. Free with
 * hud_font_unload. */
hud_font *hud_font_load(const char *ttf_path, float px, gale_err *err);
void hud_font_unload(hud_font *f); /* NULL is a no-op */

/* Pen advance of a UTF-8 string [px], kerning included; characters not in the atlas are
 * drawn (and measured) as '?'. Invalid UTF-8 bytes count as '?'. */
float hud_text_width(const hud_font *f, const char *utf8);

/* Breaks a UTF-8 text into at most max_lines lines at spaces, each no wider than max_w
 * [px] (a word wider than that alone on its line, cut at HUD_LINE_CHARS); returns the
 * count. What does not fit in max_lines is left out. */
int hud_wrap(const hud_font *f, const char *utf8, float max_w, char lines[][HUD_LINE_CHARS],
             int max_lines);

/* Whether every character of a UTF-8 string is among the baked ones (none drawn as '?'). */
bool hud_font_has(const char *utf8);

/* Ascent, descent (negative) and line advance [px]. */
void hud_font_metrics(const hud_font *f, float *ascent, float *descent, float *line_gap);

/* The atlas (owned by f): w × h bytes of coverage, row 0 at the top. */
const uint8_t *hud_font_atlas(const hud_font *f, int *w, int *h);

/* One glyph quad: screen rectangle [px, y down] and atlas texture coordinates. */
typedef struct hud_quad {
    float x0, y0, x1, y1;
    float s0, t0, s1, t1;
} hud_quad;

/* Lays out a string starting at pen (x, baseline y) [px, y down]: writes at most max
 * quads (spaces make none) and returns how many; *pen_x (may be NULL) gets the final pen. */
uint32_t hud_text_quads(const hud_font *f, float x, float y, const char *utf8, hud_quad *q,
                        uint32_t max, float *pen_x);

/* ---- what the HUD says (no GL) ------------------------------------------------------ */

/* Saffir–Simpson class of a 1-minute sustained 10 m wind (protocol/wind_scale.h, counted
 * from tropical storm): -1 tropical depression (≤ 33 kt), 0 tropical storm (34–63 kt),
 * 1..5 hurricane category (64, 83, 96, 113, 137 kt), i.e. wind_scale_ss_class - 1. Speeds
 * are rounded to the nearest knot first. */
int hud_saffir_simpson(float speed_ms);
/* wind_scale_ss_title of a class counted as above: "Tropical depression", "Category 3
 * hurricane"; "?" out of range. */
const char *hud_category_name(int cls);
/* Beaufort force 0..12 of a 10 m wind (wind_scale_beaufort: WMO No. 8 limits, rounded to
 * 0.1 m/s) and its title ("Strong breeze"): what the HUD names a wind below
 * tropical-storm strength, where "tropical depression" would mislabel a breeze on a
 * calm day. */
int hud_beaufort(float speed_ms);
const char *hud_beaufort_name(int force);

enum hud_conn {
    HUD_CONN_CONNECTING = 0,
    HUD_CONN_LIVE,         /* receiving state */
    HUD_CONN_WAIT_KEY,     /* connected, waiting for a keyframe */
    HUD_CONN_RECONNECTING, /* server went away; retrying */
    HUD_CONN_FAILED,
};

typedef struct hud_state {
    bool have_wind;
    float wind_ms;      /* wind speed [m/s] shown */
    int conn;           /* enum hud_conn */
    const char *server; /* "host:port" (borrowed) */
    double retry_in_s;  /* RECONNECTING: seconds to the next attempt */
    uint32_t attempt;   /* RECONNECTING: attempt number */
    float fps;
    float latency_ms;    /* one-way estimate (rtt/2); < 0 = unknown */
    float delay_ms;      /* playout delay */
    int detail_step;     /* the frame-time governor's step down; 0 = full detail */
    uint64_t frames_bad; /* frames dropped as undecodable */
    uint32_t trees_held;  /* a reduced view (CLIENT.md): the trees held, fewer than */
    uint32_t trees_scene; /* the scene's; both 0 when the whole scene is held */
    const char *role;    /* "viewer", "kiosk", "wall-tile" (borrowed) */
    int lang;            /* the language the HUD speaks (lang.h; 0 = English) */
    /* The server's weather (PROTOCOL.md "WEATHER"; borrowed, NULL = none yet): when set,
     * the wind lines, class and storm lines come from it (have_wind and wind_ms are
     * ignored) and hud_draw adds a wind arrow. */
    const wire_weather *wx;
    float view_heading_deg; /* the camera's heading, clockwise from north: the arrow shows
                               the wind relative to the view (up = straight ahead) */
} hud_state;

/* Compass point of a bearing [deg]: "N", "NNE", ... "NNW" (16 points, English). */
const char *hud_compass_point(float bearing_deg);
/* The point's index 0..15 from north clockwise (-1 for a bearing that is not a number),
 * and its name in a language (lang.h; "?" for -1). */
int hud_compass_index(float bearing_deg);
const char *hud_compass_text(int lang, float bearing_deg);

/* The lines of the server's weather (at most 7) in a language (lang.h): wind in the
 * language's units with its gust, class (or Beaufort force below tropical storm),
 * direction, a replay's storm or a steady scenario's name, and the expert line (knots and
 * m/s); the browser's HUD (web/hud_text.js) says the same. Returns the count. */
int hud_format_weather(const wire_weather *w, int lang,
                       char lines[HUD_MAX_LINES][HUD_LINE_CHARS]);

/* ---- units (hud_units.c) -------------------------------------------------------------- */

enum hud_unit { HUD_UNIT_MPH = 0, HUD_UNIT_KMH, HUD_UNIT_KT, HUD_UNIT_MS, HUD_UNIT_COUNT };
#define HUD_UNIT_NO_TOP 1000000L /* the top of Category 5's range: none */

/* A speed [m/s] in a unit, unrounded. */
double hud_unit_value(double ms, int unit);
/* Rounded to a whole unit, half up (a gust, or a wind with no class); 0 for <= 0 or NaN. */
long hud_unit_round(double ms, int unit);
/* NHC's Saffir-Simpson range of a class (wind_scale.h numbering) in a unit, whole units,
 * both ends included (hi HUD_UNIT_NO_TOP for Category 5); -1 out of range. */
int hud_unit_range(int ss_class, int unit, long *lo, long *hi);
/* The whole number shown for a 1-minute sustained wind of class ss_class: rounded, then
 * moved into the class's range in that unit, so it never contradicts the category. */
long hud_unit_sustained(double ms, int unit, int ss_class);
/* "120 mph · 193 km/h" in the language's order (mph first in English, km/h first in
 * Spanish and Creole), each number kept in ss_class's range (ss_class < 0: none). */
int hud_format_speed(int lang, double ms, int ss_class, char *out, size_t cap);
/* The language's first unit alone, rounded: "150 mph" (a gust). */
int hud_format_speed_first(int lang, double ms, char *out, size_t cap);

/* Formats the HUD lines into lines[HUD_MAX_LINES][HUD_LINE_CHARS]; returns the count. */
int hud_format(const hud_state *s, char lines[HUD_MAX_LINES][HUD_LINE_CHARS]);

/* ---- GL pass ------------------------------------------------------------------------ */

typedef struct hud_desc {
    const char *font_path; /* NULL = HUD_DEFAULT_FONT */
    float px;              /* text size [px]; 0 = 18 */
} hud_desc;

typedef struct hud hud;

/* Loads the font and creates the GL objects (shader, atlas texture, vertex buffer); a GL
 * 3.3 core context must be current. NULL with err on failure. */
hud *hud_create(const hud_desc *d, gale_err *err);
void hud_destroy(hud *h); /* NULL is a no-op; the context must still be current */

/* The font hud_create loaded (owned by h). */
const hud_font *hud_get_font(const hud *h);

/* Draws the HUD panel for s in the top-left corner of the bound framebuffer of fb_w × fb_h
 * pixels, alpha-blended, depth test off. The lines' panel is kept on the GPU as a picture
 * (hud_batch_flush_keep) and built again only when its text or the framebuffer changes.
 * No allocation. */
void hud_draw(hud *h, const hud_state *s, int fb_w, int fb_h);

/* The lines of the picture the last hud_draw drew (what a visitor reads) into
 * lines[HUD_MAX_LINES][HUD_LINE_CHARS]; returns their count. */
int hud_drawn_lines(const hud *h, char lines[HUD_MAX_LINES][HUD_LINE_CHARS]);

/* The calm screen of a kiosk that lost its server: the frame under it dimmed to about
 * half and text (e.g. "Reconnecting…") in a panel at its centre. */
void hud_draw_veil(hud *h, const char *text, int fb_w, int fb_h);

/* Draws text lines in a panel at (x, y) [px from the top left]; line accent_line (or none,
 * -1) in the accent colour. */
void hud_draw_lines(hud *h, const char *const *lines, int n, int accent_line, float x, float y,
                    int fb_w, int fb_h);

/* A touch button: a panel filling (x0, y0)-(x1, y1) [px from the top left] with an accent
 * edge and label centred in it, the text sized to the button's height. */
void hud_draw_button(hud *h, const char *label, float x0, float y0, float x1, float y1, int fb_w,
                     int fb_h);

/* ---- shapes and text for other panels (the kiosk's, kiosk_ui_draw.c) ---------------- */

/* A batch of solid shapes and text over a fb_w × fb_h framebuffer: begin, push, flush
 * (which draws them, alpha-blended, depth test off). A push that finds the batch full
 * draws what it holds first. No allocation. */
void hud_batch_begin(hud *h, int fb_w, int fb_h);
void hud_batch_rect(hud *h, float x0, float y0, float x1, float y1, const float rgba[4]);
void hud_batch_tri(hud *h, const float xy[6], const float rgba[4]);
/* Text with its em drawn px pixels high (the atlas scaled), its pen starting at (x, baseline
 * y) less align × its advance (0 left, 0.5 centred, 1 right aligned), under a drop shadow
 * of shadow_rgba (NULL: none). Returns the advance [px]. */
float hud_batch_text(hud *h, float x, float y, float px, const char *utf8, const float rgba[4],
                     float align, const float *shadow_rgba);
/* Advance of utf8 with its em px pixels high. */
float hud_batch_text_width(const hud *h, const char *utf8, float px);
void hud_batch_flush(hud *h);
/* Draws the batch and keeps it on the GPU under key (not 0), so that while nothing it shows
 * changes the caller draws it again with hud_batch_replay instead of building it (a batch
 * drawn in parts is not kept). It is kept as a picture (a texture of its bounding box, drawn
 * as one quad); a hud keeps two, the older replaced by a new one. */
void hud_batch_flush_keep(hud *h, uint64_t key);
/* Draws the batch kept under key over a fb_w × fb_h framebuffer: false (nothing drawn)
 * when the kept one has another key or size. */
bool hud_batch_replay(hud *h, uint64_t key, int fb_w, int fb_h);

#endif
