/* gale-render: renders a forest of demo species (or baked assets) posed by a uniform wind
 * to a PNG, offscreen (EGL, else a hidden window under Xvfb). For tests, pictures and
 * quick looks. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "damage_cut.h"
#include "debris_path.h"
#include "render.h"
#include "render_demo.h"
#include "tip_fall.h"


static void usage(FILE *f)
{
    fprintf(f,
            "usage: gale-render --out FILE.png [--size WxH] [--trees N] [--species 1..3]\n"
            "       [--nodes N] [--modes N] [--spacing M] [--wind X,Y,Z] [--time S]\n"
            "       [--falling N] [--eye X,Y,Z] [--target X,Y,Z] [--asset FILE]...\n"
            "       [--q Q0,Q1,...]   (the same modal vector for every tree instead of --wind)\n"
            "       [--box X0,Y0,Z0,X1,Y1,Z1]...   (a house filling that box, up to 16)\n"
            "       [--storm-age S]   (storm damage S seconds after it struck: every third\n"
            "                          tree tipping over (half uprooted, half snapped above\n"
            "                          a stump), branches flying off as debris in\n"
            "                          --wind, crowns thinned to half)\n"
            "       -h, --help: this text\n");
}

static int parse3(const char *s, float v[3])
{
    return sscanf(s, "%f,%f,%f", &v[0], &v[1], &v[2]) == 3 ? 0 : -1;
}

static int load_file(const char *path, asset *a, gale_err *err)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        return gale_errf(err, GALE_E_IO, "%s: cannot open", path);
    }
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    uint8_t *buf = n > 0 ? malloc((size_t)n) : NULL;
    if (!buf || fread(buf, 1, (size_t)n, f) != (size_t)n) {
        fclose(f);
        free(buf);
        return gale_errf(err, GALE_E_IO, "%s: cannot read", path);
    }
    fclose(f);
    int rc = asset_decode(buf, (size_t)n, path, a, err);
    free(buf);
    return rc;
}

static void uniform_wind(void *user, const float p[3], float out[3])
{
    (void)p;
    const float *w = user;
    out[0] = w[0];
    out[1] = w[1];
    out[2] = w[2];
}

/* --storm-age: what gale-client draws age_s seconds after a storm struck this forest
 * (client/app/client_damage.c): falls in tip_fall's closed form, branches as debris_path
 * pieces. Which tree and branch fail is a fixed hash, not a model. */
static int storm_damage(render *r, const asset *as, const render_instance *inst, uint32_t trees,
                        const float wind[3], float age_s, gale_err *err)
{
    uint64_t keys[3 * 32];
    render_debris deb[RENDER_MAX_DEBRIS];
    uint32_t nk = 0, nd = 0;
    for (uint32_t t = 0; t < trees && t < 32; t++) {
        const asset *a = &as[inst[t].species];
        /* every third tree falls: half of those snap (the stem above the stump tips),
           half uproot (the whole stem tips) */
        const bool falls = t % 3 == 1, snaps = t % 6 == 4;
        const float sc = inst[t].scale > 0.0f ? inst[t].scale : 1.0f;
        const float pole_m = render_tree_height_m(r, t) - (snaps ? sc * tip_fall_break_m(t) : 0.0f);
        float fall = falls ? (float)tip_fall_angle(age_s, pole_m) : 0.0f;
        float az = 0.8f + 0.3f * (float)t;
        render_set_damage(r, t, fall, az, 16);
        render_set_uprooted(r, t, falls && !snaps);
        if (t % 3 == 1) {
            continue; /* a falling tree keeps its branches here */
        }
        uint8_t *m = malloc(a->n_nodes);
        uint32_t picked = 0;
        for (uint32_t k = 0; m && k < a->n_nodes && picked < 3; k++) {
            uint32_t b = (uint32_t)((k * 2654435761u + t * 40503u) % a->n_nodes);
            damage_cut_mask(a->parent, a->n_nodes, &b, 1, true, m);
            uint32_t n = 0;
            for (uint32_t i = 0; i < a->n_nodes; i++) {
                n += m[i];
            }
            if (b == 0 || n * 33 < a->n_nodes || n * 8 > a->n_nodes) {
                continue;
            }
            bool inside = false; /* not within a piece already taken */
            for (uint32_t j = 0; j < picked; j++) {
                uint32_t o = (uint32_t)keys[nk - 1 - j];
                for (int32_t x = (int32_t)b; x >= 0; x = a->parent[x]) {
                    inside |= (uint32_t)x == o;
                }
                for (int32_t x = (int32_t)o; x >= 0; x = a->parent[x]) {
                    inside |= (uint32_t)x == b;
                }
            }
            if (inside) {
                continue;
            }
            keys[nk++] = (uint64_t)t << 32 | b;
            picked++;
            float centre[3], axis[3], ext, r0[9], c0[3], rot[9];
            if (nd == RENDER_MAX_DEBRIS ||
                render_piece_shape(r, t, b, centre, axis, &ext, err) != 0) {
                continue;
            }
            debris_frame_matrix(inst[t].yaw, 0.0f, 0.0f, r0);
            for (int i = 0; i < 3; i++) {
                c0[i] = inst[t].pos[i] + sc * (r0[i] * centre[0] + r0[3 + i] * centre[1] +
                                               r0[6 + i] * centre[2]);
            }
            debris_path p;
            debris_path_start(&p, t, b, 0.0, c0, r0, axis, ext * sc);
            debris_path_advance(&p, age_s, uniform_wind, (void *)wind);
            debris_path_rotation(&p, rot);
            render_debris *d = &deb[nd++];
            d->tree = t;
            d->node = b;
            for (int i = 0; i < 3; i++) {
                d->pos[i] = p.c[i] - sc * (rot[i] * centre[0] + rot[3 + i] * centre[1] +
                                           rot[6 + i] * centre[2]);
            }
            d->pos[2] -= debris_path_sink_m(&p);
            debris_frame_angles(rot, &d->yaw, &d->fall_rad, &d->fall_az_rad);
        }
        free(m);
    }
    render_trees_commit(r);
    /* keys went in tree order, nodes in pick order: sort each tree's few */
    for (uint32_t i = 1; i < nk; i++) {
        for (uint32_t j = i; j > 0 && keys[j] < keys[j - 1]; j--) {
            uint64_t x = keys[j];
            keys[j] = keys[j - 1];
            keys[j - 1] = x;
        }
    }
    int rc = render_set_broken(r, nk, keys, err);
    return rc ? rc : render_set_debris(r, nd, deb, err);
}

int main(int argc, char **argv)
{
    const char *out = NULL, *files[8];
    int nfiles = 0, w = 960, h = 540;
    uint32_t trees = 1, nspecies = 1, nodes = 60, modes = 8, falling = 0;
    float spacing = 9.0f, wind[3] = { 0, 0, 0 }, time_s = 0.0f;
    float eye[3] = { 0, -22, 6 }, target[3] = { 0, 0, 4.5f };
    bool eye_set = false;
    float qfix[64] = { 0 };
    int nqfix = -1;
    float boxes[16 * 6];
    uint32_t nboxes = 0;
    float storm_age = -1.0f;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        int bad = 0;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            usage(stdout);
            return 0;
        } else if (!v) {
            bad = 1;
        } else if (!strcmp(a, "--out")) {
            out = v;
        } else if (!strcmp(a, "--size")) {
            bad = sscanf(v, "%dx%d", &w, &h) != 2;
        } else if (!strcmp(a, "--trees")) {
            trees = (uint32_t)strtoul(v, NULL, 10);
        } else if (!strcmp(a, "--species")) {
            nspecies = (uint32_t)strtoul(v, NULL, 10);
            bad = nspecies < 1 || nspecies > 3;
        } else if (!strcmp(a, "--nodes")) {
            nodes = (uint32_t)strtoul(v, NULL, 10);
        } else if (!strcmp(a, "--modes")) {
            modes = (uint32_t)strtoul(v, NULL, 10);
        } else if (!strcmp(a, "--spacing")) {
            spacing = strtof(v, NULL);
        } else if (!strcmp(a, "--wind")) {
            bad = parse3(v, wind);
        } else if (!strcmp(a, "--time")) {
            time_s = strtof(v, NULL);
        } else if (!strcmp(a, "--falling")) {
            falling = (uint32_t)strtoul(v, NULL, 10);
        } else if (!strcmp(a, "--eye")) {
            bad = parse3(v, eye);
            eye_set = true;
        } else if (!strcmp(a, "--target")) {
            bad = parse3(v, target);
        } else if (!strcmp(a, "--q")) {
            nqfix = 0;
            for (const char *p = v; *p && nqfix < 64;) {
                char *end;
                qfix[nqfix++] = strtof(p, &end);
                bad |= end == p || !isfinite(qfix[nqfix - 1]);
                if (bad) {
                    break;
                }
                p = *end == ',' ? end + 1 : end;
            }
        } else if (!strcmp(a, "--box") && nboxes < 16) {
            float *b = &boxes[6 * nboxes++];
            bad = sscanf(v, "%f,%f,%f,%f,%f,%f", &b[0], &b[1], &b[2], &b[3], &b[4], &b[5]) != 6;
        } else if (!strcmp(a, "--storm-age")) {
            storm_age = strtof(v, NULL);
            bad = !(storm_age >= 0.0f && storm_age < 1e6f);
        } else if (!strcmp(a, "--asset") && nfiles < 8) {
            files[nfiles++] = v;
        } else {
            bad = 1;
        }
        if (bad) {
            fprintf(stderr, "gale-render: bad option %s %s\n", a, v ? v : "(missing value)");
            usage(stderr);
            return 2;
        }
        i++;
    }
    if (!out || trees == 0) {
        usage(stderr);
        return 2;
    }
    if (!eye_set && trees > 1) {
        float ext = spacing * sqrtf((float)trees);
        eye[1] = -0.5f * ext - 25.0f;
        eye[2] = 9.0f;
        target[1] = -0.5f * ext + 10.0f;
    }
    gale_err err = { 0 };
    render *r = render_create(&(render_desc){ .width = w, .height = h, .headless = true,
                                              .max_trees = trees, .max_falling = falling + 1 },
                              &err);
    if (!r) {
        fprintf(stderr, "gale-render: %s\n", err.msg);
        return 1;
    }
    asset as[8];
    int nas = nfiles ? nfiles : (int)nspecies;
    memset(as, 0, sizeof as);
    for (int s = 0; s < nas; s++) {
        int rc = nfiles ? load_file(files[s], &as[s], &err)
                        : render_demo_asset(&as[s], &(render_demo_desc){ .n_nodes = nodes,
                                                   .n_modes = modes, .leaf_shape = (uint32_t)s,
                                                   .seed = (uint32_t)s + 1 }, &err);
        if (rc < 0 || render_add_species(r, &as[s], &err) < 0) {
            fprintf(stderr, "gale-render: %s\n", err.msg);
            render_destroy(r);
            return 1;
        }
    }
    render_instance *inst = calloc(trees, sizeof *inst);
    render_demo_forest(inst, trees, (uint32_t)nas, spacing, 7);
    if (trees == 1) {
        inst[0].yaw = 0.0f;
        inst[0].scale = 1.0f;
        inst[0].pos[0] = inst[0].pos[1] = 0.0f;
    }
    int rc = render_set_instances(r, trees, inst, &err);
    float q[64];
    for (uint32_t t = 0; rc == 0 && t < trees; t++) {
        const asset *a = &as[inst[t].species];
        float c = cosf(inst[t].yaw), s = sinf(inst[t].yaw);
        float wl[3] = { c * wind[0] + s * wind[1], -s * wind[0] + c * wind[1], wind[2] };
        render_demo_pose(a, wl, time_s, t, q);
        if (nqfix >= 0) {
            for (uint32_t m = 0; m < a->n_modes; m++) {
                q[m] = (int)m < nqfix ? qfix[m] : 0.0f;
            }
        }
        rc = render_set_q(r, t, q, a->n_modes, &err);
    }
    if (rc == 0) {
        rc = render_set_wind(r, &(render_wind){ .uniform = { wind[0], wind[1], wind[2] } },
                             &err);
    }
    if (rc == 0) {
        rc = render_set_obstacles(r, nboxes, boxes, &err);
    }
    for (uint32_t k = 0; rc == 0 && k < falling; k++) {
        uint32_t t = k % trees;
        const asset *a = &as[inst[t].species];
        render_leaf_seed ls = { .tree = t, .slot = (k * 7919u) % a->n_leaves,
                                .spawn_time_s = (double)time_s * k / falling, .seed = k + 1 };
        rc = render_add_falling_leaf(r, &ls, &err);
    }
    if (rc == 0 && storm_age >= 0.0f) {
        rc = storm_damage(r, as, inst, trees, wind, storm_age, &err);
    }
    render_camera cam = { .eye = { eye[0], eye[1], eye[2] },
                          .target = { target[0], target[1], target[2] } };
    if (rc == 0) {
        rc = render_frame(r, &cam, time_s, &err);
    }
    if (rc == 0) {
        rc = render_write_png(r, out, &err);
    }
    if (rc < 0) {
        fprintf(stderr, "gale-render: %s\n", err.msg);
    } else {
        render_stats st = render_get_stats(r);
        printf("{\"out\":\"%s\",\"trees_full\":%u,\"trees_billboard\":%u,\"culled\":%u,"
               "\"draw_calls\":%u,\"falling\":%u}\n", out, st.trees_full, st.trees_billboard,
               st.trees_culled, st.draw_calls, st.falling_live);
    }
    for (int s = 0; s < nas; s++) {
        if (nfiles) {
            asset_fini(&as[s]);
        } else if (!nfiles) {
            render_demo_free(&as[s]);
        }
    }
    free(inst);
    render_destroy(r);
    return rc < 0 ? 1 : 0;
}
