/* gale-skelshot: side (x-z) and top (x-y) views of a species' generated skeleton or of
 * an imported CSV skeleton, as a PNG, so a species can be looked at while it is tuned.
 * Elements are drawn with their radius, coloured by branch order; leaf slots as dots. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "asset.h"
#include "mesh.h"
#include "plot.h"
#include "skeleton.h"
#include "species.h"

static void usage(FILE *f)
{
    fprintf(f, "usage: gale-skelshot (--species FILE.json | --skeleton FILE.csv) --out FILE.png\n"
               "                     [--nodes N] [--size PX]\n"
               "  --species FILE   generate the skeleton from a species file\n"
               "  --skeleton FILE  read a skeleton CSV (id,parent,x,y,z,radius)\n"
               "  --out FILE       PNG to write: side view, top view, tube mesh (LOD 0, 1, 2)\n"
               "  --nodes N        generate about N nodes (species only; overrides target_nodes)\n"
               "  --size PX        height of each view in pixels (default 600)\n"
               "  --help           this text\n");
}

typedef struct view {
    float ox, oy; /* pixel origin of the view */
    float scale;  /* px per metre */
    float cx, cy; /* world centre on the two view axes */
    int ax, ay;   /* world axes drawn right and up */
} view;

static void to_px(const view *v, const float *p, float *x, float *y)
{
    *x = v->ox + (p[v->ax] - v->cx) * v->scale;
    *y = v->oy - (p[v->ay] - v->cy) * v->scale;
}

static void draw_view(plot *pl, const view *v, const skeleton *s, const asset *leaves)
{
    static const uint8_t order_rgb[5][3] = {
        { 90, 60, 40 }, { 120, 85, 55 }, { 150, 110, 70 }, { 170, 130, 90 }, { 190, 150, 110 },
    };
    const uint8_t leaf_rgb[3] = { 60, 140, 50 };
    for (int i = 1; i < s->n; i++) {
        int p = s->parent[i];
        float x0, y0, x1, y1;
        to_px(v, &s->pos[3 * p], &x0, &y0);
        to_px(v, &s->pos[3 * i], &x1, &y1);
        float r = 0.5f * (s->radius[p] + s->radius[i]);
        float w = 2.0f * r * v->scale;
        int o = s->order[i] > 4 ? 4 : s->order[i];
        plot_line(pl, x0, y0, x1, y1, w < 0.6f ? 0.6f : w, order_rgb[o]);
    }
    if (leaves) {
        for (uint32_t l = 0; l < leaves->n_leaves; l++) {
            uint32_t nd = leaves->leaf_node[l];
            float q0[3], q1[3];
            for (int k = 0; k < 3; k++) {
                q0[k] = s->pos[3 * nd + k];
                q1[k] = s->pos[3 * nd + k] + 2.0f * leaves->leaf_offset[3 * l + k];
            }
            float x0, y0, x1, y1;
            to_px(v, q0, &x0, &y0);
            to_px(v, q1, &x1, &y1);
            /* blade width / length: broad leaf, palm leaflet, needle tuft */
            const float aspect = leaves->leaf_shape == 0 ? 0.35f : 0.12f;
            float wpx = aspect * leaves->leaf_size[l] * v->scale;
            plot_line(pl, x0, y0, x1, y1, wpx < 1.0f ? 1.0f : wpx, leaf_rgb);
        }
    }
}

/* Fills a triangle given in pixels (edge functions over its bounding box). */
static void fill_tri(plot *pl, const float *x, const float *y, const uint8_t c[3])
{
    float area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
    if (fabsf(area) < 1e-6f) {
        return;
    }
    int x0 = (int)fmaxf(0.0f, floorf(fminf(x[0], fminf(x[1], x[2]))));
    int x1 = (int)fminf((float)(pl->w - 1), ceilf(fmaxf(x[0], fmaxf(x[1], x[2]))));
    int y0 = (int)fmaxf(0.0f, floorf(fminf(y[0], fminf(y[1], y[2]))));
    int y1 = (int)fminf((float)(pl->h - 1), ceilf(fmaxf(y[0], fmaxf(y[1], y[2]))));
    for (int py = y0; py <= y1; py++) {
        for (int px = x0; px <= x1; px++) {
            float cx = (float)px + 0.5f, cy = (float)py + 0.5f;
            float w0 = (x[2] - x[1]) * (cy - y[1]) - (y[2] - y[1]) * (cx - x[1]);
            float w1 = (x[0] - x[2]) * (cy - y[2]) - (y[0] - y[2]) * (cx - x[2]);
            float w2 = (x[1] - x[0]) * (cy - y[0]) - (y[1] - y[0]) * (cx - x[0]);
            if ((w0 >= 0 && w1 >= 0 && w2 >= 0) || (w0 <= 0 && w1 <= 0 && w2 <= 0)) {
                memcpy(pl->rgb + 3 * ((size_t)py * (size_t)pl->w + (size_t)px), c, 3);
            }
        }
    }
}

typedef struct tri_key {
    float depth;
    uint32_t first;
} tri_key;

static int tri_cmp(const void *a, const void *b)
{
    float p = ((const tri_key *)a)->depth, q = ((const tri_key *)b)->depth;
    return p < q ? 1 : (p > q ? -1 : 0);
}

/* The tube mesh of one LOD in side view, far triangles first, shaded by a light from the
 * upper left; back faces (normal away from the viewer at -y) are skipped. */
static void draw_mesh(plot *pl, const view *v, const asset *a, int lod)
{
    uint32_t first = a->lod_first[lod], count = a->lod_count[lod];
    size_t nt = count / 3;
    tri_key *keys = malloc((nt ? nt : 1) * sizeof *keys);
    if (!keys) {
        return;
    }
    for (size_t t = 0; t < nt; t++) {
        const uint32_t *ix = &a->mesh_index[first + 3 * t];
        keys[t].depth =
            a->mesh_pos[3 * ix[0] + 1] + a->mesh_pos[3 * ix[1] + 1] + a->mesh_pos[3 * ix[2] + 1];
        keys[t].first = first + (uint32_t)(3 * t);
    }
    qsort(keys, nt, sizeof *keys, tri_cmp);
    const float light[3] = { -0.5f, -0.6f, 0.62f };
    for (size_t t = 0; t < nt; t++) {
        const uint32_t *ix = &a->mesh_index[keys[t].first];
        float x[3], y[3], n[3] = { 0, 0, 0 };
        for (int k = 0; k < 3; k++) {
            to_px(v, &a->mesh_pos[3 * ix[k]], &x[k], &y[k]);
            for (int j = 0; j < 3; j++) {
                n[j] += a->mesh_normal[3 * ix[k] + j] / 3.0f;
            }
        }
        if (n[1] > 0.05f) {
            continue;
        }
        float l = n[0] * light[0] + n[1] * light[1] + n[2] * light[2];
        float shade = 0.45f + 0.55f * fmaxf(0.0f, l);
        uint8_t c[3];
        for (int k = 0; k < 3; k++) {
            float b = a->bark_rgb[k] * 255.0f * shade * 1.6f;
            c[k] = (uint8_t)(b > 255.0f ? 255.0f : b);
        }
        fill_tri(pl, x, y, c);
    }
    free(keys);
}

int main(int argc, char **argv)
{
    const char *species_path = NULL, *csv_path = NULL, *out = NULL;
    int nodes = -1, size = 600;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            usage(stdout);
            return 0;
        }
        if (i + 1 >= argc) {
            fprintf(stderr, "gale-skelshot: %s: expected a value after it\n", a);
            usage(stderr);
            return 2;
        }
        const char *val = argv[++i];
        char *end = NULL;
        if (strcmp(a, "--species") == 0) {
            species_path = val;
        } else if (strcmp(a, "--skeleton") == 0) {
            csv_path = val;
        } else if (strcmp(a, "--out") == 0) {
            out = val;
        } else if (strcmp(a, "--nodes") == 0) {
            long v = strtol(val, &end, 10);
            if (!end || *end || v < 1 || v > 1000000) {
                fprintf(stderr, "gale-skelshot: --nodes: expected 1..1000000, got \"%s\"\n", val);
                return 2;
            }
            nodes = (int)v;
        } else if (strcmp(a, "--size") == 0) {
            long v = strtol(val, &end, 10);
            if (!end || *end || v < 64 || v > 4096) {
                fprintf(stderr, "gale-skelshot: --size: expected 64..4096, got \"%s\"\n", val);
                return 2;
            }
            size = (int)v;
        } else {
            fprintf(stderr, "gale-skelshot: unknown flag %s\n", a);
            usage(stderr);
            return 2;
        }
    }
    if ((!species_path) == (!csv_path) || !out) {
        fprintf(stderr, "gale-skelshot: expected exactly one of --species/--skeleton, and --out\n");
        usage(stderr);
        return 2;
    }
    gale_err err = { 0 };
    skeleton s = { 0 };
    species sp;
    species_default(&sp);
    asset a;
    memset(&a, 0, sizeof a);
    int have_mesh = 0;
    char title[160];
    if (species_path) {
        if (species_load(species_path, &sp, &err) != 0) {
            fprintf(stderr, "gale-skelshot: %s\n", err.msg);
            return 1;
        }
        if (nodes > 0) {
            sp.gen.target_nodes = nodes;
        }
        if (lsystem_generate(&sp.gen, &s, &err) != 0) {
            fprintf(stderr, "gale-skelshot: %s: %s\n", species_path, err.msg);
            return 1;
        }
        snprintf(title, sizeof title, "%s", sp.name);
    } else {
        if (skeleton_load_csv(csv_path, &s, &err) != 0) {
            fprintf(stderr, "gale-skelshot: %s\n", err.msg);
            return 1;
        }
        snprintf(title, sizeof title, "%s", csv_path);
    }
    if (mesh_build(&s, &sp, &a, &err) == 0) {
        have_mesh = 1;
    } else {
        fprintf(stderr, "gale-skelshot: mesh: %s (drawing the skeleton only)\n", err.msg);
    }
    float lo[3] = { 1e30f, 1e30f, 1e30f }, hi[3] = { -1e30f, -1e30f, -1e30f };
    for (int i = 0; i < s.n; i++) {
        for (int k = 0; k < 3; k++) {
            lo[k] = fminf(lo[k], s.pos[3 * i + k]);
            hi[k] = fmaxf(hi[k], s.pos[3 * i + k]);
        }
    }
    float span_side = fmaxf(fmaxf(hi[0] - lo[0], hi[2] - lo[2]), 1e-3f);
    float span_top = fmaxf(fmaxf(hi[0] - lo[0], hi[1] - lo[1]), 1e-3f);
    int margin = 30;
    plot pl;
    const uint8_t bg[3] = { 250, 250, 246 }, ink[3] = { 30, 30, 30 }, grid[3] = { 200, 200, 200 };
    int panels = have_mesh ? 3 : 2;
    if (plot_init(&pl, panels * size, size + 2 * margin, bg, &err) != 0) {
        fprintf(stderr, "gale-skelshot: %s\n", err.msg);
        skeleton_fini(&s);
        asset_fini(&a);
        return 1;
    }
    view side = { .ox = 0.5f * (float)size,
                  .oy = (float)(size + margin),
                  .scale = (float)(size - 2 * margin) / span_side,
                  .cx = 0.5f * (lo[0] + hi[0]),
                  .cy = 0.0f,
                  .ax = 0,
                  .ay = 2 };
    view top = { .ox = 1.5f * (float)size,
                 .oy = (float)margin + 0.5f * (float)size,
                 .scale = (float)(size - 2 * margin) / span_top,
                 .cx = 0.5f * (lo[0] + hi[0]),
                 .cy = 0.5f * (lo[1] + hi[1]),
                 .ax = 0,
                 .ay = 1 };
    plot_line(&pl, 0.0f, side.oy, (float)size, side.oy, 1.0f, grid);
    plot_line(&pl, (float)size, 0.0f, (float)size, (float)pl.h, 1.0f, grid);
    draw_view(&pl, &side, &s, have_mesh ? &a : NULL);
    draw_view(&pl, &top, &s, have_mesh ? &a : NULL);
    if (have_mesh && a.n_lods > 0) {
        /* third panel: the tube mesh, LOD 0 large, LODs 1 and 2 small beside it */
        plot_line(&pl, (float)(2 * size), 0.0f, (float)(2 * size), (float)pl.h, 1.0f, grid);
        view m0 = side;
        m0.ox = 2.5f * (float)size;
        draw_mesh(&pl, &m0, &a, 0);
        for (uint32_t l = 1; l < a.n_lods && l < 3; l++) {
            view ml = side;
            ml.scale = side.scale * 0.3f;
            ml.ox = 2.0f * (float)size + (float)size * (0.12f + 0.2f * (float)(l - 1));
            ml.oy = (float)margin + 0.32f * (float)size;
            draw_mesh(&pl, &ml, &a, (int)l);
        }
        char lodline[96];
        snprintf(lodline, sizeof lodline, "mesh %u verts, LOD tris %u/%u/%u", a.n_verts,
                 a.lod_count[0] / 3, a.lod_count[1] / 3, a.lod_count[2] / 3);
        plot_text(&pl, 2 * size + 8, pl.h - 22, 2, lodline, ink);
    }
    char line[256];
    snprintf(line, sizeof line, "%s: %d nodes, height %.1f m, crown %.1f x %.1f m, %u leaves",
             title, s.n, (double)hi[2], (double)(hi[0] - lo[0]), (double)(hi[1] - lo[1]),
             have_mesh ? a.n_leaves : 0u);
    plot_text(&pl, 8, 8, 2, line, ink);
    plot_text(&pl, 8, pl.h - 22, 2, "side (x-z)", ink);
    plot_text(&pl, size + 8, pl.h - 22, 2, "top (x-y)", ink);
    int rc = plot_write_png(&pl, out, &err);
    if (rc != 0) {
        fprintf(stderr, "gale-skelshot: %s\n", err.msg);
    } else {
        printf("%s\n", line);
    }
    plot_fini(&pl);
    skeleton_fini(&s);
    asset_fini(&a);
    return rc == 0 ? 0 : 1;
}
