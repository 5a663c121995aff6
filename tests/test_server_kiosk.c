/* Kiosk tokens on the real gale-server process over loopback (server/SERVER.md "Kiosk
 * tokens"): the embedded default scene refuses every kiosk and says so at start, listening
 * on 127.0.0.1; GALE_KIOSK_TOKEN and --kiosk-token-file give the token (file over
 * environment over config); a token a hello cannot carry, or an unreadable or empty file,
 * stops the server at start naming where it came from; wrong tokens from one address are
 * met with a growing delay, counted in /metrics, and the right one passes once it ends. */
#include "check.h"
#include "server_wsraw.h"
#include "wire.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <time.h>

extern char **environ;

#define CACHE "kiosk_cache"
#define T64 "0123456789012345678901234567890123456789012345678901234567890123"

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    if (f) {
        fputs(text, f);
        fclose(f);
    }
}

/* The whole file at path (caller frees), "" when unreadable. */
static char *read_file(const char *path)
{
    char *b = calloc(1, 1 << 20);
    FILE *f = fopen(path, "rb");
    if (b && f) {
        size_t n = fread(b, 1, (1 << 20) - 1, f);
        b[n] = 0;
    }
    if (f) {
        fclose(f);
    }
    return b;
}

typedef struct proc {
    pid_t pid;
    int out;           /* reads the server's stdout */
    int port;          /* from its "listening on port" line; 0 before */
    char err_path[64]; /* its stderr, a file in the build tree */
} proc;

/* Starts gale-server with args[] (after the program name), its environment without
 * GALE_KIOSK_TOKEN plus env_token when non-NULL ("GALE_KIOSK_TOKEN=..."), stderr to
 * name.err. Returns 0 or -1. */
static int spawn(proc *p, const char *name, const char *const *args, const char *env_token)
{
    memset(p, 0, sizeof *p);
    snprintf(p->err_path, sizeof p->err_path, "%s.err", name);
    const char *argv[32] = { GALE_SERVER_EXE };
    for (int i = 0; args[i] && i < 30; i++) {
        argv[i + 1] = args[i];
    }
    int n_env = 0;
    while (environ[n_env]) {
        n_env++;
    }
    const char **envp = calloc((size_t)n_env + 2, sizeof *envp);
    int po[2];
    if (!envp || pipe(po)) {
        free(envp);
        return -1;
    }
    int k = 0;
    for (int i = 0; i < n_env; i++) {
        if (strncmp(environ[i], "GALE_KIOSK_TOKEN=", 17)) {
            envp[k++] = environ[i];
        }
    }
    if (env_token) {
        envp[k++] = env_token;
    }
    p->pid = fork();
    if (p->pid == 0) {
        int fe = open(p->err_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        dup2(po[1], 1);
        dup2(fe, 2);
        close(po[0]);
        execve(GALE_SERVER_EXE, (char *const *)argv, (char *const *)envp);
        _exit(127);
    }
    free(envp);
    close(po[1]);
    p->out = po[0];
    return p->pid > 0 ? 0 : -1;
}

/* The exit status within timeout_s (killed and -1 past it). */
static int wait_exit(proc *p, double timeout_s)
{
    int rc = -1;
    for (int i = 0; i < (int)(timeout_s * 100); i++) {
        int st;
        if (waitpid(p->pid, &st, WNOHANG) == p->pid) {
            rc = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
            break;
        }
        usleep(10000);
    }
    if (rc < 0) {
        kill(p->pid, SIGKILL);
        waitpid(p->pid, NULL, 0);
    }
    close(p->out);
    return rc;
}

/* Waits for the "listening on port N" line (the first start bakes the default species). */
static int wait_listening(proc *p)
{
    char line[256] = { 0 };
    size_t n = 0;
    struct pollfd pf = { .fd = p->out, .events = POLLIN };
    while (n + 1 < sizeof line && !strchr(line, '\n') && poll(&pf, 1, 120000) > 0) {
        ssize_t k = read(p->out, line + n, sizeof line - 1 - n);
        if (k <= 0) {
            break;
        }
        n += (size_t)k;
        line[n] = 0;
    }
    if (sscanf(line, "gale-server: listening on port %d", &p->port) != 1 || p->port <= 0) {
        char *err = read_file(p->err_path);
        fprintf(stderr, "gale-server did not start: %s\n%s\n", line, err ? err : "");
        free(err);
        kill(p->pid, SIGKILL);
        return -1;
    }
    return 0;
}

/* SIGTERM, then the exit status. */
static int stop(proc *p)
{
    kill(p->pid, SIGTERM);
    return wait_exit(p, 20);
}

/* A kiosk hello carrying token (NULL: none): 0 when welcomed, else the close code, with
 * the reason in why[128]. */
static int kiosk(int port, const char *token, char *why)
{
    wsraw c;
    why[0] = 0;
    if (wsraw_open(&c, port, 0)) {
        return -1;
    }
    char h[200];
    snprintf(h, sizeof h, "{\"type\": \"hello\", \"protocol\": %d, \"role\": \"kiosk\"%s%s%s}",
             WIRE_PROTOCOL_VERSION, token ? ", \"token\": \"" : "", token ? token : "",
             token ? "\"" : "");
    wsraw_text(&c, h);
    uint8_t *m;
    size_t n;
    int op = wsraw_recv(&c, &m, &n, 5000);
    int rc = -1;
    if (op == 1 && strstr((const char *)m, "\"welcome\"")) {
        rc = 0;
    } else if (op == 8 || (op == 1 && wsraw_wait_close(&c, 5000) > 0)) {
        /* a refusal: an error message, then the close frame */
        rc = c.close_code;
        snprintf(why, 128, "%s", c.close_reason);
    }
    free(m);
    wsraw_close(&c);
    return rc;
}

static int viewer_welcomed(int port)
{
    wsraw c;
    if (wsraw_open(&c, port, 0)) {
        return 0;
    }
    char h[128];
    snprintf(h, sizeof h, "{\"type\": \"hello\", \"protocol\": %d, \"role\": \"viewer\"}",
             WIRE_PROTOCOL_VERSION);
    wsraw_text(&c, h);
    uint8_t *m;
    size_t n;
    int ok = wsraw_recv(&c, &m, &n, 5000) == 1 && strstr((const char *)m, "\"welcome\"");
    free(m);
    wsraw_close(&c);
    return ok;
}

/* A counter from /metrics, -1 when absent. */
static double metric(int port, const char *name)
{
    char *b = NULL, key[128];
    double v = -1;
    snprintf(key, sizeof key, "\n%s ", name);
    if (wsraw_http_get(port, "/metrics", &b) == 200 && b) {
        const char *p = strstr(b, key);
        if (!p || sscanf(p + strlen(key), "%lf", &v) != 1) {
            v = -1;
        }
    }
    free(b);
    return v;
}

static int count(const char *hay, const char *needle)
{
    int n = 0;
    for (const char *p = hay; (p = strstr(p, needle)); p++) {
        n++;
    }
    return n;
}

/* The embedded default scene, no token set: every kiosk refused (the token the default
 * once shipped with included), the start-up log says so once and how to enable them, and
 * the server listens on 127.0.0.1. */
static void test_default_no_kiosk(void)
{
    proc p;
    const char *args[] = { "--port", "0", "--cache", CACHE, NULL };
    CHECK(spawn(&p, "kiosk_default", args, NULL) == 0);
    if (wait_listening(&p)) {
        CHECK(0);
        wait_exit(&p, 1);
        return;
    }
    char why[128];
    CHECK(kiosk(p.port, "gale-kiosk", why) == WIRE_CLOSE_BAD_TOKEN);
    CHECK_STR_HAS(why, "hello.token: kiosks are disabled (the server has no kiosk token)");
    CHECK(kiosk(p.port, NULL, why) == WIRE_CLOSE_BAD_TOKEN);
    CHECK(kiosk(p.port, "", why) == WIRE_CLOSE_BAD_TOKEN);
    CHECK(viewer_welcomed(p.port));
    CHECK(metric(p.port, "gale_kiosk_auth_failures_total") >= 1);
    CHECK(stop(&p) == 0);
    char *err = read_file(p.err_path);
    CHECK(count(err, "kiosks disabled: no kiosk token set (give one with --kiosk-token-file "
                     "FILE, $GALE_KIOSK_TOKEN or the config's kiosk_token)") == 1);
    CHECK(count(err, "kiosks enabled") == 0);
    char where[128];
    snprintf(where, sizeof where, "gale-server: listening on 127.0.0.1 port %d (this machine only",
             p.port);
    CHECK_STR_HAS(err, where);
    free(err);
}

/* GALE_KIOSK_TOKEN enables kiosks; then wrong tokens from 127.0.0.1 as fast as the test
 * sends them: checked ones come at least 0.25, 0.5, 1 s apart, the rest are refused
 * unchecked (the right token too) until the delay ends; then the right one passes and a
 * wrong one costs 0.25 s again. /metrics counts both kinds. */
static void test_env_and_brute_force(void)
{
    proc p;
    const char *args[] = { "--port", "0", "--iface", "127.0.0.1", "--cache", CACHE, NULL };
    CHECK(spawn(&p, "kiosk_env", args, "GALE_KIOSK_TOKEN=env-secret") == 0);
    if (wait_listening(&p)) {
        CHECK(0);
        wait_exit(&p, 1);
        return;
    }
    char why[128];
    CHECK(kiosk(p.port, "env-secret", why) == 0);
    int checked = 0, delayed = 0, other = 0, attempts = 0;
    double t0 = now_s(), t_last = t0;
    while (checked < 4 && attempts < 1000 && now_s() - t0 < 30) {
        int rc = kiosk(p.port, "guess", why);
        attempts++;
        if (rc == WIRE_CLOSE_BAD_TOKEN && strstr(why, "hello.token: wrong kiosk token")) {
            checked++;
            t_last = now_s();
        } else if (rc == WIRE_CLOSE_BAD_TOKEN && strstr(why, "hello.token: not checked")) {
            delayed++;
        } else {
            if (other++ < 5) {
                fprintf(stderr, "unexpected: %d %s\n", rc, why);
            }
        }
        usleep(10000);
    }
    double took = t_last - t0;
    fprintf(stderr, "  %d attempts: %d checked, %d refused unchecked; 4 checked took %.2f s\n",
            attempts, checked, delayed, took);
    CHECK(checked == 4 && other == 0);
    CHECK(took >= 1.7);       /* 0.25 + 0.5 + 1 s of delay between the four checks */
    CHECK(delayed >= 10);     /* the attempts in between were refused unchecked */
    /* a viewer from the same address is not held */
    CHECK(viewer_welcomed(p.port));
    /* the right token during the 2 s delay after the fourth: refused unchecked */
    CHECK(kiosk(p.port, "env-secret", why) == WIRE_CLOSE_BAD_TOKEN);
    CHECK_STR_HAS(why, "hello.token: not checked: wrong kiosk tokens from this address; retry in ");
    delayed++;
    double retry = 0;
    const char *r = strstr(why, "retry in ");
    CHECK(r && sscanf(r, "retry in %lf", &retry) == 1 && retry > 0.5 && retry <= 2.0);
    usleep((useconds_t)((retry + 0.05) * 1e6));
    CHECK(kiosk(p.port, "env-secret", why) == 0);
    /* the right token reset the address: one wrong token costs 0.25 s again */
    CHECK(kiosk(p.port, "guess", why) == WIRE_CLOSE_BAD_TOKEN);
    CHECK_STR_HAS(why, "hello.token: wrong kiosk token");
    checked++;
    usleep(300000);
    CHECK(kiosk(p.port, "env-secret", why) == 0);
    CHECK(metric(p.port, "gale_kiosk_auth_failures_total") == checked);
    CHECK(metric(p.port, "gale_kiosk_auth_delayed_total") == delayed);
    CHECK(stop(&p) == 0);
    char *err = read_file(p.err_path);
    CHECK_STR_HAS(err, "gale-server: kiosks enabled: token from GALE_KIOSK_TOKEN");
    CHECK(count(err, "env-secret") == 0); /* the token itself is never logged */
    free(err);
}

/* --kiosk-token-file over GALE_KIOSK_TOKEN over the config's kiosk_token. */
static void test_file_over_env_over_config(void)
{
    char cfg[1024];
    snprintf(cfg, sizeof cfg,
             "{\"name\": \"kiosk\", \"kiosk_token\": \"cfg-secret\", \"species\": [{\"name\": "
             "\"palm\", \"file\": \"%s/configs/species/palm.json\", \"modes\": 8}],"
             " \"forest\": [{\"species\": \"palm\", \"count\": 12, \"area_min\": [-20, -20],"
             " \"area_max\": [20, 20], \"min_spacing_m\": 3}],"
             " \"wind\": {\"solver\": false, \"u10_ms\": 12}}",
             GALE_SOURCE_DIR);
    write_file("kiosk_scene.json", cfg);
    write_file("kiosk_token.txt", "file-secret\n");
    char why[128];
    /* the config's token when nothing else is set */
    proc p;
    const char *a1[] = { "--config", "kiosk_scene.json", "--port", "0", "--cache", CACHE, NULL };
    CHECK(spawn(&p, "kiosk_cfg", a1, NULL) == 0);
    if (!wait_listening(&p)) {
        CHECK(kiosk(p.port, "cfg-secret", why) == 0);
        CHECK(stop(&p) == 0);
        char *err = read_file(p.err_path);
        CHECK_STR_HAS(err, "kiosks enabled: token from the config's kiosk_token");
        free(err);
    } else {
        CHECK(0);
        wait_exit(&p, 1);
    }
    /* the file over both */
    const char *a2[] = { "--config", "kiosk_scene.json", "--port", "0", "--cache", CACHE,
                         "--kiosk-token-file", "kiosk_token.txt", NULL };
    CHECK(spawn(&p, "kiosk_file", a2, "GALE_KIOSK_TOKEN=env-secret") == 0);
    if (!wait_listening(&p)) {
        CHECK(kiosk(p.port, "file-secret", why) == 0);
        CHECK(kiosk(p.port, "env-secret", why) == WIRE_CLOSE_BAD_TOKEN);
        CHECK_STR_HAS(why, "wrong kiosk token");
        usleep(300000); /* the delay after that wrong token */
        CHECK(kiosk(p.port, "cfg-secret", why) == WIRE_CLOSE_BAD_TOKEN);
        CHECK_STR_HAS(why, "wrong kiosk token");
        CHECK(stop(&p) == 0);
        char *err = read_file(p.err_path);
        CHECK_STR_HAS(err, "kiosks enabled: token from kiosk token file kiosk_token.txt");
        free(err);
    } else {
        CHECK(0);
        wait_exit(&p, 1);
    }
    /* the environment over the config */
    CHECK(spawn(&p, "kiosk_env_cfg", a1, "GALE_KIOSK_TOKEN=env-secret") == 0);
    if (!wait_listening(&p)) {
        CHECK(kiosk(p.port, "env-secret", why) == 0);
        CHECK(kiosk(p.port, "cfg-secret", why) == WIRE_CLOSE_BAD_TOKEN);
        CHECK(stop(&p) == 0);
    } else {
        CHECK(0);
        wait_exit(&p, 1);
    }
}

/* Refused at start, exit status 1, with a message naming where the token came from. */
static void start_refused(const char *const *args, const char *env_token, const char *want)
{
    proc p;
    CHECK(spawn(&p, "kiosk_refused", args, env_token) == 0);
    CHECK(wait_exit(&p, 30) == 1);
    char *err = read_file(p.err_path);
    CHECK_STR_HAS(err, want);
    free(err);
}

static void test_refused_at_start(void)
{
    write_file("kiosk_long.txt", T64 "\n");
    write_file("kiosk_empty.txt", "\n");
    char cfg[1024];
    snprintf(cfg, sizeof cfg,
             "{\"kiosk_token\": \"" T64 "\", \"species\": [{\"name\": \"palm\", \"file\": "
             "\"%s/configs/species/palm.json\"}], \"trees\": [{\"species\": \"palm\", "
             "\"pos\": [0, 0]}]}",
             GALE_SOURCE_DIR);
    write_file("kiosk_long.json", cfg);
    const char *file_long[] = { "--port", "0", "--kiosk-token-file", "kiosk_long.txt", NULL };
    start_refused(file_long, NULL,
                  "gale-server: kiosk token: kiosk token file kiosk_long.txt: expected at most "
                  "63 bytes (what a kiosk's hello may carry), got 64");
    const char *plain[] = { "--port", "0", NULL };
    start_refused(plain, "GALE_KIOSK_TOKEN=" T64,
                  "gale-server: kiosk token: GALE_KIOSK_TOKEN: expected at most 63 bytes (what "
                  "a kiosk's hello may carry), got 64");
    const char *cfg_long[] = { "--config", "kiosk_long.json", "--port", "0", NULL };
    start_refused(cfg_long, NULL,
                  "gale-server: bad config: kiosk_long.json: kiosk_token: expected at most 63 "
                  "bytes (what a kiosk's hello may carry), got 64");
    const char *missing[] = { "--port", "0", "--kiosk-token-file", "kiosk_missing.txt", NULL };
    start_refused(missing, "GALE_KIOSK_TOKEN=env-secret",
                  "gale-server: kiosk token: kiosk token file kiosk_missing.txt: cannot open: "
                  "No such file or directory");
    const char *empty[] = { "--port", "0", "--kiosk-token-file", "kiosk_empty.txt", NULL };
    start_refused(empty, NULL,
                  "gale-server: kiosk token: kiosk token file kiosk_empty.txt: the first line is "
                  "empty (expected the kiosk token)");
    /* --check refuses them too */
    const char *check[] = { "--check", "--kiosk-token-file", "kiosk_long.txt", NULL };
    start_refused(check, NULL, "kiosk token file kiosk_long.txt: expected at most 63 bytes");
}

int main(void)
{
    signal(SIGPIPE, SIG_IGN);
    RUN(test_refused_at_start);
    RUN(test_default_no_kiosk);
    RUN(test_env_and_brute_force);
    RUN(test_file_over_env_over_config);
    return check_report();
}
