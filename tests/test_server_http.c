/* HTTP of the network module on loopback (server/SERVER.md "HTTP"): a net_server with
 * two synthetic assets, a 1 s idle timeout and a small kernel send buffer, so that a
 * slow reader outlasts the timeout many times over and still gets every byte, while a
 * reader that stops is cut and resumes with Range. HEAD, 405, ETag / 304, Range 206 /
 * 416, and a Content-Length that matches the bytes sent, on plain HTTP/1.1 sockets. */
#include "check.h"
#include "mono.h"
#include "net.h"
#include "server_wsraw.h"

#include <pthread.h>
#include <stdbool.h>
#include <strings.h>

#define BIG_LEN (1536u * 1024u) /* well past the kernel buffers the test allows */
#define IDLE_S 1

static net_server *N;
static pthread_t N_thread;
static uint8_t *big;
static const uint8_t small[] = "0123456789abcdefghijklmnopqrstuvwxyz";
static const char *big_hash = "00000000000000b1";
static const char *small_hash = "00000000000000a5";
static char big_url[64], small_url[64];

static int no_control(void *user, net_peer *peer, const char *text, size_t len, char **reply,
                      size_t *reply_len, char *why, size_t why_cap)
{
    (void)user, (void)peer, (void)text, (void)len, (void)reply, (void)reply_len;
    snprintf(why, why_cap, "no control in this test");
    return 4001;
}

static void *serve(void *arg)
{
    (void)arg;
    net_run(N, 500);
    return NULL;
}

static int start(void)
{
    big = malloc(BIG_LEN);
    if (!big) {
        return -1;
    }
    uint64_t x = 0x9e3779b97f4a7c15ull;
    for (size_t i = 0; i < BIG_LEN; i++) {
        x ^= x << 13, x ^= x >> 7, x ^= x << 17;
        big[i] = (uint8_t)(x >> 24);
    }
    static net_asset assets[2];
    snprintf(assets[0].hash, sizeof assets[0].hash, "%s", big_hash);
    assets[0].bytes = big;
    assets[0].len = BIG_LEN;
    snprintf(assets[1].hash, sizeof assets[1].hash, "%s", small_hash);
    assets[1].bytes = small;
    assets[1].len = sizeof small - 1;
    snprintf(big_url, sizeof big_url, "/assets/%s.gasset", big_hash);
    snprintf(small_url, sizeof small_url, "/assets/%s.gasset", small_hash);
    gale_err e;
    N = net_create(&(net_desc){ .port = -1, .iface = "127.0.0.1", .snap_cap = 1024,
                                .extra_cap = 1024, .assets = assets, .n_assets = 2,
                                .control = no_control, .http_idle_s = IDLE_S,
                                .http_sndbuf = 16384 },
                   &e);
    if (!N) {
        fprintf(stderr, "%s\n", e.msg);
        return -1;
    }
    return pthread_create(&N_thread, NULL, serve, NULL);
}

/* --- a small HTTP/1.1 client ------------------------------------------------------------ */

typedef struct resp {
    int status;
    char head[2048];   /* status line and headers, NUL-terminated */
    long clen;         /* Content-Length, -1 when absent */
    uint8_t *body;     /* owned, body_len bytes */
    size_t body_len;
} resp;

static void resp_free(resp *r)
{
    free(r->body);
    memset(r, 0, sizeof *r);
}

/* The value of header name (lower case, without the colon) in r, or "" (static buffer). */
static const char *hdr(const resp *r, const char *name)
{
    static char v[256];
    size_t nl = strlen(name);
    v[0] = 0;
    for (const char *l = strstr(r->head, "\r\n"); l && l[2]; l = strstr(l + 2, "\r\n")) {
        const char *k = l + 2;
        if (!strncasecmp(k, name, nl) && k[nl] == ':') {
            k += nl + 1;
            while (*k == ' ') {
                k++;
            }
            size_t n = strcspn(k, "\r");
            snprintf(v, sizeof v, "%.*s", (int)n, k);
            break;
        }
    }
    return v;
}

static int send_req(wsraw *c, const char *req)
{
    return wsraw_send_all(c->fd, req, strlen(req));
}

/* Reads one response from c: the headers, then Content-Length bytes of body unless
 * no_body (HEAD, 304). 0 ok, -1 on a malformed head or when the connection ends early
 * (r->body then holds what came). */
static int read_resp(wsraw *c, resp *r, bool no_body, int timeout_ms)
{
    memset(r, 0, sizeof *r);
    r->clen = -1;
    size_t end = 0;
    while (!end) {
        for (size_t i = 3; i < c->len; i++) {
            if (!memcmp(c->buf + i - 3, "\r\n\r\n", 4)) {
                end = i + 1;
                break;
            }
        }
        if (!end && wsraw_fill(c, timeout_ms)) {
            return -1;
        }
    }
    snprintf(r->head, sizeof r->head, "%.*s", (int)end, (const char *)c->buf);
    memmove(c->buf, c->buf + end, c->len - end);
    c->len -= end;
    if (sscanf(r->head, "HTTP/1.1 %d", &r->status) != 1) {
        return -1;
    }
    const char *cl = hdr(r, "content-length");
    if (*cl) {
        r->clen = atol(cl);
    }
    size_t want = no_body ? 0 : (size_t)(r->clen > 0 ? r->clen : 0);
    int rc = 0;
    while (c->len < want) {
        if (wsraw_fill(c, timeout_ms)) {
            rc = -1;
            want = c->len;
        }
    }
    r->body = malloc(want + 1);
    if (!r->body) {
        return -1;
    }
    memcpy(r->body, c->buf, want);
    r->body[want] = 0;
    r->body_len = want;
    memmove(c->buf, c->buf + want, c->len - want);
    c->len -= want;
    return rc;
}

/* True when the server closes c within timeout_ms with no byte left over. */
static bool ends_clean(wsraw *c, int timeout_ms)
{
    struct pollfd p = { .fd = c->fd, .events = POLLIN };
    if (c->len || poll(&p, 1, timeout_ms) <= 0) {
        return false;
    }
    char b;
    return recv(c->fd, &b, 1, 0) == 0;
}

/* One request on a fresh connection with "Connection: close" added: the response, and
 * whether the server then closed with nothing after the body. */
static bool one(const char *method, const char *path, const char *extra, bool no_body, resp *r)
{
    wsraw c;
    memset(&c, 0, sizeof c);
    c.fd = wsraw_tcp(net_port(N), 0);
    char req[1024];
    snprintf(req, sizeof req, "%s %s HTTP/1.1\r\nHost: 127.0.0.1\r\n%sConnection: close\r\n\r\n",
             method, path, extra ? extra : "");
    bool ok = c.fd >= 0 && !send_req(&c, req) && !read_resp(&c, r, no_body, 3000) &&
              ends_clean(&c, 3000);
    wsraw_close(&c);
    return ok;
}

/* --- tests ------------------------------------------------------------------------------ */

static void test_head(void)
{
    wsraw c;
    memset(&c, 0, sizeof c);
    c.fd = wsraw_tcp(net_port(N), 0);
    CHECK(c.fd >= 0);
    char req[512];
    /* HEAD then GET on one keep-alive connection: the GET's status line must come right
     * after the HEAD's headers, with no body between them. */
    snprintf(req, sizeof req,
             "HEAD %s HTTP/1.1\r\nHost: x\r\n\r\nGET %s HTTP/1.1\r\nHost: x\r\n\r\n"
             "HEAD /healthz HTTP/1.1\r\nHost: x\r\n\r\nHEAD /nothing HTTP/1.1\r\nHost: x\r\n\r\n",
             big_url, small_url);
    CHECK(!send_req(&c, req));
    resp r;
    CHECK(!read_resp(&c, &r, true, 3000));
    CHECK(r.status == 200);
    CHECK(r.clen == (long)BIG_LEN);
    CHECK(!strcmp(hdr(&r, "etag"), "\"00000000000000b1\""));
    CHECK(!strcmp(hdr(&r, "accept-ranges"), "bytes"));
    resp_free(&r);
    CHECK(c.len == 0 || !memcmp(c.buf, "HTTP/1.1 ", 9));
    CHECK(!read_resp(&c, &r, false, 3000));
    CHECK(r.status == 200 && r.body_len == sizeof small - 1 && !memcmp(r.body, small, r.body_len));
    resp_free(&r);
    CHECK(!read_resp(&c, &r, true, 3000));
    CHECK(r.status == 200 && r.clen == (long)strlen("ok tick 0 clients 0\n"));
    resp_free(&r);
    CHECK(!read_resp(&c, &r, true, 3000));
    CHECK(r.status == 404 && r.clen == (long)strlen("not found\n"));
    resp_free(&r);
    /* nothing more: no body of any HEAD came after all */
    struct pollfd p = { .fd = c.fd, .events = POLLIN };
    CHECK(c.len == 0 && poll(&p, 1, 300) == 0);
    wsraw_close(&c);

    CHECK(one("HEAD", big_url, NULL, true, &r));
    CHECK(r.status == 200 && r.clen == (long)BIG_LEN && r.body_len == 0);
    resp_free(&r);
}

static void test_methods(void)
{
    static const char *const with_body[] = { "POST", "PUT", "PATCH" };
    static const char *const without[] = { "DELETE", "OPTIONS" };
    const char *text = "method not allowed: GET and HEAD are served\n";
    resp r;
    /* Each on a keep-alive connection: 405, Allow, a body of exactly Content-Length
     * bytes, and the request's own body skipped so the next request is answered. */
    for (int i = 0; i < 5; i++) {
        const char *m = i < 3 ? with_body[i] : without[i - 3];
        wsraw c;
        memset(&c, 0, sizeof c);
        c.fd = wsraw_tcp(net_port(N), 0);
        char req[512];
        snprintf(req, sizeof req,
                 "%s %s HTTP/1.1\r\nHost: x\r\n%s\r\n%sGET /healthz HTTP/1.1\r\nHost: x\r\n"
                 "Connection: close\r\n\r\n",
                 m, i & 1 ? small_url : "/healthz",
                 i < 3 ? "Content-Length: 5\r\n" : "", i < 3 ? "hello" : "");
        CHECK(c.fd >= 0 && !send_req(&c, req));
        CHECK(!read_resp(&c, &r, false, 3000));
        CHECK(r.status == 405);
        CHECK(!strcmp(hdr(&r, "allow"), "GET, HEAD"));
        CHECK(r.clen == (long)strlen(text) && r.body_len == strlen(text));
        CHECK(r.body && !strcmp((const char *)r.body, text));
        resp_free(&r);
        CHECK(!read_resp(&c, &r, false, 3000));
        CHECK(r.status == 200 && !strcmp((const char *)r.body, "ok tick 0 clients 0\n"));
        resp_free(&r);
        CHECK(ends_clean(&c, 3000));
        wsraw_close(&c);
    }
    /* an empty POST body, and a POST with no Content-Length at all */
    CHECK(one("POST", "/metrics", "Content-Length: 0\r\n", false, &r));
    CHECK(r.status == 405 && r.clen == (long)strlen(text) && r.body_len == strlen(text));
    resp_free(&r);
    wsraw c;
    memset(&c, 0, sizeof c);
    c.fd = wsraw_tcp(net_port(N), 0);
    CHECK(c.fd >= 0 && !send_req(&c, "POST /healthz HTTP/1.1\r\nHost: x\r\n\r\n"));
    CHECK(!read_resp(&c, &r, false, 3000));
    CHECK(r.status == 405 && r.clen == (long)strlen(text) && r.body_len == strlen(text));
    resp_free(&r);
    wsraw_close(&c);
}

static void test_lengths(void)
{
    /* Every response's Content-Length is the body that follows, then the server closes. */
    static const char *const paths[] = { "/healthz", "/metrics", "/nothing", "/assets/nope" };
    resp r;
    for (int i = 0; i < 4; i++) {
        CHECK(one("GET", paths[i], NULL, false, &r));
        CHECK(r.clen >= 0 && r.body_len == (size_t)r.clen);
        CHECK(r.status == (i < 2 ? 200 : 404));
        CHECK(!strcmp(hdr(&r, "cache-control"), "no-store"));
        resp_free(&r);
    }
    CHECK(one("GET", small_url, NULL, false, &r));
    CHECK(r.status == 200 && r.body_len == sizeof small - 1 && r.clen == (long)r.body_len);
    CHECK(!strcmp(hdr(&r, "content-type"), "application/octet-stream"));
    CHECK(!strcmp(hdr(&r, "etag"), "\"00000000000000a5\""));
    resp_free(&r);
    char path[64];
    snprintf(path, sizeof path, "/assets/%s", small_hash); /* without .gasset */
    CHECK(one("GET", path, NULL, false, &r));
    CHECK(r.status == 200 && r.body_len == sizeof small - 1);
    resp_free(&r);
}

static void test_etag(void)
{
    static const char *const hit[] = { "\"00000000000000a5\"", "W/\"00000000000000a5\"", "*",
                                       "\"x\", \"00000000000000a5\"" };
    static const char *const miss[] = { "\"00000000000000b1\"", "\"x\"", "00000000000000a5" };
    char extra[256];
    resp r;
    for (int i = 0; i < 4; i++) {
        snprintf(extra, sizeof extra, "If-None-Match: %s\r\n", hit[i]);
        CHECK(one("GET", small_url, extra, true, &r)); /* no byte after the headers */
        CHECK(r.status == 304);
        CHECK(!strcmp(hdr(&r, "etag"), "\"00000000000000a5\""));
        resp_free(&r);
        CHECK(one("HEAD", small_url, extra, true, &r));
        CHECK(r.status == 304);
        resp_free(&r);
    }
    for (int i = 0; i < 3; i++) {
        snprintf(extra, sizeof extra, "If-None-Match: %s\r\n", miss[i]);
        CHECK(one("GET", small_url, extra, false, &r));
        CHECK(r.status == 200 && r.body_len == sizeof small - 1);
        resp_free(&r);
    }
    /* /healthz carries no tag: If-None-Match * does not make it 304 */
    CHECK(one("GET", "/healthz", "If-None-Match: *\r\n", false, &r));
    CHECK(r.status == 200 && !*hdr(&r, "etag"));
    resp_free(&r);
}

/* GET small_url with the given extra header lines; checks status and the body. */
static void range_case(const char *extra, int status, const char *content_range,
                       size_t first, size_t n)
{
    resp r;
    CHECK(one("GET", small_url, extra, false, &r));
    if (r.status != status) {
        fprintf(stderr, "  %s: status %d, expected %d\n", extra, r.status, status);
    }
    CHECK(r.status == status);
    CHECK(!strcmp(hdr(&r, "content-range"), content_range));
    CHECK(r.clen == (long)r.body_len);
    if (status != 416) {
        CHECK(r.body_len == n && !memcmp(r.body, small + first, n));
    }
    resp_free(&r);
}

static void test_range(void)
{
    const size_t len = sizeof small - 1; /* 36 */
    range_case("Range: bytes=10-19\r\n", 206, "bytes 10-19/36", 10, 10);
    range_case("Range: bytes=30-\r\n", 206, "bytes 30-35/36", 30, 6);
    range_case("Range: bytes=-4\r\n", 206, "bytes 32-35/36", 32, 4);
    range_case("Range: bytes=0-\r\n", 206, "bytes 0-35/36", 0, len);
    range_case("Range: bytes=35-1000\r\n", 206, "bytes 35-35/36", 35, 1);
    range_case("Range: bytes=-1000\r\n", 206, "bytes 0-35/36", 0, len);
    range_case("Range: bytes=36-\r\n", 416, "bytes */36", 0, 0);
    range_case("Range: bytes=-0\r\n", 416, "bytes */36", 0, 0);
    /* several ranges, bad syntax, another unit: the whole, 200 */
    range_case("Range: bytes=0-1,5-6\r\n", 200, "", 0, len);
    range_case("Range: bytes=5-2\r\n", 200, "", 0, len);
    range_case("Range: lines=1-2\r\n", 200, "", 0, len);
    /* If-Range: the range only when the tag is the asset's */
    range_case("Range: bytes=10-19\r\nIf-Range: \"00000000000000a5\"\r\n", 206, "bytes 10-19/36",
               10, 10);
    range_case("Range: bytes=10-19\r\nIf-Range: \"00000000000000b1\"\r\n", 200, "", 0, len);
    range_case("Range: bytes=10-19\r\nIf-Range: Tue, 01 Dec 2026 20:00:00 GMT\r\n", 200, "", 0,
               len);
    /* Range is for GET only: HEAD gets the 200 headers */
    resp r;
    CHECK(one("HEAD", small_url, "Range: bytes=10-19\r\n", true, &r));
    CHECK(r.status == 200 && r.clen == (long)len && !*hdr(&r, "content-range"));
    resp_free(&r);
    /* 416 body length matches its Content-Length */
    CHECK(one("GET", small_url, "Range: bytes=99-\r\n", false, &r));
    CHECK(r.status == 416 && r.clen == (long)strlen("range not satisfiable\n") &&
          r.body_len == (size_t)r.clen);
    resp_free(&r);
    /* the big one: a range deep inside */
    CHECK(one("GET", big_url, "Range: bytes=1000000-1000099\r\n", false, &r));
    CHECK(r.status == 206 && r.body_len == 100 && !memcmp(r.body, big + 1000000, 100));
    resp_free(&r);
}

/* Opens a connection with a fixed receive buffer of rcvbuf bytes (no autotuning, so the
 * kernel holds little ahead of the reader) and asks for big_url. */
static int big_get(wsraw *c, int rcvbuf)
{
    memset(c, 0, sizeof *c);
    c->fd = wsraw_tcp(net_port(N), rcvbuf);
    char req[512];
    snprintf(req, sizeof req, "GET %s HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n",
             big_url);
    return c->fd < 0 || send_req(c, req) ? -1 : 0;
}

static void test_slow_reader(void)
{
    /* About 16 KiB every 40 ms (~400 kB/s): the download lasts several idle timeouts,
     * with progress in every one of them. */
    wsraw c;
    uint64_t t0 = mono_ns();
    CHECK(!big_get(&c, 65536));
    resp r;
    memset(&r, 0, sizeof r);
    size_t got = 0;
    int status = 0;
    uint8_t *body = malloc(BIG_LEN);
    CHECK(body != NULL);
    for (;;) {
        struct pollfd p = { .fd = c.fd, .events = POLLIN };
        if (poll(&p, 1, 3000) <= 0) {
            break;
        }
        uint8_t chunk[16384];
        ssize_t n = recv(c.fd, chunk, sizeof chunk, 0);
        if (n <= 0) {
            break;
        }
        size_t off = 0;
        if (!status) {
            /* the headers arrive in the first segment */
            char *e = memmem(chunk, (size_t)n, "\r\n\r\n", 4);
            CHECK(e != NULL);
            if (!e) {
                break;
            }
            snprintf(r.head, sizeof r.head, "%.*s", (int)(e + 4 - (char *)chunk), chunk);
            sscanf(r.head, "HTTP/1.1 %d", &status);
            off = (size_t)(e + 4 - (char *)chunk);
        }
        if (got + (size_t)n - off > BIG_LEN) {
            break;
        }
        memcpy(body + got, chunk + off, (size_t)n - off);
        got += (size_t)n - off;
        struct timespec ts = { 0, 40 * 1000000L };
        nanosleep(&ts, NULL);
    }
    double secs = (double)(mono_ns() - t0) * 1e-9;
    fprintf(stderr, "  slow reader: %zu of %u bytes in %.1f s (idle timeout %d s)\n", got,
            BIG_LEN, secs, IDLE_S);
    CHECK(status == 200);
    CHECK(!strcmp(hdr(&r, "content-length"), "1572864"));
    CHECK(got == BIG_LEN && !memcmp(body, big, BIG_LEN));
    CHECK(secs > 2.5 * IDLE_S); /* it did outlast the timeout */
    free(body);
    wsraw_close(&c);
}

static void test_stalled_reader(void)
{
    /* A reader that stops is closed after the idle timeout, having what the kernel
     * buffers held; a Range request for the rest completes the asset. */
    wsraw c;
    CHECK(!big_get(&c, 8192));
    resp r;
    struct timespec ts = { 2 * IDLE_S + 1, 0 };
    nanosleep(&ts, NULL);
    uint64_t t0 = mono_ns();
    CHECK(read_resp(&c, &r, false, 3000) == -1); /* cut short */
    double drain = (double)(mono_ns() - t0) * 1e-9;
    fprintf(stderr, "  stalled reader: %zu of %u bytes, closed %.2f s after it read again\n",
            r.body_len, BIG_LEN, drain);
    CHECK(r.status == 200 && r.clen == (long)BIG_LEN);
    CHECK(r.body_len > 0 && r.body_len < BIG_LEN / 2);
    CHECK(drain < 2.0); /* the end came with the buffered bytes, not after a wait */
    CHECK(!memcmp(r.body, big, r.body_len));
    wsraw_close(&c);

    char extra[64];
    snprintf(extra, sizeof extra, "Range: bytes=%zu-\r\n", r.body_len);
    resp rest;
    CHECK(one("GET", big_url, extra, false, &rest));
    char want[64];
    snprintf(want, sizeof want, "bytes %zu-%u/%u", r.body_len, BIG_LEN - 1, BIG_LEN);
    CHECK(rest.status == 206 && !strcmp(hdr(&rest, "content-range"), want));
    CHECK(r.body_len + rest.body_len == BIG_LEN);
    CHECK(rest.body_len == BIG_LEN - r.body_len &&
          !memcmp(rest.body, big + r.body_len, rest.body_len));
    resp_free(&rest);
    resp_free(&r);
}

int main(void)
{
    if (start()) {
        return 1;
    }
    RUN(test_head);
    RUN(test_methods);
    RUN(test_lengths);
    RUN(test_etag);
    RUN(test_range);
    RUN(test_slow_reader);
    RUN(test_stalled_reader);
    net_stop(N);
    pthread_join(N_thread, NULL);
    net_destroy(N);
    free(big);
    return check_report();
}
