/* Fuzz target for JSON control messages: any bytes are parsed in both directions' size
 * limits; a rejection must carry a close code and a message, an accepted message must
 * encode, decode to the same type and encode to the same bytes again, and that encoding
 * must decode to the same message, every field of it (the types made of plain fields
 * compared whole, the welcome field by field and array by array). Nothing may crash or
 * leak. */
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "ctl.h"
#include "wire.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* a and b hold the same message (ctl_decode zeroes the whole struct first, so the bytes
   past the active member and the padding compare equal). */
static bool same_msg(const ctl_msg *a, const ctl_msg *b)
{
    switch (a->type) {
    case CTL_HELLO:
    case CTL_VIEW:
    case CTL_WIND:
    case CTL_RESYNC:
    case CTL_PING:
    case CTL_PONG:
    case CTL_ERROR:
    case CTL_RESET:
    case CTL_KIOSK_STATE:
    case CTL_SCHEDULE:
        return memcmp(a, b, sizeof *a) == 0;
    case CTL_WELCOME: {
        const ctl_welcome *x = &a->u.welcome, *y = &b->u.welcome;
        return x->protocol == y->protocol && x->client_id == y->client_id &&
               x->role == y->role && x->tick_hz == y->tick_hz &&
               x->snapshot_hz == y->snapshot_hz && x->server_us == y->server_us &&
               x->tick == y->tick && x->n_species == y->n_species &&
               x->n_instances == y->n_instances && x->n_obstacles == y->n_obstacles &&
               (!x->n_species ||
                !memcmp(x->species, y->species, x->n_species * sizeof *x->species)) &&
               (!x->n_instances ||
                !memcmp(x->instances, y->instances, x->n_instances * sizeof *x->instances)) &&
               (!x->n_obstacles ||
                !memcmp(x->obstacles, y->obstacles, x->n_obstacles * sizeof *x->obstacles)) &&
               x->n_scenarios == y->n_scenarios &&
               (!x->n_scenarios ||
                !memcmp(x->scenarios, y->scenarios, x->n_scenarios * sizeof *x->scenarios));
    }
    default:
        return true; /* other types: the byte comparison of their encodings below */
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    for (int dir = 0; dir < 2; dir++) {
        ctl_msg m;
        int close = 0;
        gale_err e;
        size_t max = dir ? CTL_MAX_SERVER_BYTES : CTL_MAX_CLIENT_BYTES;
        int rc = ctl_decode((const char *)data, size, max, &m, &close, &e);
        if (rc != 0) {
            if (close < 4000 || close > 4999 || e.msg[0] == '\0') {
                abort();
            }
            continue;
        }
        char *out = NULL;
        size_t n = 0;
        if (ctl_encode(&m, &out, &n, &e) == 0) {
            /* floats are printed with 7 significant digits (PROTOCOL.md), so the first
             * encoding may round what the input said; from there the message is a fixed
             * point: it decodes to the same fields and encodes to the same bytes */
            ctl_msg back, back2;
            if (ctl_decode(out, n, CTL_MAX_SERVER_BYTES, &back, &close, &e) != 0 ||
                back.type != m.type) {
                abort();
            }
            char *again = NULL;
            size_t n2 = 0;
            if (ctl_encode(&back, &again, &n2, &e) != 0 || n2 != n || memcmp(out, again, n)) {
                abort();
            }
            if (ctl_decode(again, n2, CTL_MAX_SERVER_BYTES, &back2, &close, &e) != 0 ||
                !same_msg(&back, &back2)) {
                abort();
            }
            free(again);
            ctl_msg_fini(&back2);
            ctl_msg_fini(&back);
        }
        free(out);
        ctl_msg_fini(&m);
    }
    return 0;
}
