/* Fuzz target: scene configs. Any bytes must either parse into a bounded scene or fail
 * with a message; never crash, leak or read out of bounds. Forest counts are capped so
 * that one input stays fast. */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > 1 << 16) {
        return 0;
    }
    scene s;
    gale_err e;
    if (scene_parse(&s, "fuzz.json", (const char *)data, size, "/tmp", &e) == 0) {
        if (s.n_trees < 1 || s.n_trees > SCENE_MAX_TREES || s.n_species < 1) {
            __builtin_trap();
        }
        for (int i = 0; i < s.n_trees; i++) {
            if (s.trees[i].species < 0 || s.trees[i].species >= s.n_species) {
                __builtin_trap();
            }
        }
        scene_fini(&s);
    } else if (!e.msg[0]) {
        __builtin_trap();
    }
    return 0;
}
