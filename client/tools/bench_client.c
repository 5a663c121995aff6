/* gale-bench-client client: client CPU time per display frame for a stream of T trees × M
 * modes (the client frame of gale-client): receive (copy of the frame bytes as the socket
 * layer reassembles them), decode (each snapshot a BUNDLE with the server's WEATHER every
 * tenth, as srv_publish.c sends it), dequantise into a snapshot, jitter insert, Hermite
 * interpolation into the q staging array, and when a context can be made the GL upload,
 * the HUD (hud.h: its lines from the weather, the wind arrow) drawn over a 1280 x 720
 * framebuffer and the kiosk's touch panel (kiosk_ui.h) laid out for 1920x1080 and drawn:
 * hud_draw (layout, vertices, upload, draw calls), the panel, and the glFinish after
 * them (llvmpipe's fill of both) timed apart. */
#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mono.h"
#include "hud.h"
#include "jitter.h"
#include "kiosk_ui_draw.h"
#include "wire.h"

int bench_client(int argc, char **argv);
int bench_client_live(const char *url, uint32_t frames);

#define N_STAGES 9
static const char *stage_name[N_STAGES] = { "receive",       "decode",      "dequantize",
                                            "jitter_insert", "interpolate", "gl_upload",
                                            "hud",           "kiosk_panel", "hud_finish" };
enum { HUD_W = 1280, HUD_H = 720, WEATHER_EVERY = 10 /* SRV_WEATHER_EVERY */ };

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double quantile(double *v, int n, double p)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    int i = (int)floor(p * (n - 1) + 0.5);
    return v[i];
}

/* q of tree t, mode m at snapshot k: a smooth sway, different per tree and mode. */
static float sway(uint32_t t, uint32_t m, uint32_t k)
{
    double w = 0.8 + 0.37 * m, ph = 0.013 * t + 0.7 * m;
    return (float)(0.6 / (1.0 + m) * sin(w * k / 60.0 + ph));
}

int bench_client(int argc, char **argv)
{
    uint32_t trees = 4000, modes = 32, frames = 600, changes = 0;
    bool want_gl = true;
    const char *url = NULL;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--trees") && i + 1 < argc) {
            trees = (uint32_t)atoi(argv[++i]);
        } else if (!strcmp(argv[i], "--modes") && i + 1 < argc) {
            modes = (uint32_t)atoi(argv[++i]);
        } else if (!strcmp(argv[i], "--frames") && i + 1 < argc) {
            frames = (uint32_t)atoi(argv[++i]);
        } else if (!strcmp(argv[i], "--hud-changes") && i + 1 < argc) {
            changes = (uint32_t)atoi(argv[++i]); /* 0: the HUD and the panel hold still */
        } else if (!strcmp(argv[i], "--url") && i + 1 < argc) {
            url = argv[++i]; /* live: bench_client_live.c */
        } else if (!strcmp(argv[i], "--no-gl")) {
            want_gl = false;
        } else if (!strcmp(argv[i], "--json")) {
            /* JSON is the only output */
        } else {
            bool help = !strcmp(argv[i], "--help") || !strcmp(argv[i], "-h");
            fprintf(help ? stdout : stderr,
                    "usage: gale-bench-client client [--trees N] [--modes M] [--frames F] "
                    "[--no-gl] [--hud-changes N] [--url ws://HOST:PORT] [--json]\n  per-frame client "
                    "CPU: receive, decode, dequantize, jitter insert, interpolate, GL upload, HUD, "
                    "kiosk panel (target <= 1 ms);\n  --hud-changes N: the HUD's fps figure and "
                    "the panel's wind change every N frames (default: they hold still)\n"
                    "  --url: from a live server's socket bytes (WebSocket parsing included)\n");
            return help ? 0 : 2;
        }
    }
    if (trees < 1 || trees > WIRE_MAX_TREES || modes < 1 || modes > WIRE_MAX_MODES || frames < 10) {
        fprintf(stderr, "gale-bench-client client: expected 1..%u trees, 1..%u modes, >= 10 frames\n",
                WIRE_MAX_TREES, WIRE_MAX_MODES);
        return 2;
    }
    if (url) {
        return bench_client_live(url, frames);
    }
    gale_err err = { 0 };
    int status = 1;
    /* the server side: one species, quantised sway, a keyframe then deltas (not timed) */
    const uint32_t n_pre = 64; /* distinct encoded frames, replayed as a loop of deltas */
    wire_scene scene = { .n_trees = trees, .n_species = 1 };
    scene.n_modes[0] = (uint8_t)modes;
    for (uint32_t m = 0; m < modes; m++) {
        scene.step[0][m] = 1e-4f;
    }
    uint8_t *species = calloc(trees, 1), *nm = malloc(trees);
    int16_t *qs[3];
    /* room for the bundle around the state: its header, the index, one WEATHER */
    size_t bound = wire_state_bound(trees, modes, 1) + WIRE_HEADER_BYTES + 64 +
                   WIRE_WEATHER_MAX_BYTES;
    uint8_t **enc = calloc(n_pre + 1, sizeof *enc);
    size_t *enc_len = calloc(n_pre + 1, sizeof *enc_len);
    uint8_t *rx = malloc(bound);
    float *snap = malloc((size_t)trees * modes * sizeof(float));
    float *staging = malloc((size_t)trees * modes * sizeof(float));
    wire_decoder *dec =
        wire_decoder_create(&(wire_decoder_desc){ .max_trees = trees, .max_modes = modes }, &err);
    jitter *jit = jitter_create(
        &(jitter_desc){ .n_values = trees * modes, .capacity = 32, .playout_delay_s = 0.1 }, &err);
    double *t_stage[N_STAGES];
    for (int s = 0; s < N_STAGES; s++) {
        t_stage[s] = calloc(frames, sizeof(double));
    }
    double *t_total = calloc(frames, sizeof(double));
    double *t_cpu = calloc(frames, sizeof(double));
    for (int k = 0; k < 3; k++) {
        qs[k] = malloc((size_t)trees * modes * sizeof(int16_t));
    }
    scene.species = species;
    if (!species || !nm || !enc || !enc_len || !rx || !snap || !staging || !dec || !jit ||
        !t_total || !t_cpu || !qs[0] || !qs[1] || !qs[2]) {
        fprintf(stderr, "gale-bench-client client: setup: %s\n", err.msg[0] ? err.msg : "no memory");
        goto done;
    }
    memset(nm, (int)modes, trees);
    double bytes_sum = 0;
    for (uint32_t k = 0; k <= n_pre; k++) {
        int16_t *cur = qs[k % 3];
        for (uint32_t t = 0; t < trees; t++) {
            for (uint32_t m = 0; m < modes; m++) {
                cur[t * modes + m] = wire_quantize(sway(t, m, k), 1.0f / scene.step[0][m]);
            }
        }
        wire_state sc = { trees, modes, nm, cur };
        wire_state sp = { trees, modes, nm, qs[(k + 2) % 3] };
        wire_state sp2 = { trees, modes, nm, qs[(k + 1) % 3] };
        wire_header h = { .tick = k, .server_time_us = (uint64_t)k * 1000000 / 60 };
        enc[k] = malloc(bound);
        int rc = !enc[k]  ? GALE_E_NOMEM
                 : k == 0 ? wire_encode_keyframe(&h, k + 1, &scene, &sc, enc[k], bound, &enc_len[k],
                                                 &err)
                          : wire_encode_delta(&h, k + 1, &scene, &sc, &sp, k >= 2 ? &sp2 : NULL,
                                              enc[k], bound, &enc_len[k], &err);
        if (rc == 0 && k % WEATHER_EVERY == 1) {
            /* a Category 4 replay's weather, name and eye included (the HUD's longest) */
            wire_weather wx = { .sustained_ms = 62.0f, .gust_ms = 78.0f, .dir_from_deg = 120.0f,
                                .ss_class = 5, .beaufort = 12,
                                .flags = WIRE_WEATHER_STORM | WIRE_WEATHER_CLOCK,
                                .storm_class = 5, .pressure_hpa = 960.0f,
                                .central_hpa = 922.0f, .distance_km = 28.0f,
                                .bearing_deg = 95.0f, .utc_min = 11864160u,
                                .utc_offset_min = -240, .storm_min = 30.0f,
                                .replay_pos_s = 60.0f, .replay_len_s = 900.0f,
                                .replay_speed = 10.0f, .name = "Andrew 1992" };
            uint8_t wbuf[WIRE_WEATHER_MAX_BYTES];
            size_t wlen = 0;
            h.type = WIRE_MSG_WEATHER;
            const uint8_t *more[1] = { wbuf };
            rc = wire_encode_weather(&h, &wx, wbuf, sizeof wbuf, &wlen, &err);
            rc = rc ? rc : wire_bundle_wrap(enc[k], bound, &enc_len[k], more, &wlen, 1, &err);
        }
        if (rc != 0) {
            fprintf(stderr, "gale-bench-client client: encode: %s\n", err.msg);
            goto done;
        }
        if (k > 0) {
            bytes_sum += (double)enc_len[k];
        }
    }

    /* optional GL context for the upload stage */
    GLFWwindow *win = NULL;
    GLuint buf = 0;
    hud *hd = NULL;
    wire_weather wx_last;
    bool have_wx = false;
    if (want_gl && getenv("DISPLAY") && glfwInit()) {
        glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
        glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
        glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
        glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
        glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
        win = glfwCreateWindow(HUD_W, HUD_H, "bench", NULL, NULL);
        if (win) {
            glfwMakeContextCurrent(win);
            hd = hud_create(&(hud_desc){ 0 }, &err);
            if (!hd) {
                fprintf(stderr, "gale-bench-client client: hud: %s (timed without it)\n", err.msg);
            }
            glGenBuffers(1, &buf);
            glBindBuffer(GL_ARRAY_BUFFER, buf);
            glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)((size_t)trees * modes * sizeof(float)), NULL,
                         GL_STREAM_DRAW);
        }
    }

    /* the client: the keyframe first, then one delta per display frame (60 Hz both) */
    wire_frame f;
    if (wire_decode(dec, enc[0], enc_len[0], &f, &err) != 0) {
        fprintf(stderr, "gale-bench-client client: decode keyframe: %s\n", err.msg);
        goto done;
    }
    /* the kiosk's panel as a kiosk draws it every frame: ten scenario buttons, a replay */
    hud *panel_hud = win ? hud_create(&(hud_desc){ .px = 22.0f }, &err) : NULL;
    kiosk_ui panel;
    kiosk_ui_init(&panel);
    for (int k = 0; k < 10; k++) {
        kiosk_ui_set_scenario(&panel, k, "scenario", "Gusty afternoon", k >= 8);
    }
    kiosk_ui_set_scenario_count(&panel, 10);
    wire_weather panel_wx = { .sustained_ms = 57.0f, .dir_from_deg = 120.0f,
                              .replay_speed = 50.0f, .flags = WIRE_WEATHER_STORM };
    uint64_t decode_errors = 0;
    uint32_t seq_base = 0;
    for (uint32_t i = 0; i < frames; i++) {
        uint32_t k = 1 + i % n_pre;
        if (i > 0 && k == 1) {
            /* the loop of deltas restarts: resync from the keyframe (untimed) */
            seq_base += n_pre;
            wire_decoder_destroy(dec);
            dec = wire_decoder_create(
                &(wire_decoder_desc){ .max_trees = trees, .max_modes = modes }, &err);
            wire_decode(dec, enc[0], enc_len[0], &f, &err);
        }
        double t[N_STAGES + 1] = { 0 };
        t[0] = mono_s();
        memcpy(rx, enc[k], enc_len[k]);
        t[1] = mono_s();
        if (wire_decode(dec, rx, enc_len[k], &f, &err) != 0) {
            decode_errors++;
        } else if (f.types & (1u << WIRE_MSG_WEATHER)) {
            wx_last = f.weather; /* what the client keeps of it (client_stream.c) */
            have_wx = true;
        }
        t[2] = mono_s();
        for (uint32_t tr = 0; tr < trees; tr++) {
            wire_decoder_q(dec, tr, snap + (size_t)tr * modes, modes);
        }
        t[3] = mono_s();
        double ts = ((double)(seq_base + k)) / 60.0;
        jitter_insert(jit, seq_base + k, ts, snap, NULL);
        t[4] = mono_s();
        /* render 0.1 s behind the newest: between two held snapshots, all four present */
        jitter_sample(jit, ts - 0.1 + 0.37 / 60.0, staging, NULL);
        t[5] = mono_s();
        if (win) {
            glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)((size_t)trees * modes * sizeof(float)),
                            staging);
            glFinish();
        }
        t[6] = mono_s();
        /* what the HUD and the panel show changes every `changes` frames, as a replay's
           WEATHER and the fps counter change it (kept pictures are built again) */
        const float change = changes ? (float)((i / changes) % 7) : 0.0f;
        if (hd) {
            hud_state hs = { .conn = HUD_CONN_LIVE, .server = "127.0.0.1:8080",
                             .fps = 60.0f + change, .latency_ms = 2.0f, .delay_ms = 100.0f,
                             .role = "kiosk",
                             .wx = have_wx ? &wx_last : NULL, .view_heading_deg = 30.0f };
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
            hud_draw(hd, &hs, HUD_W, HUD_H);
        }
        t[7] = mono_s();
        if (panel_hud) {
            panel_wx.sustained_ms = 57.0f + 0.2f * change;
            kiosk_ui_set_weather(&panel, &panel_wx);
            kiosk_ui_layout(&panel, 1920, 1080);
            kiosk_ui_draw(panel_hud, &panel);
            glBindBuffer(GL_ARRAY_BUFFER, buf); /* the upload's buffer again */
        }
        t[8] = mono_s();
        if (hd || panel_hud) {
            glFinish(); /* llvmpipe rasterises the HUD and the panel here */
        }
        t[9] = mono_s();
        for (int s = 0; s < N_STAGES; s++) {
            t_stage[s][i] = (t[s + 1] - t[s]) * 1e3;
        }
        t_total[i] = (t[9] - t[0]) * 1e3;
        t_cpu[i] = (t[8] - t[0]) * 1e3; /* without the rasterisation a GPU does */
    }
    printf("{\"bench\": \"client\", \"trees\": %u, \"modes\": %u, \"frames\": %u,\n", trees, modes,
           frames);
    printf(" \"delta_bytes_mean\": %.0f, \"keyframe_bytes\": %zu, \"decode_errors\": %llu,\n",
           bytes_sum / n_pre, enc_len[0], (unsigned long long)decode_errors);
    printf(" \"gl_upload\": %s, \"hud\": %s, \"weather_every\": %d, \"hud_changes_every\": %u,\n"
           " \"stages_ms\": {",
           win ? "true" : "false", hd ? "\"drawn at 1280x720\"" : "false", WEATHER_EVERY,
           changes);
    for (int s = 0; s < N_STAGES; s++) {
        double med = quantile(t_stage[s], (int)frames, 0.5);
        double p95 = quantile(t_stage[s], (int)frames, 0.95);
        printf("%s\"%s\": {\"median\": %.4f, \"p95\": %.4f}", s ? ", " : "", stage_name[s], med,
               p95);
    }
    double med = quantile(t_total, (int)frames, 0.5), p95 = quantile(t_total, (int)frames, 0.95);
    double load[3] = { 0 };
    FILE *lf = fopen("/proc/loadavg", "r");
    if (lf) {
        if (fscanf(lf, "%lf %lf %lf", &load[0], &load[1], &load[2]) != 3) {
            load[0] = -1;
        }
        fclose(lf);
    }
    /* receive here is a copy of bytes already in memory: no socket, no WebSocket parsing
       (--url measures those against a live server) */
    /* the target is the client's CPU: every stage but the final glFinish, where llvmpipe
       rasterises what a GPU would */
    double cmed = quantile(t_cpu, (int)frames, 0.5), cp95 = quantile(t_cpu, (int)frames, 0.95);
    printf("},\n \"total_ms\": {\"median\": %.4f, \"p95\": %.4f}, "
           "\"client_cpu_ms\": {\"median\": %.4f, \"p95\": %.4f}, \"target_ms\": 1.0, "
           "\"meets_target\": %s, \"receive\": \"memcpy\", \"loadavg\": [%.2f, %.2f, %.2f]}\n",
           med, p95, cmed, cp95, cmed <= 1.0 ? "true" : "false", load[0], load[1], load[2]);
    status = 0;
    hud_destroy(panel_hud);
    if (win) {
        hud_destroy(hd);
        glDeleteBuffers(1, &buf);
        glfwDestroyWindow(win);
        glfwTerminate();
    }
done:
    for (uint32_t k = 0; enc && k <= n_pre; k++) {
        free(enc[k]);
    }
    for (int s = 0; s < N_STAGES; s++) {
        free(t_stage[s]);
    }
    for (int k = 0; k < 3; k++) {
        free(qs[k]);
    }
    free(t_total);
    free(t_cpu);
    free(enc);
    free(enc_len);
    free(species);
    free(nm);
    free(rx);
    free(snap);
    free(staging);
    wire_decoder_destroy(dec);
    jitter_destroy(jit);
    return status;
}
