/* JSON control messages of the gale wire (PROTOCOL.md "Control messages"): the
 * dispatcher. ctl_decode bounds, parses (line:col on bad JSON), reads "type" and hands the
 * object to that message's parser (ctl_hello.c, ctl_view.c, ctl_kiosk.c, ctl_link.c,
 * ctl_welcome.c, ctl_scenarios.c, ctl_wall.c, ctl_ops.c); ctl_encode hands the struct to its encoder, which checks what it writes
 * against the parser's own limits, so no output is parsed again on send. */
#include "ctl.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ctl_int.h"

/* ---- decoding ------------------------------------------------------------------------ */

/* Bad JSON: line:col of where cJSON stopped and a printable excerpt from there. */
static int fail_syntax(ctl_rd *c, const char *text, size_t len, size_t at, bool trailing)
{
    int line, col;
    json_line_col(text, at, &line, &col);
    char near[16] = "";
    size_t k = 0;
    for (; k < 12 && at + k < len; k++) {
        char ch = text[at + k];
        near[k] = ch >= 0x20 && ch < 0x7f && ch != '"' ? ch : '?';
    }
    near[k] = '\0';
    return ctl_fail(c, WIRE_CLOSE_BAD_JSON, GALE_E_PARSE, "%d:%d: %s near \"%s\"", line, col,
                    trailing ? "trailing characters after the JSON value" : "invalid JSON",
                    near);
}

/* *type = the message type named by root.type. */
static int read_type(ctl_rd *c, const cJSON *root, int *type)
{
    const cJSON *ty = cJSON_GetObjectItemCaseSensitive(root, "type");
    if (!cJSON_IsString(ty)) {
        return ctl_fail(c, WIRE_CLOSE_UNKNOWN_TYPE, GALE_E_PARSE,
                        "type: %s: expected a string, got %s", ty ? "wrong type" : "missing",
                        json_kind(ty));
    }
    for (int i = 1; ctl_type_name(i); i++) {
        if (strcmp(ty->valuestring, ctl_type_name(i)) == 0) {
            *type = i;
            return 0;
        }
    }
    return ctl_fail(c, WIRE_CLOSE_UNKNOWN_TYPE, GALE_E_PARSE,
                    "type: expected one of hello|view|wind|resync|ping|welcome|pong|error|wall_*|reset|kiosk_state|schedule, "
                    "got \"%.40s\"",
                    ty->valuestring);
}

static int parse_body(ctl_rd *c, const cJSON *root, ctl_msg *m)
{
    switch (m->type) {
    case CTL_HELLO: return ctl_hello_parse(c, root, &m->u.hello);
    case CTL_VIEW: return ctl_view_msg_parse(c, root, &m->u.view);
    case CTL_WIND: return ctl_wind_parse(c, root, &m->u.wind);
    case CTL_RESYNC: return ctl_resync_parse(c, root, &m->u.resync_seq);
    case CTL_PING: return ctl_ping_parse(c, root, &m->u.ping);
    case CTL_WELCOME: return ctl_welcome_parse(c, root, &m->u.welcome);
    case CTL_PONG: return ctl_pong_parse(c, root, &m->u.pong);
    case CTL_WALL_JOIN:
    case CTL_WALL_DRAWN:
    case CTL_WALL_CAMERA:
    case CTL_WALL_SYNC:
    case CTL_WALL_SWAP: return ctl_wall_parse(c, root, m->type, m);
    case CTL_RESET: return ctl_reset_parse(c, root, &m->u.reset);
    case CTL_KIOSK_STATE: return ctl_kiosk_state_parse(c, root, &m->u.kiosk_state);
    case CTL_SCHEDULE: return ctl_schedule_parse(c, root, &m->u.schedule);
    default: return ctl_error_parse(c, root, &m->u.error); /* CTL_ERROR */
    }
}

int ctl_decode(const char *text, size_t len, size_t max_len, ctl_msg *m, int *close_code,
               gale_err *err)
{
    memset(m, 0, sizeof *m);
    ctl_rd c = { { "ctl", JSON_VOICE_WIRE, err }, 0 };
    if (max_len == 0) {
        max_len = CTL_MAX_CLIENT_BYTES;
    }
    int rc = 0;
    cJSON *root = NULL;
    if (len > max_len) {
        rc = ctl_fail(&c, WIRE_CLOSE_TOO_BIG, GALE_E_RANGE,
                      "message: expected <= %zu bytes, got %zu", max_len, len);
        goto done;
    }
    size_t at = 0;
    root = json_parse(text, len, &at);
    if (root) {
        at = json_skip_space(text, len, at);
    }
    if (!root || at < len) {
        rc = fail_syntax(&c, text, len, at, root != NULL);
        goto done;
    }
    if (!cJSON_IsObject(root)) {
        rc = ctl_fail(&c, WIRE_CLOSE_BAD_JSON, GALE_E_PARSE, "message: expected an object, got %s",
                      json_kind(root));
        goto done;
    }
    if (json_depth(root, CTL_MAX_DEPTH) > CTL_MAX_DEPTH) {
        rc = ctl_fail(&c, WIRE_CLOSE_BAD_JSON, GALE_E_RANGE,
                      "message: nesting: expected <= %d levels, got more", CTL_MAX_DEPTH);
        goto done;
    }
    rc = read_type(&c, root, &m->type);
    if (!rc) {
        rc = parse_body(&c, root, m);
    }
done:
    cJSON_Delete(root);
    if (rc) {
        ctl_msg_fini(m);
    }
    if (close_code) {
        *close_code = rc == 0 ? 0 : c.close ? c.close : WIRE_CLOSE_BAD_FIELD;
    }
    return rc;
}

void ctl_msg_fini(ctl_msg *m)
{
    if (!m) {
        return;
    }
    if (m->type == CTL_WELCOME) {
        free(m->u.welcome.species);
        free(m->u.welcome.instances);
        free(m->u.welcome.obstacles);
        free(m->u.welcome.scenarios);
    }
    memset(m, 0, sizeof *m);
}

/* ---- encoding ------------------------------------------------------------------------ */

static int encode_body(ctl_rd *c, const ctl_msg *m, cJSON *o)
{
    switch (m->type) {
    case CTL_HELLO: return ctl_hello_encode(c, &m->u.hello, o);
    case CTL_VIEW: return ctl_view_msg_encode(c, &m->u.view, o);
    case CTL_WIND: return ctl_wind_encode(c, &m->u.wind, o);
    case CTL_RESYNC: return ctl_resync_encode(c, m->u.resync_seq, o);
    case CTL_PING: return ctl_ping_encode(c, &m->u.ping, o);
    case CTL_WELCOME: return ctl_welcome_encode(c, &m->u.welcome, o);
    case CTL_PONG: return ctl_pong_encode(c, &m->u.pong, o);
    case CTL_WALL_JOIN:
    case CTL_WALL_DRAWN:
    case CTL_WALL_CAMERA:
    case CTL_WALL_SYNC:
    case CTL_WALL_SWAP: return ctl_wall_encode(c, m, o);
    case CTL_RESET: return ctl_reset_encode(c, &m->u.reset, o);
    case CTL_KIOSK_STATE: return ctl_kiosk_state_encode(c, &m->u.kiosk_state, o);
    case CTL_SCHEDULE: return ctl_schedule_encode(c, &m->u.schedule, o);
    default: return ctl_error_encode(c, &m->u.error, o); /* CTL_ERROR */
    }
}

/* *out = the checked JSON tree of *m; on failure NULL and err filled ("ctl_encode: ..."). */
static int to_json(const ctl_msg *m, cJSON **out, gale_err *err)
{
    *out = NULL;
    const char *tn = ctl_type_name(m->type);
    if (!tn) {
        return gale_errf(err, GALE_E_ARG, "ctl_encode: type: expected a ctl_type, got %d",
                         m->type);
    }
    gale_err e2 = { 0 };
    ctl_rd c = { { "ctl", JSON_VOICE_WIRE, &e2 }, 0 };
    cJSON *o = cJSON_CreateObject();
    int rc = o && cJSON_AddStringToObject(o, "type", tn)
                 ? encode_body(&c, m, o)
                 : ctl_fail(&c, 0, GALE_E_NOMEM, "%s: out of memory", tn);
    if (rc) {
        cJSON_Delete(o);
        return gale_errf(err, rc == GALE_E_NOMEM || rc == GALE_E_ARG ? rc : GALE_E_RANGE,
                         "ctl_encode: %s", e2.msg);
    }
    *out = o;
    return 0;
}

/* What a decoder accepts of this length (both directions: the server's limit). */
static int check_size(size_t n, gale_err *err)
{
    if (n > CTL_MAX_SERVER_BYTES) {
        return gale_errf(err, GALE_E_RANGE, "ctl_encode: ctl: message: expected <= %u bytes, got %zu",
                         CTL_MAX_SERVER_BYTES, n);
    }
    return 0;
}

int ctl_encode(const ctl_msg *m, char **out, size_t *len, gale_err *err)
{
    *out = NULL;
    *len = 0;
    cJSON *o = NULL;
    int rc = to_json(m, &o, err);
    if (rc) {
        return rc;
    }
    char *s = cJSON_PrintUnformatted(o);
    cJSON_Delete(o);
    if (!s) {
        return gale_errf(err, GALE_E_NOMEM, "ctl_encode: out of memory");
    }
    size_t n = strlen(s);
    rc = check_size(n, err);
    if (rc) {
        cJSON_free(s);
        return rc;
    }
    /* Hand back memory the caller frees with free(), whatever cJSON's hooks are. */
    char *copy = malloc(n + 1);
    if (!copy) {
        cJSON_free(s);
        return gale_errf(err, GALE_E_NOMEM, "ctl_encode: out of memory");
    }
    memcpy(copy, s, n + 1);
    cJSON_free(s);
    *out = copy;
    *len = n;
    return 0;
}

int ctl_encode_into(const ctl_msg *m, char *buf, size_t cap, size_t *len, gale_err *err)
{
    *len = 0;
    cJSON *o = NULL;
    int rc = to_json(m, &o, err);
    if (rc) {
        return rc;
    }
    if (cap > 0x7fffffff) {
        cap = 0x7fffffff;
    }
    cJSON_bool ok = cJSON_PrintPreallocated(o, buf, (int)cap, 0);
    cJSON_Delete(o);
    if (!ok) {
        return gale_errf(err, GALE_E_RANGE, "ctl_encode_into: buffer: %zu bytes too small", cap);
    }
    size_t n = strlen(buf);
    rc = check_size(n, err);
    if (rc) {
        return rc;
    }
    *len = n;
    return 0;
}
