/* The relay link's gale.scene message (server/relay/link.h, server/SERVER.md "Relays"):
 * encoded and decoded back field for field; a truncated, padded or out-of-range message
 * is refused with the message's length in the error. */
#include "check.h"
#include "link.h"

#include <stdlib.h>
#include <string.h>

static void test_scene_round_trip(void)
{
    float pos[9] = { -1.5f, 2.0f, 0.25f, 100.0f, -200.0f, 3.0f, 0.0f, 0.0f, -0.5f };
    link_scene in = { .n_trees = 3,
                      .lod_modes = 4,
                      .key_every = 150,
                      .max_modes = 32,
                      .margin_m = 18.5f,
                      .cell_m = 32.0f,
                      .pos = pos };
    size_t n = link_scene_size(in.n_trees);
    CHECK(n == 8 + 16 + 8 + 3 * 12);
    uint8_t *buf = malloc(n);
    link_scene_encode(&in, buf);
    CHECK(link_scene_total(buf, n) == n);
    CHECK(link_scene_total(buf, 7) == 0);
    link_scene out;
    gale_err e;
    CHECK(link_scene_decode(buf, n, &out, &e) == 0);
    CHECK(out.n_trees == 3 && out.lod_modes == 4 && out.key_every == 150 && out.max_modes == 32 &&
          out.margin_m == 18.5f && out.cell_m == 32.0f);
    CHECK(out.pos && !memcmp(out.pos, pos, sizeof pos));
    free(out.pos);
    free(buf);
}

static void test_scene_refused(void)
{
    float pos[3] = { 0 };
    link_scene in = { .n_trees = 1,
                      .lod_modes = 4,
                      .key_every = 150,
                      .max_modes = 8,
                      .margin_m = 10.0f,
                      .cell_m = 32.0f,
                      .pos = pos };
    size_t n = link_scene_size(1);
    uint8_t *buf = calloc(1, n + 1);
    link_scene_encode(&in, buf);
    link_scene out;
    gale_err e;
    CHECK(link_scene_decode(buf, n - 1, &out, &e) == GALE_E_FORMAT && !out.pos);
    CHECK_STR_HAS(e.msg, "link: scene: malformed message of 43 bytes");
    CHECK(link_scene_decode(buf, n + 1, &out, &e) == GALE_E_FORMAT);
    in.lod_modes = 0;
    link_scene_encode(&in, buf);
    CHECK(link_scene_decode(buf, n, &out, &e) == GALE_E_FORMAT);
    in.lod_modes = 4;
    in.cell_m = 0.0f;
    link_scene_encode(&in, buf);
    CHECK(link_scene_decode(buf, n, &out, &e) == GALE_E_FORMAT);
    free(buf);
}

int main(void)
{
    RUN(test_scene_round_trip);
    RUN(test_scene_refused);
    return check_report();
}
