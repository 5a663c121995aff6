/* gale-bench-client render: frame time of gale_render, headless (EGL, else hidden window). Default:
 * a small forest for llvmpipe; --trees 4000 --nodes 3500 --size 1920x1080 is the paper's
 * scene (Diener 2008 section 6) for a real GPU. Prints JSON with the median. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <epoxy/gl.h>

#include "mono.h"
#include "render.h"
#include "render_demo.h"

int bench_render(int argc, char **argv);

static int cmp_d(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int bench_render(int argc, char **argv)
{
    uint32_t trees = 64, nodes = 200, modes = 16, frames = 20, falling = 500;
    int w = 960, h = 540;
    float spacing = 9.0f;
    float storm_ms = 0.0f; /* sustained wind of the storm look (storm_fx.h); 0 = calm */
    storm_fx_quality storm_q = STORM_FX_LOW;
    float damage = 0.0f; /* fraction of trees with broken branches (render_set_broken) */
    bool all_fx = false; /* --storm-fx all: off, low, high in turn, frame by frame */
    for (int i = 1; i < argc; i++) {
        const char *v = i + 1 < argc ? argv[i + 1] : "";
        if (!strcmp(argv[i], "--trees")) {
            trees = (uint32_t)strtoul(v, NULL, 10);
        } else if (!strcmp(argv[i], "--nodes")) {
            nodes = (uint32_t)strtoul(v, NULL, 10);
        } else if (!strcmp(argv[i], "--modes")) {
            modes = (uint32_t)strtoul(v, NULL, 10);
        } else if (!strcmp(argv[i], "--frames")) {
            frames = (uint32_t)strtoul(v, NULL, 10);
        } else if (!strcmp(argv[i], "--falling")) {
            falling = (uint32_t)strtoul(v, NULL, 10);
        } else if (!strcmp(argv[i], "--spacing")) {
            spacing = strtof(v, NULL);
        } else if (!strcmp(argv[i], "--storm")) {
            storm_ms = strtof(v, NULL);
        } else if (!strcmp(argv[i], "--storm-fx")) {
            all_fx = !strcmp(v, "all");
            if (!all_fx && storm_fx_quality_parse(v, &storm_q) != 0) {
                fprintf(stderr, "gale-bench-client render: --storm-fx: expected off, low, "
                                "high or all, got \"%s\"\n",
                        v);
                return 2;
            }
        } else if (!strcmp(argv[i], "--damage")) {
            damage = strtof(v, NULL);
        } else if (!strcmp(argv[i], "--size")) {
            if (sscanf(v, "%dx%d", &w, &h) != 2) {
                w = 0;
            }
        } else {
            bool help = !strcmp(argv[i], "--help") || !strcmp(argv[i], "-h");
            fprintf(help ? stdout : stderr,
                    "usage: gale-bench-client render [--trees N] [--nodes N] [--modes N] "
                    "[--size WxH] [--frames N] [--falling N] [--spacing M] [--storm M/S] "
                    "[--storm-fx off|low|high|all] [--damage F]\n"
                    "  --storm-fx all: the three levels in turn, frame by frame, each level's "
                    "figures\n  in \"storm_fx_levels\" (the top-level ones: low)\n"
                    "  --damage F: a fraction F of the trees lose 3 branches each, every 20th lies\n"
                    "  fallen, and 64 pieces fly as debris\n");
            return help ? 0 : 2;
        }
        i++;
    }
    if (trees == 0 || frames == 0 || w <= 0 || modes < 2 || modes > 64) {
        fprintf(stderr, "gale-bench-client render: bad arguments\n");
        return 2;
    }
    gale_err err = { 0 };
    render *r = render_create(&(render_desc){ .width = w, .height = h, .headless = true,
                                              .max_trees = trees,
                                              .max_falling = falling + 1 }, &err);
    if (!r) {
        fprintf(stderr, "gale-bench-client render: %s\n", err.msg);
        return 1;
    }
    asset a[2];
    int nsp = 2;
    for (int s = 0; s < nsp; s++) {
        if (render_demo_asset(&a[s], &(render_demo_desc){ .n_nodes = nodes, .n_modes = modes,
                                     .leaf_shape = (uint32_t)s * 2, .seed = (uint32_t)s + 3 },
                              &err) < 0 ||
            render_add_species(r, &a[s], &err) < 0) {
            fprintf(stderr, "gale-bench-client render: %s\n", err.msg);
            render_destroy(r);
            return 1;
        }
    }
    render_instance *inst = calloc(trees, sizeof *inst);
    render_demo_forest(inst, trees, (uint32_t)nsp, spacing, 11);
    if (render_set_instances(r, trees, inst, &err) < 0) {
        fprintf(stderr, "gale-bench-client render: %s\n", err.msg);
        return 1;
    }
    for (uint32_t k = 0; k < falling; k++) {
        uint32_t t = (k * 2654435761u) % trees;
        render_add_falling_leaf(r, &(render_leaf_seed){ .tree = t, .slot = k % a[inst[t].species].n_leaves,
                                                        .spawn_time_s = 0.01 * k, .seed = k },
                                &err);
    }
    render_set_wind(r, &(render_wind){ .uniform = { 12.0f, 3.0f, 0.0f } }, &err);
    uint32_t n_broken = 0, n_debris = 0;
    if (damage > 0.0f) {
        uint64_t *keys = calloc((size_t)trees * 3 + 1, sizeof *keys);
        render_debris deb[RENDER_MAX_DEBRIS];
        for (uint32_t t = 0; keys && t < trees; t++) {
            if ((float)((t * 2654435761u) % 1000u) >= 1000.0f * damage) {
                continue;
            }
            if (t % 20 == 0) {
                render_set_damage(r, t, 1.536f, 0.3f * (float)t, 8);
                render_set_uprooted(r, t, true);
            }
            const uint32_t nn = a[inst[t].species].n_nodes;
            for (uint32_t k = 0; k < 3; k++) { /* three nodes, ascending */
                keys[n_broken++] = (uint64_t)t << 32 | (nn / 4 + k * nn / 4);
            }
            if (n_debris < RENDER_MAX_DEBRIS) {
                deb[n_debris] = (render_debris){ .tree = t, .node = nn / 4,
                                                 .pos = { inst[t].pos[0] + 3.0f, inst[t].pos[1],
                                                          4.0f },
                                                 .yaw = 0.5f, .fall_rad = 1.0f,
                                                 .fall_az_rad = 0.2f * (float)n_debris };
                n_debris++;
            }
        }
        render_trees_commit(r);
        if (!keys || render_set_broken(r, n_broken, keys, &err) < 0 ||
            render_set_debris(r, n_debris, deb, &err) < 0) {
            fprintf(stderr, "gale-bench-client render: --damage: %s\n", keys ? err.msg : "no memory");
            return 1;
        }
        free(keys);
    }
    storm_fx fx, fx_lv[3];
    for (int l = 0; l < 3; l++) {
        storm_fx_from_weather(storm_ms, 250.0f, (storm_fx_quality)l, &fx_lv[l]);
    }
    storm_fx_from_weather(storm_ms, 250.0f, storm_q, &fx);
    render_set_storm(r, &fx);
    const uint32_t n_lv = all_fx ? 3 : 1;
    float ext = spacing * sqrtf((float)trees);
    render_camera cam = { .eye = { 0.0f, -0.5f * ext - 20.0f, 12.0f },
                          .target = { 0.0f, -0.5f * ext + 30.0f, 4.0f } };
    double *ft = calloc(frames, sizeof *ft), *cpu = calloc(frames, sizeof *cpu);
    double *cull = calloc(frames, sizeof *cull); /* the frame at the top level's culling */
    double *ft_lv[3], *cpu_lv[3];
    for (int l = 0; l < 3; l++) {
        ft_lv[l] = calloc(frames, sizeof(double));
        cpu_lv[l] = calloc(frames, sizeof(double));
    }
    uint32_t stride;
    float *q = render_q_staging(r, &stride);
    render_stats st = { 0 };
    /* with all levels: frame f at level f % 3, two warm-up frames of each */
    for (uint32_t f = 0; f < n_lv * (frames + 2); f++) {
        const uint32_t lv = f % n_lv, k = f / n_lv;
        if (all_fx) {
            render_set_storm(r, &fx_lv[lv]);
        }
        double t = 5.0 + k / 60.0;
        for (uint32_t i = 0; i < trees; i++) {
            const float wl[3] = { 12.0f, 3.0f, 0.0f };
            render_demo_pose(&a[inst[i].species], wl, (float)t, i, &q[(size_t)i * stride]);
        }
        double t0 = mono_s();
        if (render_frame(r, &cam, t, &err) < 0) {
            fprintf(stderr, "gale-bench-client render: %s\n", err.msg);
            return 1;
        }
        double t1 = mono_s();
        glFinish();
        double t2 = mono_s();
        if (k >= 2) {
            cpu_lv[lv][k - 2] = 1e3 * (t1 - t0);
            ft_lv[lv][k - 2] = 1e3 * (t2 - t0);
        }
        st = render_get_stats(r);
        if (k >= 2 && lv == (all_fx ? (uint32_t)STORM_FX_LOW : 0u)) {
            cull[k - 2] = st.cull_ms;
        }
    }
    for (uint32_t l = 0; l < n_lv; l++) {
        qsort(ft_lv[l], frames, sizeof(double), cmp_d);
        qsort(cpu_lv[l], frames, sizeof(double), cmp_d);
    }
    qsort(cull, frames, sizeof(double), cmp_d);
    const uint32_t top = all_fx ? (uint32_t)STORM_FX_LOW : 0;
    memcpy(ft, ft_lv[top], sizeof(double) * frames);
    memcpy(cpu, cpu_lv[top], sizeof(double) * frames);
    if (all_fx) {
        fx = fx_lv[STORM_FX_LOW];
    }
    const char *rend = (const char *)glGetString(GL_RENDERER);
    double la[3] = { 0 };
    FILE *lf = fopen("/proc/loadavg", "r");
    if (lf) {
        if (fscanf(lf, "%lf %lf %lf", &la[0], &la[1], &la[2]) != 3) {
            la[0] = la[1] = la[2] = 0.0;
        }
        fclose(lf);
    }
    printf("{\"bench\":\"render\",\"renderer\":\"%s\",\"trees\":%u,\"nodes\":%u,\"modes\":%u,"
           "\"size\":\"%dx%d\",\"frames\":%u,\"frame_ms_median\":%.3f,\"frame_ms_min\":%.3f,"
           "\"frame_ms_max\":%.3f,\"fps_median\":%.1f,\"cpu_submit_ms_median\":%.3f,"
           "\"trees_full\":%u,\"trees_thin\":%u,\"trees_billboard\":%u,\"culled\":%u,"
           "\"draw_calls\":%u,\"triangles\":%llu,\"cull_ms_median\":%.3f,\"lod_scale\":%.3f,"
           "\"leaves_drawn\":%llu,\"falling\":%u,\"storm_ms\":%.1f,\"rain_layers\":%d,"
           "\"broken_branches\":%u,\"debris\":%u,"
           "\"loadavg\":[%.2f,%.2f,%.2f]",
           rend ? rend : "?", trees, a[0].n_nodes, modes, w, h, frames, ft[frames / 2], ft[0],
           ft[frames - 1], 1e3 / ft[frames / 2], cpu[frames / 2], st.trees_full, st.trees_thin,
           st.trees_billboard, st.trees_culled, st.draw_calls,
           (unsigned long long)st.triangles, cull[frames / 2], (double)st.lod_scale,
           (unsigned long long)st.leaves_drawn, st.falling_live, (double)storm_ms,
           fx.rain_layers, n_broken, n_debris, la[0], la[1], la[2]);
    if (all_fx) {
        static const char *const lv_name[3] = { "off", "low", "high" };
        printf(",\"storm_fx_levels\":{");
        for (int l = 0; l < 3; l++) {
            const double med = ft_lv[l][frames / 2];
            printf("%s\"%s\":{\"frame_ms_median\":%.3f,\"frame_ms_p95\":%.3f,"
                   "\"fps_median\":%.2f,\"cpu_submit_ms_median\":%.3f,\"rain_layers\":%d,"
                   "\"of_off\":%.3f}",
                   l ? "," : "", lv_name[l], med, ft_lv[l][(frames * 95) / 100], 1e3 / med,
                   cpu_lv[l][frames / 2], fx_lv[l].rain_layers,
                   ft_lv[0][frames / 2] > 0.0 ? med / ft_lv[0][frames / 2] : 0.0);
        }
        printf("}");
    }
    printf("}\n");
    for (int l = 0; l < 3; l++) {
        free(ft_lv[l]);
        free(cpu_lv[l]);
    }
    free(ft);
    free(cull);
    free(cpu);
    free(inst);
    for (int s = 0; s < nsp; s++) {
        render_demo_free(&a[s]);
    }
    render_destroy(r);
    return 0;
}
