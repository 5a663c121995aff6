/* gale-client: the thin render client (DESIGN.md "Data flow", client frame). Connects as
 * viewer, kiosk or wall tile, fetches the scene's assets (disk cache by content hash),
 * plays the q stream a fixed delay behind the server through the jitter buffer, draws it
 * with gale_render and a HUD; survives the server going away. main: args, loop, teardown. */
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

#include "asset.h"
#include "asset_cache.h"
#include "camera.h"
#include "hud.h"
#include "jitter.h"
#include "cli_net.h"
#include "render.h"

#define MAX_SPECIES WIRE_MAX_SPECIES

typedef struct cli_args {
    const char *url;
    int role; /* enum ctl_role */
    int width, height;
    bool headless;
    int frames;             /* headless: frames to draw once state arrives */
    const char *screenshot; /* headless: PNG of the last frame */
    const char *token;      /* kiosk */
    double delay_s;         /* playout delay */
    double wait_s;          /* headless: give up after this long without state */
    int tile[4];            /* wall-tile: col, row, cols, rows */
    float bezel;            /* wall-tile: hidden strip / tile width */
    const char *cache_dir;
} cli_args;

typedef struct cli_species {
    char hash[17];
    int render_id; /* id in gale_render, -1 until loaded */
} cli_species;

typedef struct cli {
    cli_args a;
    cli_net *net;
    render *r;
    hud *hud;
    asset_cache *cache;
    jitter *jit;
    camera cam;

    /* scene of the last welcome (owned copies) */
    bool scene_pending, scene_ready;
    ctl_welcome w;             /* arrays owned below */
    ctl_species *w_species;    /* owned */
    ctl_instance *w_instances; /* owned */
    float *w_boxes;            /* owned: [6 w.n_obstacles] house boxes, min xyz, max xyz */
    cli_species loaded[MAX_SPECIES];
    uint32_t n_loaded;
    int species_id[MAX_SPECIES]; /* welcome index → render id */
    uint32_t stride, n_values;
    float *snap; /* owned: [n_values] scratch for one decoded snapshot */

    /* coarse wind of the last WIND frame */
    float *wind_v; /* owned: [WIRE_MAX_WIND_SIDE² × 3] */
    bool have_wind;
    float wind_ms;
    float kiosk_speed_ms; /* kiosk dial */

    bool got_state;
    bool live_since_welcome;  /* state taken since the last welcome */
    uint64_t frames_mismatch; /* state frames whose tree count disagreed with the scene */
    uint64_t leaves_bad;
    double fps, last_frame_s;
    bool fly_keys;
    double cursor[2];
    int drag; /* 0 none, 1 orbit, 2 pan */
    bool want_screenshot;
    bool fullscreen;
    int win_pos[2], win_size[2];
} cli;

static volatile sig_atomic_t quit_flag;

static void on_signal(int sig)
{
    (void)sig;
    quit_flag = 1;
}

static void usage(FILE *f)
{
    fprintf(f,
            "usage: gale-client --url ws://HOST:PORT [--role viewer|kiosk|wall-tile]\n"
            "                   [--size WxH] [--headless --frames N --screenshot FILE.png]\n"
            "options:\n"
            "  --url ws://HOST:PORT   server to connect to (required)\n"
            "  --role R               viewer (default), kiosk (may dial the wind), wall-tile\n"
            "  --size WxH             window or offscreen size, default 1280x720\n"
            "  --headless             render offscreen; no window, no input\n"
            "  --frames N             headless: frames to draw after state arrives (default 60)\n"
            "  --screenshot FILE.png  headless: write the last frame there\n"
            "  --wait S               headless: give up after S s without state (default 30)\n"
            "  --token T              kiosk token (wind commands)\n"
            "  --delay MS             playout delay behind server time, default 100\n"
            "  --tile C,R,COLS,ROWS   wall-tile: this tile of a COLS x ROWS wall (0,0 top left)\n"
            "  --bezel F              wall-tile: hidden glass between tiles / tile width (0)\n"
            "  --cache DIR            asset cache (default $XDG_CACHE_HOME/gale)\n"
            "  --help                 this text\n"
            "keys: left-drag orbit, right-drag pan, wheel zoom, WASD/QE fly, F11 fullscreen,\n"
            "      F12 or P screenshot, R reset view, kiosk: + / - dial the wind, Esc quit.\n"
            "Exit status: 0 ok, 2 bad arguments, 3 no state received (headless), 1 other.\n");
}

static int parse_args(int argc, char **argv, cli_args *a)
{
    *a = (cli_args){ .role = CTL_ROLE_VIEWER,
                     .width = 1280,
                     .height = 720,
                     .frames = 60,
                     .delay_s = 0.1,
                     .wait_s = 30.0 };
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
        } else if (!v) {
            fprintf(stderr, "gale-client: %s: expected a value\n", o);
            return -1;
        } else if (strcmp(o, "--url") == 0) {
            a->url = v;
        } else if (strcmp(o, "--role") == 0) {
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
            if (sscanf(v, "%dx%d", &a->width, &a->height) != 2 || a->width < 16 || a->height < 16 ||
                a->width > 16384 || a->height > 16384) {
                fprintf(stderr, "gale-client: --size: expected WxH within 16..16384, got \"%s\"\n",
                        v);
                return -1;
            }
        } else if (strcmp(o, "--frames") == 0) {
            a->frames = atoi(v);
            if (a->frames < 1) {
                fprintf(stderr, "gale-client: --frames: expected >= 1, got \"%s\"\n", v);
                return -1;
            }
        } else if (strcmp(o, "--screenshot") == 0) {
            a->screenshot = v;
        } else if (strcmp(o, "--token") == 0) {
            a->token = v;
        } else if (strcmp(o, "--delay") == 0) {
            a->delay_s = atof(v) * 1e-3;
            if (!(a->delay_s > 0.0 && a->delay_s < 10.0)) {
                fprintf(stderr, "gale-client: --delay: expected 1..9999 ms, got \"%s\"\n", v);
                return -1;
            }
        } else if (strcmp(o, "--wait") == 0) {
            a->wait_s = atof(v);
            if (!(a->wait_s > 0.0)) {
                fprintf(stderr, "gale-client: --wait: expected > 0 s, got \"%s\"\n", v);
                return -1;
            }
        } else if (strcmp(o, "--tile") == 0) {
            int *t = a->tile;
            if (sscanf(v, "%d,%d,%d,%d", &t[0], &t[1], &t[2], &t[3]) != 4 || t[2] < 1 || t[3] < 1 ||
                t[0] < 0 || t[1] < 0 || t[0] >= t[2] || t[1] >= t[3]) {
                fprintf(stderr,
                        "gale-client: --tile: expected C,R,COLS,ROWS with C < COLS, R < ROWS, "
                        "got \"%s\"\n",
                        v);
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
        } else {
            fprintf(stderr, "gale-client: unknown option \"%s\" (see --help)\n", o);
            return -1;
        }
        if (takes) {
            i++;
        }
    }
    if (!a->url) {
        fprintf(stderr, "gale-client: --url ws://HOST:PORT is required (see --help)\n");
        return -1;
    }
    if (a->tile[2] == 0) {
        a->tile[2] = a->tile[3] = 1;
    }
    return 0;
}

/* ---- network events ----------------------------------------------------------------- */

static void on_welcome(void *user, const ctl_welcome *w)
{
    cli *c = user;
    free(c->w_species);
    free(c->w_instances);
    free(c->w_boxes);
    c->w = *w;
    c->w.obstacles = NULL; /* kept as c->w_boxes */
    c->w_species = malloc((w->n_species ? w->n_species : 1) * sizeof *c->w_species);
    c->w_instances = malloc((w->n_instances ? w->n_instances : 1) * sizeof *c->w_instances);
    c->w_boxes = malloc((w->n_obstacles ? w->n_obstacles : 1) * 6 * sizeof *c->w_boxes);
    if (!c->w_species || !c->w_instances || !c->w_boxes || w->n_species > MAX_SPECIES) {
        fprintf(stderr, "gale-client: welcome: cannot hold %u species, %u trees\n", w->n_species,
                w->n_instances);
        c->w.n_species = c->w.n_instances = c->w.n_obstacles = 0;
        return;
    }
    for (uint32_t i = 0; i < w->n_obstacles; i++) {
        memcpy(&c->w_boxes[6 * i], w->obstacles[i].min, 3 * sizeof(float));
        memcpy(&c->w_boxes[6 * i + 3], w->obstacles[i].max, 3 * sizeof(float));
    }
    memcpy(c->w_species, w->species, w->n_species * sizeof *c->w_species);
    memcpy(c->w_instances, w->instances, w->n_instances * sizeof *c->w_instances);
    c->w.species = c->w_species;
    c->w.instances = c->w_instances;
    c->scene_pending = true;
    c->scene_ready = false;
    c->live_since_welcome = false;
    fprintf(stderr,
            "gale-client: %s: welcome as %s, %u species, %u trees, %u houses, %.0f Hz snapshots\n",
            cli_net_server_name(c->net), ctl_role_name(w->role) ? ctl_role_name(w->role) : "?",
            w->n_species, w->n_instances, w->n_obstacles, (double)w->snapshot_hz);
}

static void take_state(cli *c, const wire_frame *f, const wire_decoder *dec)
{
    wire_state st = wire_decoder_state(dec);
    if (st.n_trees != c->w.n_instances) {
        c->frames_mismatch++;
        return;
    }
    for (uint32_t t = 0; t < st.n_trees; t++) {
        wire_decoder_q(dec, t, c->snap + (size_t)t * c->stride, c->stride);
    }
    gale_err err = { 0 };
    if (jitter_insert(c->jit, f->hdr.tick, (double)f->hdr.server_time_us * 1e-6, c->snap, &err) <
        0) {
        fprintf(stderr, "gale-client: %s\n", err.msg);
        return;
    }
    if (!c->live_since_welcome) {
        c->live_since_welcome = true;
        fprintf(stderr, "gale-client: receiving state from tick %u\n", f->hdr.tick);
    }
    c->got_state = true;
}

static void take_leaves(cli *c, const wire_frame *f)
{
    const double tick_hz = c->w.tick_hz > 0.0f ? (double)c->w.tick_hz : 60.0;
    const double t_hdr = (double)f->hdr.server_time_us * 1e-6;
    for (uint32_t i = 0; i < f->n_leaves; i++) {
        const wire_leaf *l = &f->leaves[i];
        render_leaf_seed s = {
            .tree = l->instance,
            .slot = l->slot,
            .spawn_time_s =
                t_hdr - (double)((int64_t)f->hdr.tick - (int64_t)l->spawn_tick) / tick_hz,
            .seed = l->seed,
        };
        if (render_add_falling_leaf(c->r, &s, NULL) != 0) {
            c->leaves_bad++;
        }
    }
}

static void take_wind(cli *c, const wire_wind *w)
{
    const uint32_t n = (uint32_t)w->nx * w->ny;
    double sum_speed = 0.0, mean[3] = { 0, 0, 0 };
    for (uint32_t i = 0; i < n; i++) {
        float v[3];
        for (int k = 0; k < 3; k++) {
            v[k] = (float)w->v[3 * i + k] * w->scale_ms;
            c->wind_v[3 * i + k] = v[k];
            mean[k] += (double)v[k];
        }
        sum_speed += sqrt((double)(v[0] * v[0] + v[1] * v[1]));
    }
    c->wind_ms = n ? (float)(sum_speed / n) : 0.0f;
    c->have_wind = n > 0;
    render_wind rw = {
        .uniform = { n ? (float)(mean[0] / n) : 0, n ? (float)(mean[1] / n) : 0,
                     n ? (float)(mean[2] / n) : 0 },
        .nx = w->nx,
        .ny = w->ny,
        .nz = 1,
        .origin = { w->x0_m, w->y0_m, 0.0f },
        .cell = { w->cell_m, w->cell_m, 2.0f * w->z_m > 1.0f ? 2.0f * w->z_m : 1.0f },
        .v = c->wind_v,
    };
    if (c->r) {
        render_set_wind(c->r, &rw, NULL);
    }
}

static void on_frame(void *user, const wire_frame *f, const wire_decoder *dec, double recv_s)
{
    cli *c = user;
    (void)recv_s;
    if (f->hdr.type == WIRE_MSG_WIND) {
        take_wind(c, &f->wind);
        return;
    }
    if (!c->scene_ready) {
        return; /* the decoder keeps its state; the jitter buffer starts once assets are in */
    }
    if (f->hdr.type == WIRE_MSG_KEYFRAME || f->hdr.type == WIRE_MSG_DELTA) {
        take_state(c, f, dec);
    } else if (f->hdr.type == WIRE_MSG_LEAVES) {
        take_leaves(c, f);
    }
}

static void on_lost(void *user, int close_code, const char *why)
{
    cli *c = user;
    (void)close_code;
    (void)why;
    /* keep drawing the last state; the stream resumes from the next keyframe */
    if (c->jit) {
        jitter_reset(c->jit);
    }
}

/* ---- scene setup -------------------------------------------------------------------- */

/* The asset of one species: from the disk cache, else over HTTP (then cached). */
static int load_species_asset(cli *c, const ctl_species *s, asset *a, gale_err *err)
{
    uint8_t *buf = NULL;
    size_t len = 0;
    gale_err cerr = { 0 };
    char key[64];
    snprintf(key, sizeof key, "%s.gasset", s->hash);
    bool cached = c->cache && asset_cache_load(c->cache, key, &buf, &len, &cerr) == 0;
    if (!cached) {
        if (cerr.code != GALE_E_IO && cerr.code != 0) {
            fprintf(stderr, "gale-client: cache: %s (fetching again)\n", cerr.msg);
        }
        int rc = cli_net_fetch(c->net, s->url, ASSET_CACHE_MAX_BYTES, 60.0, &buf, &len, err);
        if (rc != 0) {
            return rc;
        }
    }
    int rc = asset_decode(buf, len, s->url, a, err);
    if (rc == 0 && !cached && c->cache) {
        gale_err serr = { 0 };
        if (asset_cache_store(c->cache, key, buf, len, &serr) != 0) {
            fprintf(stderr, "gale-client: cache: %s\n", serr.msg);
        }
    }
    fprintf(stderr, "gale-client: species %s: %zu bytes %s\n", s->name, len,
            cached ? "from the cache" : "downloaded");
    free(buf);
    return rc;
}

static void reset_camera(cli *c)
{
    float centre[3] = { 0, 0, 0 }, radius = 10.0f;
    uint32_t n = c->w.n_instances;
    for (uint32_t i = 0; i < n; i++) {
        for (int k = 0; k < 3; k++) {
            centre[k] += c->w_instances[i].pos[k] / (float)n;
        }
    }
    for (uint32_t i = 0; i < n; i++) {
        float dx = c->w_instances[i].pos[0] - centre[0], dy = c->w_instances[i].pos[1] - centre[1];
        radius = fmaxf(radius, sqrtf(dx * dx + dy * dy));
    }
    centre[2] += 4.0f; /* about crown height of the default species */
    camera_init(&c->cam, centre, fminf(1.6f * radius + 22.0f, 1500.0f));
}

static int setup_scene(cli *c, gale_err *err)
{
    c->scene_pending = false;
    for (uint32_t s = 0; s < c->w.n_species; s++) {
        const ctl_species *sp = &c->w_species[s];
        c->species_id[s] = -1;
        for (uint32_t k = 0; k < c->n_loaded; k++) {
            if (strcmp(c->loaded[k].hash, sp->hash) == 0) {
                c->species_id[s] = c->loaded[k].render_id;
            }
        }
        if (c->species_id[s] >= 0) {
            continue; /* already on the GPU (a reconnection to the same scene) */
        }
        if (c->n_loaded == MAX_SPECIES) {
            return gale_errf(err, GALE_E_RANGE, "more than %u species over this session",
                             MAX_SPECIES);
        }
        asset a = { 0 };
        int rc = load_species_asset(c, sp, &a, err);
        if (rc != 0) {
            return rc;
        }
        int id = render_add_species(c->r, &a, err);
        asset_fini(&a);
        if (id < 0) {
            return id;
        }
        c->species_id[s] = id;
        snprintf(c->loaded[c->n_loaded].hash, sizeof c->loaded[c->n_loaded].hash, "%s", sp->hash);
        c->loaded[c->n_loaded++].render_id = id;
    }
    uint32_t n = c->w.n_instances;
    render_instance *inst = calloc(n ? n : 1, sizeof *inst);
    if (!inst) {
        return gale_errf(err, GALE_E_NOMEM, "no memory for %u trees", n);
    }
    for (uint32_t i = 0; i < n; i++) {
        const ctl_instance *w = &c->w_instances[i];
        if (w->species >= c->w.n_species) {
            free(inst);
            return gale_errf(err, GALE_E_RANGE,
                             "welcome.instances[%u].species: expected < %u, got %u", i,
                             c->w.n_species, w->species);
        }
        inst[i] = (render_instance){ .species = (uint32_t)c->species_id[w->species],
                                     .pos = { w->pos[0], w->pos[1], w->pos[2] },
                                     .yaw = w->yaw_rad,
                                     .scale = w->scale };
    }
    int rc = render_set_instances(c->r, n, inst, err);
    free(inst);
    if (rc == 0) {
        rc = render_set_obstacles(c->r, c->w.n_obstacles, c->w_boxes, err);
    }
    if (rc != 0) {
        return rc;
    }
    uint32_t stride = 0;
    render_q_staging(c->r, &stride);
    c->stride = stride ? stride : 1;
    c->n_values = (n ? n : 1) * c->stride;
    jitter_destroy(c->jit);
    free(c->snap);
    c->snap = calloc(c->n_values, sizeof(float));
    c->jit = jitter_create(
        &(jitter_desc){ .n_values = c->n_values, .capacity = 64, .playout_delay_s = c->a.delay_s },
        err);
    if (!c->snap || !c->jit) {
        return err && err->code ? err->code : GALE_E_NOMEM;
    }
    static bool camera_set;
    if (!camera_set) {
        reset_camera(c);
        camera_set = true;
    }
    c->scene_ready = true;
    fprintf(stderr, "gale-client: scene ready: %u species on the GPU, %u trees, %u q per tree\n",
            c->n_loaded, n, c->stride);
    return 0;
}

/* ---- input -------------------------------------------------------------------------- */

static void screenshot_name(char *buf, size_t cap)
{
    time_t t = time(NULL);
    struct tm tm;
    localtime_r(&t, &tm);
    strftime(buf, cap, "gale-%Y%m%d-%H%M%S.png", &tm);
}

static void dial_wind(cli *c, float delta)
{
    if (c->a.role != CTL_ROLE_KIOSK) {
        return;
    }
    if (c->kiosk_speed_ms == 0.0f && c->have_wind) {
        c->kiosk_speed_ms = c->wind_ms;
    }
    c->kiosk_speed_ms = fminf(fmaxf(c->kiosk_speed_ms + delta, 0.0f), 100.0f);
    ctl_wind w = { .has_speed = true, .speed_ms = c->kiosk_speed_ms };
    snprintf(w.token, sizeof w.token, "%s", c->a.token ? c->a.token : "");
    gale_err err = { 0 };
    if (cli_net_send_wind(c->net, &w, &err) != 0) {
        fprintf(stderr, "gale-client: wind: %s\n", err.msg);
    } else {
        fprintf(stderr, "gale-client: wind dialled to %.0f m/s\n", (double)c->kiosk_speed_ms);
    }
}

static void toggle_fullscreen(cli *c, GLFWwindow *win)
{
    if (!c->fullscreen) {
        GLFWmonitor *m = glfwGetPrimaryMonitor();
        const GLFWvidmode *mode = m ? glfwGetVideoMode(m) : NULL;
        if (!mode) {
            return;
        }
        glfwGetWindowPos(win, &c->win_pos[0], &c->win_pos[1]);
        glfwGetWindowSize(win, &c->win_size[0], &c->win_size[1]);
        glfwSetWindowMonitor(win, m, 0, 0, mode->width, mode->height, mode->refreshRate);
    } else {
        glfwSetWindowMonitor(win, NULL, c->win_pos[0], c->win_pos[1], c->win_size[0],
                             c->win_size[1], 0);
    }
    c->fullscreen = !c->fullscreen;
}

static void key_cb(GLFWwindow *win, int key, int scancode, int action, int mods)
{
    cli *c = glfwGetWindowUserPointer(win);
    (void)scancode;
    (void)mods;
    if (action != GLFW_PRESS) {
        return;
    }
    switch (key) {
    case GLFW_KEY_ESCAPE:
        glfwSetWindowShouldClose(win, GLFW_TRUE);
        break;
    case GLFW_KEY_F11:
        toggle_fullscreen(c, win);
        break;
    case GLFW_KEY_F12:
    case GLFW_KEY_P:
        c->want_screenshot = true;
        break;
    case GLFW_KEY_R:
        reset_camera(c);
        break;
    case GLFW_KEY_EQUAL:
    case GLFW_KEY_KP_ADD:
        dial_wind(c, 5.0f);
        break;
    case GLFW_KEY_MINUS:
    case GLFW_KEY_KP_SUBTRACT:
        dial_wind(c, -5.0f);
        break;
    default:
        break;
    }
}

static void mouse_cb(GLFWwindow *win, int button, int action, int mods)
{
    cli *c = glfwGetWindowUserPointer(win);
    (void)mods;
    if (action == GLFW_PRESS) {
        c->drag = button == GLFW_MOUSE_BUTTON_LEFT ? 1 : button == GLFW_MOUSE_BUTTON_RIGHT ? 2 : 0;
        glfwGetCursorPos(win, &c->cursor[0], &c->cursor[1]);
    } else {
        c->drag = 0;
    }
}

static void cursor_cb(GLFWwindow *win, double x, double y)
{
    cli *c = glfwGetWindowUserPointer(win);
    if (c->a.role == CTL_ROLE_WALL_TILE) {
        return; /* every tile shows one fixed camera */
    }
    float dx = (float)(x - c->cursor[0]), dy = (float)(y - c->cursor[1]);
    c->cursor[0] = x;
    c->cursor[1] = y;
    int w, h;
    glfwGetWindowSize(win, &w, &h);
    if (c->drag == 1) {
        camera_orbit(&c->cam, dx, dy);
    } else if (c->drag == 2) {
        camera_pan(&c->cam, dx, dy, h);
    }
}

static void scroll_cb(GLFWwindow *win, double xoff, double yoff)
{
    cli *c = glfwGetWindowUserPointer(win);
    (void)xoff;
    if (c->a.role != CTL_ROLE_WALL_TILE) {
        camera_zoom(&c->cam, (float)yoff);
    }
}

static void fly_keys(cli *c, GLFWwindow *win, float dt)
{
    if (c->a.role == CTL_ROLE_WALL_TILE) {
        return;
    }
#define KEY(k) (glfwGetKey(win, (k)) == GLFW_PRESS ? 1.0f : 0.0f)
    float f = KEY(GLFW_KEY_W) - KEY(GLFW_KEY_S);
    float r = KEY(GLFW_KEY_D) - KEY(GLFW_KEY_A);
    float u = KEY(GLFW_KEY_E) - KEY(GLFW_KEY_Q);
#undef KEY
    camera_fly(&c->cam, f, r, u, dt);
}

/* ---- frame -------------------------------------------------------------------------- */

static int hud_conn(const cli *c, const cli_net_stats *ns)
{
    switch (ns->state) {
    case CLI_NET_LIVE:
        return c->got_state ? HUD_CONN_LIVE : HUD_CONN_WAIT_KEY;
    case CLI_NET_HELLO:
        return HUD_CONN_WAIT_KEY;
    case CLI_NET_BACKOFF:
        return HUD_CONN_RECONNECTING;
    default:
        return HUD_CONN_CONNECTING;
    }
}

static int draw_frame(cli *c, double now, gale_err *err)
{
    double server_now = now;
    jitter_clock_server_time(cli_net_clock(c->net), now, &server_now);
    double render_t = server_now - c->a.delay_s;
    if (c->scene_ready && c->jit) {
        uint32_t stride = 0;
        float *staging = render_q_staging(c->r, &stride);
        if (staging && stride == c->stride) {
            /* empty buffer (reconnecting): the staging keeps the last q on screen */
            jitter_sample(c->jit, render_t, staging, NULL);
        }
    }
    int fb_w, fb_h;
    render_size(c->r, &fb_w, &fb_h);
    render_camera rc = { .fov_y_deg = c->cam.fov_y_deg, .z_near = 0.3f, .z_far = 3000.0f };
    camera_eye(&c->cam, rc.eye);
    float f[3];
    camera_forward(&c->cam, f);
    for (int k = 0; k < 3; k++) {
        rc.target[k] = rc.eye[k] + f[k];
    }
    rc.up[2] = 1.0f;
    if (c->a.role == CTL_ROLE_WALL_TILE) {
        rc.matrices = true;
        camera_view(&c->cam, rc.view);
        camera_tile_proj(&c->cam, c->a.tile[0], c->a.tile[1], c->a.tile[2], c->a.tile[3],
                         (float)fb_w / (float)fb_h, c->a.bezel, rc.z_near, rc.z_far, rc.proj);
    }
    int rc_frame = render_frame(c->r, &rc, render_t, err);
    if (rc_frame != 0) {
        return rc_frame;
    }
    cli_net_stats ns = cli_net_get_stats(c->net);
    double rtt = jitter_clock_rtt(cli_net_clock(c->net));
    hud_state hs = {
        .have_wind = c->have_wind,
        .wind_ms = c->wind_ms,
        .conn = hud_conn(c, &ns),
        .server = cli_net_server_name(c->net),
        .retry_in_s = fmax(ns.retry_at_s - now, 0.0),
        .attempt = ns.attempt,
        .fps = (float)c->fps,
        .latency_ms = rtt >= 0.0 ? (float)(rtt * 500.0) : -1.0f,
        .delay_ms = (float)(c->a.delay_s * 1e3),
        .frames_bad = ns.frames_bad,
        .role = ctl_role_name(c->a.role),
    };
    if (c->a.role != CTL_ROLE_WALL_TILE || (c->a.tile[0] == 0 && c->a.tile[1] == 0)) {
        hud_draw(c->hud, &hs, fb_w, fb_h);
    }
    return 0;
}

int main(int argc, char **argv)
{
    cli c;
    memset(&c, 0, sizeof c);
    if (parse_args(argc, argv, &c.a) != 0) {
        return 2;
    }
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
    signal(SIGPIPE, SIG_IGN);
    srand((unsigned)time(NULL) ^ (unsigned)getpid());

    int status = 1;
    gale_err err = { 0 };
    c.wind_v = calloc((size_t)WIRE_MAX_WIND_SIDE * WIRE_MAX_WIND_SIDE * 3, sizeof(float));
    c.cache = asset_cache_create(&(asset_cache_desc){ .dir = c.a.cache_dir }, &err);
    if (!c.cache) {
        fprintf(stderr, "gale-client: %s (running without a disk cache)\n", err.msg);
        gale_err_clear(&err);
    }
    c.net = cli_net_create(
        &(cli_net_desc){ .url = c.a.url, .role = c.a.role, .token = c.a.token },
        &(cli_net_handler){
            .user = &c, .on_welcome = on_welcome, .on_frame = on_frame, .on_lost = on_lost },
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
    c.hud = hud_create(&(hud_desc){ .px = c.a.height >= 1000 ? 22.0f : 18.0f }, &err);
    if (!c.hud) {
        fprintf(stderr, "gale-client: hud: %s\n", err.msg);
        goto done;
    }
    const float origin[3] = { 0, 0, 6 };
    camera_init(&c.cam, origin, 60.0f);
    GLFWwindow *win = render_window(c.r);
    if (win) {
        glfwSetWindowUserPointer(win, &c);
        glfwSetKeyCallback(win, key_cb);
        glfwSetMouseButtonCallback(win, mouse_cb);
        glfwSetCursorPosCallback(win, cursor_cb);
        glfwSetScrollCallback(win, scroll_cb);
    }

    const double start = cli_net_now();
    c.last_frame_s = start;
    int frames_after_state = 0, fps_frames = 0;
    double fps_t0 = start;
    status = 0;
    while (!quit_flag && !(win && glfwWindowShouldClose(win))) {
        double now = cli_net_now();
        cli_net_poll(c.net, now);
        if (c.scene_pending) {
            if (setup_scene(&c, &err) != 0) {
                fprintf(stderr, "gale-client: scene: %s\n", err.msg);
                gale_err_clear(&err);
                cli_net_drop(c.net); /* try again on the next connection */
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
            fly_keys(&c, win, (float)fmin(dt, 0.1));
            int w, h, fw, fh;
            glfwGetFramebufferSize(win, &w, &h);
            render_size(c.r, &fw, &fh);
            if (w > 0 && h > 0 && (w != fw || h != fh)) {
                render_resize(c.r, w, h, NULL);
            }
        }
        if (draw_frame(&c, now, &err) != 0) {
            fprintf(stderr, "gale-client: frame: %s\n", err.msg);
            status = 1;
            break;
        }
        if (c.want_screenshot) {
            char name[64];
            screenshot_name(name, sizeof name);
            if (render_write_png(c.r, name, &err) == 0) {
                fprintf(stderr, "gale-client: screenshot %s\n", name);
            } else {
                fprintf(stderr, "gale-client: screenshot: %s\n", err.msg);
            }
            c.want_screenshot = false;
        }
        render_present(c.r);
        if (c.a.headless) {
            if (c.got_state && ++frames_after_state >= c.a.frames) {
                break;
            }
            if (!c.got_state && now - start > c.a.wait_s) {
                break;
            }
            /* pace at ~60 Hz so the stream advances between frames */
            double spent = cli_net_now() - now;
            if (spent < 1.0 / 60.0) {
                usleep((useconds_t)((1.0 / 60.0 - spent) * 1e6));
            }
        }
    }
    if (c.a.headless && status == 0) {
        if (c.a.screenshot && render_write_png(c.r, c.a.screenshot, &err) != 0) {
            fprintf(stderr, "gale-client: screenshot: %s\n", err.msg);
            status = 1;
        }
        if (!c.got_state) {
            cli_net_stats ns = cli_net_get_stats(c.net);
            fprintf(stderr, "gale-client: %s: no state received in %.1f s (%s)\n",
                    cli_net_server_name(c.net), cli_net_now() - start,
                    ns.last_error[0] ? ns.last_error : "no keyframe");
            status = 3;
        }
    }
    {
        cli_net_stats ns = cli_net_get_stats(c.net);
        fprintf(stderr,
                "gale-client: frames ok %llu, bad %llu, gaps %llu, control bad %llu, "
                "tree-count mismatches %llu, connects %u\n",
                (unsigned long long)ns.frames_ok, (unsigned long long)ns.frames_bad,
                (unsigned long long)ns.frames_gap, (unsigned long long)ns.ctl_bad,
                (unsigned long long)c.frames_mismatch, ns.connects);
    }
done:
    hud_destroy(c.hud);
    jitter_destroy(c.jit);
    cli_net_destroy(c.net);
    render_destroy(c.r);
    asset_cache_destroy(c.cache);
    free(c.snap);
    free(c.wind_v);
    free(c.w_species);
    free(c.w_instances);
    free(c.w_boxes);
    return status;
}
