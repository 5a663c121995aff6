/* Fuzz target for the HTTP header values gale parses itself (server/serve/http_hdr.h):
 * every input is a Range value against bodies of several lengths, and an If-None-Match /
 * If-Range value against a fixed tag. A satisfiable range must lie inside the body, the
 * verdict must not depend on bytes past the input, and nothing may crash. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "http_hdr.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const uint64_t lens[] = { 0, 1, 2, 500, 10000, 7011751, UINT64_MAX };
    /* A copy with no slack after it, so ASan sees any read past size. */
    char *v = malloc(size ? size : 1);
    if (!v) {
        return 0;
    }
    memcpy(v, data, size);
    for (size_t i = 0; i < sizeof lens / sizeof lens[0]; i++) {
        uint64_t a, b;
        http_hdr_range_kind k = http_hdr_range(v, size, lens[i], &a, &b);
        if (k == HTTP_HDR_RANGE_ONE) {
            if (!(a <= b && b < lens[i])) {
                abort();
            }
        } else if (a || b) {
            abort();
        } else if (k != HTTP_HDR_RANGE_NONE && k != HTTP_HDR_RANGE_MULTI &&
                   k != HTTP_HDR_RANGE_UNSATISFIABLE) {
            abort();
        }
    }
    bool weak = http_hdr_etag_match(v, size, "00000000000000aa", true);
    bool strong = http_hdr_etag_match(v, size, "00000000000000aa", false);
    if (strong && !weak) {
        abort(); /* a strong match is also a weak one */
    }
    free(v);
    return 0;
}
