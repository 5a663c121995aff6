/* The connection's small messages (PROTOCOL.md "Control messages"): resync (a client
 * asking for a keyframe), ping and pong (the clock round trip), and the error the server
 * sends before it closes. */
#include "ctl_int.h"

#define CODE_MIN 1000 /* close codes a message may carry: WebSocket 1000..4999 */
#define CODE_MAX 4999

static int oom(ctl_rd *c, const char *what)
{
    return ctl_fail(c, 0, GALE_E_NOMEM, "%s: out of memory", what);
}

/* A clock [us] goes out as a JSON double: it must be an exact integer there. */
static int check_us(ctl_rd *c, const char *path, const char *key, uint64_t us)
{
    return json_check_int(&c->j, path, key, 0, CTL_U53, (double)us);
}

int ctl_resync_parse(ctl_rd *c, const cJSON *o, uint32_t *seq)
{
    static const char *const keys[] = { "type", "seq", NULL };
    long long v = 0;
    int rc = json_check_keys(&c->j, o, "resync", keys);
    if (!rc) {
        rc = json_int(&c->j, o, "resync", "seq", true, 0, CTL_U32, &v, NULL);
    }
    *seq = (uint32_t)v;
    return rc;
}

int ctl_resync_encode(ctl_rd *c, uint32_t seq, cJSON *o)
{
    return ctl_add_num(o, "seq", seq) ? 0 : oom(c, "resync");
}

int ctl_ping_parse(ctl_rd *c, const cJSON *o, ctl_ping *p)
{
    static const char *const keys[] = { "type", "id", "client_us", NULL };
    const json_rd *r = &c->j;
    long long id = 0, cu = 0;
    int rc = json_check_keys(r, o, "ping", keys);
    if (!rc) {
        rc = json_int(r, o, "ping", "id", true, 0, CTL_U32, &id, NULL);
    }
    if (!rc) {
        rc = json_int(r, o, "ping", "client_us", true, 0, CTL_U53, &cu, NULL);
    }
    p->id = (uint32_t)id;
    p->client_us = (uint64_t)cu;
    return rc;
}

int ctl_ping_encode(ctl_rd *c, const ctl_ping *p, cJSON *o)
{
    int rc = check_us(c, "ping", "client_us", p->client_us);
    if (rc) {
        return rc;
    }
    return ctl_add_num(o, "id", p->id) && ctl_add_num(o, "client_us", (double)p->client_us)
               ? 0
               : oom(c, "ping");
}

int ctl_pong_parse(ctl_rd *c, const cJSON *o, ctl_pong *p)
{
    static const char *const keys[] = { "type", "id", "client_us", "server_us", "tick", NULL };
    const json_rd *r = &c->j;
    long long id = 0, cu = 0, su = 0, tick = 0;
    int rc = json_check_keys(r, o, "pong", keys);
    if (!rc) {
        rc = json_int(r, o, "pong", "id", true, 0, CTL_U32, &id, NULL);
    }
    if (!rc) {
        rc = json_int(r, o, "pong", "client_us", true, 0, CTL_U53, &cu, NULL);
    }
    if (!rc) {
        rc = json_int(r, o, "pong", "server_us", true, 0, CTL_U53, &su, NULL);
    }
    if (!rc) {
        rc = json_int(r, o, "pong", "tick", true, 0, CTL_U32, &tick, NULL);
    }
    p->id = (uint32_t)id;
    p->client_us = (uint64_t)cu;
    p->server_us = (uint64_t)su;
    p->tick = (uint32_t)tick;
    return rc;
}

int ctl_pong_encode(ctl_rd *c, const ctl_pong *p, cJSON *o)
{
    int rc = check_us(c, "pong", "client_us", p->client_us);
    if (!rc) {
        rc = check_us(c, "pong", "server_us", p->server_us);
    }
    if (rc) {
        return rc;
    }
    return ctl_add_num(o, "id", p->id) && ctl_add_num(o, "client_us", (double)p->client_us) &&
                   ctl_add_num(o, "server_us", (double)p->server_us) &&
                   ctl_add_num(o, "tick", p->tick)
               ? 0
               : oom(c, "pong");
}

int ctl_error_parse(ctl_rd *c, const cJSON *o, ctl_error *e)
{
    static const char *const keys[] = { "type", "code", "message", NULL };
    long long code = 0;
    int rc = json_check_keys(&c->j, o, "error", keys);
    if (!rc) {
        rc = json_int(&c->j, o, "error", "code", true, CODE_MIN, CODE_MAX, &code, NULL);
    }
    if (!rc) {
        rc = json_string(&c->j, o, "error", "message", true, NULL, e->message,
                         sizeof e->message, NULL);
    }
    e->code = (int)code;
    return rc;
}

int ctl_error_encode(ctl_rd *c, const ctl_error *e, cJSON *o)
{
    int rc = json_check_int(&c->j, "error", "code", CODE_MIN, CODE_MAX, e->code);
    if (!rc) {
        rc = json_check_string(&c->j, "error", "message", e->message, sizeof e->message);
    }
    if (rc) {
        return rc;
    }
    return ctl_add_num(o, "code", e->code) && cJSON_AddStringToObject(o, "message", e->message)
               ? 0
               : oom(c, "error");
}
