/* Fuzz target for the usage counters' file (server/serve/ops_usage.c, SERVER.md "Usage
 * counters"): any bytes are parsed; a refusal must carry a message and leave the counters
 * zero; an accepted file must write (ops_usage_json) and parse again to the same
 * counters, and that text must be a fixed point. Nothing may crash or leak. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "ops_usage.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    ops_usage u, v;
    gale_err e = { 0 };
    if (ops_usage_parse(&u, "usage.json", (const char *)data, size, &e)) {
        if (!e.msg[0] || u.sessions || u.n_replays || u.n_langs) {
            abort();
        }
        return 0;
    }
    char *t = ops_usage_json(&u);
    if (!t) {
        abort();
    }
    if (ops_usage_parse(&v, "usage.json", t, strlen(t), &e) || v.sessions != u.sessions ||
        v.n_replays != u.n_replays || v.n_langs != u.n_langs ||
        memcmp(v.categories, u.categories, sizeof u.categories) ||
        memcmp(v.replays, u.replays, sizeof u.replays) ||
        memcmp(v.langs, u.langs, sizeof u.langs)) {
        abort();
    }
    char *t2 = ops_usage_json(&v);
    if (!t2 || strcmp(t, t2)) {
        abort();
    }
    free(t);
    free(t2);
    return 0;
}
