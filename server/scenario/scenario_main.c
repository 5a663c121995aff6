/* gale-wind: runs a wind scenario on a real wind grid. Prints the timeline (sustained and
 * gust speed, direction, Saffir–Simpson class, pressure, distance to the storm, and the
 * grid's own wind at the scene centre) and writes a horizontal slice of the field as a
 * PNG: speed as colour, arrows for direction, obstacles drawn, a legend. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cfg.h"
#include "plot.h"
#include "scenario.h"
#include "scenario_int.h"
#include "wind.h"

#define MAX_BOXES 256

typedef struct opts {
    const char *scenario_path, *scene_path, *png;
    double seconds, time_scale, height_m, at_s, dt_s, every_s, spinup_s;
    int timeline;
    int no_grid;
    int nx, ny, nz;
    double cell_m;
    double origin[3];
    int has_origin;
    wind_box boxes[MAX_BOXES];
    int n_boxes;
} opts;

static void usage(FILE *o)
{
    fprintf(o,
            "usage: gale-wind --scenario F.json [--seconds T] [--time-scale K] [--timeline]\n"
            "                 [--no-grid] [--every S] [--slice-png out.png] [--height Z] [--at T]\n"
            "                 [--grid NXxNYxNZ] [--cell M] [--origin X,Y,Z] [--dt S]\n"
            "                 [--box X0,Y0,Z0,X1,Y1,Z1]... [--scene scene.json] [--spinup S]\n"
            "  --seconds   server seconds to run (default: the replay's length, or 60)\n"
            "  --time-scale  override the scenario's time compression\n"
            "  --timeline  print one line per --every seconds (default length/40)\n"
            "  --no-grid   the scenario alone, without the wind grid (fast; no picture)\n"
            "  --slice-png write the horizontal slice at height --height (10 m) at --at\n"
            "              (default: the end) as PNG\n"
            "  --grid, --cell, --origin  the wind grid (64x64x16, 2 m, centred on 0,0)\n"
            "  --dt        wind step [s] (default 1/30: a 60 Hz server stepping it every\n"
            "              second tick)\n"
            "  --box       a solid obstacle (repeatable); --scene takes the obstacles and\n"
            "              wind grid of a scene file\n"
            "  --spinup    the grid starts this many seconds before --at (default 60;\n"
            "              the scenario itself always runs from 0)\n");
}

static int parse_list(const char *s, double *v, int n)
{
    char *end;
    for (int i = 0; i < n; i++) {
        v[i] = strtod(s, &end);
        if (end == s || !isfinite(v[i])) {
            return -1;
        }
        s = end;
        if (i < n - 1) {
            if (*s != ',') {
                return -1;
            }
            s++;
        }
    }
    return *s ? -1 : 0;
}

/* Reads the wind grid and obstacles of a scene file ("wind": grid, cell_m, origin;
 * "obstacles": [{min, max}]); other keys are the scene loader's business. */
static int read_scene(opts *o, const char *path)
{
    cfg_doc d;
    gale_err err = { 0 };
    if (cfg_load(&d, path, &err) < 0) {
        fprintf(stderr, "gale-wind: %s\n", err.msg);
        return -1;
    }
    int rc = 0;
    const cJSON *w = cJSON_GetObjectItemCaseSensitive(d.root, "wind");
    if (cJSON_IsObject(w)) {
        double g[3] = { o->nx, o->ny, o->nz }, org[3];
        if (cfg_vec(&d, w, "wind", "grid", false, 3, g, 4, 1024, g, &err) < 0 ||
            cfg_number(&d, w, "wind", "cell_m", false, o->cell_m, 0.05, 100, &o->cell_m, &err) <
                0) {
            rc = -1;
        } else {
            o->nx = (int)g[0];
            o->ny = (int)g[1];
            o->nz = (int)g[2];
            if (cJSON_GetObjectItemCaseSensitive(w, "origin")) {
                if (cfg_vec(&d, w, "wind", "origin", true, 3, NULL, -1e5, 1e5, org, &err) < 0) {
                    rc = -1;
                } else {
                    memcpy(o->origin, org, sizeof org);
                    o->has_origin = 1;
                }
            }
        }
    }
    const cJSON *obs = cJSON_GetObjectItemCaseSensitive(d.root, "obstacles");
    int i = 0;
    for (const cJSON *b = obs ? obs->child : NULL; b && rc == 0; b = b->next, i++) {
        char p[64];
        cfg_path_index(p, sizeof p, "obstacles", i);
        double mn[3], mx[3];
        if (o->n_boxes == MAX_BOXES ||
            cfg_vec(&d, b, p, "min", true, 3, NULL, -1e5, 1e5, mn, &err) < 0 ||
            cfg_vec(&d, b, p, "max", true, 3, NULL, -1e5, 1e5, mx, &err) < 0) {
            if (o->n_boxes == MAX_BOXES) {
                gale_errf(&err, GALE_E_RANGE, "%s: more than %d obstacles", path, MAX_BOXES);
            }
            rc = -1;
            break;
        }
        wind_box *wb = &o->boxes[o->n_boxes++];
        for (int k = 0; k < 3; k++) {
            wb->min[k] = (float)mn[k];
            wb->max[k] = (float)mx[k];
        }
    }
    if (rc < 0) {
        fprintf(stderr, "gale-wind: %s\n", err.msg);
    }
    cfg_fini(&d);
    return rc;
}

static int parse_args(opts *o, int argc, char **argv)
{
    memset(o, 0, sizeof *o);
    o->seconds = -1.0;
    o->time_scale = -1.0;
    o->height_m = 10.0;
    o->at_s = -1.0;
    o->dt_s = 1.0 / 30.0;
    o->every_s = -1.0;
    o->spinup_s = 60.0;
    o->nx = 64;
    o->ny = 64;
    o->nz = 16;
    o->cell_m = 2.0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        double *num = NULL;
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            usage(stdout);
            exit(0);
        }
        if (strcmp(a, "--timeline") == 0) {
            o->timeline = 1;
            continue;
        }
        if (strcmp(a, "--no-grid") == 0) {
            o->no_grid = 1;
            continue;
        }
        if (!v) {
            fprintf(stderr, "gale-wind: %s: missing value (see --help)\n", a);
            return -1;
        }
        i++;
        if (strcmp(a, "--scenario") == 0) {
            o->scenario_path = v;
        } else if (strcmp(a, "--slice-png") == 0) {
            o->png = v;
        } else if (strcmp(a, "--scene") == 0) {
            if (read_scene(o, v) < 0) {
                return -1;
            }
        } else if (strcmp(a, "--seconds") == 0) {
            num = &o->seconds;
        } else if (strcmp(a, "--time-scale") == 0) {
            num = &o->time_scale;
        } else if (strcmp(a, "--height") == 0) {
            num = &o->height_m;
        } else if (strcmp(a, "--at") == 0) {
            num = &o->at_s;
        } else if (strcmp(a, "--dt") == 0) {
            num = &o->dt_s;
        } else if (strcmp(a, "--every") == 0) {
            num = &o->every_s;
        } else if (strcmp(a, "--spinup") == 0) {
            num = &o->spinup_s;
        } else if (strcmp(a, "--cell") == 0) {
            num = &o->cell_m;
        } else if (strcmp(a, "--grid") == 0) {
            if (sscanf(v, "%dx%dx%d", &o->nx, &o->ny, &o->nz) != 3 || o->nx < 4 || o->ny < 4 ||
                o->nz < 2 || o->nx > 1024 || o->ny > 1024 || o->nz > 256) {
                fprintf(stderr,
                        "gale-wind: --grid: expected NXxNYxNZ (4..1024, 2..256), got "
                        "'%s'\n",
                        v);
                return -1;
            }
        } else if (strcmp(a, "--origin") == 0) {
            if (parse_list(v, o->origin, 3) < 0) {
                fprintf(stderr, "gale-wind: --origin: expected X,Y,Z, got '%s'\n", v);
                return -1;
            }
            o->has_origin = 1;
        } else if (strcmp(a, "--box") == 0) {
            double b[6];
            if (o->n_boxes == MAX_BOXES || parse_list(v, b, 6) < 0 || b[3] <= b[0] ||
                b[4] <= b[1] || b[5] <= b[2]) {
                fprintf(stderr,
                        "gale-wind: --box: expected X0,Y0,Z0,X1,Y1,Z1 with max > min, "
                        "got '%s'\n",
                        v);
                return -1;
            }
            wind_box *wb = &o->boxes[o->n_boxes++];
            for (int k = 0; k < 3; k++) {
                wb->min[k] = (float)b[k];
                wb->max[k] = (float)b[k + 3];
            }
        } else {
            fprintf(stderr, "gale-wind: unknown argument '%s' (see --help)\n", a);
            return -1;
        }
        if (num) {
            char *end;
            *num = strtod(v, &end);
            if (*end || end == v || !isfinite(*num)) {
                fprintf(stderr, "gale-wind: %s: expected a number, got '%s'\n", a, v);
                return -1;
            }
        }
    }
    if (o->no_grid && o->png) {
        fprintf(stderr, "gale-wind: --slice-png needs the grid (drop --no-grid)\n");
        return -1;
    }
    if (!o->scenario_path) {
        fprintf(stderr, "gale-wind: --scenario is required\n");
        usage(stderr);
        return -1;
    }
    if (!(o->dt_s > 0.0 && o->dt_s <= 1.0) || !(o->cell_m > 0.0)) {
        fprintf(stderr, "gale-wind: --dt must be in (0, 1] s and --cell > 0\n");
        return -1;
    }
    if (o->time_scale != -1.0 && !(o->time_scale >= 1.0 && o->time_scale <= 10000.0)) {
        fprintf(stderr, "gale-wind: --time-scale: expected a number in [1, 10000], got %g\n",
                o->time_scale);
        return -1;
    }
    if (!o->has_origin) {
        o->origin[0] = -0.5 * o->nx * o->cell_m;
        o->origin[1] = -0.5 * o->ny * o->cell_m;
        o->origin[2] = 0.0;
    }
    return 0;
}

static void print_header(void)
{
    printf("#  t_s  clock              storm_min  sust_ms gust_ms from_deg class                "
           "bft  p_hPa   dist_km grid_ms grid_from\n");
}

static void print_line(const scenario_state *st, const float *gv)
{
    printf("%7.1f  %-17s %9.1f  %7.1f %7.1f %8.1f %-20s %3d %7.1f %9.1f", st->t_s,
           st->clock_utc[0] ? st->clock_utc : "-", st->storm_min, st->sustained_ms, st->gust_ms,
           st->dir_from_deg, st->category_name, st->beaufort, st->pressure_hpa, st->distance_km);
    if (gv) {
        double gs = hypot((double)gv[0], (double)gv[1]);
        double gfrom =
            fmod(270.0 - atan2((double)gv[1], (double)gv[0]) * 180.0 / M_PI + 720.0, 360.0);
        printf(" %7.1f %9.1f\n", gs, gfrom);
    } else {
        printf("       -         -\n");
    }
}

/* Colour of obstacles cut by the slice, and of those below it (outline). */
static const uint8_t solid_cut[3] = { 70, 70, 78 };
static const uint8_t solid_below[3] = { 255, 110, 60 };
static const uint8_t arrow_edge[3] = { 20, 20, 28 };
static const uint8_t white[3] = { 255, 255, 255 };
static const uint8_t black[3] = { 0, 0, 0 };
static const uint8_t bg[3] = { 248, 248, 246 };

static int write_slice(const opts *o, const wind_grid *w, const scenario *s,
                       const scenario_state *st, const char *path)
{
    wind_desc wd = wind_get_desc(w);
    double ox = wd.origin[0], oy = wd.origin[1], cell = wd.cell_m;
    double ext_x = wd.nx * cell, ext_y = wd.ny * cell;
    const int map = 640;
    double ppm = map / (ext_x > ext_y ? ext_x : ext_y); /* pixels per metre */
    int mw = (int)lround(ext_x * ppm), mh = (int)lround(ext_y * ppm);
    const int left = 16, top = 56, legend_w = 250;
    int W = left + mw + legend_w, H = top + mh + 40;
    if (H < top + 420) {
        H = top + 420;
    }
    plot p;
    gale_err err = { 0 };
    if (plot_init(&p, W, H, bg, &err) < 0) {
        fprintf(stderr, "gale-wind: %s\n", err.msg);
        return -1;
    }
    /* speeds on the pixel raster, and the colour scale's top (a round number ≥ the max) */
    double *spd = malloc((size_t)mw * (size_t)mh * sizeof *spd);
    if (!spd) {
        plot_fini(&p);
        fprintf(stderr, "gale-wind: out of memory\n");
        return -1;
    }
    double z = o->height_m;
    double vmax = 0.0;
    for (int j = 0; j < mh; j++) {
        for (int i = 0; i < mw; i++) {
            float pt[3] = { (float)(ox + (i + 0.5) / ppm), (float)(oy + ext_y - (j + 0.5) / ppm),
                            (float)z };
            float v[3];
            wind_sample(w, pt, v);
            double sp = sqrt((double)(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
            spd[(size_t)j * (size_t)mw + (size_t)i] = sp;
            if (sp > vmax) {
                vmax = sp;
            }
        }
    }
    /* a round tick step (1, 2 or 5 × 10^k) giving at most 5 ticks, and the scale's top
     * the first tick at or above the slice's fastest wind */
    double raw = (vmax > 1.0 ? vmax : 1.0) / 5.0, mag = pow(10.0, floor(log10(raw)));
    double tick = raw <= mag         ? mag
                  : raw <= 2.0 * mag ? 2.0 * mag
                  : raw <= 5.0 * mag ? 5.0 * mag
                                     : 10.0 * mag;
    int n_ticks = (int)ceil(vmax / tick - 1e-9);
    if (n_ticks < 1) {
        n_ticks = 1;
    }
    double top_ms = n_ticks * tick;
    for (int j = 0; j < mh; j++) {
        for (int i = 0; i < mw; i++) {
            uint8_t c[3];
            plot_colormap((float)(spd[(size_t)j * (size_t)mw + (size_t)i] / top_ms), c);
            plot_rect(&p, left + i, top + j, left + i + 1, top + j + 1, c);
        }
    }
    free(spd);
    /* obstacles: filled where the slice cuts them, outlined where they lie below it */
    for (int b = 0; b < o->n_boxes; b++) {
        const wind_box *bx = &o->boxes[b];
        float x0 = (float)(left + ((double)bx->min[0] - ox) * ppm);
        float x1 = (float)(left + ((double)bx->max[0] - ox) * ppm);
        float y0 = (float)(top + (oy + ext_y - (double)bx->max[1]) * ppm);
        float y1 = (float)(top + (oy + ext_y - (double)bx->min[1]) * ppm);
        if ((double)bx->min[2] <= z && (double)bx->max[2] >= z) {
            plot_rect(&p, (int)lroundf(x0), (int)lroundf(y0), (int)lroundf(x1), (int)lroundf(y1),
                      solid_cut);
        } else if ((double)bx->max[2] < z) {
            plot_line(&p, x0, y0, x1, y0, 2.0f, solid_below);
            plot_line(&p, x1, y0, x1, y1, 2.0f, solid_below);
            plot_line(&p, x1, y1, x0, y1, 2.0f, solid_below);
            plot_line(&p, x0, y1, x0, y0, 2.0f, solid_below);
        }
    }
    /* arrows on a lattice of 16 per side, length ∝ speed (a full lattice step at the
     * scale's top), white on a dark edge so they read on every colour */
    double step_m = (ext_x > ext_y ? ext_x : ext_y) / 16.0;
    double alen = step_m * ppm * 0.95;
    for (double y = oy + step_m / 2; y < oy + ext_y; y += step_m) {
        for (double x = ox + step_m / 2; x < ox + ext_x; x += step_m) {
            float pt[3] = { (float)x, (float)y, (float)z }, v[3];
            wind_sample(w, pt, v);
            double sp = hypot((double)v[0], (double)v[1]);
            if (sp < 1e-3 * top_ms) {
                continue;
            }
            double l = alen * sp / top_ms;
            float cx = (float)(left + (x - ox) * ppm);
            float cy = (float)(top + (oy + ext_y - y) * ppm);
            float dx = (float)(l * (double)v[0] / sp / 2), dy = (float)(-l * (double)v[1] / sp / 2);
            plot_arrow(&p, cx - dx, cy - dy, cx + dx, cy + dy, 3.5f, arrow_edge);
            plot_arrow(&p, cx - dx, cy - dy, cx + dx, cy + dy, 1.5f, white);
        }
    }
    /* header */
    char line[160];
    snprintf(line, sizeof line, "%s", scenario_name(s));
    plot_text(&p, left, 8, 2, line, black);
    snprintf(line, sizeof line, "slice z = %.1f m   t = %.1f s   %s   grid %dx%dx%d, %.1f m",
             o->height_m, st->t_s, st->clock_utc, wd.nx, wd.ny, wd.nz, cell);
    plot_text(&p, left, 32, 1, line, black);
    /* legend: colour bar with ticks */
    int lx = left + mw + 30, ly = top, bar_h = 240;
    plot_text(&p, lx, ly - 4, 1, "speed [m/s]", black);
    for (int j = 0; j < bar_h; j++) {
        uint8_t c[3];
        plot_colormap(1.0f - (float)j / (float)(bar_h - 1), c);
        plot_rect(&p, lx, ly + 10 + j, lx + 24, ly + 11 + j, c);
    }
    for (int k = 0; k <= n_ticks; k++) {
        int yy = ly + 10 + (int)lround((bar_h - 1) * (1.0 - (double)k / n_ticks));
        plot_line(&p, (float)(lx + 24), (float)yy, (float)(lx + 30), (float)yy, 1.0f, black);
        snprintf(line, sizeof line, "%g", tick * k);
        plot_text(&p, lx + 34, yy - 4, 1, line, black);
    }
    int ty = ly + bar_h + 30;
    snprintf(line, sizeof line, "sustained %.1f m/s", st->sustained_ms);
    plot_text(&p, lx, ty, 1, line, black);
    snprintf(line, sizeof line, "now       %.1f m/s", st->gust_ms);
    plot_text(&p, lx, ty + 14, 1, line, black);
    snprintf(line, sizeof line, "from      %.0f deg", st->dir_from_deg);
    plot_text(&p, lx, ty + 28, 1, line, black);
    snprintf(line, sizeof line, "%s",
             st->sustained_ms >= saffir_lower_ms(SAFFIR_TS) ? st->category_name
                                                            : saffir_beaufort_name(st->beaufort));
    plot_text(&p, lx, ty + 42, 1, line, black);
    if (st->distance_km >= 0.0) {
        snprintf(line, sizeof line, "%.0f hPa, eye %.1f km", st->pressure_hpa, st->distance_km);
        plot_text(&p, lx, ty + 56, 1, line, black);
    }
    plot_rect(&p, lx, ty + 76, lx + 14, ty + 86, solid_cut);
    plot_text(&p, lx + 20, ty + 78, 1, "solid at z", black);
    plot_line(&p, (float)lx, (float)(ty + 92), (float)(lx + 14), (float)(ty + 92), 2.0f,
              solid_below);
    plot_line(&p, (float)lx, (float)(ty + 100), (float)(lx + 14), (float)(ty + 100), 2.0f,
              solid_below);
    plot_line(&p, (float)lx, (float)(ty + 92), (float)lx, (float)(ty + 100), 2.0f, solid_below);
    plot_line(&p, (float)(lx + 14), (float)(ty + 92), (float)(lx + 14), (float)(ty + 100), 2.0f,
              solid_below);
    plot_text(&p, lx + 20, ty + 93, 1, "roof below z", black);
    snprintf(line, sizeof line, "x east, y north, %.0f m", ext_x);
    plot_text(&p, lx, ty + 112, 1, line, black);
    int rc = plot_write_png(&p, path, &err);
    if (rc < 0) {
        fprintf(stderr, "gale-wind: %s\n", err.msg);
    }
    plot_fini(&p);
    return rc;
}

int main(int argc, char **argv)
{
    static opts o; /* 256 boxes: off the stack */
    setvbuf(stdout, NULL, _IOLBF, 0);
    if (parse_args(&o, argc, argv) < 0) {
        return 2;
    }
    gale_err err = { 0 };
    scenario *s = scenario_load(o.scenario_path, &err);
    if (!s) {
        fprintf(stderr, "gale-wind: %s\n", err.msg);
        return 1;
    }
    if (o.time_scale > 0.0) {
        s->time_scale = o.time_scale;
    }
    double len = scenario_duration_s(s);
    if (o.seconds < 0.0) {
        o.seconds = len > 0.0 ? len : 60.0;
    }
    if (o.at_s < 0.0) {
        o.at_s = o.seconds;
    }
    double end = o.png && o.at_s > o.seconds ? o.at_s : o.seconds;
    if (o.every_s <= 0.0) {
        o.every_s = end / 40.0;
    }
    wind_desc wd = { .nx = o.nx,
                     .ny = o.ny,
                     .nz = o.nz,
                     .cell_m = (float)o.cell_m,
                     .seed = s->seed,
                     .obstacles = o.boxes,
                     .n_obstacles = o.n_boxes };
    for (int k = 0; k < 3; k++) {
        wd.origin[k] = (float)o.origin[k];
    }
    wind_grid *w = o.no_grid ? NULL : wind_create(&wd, &err);
    if (!w && !o.no_grid) {
        fprintf(stderr, "gale-wind: %s\n", err.msg);
        scenario_destroy(s);
        return 1;
    }
    /* the scene centre at 10 m, where the timeline reads the grid */
    float probe[3] = { (float)(o.origin[0] + 0.5 * o.nx * o.cell_m),
                       (float)(o.origin[1] + 0.5 * o.ny * o.cell_m), 10.0f };
    /* the grid runs only in the window that matters: the whole run for a timeline, the
     * spin-up before --at for a picture alone */
    double grid_from = o.timeline ? 0.0 : o.at_s - o.spinup_s;
    if (grid_from < 0.0) {
        grid_from = 0.0;
    }
    if (o.timeline) {
        printf("# %s: %s%s\n", o.scenario_path, scenario_name(s), len > 0.0 ? "" : " (steady)");
        print_header();
    }
    int rc = 0, png_done = 0;
    long n = (long)ceil(end / o.dt_s);
    double next_print = 0.0;
    wind_step_stats ws = { 0 };
    double div_worst = 0.0;
    for (long i = 0; i <= n; i++) {
        double t = i * o.dt_s;
        scenario_state st;
        if (w && t >= grid_from) {
            scenario_apply(s, w, t, &st);
            if (wind_step(w, (float)o.dt_s, &ws) < 0) {
                fprintf(stderr, "gale-wind: t %.2f s: the wind grid broke down\n", t);
                rc = 1;
                break;
            }
            if (ws.div_before > 0.0 && ws.div_after / ws.div_before > div_worst) {
                div_worst = ws.div_after / ws.div_before;
            }
        } else {
            scenario_eval(s, t, &st);
        }
        if (o.timeline && t + 1e-9 >= next_print) {
            float gv[3] = { 0, 0, 0 };
            if (w) {
                wind_sample(w, probe, gv);
            }
            print_line(&st, w ? gv : NULL);
            next_print += o.every_s;
        }
        if (o.png && !png_done && t + 1e-9 >= o.at_s) {
            if (write_slice(&o, w, s, &st, o.png) < 0) {
                rc = 1;
            } else {
                fprintf(stderr, "gale-wind: wrote %s (z %.1f m, t %.1f s)\n", o.png, o.height_m, t);
            }
            png_done = 1;
        }
    }
    if (o.timeline && div_worst > 0.0) {
        printf("# worst divergence after/before projection: %.3g\n", div_worst);
    }
    wind_destroy(w);
    scenario_destroy(s);
    return rc;
}
