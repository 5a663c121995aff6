/* gale-server with TLS (server/SERVER.md "TLS"), against a self-signed certificate this
 * test makes with the openssl command under the build tree:
 * - curl gets / and /status over https, trusting that certificate;
 * - a real gale-client (headless kiosk) streams over wss with --tls-ca, and goes on
 *   untouched (one connect, no gap) while beside it a plain HTTP request and a handshake of
 *   garbage hit the same port and are dropped;
 * - a gale-client trusting the system's certificates, or another certificate, is refused
 *   in the handshake and gets no state;
 * - --tls-cert without --tls-key, or an unreadable key, stops the server with the flag
 *   and file named.
 * Exit 77 (skipped) without the openssl or curl commands. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "kiosk_fixture.h"

static char cert[300], key[300], other[300], otherkey[300];

static int sh(const char *cmd)
{
    int st = system(cmd);
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

static int make_certs(void)
{
    snprintf(cert, sizeof cert, "%s/cert.pem", kf_dir);
    snprintf(key, sizeof key, "%s/key.pem", kf_dir);
    snprintf(other, sizeof other, "%s/other.pem", kf_dir);
    snprintf(otherkey, sizeof otherkey, "%s/otherkey.pem", kf_dir);
    char cmd[1600];
    snprintf(cmd, sizeof cmd,
             "openssl req -x509 -newkey rsa:2048 -nodes -keyout %s -out %s -days 2 "
             "-subj /CN=127.0.0.1 -addext subjectAltName=IP:127.0.0.1 2>/dev/null && "
             "openssl req -x509 -newkey rsa:2048 -nodes -keyout %s -out %s -days 2 "
             "-subj /CN=127.0.0.1 -addext subjectAltName=IP:127.0.0.1 2>/dev/null",
             key, cert, otherkey, other);
    return sh(cmd);
}

/* A TCP connection to the port that sends text and reads what comes back for a moment
 * (the server's refusal or nothing). */
static void poke(const char *text, size_t len)
{
    int fd = wsraw_tcp(kf_port, 0);
    if (fd < 0) {
        return;
    }
    wsraw c = { .fd = fd };
    wsraw_send_all(fd, text, len);
    while (wsraw_fill(&c, 1000) == 0 && c.len < 4096) {
    }
    free(c.buf);
    close(fd);
}

static pid_t client(const char *name, const char *ca, const char *frames, char *log, size_t cap)
{
    static char url[64], cache[300], tok[300], out[300];
    snprintf(url, sizeof url, "wss://127.0.0.1:%d", kf_port);
    snprintf(cache, sizeof cache, "%s/cache", kf_dir);
    snprintf(tok, sizeof tok, "%s/token", kf_dir);
    snprintf(log, cap, "%s/%s.log", kf_dir, name);
    snprintf(out, sizeof out, "%s/%s.out", kf_dir, name);
    FILE *f = fopen(tok, "w");
    if (f) {
        fputs(KIOSK_TOKEN "\n", f);
        fclose(f);
    }
    const char *argv[24] = { GALE_CLIENT_EXE, "--url", url, "--role", "kiosk", "--token-file",
                             tok, "--headless", "--frames", frames, "--max-fps", "20",
                             "--size", "320x180", "--wait", "8", "--cache", cache };
    int n = 18;
    if (ca) {
        argv[n++] = "--tls-ca";
        argv[n++] = ca;
    }
    argv[n] = NULL;
    return kf_spawn((char *const *)argv, log, out);
}

static void test_https_wss(void)
{
    const char *extra[] = { "--tls-cert", cert, "--tls-key", key, NULL };
    CHECK(kf_start_server(NULL, extra) == 0);
    char cmd[1600], out[300];
    snprintf(out, sizeof out, "%s/curl.out", kf_dir);
    snprintf(cmd, sizeof cmd,
             "curl -sS --max-time 10 --cacert %s -o /dev/null -w '%%{http_code}\\n' "
             "https://127.0.0.1:%d/ > %s && curl -sS --max-time 10 --cacert %s "
             "https://127.0.0.1:%d/status >> %s",
             cert, kf_port, out, cert, kf_port, out);
    CHECK(sh(cmd) == 0);
    CHECK(proc_log_count(out, "200") >= 1);
    CHECK(proc_log_count(out, "{\"state\":\"open\"") == 1);
    /* plain http to the https port: that request fails, nothing else */
    snprintf(cmd, sizeof cmd, "curl -s --max-time 5 http://127.0.0.1:%d/healthz > /dev/null",
             kf_port);
    CHECK(sh(cmd) != 0);

    /* a kiosk over wss through a plain request and a garbage handshake beside it */
    char good[300];
    pid_t g = client("wss", cert, "160", good, sizeof good);
    CHECK(proc_wait_log(good, "receiving state from tick", 1, 60.0));
    for (int i = 0; i < 3; i++) {
        static const char plain[] = "GET /healthz HTTP/1.1\r\nHost: x\r\n\r\n";
        poke(plain, sizeof plain - 1);
        static const char junk[] = "\x16\x03\x01\x00\x05hello, this is not a TLS handshake";
        poke(junk, sizeof junk - 1);
        usleep(300000);
    }
    CHECK(proc_wait_exit(g, 90.0) == 0);
    CHECK(proc_log_count(good, "connects 1;") == 1);
    CHECK(proc_log_count(good, "gaps 0,") == 1);
    if (proc_log_count(good, "connects 1;") != 1) {
        proc_dump(good);
    }
    snprintf(cmd, sizeof cmd, "curl -sS --max-time 10 --cacert %s https://127.0.0.1:%d/healthz "
                              "> %s", cert, kf_port, out);
    CHECK(sh(cmd) == 0 && proc_log_count(out, "ok tick") == 1);

    /* refused in the handshake: the system's certificates, another certificate */
    char sys[300], oth[300];
    pid_t a = client("system-ca", NULL, "5", sys, sizeof sys);
    CHECK(proc_wait_exit(a, 60.0) != 0);
    CHECK(proc_log_count(sys, "SSL") >= 1);
    CHECK(proc_log_count(sys, "connects 0;") == 1);
    pid_t b = client("other-ca", other, "5", oth, sizeof oth);
    CHECK(proc_wait_exit(b, 60.0) != 0);
    CHECK(proc_log_count(oth, "connects 0;") == 1);
    kf_stop_server();
}

static void test_bad_args(void)
{
    char log[300];
    snprintf(log, sizeof log, "%s/bad.log", kf_dir);
    const char *a1[] = { GALE_SERVER_EXE, "--port", "0", "--tls-cert", cert, NULL };
    pid_t p = kf_spawn((char *const *)a1, log, NULL);
    CHECK(proc_wait_exit(p, 30.0) == 2);
    CHECK(proc_log_count(log, "expected --tls-cert and --tls-key together") == 1);
    const char *a2[] = { GALE_SERVER_EXE, "--port", "0", "--tls-cert", cert, "--tls-key",
                         "/nonexistent/key.pem", NULL };
    p = kf_spawn((char *const *)a2, log, NULL);
    CHECK(proc_wait_exit(p, 30.0) == 1);
    CHECK(proc_log_count(log, "--tls-key /nonexistent/key.pem: cannot read") == 1);
}

int main(void)
{
    kf_init("test_server_tls");
    if (sh("command -v openssl >/dev/null && command -v curl >/dev/null") != 0 ||
        make_certs() != 0) {
        fprintf(stderr, "skipped: the openssl and curl commands are needed\n");
        return 77;
    }
    RUN(test_https_wss);
    RUN(test_bad_args);
    kf_stop_server();
    return check_report();
}
