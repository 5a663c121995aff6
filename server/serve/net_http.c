/* HTTP on the WebSocket port: baked assets by content hash, /healthz, and /metrics (the
 * registry of net_desc.metrics rendered as Prometheus text). Headers then body in
 * HTTP_WRITEABLE, as lws minimal-http-server-dynamic does; lws service thread. */
#include "net_int.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "metric.h"

static int http_respond(net_server *s, net_conn *c, unsigned code, const char *type,
                        const uint8_t *body, size_t len)
{
    uint8_t hdr[LWS_PRE + 512], *start = hdr + LWS_PRE, *p = start, *end = hdr + sizeof hdr;
    c->http_body = body;
    c->http_len = len;
    c->http_off = 0;
    (void)s;
    if (lws_add_http_common_headers(c->wsi, code, type, (lws_filepos_t)len, &p, end) ||
        lws_finalize_write_http_header(c->wsi, start, &p, end)) {
        return 1;
    }
    lws_callback_on_writable(c->wsi);
    return 0;
}

int net_http_request(net_server *s, net_conn *c, const char *uri)
{
    static const char not_found[] = "not found\n";
    static const char bad_method[] = "only GET is served\n";
    if (lws_hdr_total_length(c->wsi, WSI_TOKEN_GET_URI) <= 0) {
        return http_respond(s, c, HTTP_STATUS_METHOD_NOT_ALLOWED, "text/plain",
                            (const uint8_t *)bad_method, sizeof bad_method - 1);
    }
    if (!strcmp(uri, "/healthz")) {
        char t[128];
        int n = snprintf(t, sizeof t, "ok tick %u clients %d\n",
                         net_tick(s), s->n_conns);
        c->http_owned = malloc((size_t)n + 1);
        if (!c->http_owned) {
            return 1;
        }
        memcpy(c->http_owned, t, (size_t)n + 1);
        return http_respond(s, c, HTTP_STATUS_OK, "text/plain", c->http_owned, (size_t)n);
    }
    if (!strcmp(uri, "/metrics")) {
        size_t len = 0;
        char *t = s->d.metrics ? metric_reg_render(s->d.metrics, &len) : calloc(1, 1);
        if (!t) {
            return 1;
        }
        c->http_owned = (uint8_t *)t;
        return http_respond(s, c, HTTP_STATUS_OK, "text/plain; version=0.0.4", c->http_owned,
                            len);
    }
    if (!strncmp(uri, "/assets/", 8)) {
        const char *h = uri + 8;
        for (int i = 0; i < s->d.n_assets; i++) {
            const net_asset *a = &s->d.assets[i];
            size_t hl = strlen(a->hash);
            if (a->bytes && hl && !strncmp(h, a->hash, hl) &&
                (!strcmp(h + hl, ".gasset") || !h[hl])) {
                return http_respond(s, c, HTTP_STATUS_OK, "application/octet-stream", a->bytes,
                                    a->len);
            }
        }
    }
    return http_respond(s, c, HTTP_STATUS_NOT_FOUND, "text/plain", (const uint8_t *)not_found,
                        sizeof not_found - 1);
}

int net_http_writeable(net_server *s, net_conn *c)
{
    size_t left = c->http_len - c->http_off;
    size_t n = left < NET_HTTP_CHUNK ? left : NET_HTTP_CHUNK;
    bool last = n == left;
    if (n) {
        memcpy(s->http_buf + LWS_PRE, c->http_body + c->http_off, n);
    }
    if (lws_write(c->wsi, s->http_buf + LWS_PRE, n,
                  last ? LWS_WRITE_HTTP_FINAL : LWS_WRITE_HTTP) != (int)n) {
        return 1;
    }
    c->http_off += n;
    if (!last) {
        lws_callback_on_writable(c->wsi);
        return 0;
    }
    free(c->http_owned);
    c->http_owned = NULL;
    return lws_http_transaction_completed(c->wsi) ? -1 : 0;
}
