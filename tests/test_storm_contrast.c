/* Crowns against the storm sky (storm_fx.h; client/CLIENT.md, gale-client --storm-fx): a 1280x720
 * kiosk frame of a row of trees seen from the street, rendered under Mesa llvmpipe at a
 * breeze, 30 m/s and 50 m/s (Category 3), measures how far the crowns stand out from the sky
 * beside them, and that the 50 m/s frame still reads as a storm (darker than the calm one).
 *
 * Which pixels are crown and which are sky comes from the scene, not from the storm frame:
 * the same view is drawn in the calm look with the trees and without them (same pose, same
 * time). A pixel the trees change by more than 6 levels and whose calm colour is
 * green-dominant (leaves; bark is red-dominant) is crown; a pixel they leave unchanged, blue
 * in the calm frame without trees (sky, not ground) and within RING_PX of a crown pixel is
 * the sky next to the crowns. On the storm frame, with Y the relative luminance a screen
 * shows for a pixel (sRGB decoded, Rec. 709 weights, white = 1):
 *     Y_crown, Y_sky   the mean Y over each set
 *     dY = Y_sky - Y_crown                  the crown's luminance step against the sky
 *     Weber = dY / Y_sky                    how dark the crown is beside the sky
 * A kiosk stands in a lit hall: the eye keeps to the room's light, not the frame's, so the
 * step dY a screen shows is what makes a crown readable, where a dark frame can keep a high
 * Weber contrast and still show the crown as black on near-black. The floors ask both.
 * The frames are written to GALE_TEST_DIR/storm_contrast_{calm,30,50}.png. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "render.h"
#include "render_demo.h"

#define W       1280
#define H       720
#define N_TREES 8
#define RING_PX 8
#define T_S     1.0
/* Floors at 30 and 50 m/s: the crowns' luminance step against the sky, and their Weber
 * contrast. A storm look whose dark sky, fog and rain hid the crowns measured dY 0.087 at
 * 50 m/s and 0.138 at 30 (Weber 0.815, 0.876); this one 0.141 and 0.186 (0.892, 0.916);
 * the calm frame 0.333 (0.907). */
#define FLOOR_DY    0.125
#define FLOOR_WEBER 0.85
/* still a storm: the 50 m/s frame's mean luminance under this share of the calm one's */
#define STORM_DARKER 0.55

static render *R;
static gale_err err;
static asset A[2];
static render_instance inst[N_TREES];
/* the street camera of a kiosk: eye at 1.7 m, looking up at the crowns of the near row,
 * its subject (17.2 m away), as the kiosk's street preset looks up at the palms */
static const render_camera CAM = { .eye = { 0.0f, -8.0f, 1.7f },
                                   .target = { 0.0f, 8.0f, 8.0f },
                                   .subject_m = 17.2f };

static void set_trees(uint32_t n, float wind_ms)
{
    CHECK(render_set_instances(R, n, inst, &err) == 0);
    float q[64];
    for (uint32_t t = 0; t < n; t++) {
        const asset *a = &A[inst[t].species];
        /* wind from the west (towards +x), in the tree's frame */
        float c = cosf(inst[t].yaw), s = sinf(inst[t].yaw);
        float wl[3] = { c * wind_ms, -s * wind_ms, 0.0f };
        render_demo_pose(a, wl, (float)T_S, t, q);
        CHECK(render_set_q(R, t, q, a->n_modes, &err) == 0);
    }
}

static uint8_t *shot(const storm_fx *fx)
{
    uint8_t *rgb = malloc((size_t)W * H * 3);
    render_set_storm(R, fx);
    CHECK(render_frame(R, &CAM, T_S, &err) == 0);
    CHECK(render_read_rgb(R, rgb, &err) == 0);
    return rgb;
}

/* Relative luminance a screen shows for an sRGB pixel (IEC 61966-2-1 decoding), white 1. */
static double lum(const uint8_t *p)
{
    double c[3];
    for (int k = 0; k < 3; k++) {
        double v = p[k] / 255.0;
        c[k] = v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4);
    }
    return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
}

typedef struct masks {
    uint8_t *crown, *sky; /* W x H, 1 where crown / sky next to a crown */
    int n_crown, n_sky;
} masks;

/* The crown and sky-ring masks of the trees posed for wind_ms (see the top comment). */
static masks make_masks(float wind_ms)
{
    masks m = { calloc((size_t)W * H, 1), calloc((size_t)W * H, 1), 0, 0 };
    set_trees(N_TREES, wind_ms);
    uint8_t *with = shot(NULL);
    set_trees(0, wind_ms);
    uint8_t *without = shot(NULL);
    set_trees(N_TREES, wind_ms);
    uint8_t *tree = calloc((size_t)W * H, 1);
    for (size_t i = 0; i < (size_t)W * H; i++) {
        const uint8_t *a = with + 3 * i, *b = without + 3 * i;
        int d = abs(a[0] - b[0]) + abs(a[1] - b[1]) + abs(a[2] - b[2]);
        tree[i] = d > 6;
        if (tree[i] && a[1] > a[0] && a[1] > a[2]) {
            m.crown[i] = 1;
            m.n_crown++;
        }
    }
    for (int y = 0; y < H; y++) {
        for (int x = 0; x < W; x++) {
            size_t i = (size_t)y * W + (size_t)x;
            const uint8_t *b = without + 3 * i;
            if (tree[i] || !(b[2] > b[1] && b[2] > b[0])) {
                continue;
            }
            bool near = false;
            for (int dy = -RING_PX; dy <= RING_PX && !near; dy++) {
                for (int dx = -RING_PX; dx <= RING_PX && !near; dx++) {
                    int xx = x + dx, yy = y + dy;
                    near = xx >= 0 && xx < W && yy >= 0 && yy < H &&
                           m.crown[(size_t)yy * W + (size_t)xx];
                }
            }
            if (near) {
                m.sky[i] = 1;
                m.n_sky++;
            }
        }
    }
    free(with);
    free(without);
    free(tree);
    return m;
}

typedef struct readout {
    double y_crown, y_sky, dy, weber, y_frame;
} readout;

/* The storm frame of fx over masks m, written to storm_contrast_<name>.png (name NULL:
 * not written), and its crowns against the sky beside them. */
static readout readout_of(const storm_fx *fx, const masks *m, const char *name)
{
    uint8_t *rgb = shot(fx);
    if (name) {
        char path[512];
        snprintf(path, sizeof path, "%s/storm_contrast_%s.png", GALE_TEST_DIR, name);
        CHECK(render_write_png(R, path, &err) == 0);
    }
    double sc = 0.0, ss = 0.0, sf = 0.0;
    for (size_t i = 0; i < (size_t)W * H; i++) {
        double y = lum(rgb + 3 * i);
        sc += m->crown[i] ? y : 0.0;
        ss += m->sky[i] ? y : 0.0;
        sf += y;
    }
    free(rgb);
    readout r = { .y_crown = sc / m->n_crown, .y_sky = ss / m->n_sky, .y_frame = sf / (W * H) };
    r.dy = r.y_sky - r.y_crown;
    r.weber = r.dy / r.y_sky;
    fprintf(stderr,
            "%-26s crown pixels %d, sky beside them %d; luminance crown %.4f, sky %.4f, "
            "frame %.4f; dY %.3f, Weber %.3f\n",
            name ? name : "", m->n_crown, m->n_sky, r.y_crown, r.y_sky, r.y_frame, r.dy, r.weber);
    /* enough of both to measure: the crowns fill a good part of the frame */
    CHECK(m->n_crown > 20000);
    CHECK(m->n_sky > 20000);
    return r;
}

static void free_masks(masks *m)
{
    free(m->crown);
    free(m->sky);
}

static void test_crowns_readable(void)
{
    storm_fx fx;
    masks m = make_masks(6.0f);
    storm_fx_from_weather(6.0f, 270.0f, STORM_FX_HIGH, &fx);
    readout calm = readout_of(&fx, &m, "calm");
    free_masks(&m);
    m = make_masks(30.0f);
    storm_fx_from_weather(30.0f, 270.0f, STORM_FX_HIGH, &fx);
    readout s30 = readout_of(&fx, &m, "30");
    free_masks(&m);
    m = make_masks(50.0f);
    storm_fx_from_weather(50.0f, 270.0f, STORM_FX_HIGH, &fx);
    readout s50 = readout_of(&fx, &m, "50");
    fprintf(stderr,
            "dY at 30, 50 m/s %.3f, %.3f (floor %.3f); Weber %.3f, %.3f (floor %.2f); "
            "50 m/s frame %.2f of calm's luminance (below %.2f)\n",
            s30.dy, s50.dy, FLOOR_DY, s30.weber, s50.weber, FLOOR_WEBER, s50.y_frame / calm.y_frame,
            STORM_DARKER);
    CHECK(calm.dy > s50.dy); /* the calm day's crowns on a bright sky stand out most */
    CHECK(s30.dy >= FLOOR_DY && s50.dy >= FLOOR_DY);
    CHECK(s30.weber >= FLOOR_WEBER && s50.weber >= FLOOR_WEBER);
    CHECK(s50.y_frame < STORM_DARKER * calm.y_frame);

    /* each part earns its place: without the subject kept clear of fog and rain, or dry,
     * the 50 m/s crowns are lighter (measured 16 % and 13 %) and stand out less */
    storm_fx part = fx;
    part.subject_clear = 0.0f;
    readout no_clear = readout_of(&part, &m, "50, nothing kept clear");
    part = fx;
    part.wet = 0.0f;
    readout dry = readout_of(&part, &m, "50, dry");
    CHECK(no_clear.y_crown > 1.08 * s50.y_crown && no_clear.weber < s50.weber);
    CHECK(dry.y_crown > 1.08 * s50.y_crown && dry.weber < s50.weber);
    /* the fog alone (no rain, no spray) and the rain alone (the calm fog distance, no
     * spray), each with the subject kept clear and without */
    readout fog[2], rain[2];
    for (int k = 0; k < 2; k++) {
        part = fx;
        part.rain_layers = 0;
        part.spray = 0.0f;
        part.subject_clear = k ? 0.0f : fx.subject_clear;
        fog[k] = readout_of(&part, &m, k ? "50, fog only, not clear" : "50, fog only");
        part = fx;
        part.fog_scale = 1.0f;
        part.spray = 0.0f;
        part.subject_clear = k ? 0.0f : fx.subject_clear;
        rain[k] = readout_of(&part, &m, k ? "50, rain only, not clear" : "50, rain only");
    }
    fprintf(stderr, "crowns kept clear / not: fog alone %.3f, rain alone %.3f of the luminance\n",
            fog[0].y_crown / fog[1].y_crown, rain[0].y_crown / rain[1].y_crown);
    CHECK(fog[0].y_crown < 0.95 * fog[1].y_crown);
    CHECK(rain[0].y_crown < 0.95 * rain[1].y_crown);
    free_masks(&m);
}

int main(void)
{
    R = render_create(
        &(render_desc){
            .width = W, .height = H, .headless = true, .max_trees = N_TREES, .max_falling = 16 },
        &err);
    if (!R) {
        fprintf(stderr, "render_create: %s\n", err.msg);
        return 1;
    }
    for (uint32_t s = 0; s < 2; s++) {
        /* a broad-leaved tree and a palm, as on the town block's street */
        if (render_demo_asset(&A[s],
                              &(render_demo_desc){
                                  .n_nodes = 150, .n_modes = 10, .leaf_shape = s, .seed = s + 1 },
                              &err) < 0 ||
            render_add_species(R, &A[s], &err) < 0) {
            fprintf(stderr, "species: %s\n", err.msg);
            return 1;
        }
    }
    /* a near row the camera looks at (the subject) and a far row 40 m behind it */
    for (uint32_t t = 0; t < N_TREES; t++) {
        bool far = t >= 5;
        float x = far ? -14.0f + 14.0f * (float)(t - 5) : -14.0f + 7.0f * (float)t;
        inst[t] = (render_instance){ .species = t % 2,
                                     .pos = { x, far ? 48.0f : 8.0f, 0.0f },
                                     .yaw = 0.7f * (float)t,
                                     .scale = far ? 1.3f : 1.3f + 0.1f * (float)(t % 3) };
    }
    RUN(test_crowns_readable);
    for (uint32_t s = 0; s < 2; s++) {
        render_demo_free(&A[s]);
    }
    render_destroy(R);
    return check_report();
}
