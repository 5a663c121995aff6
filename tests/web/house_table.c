/* gale-client's house meshes (client/render/render_house.c) for a few boxes, one JSON object a
 * line ({"box": [...], "mesh": [...]}), for tests/web/test_house_js.mjs to hold
 * web/house.js to. */
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "render_house.h"

int main(int argc, char **argv)
{
    if (argc > 1) {
        bool help = strcmp(argv[1], "--help") == 0;
        fprintf(help ? stdout : stderr, "usage: gale-web-house-table\n"
                                        "  prints the house mesh of a few boxes, JSON lines\n");
        return help ? 0 : 2;
    }
    /* long in x, long in y, a flat slab (pitch capped), a square, a degenerate one */
    static const float boxes[][6] = {
        { 20.0f, -4.0f, 0.0f, 28.0f, 4.0f, 6.5f },   { -30.5f, 10.0f, 0.2f, -22.0f, 31.0f, 9.0f },
        { 0.0f, 0.0f, 0.0f, 40.0f, 1.0f, 12.0f },    { 5.0f, 5.0f, -1.0f, 15.0f, 15.0f, 7.0f },
        { 3.0f, 3.0f, 0.0f, 3.0f, 3.0f, 0.0f },
    };
    float mesh[RENDER_HOUSE_VERTS * RENDER_HOUSE_FLOATS];
    for (size_t i = 0; i < sizeof boxes / sizeof boxes[0]; i++) {
        float *end = render_house_mesh(boxes[i], mesh);
        printf("{\"box\":[");
        for (int k = 0; k < 6; k++) {
            printf("%s%.9g", k ? "," : "", (double)boxes[i][k]);
        }
        printf("],\"mesh\":[");
        for (long k = 0; k < end - mesh; k++) {
            printf("%s%.9g", k ? "," : "", (double)mesh[k]);
        }
        printf("]}\n");
    }
    return 0;
}
