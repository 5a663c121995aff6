/* hello (PROTOCOL.md "Control messages"): a client's first message, with its protocol
 * version, role, optional view and optional kiosk token. The version is read first: a
 * client of another version may not share the other fields. */
#include "ctl_int.h"

int ctl_hello_parse(ctl_rd *c, const cJSON *o, ctl_hello *h)
{
    static const char *const keys[] = { "type", "protocol", "role", "view", "token", NULL };
    const json_rd *r = &c->j;
    int rc = json_check_keys(r, o, "hello", keys);
    long long proto = 0;
    if (!rc) {
        rc = json_int(r, o, "hello", "protocol", true, 0, 65535, &proto, NULL);
    }
    if (!rc && proto != WIRE_PROTOCOL_VERSION) {
        rc = ctl_fail(c, WIRE_CLOSE_VERSION, GALE_E_VERSION,
                      "hello.protocol: expected %d, got %d", WIRE_PROTOCOL_VERSION, (int)proto);
    }
    h->protocol = (int)proto;
    if (!rc) {
        rc = ctl_get_enum(c, o, "hello", "role", ctl_role_names, CTL_N_ROLES,
                          "viewer|kiosk|wall-tile|load", &h->role);
    }
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, "view");
    if (!rc && v) {
        rc = ctl_view_parse(c, v, "hello.view", &h->view);
    }
    if (!rc) {
        rc = json_string(r, o, "hello", "token", false, NULL, h->token, sizeof h->token, NULL);
    }
    return rc;
}

int ctl_hello_encode(ctl_rd *c, const ctl_hello *h, cJSON *o)
{
    /* Arguments outside their enums first: they are the caller's bug, whatever else. */
    const char *rn = ctl_role_name(h->role);
    if (!rn) {
        return ctl_fail(c, 0, GALE_E_ARG, "hello.role: expected a ctl_role, got %d", h->role);
    }
    if (h->view.kind != CTL_VIEW_ALL && (h->view.kind < 0 || h->view.kind >= CTL_N_VIEWS)) {
        return ctl_fail(c, 0, GALE_E_ARG, "hello.view.kind: expected a ctl_view_kind, got %d",
                        h->view.kind);
    }
    if (h->protocol != WIRE_PROTOCOL_VERSION) {
        return ctl_fail(c, WIRE_CLOSE_VERSION, GALE_E_RANGE, "hello.protocol: expected %d, got %d",
                        WIRE_PROTOCOL_VERSION, h->protocol);
    }
    if (h->token[0]) {
        int rc = json_check_string(&c->j, "hello", "token", h->token, sizeof h->token);
        if (rc) {
            return rc;
        }
    }
    if (!ctl_add_num(o, "protocol", h->protocol) || !cJSON_AddStringToObject(o, "role", rn)) {
        return ctl_fail(c, 0, GALE_E_NOMEM, "hello: out of memory");
    }
    if (h->view.kind != CTL_VIEW_ALL) {
        cJSON *v = NULL;
        int rc = ctl_view_encode(c, &h->view, "hello.view", &v);
        if (rc) {
            return rc;
        }
        if (!cJSON_AddItemToObject(o, "view", v)) {
            cJSON_Delete(v);
            return ctl_fail(c, 0, GALE_E_NOMEM, "hello: out of memory");
        }
    }
    if (h->token[0] && !cJSON_AddStringToObject(o, "token", h->token)) {
        return ctl_fail(c, 0, GALE_E_NOMEM, "hello: out of memory");
    }
    return 0;
}
