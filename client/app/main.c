/* gale-client: the thin render client (protocol/PROTOCOL.md). Connects as viewer, kiosk or
 * wall tile, fetches the scene's assets (disk cache by content hash), plays the q stream a
 * fixed delay behind the server through the jitter buffer, draws it with gale_render and a
 * HUD; survives the server going away. This file: args, loop, teardown (client.h). */
#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "mono.h"
#include "client.h"
#include "sound_policy.h"
#include "token_file.h"

static volatile sig_atomic_t quit_flag, shot_flag;

static void on_signal(int sig)
{
    if (sig == SIGUSR1) {
        shot_flag = 1;
    } else {
        quit_flag = 1;
    }
}

static void usage(FILE *f)
{
    fprintf(f,
            "usage: gale-client --url ws://HOST:PORT [--role viewer|kiosk|wall-tile]\n"
            "                   [--size WxH] [--headless --frames N --screenshot FILE.png]\n"
            "options:\n"
            "  --url ws://HOST:PORT   server to connect to (required); wss://HOST:PORT for a\n"
            "                         server with TLS (gale-server --tls-cert)\n"
            "  --tls-ca FILE          wss: trust the certificates of this PEM file (a\n"
            "                         self-signed server's own; default: the system's)\n"
            "  --role R               viewer (default), kiosk (may dial the wind), wall-tile\n"
            "  --size WxH             window or offscreen size, default 1280x720\n"
            "  --headless             render offscreen; no window, no input\n"
            "  --frames N             headless: frames to draw after state arrives (default 60)\n"
            "  --screenshot FILE.png  headless: write the last frame there\n"
            "  --screenshot-every K   headless: also write every Kth frame as PREFIX-N.png\n"
            "                         (N the frame number --frame-log gives it, 6 digits;\n"
            "                         PREFIX: --screenshot without .png, else gale)\n"
            "  --wait S               headless: give up after S s without state (default 30)\n"
            "  --max-fps HZ           draw at most HZ frames a second (0.1..1000; a slow\n"
            "                         renderer's pace; headless default 60)\n"
            "  --token-file F         kiosk token (wind commands): the file's first line\n"
            "                         (gale-server --kiosk-token-file); kept out of the\n"
            "                         process list, where --token T shows to local users\n"
            "  --token T              kiosk token on the command line\n"
            "  --delay MS             playout delay behind server time, default 100\n"
            "  --tile C,R,COLS,ROWS   wall-tile: this tile of a COLS x ROWS wall (0,0 top left)\n"
            "  --bezel F              wall-tile: hidden glass between tiles / tile width (0)\n"
            "  --wall FILE            wall-tile: the wall file (configs/walls/README.md); then\n"
            "                         --tile NAME names this tile and implies --role wall-tile;\n"
            "                         with --role kiosk: this client's camera drives the wall\n"
            "  --list-tiles           with --wall: print the file's tile names and exit\n"
            "  --swap-lock            with --wall: present frame N on the group's \"swap N\"\n"
            "  --rate HZ              with --wall: the group's frame rate (default 60)\n"
            "  --budget MS            with --swap-lock: longest wait for the others (default 8)\n"
            "  --frame-log FILE       one line a presented frame: mono_us server_us_rendered\n"
            "                         frame_no (CLOCK_MONOTONIC at swap, the server time shown)\n"
            "  --cache DIR            asset cache (default $XDG_CACHE_HOME/gale)\n"
            "  --lang CODE            the visitor's language: en (default), es or ht (Haitian\n"
            "                         Creole); a kiosk visitor may choose another, and idle\n"
            "                         returns to this one\n"
            "  --attract S            kiosk: after S s without a touch (default 90) release the\n"
            "                         dial and tour the cameras; a touch wakes it\n"
            "  --camera NAME          street (beside the palms), garden (an oak close up),\n"
            "                         roof, aerial, or tour (each in turn, for attract mode)\n"
            "  --storm-fx Q           storm look from the streamed weather: off, low (one layer\n"
            "                         of rain, the default) or high\n"
            "  --view MODE            follow (the default): ask the server for the trees in\n"
            "                         the camera's view only, few modes past the billboards;\n"
            "                         all: the whole scene at full modes\n"
            "  --max-trees N          hold at most N trees (1..262144): of a scene with more,\n"
            "                         the N nearest the point the camera looks at (the scene's\n"
            "                         centre at first), the others not drawn nor streamed\n"
            "                         (said on stderr and the HUD); default: what the GPU's\n"
            "                         texture buffers and the snapshot memory take\n"
            "  --governor MS|off      keep frames under MS by drawing less detail far off, in\n"
            "                         steps (shown on the HUD's status line); default 33 in\n"
            "                         a window (a software renderer starts 3 steps down),\n"
            "                         off headless\n"
            "  --fullscreen           open fullscreen on the primary monitor (F11 toggles)\n"
            "  --touch SPEC           headless kiosk: touches on its panel, one a frame:\n"
            "                         \"tap X,Y; down X,Y; move X,Y; up X,Y; wait\" (pixels)\n"
            "  --fall-shots T,T,...   headless: frame the first fall seen begin live and write\n"
            "                         PREFIX-fall-S.Ss.png T s after its stem gave way (PREFIX:\n"
            "                         --screenshot without .png, else gale); ends after the last\n"
            "  --audio-out F.wav      headless: write what the speakers would play (48 kHz\n"
            "                         16-bit stereo; 1/60 s a frame, 1/HZ with --max-fps)\n"
            "  --sound on|off         the wind's sound and its captions (default on; headless\n"
            "                         only with --audio-out)\n"
            "  --audio-device PCM     ALSA PCM to play on (default \"default\"); none there:\n"
            "                         the null device, captions only; headless, plays there\n"
            "  --volume DB            master gain, -60..0 dB (default -6)\n"
            "  --volume-max DBFS      the limiter's ceiling: no sample louder, -40..0 (default -1)\n"
            "  --quiet                quiet preset (sensory-friendly hours): volume at most\n"
            "                         -20 dB, ceiling at most -14 dBFS, one-shots 6 dB down\n"
            "  --help                 this text\n"
            "SIGUSR1 writes a screenshot as F12 does (gale-DATE-TIME.png in the working\n"
            "directory).\n"
            "keys: left-drag orbit, right-drag pan, wheel zoom, WASD/QE fly, F11 fullscreen,\n"
            "      F12 or P screenshot, R reset view, C next camera (kiosk: also the Camera\n"
            "      button, top right), kiosk: + / - dial the wind, touch the panel (wind dial,\n"
            "      direction, scenarios, replay, reset; the cursor is hidden), ] / [ the sound\n"
            "      3 dB up / down (back to the default when a kiosk goes idle), Esc quit.\n"
            "Exit status: 0 ok, 2 bad arguments, 3 no state received (headless), 4 kiosk\n"
            "token refused by the server, 5 not one tree of the scene fits in memory, 1 other.\n");
}

/* --tile and --wall belong to wall tiles: refused with another role; --wall alone sets it. */
static int client_args_wall_check(client_args *a, bool role_given)
{
    bool tile_given = a->tile_name || a->tile[2] > 0;
    if (a->wall_path && !role_given) {
        a->role = CTL_ROLE_WALL_TILE;
    }
    /* a kiosk with --wall is the wall's operator: its camera drives the wall */
    if ((tile_given || (a->wall_path && a->role != CTL_ROLE_KIOSK)) &&
        a->role != CTL_ROLE_WALL_TILE) {
        fprintf(stderr, "gale-client: %s: only for wall tiles, but the role is %s (use --role "
                        "wall-tile, or --wall FILE --tile NAME)\n",
                tile_given ? "--tile" : "--wall", ctl_role_name(a->role));
        return -1;
    }
    if (a->tile_name && !a->wall_path) {
        fprintf(stderr, "gale-client: --tile %s: a tile name needs --wall FILE (or give "
                        "C,R,COLS,ROWS)\n", a->tile_name);
        return -1;
    }
    if (a->swap_lock && !a->wall_path) {
        fprintf(stderr, "gale-client: --swap-lock: needs --wall FILE (the group is the wall)\n");
        return -1;
    }
    if (a->list_tiles && !a->wall_path) {
        fprintf(stderr, "gale-client: --list-tiles: needs --wall FILE\n");
        return -1;
    }
    return 0;
}

/* HUD text size [px] for a framebuffer h pixels high: 22 px at 1080p, in proportion
 * above, 18 px at least. */
static float client_hud_px(int h)
{
    return fmaxf(18.0f, 22.0f * (float)h / 1080.0f);
}

/* After a resize (F11 onto a larger monitor): the HUD's font at the new size, when it
 * differs by more than a sixth. */
static void client_hud_rescale(client *c, int fb_h)
{
    if (!c->hud_on || c->wall) {
        return;
    }
    float px = client_hud_px(fb_h), cur = c->hud_px;
    if (fabsf(px - cur) <= cur / 6.0f) {
        return;
    }
    gale_err err = { 0 };
    hud *h = hud_create(&(hud_desc){ .px = px }, &err);
    if (!h) {
        fprintf(stderr, "gale-client: hud at %.0f px: %s (keeping %.0f px)\n", (double)px, err.msg,
                (double)cur);
        return;
    }
    hud_destroy(c->hud);
    c->hud = h;
    c->hud_px = px;
}

static int parse_args(int argc, char **argv, client_args *a)
{
    *a = (client_args){ .role = CTL_ROLE_VIEWER,
                        .width = 1280,
                        .height = 720,
                        .frames = 60,
                        .delay_s = 0.1,
                        .wait_s = 30.0,
                        .rate_hz = 60.0f,
                        .budget_ms = 8,
                        .camera_preset = -1,
                        .storm_fx = STORM_FX_LOW,
                        .governor_ms = -1.0,
                        .volume_db = SOUND_VOLUME_DB,
                        .volume_max_dbfs = SOUND_CEILING_DBFS };
    bool role_given = false;
    for (int i = 1; i < argc; i++) {
        const char *o = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        bool takes = true;
        if (strcmp(o, "--help") == 0 || strcmp(o, "-h") == 0) {
            usage(stdout);
            exit(0);
        } else if (strcmp(o, "--headless") == 0) {
            a->headless = true;
            takes = false;
        } else if (strcmp(o, "--list-tiles") == 0) {
            a->list_tiles = true;
            takes = false;
        } else if (strcmp(o, "--fullscreen") == 0) {
            a->fullscreen = true;
            takes = false;
        } else if (strcmp(o, "--quiet") == 0) {
            a->quiet = true;
            takes = false;
        } else if (strcmp(o, "--swap-lock") == 0) {
            a->swap_lock = true;
            takes = false;
        } else if (strcmp(o, "--frame-log") == 0 && v) {
            a->frame_log = v;
        } else if (strcmp(o, "--rate") == 0 && v) {
            a->rate_hz = (float)atof(v);
            if (!(a->rate_hz >= 1.0f && a->rate_hz <= (float)CTL_WALL_MAX_RATE_HZ)) {
                fprintf(stderr, "gale-client: --rate: expected 1..%d Hz, got \"%s\"\n",
                        CTL_WALL_MAX_RATE_HZ, v);
                return -1;
            }
        } else if (strcmp(o, "--budget") == 0 && v) {
            a->budget_ms = atoi(v);
            if (a->budget_ms < 1 || a->budget_ms > 1000) {
                fprintf(stderr, "gale-client: --budget: expected 1..1000 ms, got \"%s\"\n", v);
                return -1;
            }
        } else if (strcmp(o, "--wall") == 0 && v) {
            a->wall_path = v;
        } else if (!v) {
            fprintf(stderr, "gale-client: %s: expected a value\n", o);
            return -1;
        } else if (strcmp(o, "--url") == 0) {
            a->url = v;
        } else if (strcmp(o, "--role") == 0) {
            role_given = true;
            if (strcmp(v, "viewer") == 0) {
                a->role = CTL_ROLE_VIEWER;
            } else if (strcmp(v, "kiosk") == 0) {
                a->role = CTL_ROLE_KIOSK;
            } else if (strcmp(v, "wall-tile") == 0) {
                a->role = CTL_ROLE_WALL_TILE;
            } else {
                fprintf(stderr,
                        "gale-client: --role: expected viewer|kiosk|wall-tile, got \"%s\"\n", v);
                return -1;
            }
        } else if (strcmp(o, "--size") == 0) {
            a->size_set = true;
            if (sscanf(v, "%dx%d", &a->width, &a->height) != 2 || a->width < 16 || a->height < 16 ||
                a->width > 16384 || a->height > 16384) {
                fprintf(stderr, "gale-client: --size: expected WxH within 16..16384, got \"%s\"\n",
                        v ? v : "");
                return -1;
            }
        } else if (strcmp(o, "--frames") == 0) {
            a->frames = atoi(v);
            if (a->frames < 1) {
                fprintf(stderr, "gale-client: --frames: expected >= 1, got \"%s\"\n", v);
                return -1;
            }
        } else if (strcmp(o, "--fall-shots") == 0) {
            if (client_fall_shots_parse(v, a) != 0) {
                return -1;
            }
        } else if (strcmp(o, "--screenshot") == 0) {
            a->screenshot = v;
        } else if (strcmp(o, "--screenshot-every") == 0) {
            a->shot_every = v ? atoi(v) : 0;
            if (a->shot_every < 1) {
                fprintf(stderr, "gale-client: --screenshot-every: expected >= 1, got \"%s\"\n",
                        v ? v : "");
                return -1;
            }
        } else if (strcmp(o, "--token") == 0) {
            a->token = v;
        } else if (strcmp(o, "--tls-ca") == 0) {
            a->tls_ca = v;
        } else if (strcmp(o, "--token-file") == 0) {
            if (token_file_read("gale-client", v, a->token_buf, sizeof a->token_buf) != 0) {
                return -1;
            }
            a->token = a->token_buf;
        } else if (strcmp(o, "--delay") == 0) {
            a->delay_s = atof(v) * 1e-3;
            if (!(a->delay_s > 0.0 && a->delay_s < 10.0)) {
                fprintf(stderr, "gale-client: --delay: expected 1..9999 ms, got \"%s\"\n", v);
                return -1;
            }
        } else if (strcmp(o, "--max-fps") == 0) {
            a->max_fps = atof(v);
            if (!(a->max_fps >= 0.1 && a->max_fps <= 1000.0)) {
                fprintf(stderr, "gale-client: --max-fps: expected 0.1..1000, got \"%s\"\n", v);
                return -1;
            }
        } else if (strcmp(o, "--wait") == 0) {
            a->wait_s = atof(v);
            if (!(a->wait_s > 0.0)) {
                fprintf(stderr, "gale-client: --wait: expected > 0 s, got \"%s\"\n", v);
                return -1;
            }
        } else if (strcmp(o, "--tile") == 0 && !strchr(v, ',')) {
            a->tile_name = v; /* a tile of --wall FILE */
        } else if (strcmp(o, "--tile") == 0) {
            int *t = a->tile;
            if (sscanf(v, "%d,%d,%d,%d", &t[0], &t[1], &t[2], &t[3]) != 4 || t[2] < 1 || t[3] < 1 ||
                t[0] < 0 || t[1] < 0 || t[0] >= t[2] || t[1] >= t[3]) {
                fprintf(stderr,
                        "gale-client: --tile: expected C,R,COLS,ROWS with C < COLS, R < ROWS, "
                        "got \"%s\"\n",
                        v ? v : "");
                return -1;
            }
        } else if (strcmp(o, "--bezel") == 0) {
            a->bezel = (float)atof(v);
            if (!(a->bezel >= 0.0f && a->bezel < 1.0f)) {
                fprintf(stderr, "gale-client: --bezel: expected 0 <= F < 1, got \"%s\"\n", v);
                return -1;
            }
        } else if (strcmp(o, "--cache") == 0) {
            a->cache_dir = v;
        } else if (strcmp(o, "--attract") == 0) {
            a->attract_s = atof(v);
            if (!(a->attract_s >= 1.0 && a->attract_s <= 86400.0)) {
                fprintf(stderr, "gale-client: --attract: expected 1..86400 s, got \"%s\"\n", v);
                return -1;
            }
        } else if (strcmp(o, "--touch") == 0) {
            a->touch = v;
        } else if (strcmp(o, "--lang") == 0) {
            a->lang = lang_find(v);
            if (a->lang < 0) {
                fprintf(stderr, "gale-client: --lang: expected en, es or ht, got \"%s\"\n", v);
                return -1;
            }
        } else if (strcmp(o, "--camera") == 0) {
            a->camera_preset = camera_preset_find(v);
            if (a->camera_preset < 0) {
                fprintf(stderr, "gale-client: --camera: expected %s, got \"%s\"\n",
                        camera_preset_names(), v);
                return -1;
            }
        } else if (strcmp(o, "--storm-fx") == 0) {
            storm_fx_quality q;
            if (storm_fx_quality_parse(v, &q) != 0) {
                fprintf(stderr, "gale-client: --storm-fx: expected off, low or high, got \"%s\"\n",
                        v);
                return -1;
            }
            a->storm_fx = (int)q;
        } else if (strcmp(o, "--governor") == 0) {
            char *end = NULL;
            double ms = strcmp(v, "off") == 0 ? 0.0 : strtod(v, &end);
            if (strcmp(v, "off") != 0 && (end == v || *end || !(ms > 0.0 && ms <= 10000.0))) {
                fprintf(stderr, "gale-client: --governor: expected a frame time in ms "
                                "(0, 10000] or off, got \"%s\"\n", v);
                return -1;
            }
            a->governor_ms = ms;
        } else if (strcmp(o, "--audio-out") == 0) {
            a->audio_out = v;
        } else if (strcmp(o, "--audio-device") == 0) {
            a->audio_device = v;
        } else if (strcmp(o, "--sound") == 0) {
            if (strcmp(v, "on") != 0 && strcmp(v, "off") != 0) {
                fprintf(stderr, "gale-client: --sound: expected on or off, got \"%s\"\n", v);
                return -1;
            }
            a->sound_off = strcmp(v, "off") == 0;
        } else if (strcmp(o, "--volume") == 0 || strcmp(o, "--volume-max") == 0) {
            char *end = NULL;
            const bool max = strcmp(o, "--volume-max") == 0;
            const double db = strtod(v, &end), lo = max ? -40.0 : -60.0;
            if (end == v || *end || !(db >= lo && db <= 0.0)) {
                fprintf(stderr, "gale-client: %s: expected %s in %.0f..0, got \"%s\"\n", o,
                        max ? "a ceiling in dBFS" : "a gain in dB", lo, v);
                return -1;
            }
            *(max ? &a->volume_max_dbfs : &a->volume_db) = (float)db;
        } else if (strcmp(o, "--max-trees") == 0) {
            char *end = NULL;
            const unsigned long n = strtoul(v, &end, 10);
            if (end == v || *end || v[0] == '-' || n < 1 || n > WIRE_MAX_TREES) {
                fprintf(stderr, "gale-client: --max-trees: expected 1..%u, got \"%s\"\n",
                        WIRE_MAX_TREES, v);
                return -1;
            }
            a->max_trees = (uint32_t)n;
        } else if (strcmp(o, "--view") == 0) {
            if (strcmp(v, "follow") != 0 && strcmp(v, "all") != 0) {
                fprintf(stderr, "gale-client: --view: expected follow or all, got \"%s\"\n", v);
                return -1;
            }
            a->view_all = strcmp(v, "all") == 0;
        } else {
            fprintf(stderr, "gale-client: unknown option \"%s\" (see --help)\n", o);
            return -1;
        }
        if (takes) {
            i++;
        }
    }
    if (client_args_wall_check(a, role_given) != 0) {
        return -1;
    }
    if (!a->url && !a->list_tiles) {
        fprintf(stderr, "gale-client: --url ws://HOST:PORT is required (see --help)\n");
        return -1;
    }
    if (a->tile[2] == 0) {
        a->tile[2] = a->tile[3] = 1;
    }
    if (a->audio_out && !a->headless) {
        fprintf(stderr, "gale-client: --audio-out: only with --headless (a window plays on "
                        "the device)\n");
        return -1;
    }
    return 0;
}

/* The median of n samples (reordered); 0 for none. */
static double median_ms(float *v, uint32_t n)
{
    for (uint32_t i = 1; i < n; i++) { /* insertion sort: a few thousand at most */
        float x = v[i];
        uint32_t j = i;
        for (; j > 0 && v[j - 1] > x; j--) {
            v[j] = v[j - 1];
        }
        v[j] = x;
    }
    return n ? (double)v[n / 2] : 0.0;
}

int main(int argc, char **argv)
{
    client c;
    memset(&c, 0, sizeof c);
    if (parse_args(argc, argv, &c.a) != 0) {
        return 2;
    }
    kiosk_ui_init(&c.kiosk);
    if (c.a.touch && client_kiosk_touch_script(&c, c.a.touch) != 0) {
        return 2;
    }
    int ws = client_wall_setup(&c);
    if (ws != 0) {
        free(c.wall);
        return ws > 0 ? 0 : 2;
    }
    if (c.a.frame_log && !(c.wg.log = fopen(c.a.frame_log, "w"))) {
        fprintf(stderr, "gale-client: --frame-log %s: cannot open for writing\n", c.a.frame_log);
        free(c.wall);
        return 2;
    }
    if (c.wg.log) {
        setvbuf(c.wg.log, NULL, _IOLBF, 0); /* readable while the client runs */
    }
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
    signal(SIGUSR1, on_signal);
    signal(SIGPIPE, SIG_IGN);
    srand((unsigned)time(NULL) ^ (unsigned)getpid());

    int status = 1;
    gale_err err = { 0 };
    c.lang = c.a.lang;
    c.wind_v = calloc((size_t)WIRE_MAX_WIND_SIDE * WIRE_MAX_WIND_SIDE * 3, sizeof(float));
    c.cache = asset_cache_create(&(asset_cache_desc){ .dir = c.a.cache_dir }, &err);
    if (!c.cache) {
        fprintf(stderr, "gale-client: %s (running without a disk cache)\n", err.msg);
        gale_err_clear(&err);
    }
    c.net = cli_net_create(&(cli_net_desc){ .url = c.a.url, .role = c.a.role, .token = c.a.token,
                                            .tls_ca = c.a.tls_ca },
                           &(cli_net_handler){ .user = &c,
                                               .on_welcome = client_stream_on_welcome,
                                               .on_frame = client_stream_on_frame,
                                               .on_lost = client_stream_on_lost,
                                               .on_wall = client_wall_group_on_wall },
                           &err);
    if (!c.net) {
        fprintf(stderr, "gale-client: %s\n", err.msg);
        status = err.code == GALE_E_ARG ? 2 : 1;
        goto done;
    }
    c.r = render_create(&(render_desc){ .width = c.a.width,
                                        .height = c.a.height,
                                        .headless = c.a.headless,
                                        .vsync = true,
                                        .title = "gale" },
                        &err);
    if (!c.r) {
        fprintf(stderr, "gale-client: render: %s\n", err.msg);
        goto done;
    }
    {
        /* headless frames are pictures to compare: drawn at full detail unless asked */
        double target_ms = c.a.governor_ms >= 0.0 ? c.a.governor_ms
                                                  : (c.a.headless ? 0.0 : CLIENT_FRAME_MS);
        const char *gl = (const char *)glGetString(GL_RENDERER);
        governor_init(&c.gov, target_ms, governor_software_renderer(gl), mono_s());
        render_set_lod_scale(c.r, governor_lod_scale(&c.gov));
        render_set_res_scale(c.r, governor_res_scale(&c.gov));
    }
    float hud_px = client_wall_hud_px(&c, client_hud_px(c.a.height));
    c.hud_on = hud_px > 0.0f;
    c.hud_px = c.hud_on ? hud_px : 18.0f;
    c.hud = hud_create(&(hud_desc){ .px = c.hud_px }, &err);
    if (!c.hud) {
        fprintf(stderr, "gale-client: hud: %s\n", err.msg);
        goto done;
    }
    if (client_audio_start(&c) != 0) {
        status = 2;
        goto done;
    }
    const float origin[3] = { 0, 0, 6 };
    camera_init(&c.cam, origin, 60.0f);
    GLFWwindow *win = render_window(c.r);
    if (win) {
        client_input_attach(&c, win);
        if (c.a.fullscreen) {
            client_input_toggle_fullscreen(&c, win);
        }
        if (c.a.role == CTL_ROLE_KIOSK) {
            /* a kiosk shows no pointer; touches (clicks) still arrive */
            glfwSetInputMode(win, GLFW_CURSOR, GLFW_CURSOR_HIDDEN);
        }
    }

    const double start = mono_s();
    attract_init(&c.attract, c.a.attract_s, start);
    c.last_frame_s = start;
    int frames_after_state = 0, fps_frames = 0;
    double state_t0 = -1.0; /* when state first arrived */
    double fps_t0 = start;
    status = 0;
    while (!quit_flag && !(win && glfwWindowShouldClose(win))) {
        double now = mono_s();
        c.leaves_frame = 0;
        cli_net_poll(c.net);
        if (cli_net_get_stats(c.net).state == CLI_NET_REFUSED) {
            /* an operator's error: say what to fix, once, and stop (no retry loop) */
            cli_net_stats ns = cli_net_get_stats(c.net);
            fprintf(stderr,
                    "gale-client: %s refused this kiosk: %s. Give the server's kiosk token "
                    "with --token-file (gale-server --kiosk-token-file sets it); not retrying.\n",
                    cli_net_server_name(c.net), ns.last_error);
            status = 4;
            break;
        }
        if (c.scene_pending) {
            if (client_scene_setup(&c, &err) != 0) {
                if (err.code == GALE_E_NOMEM && client_hold_fewer(&c, err.msg) == 0) {
                    /* fewer trees, the nearest, on this connection: a new one would bring
                       the same scene */
                    gale_err_clear(&err);
                } else if (err.code == GALE_E_NOMEM) {
                    fprintf(stderr,
                            "gale-client: %s: not even %u of the scene's %u trees fit in this "
                            "machine's memory (%s); not retrying.\n",
                            cli_net_server_name(c.net), c.w.n_instances, c.hold.n_scene,
                            err.msg);
                    status = 5;
                    break;
                } else {
                    fprintf(stderr, "gale-client: scene: %s\n", err.msg);
                    gale_err_clear(&err);
                    cli_net_drop(c.net); /* try again on the next connection */
                }
            }
        }
        double dt = now - c.last_frame_s;
        c.last_frame_s = now;
        /* frames counted over half-second windows */
        fps_frames++;
        if (now - fps_t0 >= 0.5) {
            c.fps = fps_frames / (now - fps_t0);
            fps_frames = 0;
            fps_t0 = now;
        }
        if (win) {
            glfwPollEvents();
            client_input_fly(&c, win, (float)fmin(dt, 0.1));
            int w, h, fw, fh;
            glfwGetFramebufferSize(win, &w, &h);
            render_size(c.r, &fw, &fh);
            if (w > 0 && h > 0 && (w != fw || h != fh)) {
                render_resize(c.r, w, h, NULL);
                client_hud_rescale(&c, h);
            }
        }
        /* a window's kiosk, or a headless one a --touch script plays the visitor of */
        if ((win || c.a.touch) && c.a.role == CTL_ROLE_KIOSK && attract_tick(&c.attract, now)) {
            /* nobody at the kiosk: let the scenario's wind return, tour the cameras, speak
             * the operator's language again */
            client_kiosk_release(&c);
            if (c.lang != c.a.lang) {
                c.lang = c.a.lang;
                client_kiosk_send_state(&c);
            }
            c.kiosk.page = 0; /* the next visitor starts at the first page of scenarios */
            client_audio_idle(&c); /* the next visitor starts at the operator's volume */
            c.tour_t0_s = now;
        }
        if (c.attract.active && c.scene_ready) {
            camera_preset_tour(&c.cam, now - c.tour_t0_s, c.w_instances, c.w.n_instances,
                               c.w_species, c.w.n_species);
        } else if (c.a.camera_preset == CAMERA_PRESET_TOUR && c.scene_ready) {
            camera_preset_tour(&c.cam, now - start, c.w_instances, c.w.n_instances, c.w_species,
                               c.w.n_species);
        }
        /* headless: no frame before there is state to draw (llvmpipe frames are slow), nor
         * before the server's weather that follows its keyframe (the HUD names it) */
        if (c.got_state && state_t0 < 0.0) {
            state_t0 = now;
        }
        bool draw = !c.a.headless || (c.got_state && (c.have_wx || now - state_t0 > 1.0));
        if (draw) {
            client_wall_group_begin(&c);
        }
        if (draw && client_frame_draw(&c, now, &err) != 0) {
            fprintf(stderr, "gale-client: frame: %s\n", err.msg);
            status = 1;
            break;
        }
        if (shot_flag && draw) {
            shot_flag = 0;
            c.want_screenshot = true;
        }
        if (c.want_screenshot) {
            char name[64];
            client_input_screenshot_name(name, sizeof name);
            if (render_write_png(c.r, name, &err) == 0) {
                fprintf(stderr, "gale-client: screenshot %s\n", name);
            } else {
                fprintf(stderr, "gale-client: screenshot: %s\n", err.msg);
            }
            c.want_screenshot = false;
        }
        if (draw && c.a.headless && c.a.shot_every > 0 &&
            (frames_after_state + 1) % c.a.shot_every == 0) {
            client_shot_numbered(&c);
        }
        if (draw && c.a.headless && client_fall_shots_step(&c) == 1) {
            break; /* --fall-shots: the last is written */
        }
        if (draw) {
            client_wall_group_before_present(&c);
            render_present(c.r);
            client_wall_group_after_present(&c);
            client_kiosk_touch_step(&c); /* --touch: the panel is laid out now */
            /* the frame's work, from its start to its present (pacing sleeps left out) */
            double done = mono_s();
            if (governor_frame(&c.gov, 1e3 * (done - now), done)) {
                render_set_lod_scale(c.r, governor_lod_scale(&c.gov));
                render_set_res_scale(c.r, governor_res_scale(&c.gov));
                fprintf(stderr, "gale-client: frame %.1f ms against %.1f: detail step %d "
                        "(distances × %.2f, resolution × %.2f)\n",
                        1e3 * (done - now), c.gov.target_ms, c.gov.step,
                        (double)governor_lod_scale(&c.gov), (double)governor_res_scale(&c.gov));
            }
        }
        if (c.a.headless) {
            if (draw && ++frames_after_state >= c.a.frames) {
                break;
            }
            if (!c.got_state && now - start > c.a.wait_s) {
                break;
            }
        }
        /* pace: --max-fps, or ~60 Hz headless so the stream advances between frames (a
         * wall group paces itself); the network thread reads the socket meanwhile */
        const double period = c.a.max_fps > 0.0 ? 1.0 / c.a.max_fps : c.a.headless ? 1.0 / 60.0 : 0.0;
        double spent = mono_s() - now;
        if (!c.wg.have_sync && spent < period && !quit_flag) {
            const double rest = period - spent;
            struct timespec ts = { .tv_sec = (time_t)rest,
                                   .tv_nsec = (long)((rest - (double)(time_t)rest) * 1e9) };
            nanosleep(&ts, NULL); /* a signal ends it early */
        }
    }
    if (c.a.headless && status == 0) { /* (a refused kiosk writes no screenshot) */
        if (c.a.screenshot && render_write_png(c.r, c.a.screenshot, &err) != 0) {
            fprintf(stderr, "gale-client: screenshot: %s\n", err.msg);
            status = 1;
        }
        /* what a visitor would read on the last frame, for scripts (one line each) */
        for (int i = 0; i < c.hud_lines; i++) {
            printf("hud: %s\n", c.hud_text[i]);
        }
        /* and what the last frame drew, the frames' median culling and LOD time */
        const render_stats *st = &c.last_stats;
        printf("render: draw_calls %u triangles %llu trees_full %u trees_thin %u impostors %u "
               "culled %u lod_scale %.3f cull_ms_median %.3f\n",
               st->draw_calls, (unsigned long long)st->triangles, st->trees_full,
               st->trees_thin, st->trees_billboard, st->trees_culled, (double)st->lod_scale,
               median_ms(c.cull_ms, c.n_cull));
        /* and the storm damage it holds (a late joiner's whole state: PROTOCOL.md "FOREST") */
        uint32_t fallen = 0, stripped = 0;
        for (uint32_t t = 0; c.dmg.tree && t < c.dmg.n_trees; t++) {
            fallen += c.dmg.tree[t].fallen != 0;
            stripped += c.dmg.tree[t].level < WIRE_DAMAGE_LEVELS;
        }
        printf("damage: trees %u fallen %u stripped %u branches_broken %u\n", c.dmg.n_trees,
               fallen, stripped, c.dmg.n_broken);
        fflush(stdout);
        if (!c.got_state) {
            cli_net_stats ns = cli_net_get_stats(c.net);
            fprintf(stderr, "gale-client: %s: no state received in %.1f s (%s)\n",
                    cli_net_server_name(c.net), mono_s() - start,
                    ns.last_error[0] ? ns.last_error : "no keyframe");
            status = 3;
        }
    }
    {
        cli_net_stats ns = cli_net_get_stats(c.net);
        double since_s = mono_s() - c.state_t0_s;
        double stream_bps = c.got_state && since_s > 0.0
                                ? (double)(ns.bytes_rx - c.state_bytes0) / since_s
                                : 0.0;
        fprintf(stderr,
                "gale-client: frames ok %llu, bad %llu, gaps %llu, control bad %llu, "
                "tree-count mismatches %llu, connects %u; frames left unread %llu, leaf "
                "seeds left out %llu; views sent %llu; stream %.0f bytes/s; trees held %u "
                "of %u, trees a snapshot %u\n",
                (unsigned long long)ns.frames_ok, (unsigned long long)ns.frames_bad,
                (unsigned long long)ns.frames_gap, (unsigned long long)ns.ctl_bad,
                (unsigned long long)c.frames_mismatch, ns.connects,
                (unsigned long long)ns.inbox_dropped, (unsigned long long)c.leaves_thinned,
                (unsigned long long)c.view.n_sent, stream_bps, c.w.n_instances, c.hold.n_scene,
                c.hold.trees_sent);
    }
done:
    client_audio_stop(&c);
    hud_destroy(c.hud);
    jitter_destroy(c.jit);
    cli_net_destroy(c.net);
    render_destroy(c.r);
    asset_cache_destroy(c.cache);
    free(c.snap);
    free(c.wind_v);
    damage_view_fini(&c.dmg);
    client_damage_free(&c);
    free(c.w_species);
    free(c.w_instances);
    free(c.w_boxes);
    client_hold_free(&c);
    if (c.wall) {
        fprintf(stderr, "gale-client: wall frames presented %llu, skipped %llu, swap timeouts %llu\n",
                (unsigned long long)c.wg.presented, (unsigned long long)c.wg.skipped,
                (unsigned long long)c.wg.swap_timeouts);
    }
    if (c.wg.log) {
        fclose(c.wg.log);
    }
    free(c.wall);
    return status;
}
