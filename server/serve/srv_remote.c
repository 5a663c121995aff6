/* Control handling for relayed connections (server/SERVER.md "Relays"): a broker bridge
 * hands the server a relayed client's control message with the connection state the relay
 * keeps, on the bridge's own thread; the same handler as for direct clients answers it,
 * serialised with the lws thread by ctl_lock (the kiosk gate and view slots are the
 * handler's state). */
#include "srv_int.h"

int srv_control_serial(void *user, net_peer *p, const char *text, size_t len, char **reply,
                       size_t *reply_len, char *why, size_t why_cap)
{
    srv *s = user;
    pthread_mutex_lock(&s->ctl_lock);
    int rc = srv_on_control(s, p, text, len, reply, reply_len, why, why_cap);
    pthread_mutex_unlock(&s->ctl_lock);
    return rc;
}

void srv_closed_serial(void *user, const net_peer *p)
{
    srv *s = user;
    pthread_mutex_lock(&s->ctl_lock);
    srv_on_closed(s, p);
    pthread_mutex_unlock(&s->ctl_lock);
}

int srv_remote_control(srv *s, net_peer *p, const char *text, size_t len, char **reply,
                       size_t *reply_len, char *why, size_t why_cap)
{
    return srv_control_serial(s, p, text, len, reply, reply_len, why, why_cap);
}

void srv_remote_closed(srv *s, const net_peer *p)
{
    srv_closed_serial(s, p);
}

const net_asset *srv_assets(const srv *s, int *n)
{
    *n = s->d.sc->n_species;
    return s->assets;
}

void srv_snap_caps(const srv *s, size_t *snap_cap, size_t *extra_cap, int *max_streams)
{
    *max_streams = SRV_MAX_VIEWS;
    *snap_cap = s->snap_cap;
    *extra_cap = s->extra_cap;
}
