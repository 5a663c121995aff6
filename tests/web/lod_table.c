/* gale-client's level-of-detail policy (client/render/lod_policy.h) as one JSON object, for
 * tests/web/test_lod_policy_js.mjs to hold web/lod_policy.js to: every number, the leaves
 * drawn at each level for a range of leaf counts (render_leaves_at), the fog distance of a
 * few scenes' boxes, the level render_lod_pick gives a standing tree at distances
 * outside the fade bands, and a few falls' impostor codes (render_bill_fall_code). */
#include <stdio.h>
#include <string.h>

#include "lod_policy.h"
#include "render_cull.h"

static void floats(const char *name, const float *v, int n)
{
    printf("\"%s\":[", name);
    for (int i = 0; i < n; i++) {
        printf("%s%.9g", i ? "," : "", (double)v[i]);
    }
    printf("],");
}

int main(int argc, char **argv)
{
    if (argc > 1) {
        printf("usage: gale-web-lod-table (prints the policy as JSON)\n");
        return strcmp(argv[1], "--help") == 0 ? 0 : 2;
    }
    printf("{\"LOD\":{\"FULL\":%d,\"THIN\":%d,\"IMPOSTOR\":%d},\"LOD_LEVELS\":%d,", LOD_FULL,
           LOD_THIN, LOD_IMPOSTOR, LOD_LEVELS);
    floats("LOD_OUTER_M", lod_outer_m, LOD_LEVELS);
    floats("LOD_LEAF_SHARE", lod_leaf_share, LOD_LEVELS);
    floats("LOD_LEAF_GROW", lod_leaf_grow, LOD_LEVELS);
    printf("\"LOD_BARK\":[%s,%s,%s],\"LOD_MODES_MAX\":[%d,%d,%d],", lod_bark[0] ? "true" : "false",
           lod_bark[1] ? "true" : "false", lod_bark[2] ? "true" : "false", lod_modes_max[0],
           lod_modes_max[1], lod_modes_max[2]);
    printf("\"LOD_IMPOSTOR_MODES\":%d,\"LOD_FADE_SHARE\":%.9g,\"LOD_HYSTERESIS\":%.9g,"
           "\"LOD_MESH_STEP_M\":%.9g,\"LOD_BUDGET_TRIANGLES\":%d,\"LOD_BUDGET_NODES\":%d,"
           "\"LOD_BUDGET_DRAWS\":%d,\"LOD_FELLED_TRIANGLES\":%u,\"LOD_GROW_PER_FRAME\":%.9g,\"VIEW_FAR_M\":%.9g,"
           "\"VIEW_LOD_M\":%.9g,\"FOG_MIN_M\":%.9g,\"FOG_PER_SCENE_RADIUS_M\":%.9g,",
           LOD_IMPOSTOR_MODES, (double)LOD_FADE_SHARE, (double)LOD_HYSTERESIS,
           (double)LOD_MESH_STEP_M, LOD_BUDGET_TRIANGLES, LOD_BUDGET_NODES, LOD_BUDGET_DRAWS,
           RENDER_FELLED_TRIS_MAX,
           (double)LOD_GROW_PER_FRAME, (double)VIEW_FAR_M, (double)VIEW_LOD_M,
           (double)FOG_MIN_M, (double)FOG_PER_SCENE_RADIUS_M);
    printf("\"leaves_at\":[");
    static const uint32_t counts[] = { 0, 1, 2, 3, 5, 7, 10, 333, 1000, 4097, 5312 };
    for (size_t i = 0; i < sizeof counts / sizeof counts[0]; i++) {
        printf("%s[%u", i ? "," : "", counts[i]);
        for (int l = 0; l < LOD_LEVELS; l++) {
            printf(",%u", render_leaves_at(counts[i], lod_leaf_share[l]));
        }
        printf("]");
    }
    printf("],\"fog\":[");
    static const float boxes[][4] = { { 0, 0, 10, 10 },          { -60, -40, 60, 40 },
                                      { -300, -300, 300, 300 },  { -1000, -1000, 1000, 1000 },
                                      { 5, -2000, 25, 2000 } };
    for (size_t i = 0; i < sizeof boxes / sizeof boxes[0]; i++) {
        const float *b = boxes[i];
        printf("%s[%.9g,%.9g,%.9g,%.9g,%.9g]", i ? "," : "", (double)b[0], (double)b[1],
               (double)b[2], (double)b[3], (double)fog_for_scene(&b[0], &b[2]));
    }
    printf("],\"levels\":[");
    const render_cull_species sp = { .height_m = 10.0f, .crown_r_m = 3.0f, .n_modes = 16,
                                     .n_lods = 3 };
    const render_lod_desc d = { .mode_dist_m = 40.0f, .scale = 1.0f };
    static const float dist[] = { 1, 30, 60, 71, 95, 150, 199, 260, 1000, 3999, 4100 };
    for (size_t i = 0; i < sizeof dist / sizeof dist[0]; i++) {
        render_tree_lod t = render_lod_pick(dist[i], &sp, &d, false);
        printf("%s[%.9g,%d]", i ? "," : "", (double)dist[i], t.flags ? (int)t.level : 255);
    }
    printf("],\"bill_fall\":[");
    static const float falls[][2] = { { 0.0f, 1.0f },       { 1.5707963f, 0.0f },
                                      { 0.3f, 1.87f },      { 1.2f, -0.4f },
                                      { 2.9f, 3.1f },       { 1e-4f, 6.2830f },
                                      { 0.7f, -6.2f },      { 1.536f, 4.71238898f },
                                      { 0.01f, 0.0122718f } };
    for (size_t i = 0; i < sizeof falls / sizeof falls[0]; i++) {
        printf("%s[%.9g,%.9g,%.9g]", i ? "," : "", (double)falls[i][0], (double)falls[i][1],
               (double)render_bill_fall_code(falls[i][0], falls[i][1]));
    }
    printf("]}\n");
    return 0;
}
