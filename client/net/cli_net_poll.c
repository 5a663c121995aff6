/* The caller's side of the client's connection (cli_net.h): the inbox handed to the
 * handlers in arrival order (cli_net_poll: the decoder and the clock live on this
 * thread), control messages queued for the network thread to write, HTTP fetches waited
 * on, and the stats read under the lock. */
#include "cli_net_int.h"
#include "asset_cache.h"
#include "mono.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static void handle_text(cli_net *n, const char *text, size_t len)
{
    ctl_msg m;
    int close_code = 0;
    if (ctl_decode(text, len, CTL_MAX_SERVER_BYTES, &m, &close_code, NULL) != 0) {
        return; /* the network thread decoded it already: not reached */
    }
    if (m.type == CTL_WELCOME && n->h.on_welcome) {
        n->h.on_welcome(n->h.user, &m.u.welcome);
    } else if (m.type != CTL_WELCOME && n->h.on_wall) {
        n->h.on_wall(n->h.user, &m);
    }
    ctl_msg_fini(&m);
}

static void handle_binary(cli_net *n, const uint8_t *buf, size_t len, double recv_s)
{
    wire_frame f;
    gale_err err = { 0 };
    int rc = wire_decode(n->dec, buf, len, &f, &err);
    if (rc == GALE_E_STATE) {
        /* a delta whose base we lack: ask for a keyframe (once per gap) */
        ctl_msg m = { .type = CTL_RESYNC };
        m.u.resync_seq = wire_decoder_seq(n->dec);
        pthread_mutex_lock(&n->lock);
        n->st.frames_gap++;
        cli_net_queue_ctl(n, &m, false, NULL);
        pthread_mutex_unlock(&n->lock);
        cli_net_log(n, "%s: %s; keyframe requested", n->server_name, err.msg);
        return;
    }
    pthread_mutex_lock(&n->lock);
    if (rc != 0) {
        n->st.frames_bad++;
    } else {
        n->st.frames_ok++;
    }
    pthread_mutex_unlock(&n->lock);
    if (rc != 0) {
        cli_net_log(n, "%s: frame of %zu bytes dropped: %s", n->server_name, len, err.msg);
        return;
    }
    if (f.hdr.type == WIRE_MSG_KEYFRAME || f.hdr.type == WIRE_MSG_DELTA) {
        jitter_clock_arrival(&n->clock, (double)f.hdr.server_time_us * 1e-6, recv_s);
    }
    if (n->h.on_frame) {
        n->h.on_frame(n->h.user, &f, n->dec, recv_s);
    }
}

void cli_net_poll(cli_net *n)
{
    pthread_mutex_lock(&n->lock);
    cli_net_msg *m = n->in_head;
    n->in_head = n->in_tail = NULL;
    n->in_bytes = 0;
    pthread_mutex_unlock(&n->lock);
    while (m) {
        cli_net_msg *next = m->next;
        switch (m->kind) {
        case MSG_CONNECT: {
            /* a fresh decoder: the next keyframe starts the new stream */
            gale_err err = { 0 };
            wire_decoder *dec = wire_decoder_create(
                &(wire_decoder_desc){ .max_trees = n->d.max_trees, .max_modes = n->d.max_modes },
                &err);
            if (dec) {
                wire_decoder_destroy(n->dec);
                n->dec = dec;
            }
            jitter_clock_init(&n->clock);
            break;
        }
        case MSG_TEXT:
            handle_text(n, (const char *)m->data, m->len);
            break;
        case MSG_BINARY:
            handle_binary(n, m->data, m->len, m->recv_s);
            break;
        case MSG_PONG:
            jitter_clock_pong(&n->clock, m->pong[0], m->pong[1], m->recv_s);
            break;
        case MSG_LOST:
            if (n->h.on_lost) {
                n->h.on_lost(n->h.user, m->code, (const char *)m->data);
            }
            break;
        default:
            break;
        }
        free(m);
        m = next;
    }
}

/* Queues m from the poller's thread once live. */
static int send_live(cli_net *n, const ctl_msg *m, const char *what, char *text, size_t cap,
                     gale_err *err)
{
    pthread_mutex_lock(&n->lock);
    int rc;
    if (n->st.state != CLI_NET_LIVE) {
        rc = gale_errf(err, GALE_E_STATE, "%s: %s: not connected", n->server_name, what);
    } else {
        rc = cli_net_queue_ctl(n, m, false, err);
    }
    if (rc == 0 && text && cap > 0) {
        const cli_net_tx *t = &n->tx[(n->tx_head + n->tx_count - 1) % CLI_NET_TX_SLOTS];
        size_t k = t->len < cap - 1 ? t->len : cap - 1;
        memcpy(text, t->buf + LWS_PRE, k);
        text[k] = '\0';
    }
    pthread_mutex_unlock(&n->lock);
    return rc;
}

int cli_net_send_wall(cli_net *n, const ctl_msg *m, gale_err *err)
{
    return send_live(n, m, ctl_type_name(m->type) ? ctl_type_name(m->type) : "wall message",
                     NULL, 0, err);
}

int cli_net_send_wind(cli_net *n, const ctl_wind *w, gale_err *err)
{
    ctl_msg m = { .type = CTL_WIND };
    m.u.wind = *w;
    return send_live(n, &m, "wind command", NULL, 0, err);
}

int cli_net_send_ctl(cli_net *n, const ctl_msg *m, char *text, size_t cap, gale_err *err)
{
    return send_live(n, m, ctl_type_name(m->type) ? ctl_type_name(m->type) : "control message",
                     text, cap, err);
}

/* Waits on the fetch (lock held) until it ended and its socket is gone, or until_s. */
static void fetch_wait(cli_net *n, double until_s)
{
    while (!(n->fetch_done && !n->http_open && !n->want_fetch) && mono_s() < until_s) {
        struct timespec ts;
        clock_gettime(CLOCK_MONOTONIC, &ts);
        double t = (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9 + fmin(until_s - mono_s(), 0.05);
        ts.tv_sec = (time_t)t;
        ts.tv_nsec = (long)((t - (double)ts.tv_sec) * 1e9);
        pthread_cond_timedwait(&n->cond, &n->lock, &ts);
    }
}

int cli_net_fetch(cli_net *n, const char *path, size_t max_len, double timeout_s, uint8_t **out,
              size_t *len, gale_err *err)
{
    *out = NULL;
    *len = 0;
    pthread_mutex_lock(&n->lock);
    if (n->want_fetch || n->http_open) {
        pthread_mutex_unlock(&n->lock);
        return gale_errf(err, GALE_E_STATE, "%s%s: a fetch is already under way", n->server_name,
                         path);
    }
    if (strlen(path) >= sizeof n->fetch_path) {
        pthread_mutex_unlock(&n->lock);
        return gale_errf(err, GALE_E_ARG, "%s%s: path longer than %zu bytes", n->server_name,
                         path, sizeof n->fetch_path - 1);
    }
    snprintf(n->fetch_path, sizeof n->fetch_path, "%s", path);
    n->fetch_len = 0;
    n->fetch_max = max_len;
    n->fetch_status = 0;
    n->fetch_done = false;
    n->fetch_complete = false;
    n->fetch_err[0] = '\0';
    n->want_fetch = true;
    lws_cancel_service(n->ctx);
    fetch_wait(n, mono_s() + timeout_s);
    if (!n->fetch_done || n->want_fetch || n->http_open) {
        /* past the time: the network thread drops the socket; wait for it to go */
        const bool started = !n->want_fetch;
        n->want_fetch = false;
        n->fetch_abort = true;
        lws_cancel_service(n->ctx);
        if (!n->fetch_done) {
            n->fetch_done = true;
        }
        fetch_wait(n, mono_s() + 2.0);
        size_t got = n->fetch_len;
        pthread_mutex_unlock(&n->lock);
        return gale_errf(err, GALE_E_IO, "http://%s%s: timed out after %.1f s (%zu bytes%s)",
                         n->server_name, path, timeout_s, got, started ? "" : ", not started");
    }
    int rc = 0;
    if (!n->fetch_complete || n->fetch_err[0]) {
        int code = strstr(n->fetch_err, "body over") ? GALE_E_RANGE : GALE_E_IO;
        rc = gale_errf(err, code, "http://%s%s: %s", n->server_name, path,
                       n->fetch_err[0] ? n->fetch_err : "incomplete");
    } else {
        *out = n->fetch_buf ? n->fetch_buf : malloc(1);
        *len = n->fetch_len;
        n->fetch_buf = NULL;
        n->fetch_cap = 0;
        n->fetch_len = 0;
        rc = *out ? 0 : gale_errf(err, GALE_E_NOMEM, "cli_net_fetch: no memory");
    }
    pthread_mutex_unlock(&n->lock);
    return rc;
}

int cli_net_fetch_asset(cli_net *n, const char *path, const char *hash_hex, size_t max_len,
                        double timeout_s, uint8_t **out, size_t *len, gale_err *err)
{
    int rc = cli_net_fetch(n, path, max_len, timeout_s, out, len, err);
    if (rc) {
        return rc;
    }
    char what[400];
    snprintf(what, sizeof what, "http://%s%s", n->server_name, path);
    rc = asset_cache_verify(hash_hex, *out, *len, what, err);
    if (rc) {
        free(*out);
        *out = NULL;
        *len = 0;
    }
    return rc;
}

cli_net_stats cli_net_get_stats(const cli_net *n)
{
    cli_net *m = (cli_net *)n; /* the lock, not the state, changes */
    pthread_mutex_lock(&m->lock);
    cli_net_stats st = n->st;
    pthread_mutex_unlock(&m->lock);
    return st;
}

const jitter_clock *cli_net_clock(const cli_net *n)
{
    return &n->clock;
}

void cli_net_drop(cli_net *n)
{
    pthread_mutex_lock(&n->lock);
    if (n->ws) {
        n->kill = true;
        lws_cancel_service(n->ctx);
    }
    pthread_mutex_unlock(&n->lock);
}
