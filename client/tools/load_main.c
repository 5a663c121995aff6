/* gale-load: a headless load client (protocol/PROTOCOL.md, by the hundreds). N WebSocket
 * connections on one lws service thread (after the v4.1.6 minimal-ws-client example);
 * each says hello, reads the welcome, then decodes every binary frame with the protocol
 * library, checking sequence and integrity. Reports connected, frames, bytes, decode
 * errors, disconnects and end-to-end latency (server timestamp to decode, both on this
 * host's CLOCK_MONOTONIC) percentiles. With --views each client asks in its hello for a
 * view of its own (view_kinds.h: street, roof and aerial in turn, at seeded places) and
 * the bytes each kind receives are reported; with --per-client each client's own figures
 * (its welcome's first byte and end after the hello, the bytes a second it received after
 * the welcome, its latency p50/p99, its close code). A welcome whose scene part another
 * client of this process decoded is compared, not decoded again. Loopback only; bounded in
 * count and time. */
#include <ctype.h>
#include <inttypes.h>
#include <math.h>
#include <pthread.h>
#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sys/socket.h>

#include <libwebsockets.h>

#include "mono.h"
#include "ctl.h"
#include "view_kinds.h"
#include "wire.h"

#define LOAD_MAX_CLIENTS 5000
#define LOAD_MAX_SECONDS 3600
#define LOAD_MAX_THREADS 16
#define LAT_BUCKET_US 10          /* latency histogram resolution */
#define LAT_BUCKETS 3000000       /* 10 µs x 3 000 000 = 30 s; slower goes to the last bucket */
#define LOAD_VIEW_LOD_M 120.0f    /* --views: the views' lod_m, as a client's camera sends it */
/* --per-client latency: a histogram per client whose buckets grow by 2 % from 10 µs to
 * past 30 s, so 20 clients or 5000 cost kilobytes each, not a fine histogram each */
#define CLIENT_LAT_GROWTH 1.02
#define CLIENT_LAT_BUCKETS 760

typedef struct load_conn {
    struct lws *wsi;
    int index;
    bool established, hello_sent, welcomed, closed, closing;
    uint8_t *rx;          /* owned: message reassembly */
    size_t rx_len, rx_cap;
    wire_decoder *dec;    /* owned, sized from the welcome */
    uint32_t last_seq;
    int close_code;
    uint64_t bytes;       /* received */
    /* --per-client */
    uint64_t hello_us;    /* mono_us when the hello went out */
    uint64_t welcome_first_us; /* when the welcome's first bytes came (0: not yet) */
    uint64_t welcome_us;  /* when the whole welcome was decoded (0: not yet) */
    uint64_t stream_bytes; /* binary bytes received after the welcome */
    uint32_t *lat;        /* owned [CLIENT_LAT_BUCKETS] with --per-client, else NULL */
} load_conn;

typedef struct load_run {
    struct lws_context *ctx;
    char host[128], path[128];
    int port, n, role;
    char token[CTL_MAX_TOKEN];
    double seconds;
    double views_half_m;  /* --views: eyes within this of the origin; 0: no views */
    bool per_client;      /* --per-client */
    uint64_t end_us;      /* mono_us when the run's clients were told to end */
    bool ending;
    load_conn *conns;     /* owned [n] */
    int connected, welcomed, open_now;
    uint64_t frames, state_frames, keyframes, leaf_frames, wind_frames, bytes, decode_errors, seq_gaps,
        skipped_seqs, disconnects, connect_errors, text_msgs;
    int close_codes[8];   /* first few unexpected close codes, for the report */
    int n_close_codes;
    uint32_t *lat;        /* owned [LAT_BUCKETS] histogram */
    uint64_t lat_n, lat_max_us;
    char first_error[256];
    int first;            /* index of this thread's first client */
    bool failed;          /* lws_create_context failed */
    double elapsed;       /* [s] */
} load_run;

static volatile sig_atomic_t interrupted; /* read by every service thread */

static void on_signal(int sig)
{
    (void)sig;
    interrupted = 1;
}

/* Keeps the first error of the run for the report: "what: message". */
static void note_error(load_run *r, const char *what, const char *msg)
{
    if (!r->first_error[0]) {
        int n = snprintf(r->first_error, sizeof r->first_error, "%s: %.200s", what, msg);
        (void)n;
    }
}

static void on_binary(load_run *r, load_conn *c, const uint8_t *b, size_t len)
{
    r->frames++;
    if (!c->dec) {
        r->decode_errors++;
        note_error(r, "frame", "binary frame before the welcome");
        return;
    }
    wire_frame f;
    gale_err e;
    int rc = wire_decode(c->dec, b, len, &f, &e);
    uint64_t now = mono_us();
    if (rc) {
        if (rc == GALE_E_STATE) {
            r->seq_gaps++;
        }
        r->decode_errors++;
        note_error(r, "decode", e.msg);
        return;
    }
    /* f.types: one frame, or every frame of a BUNDLE (PROTOCOL.md "BUNDLE") */
    r->leaf_frames += (f.types >> WIRE_MSG_LEAVES) & 1u;
    r->wind_frames += (f.types >> WIRE_MSG_WIND) & 1u;
    if (f.hdr.type == WIRE_MSG_KEYFRAME || f.hdr.type == WIRE_MSG_DELTA) {
        r->state_frames++;
        if (f.hdr.type == WIRE_MSG_KEYFRAME) {
            r->keyframes++;
            if (c->last_seq && f.seq > c->last_seq + 1u) {
                r->skipped_seqs += f.seq - c->last_seq - 1u; /* the server dropped them for us */
            }
        }
        if (c->last_seq && f.seq <= c->last_seq) {
            r->decode_errors++;
            note_error(r, "sequence", "went backwards");
        }
        c->last_seq = f.seq;
        uint64_t lat = now > f.hdr.server_time_us ? now - f.hdr.server_time_us : 0;
        if (c->lat) {
            double kb = lat > 10 ? log((double)lat / 10.0) / log(CLIENT_LAT_GROWTH) : 0.0;
            c->lat[kb < CLIENT_LAT_BUCKETS - 1 ? (int)kb : CLIENT_LAT_BUCKETS - 1]++;
        }
        uint64_t k = lat / LAT_BUCKET_US;
        r->lat[k < LAT_BUCKETS ? k : LAT_BUCKETS - 1]++;
        r->lat_n++;
        if (lat > r->lat_max_us) {
            r->lat_max_us = lat;
        }
    }
}

/* The welcome's scene part (from its species on: the same bytes for every client of a
 * server, SERVER.md "The welcome") as the first client decoded it, and the sizes it gave:
 * a later client whose welcome ends in the same bytes compares them instead of decoding
 * them again. Twenty clients each parsing megabytes of JSON on the cores the server runs
 * on would measure this tool, where viewers each parse theirs on a machine of their own.
 * While one thread decodes a welcome the others wait for it rather than decode theirs
 * too (a thread waiting stalls only its own connections: --threads spreads them). */
static struct {
    pthread_mutex_t lock;
    pthread_cond_t done; /* a decode claimed by `decoding` ended */
    bool decoding;       /* a thread is decoding a welcome to keep here */
    char *text;          /* owned [len]: the scene part */
    size_t len;
    uint32_t max_trees, max_modes;
} known = { .lock = PTHREAD_MUTEX_INITIALIZER, .done = PTHREAD_COND_INITIALIZER };

/* Where a welcome's scene part starts in t[len] (its head is a few hundred bytes), or 0. */
static size_t scene_part_at(const char *t, size_t len)
{
    static const char key[] = ",\"species\":";
    const size_t k = sizeof key - 1;
    for (size_t i = 0; i + k <= len && i < 1024; i++) {
        if (!memcmp(t + i, key, k)) {
            return i;
        }
    }
    return 0;
}

/* A decoder sized for a welcome t[len] whose scene part this process already decoded,
 * else NULL: decode it, and when *claimed call known_done after (the other threads wait
 * for that decode). */
static wire_decoder *known_decoder(const char *t, size_t len, bool *claimed)
{
    *claimed = false;
    const size_t at = scene_part_at(t, len);
    if (!at || strncmp(t, "{\"type\":\"welcome\",", 19)) {
        return NULL;
    }
    wire_decoder *dec = NULL;
    pthread_mutex_lock(&known.lock);
    while (known.decoding) {
        pthread_cond_wait(&known.done, &known.lock);
    }
    if (known.text && known.len == len - at && !memcmp(known.text, t + at, known.len)) {
        dec = wire_decoder_create(
            &(wire_decoder_desc){ .max_trees = known.max_trees, .max_modes = known.max_modes },
            NULL);
    } else {
        known.decoding = true;
        *claimed = true;
    }
    pthread_mutex_unlock(&known.lock);
    return dec;
}

/* Ends a decode known_decoder claimed; keeps the scene part of welcome t[len] with the
 * sizes it gave when ok. */
static void known_done(bool ok, const char *t, size_t len, uint32_t max_trees,
                       uint32_t max_modes)
{
    const size_t at = scene_part_at(t, len);
    pthread_mutex_lock(&known.lock);
    known.decoding = false;
    pthread_cond_broadcast(&known.done);
    char *copy = ok && at ? malloc(len - at) : NULL;
    if (copy) {
        memcpy(copy, t + at, len - at);
        free(known.text);
        known.text = copy;
        known.len = len - at;
        known.max_trees = max_trees;
        known.max_modes = max_modes;
    }
    pthread_mutex_unlock(&known.lock);
}

static void on_text(load_run *r, load_conn *c, const char *t, size_t len)
{
    r->text_msgs++;
    bool claimed = false;
    if (!c->dec && (c->dec = known_decoder(t, len, &claimed))) {
        c->welcomed = true;
        c->welcome_us = mono_us();
        r->welcomed++;
        return;
    }
    ctl_msg m;
    gale_err e;
    if (ctl_decode(t, len, CTL_MAX_SERVER_BYTES, &m, NULL, &e)) {
        if (claimed) {
            known_done(false, t, len, 0, 0);
        }
        r->decode_errors++;
        note_error(r, "control", e.msg);
        return;
    }
    if (m.type == CTL_WELCOME && !c->dec) {
        uint32_t modes = 1;
        for (uint32_t i = 0; i < m.u.welcome.n_species; i++) {
            modes = m.u.welcome.species[i].n_modes > modes ? m.u.welcome.species[i].n_modes
                                                            : modes;
        }
        const uint32_t trees = m.u.welcome.n_instances ? m.u.welcome.n_instances : 1;
        c->dec = wire_decoder_create(
            &(wire_decoder_desc){ .max_trees = trees, .max_modes = modes }, &e);
        if (claimed) {
            known_done(c->dec != NULL, t, len, trees, modes);
            claimed = false;
        }
        if (!c->dec) {
            note_error(r, "decoder", e.msg);
        } else {
            c->welcomed = true;
            c->welcome_us = mono_us();
            r->welcomed++;
        }
    } else if (m.type == CTL_ERROR) {
        note_error(r, "server error", m.u.error.message);
    }
    if (claimed) {
        known_done(false, t, len, 0, 0);
    }
    ctl_msg_fini(&m);
}

static int callback(struct lws *wsi, enum lws_callback_reasons reason, void *user, void *in,
                    size_t len)
{
    load_run *r = lws_context_user(lws_get_context(wsi));
    load_conn *c = user;
    switch (reason) {
    case LWS_CALLBACK_CLIENT_CONNECTION_ERROR:
        if (c) {
            r->connect_errors++;
            c->closed = true;
            note_error(r, "connect", in ? (const char *)in : "failed");
        }
        break;
    case LWS_CALLBACK_CLIENT_ESTABLISHED: {
        /* A viewer-sized receive buffer: backlog stays in the server's bounded queue
         * (newest wins) instead of seconds of frames in this socket. Not smaller: set
         * after the connection is made, a buffer whose window is below one loopback
         * segment (32 KiB here) leaves the sender a segment per 200 ms persist timer,
         * some 200 kB/s whatever the server does (a 4 MB welcome then takes 20 s). */
        int fd = lws_get_socket_fd(wsi), rcv = 65536;
        setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &rcv, sizeof rcv);
        c->established = true;
        r->connected++;
        r->open_now++;
        lws_callback_on_writable(wsi);
        break;
    }
    case LWS_CALLBACK_CLIENT_WRITEABLE: {
        if (c->closing) {
            lws_close_reason(wsi, LWS_CLOSE_STATUS_NORMAL, (unsigned char *)"done", 4);
            return -1;
        }
        if (c->hello_sent) {
            break;
        }
        c->hello_sent = true;
        char buf[LWS_PRE + 768];
        ctl_msg m = { .type = CTL_HELLO };
        m.u.hello.protocol = WIRE_PROTOCOL_VERSION;
        m.u.hello.role = r->role;
        if (r->views_half_m > 0) {
            uint64_t rng = 0x9e3779b97f4a7c15ull * (uint64_t)(c->index + 1);
            m.u.hello.view = view_kind_make(c->index % VIEW_KINDS, &rng, r->views_half_m,
                                            LOAD_VIEW_LOD_M);
        }
        snprintf(m.u.hello.token, sizeof m.u.hello.token, "%s", r->token);
        size_t n = 0;
        gale_err e = { 0 };
        if (ctl_encode_into(&m, buf + LWS_PRE, sizeof buf - LWS_PRE, &n, &e)) {
            note_error(r, "hello", e.msg);
            return -1;
        }
        if (lws_write(wsi, (unsigned char *)buf + LWS_PRE, n, LWS_WRITE_TEXT) < (int)n) {
            return -1;
        }
        c->hello_us = mono_us();
        break;
    }
    case LWS_CALLBACK_CLIENT_RECEIVE: {
        size_t need = c->rx_len + len;
        if (need > WIRE_MAX_FRAME_BYTES) {
            r->decode_errors++;
            note_error(r, "receive", "message over WIRE_MAX_FRAME_BYTES");
            return -1;
        }
        if (need > c->rx_cap) {
            size_t cap = c->rx_cap ? c->rx_cap : 65536;
            while (cap < need) {
                cap *= 2;
            }
            uint8_t *nb = realloc(c->rx, cap);
            if (!nb) {
                return -1;
            }
            c->rx = nb;
            c->rx_cap = cap;
        }
        memcpy(c->rx + c->rx_len, in, len);
        c->rx_len += len;
        if (!c->welcome_first_us && !lws_frame_is_binary(wsi)) {
            c->welcome_first_us = mono_us(); /* the first text is the hello's answer */
        }
        if (!lws_is_final_fragment(wsi) || lws_remaining_packet_payload(wsi)) {
            break;
        }
        r->bytes += c->rx_len;
        c->bytes += c->rx_len;
        if (c->dec && lws_frame_is_binary(wsi)) {
            c->stream_bytes += c->rx_len;
        }
        if (lws_frame_is_binary(wsi)) {
            on_binary(r, c, c->rx, c->rx_len);
        } else {
            on_text(r, c, (const char *)c->rx, c->rx_len);
        }
        c->rx_len = 0;
        break;
    }
    case LWS_CALLBACK_WS_PEER_INITIATED_CLOSE:
        if (len >= 2) {
            const uint8_t *p = in;
            c->close_code = p[0] << 8 | p[1];
        }
        break;
    case LWS_CALLBACK_CLIENT_CLOSED:
        if (c && !c->closed) {
            c->closed = true;
            r->open_now--;
            if (!c->closing) {
                r->disconnects++;
                if (r->n_close_codes < 8) {
                    r->close_codes[r->n_close_codes++] = c->close_code;
                }
            }
        }
        break;
    default:
        break;
    }
    return 0;
}

static const struct lws_protocols protocols[] = {
    { "gale", callback, 0, 65536, 0, NULL, 0 },
    { NULL, NULL, 0, 0, 0, NULL, 0 },
};

/* One service thread: connects its share of the clients, services them for the run's
 * length, then closes them (1000) and waits up to 3 s for the closes. */
static void *run_part(void *arg)
{
    load_run *r = arg;
    struct lws_context_creation_info info;
    memset(&info, 0, sizeof info);
    info.port = CONTEXT_PORT_NO_LISTEN;
    info.protocols = protocols;
    info.user = r;
    info.fd_limit_per_thread = (unsigned int)(r->n + 16);
    info.timeout_secs = 10;
    r->ctx = lws_create_context(&info);
    if (!r->ctx) {
        r->failed = true;
        return NULL;
    }
    /* Connect in batches of 50 per service pass so the listen backlog is never flooded. */
    uint64_t t_start = mono_us(), t_end = 0;
    int next = 0;
    while (!interrupted) {
        for (int k = 0; k < 50 && next < r->n; k++, next++) {
            load_conn *c = &r->conns[next];
            c->index = r->first + next;
            struct lws_client_connect_info ci;
            memset(&ci, 0, sizeof ci);
            ci.context = r->ctx;
            ci.address = r->host;
            ci.port = r->port;
            ci.path = r->path;
            ci.host = r->host;
            ci.origin = r->host;
            ci.protocol = "gale";
            ci.pwsi = &c->wsi;
            ci.userdata = c;
            if (!lws_client_connect_via_info(&ci)) {
                r->connect_errors++;
                c->closed = true;
            }
        }
        lws_service(r->ctx, 0);
        uint64_t now = mono_us();
        if (!r->ending && (double)(now - t_start) * 1e-6 >= r->seconds) {
            r->ending = true;
            t_end = now;
            r->end_us = now;
            for (int i = 0; i < r->n; i++) {
                load_conn *c = &r->conns[i];
                if (c->wsi && c->established && !c->closed) {
                    c->closing = true;
                    lws_callback_on_writable(c->wsi);
                }
            }
        }
        if (r->ending && (r->open_now <= 0 || now - t_end > 3000000)) {
            break;
        }
    }
    r->elapsed = (double)((t_end ? t_end : mono_us()) - t_start) * 1e-6;
    lws_context_destroy(r->ctx);
    for (int i = 0; i < r->n; i++) {
        free(r->conns[i].rx);
        r->conns[i].rx = NULL;
        wire_decoder_destroy(r->conns[i].dec);
        r->conns[i].dec = NULL;
    }
    return NULL;
}

static double lat_pct(const load_run *r, double p)
{
    if (!r->lat_n) {
        return 0;
    }
    uint64_t want = (uint64_t)(p * (double)r->lat_n + 0.5), acc = 0;
    want = want < 1 ? 1 : want;
    for (int k = 0; k < LAT_BUCKETS; k++) {
        acc += r->lat[k];
        if (acc >= want) {
            return (double)(k + 1) * LAT_BUCKET_US * 1e-3; /* upper edge of the bucket [ms] */
        }
    }
    return (double)r->lat_max_us * 1e-3;
}

/* Quantile p of client c's latency [ms]: the upper edge of its bucket; 0 without samples. */
static double client_lat_pct(const load_conn *c, double p)
{
    uint64_t n = 0, acc = 0;
    for (int k = 0; k < CLIENT_LAT_BUCKETS; k++) {
        n += c->lat[k];
    }
    if (!n) {
        return 0;
    }
    uint64_t want = (uint64_t)(p * (double)n + 0.5);
    want = want < 1 ? 1 : want;
    for (int k = 0; k < CLIENT_LAT_BUCKETS; k++) {
        acc += c->lat[k];
        if (acc >= want) {
            return 10.0 * pow(CLIENT_LAT_GROWTH, k + 1) * 1e-3;
        }
    }
    return 0;
}

/* One client's figures as a JSON object (--per-client). */
static void client_json(const load_run *r, const load_conn *c)
{
    const double after_s = c->welcome_us && r->end_us > c->welcome_us
                               ? (double)(r->end_us - c->welcome_us) * 1e-6
                               : 0.0;
    printf("{\"client\": %d", c->index);
    if (r->views_half_m > 0) {
        printf(", \"view\": \"%s\"", view_kind_name(c->index % VIEW_KINDS));
    }
    printf(", \"welcome_first_ms\": %.1f, \"welcome_ms\": %.1f, \"bytes_per_s\": %.0f, "
           "\"latency_ms\": {\"p50\": %.2f, \"p99\": %.2f}, \"close_code\": %d}",
           c->hello_us && c->welcome_first_us ? (double)(c->welcome_first_us - c->hello_us) * 1e-3
                                              : -1.0,
           c->hello_us && c->welcome_us ? (double)(c->welcome_us - c->hello_us) * 1e-3 : -1.0,
           after_s > 0 ? (double)c->stream_bytes / after_s : 0.0, client_lat_pct(c, 0.50),
           client_lat_pct(c, 0.99), c->closed && !c->closing ? c->close_code : 0);
}

static int parse_url(load_run *r, const char *url)
{
    if (strncmp(url, "ws://", 5)) {
        fprintf(stderr, "gale-load: --url: expected ws://HOST:PORT[/path], got \"%s\"\n", url);
        return -1;
    }
    const char *h = url + 5, *colon = strchr(h, ':'), *slash = strchr(h, '/');
    if (!colon || (slash && slash < colon) || (size_t)(colon - h) >= sizeof r->host) {
        fprintf(stderr, "gale-load: --url: expected ws://HOST:PORT[/path], got \"%s\"\n", url);
        return -1;
    }
    memcpy(r->host, h, (size_t)(colon - h));
    r->host[colon - h] = 0;
    char *end;
    long port = strtol(colon + 1, &end, 10);
    if (port < 1 || port > 65535 || (*end && *end != '/')) {
        fprintf(stderr, "gale-load: --url: port: expected 1..65535, got \"%s\"\n", colon + 1);
        return -1;
    }
    r->port = (int)port;
    snprintf(r->path, sizeof r->path, "%s", *end ? end : "/");
    /* loopback only: this tool opens hundreds of connections on purpose */
    if (strcmp(r->host, "localhost") && strncmp(r->host, "127.", 4)) {
        fprintf(stderr, "gale-load: --url: host: expected loopback (127.x.x.x or localhost), "
                        "got \"%s\"\n",
                r->host);
        return -1;
    }
    if (!strcmp(r->host, "localhost")) {
        snprintf(r->host, sizeof r->host, "127.0.0.1");
    }
    return 0;
}

static void usage(FILE *f)
{
    fprintf(f, "usage: gale-load --url ws://HOST:PORT --clients N --seconds S "
               "[--role viewer|kiosk|wall-tile|load] [--token T] [--threads T] [--views HALF_M] "
               "[--per-client] [--json]\n"
               "  N in 1..%d, S in 1..%d; HOST must be loopback; -h, --help: this text\n"
               "  --views HALF_M: client i asks for a street, roof or aerial view (i mod 3) "
               "with its eye\n"
               "    at a seeded place within HALF_M of the origin, lod_m 120\n"
               "  --per-client: each client's welcome times, bytes a second after its welcome,\n"
               "    latency p50/p99 and close code besides the totals\n",
            LOAD_MAX_CLIENTS, LOAD_MAX_SECONDS);
}

int main(int argc, char **argv)
{
    load_run r;
    memset(&r, 0, sizeof r);
    r.role = CTL_ROLE_LOAD;
    bool json = false;
    int threads = 2;
    const char *url = NULL;
    long n = 0;
    double secs = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        char *end = NULL;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(a, "--json")) {
            json = true;
        } else if (!strcmp(a, "--per-client")) {
            r.per_client = true;
        } else if (!strcmp(a, "--url") && v) {
            url = v;
            i++;
        } else if (!strcmp(a, "--clients") && v) {
            n = strtol(v, &end, 10);
            if (*end || n < 1 || n > LOAD_MAX_CLIENTS) {
                fprintf(stderr, "gale-load: --clients: expected 1..%d, got \"%s\"\n",
                        LOAD_MAX_CLIENTS, v);
                return 2;
            }
            i++;
        } else if (!strcmp(a, "--seconds") && v) {
            secs = strtod(v, &end);
            if (*end || !(secs >= 1 && secs <= LOAD_MAX_SECONDS)) {
                fprintf(stderr, "gale-load: --seconds: expected 1..%d, got \"%s\"\n",
                        LOAD_MAX_SECONDS, v);
                return 2;
            }
            i++;
        } else if (!strcmp(a, "--role") && v) {
            int k = -1;
            for (int j = 0; j < 4; j++) {
                if (ctl_role_name(j) && !strcmp(ctl_role_name(j), v)) {
                    k = j;
                }
            }
            if (k < 0) {
                fprintf(stderr, "gale-load: --role: expected viewer|kiosk|wall-tile|load, got \"%s\"\n",
                        v);
                return 2;
            }
            r.role = k;
            i++;
        } else if (!strcmp(a, "--threads") && v) {
            long t = strtol(v, &end, 10);
            if (*end || t < 1 || t > LOAD_MAX_THREADS) {
                fprintf(stderr, "gale-load: --threads: expected 1..%d, got \"%s\"\n",
                        LOAD_MAX_THREADS, v);
                return 2;
            }
            threads = (int)t;
            i++;
        } else if (!strcmp(a, "--views") && v) {
            r.views_half_m = strtod(v, &end);
            if (*end || !(r.views_half_m > 0 && r.views_half_m <= 1e6)) {
                fprintf(stderr, "gale-load: --views: expected (0, 1e6] m, got \"%s\"\n", v);
                return 2;
            }
            i++;
        } else if (!strcmp(a, "--token") && v) {
            snprintf(r.token, sizeof r.token, "%s", v);
            i++;
        } else {
            fprintf(stderr, "gale-load: unknown or incomplete argument \"%s\"\n", a);
            usage(stderr);
            return 2;
        }
    }
    if (!url || !n || !secs) {
        usage(stderr);
        return 2;
    }
    if (parse_url(&r, url)) {
        return 2;
    }
    r.n = (int)n;
    r.seconds = secs;
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
    lws_set_log_level(LLL_ERR, NULL);
    /* The clients are split over `threads` service threads, each with its own lws
     * context, so decoding is not held to one core. */
    if (threads > r.n) {
        threads = r.n;
    }
    load_run parts[LOAD_MAX_THREADS];
    pthread_t tid[LOAD_MAX_THREADS];
    int first = 0;
    for (int i = 0; i < threads; i++) {
        parts[i] = r;
        parts[i].n = r.n / threads + (i < r.n % threads);
        parts[i].first = first;
        first += parts[i].n;
        parts[i].conns = calloc((size_t)parts[i].n, sizeof *parts[i].conns);
        parts[i].lat = calloc(LAT_BUCKETS, sizeof *parts[i].lat);
        if (!parts[i].conns || !parts[i].lat) {
            fprintf(stderr, "gale-load: no memory\n");
            return 1;
        }
        for (int j = 0; r.per_client && j < parts[i].n; j++) {
            parts[i].conns[j].lat = calloc(CLIENT_LAT_BUCKETS, sizeof(uint32_t));
            if (!parts[i].conns[j].lat) {
                fprintf(stderr, "gale-load: no memory\n");
                return 1;
            }
        }
    }
    for (int i = 0; i < threads; i++) {
        if (pthread_create(&tid[i], NULL, run_part, &parts[i])) {
            fprintf(stderr, "gale-load: cannot start a thread\n");
            return 1;
        }
    }
    double elapsed = 0;
    r.lat = parts[0].lat;
    for (int i = 0; i < threads; i++) {
        pthread_join(tid[i], NULL);
        load_run *q = &parts[i];
        if (q->failed) {
            fprintf(stderr, "gale-load: lws_create_context failed\n");
            return 1;
        }
        elapsed = q->elapsed > elapsed ? q->elapsed : elapsed;
        r.connected += q->connected;
        r.welcomed += q->welcomed;
        r.frames += q->frames;
        r.state_frames += q->state_frames;
        r.keyframes += q->keyframes;
        r.leaf_frames += q->leaf_frames;
        r.wind_frames += q->wind_frames;
        r.bytes += q->bytes;
        r.decode_errors += q->decode_errors;
        r.seq_gaps += q->seq_gaps;
        r.skipped_seqs += q->skipped_seqs;
        r.disconnects += q->disconnects;
        r.connect_errors += q->connect_errors;
        r.lat_n += q->lat_n;
        r.lat_max_us = q->lat_max_us > r.lat_max_us ? q->lat_max_us : r.lat_max_us;
        for (int k = 0; k < q->n_close_codes && r.n_close_codes < 8; k++) {
            r.close_codes[r.n_close_codes++] = q->close_codes[k];
        }
        if (!r.first_error[0] && q->first_error[0]) {
            memcpy(r.first_error, q->first_error, sizeof r.first_error);
        }
        if (i > 0) {
            for (int k = 0; k < LAT_BUCKETS; k++) {
                r.lat[k] += q->lat[k];
            }
        }
    }

    /* bytes a second per client of each kind of view (--views) */
    double kind_bytes[VIEW_KINDS] = { 0 };
    int kind_n[VIEW_KINDS] = { 0 };
    for (int i = 0; i < threads; i++) {
        for (int j = 0; j < parts[i].n; j++) {
            const int k = (parts[i].first + j) % VIEW_KINDS;
            kind_bytes[k] += (double)parts[i].conns[j].bytes;
            kind_n[k]++;
        }
    }
    double p50 = lat_pct(&r, 0.50), p95 = lat_pct(&r, 0.95), p99 = lat_pct(&r, 0.99);
    double maxms = (double)r.lat_max_us * 1e-3;
    if (json) {
        printf("{\"url\": \"%s\", \"clients\": %d, \"seconds\": %.1f, \"role\": \"%s\", "
               "\"connected\": %d, \"welcomed\": %d, \"connect_errors\": %" PRIu64 ", "
               "\"frames\": %" PRIu64 ", \"state_frames\": %" PRIu64 ", \"keyframes\": %" PRIu64
               ", \"leaf_frames\": %" PRIu64 ", \"wind_frames\": %" PRIu64 ", \"bytes\": %" PRIu64 ", "
               "\"state_frames_per_client_s\": %.2f, \"decode_errors\": %" PRIu64
               ", \"sequence_gaps\": %" PRIu64 ", \"skipped_snapshots\": %" PRIu64
               ", \"disconnects\": %" PRIu64 ", \"latency_ms\": {\"p50\": %.3f, \"p95\": %.3f, "
               "\"p99\": %.3f, \"max\": %.3f, \"samples\": %" PRIu64 "}",
               url, r.n, elapsed, ctl_role_name(r.role), r.connected, r.welcomed,
               r.connect_errors, r.frames, r.state_frames, r.keyframes, r.leaf_frames,
               r.wind_frames, r.bytes,
               r.connected ? (double)r.state_frames / r.connected / elapsed : 0.0,
               r.decode_errors, r.seq_gaps, r.skipped_seqs, r.disconnects, p50, p95, p99, maxms,
               r.lat_n);
        if (r.views_half_m > 0) {
            printf(", \"views_bytes_per_client_s\": {");
            for (int k = 0; k < VIEW_KINDS; k++) {
                printf("%s\"%s\": %.0f", k ? ", " : "", view_kind_name(k),
                       kind_n[k] && elapsed > 0 ? kind_bytes[k] / kind_n[k] / elapsed : 0.0);
            }
            printf("}");
        }
        if (r.per_client) {
            printf(", \"per_client\": [");
            for (int i = 0, k = 0; i < threads; i++) {
                for (int j = 0; j < parts[i].n; j++, k++) {
                    printf("%s", k ? ", " : "");
                    client_json(&parts[i], &parts[i].conns[j]);
                }
            }
            printf("]");
        }
        printf(", \"close_codes\": [");
        for (int i = 0; i < r.n_close_codes; i++) {
            printf("%s%d", i ? ", " : "", r.close_codes[i]);
        }
        printf("], \"first_error\": \"");
        for (const char *p = r.first_error; *p; p++) {
            putchar(*p == '"' || *p == '\\' ? '\'' : (isprint((unsigned char)*p) ? *p : ' '));
        }
        printf("\"}\n");
    } else {
        printf("gale-load: %s, %d clients, %.1f s\n"
               "  connected %d (welcomed %d, connect errors %" PRIu64 ")\n"
               "  frames %" PRIu64 " (state %" PRIu64 ", keyframes %" PRIu64 ", leaves %" PRIu64
               ", wind %" PRIu64 "), bytes %" PRIu64 "\n"
               "  decode errors %" PRIu64 " (sequence gaps %" PRIu64 "), snapshots skipped by "
               "the server %" PRIu64 ", disconnects %" PRIu64 "\n"
               "  latency ms: p50 %.3f  p95 %.3f  p99 %.3f  max %.3f (%" PRIu64 " samples)\n",
               url, r.n, elapsed, r.connected, r.welcomed, r.connect_errors, r.frames,
               r.state_frames, r.keyframes, r.leaf_frames, r.wind_frames, r.bytes, r.decode_errors,
               r.seq_gaps,
               r.skipped_seqs, r.disconnects, p50, p95, p99, maxms, r.lat_n);
        if (r.views_half_m > 0) {
            printf("  bytes a second per client:");
            for (int k = 0; k < VIEW_KINDS; k++) {
                printf(" %s %.0f", view_kind_name(k),
                       kind_n[k] && elapsed > 0 ? kind_bytes[k] / kind_n[k] / elapsed : 0.0);
            }
            printf("\n");
        }
        if (r.first_error[0]) {
            printf("  first error: %s\n", r.first_error);
        }
    }
    for (int i = 0; i < threads; i++) {
        for (int j = 0; j < parts[i].n; j++) {
            free(parts[i].conns[j].lat);
        }
        free(parts[i].conns);
        free(parts[i].lat);
    }
    free(known.text);
    bool ok = r.connected == r.n && r.decode_errors == 0 && r.disconnects == 0;
    return ok ? 0 : 1;
}
