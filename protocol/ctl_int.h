/* Private to the control codec: the reader state every message parser shares, the helpers
 * of ctl_common.c, and each message's parse/encode pair that ctl.c dispatches to.
 * Included by ctl*.c only. */
#ifndef GALE_CTL_INT_H
#define GALE_CTL_INT_H

#include <cjson/cJSON.h>

#include "ctl.h"
#include "json.h"
#include "wire.h"

/* 2^53: integers above are not exact in a JSON double. */
#define CTL_U53 9007199254740992LL
#define CTL_U32 4294967295LL

/* One decode or encode: the kit's reader (where "ctl", WIRE voice) and the close code of
 * the first failure; 0 there means a field error (WIRE_CLOSE_BAD_FIELD). */
typedef struct ctl_rd {
    json_rd j;
    int close;
} ctl_rd;

/* Fails with close code, GALE_E_* code and "ctl: " + the formatted text. */
int ctl_fail(ctl_rd *c, int close, int code, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

/* Wire names, indexed by enum value (type_names[0] is NULL). */
extern const char *const ctl_role_names[];
extern const char *const ctl_view_names[];
#define CTL_N_ROLES 4
#define CTL_N_VIEWS 3

/* o[key] as one of names[0..n) (NULL entries skipped) into *out; list is "a|b|c" for the
 * message. */
int ctl_get_enum(ctl_rd *c, const cJSON *o, const char *path, const char *key,
                 const char *const *names, int n, const char *list, int *out);

/* A float as the shortest decimal of 7 significant digits, so JSON shows 1.3, not
 * 1.2999999523162842; exact to float precision for the control channel's needs. The
 * encoders check the value they write, so a check sees what a decoder will. */
double ctl_jnum(float f);

/* Adds o[k] = v (json_add_number: an integer of magnitude <= 2^53 exactly); false when out
 * of memory. */
bool ctl_add_num(cJSON *o, const char *k, double v);

/* Each message's pair. parse: o is the message object (its "type" already read); fills
 * *out, returns 0 or a GALE_E_* with the failure reported on c. encode: checks *m as
 * the parser would (same limits, same messages) and adds its fields to o; GALE_E_RANGE
 * for a value a decoder would reject, GALE_E_ARG for an enum out of its range,
 * GALE_E_NOMEM. A view object is the part hello and view share. */
int ctl_view_parse(ctl_rd *c, const cJSON *j, const char *path, ctl_view *v);
int ctl_view_encode(ctl_rd *c, const ctl_view *v, const char *path, cJSON **out);
int ctl_view_msg_parse(ctl_rd *c, const cJSON *o, ctl_view *v);
int ctl_view_msg_encode(ctl_rd *c, const ctl_view *v, cJSON *o);
int ctl_hello_parse(ctl_rd *c, const cJSON *o, ctl_hello *h);
int ctl_hello_encode(ctl_rd *c, const ctl_hello *h, cJSON *o);
int ctl_wind_parse(ctl_rd *c, const cJSON *o, ctl_wind *w);
int ctl_wind_encode(ctl_rd *c, const ctl_wind *w, cJSON *o);
int ctl_resync_parse(ctl_rd *c, const cJSON *o, uint32_t *seq);
int ctl_resync_encode(ctl_rd *c, uint32_t seq, cJSON *o);
int ctl_ping_parse(ctl_rd *c, const cJSON *o, ctl_ping *p);
int ctl_ping_encode(ctl_rd *c, const ctl_ping *p, cJSON *o);
int ctl_pong_parse(ctl_rd *c, const cJSON *o, ctl_pong *p);
int ctl_pong_encode(ctl_rd *c, const ctl_pong *p, cJSON *o);
int ctl_error_parse(ctl_rd *c, const cJSON *o, ctl_error *e);
int ctl_error_encode(ctl_rd *c, const ctl_error *e, cJSON *o);
int ctl_welcome_parse(ctl_rd *c, const cJSON *o, ctl_welcome *w);
int ctl_welcome_encode(ctl_rd *c, const ctl_welcome *w, cJSON *o);
/* welcome.scenarios (optional): ctl_scenarios.c */
int ctl_scenarios_parse(ctl_rd *c, const cJSON *o, ctl_welcome *w);
int ctl_scenarios_encode(ctl_rd *c, const ctl_welcome *w, cJSON *o);
/* reset: ctl_kiosk.c */
int ctl_reset_parse(ctl_rd *c, const cJSON *o, ctl_reset *m);
int ctl_reset_encode(ctl_rd *c, const ctl_reset *m, cJSON *o);
/* kiosk_state, schedule: ctl_ops.c */
int ctl_kiosk_state_parse(ctl_rd *c, const cJSON *o, ctl_kiosk_state *k);
int ctl_kiosk_state_encode(ctl_rd *c, const ctl_kiosk_state *k, cJSON *o);
int ctl_schedule_parse(ctl_rd *c, const cJSON *o, ctl_schedule *m);
int ctl_schedule_encode(ctl_rd *c, const ctl_schedule *m, cJSON *o);
/* display walls: ctl_wall.c */
int ctl_wall_parse(ctl_rd *c, const cJSON *o, int type, ctl_msg *m);
int ctl_wall_encode(ctl_rd *c, const ctl_msg *m, cJSON *o);

#endif
