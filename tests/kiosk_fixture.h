/* The real gale-server and gale-client processes on loopback for the kiosk tests
 * (tests/data/clientnet_scene.json: one palm species, kiosk token "test-token"): spawn
 * with output into a log, wait for a log line, wait for an exit, and a raw kiosk
 * connection (server_wsraw.h) that reads the server's WEATHER frames. Header-only. */
#ifndef GALE_KIOSK_FIXTURE_H
#define GALE_KIOSK_FIXTURE_H

#include <pthread.h>
#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "mono.h"
#include "proc_fixture.h"
#include "server_wsraw.h"
#include "wire.h"

#ifndef GALE_SERVER_EXE
#error "GALE_SERVER_EXE (path of gale-server) must be defined by the build"
#endif
#ifndef GALE_CLIENT_EXE
#error "GALE_CLIENT_EXE (path of gale-client) must be defined by the build"
#endif

#define KIOSK_TOKEN "test-token"

static char kf_dir[256]; /* this test's directory under the build tree */
static int kf_port;
static pid_t kf_server;

/* Starts argv with stdout and stderr into the files out and log (out NULL: into log). */
static inline pid_t kf_spawn(char *const argv[], const char *log, const char *out)
{
    pid_t pid = fork();
    if (pid == 0) {
        FILE *f = freopen(log, "w", stderr);
        if (!f) {
            _exit(126);
        }
        if (out ? !freopen(out, "w", stdout) : dup2(fileno(stderr), 1) < 0) {
            _exit(126);
        }
        execv(argv[0], argv);
        _exit(127);
    }
    return pid;
}

/* Makes kf_dir (name under the working directory, the build tree). */
static inline void kf_init(const char *name)
{
    snprintf(kf_dir, sizeof kf_dir, "%s.d", name);
    mkdir(kf_dir, 0755);
}

/* gale-server on an ephemeral port with a scene config under tests/data (NULL:
 * clientnet_scene.json; an absolute path: that file) and extra arguments (NULL-terminated, may be NULL). */
static inline int kf_start_server(const char *config, const char *const *extra)
{
    static char cfg[400];
    if (config && config[0] == '/') {
        snprintf(cfg, sizeof cfg, "%s", config); /* a scene the test wrote */
    } else {
        snprintf(cfg, sizeof cfg, GALE_SOURCE_DIR "/tests/data/%s",
                 config ? config : "clientnet_scene.json");
    }
    char log[300], cache[300];
    snprintf(log, sizeof log, "%s/server.log", kf_dir);
    snprintf(cache, sizeof cache, "%s/../kiosk-srvcache", kf_dir);
    const char *argv[32] = { GALE_SERVER_EXE, "--config", cfg, "--port", "0",
                             "--iface", "127.0.0.1", "--cache", cache };
    int n = 9;
    for (int i = 0; extra && extra[i] && n < 31; i++) {
        argv[n++] = extra[i];
    }
    argv[n] = NULL;
    unlink(log);
    kf_server = kf_spawn((char *const *)argv, log, NULL);
    if (!proc_wait_log(log, "listening on port", 1, 300.0)) {
        proc_dump(log);
        return -1;
    }
    FILE *f = fopen(log, "r");
    char line[512];
    kf_port = 0;
    while (f && fgets(line, sizeof line, f)) {
        const char *p = strstr(line, "listening on port ");
        if (p) {
            kf_port = atoi(p + 18);
        }
    }
    if (f) {
        fclose(f);
    }
    return kf_port > 0 ? 0 : -1;
}

static inline void kf_stop_server(void)
{
    if (kf_server > 0) {
        kill(kf_server, SIGTERM);
        proc_wait_exit(kf_server, 10.0);
        kf_server = 0;
    }
}

/* A raw connection that said hello as role (with the kiosk token for "kiosk") and got
 * its welcome; 0 or -1. */
static inline int kf_hello(wsraw *c, const char *role, const char *token)
{
    if (wsraw_open(c, kf_port, 0)) {
        return -1;
    }
    char h[256];
    snprintf(h, sizeof h, "{\"type\": \"hello\", \"protocol\": 1, \"role\": \"%s\"%s%s%s}", role,
             token ? ", \"token\": \"" : "", token ? token : "", token ? "\"" : "");
    wsraw_text(c, h);
    uint8_t *m;
    size_t n;
    int op = wsraw_recv(c, &m, &n, 10000);
    bool ok = op == 1 && m && strstr((const char *)m, "\"welcome\"");
    free(m);
    return ok ? 0 : -1;
}


/* A connection read on its own thread (so it never falls behind while the test waits on
 * a client process), keeping the latest WEATHER and the close code. Commands are sent
 * from the test's thread with wsraw_text (sending touches only the socket). */
typedef struct kf_reader {
    wsraw c;
    wire_decoder *d;
    pthread_t th;
    pthread_mutex_t lock;
    wire_weather w; /* under lock */
    int n_weather;  /* under lock: WEATHER frames read */
    int close_code; /* under lock: 0 while open */
    int dmg_events; /* under lock: DAMAGE events read (frames that are not the whole state) */
    int dmg_empty;  /* under lock: DAMAGE frames of the whole state, empty (a healed forest) */
    volatile int stop;
} kf_reader;

static inline void *kf_reader_main(void *arg)
{
    kf_reader *r = arg;
    while (!r->stop) {
        uint8_t *m;
        size_t n;
        int op = wsraw_recv(&r->c, &m, &n, 100);
        if (op == 2) {
            wire_frame f;
            bool ok = wire_decode(r->d, m, n, &f, NULL) == 0;
            if (ok && (f.types & (1u << WIRE_MSG_WEATHER))) {
                pthread_mutex_lock(&r->lock);
                r->w = f.weather;
                r->n_weather++;
                pthread_mutex_unlock(&r->lock);
            }
            if (ok && (f.types & (1u << WIRE_MSG_DAMAGE))) {
                pthread_mutex_lock(&r->lock);
                r->dmg_events += f.damage_full ? 0 : (int)f.n_damage;
                r->dmg_empty += f.damage_full && f.n_damage == 0;
                pthread_mutex_unlock(&r->lock);
            }
        } else if (op == 8) {
            pthread_mutex_lock(&r->lock);
            r->close_code = r->c.close_code;
            pthread_mutex_unlock(&r->lock);
            free(m);
            break;
        }
        free(m);
    }
    return NULL;
}

/* Opens a connection (kf_hello) and starts its reader; 0 or -1. */
static inline int kf_reader_start(kf_reader *r, const char *role, const char *token)
{
    memset(r, 0, sizeof *r);
    r->c.fd = -1;
    pthread_mutex_init(&r->lock, NULL);
    r->d = wire_decoder_create(&(wire_decoder_desc){ .max_trees = 64, .max_modes = 32 }, NULL);
    if (!r->d || kf_hello(&r->c, role, token)) {
        return -1;
    }
    return pthread_create(&r->th, NULL, kf_reader_main, r) ? -1 : 0;
}

/* Waits up to timeout_s for a WEATHER satisfying done (NULL: any); *w gets the latest. */
static inline bool kf_reader_wait(kf_reader *r, double timeout_s,
                           bool (*done)(const wire_weather *w, double arg), double arg,
                           wire_weather *w)
{
    double until = mono_s() + timeout_s;
    do {
        pthread_mutex_lock(&r->lock);
        bool have = r->n_weather > 0;
        *w = r->w;
        pthread_mutex_unlock(&r->lock);
        if (have && (!done || done(w, arg))) {
            return true;
        }
        usleep(20000);
    } while (mono_s() < until);
    return false;
}

/* Stops the reader and closes the connection (the socket's end is the disconnect). */
static inline void kf_reader_stop(kf_reader *r)
{
    r->stop = 1;
    if (r->th) {
        pthread_join(r->th, NULL);
    }
    wsraw_close(&r->c);
    wire_decoder_destroy(r->d);
    pthread_mutex_destroy(&r->lock);
}

#endif
