/* HTTP on the WebSocket port (server/SERVER.md "HTTP"): baked assets by content hash
 * (ETag, If-None-Match, one Range), /healthz, /status (net_desc.status), and /metrics (the registry of
 * net_desc.metrics rendered as Prometheus text), the browser client (net_web.c); GET and HEAD, 405 otherwise. Headers
 * at the request, the body in HTTP_WRITEABLE, as lws minimal-http-server-dynamic does;
 * an idle timeout re-armed on every chunk written. lws service thread. */
#include "net_int.h"

#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>

#include "http_hdr.h"
#include "metric.h"
#include "net_web.h"

#define NET_HTTP_IDLE_S 10     /* net_desc.http_idle_s default */
#define NET_HTTP_HDR_MAX 256   /* longest Range / If-None-Match / If-Range value read */

/* The headers of one response. */
typedef struct http_head {
    unsigned code;
    const char *type;      /* Content-Type */
    uint64_t length;       /* Content-Length: the body a GET gets (HEAD and 304 send none) */
    const char *etag;      /* opaque entity tag, sent quoted; NULL: no ETag (nor caching) */
    const char *range;     /* Content-Range value; NULL: none */
    bool allow;            /* Allow: GET, HEAD */
} http_head;

static void http_arm_idle(const net_server *s, net_conn *c)
{
    lws_set_timeout(c->wsi, PENDING_TIMEOUT_HTTP_CONTENT,
                    s->d.http_idle_s > 0 ? s->d.http_idle_s : NET_HTTP_IDLE_S);
}

static int http_add(net_conn *c, const char *name, const char *value, uint8_t **p, uint8_t *end)
{
    return lws_add_http_header_by_name(c->wsi, (const unsigned char *)name,
                                       (const unsigned char *)value, (int)strlen(value), p, end);
}

/* Writes h and schedules body[len] (borrowed until the transaction completes; not sent
 * when send_body is false). Nonzero closes the transaction. */
static int http_respond(net_server *s, net_conn *c, const http_head *h, const uint8_t *body,
                        size_t len, bool send_body)
{
    uint8_t hdr[LWS_PRE + 768], *start = hdr + LWS_PRE, *p = start, *end = hdr + sizeof hdr;
    char v[96];
    c->http_body = body;
    c->http_len = send_body ? len : 0;
    c->http_off = 0;
    c->http_active = true;
    if (lws_add_http_header_status(c->wsi, h->code, &p, end) ||
        lws_add_http_header_by_token(c->wsi, WSI_TOKEN_HTTP_CONTENT_TYPE,
                                     (const unsigned char *)h->type, (int)strlen(h->type), &p,
                                     end) ||
        lws_add_http_header_content_length(c->wsi, (lws_filepos_t)h->length, &p, end)) {
        return 1;
    }
    if (h->etag) {
        snprintf(v, sizeof v, "\"%s\"", h->etag);
        /* The URL names the content: it never changes, so caches may keep it. */
        if (http_add(c, "etag:", v, &p, end) || http_add(c, "accept-ranges:", "bytes", &p, end) ||
            http_add(c, "cache-control:", "public, max-age=31536000, immutable", &p, end)) {
            return 1;
        }
    } else if (http_add(c, "cache-control:", "no-store", &p, end)) {
        return 1;
    }
    if ((h->range && http_add(c, "content-range:", h->range, &p, end)) ||
        (h->allow && http_add(c, "allow:", "GET, HEAD", &p, end)) ||
        lws_finalize_write_http_header(c->wsi, start, &p, end)) {
        return 1;
    }
    int fd = lws_get_socket_fd(c->wsi);
    if (s->d.http_sndbuf > 0 && fd >= 0) {
        setsockopt(fd, SOL_SOCKET, SO_SNDBUF, &s->d.http_sndbuf, sizeof s->d.http_sndbuf);
    }
    http_arm_idle(s, c);
    lws_callback_on_writable(c->wsi);
    return 0;
}

/* A text body (static) with the given status. */
static int http_text(net_server *s, net_conn *c, unsigned code, const char *text, bool head,
                     bool allow)
{
    size_t n = strlen(text);
    http_head h = { .code = code, .type = "text/plain", .length = n, .allow = allow };
    return http_respond(s, c, &h, (const uint8_t *)text, n, !head);
}

/* Header t of the request into buf[NET_HTTP_HDR_MAX]: its length, 0 when absent, -1 when
 * longer than the buffer (acted on as if absent). */
static int http_hdr_get(net_conn *c, enum lws_token_indexes t, char *buf)
{
    if (lws_hdr_total_length(c->wsi, t) <= 0) {
        return 0;
    }
    return lws_hdr_copy(c->wsi, buf, NET_HTTP_HDR_MAX, t);
}

/* An asset a: 304 when If-None-Match names its hash, 206 / 416 for one Range (GET only,
 * and only when an If-Range names the same hash), else 200 with the whole. */
static int http_asset(net_server *s, net_conn *c, const net_asset *a, bool head)
{
    char v[NET_HTTP_HDR_MAX], cr[80];
    http_head h = { .code = HTTP_STATUS_OK, .type = "application/octet-stream",
                    .length = a->len, .etag = a->hash };
    int n = http_hdr_get(c, WSI_TOKEN_HTTP_IF_NONE_MATCH, v);
    if (n > 0 && http_hdr_etag_match(v, (size_t)n, a->hash, true)) {
        h.code = HTTP_STATUS_NOT_MODIFIED;
        return http_respond(s, c, &h, NULL, 0, false);
    }
    n = head ? 0 : http_hdr_get(c, WSI_TOKEN_HTTP_RANGE, v);
    if (n <= 0) {
        return http_respond(s, c, &h, a->bytes, a->len, !head);
    }
    uint64_t first, last;
    http_hdr_range_kind k = http_hdr_range(v, (size_t)n, a->len, &first, &last);
    int m = http_hdr_get(c, WSI_TOKEN_HTTP_IF_RANGE, v);
    if (m != 0 && !(m > 0 && http_hdr_etag_match(v, (size_t)m, a->hash, false))) {
        k = HTTP_HDR_RANGE_NONE; /* the client holds other bytes: it gets the whole */
    }
    if (k == HTTP_HDR_RANGE_ONE) {
        snprintf(cr, sizeof cr, "bytes %" PRIu64 "-%" PRIu64 "/%zu", first, last, a->len);
        h.code = HTTP_STATUS_PARTIAL_CONTENT;
        h.length = last - first + 1;
        h.range = cr;
        return http_respond(s, c, &h, a->bytes + first, (size_t)h.length, true);
    }
    if (k == HTTP_HDR_RANGE_UNSATISFIABLE) {
        static const char text[] = "range not satisfiable\n";
        snprintf(cr, sizeof cr, "bytes */%zu", a->len);
        h.code = HTTP_STATUS_REQ_RANGE_NOT_SATISFIABLE;
        h.type = "text/plain";
        h.etag = NULL; /* an error about this request, not the asset: not cached */
        h.length = sizeof text - 1;
        h.range = cr;
        return http_respond(s, c, &h, (const uint8_t *)text, sizeof text - 1, true);
    }
    return http_respond(s, c, &h, a->bytes, a->len, true); /* none, or several ranges */
}

int net_http_request(net_server *s, net_conn *c, const char *uri)
{
    free(c->http_owned);
    c->http_owned = NULL;
    const bool head = lws_hdr_total_length(c->wsi, WSI_TOKEN_HEAD_URI) > 0;
    if (!head && lws_hdr_total_length(c->wsi, WSI_TOKEN_GET_URI) <= 0) {
        return http_text(s, c, HTTP_STATUS_METHOD_NOT_ALLOWED,
                         "method not allowed: GET and HEAD are served\n", false, true);
    }
    if (!strcmp(uri, "/healthz") || !strcmp(uri, "/metrics")) {
        http_head h = { .code = HTTP_STATUS_OK, .type = "text/plain" };
        size_t len = 0;
        char *t;
        if (uri[1] == 'h') {
            char line[128];
            int n = snprintf(line, sizeof line, "ok tick %u clients %d\n", net_tick(s),
                             s->n_conns);
            t = malloc((size_t)n + 1);
            if (t) {
                memcpy(t, line, (size_t)n + 1);
                len = (size_t)n;
            }
        } else {
            t = s->d.metrics ? metric_reg_render(s->d.metrics, &len) : calloc(1, 1);
            h.type = "text/plain; version=0.0.4";
            size_t more_len = 0;
            char *more = t && s->d.metrics_more ? s->d.metrics_more(s->d.metrics_user, &more_len)
                                                : NULL;
            char *all = more ? realloc(t, len + more_len + 1) : NULL;
            if (all) {
                memcpy(all + len, more, more_len + 1);
                t = all;
                len += more_len;
            }
            free(more);
        }
        if (!t) {
            return 1;
        }
        c->http_owned = (uint8_t *)t;
        h.length = len;
        return http_respond(s, c, &h, c->http_owned, len, !head);
    }
    if (!strcmp(uri, "/status") && s->d.status) {
        size_t len = 0;
        char *t = s->d.status(s->d.status_user, &len);
        if (!t) {
            return 1;
        }
        c->http_owned = (uint8_t *)t;
        http_head h = { .code = HTTP_STATUS_OK, .type = "application/json", .length = len };
        return http_respond(s, c, &h, c->http_owned, len, !head);
    }
    if (!strncmp(uri, "/assets/", 8)) {
        const char *h = uri + 8;
        for (int i = 0; i < s->d.n_assets; i++) {
            const net_asset *a = &s->d.assets[i];
            size_t hl = strlen(a->hash);
            if (a->bytes && hl && !strncmp(h, a->hash, hl) &&
                (!strcmp(h + hl, ".gasset") || !h[hl])) {
                return http_asset(s, c, a, head);
            }
        }
    }
    const char *type;
    const net_web_file *w = net_web_find(uri, &type);
    if (w) { /* the browser client (net_web.c) */
        http_head h = { .code = HTTP_STATUS_OK, .type = type, .length = w->len };
        return http_respond(s, c, &h, w->bytes, w->len, !head);
    }
    return http_text(s, c, HTTP_STATUS_NOT_FOUND, "not found\n", head, false);
}

int net_http_writeable(net_server *s, net_conn *c)
{
    if (!c->http_active) {
        return 0; /* a late writeable after the transaction completed */
    }
    size_t left = c->http_len - c->http_off;
    if (left) {
        size_t n = left < NET_HTTP_CHUNK ? left : NET_HTTP_CHUNK;
        bool last = n == left;
        memcpy(s->http_buf + LWS_PRE, c->http_body + c->http_off, n);
        if (lws_write(c->wsi, s->http_buf + LWS_PRE, n,
                      last ? LWS_WRITE_HTTP_FINAL : LWS_WRITE_HTTP) != (int)n) {
            return 1;
        }
        c->http_off += n;
        if (!last) {
            http_arm_idle(s, c); /* the reader made room for a chunk: progress */
            lws_callback_on_writable(c->wsi);
            return 0;
        }
    }
    free(c->http_owned);
    c->http_owned = NULL;
    c->http_active = false;
    return lws_http_transaction_completed(c->wsi) ? -1 : 0;
}
