/* Fuzz target for skeleton_parse_csv: any bytes either parse into a skeleton that keeps
 * its invariants (parents first, root at the origin, radii > 0) or fail with a message. */
#include <stdint.h>
#include <stdlib.h>

#include "skeleton.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    skeleton s;
    gale_err err = { 0 };
    int rc = skeleton_parse_csv((const char *)data, size, "fuzz.csv", &s, &err);
    if (rc == 0) {
        if (s.n < 1 || s.parent[0] != -1 || s.pos[0] != 0.0f || s.pos[1] != 0.0f ||
            s.pos[2] != 0.0f) {
            abort();
        }
        for (int i = 1; i < s.n; i++) {
            if (s.parent[i] < 0 || s.parent[i] >= i || !(s.radius[i] > 0.0f)) {
                abort();
            }
        }
    } else if (err.msg[0] == '\0' || s.n != 0) {
        abort();
    }
    skeleton_fini(&s);
    return 0;
}
