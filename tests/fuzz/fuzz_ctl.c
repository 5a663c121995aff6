/* Fuzz target for JSON control messages: any bytes are parsed in both directions' size
 * limits; a rejection must carry a close code and a message, an accepted message must
 * encode and decode again to the same type. Nothing may crash or leak. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "ctl.h"
#include "wire.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

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
            ctl_msg back;
            if (ctl_decode(out, n, CTL_MAX_SERVER_BYTES, &back, &close, &e) != 0 ||
                back.type != m.type) {
                abort();
            }
            ctl_msg_fini(&back);
        }
        free(out);
        ctl_msg_fini(&m);
    }
    return 0;
}
