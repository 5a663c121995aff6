/* gale-server's side of the NATS link: see link_server.h. */
#include "link_server.h"

#include <nats/nats.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <unistd.h>

#include "link.h"
#include "mono.h"
#include "wire_cursor.h"

struct link_server {
    natsConnection *nc;
    natsSubscription *sub[5];
    srv *s;
    uint8_t *scene; /* owned: the gale.scene message, encoded at attach */
    size_t scene_len;
    uint64_t epoch; /* drawn at start (link.h) */
    uint8_t *buf; /* publishing thread: one snapshot message */
    size_t buf_cap;
    atomic_ullong published, failed;
};

natsOptions *link_nats_options(const char *url, const char *name, gale_err *err)
{
    natsOptions *o = NULL;
    natsStatus st = natsOptions_Create(&o);
    if (st == NATS_OK) {
        st = natsOptions_SetURL(o, url);
    }
    if (st == NATS_OK) {
        st = natsOptions_SetName(o, name);
    }
    if (st == NATS_OK) {
        st = natsOptions_SetMaxReconnect(o, -1);
    }
    if (st == NATS_OK) {
        st = natsOptions_SetReconnectWait(o, 250);
    }
    if (st == NATS_OK) {
        st = natsOptions_SetReconnectBufSize(o, 8 << 20);
    }
    if (st == NATS_OK) {
        st = natsOptions_SetRetryOnFailedConnect(o, true, NULL, NULL);
    }
    if (st == NATS_OK) {
        /* a dead server is noticed within ~1 s, not the default 2 minutes x 2 pings */
        st = natsOptions_SetPingInterval(o, 500);
    }
    if (st == NATS_OK) {
        st = natsOptions_SetMaxPingsOut(o, 2);
    }
    if (st != NATS_OK) {
        gale_errf(err, GALE_E_ARG, "--nats %s: %s", url, natsStatus_GetText(st));
        natsOptions_Destroy(o);
        return NULL;
    }
    return o;
}

link_server *link_server_create(const char *url, gale_err *err)
{
    link_server *l = calloc(1, sizeof *l);
    natsOptions *o = link_nats_options(url, "gale-server", err);
    if (!l || !o) {
        free(l);
        natsOptions_Destroy(o);
        return NULL;
    }
    l->epoch = mono_ns() ^ ((uint64_t)getpid() << 40);
    natsStatus st = natsConnection_Connect(&l->nc, o);
    natsOptions_Destroy(o);
    if (st != NATS_OK && st != NATS_NOT_YET_CONNECTED) {
        gale_errf(err, GALE_E_IO, "--nats %s: %s", url, natsStatus_GetText(st));
        free(l);
        return NULL;
    }
    return l;
}

void link_server_publish(void *user, const net_snap *p)
{
    link_server *l = user;
    if (p->stream) {
        return; /* the server's own clients' views: relays select theirs (relay_views.h) */
    }
    size_t n = link_snap_size(p);
    if (n > l->buf_cap) {
        uint8_t *b = realloc(l->buf, n);
        if (!b) {
            atomic_fetch_add(&l->failed, 1);
            return;
        }
        l->buf = b;
        l->buf_cap = n;
    }
    link_snap_encode(p, l->epoch, l->buf);
    char subj[64];
    snprintf(subj, sizeof subj, LINK_SUBJ_SNAP ".%u", p->stream);
    if (natsConnection_Publish(l->nc, subj, l->buf, (int)n) == NATS_OK) {
        atomic_fetch_add(&l->published, 1);
    } else {
        atomic_fetch_add(&l->failed, 1);
    }
}

static void on_ctl(natsConnection *nc, natsSubscription *sub, natsMsg *msg, void *user)
{
    (void)sub;
    link_server *l = user;
    link_ctl c;
    char addr[64], why_in[8], why[256] = "";
    gale_err e;
    const char *reply_to = natsMsg_GetReply(msg);
    if (link_ctl_decode((const uint8_t *)natsMsg_GetData(msg), (size_t)natsMsg_GetDataLength(msg),
                        &c, addr, sizeof addr, why_in, sizeof why_in, &e) == 0 && reply_to) {
        char *reply = NULL;
        size_t reply_len = 0;
        c.rc = srv_remote_control(l->s, &c.peer, c.text, c.text_len, &reply, &reply_len, why,
                                  sizeof why);
        c.text = reply;
        c.text_len = reply ? reply_len : 0;
        c.why = why;
        uint8_t *out;
        size_t out_len;
        if (link_ctl_encode(&c, &out, &out_len, &e) == 0) {
            natsConnection_Publish(nc, reply_to, out, (int)out_len);
            free(out);
        }
        free(reply);
    } else {
        fprintf(stderr, "gale-server: nats: %s dropped: %s\n", LINK_SUBJ_CTL,
                reply_to ? e.msg : "no reply subject");
    }
    natsMsg_Destroy(msg);
}

static void on_closed(natsConnection *nc, natsSubscription *sub, natsMsg *msg, void *user)
{
    (void)nc;
    (void)sub;
    link_server *l = user;
    link_ctl c;
    char addr[64], why[8];
    if (link_ctl_decode((const uint8_t *)natsMsg_GetData(msg), (size_t)natsMsg_GetDataLength(msg),
                        &c, addr, sizeof addr, why, sizeof why, NULL) == 0) {
        srv_remote_closed(l->s, &c.peer);
    }
    natsMsg_Destroy(msg);
}

static void on_info(natsConnection *nc, natsSubscription *sub, natsMsg *msg, void *user)
{
    (void)sub;
    link_server *l = user;
    link_info in = { 0 };
    size_t sc, ec;
    int ms;
    srv_snap_caps(l->s, &sc, &ec, &ms);
    in.max_streams = (uint32_t)ms;
    in.snap_cap = sc;
    in.extra_cap = ec;
    int n = 0;
    const net_asset *a = srv_assets(l->s, &n);
    in.n_assets = (uint32_t)(n < 64 ? n : 64);
    for (uint32_t i = 0; i < in.n_assets; i++) {
        in.assets[i] = a[i];
    }
    uint8_t buf[64 * 40 + 64];
    size_t len;
    if (natsMsg_GetReply(msg) && link_info_encode(&in, buf, sizeof buf, &len) == 0) {
        natsConnection_Publish(nc, natsMsg_GetReply(msg), buf, (int)len);
    }
    natsMsg_Destroy(msg);
}

/* Request: the asset's 24-byte hash field and a u64 offset; reply: up to LINK_ASSET_CHUNK
 * bytes from there (empty: unknown asset or past its end). */
static void on_asset(natsConnection *nc, natsSubscription *sub, natsMsg *msg, void *user)
{
    (void)sub;
    link_server *l = user;
    const uint8_t *b = (const uint8_t *)natsMsg_GetData(msg);
    int blen = natsMsg_GetDataLength(msg);
    const char *to = natsMsg_GetReply(msg);
    const void *data = "";
    int dlen = 0;
    if (to && blen == 24 + 8) {
        wire_reader r = wire_reader_make(b + 24, 8);
        uint64_t off = wire_get_u64(&r);
        int n = 0;
        const net_asset *a = srv_assets(l->s, &n);
        for (int i = 0; i < n; i++) {
            if (!strncmp(a[i].hash, (const char *)b, 24) && off < a[i].len) {
                size_t left = a[i].len - off;
                data = a[i].bytes + off;
                dlen = (int)(left < LINK_ASSET_CHUNK ? left : LINK_ASSET_CHUNK);
            }
        }
    }
    if (to) {
        natsConnection_Publish(nc, to, data, dlen);
    }
    natsMsg_Destroy(msg);
}

/* Request: a u64 offset; reply: up to LINK_ASSET_CHUNK bytes of the gale.scene message
 * from there (empty past its end). */
static void on_scene(natsConnection *nc, natsSubscription *sub, natsMsg *msg, void *user)
{
    (void)sub;
    link_server *l = user;
    const char *to = natsMsg_GetReply(msg);
    const void *data = "";
    int dlen = 0;
    if (to && natsMsg_GetDataLength(msg) == 8) {
        wire_reader r = wire_reader_make((const uint8_t *)natsMsg_GetData(msg), 8);
        uint64_t off = wire_get_u64(&r);
        if (off < l->scene_len) {
            size_t left = l->scene_len - (size_t)off;
            data = l->scene + off;
            dlen = (int)(left < LINK_ASSET_CHUNK ? left : LINK_ASSET_CHUNK);
        }
    }
    if (to) {
        natsConnection_Publish(nc, to, data, dlen);
    }
    natsMsg_Destroy(msg);
}

int link_server_attach(link_server *l, srv *s, gale_err *err)
{
    l->s = s;
    const srv_view_rule vr = srv_view_rule_get(s);
    const link_scene sc = { .n_trees = vr.n_trees, .lod_modes = vr.lod_modes,
                            .key_every = vr.key_every, .max_modes = vr.max_modes,
                            .margin_m = vr.margin_m,
                            .cell_m = vr.cell_m, .pos = (float *)vr.tree_pos };
    l->scene_len = link_scene_size(sc.n_trees);
    l->scene = malloc(l->scene_len);
    if (!l->scene) {
        return gale_errf(err, GALE_E_NOMEM, "nats: no memory for the %zu-byte scene message",
                         l->scene_len);
    }
    link_scene_encode(&sc, l->scene);
    static const char *subj[5] = { LINK_SUBJ_CTL, LINK_SUBJ_CLOSED, LINK_SUBJ_INFO,
                                   LINK_SUBJ_ASSET, LINK_SUBJ_SCENE };
    natsMsgHandler fn[5] = { on_ctl, on_closed, on_info, on_asset, on_scene };
    for (int i = 0; i < 5; i++) {
        natsStatus st = natsConnection_Subscribe(&l->sub[i], l->nc, subj[i], fn[i], l);
        if (st != NATS_OK) {
            return gale_errf(err, GALE_E_IO, "nats: subscribe %s: %s", subj[i],
                             natsStatus_GetText(st));
        }
    }
    return 0;
}

void link_server_counts(const link_server *l, unsigned long long *published,
                        unsigned long long *failed)
{
    *published = atomic_load(&l->published);
    *failed = atomic_load(&l->failed);
}

void link_server_destroy(link_server *l)
{
    if (!l) {
        return;
    }
    for (int i = 0; i < 5; i++) {
        if (l->sub[i]) {
            natsSubscription_Unsubscribe(l->sub[i]);
            natsSubscription_Destroy(l->sub[i]);
        }
    }
    natsConnection_Destroy(l->nc);
    free(l->buf);
    free(l->scene);
    free(l);
}
