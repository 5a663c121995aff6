/* What the control-message codecs share (ctl_int.h): the name tables of roles, views and
 * message types, the failure that records a close code, the number form of the encoders
 * and the enum reader. The dispatcher (ctl.c) and every ctl_<message>.c build on it. */
#include "ctl.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ctl_int.h"

const char *const ctl_role_names[CTL_N_ROLES] = { "viewer", "kiosk", "wall-tile", "load" };
const char *const ctl_view_names[CTL_N_VIEWS] = { "all", "circle", "frustum" };
static const char *const type_names[] = { NULL,      "hello",   "view", "wind", "resync",
                                          "ping",    "welcome", "pong", "error",
                                          /* display walls */
                                          "wall_join", "wall_drawn", "wall_camera",
                                          "wall_sync", "wall_swap",
                                          /* kiosk */
                                          "reset",
                                          /* operations */
                                          "kiosk_state", "schedule" };

#define N_TYPES (int)(sizeof type_names / sizeof type_names[0])

const char *ctl_role_name(int role)
{
    return role >= 0 && role < CTL_N_ROLES ? ctl_role_names[role] : NULL;
}

const char *ctl_type_name(int type)
{
    return type > 0 && type < N_TYPES ? type_names[type] : NULL;
}

bool ctl_from_client(int type)
{
    return (type >= CTL_HELLO && type <= CTL_PING) ||
           (type >= CTL_WALL_JOIN && type <= CTL_WALL_CAMERA) || type == CTL_RESET ||
           type == CTL_KIOSK_STATE;
}

int ctl_fail(ctl_rd *c, int close, int code, const char *fmt, ...)
{
    char msg[sizeof c->j.err->msg];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    c->close = close;
    return json_fail(&c->j, code, "%s", msg);
}

double ctl_jnum(float f)
{
    char b[32];
    snprintf(b, sizeof b, "%.7g", (double)f);
    return strtod(b, NULL);
}

bool ctl_add_num(cJSON *o, const char *k, double v)
{
    return json_add_number(o, k, v) != NULL;
}

int ctl_get_enum(ctl_rd *c, const cJSON *o, const char *path, const char *key,
                 const char *const *names, int n, const char *list, int *out)
{
    char s[32];
    int rc = json_string(&c->j, o, path, key, true, NULL, s, sizeof s, NULL);
    if (rc) {
        const cJSON *j = cJSON_GetObjectItemCaseSensitive(o, key);
        if (j && cJSON_IsString(j)) { /* too long: report as not one of the names */
            return ctl_fail(c, 0, GALE_E_RANGE, "%s.%s: expected one of %s, got \"%.31s...\"",
                            path, key, list, j->valuestring);
        }
        return rc;
    }
    for (int i = 0; i < n; i++) {
        if (names[i] && strcmp(s, names[i]) == 0) {
            *out = i;
            return 0;
        }
    }
    return ctl_fail(c, 0, GALE_E_RANGE, "%s.%s: expected one of %s, got \"%s\"", path, key, list,
                    s);
}
