/* Connection hygiene of the real gale-server process on loopback (server/SERVER.md
 * "Connections"): upgrades that never say hello are closed with 4009 after the deadline;
 * a stuck reader is culled and its descriptor released within the close bound; under a
 * lowered RLIMIT_NOFILE the extra connections get 4010 or are refused, /healthz answers
 * and the server does not spin; SIGTERM with stuck peers ends within ~3 s and a reading
 * peer gets 1001; --max-connections turns the next away with 4010; a ping flood is closed
 * with 4012, by the unread replies or by the rate; bad option values are refused. Palm
 * scenes, assets cached in the build tree. */
#include "check.h"
#include "mono.h"
#include "net.h"
#include "server_wsraw.h"
#include "wire.h"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>

static const char *small_cfg = "hygiene_small.json"; /* 12 trees: cheap to serve */
static const char *big_cfg = "hygiene_big.json";     /* 600 trees: fills a socket fast */

typedef struct child {
    pid_t pid;
    int port;
    char log[64]; /* its stderr, a file in the build tree */
} child;

static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (f) {
        fputs(text, f);
        fclose(f);
    }
}

static void write_scene(const char *path, int trees)
{
    char cfg[1024];
    snprintf(cfg, sizeof cfg,
             "{\"name\": \"hygiene\", \"species\": [{\"name\": \"palm\", \"file\": "
             "\"%s/configs/species/palm.json\", \"modes\": 8}],"
             " \"forest\": [{\"species\": \"palm\", \"count\": %d, \"area_min\": [-120, -120],"
             " \"area_max\": [120, 120], \"min_spacing_m\": 3}],"
             " \"wind\": {\"solver\": false, \"u10_ms\": 12}}",
             GALE_SOURCE_DIR, trees);
    write_file(path, cfg);
}

/* Starts gale-server on an ephemeral loopback port with the given extra arguments (NULL
 * ended); nofile > 0 sets both RLIMIT_NOFILE limits in the child before exec. 0 ok. */
static int start(child *c, const char *cfg, int nofile, const char *const *extra, const char *tag)
{
    memset(c, 0, sizeof *c);
    snprintf(c->log, sizeof c->log, "hygiene_%s.log", tag);
    const char *args[24] = { GALE_SERVER_EXE, "--config", cfg, "--port", "0", "--iface",
                             "127.0.0.1", "--cache", "hygiene_cache" };
    int n = 9;
    for (int i = 0; extra && extra[i] && n < 23; i++) {
        args[n++] = extra[i];
    }
    args[n] = NULL;
    int po[2];
    if (pipe(po)) {
        return -1;
    }
    c->pid = fork();
    if (c->pid == 0) {
        int lf = open(c->log, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        dup2(po[1], 1);
        dup2(lf, 2);
        close(po[0]);
        close(po[1]);
        close(lf);
        if (nofile > 0) {
            struct rlimit rl = { (rlim_t)nofile, (rlim_t)nofile };
            setrlimit(RLIMIT_NOFILE, &rl);
        }
        execv(GALE_SERVER_EXE, (char *const *)args);
        _exit(127);
    }
    close(po[1]);
    char line[256];
    size_t got = 0;
    struct pollfd p = { .fd = po[0], .events = POLLIN };
    while (got + 1 < sizeof line && !memchr(line, '\n', got) && poll(&p, 1, 60000) > 0) {
        ssize_t k = read(po[0], line + got, sizeof line - 1 - got); /* the first run bakes */
        if (k <= 0) {
            break;
        }
        got += (size_t)k;
    }
    line[got] = 0;
    close(po[0]);
    if (sscanf(line, "gale-server: listening on port %d", &c->port) != 1 || c->port <= 0) {
        fprintf(stderr, "  server did not start: \"%s\"\n", line);
        kill(c->pid, SIGKILL);
        waitpid(c->pid, NULL, 0);
        c->pid = 0;
        return -1;
    }
    return 0;
}

/* Waits for the child's exit: its status, 128 + signal, or -1 after timeout_s (killed). */
static int wait_exit(child *c, double timeout_s)
{
    double t0 = mono_s();
    while (mono_s() - t0 < timeout_s) {
        int st;
        if (waitpid(c->pid, &st, WNOHANG) == c->pid) {
            c->pid = 0;
            return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
        }
        usleep(5000);
    }
    kill(c->pid, SIGKILL);
    waitpid(c->pid, NULL, 0);
    c->pid = 0;
    return -1;
}

static void stop(child *c)
{
    if (c->pid > 0) {
        kill(c->pid, SIGTERM);
        CHECK(wait_exit(c, 10) == 0);
    }
}

/* Descriptors the child holds (/proc/PID/fd), -1 when unreadable. */
static int child_fds(const child *c)
{
    char path[64];
    snprintf(path, sizeof path, "/proc/%d/fd", (int)c->pid);
    DIR *d = opendir(path);
    if (!d) {
        return -1;
    }
    int n = 0;
    for (struct dirent *e; (e = readdir(d));) {
        n += e->d_name[0] != '.';
    }
    closedir(d);
    return n;
}

/* The child's CPU time (user + system) [s], -1 when unreadable. */
static double child_cpu_s(const child *c)
{
    char path[64], buf[1024];
    snprintf(path, sizeof path, "/proc/%d/stat", (int)c->pid);
    FILE *f = fopen(path, "r");
    if (!f) {
        return -1;
    }
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = 0;
    const char *p = strrchr(buf, ')');
    unsigned long long ut = 0, st = 0;
    if (!p || sscanf(p + 2, "%*c %*d %*d %*d %*d %*d %*u %*u %*u %*u %*u %llu %llu", &ut, &st) != 2) {
        return -1;
    }
    return (double)(ut + st) / (double)sysconf(_SC_CLK_TCK);
}

/* The M of /healthz's "ok tick N clients M", -1 when it does not answer 200. */
static int healthz_clients(int port)
{
    char *body;
    int st = wsraw_http_get(port, "/healthz", &body);
    int tick = 0, clients = -1;
    if (st != 200 || !body || sscanf(body, "ok tick %d clients %d", &tick, &clients) != 2) {
        clients = -1;
    }
    free(body);
    return clients;
}

static void send_hello(wsraw *w)
{
    char h[128];
    snprintf(h, sizeof h, "{\"type\": \"hello\", \"protocol\": %d, \"role\": \"viewer\"}",
             WIRE_PROTOCOL_VERSION);
    wsraw_text(w, h);
}

/* Opens a connection and says hello; 1 when the welcome came, else the close code seen
 * (4010...) or -1 when the connection was refused or dropped. */
static int join(wsraw *w, int port)
{
    if (wsraw_open(w, port, 0)) {
        return -1;
    }
    send_hello(w);
    uint8_t *m;
    size_t n;
    int op = wsraw_recv(w, &m, &n, 3000);
    int ok = op == 1 && strstr((const char *)m, "\"welcome\"") != NULL;
    free(m);
    if (ok) {
        return 1;
    }
    if (op == 8) {
        return w->close_code;
    }
    int code = op == 1 ? wsraw_wait_close(w, 3000) : 0; /* an error message, then the close */
    return code ? code : -1;
}

/* Upgrades that say nothing are closed with 4009 after the deadline (0.5 s here); one that
 * said hello stays. */
static void test_hello_deadline(void)
{
    const char *extra[] = { "--hello-timeout", "0.5", NULL };
    child c;
    if (start(&c, small_cfg, 0, extra, "hello")) {
        CHECK(0);
        return;
    }
    wsraw good, idle[3];
    CHECK(join(&good, c.port) == 1);
    double t0 = mono_s();
    for (int i = 0; i < 3; i++) {
        CHECK(wsraw_open(&idle[i], c.port, 0) == 0);
    }
    CHECK(healthz_clients(c.port) == 4);
    for (int i = 0; i < 3; i++) {
        CHECK(wsraw_wait_close(&idle[i], 3000) == WIRE_CLOSE_ORDER);
        CHECK_STR_HAS(idle[i].close_reason, "hello: expected within 500 ms");
    }
    double dt = mono_s() - t0;
    fprintf(stderr, "  idle upgrades closed after %.2f s\n", dt);
    CHECK(dt >= 0.45 && dt < 1.5);
    for (int i = 0; i < 3; i++) {
        wsraw_close(&idle[i]);
    }
    /* their slots are free again; the one that said hello is still served */
    int clients = -1;
    for (int i = 0; i < 50 && clients != 1; i++) {
        usleep(20000);
        clients = healthz_clients(c.port);
    }
    CHECK(clients == 1);
    char *metrics = NULL;
    CHECK(wsraw_http_get(c.port, "/metrics", &metrics) == 200);
    CHECK_STR_HAS(metrics ? metrics : "", "gale_hello_timeouts_total 3\n");
    free(metrics);
    int state = 0;
    for (int i = 0; i < 40 && state < 10; i++) {
        uint8_t *b;
        size_t n;
        int op = wsraw_recv(&good, &b, &n, 2000);
        free(b);
        state += op == 2;
        if (op < 0 || op == 8) {
            break;
        }
    }
    CHECK(state >= 10);
    CHECK(good.close_code == 0);
    wsraw_close(&good);
    stop(&c);
}

/* A reader that never reads (small receive buffer) is culled with 4008 and the server's
 * socket for it is closed within the close bound though the peer never takes the close:
 * the child's descriptor count and /healthz's client count come back down. */
static void test_stuck_reader_released(void)
{
    child c;
    if (start(&c, big_cfg, 0, NULL, "stuck")) {
        CHECK(0);
        return;
    }
    int fds0 = child_fds(&c);
    wsraw stuck;
    CHECK(wsraw_open(&stuck, c.port, 4096) == 0);
    send_hello(&stuck);
    double t0 = mono_s();
    usleep(300000);
    CHECK(child_fds(&c) == fds0 + 1);
    CHECK(healthz_clients(c.port) == 1);
    /* nothing taken for NET_STALL_MS (10 s) once the socket is full, then at most the
     * close bound (2 s) */
    double culled = -1, released = -1;
    char log[8192] = "";
    while (mono_s() - t0 < 20.0 && released < 0) {
        if (culled < 0) {
            FILE *f = fopen(c.log, "r");
            if (f) {
                log[fread(log, 1, sizeof log - 1, f)] = 0;
                fclose(f);
            }
            culled = strstr(log, "closing 4008 (slow)") ? mono_s() - t0 : -1;
        }
        if (child_fds(&c) == fds0 && healthz_clients(c.port) == 0) {
            released = mono_s() - t0;
        }
        usleep(20000);
    }
    fprintf(stderr, "  stuck reader culled %.2f s and its socket released %.2f s after its hello\n",
            culled, released);
    CHECK(culled > 0 && released >= culled);
    CHECK(released - culled < (NET_CLOSE_BOUND_MS + 400) * 1e-3);
    CHECK_STR_HAS(log, "closing 4008 (slow)");
    wsraw_close(&stuck);
    stop(&c);
}

/* Under RLIMIT_NOFILE 64 (soft and hard, so the server cannot raise it): the limit is
 * lowered and logged; connections past it get 4010; idle sockets past the descriptor cap
 * are refused at accept; /healthz answers and the server does not spin on EMFILE. */
static void test_fd_limit(void)
{
    child c;
    if (start(&c, small_cfg, 64, NULL, "nofile")) {
        CHECK(0);
        return;
    }
    FILE *f = fopen(c.log, "r");
    char log[4096] = "";
    if (f) {
        log[fread(log, 1, sizeof log - 1, f)] = 0;
        fclose(f);
    }
    int limit = 0;
    const char *l = strstr(log, "connection limit ");
    CHECK(l && sscanf(l, "connection limit %d, lowered from 2048", &limit) == 1);
    CHECK_STR_HAS(log, "RLIMIT_NOFILE 64");
    fprintf(stderr, "  connection limit under RLIMIT_NOFILE 64: %d\n", limit);
    CHECK(limit > 4 && limit < 64);
    enum { N = 70 };
    static wsraw w[N];
    int welcomed = 0, full = 0, refused = 0;
    for (int i = 0; i < N; i++) {
        int r = join(&w[i], c.port);
        welcomed += r == 1;
        full += r == WIRE_CLOSE_FULL;
        refused += r == -1;
        if (r != 1) {
            wsraw_close(&w[i]);
        }
    }
    fprintf(stderr, "  %d connections: %d welcomed, %d closed with 4010, %d refused\n", N,
            welcomed, full, refused);
    CHECK(welcomed == limit);
    CHECK(welcomed + full + refused == N);
    CHECK(full > 0);
    CHECK(healthz_clients(c.port) == limit);
    /* idle sockets that never send a request fill the descriptors up to the cap: those past
     * it are closed at once, and the server stays idle instead of spinning on accept */
    enum { IDLE = 40 };
    int idle[IDLE], ended = 0;
    for (int i = 0; i < IDLE; i++) {
        idle[i] = wsraw_tcp(c.port, 0);
    }
    double cpu0 = child_cpu_s(&c), t0 = mono_s();
    usleep(1000000);
    double cpu = child_cpu_s(&c) - cpu0, dt = mono_s() - t0;
    for (int i = 0; i < IDLE; i++) {
        struct pollfd p = { .fd = idle[i], .events = POLLIN };
        char b;
        ended += idle[i] < 0 || (poll(&p, 1, 0) > 0 && recv(idle[i], &b, 1, 0) <= 0);
    }
    fprintf(stderr, "  %d idle sockets: %d ended at once; server CPU %.2f s in %.2f s\n", IDLE,
            ended, cpu, dt);
    CHECK(ended > 0);
    CHECK(cpu >= 0 && cpu < 0.3 * dt);
    for (int i = 0; i < IDLE; i++) {
        if (idle[i] >= 0) {
            close(idle[i]);
        }
    }
    int clients = -1;
    for (int i = 0; i < 50 && clients < 0; i++) {
        usleep(20000);
        clients = healthz_clients(c.port);
    }
    CHECK(clients == limit);
    for (int i = 0; i < N; i++) {
        if (w[i].fd > 0) {
            wsraw_close(&w[i]);
        }
    }
    struct stat st;
    CHECK(stat(c.log, &st) == 0 && st.st_size < 65536); /* no flood of log lines */
    stop(&c);
}

/* SIGTERM with a stuck reader and idle upgrades: the process exits 0 within ~3 s, and the
 * peers that read get 1001. */
static void test_sigterm_stuck_peers(void)
{
    child c;
    if (start(&c, big_cfg, 0, NULL, "sigterm")) {
        CHECK(0);
        return;
    }
    wsraw stuck[3], idle, good;
    for (int i = 0; i < 3; i++) {
        CHECK(wsraw_open(&stuck[i], c.port, 4096) == 0);
        send_hello(&stuck[i]);
    }
    CHECK(wsraw_open(&idle, c.port, 0) == 0);
    CHECK(join(&good, c.port) == 1);
    /* let the stuck readers' sockets fill (the good one keeps reading) */
    double t0 = mono_s();
    while (mono_s() - t0 < 1.0) {
        uint8_t *b;
        size_t n;
        wsraw_recv(&good, &b, &n, 200);
        free(b);
    }
    CHECK(kill(c.pid, SIGTERM) == 0);
    t0 = mono_s();
    CHECK(wsraw_wait_close(&good, 4000) == WIRE_CLOSE_GOING_AWAY);
    CHECK_STR_HAS(good.close_reason, "shutting down");
    CHECK(wsraw_wait_close(&idle, 4000) == WIRE_CLOSE_GOING_AWAY);
    int rc = wait_exit(&c, 10);
    double dt = mono_s() - t0;
    fprintf(stderr, "  SIGTERM with 3 stuck readers: exit %d after %.2f s\n", rc, dt);
    CHECK(rc == 0);
    CHECK(dt < (NET_CLOSE_BOUND_MS + 350) * 1e-3); /* the bound, not the drain's backstop */
    for (int i = 0; i < 3; i++) {
        wsraw_close(&stuck[i]);
    }
    wsraw_close(&idle);
    wsraw_close(&good);
}

/* --max-connections 3: the fourth gets 4010; a ping flood is closed with 4012 (too many
 * messages); pings at 5 a second are not. */
static void test_ping_flood(void)
{
    const char *extra[] = { "--max-connections", "3", NULL };
    child c;
    if (start(&c, small_cfg, 0, extra, "flood")) {
        CHECK(0);
        return;
    }
    wsraw calm, flood, third, fourth;
    CHECK(join(&calm, c.port) == 1);
    CHECK(join(&flood, c.port) == 1);
    CHECK(join(&third, c.port) == 1);
    CHECK(join(&fourth, c.port) == WIRE_CLOSE_FULL);
    CHECK_STR_HAS(fourth.close_reason, "server full: 3 connections");
    wsraw_close(&fourth);
    wsraw_close(&third);
    /* 60 at once: the replies pile up unread */
    for (int i = 0; i < 60; i++) {
        char p[96];
        snprintf(p, sizeof p, "{\"type\": \"ping\", \"id\": %d, \"client_us\": 1}", i);
        wsraw_text(&flood, p);
    }
    CHECK(wsraw_wait_close(&flood, 3000) == WIRE_CLOSE_RATE);
    CHECK_STR_HAS(flood.close_reason, "too many messages");
    wsraw_close(&flood);
    /* 50 a second, reading every pong: the bucket (a burst of 20, then 10 a second) ends it
     * after about 25 */
    CHECK(join(&flood, c.port) == 1);
    int flood_pongs = 0;
    double f0 = mono_s(), fnext = f0;
    while (mono_s() - f0 < 3.0 && !flood.close_code) {
        if (mono_s() >= fnext) {
            wsraw_text(&flood, "{\"type\": \"ping\", \"id\": 2, \"client_us\": 1}");
            fnext += 0.02;
        }
        uint8_t *b;
        size_t n;
        int op = wsraw_recv(&flood, &b, &n, 5);
        flood_pongs += op == 1 && strstr((const char *)b, "\"pong\"");
        free(b);
    }
    fprintf(stderr, "  50 pings a second: %d pongs, then close %d after %.2f s\n", flood_pongs,
            flood.close_code, mono_s() - f0);
    CHECK(flood.close_code == WIRE_CLOSE_RATE);
    CHECK_STR_HAS(flood.close_reason, "expected <= 10 a second after a burst of 20");
    CHECK(flood_pongs >= 20 && flood_pongs <= 40);
    int pongs = 0;
    double t0 = mono_s(), next = t0;
    while (mono_s() - t0 < 3.0 && !calm.close_code) {
        if (mono_s() >= next) {
            wsraw_text(&calm, "{\"type\": \"ping\", \"id\": 1, \"client_us\": 1}");
            next += 0.2;
        }
        uint8_t *b;
        size_t n;
        int op = wsraw_recv(&calm, &b, &n, 50);
        pongs += op == 1 && strstr((const char *)b, "\"pong\"");
        free(b);
    }
    CHECK(calm.close_code == 0);
    CHECK(pongs >= 13);
    wsraw_close(&calm);
    wsraw_close(&flood);
    stop(&c);
}

/* Bad values of the new options are refused with exit status 2. */
static void test_bad_options(void)
{
    const char *bad[][3] = { { "--max-connections", "0", "expected 1..1000000" },
                             { "--hello-timeout", "0", "expected seconds in [0.01, 3600]" } };
    for (int i = 0; i < 2; i++) {
        child c;
        const char *extra[] = { bad[i][0], bad[i][1], NULL };
        CHECK(start(&c, small_cfg, 0, extra, "badopt") == -1);
        FILE *f = fopen(c.log, "r");
        char log[1024] = "";
        if (f) {
            log[fread(log, 1, sizeof log - 1, f)] = 0;
            fclose(f);
        }
        CHECK_STR_HAS(log, bad[i][2]);
    }
}

int main(void)
{
    signal(SIGPIPE, SIG_IGN);
    write_scene(small_cfg, 12);
    write_scene(big_cfg, 600);
    RUN(test_hello_deadline);
    RUN(test_stuck_reader_released);
    RUN(test_fd_limit);
    RUN(test_sigterm_stuck_peers);
    RUN(test_ping_flood);
    RUN(test_bad_options);
    return check_report();
}
