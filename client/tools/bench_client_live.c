/* gale-bench-client client --url: the client's CPU per display frame from received
 * messages to the GL upload, against a real gale-server: cli_net_poll (the control
 * messages, the wire decode; the socket reads and the libwebsockets frame parsing and
 * reassembly run on cli_net's own thread, not counted here),
 * dequantisation of each state frame into a snapshot, jitter insert, Hermite
 * interpolation into the staging array and the upload into a GL buffer (a hidden window:
 * run under Xvfb, deploy/bench-client.sh), and with it the kiosk's touch panel (kiosk_ui.h)
 * laid out for 1920x1080 and drawn. Display frames at 60 Hz; CPU time counted per frame
 * (this thread), the panel's share and wall time beside it. Prints JSON with the load
 * average. */
#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "cli_net.h"
#include "hud.h"
#include "jitter.h"
#include "kiosk_ui_draw.h"
#include "mono.h"
#include "wire.h"

int bench_client_live(const char *url, uint32_t frames);

typedef struct live {
    jitter *jit;
    float *snap;
    uint32_t n_values, stride_modes, n_trees;
    uint64_t state_frames, other_frames, bytes;
    double tick_hz;
    int welcomed;
    char err[300];
} live;

static double thread_cpu_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double quantile(double *v, int n, double p)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return v[(int)floor(p * (n - 1) + 0.5)];
}

static void on_welcome(void *user, const ctl_welcome *w)
{
    live *l = user;
    if (l->welcomed) {
        return;
    }
    uint32_t maxm = 1;
    for (uint32_t s = 0; s < w->n_species; s++) {
        maxm = w->species[s].n_modes > maxm ? w->species[s].n_modes : maxm;
    }
    l->n_trees = w->n_instances;
    l->stride_modes = maxm;
    l->n_values = w->n_instances * maxm;
    l->tick_hz = w->tick_hz;
    gale_err e = { 0 };
    l->snap = calloc(l->n_values ? l->n_values : 1, sizeof(float));
    l->jit = jitter_create(&(jitter_desc){ .n_values = l->n_values ? l->n_values : 1 }, &e);
    if (!l->snap || !l->jit) {
        snprintf(l->err, sizeof l->err, "welcome: %s", e.msg[0] ? e.msg : "no memory");
    }
    l->welcomed = 1;
}

static void on_frame(void *user, const wire_frame *f, const wire_decoder *dec, double recv_s)
{
    (void)recv_s;
    live *l = user;
    if (!l->jit || (f->hdr.type != WIRE_MSG_KEYFRAME && f->hdr.type != WIRE_MSG_DELTA)) {
        l->other_frames++;
        return;
    }
    l->state_frames++;
    for (uint32_t t = 0; t < l->n_trees; t++) {
        wire_decoder_q(dec, t, l->snap + (size_t)t * l->stride_modes, l->stride_modes);
    }
    jitter_insert(l->jit, f->hdr.tick, (double)f->hdr.server_time_us * 1e-6, l->snap, NULL);
}

int bench_client_live(const char *url, uint32_t frames)
{
    live l = { 0 };
    gale_err err = { 0 };
    cli_net *n = cli_net_create(&(cli_net_desc){ .url = url, .role = CTL_ROLE_VIEWER },
                                &(cli_net_handler){ .user = &l, .on_welcome = on_welcome,
                                                    .on_frame = on_frame },
                                &err);
    if (!n) {
        fprintf(stderr, "gale-bench-client client: %s\n", err.msg);
        return 2;
    }
    double until = mono_s() + 30.0;
    while (!l.state_frames && mono_s() < until) {
        cli_net_poll(n);
        usleep(2000);
    }
    if (!l.state_frames || l.err[0]) {
        fprintf(stderr, "gale-bench-client client: %s: %s\n", url,
                l.err[0] ? l.err : "no state within 30 s");
        cli_net_destroy(n);
        return 1;
    }
    GLFWwindow *win = NULL;
    GLuint buf = 0;
    if (getenv("DISPLAY") && glfwInit()) {
        glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
        glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
        glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
        glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
        glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
        win = glfwCreateWindow(64, 64, "bench", NULL, NULL);
        if (win) {
            glfwMakeContextCurrent(win);
            glGenBuffers(1, &buf);
            glBindBuffer(GL_ARRAY_BUFFER, buf);
            glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(l.n_values * sizeof(float)), NULL,
                         GL_STREAM_DRAW);
        }
    }
    float *staging = calloc(l.n_values ? l.n_values : 1, sizeof(float));
    double *cpu = calloc(frames, sizeof(double)), *wall = calloc(frames, sizeof(double));
    double *panel_cpu = calloc(frames, sizeof(double));
    if (!staging || !cpu || !wall || !panel_cpu) {
        return 1;
    }
    /* a kiosk's panel: ten scenario buttons, a replay running */
    hud *panel_hud = win ? hud_create(&(hud_desc){ .px = 22.0f }, NULL) : NULL;
    kiosk_ui panel;
    kiosk_ui_init(&panel);
    for (int k = 0; k < 10; k++) {
        kiosk_ui_set_scenario(&panel, k, "scenario", "Gusty afternoon", k >= 8);
    }
    kiosk_ui_set_scenario_count(&panel, 10);
    const wire_weather panel_wx = { .sustained_ms = 57.0f, .dir_from_deg = 120.0f,
                                    .replay_speed = 50.0f, .flags = WIRE_WEATHER_STORM };
    cli_net_stats s0 = cli_net_get_stats(n);
    uint64_t sf0 = l.state_frames;
    double t_start = mono_s(), next = t_start;
    for (uint32_t i = 0; i < frames; i++) {
        double c0 = thread_cpu_ms(), w0 = mono_s();
        cli_net_poll(n);
        /* the newest snapshot's server time less the playout delay (0.1 s) */
        jitter_sample(l.jit, jitter_newest_time(l.jit) - 0.1, staging, NULL);
        double p0 = thread_cpu_ms();
        if (panel_hud) {
            kiosk_ui_set_weather(&panel, &panel_wx);
            kiosk_ui_layout(&panel, 1920, 1080);
            kiosk_ui_draw(panel_hud, &panel);
            glBindBuffer(GL_ARRAY_BUFFER, buf); /* the upload's buffer again */
        }
        panel_cpu[i] = thread_cpu_ms() - p0;
        if (win) {
            glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)(l.n_values * sizeof(float)),
                            staging);
            glFinish();
        }
        cpu[i] = thread_cpu_ms() - c0;
        wall[i] = (mono_s() - w0) * 1e3;
        next += 1.0 / 60.0;
        double now = mono_s();
        if (next > now) {
            usleep((useconds_t)((next - now) * 1e6));
        }
    }
    double elapsed = mono_s() - t_start;
    cli_net_stats s1 = cli_net_get_stats(n);
    double load[3] = { 0 };
    FILE *lf = fopen("/proc/loadavg", "r");
    if (lf) {
        if (fscanf(lf, "%lf %lf %lf", &load[0], &load[1], &load[2]) != 3) {
            load[0] = -1;
        }
        fclose(lf);
    }
    double cmed = quantile(cpu, (int)frames, 0.5), cp95 = quantile(cpu, (int)frames, 0.95);
    double wmed = quantile(wall, (int)frames, 0.5), wp95 = quantile(wall, (int)frames, 0.95);
    double pmed = quantile(panel_cpu, (int)frames, 0.5);
    double pp95 = quantile(panel_cpu, (int)frames, 0.95);
    printf("{\"bench\": \"client_live\", \"url\": \"%s\", \"trees\": %u, \"modes_max\": %u, "
           "\"frames\": %u, \"seconds\": %.1f, \"state_frames\": %llu, "
           "\"socket_bytes\": %llu, \"socket_bytes_per_s\": %.0f, \"frames_bad\": %llu, "
           "\"gl_upload\": %s, \"cpu_ms_per_frame\": {\"median\": %.4f, \"p95\": %.4f}, "
           "\"kiosk_panel_cpu_ms\": {\"median\": %.4f, \"p95\": %.4f}, "
           "\"wall_ms_per_frame\": {\"median\": %.4f, \"p95\": %.4f}, \"target_ms\": 1.0, "
           "\"loadavg\": [%.2f, %.2f, %.2f]}\n",
           url, l.n_trees, l.stride_modes, frames, elapsed,
           (unsigned long long)(l.state_frames - sf0),
           (unsigned long long)(s1.bytes_rx - s0.bytes_rx),
           (double)(s1.bytes_rx - s0.bytes_rx) / elapsed,
           (unsigned long long)(s1.frames_bad - s0.frames_bad), win ? "true" : "false", cmed,
           cp95, pmed, pp95, wmed, wp95, load[0], load[1], load[2]);
    hud_destroy(panel_hud);
    if (win) {
        glDeleteBuffers(1, &buf);
        glfwDestroyWindow(win);
        glfwTerminate();
    }
    free(staging);
    free(panel_cpu);
    free(cpu);
    free(wall);
    cli_net_destroy(n);
    jitter_destroy(l.jit);
    free(l.snap);
    return 0;
}
