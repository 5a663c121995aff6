/* gale-bench wire: bytes per tree per snapshot and skeleton node error of the state
 * stream (protocol/PROTOCOL.md) over a gusty run. Trees are the shipped species
 * (configs/species: oak, palm, pine) baked by bake_run (FEM, lowest modes, wind basis p_i,
 * length-true pose: Diener 2008 sections 3-4, PHYSICS.md), or with --synthetic seeded
 * synthetic skeletons through the same stages; driven by a mean wind with an
 * Ornstein-Uhlenbeck gust process per tree, advanced by gale_modal at 60 Hz, encoded at
 * 30 snapshots/s by the real encoder and decoded by the real decoder. Node error: the
 * client's decoded q against the server's float q, both through the reconstruction
 * u = rest + sum q~ v + q~^2 w, as a fraction of tree height; and what a client shows:
 * the decoded snapshots through the client's jitter buffer (client/playout/jitter.c, 0.1 s
 * playout delay) and its Hermite interpolation at every 60 Hz display tick, against the
 * server's q at that render time. The stream counts every frame a viewer gets, by frame
 * type from the header (KEYFRAME, DELTA, LEAVES from leaf.c shedding, WIND slices, the
 * pong text frames answering its pings), with the WebSocket frame headers (RFC 6455
 * section 5.2, server to client, unmasked), in bytes per client-second. Prints JSON. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mono.h"
#include "bench.h"
#include "asset.h"
#include "bake.h"
#include "bake_tree.h"
#include "basis.h"
#include "eigen.h"
#include "fem.h"
#include "gust.h"
#include "jitter.h"
#include "leaf.h"
#include "ctl.h"
#include "lsystem.h"
#include "modal.h"
#include "quant_steps.h"
#include "species.h"
#include "wire.h"


static float *to_float(const double *d, size_t n)
{
    float *f = malloc(sizeof(float) * (n ? n : 1));
    for (size_t i = 0; f && i < n; i++) {
        f[i] = (float)d[i];
    }
    return f;
}

/* Bakes one species from a seeded synthetic skeleton into *a (arrays owned by a; free
 * with asset_fini). Rayleigh damping alpha, beta (Diener 2008 eq. 9). */
static int bake_species(int n_nodes, uint64_t seed, int n_modes, double alpha, double beta,
                        asset *a, gale_err *err)
{
    skeleton sk = { 0 };
    fem_model fm = { 0 };
    eigen_result er = { 0 };
    double *trans = NULL, *rot = NULL, *p = NULL, *rest = NULL;
    int rc = bake_tree_generate(n_nodes, seed, &sk, err);
    if (!rc) {
        rc = fem_build(&sk, &(fem_material){ 0 }, &fm, err);
    }
    if (!rc) {
        rc = eigen_lowest(&fm, n_modes, &er, err);
    }
    if (rc) {
        goto done;
    }
    size_t nn = (size_t)sk.n;
    trans = calloc((size_t)n_modes * nn * 3, sizeof *trans);
    rot = calloc((size_t)n_modes * nn * 3, sizeof *rot);
    p = calloc((size_t)n_modes * 3, sizeof *p);
    rest = calloc(nn * 3, sizeof *rest);
    if (!trans || !rot || !p || !rest) {
        rc = gale_errf(err, GALE_E_NOMEM, "bench wire: out of memory");
        goto done;
    }
    fem_split_modes(&fm, er.phi, n_modes, trans, rot);
    /* C = 1/2 rho_air C_D with rho_air = 1.2 kg/m^3, C_D = 1 for a cylinder. */
    basis_compute(&fm, er.phi, n_modes, 0.6, NULL, p);
    for (size_t i = 0; i < 3 * nn; i++) {
        rest[i] = sk.pos[i];
    }
    memset(a, 0, sizeof *a);
    snprintf(a->species, sizeof a->species, "synthetic-%d-%llu", n_nodes,
             (unsigned long long)seed);
    a->n_nodes = (uint32_t)sk.n;
    a->n_modes = (uint32_t)n_modes;
    a->parent = malloc(sizeof(int32_t) * nn);
    a->rest = to_float(rest, 3 * nn);
    a->radius = to_float(rest, nn); /* unused here */
    a->omega = malloc(sizeof(float) * (size_t)n_modes);
    a->gamma = malloc(sizeof(float) * (size_t)n_modes);
    a->wind_basis = to_float(p, 3 * (size_t)n_modes);
    a->phi = to_float(trans, (size_t)n_modes * nn * 3);
    a->corr_v = malloc(sizeof(float) * (size_t)n_modes * nn * 3);
    a->corr_w = malloc(sizeof(float) * (size_t)n_modes * nn * 3);
    a->corr_a = malloc(sizeof(float) * (size_t)n_modes);
    a->corr_b = malloc(sizeof(float) * (size_t)n_modes);
    if (!a->parent || !a->rest || !a->omega || !a->gamma || !a->wind_basis || !a->phi ||
        !a->corr_v || !a->corr_w || !a->corr_a || !a->corr_b) {
        rc = gale_errf(err, GALE_E_NOMEM, "bench wire: out of memory");
        goto done;
    }
    for (size_t i = 0; i < nn; i++) {
        a->parent[i] = sk.parent[i];
        a->height_m = sk.pos[3 * i + 2] > a->height_m ? sk.pos[3 * i + 2] : a->height_m;
    }
    asset_pose_fields(a->rest, a->parent, a->n_nodes, a->phi, a->n_modes, a->corr_v, a->corr_w);
    for (int m = 0; m < n_modes; m++) {
        double w2 = er.omega2[m];
        a->corr_a[m] = 1.0f;
        a->corr_b[m] = 0.0f;
        a->omega[m] = (float)sqrt(w2);
        a->gamma[m] = (float)(alpha + beta * w2);
    }
done:
    free(trans);
    free(rot);
    free(p);
    free(rest);
    eigen_result_fini(&er);
    fem_fini(&fm);
    skeleton_fini(&sk);
    return rc;
}

/* Bakes the shipped species `name` (configs/species/<name>.json) into *a (asset_fini). */
static int bake_shipped(const char *name, int n_modes, asset *a, gale_err *err)
{
    char path[512];
    snprintf(path, sizeof path, "%s/configs/species/%s.json", GALE_SOURCE_DIR, name);
    species sp;
    skeleton sk = { 0 };
    int rc = species_load(path, &sp, err);
    if (!rc) {
        rc = lsystem_generate(&sp.gen, &sk, err);
    }
    if (!rc) {
        rc = bake_run(&sk, &sp, &(bake_desc){ .n_modes = n_modes }, a, NULL, err);
    }
    skeleton_fini(&sk);
    return rc;
}

#define HBINS 4000
#define HMAX 0.02 /* histogram of node error / H over [0, 2 %] */

static double hist_pct(const uint64_t *h, uint64_t n, double p)
{
    uint64_t want = (uint64_t)ceil(p * (double)n), acc = 0;
    for (int i = 0; i < HBINS; i++) {
        acc += h[i];
        if (acc >= want) {
            return (i + 1) * (HMAX / HBINS);
        }
    }
    return HMAX;
}

/* The frame type's byte in every binary frame: after the 4-byte magic and the 2-byte
 * version (PROTOCOL.md "Frame header"; wire_header.c). */
enum { WIRE_TYPE_BYTE = 6 };

/* WebSocket frame header bytes of a server-to-client frame of len payload bytes. */
static size_t ws_header_bytes(size_t len)
{
    return len < 126 ? 2 : len < 65536 ? 4 : 10;
}

int bench_wire(int argc, char **argv)
{
    double seconds = 60.0, mean_ms = 20.0, intensity = 0.3, eps = QUANT_STEPS_DEFAULT_EPS;
    double keyframe_s = 10.0;
    int n_trees = 200, n_modes = 32, error_every = 3;
    bool json = false, synthetic = false;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--seconds") == 0 && i + 1 < argc) {
            seconds = atof(argv[++i]);
        } else if (strcmp(argv[i], "--trees") == 0 && i + 1 < argc) {
            n_trees = atoi(argv[++i]);
        } else if (strcmp(argv[i], "--modes") == 0 && i + 1 < argc) {
            n_modes = atoi(argv[++i]);
        } else if (strcmp(argv[i], "--wind") == 0 && i + 1 < argc) {
            mean_ms = atof(argv[++i]);
        } else if (strcmp(argv[i], "--gust") == 0 && i + 1 < argc) {
            intensity = atof(argv[++i]);
        } else if (strcmp(argv[i], "--eps") == 0 && i + 1 < argc) {
            eps = atof(argv[++i]);
        } else if (strcmp(argv[i], "--keyframe-s") == 0 && i + 1 < argc) {
            keyframe_s = atof(argv[++i]);
        } else if (strcmp(argv[i], "--json") == 0) {
            json = true;
        } else if (strcmp(argv[i], "--synthetic") == 0) {
            synthetic = true;
        } else {
            return bench_usage(argv[i], "usage: gale-bench wire [--seconds S] [--trees N] [--modes M] "
                                        "[--wind MEAN_MS] [--gust INTENSITY] [--eps E] "
                                        "[--keyframe-s K] [--synthetic] [--json]\n");
        }
    }
    if (!(seconds >= 1 && seconds <= 3600) || n_trees < 1 || n_trees > 100000 || n_modes < 1 ||
        n_modes > (int)WIRE_MAX_MODES || !(mean_ms >= 0 && mean_ms <= 100) ||
        !(intensity >= 0 && intensity <= 1) || !(eps > 0 && eps < 0.1) || !(keyframe_s > 0)) {
        fprintf(stderr, "gale-bench wire: --seconds 1..3600, --trees 1..100000, --modes 1..%u, "
                        "--wind 0..100, --gust 0..1, --eps (0, 0.1), --keyframe-s > 0\n",
                WIRE_MAX_MODES);
        return 2;
    }
    gale_err err;
    enum { NS = 3 };
    static const int nodes[NS] = { 300, 450, 220 };
    static const char *const shipped[NS] = { "oak", "palm", "pine" };
    asset sp[NS];
    memset(sp, 0, sizeof sp);
    float steps[NS][WIRE_MAX_MODES];
    modal_species msp[NS];
    double t_bake = mono_s();
    for (int s = 0; s < NS; s++) {
        int rc = synthetic
                     ? bake_species(nodes[s], 101 + (uint64_t)s, n_modes, 0.3, 2e-3, &sp[s], &err)
                     : bake_shipped(shipped[s], n_modes, &sp[s], &err);
        if (rc || quant_steps_derive(&sp[s], (float)eps, steps[s], &err)) {
            fprintf(stderr, "gale-bench wire: species %d: %s\n", s, err.msg);
            return 1;
        }
        msp[s] = (modal_species){ (uint32_t)n_modes, sp[s].omega, sp[s].gamma,
                                  sp[s].wind_basis, steps[s] };
    }
    t_bake = mono_s() - t_bake;

    uint8_t *tree_sp = malloc((size_t)n_trees);
    float *yaw = malloc(sizeof(float) * (size_t)n_trees);
    float *wind = malloc(sizeof(float) * 3 * (size_t)n_trees);
    gust *gu = malloc(sizeof(gust) * (size_t)n_trees);
    const size_t stride = (size_t)n_modes;
    int16_t *snap[3];
    for (int k = 0; k < 3; k++) {
        snap[k] = calloc((size_t)n_trees * stride, sizeof(int16_t));
    }
    uint8_t *nm = malloc((size_t)n_trees);
    size_t cap = wire_state_bound((uint32_t)n_trees, (uint32_t)n_modes, NS);
    uint8_t *frame = malloc(cap);
    /* the extras of a snapshot (wind, leaves, weather, damage state) and the BUNDLE the
       server wraps them in with the state (server/serve/net.c, PROTOCOL.md "BUNDLE") */
    enum { X_WIND, X_LEAVES, X_WEATHER, X_DAMAGE, N_X };
    const size_t xcap = 65536;
    uint8_t *xbuf = malloc(N_X * xcap), *bundle = malloc(cap + N_X * xcap + 256);
    size_t xlen[N_X] = { 0 };
    uint64_t bundle_bytes = 0, bundle_key_bytes = 0, x_bytes[N_X] = { 0 };
    uint32_t max_nodes = 0;
    for (int s = 0; s < NS; s++) {
        max_nodes = sp[s].n_nodes > max_nodes ? sp[s].n_nodes : max_nodes;
    }
    float *pa = malloc(sizeof(float) * 3 * max_nodes), *pb = malloc(sizeof(float) * 3 * max_nodes);
    float *qf = malloc(sizeof(float) * stride), *qd = malloc(sizeof(float) * stride);
    uint64_t *hist = calloc(HBINS, sizeof *hist), *hist_shown = calloc(HBINS, sizeof *hist_shown);
    /* the server's float q of the last 8 ticks (render time is 6 ticks back) and the
       client's decoded snapshot and interpolated display */
    enum { RING = 8, DELAY_TICKS = 6 };
    float *ring = malloc(sizeof(float) * RING * (size_t)n_trees * stride);
    float *csnap = malloc(sizeof(float) * (size_t)n_trees * stride);
    float *shown = malloc(sizeof(float) * (size_t)n_trees * stride);
    jitter *jit = jitter_create(&(jitter_desc){ .n_values = (uint32_t)(n_trees * (int)stride),
                                                .playout_delay_s = 0.1 }, &err);
    enum { LEAF_CAP = 4096 };
    leaf_seed *shed = malloc(LEAF_CAP * sizeof *shed);
    wire_leaf *wl = malloc(LEAF_CAP * sizeof *wl);
    int n_shed = 0;
    const leaf_desc ld = { .rate_hz = 0.002f, .calm_ms = 3.0f, .ref_ms = 20.0f, .seed = 11 };
    const uint32_t slots = 1500; /* leaf slots per tree: the shipped species' 1500-5300 */
    /* the coarse wind slice of the default scene's 48 x 48 grid at 4 cells per coarse cell */
    enum { WNX = 12, WNY = 12 };
    int8_t slice[3 * WNX * WNY];
    uint64_t type_bytes[256] = { 0 }, type_frames[256] = { 0 }, ws_bytes = 0, text_bytes = 0,
             text_frames = 0, n_shown = 0;
    double shown_max = 0.0;
    if (!tree_sp || !yaw || !wind || !gu || !snap[0] || !snap[1] || !snap[2] || !nm ||
        !frame || !xbuf || !bundle || !pa || !pb || !qf || !qd || !hist || !hist_shown || !ring || !csnap ||
        !shown || !jit || !shed || !wl) {
        fprintf(stderr, "gale-bench wire: out of memory\n");
        return 1;
    }
    wire_scene scene = { .n_trees = (uint32_t)n_trees, .n_species = NS, .species = tree_sp };
    for (int s = 0; s < NS; s++) {
        scene.n_modes[s] = (uint8_t)n_modes;
        memcpy(scene.step[s], steps[s], sizeof(float) * (size_t)n_modes);
    }
    uint64_t rs = 777;
    for (int t = 0; t < n_trees; t++) {
        tree_sp[t] = (uint8_t)(t % NS);
        rs = rs * 6364136223846793005ull + 1442695040888963407ull;
        yaw[t] = (float)((double)(rs >> 11) * (6.283185307179586 / 9007199254740992.0));
        nm[t] = (uint8_t)n_modes;
        gust_init(&gu[t], &(gust_desc){ .seed = 1000 + (uint64_t)t, .intensity = intensity,
                                        .z_m = 8.0 });
    }
    modal *m = modal_create(&(modal_desc){ .n_trees = (uint32_t)n_trees, .n_species = NS,
                                           .species = msp, .tree_species = tree_sp,
                                           .tree_yaw_rad = yaw, .dt_s = 1.0 / 60,
                                           .n_threads = 1 },
                            &err);
    wire_decoder *dec = wire_decoder_create(&(wire_decoder_desc){ .max_trees = (uint32_t)n_trees,
                                                                  .max_modes = (uint32_t)n_modes },
                                            &err);
    if (!m || !dec) {
        fprintf(stderr, "gale-bench wire: %s\n", err.msg);
        return 1;
    }
    /* Wind blows towards +x on average; gusts along, across, up. Warm up 10 s so the
     * trees are swaying when measuring starts. */
    const double dt = 1.0 / 60;
    const int warm = 600, ticks = (int)(seconds * 60.0);
    const int key_every = (int)(keyframe_s * 30.0 + 0.5) > 0 ? (int)(keyframe_s * 30.0 + 0.5) : 1;
    uint64_t bytes_key = 0, bytes_delta = 0, n_key = 0, n_delta = 0, n_err = 0;
    double err_max = 0.0, q_disp_max = 0.0, enc_s = 0.0, dec_s = 0.0;
    double sp_disp[NS] = { 0 };
    int decode_errors = 0, mismatches = 0, hist_n = 0;
    uint32_t seq = 0;
    for (int k = -warm; k < ticks; k++) {
        for (int t = 0; t < n_trees; t++) {
            double g[3];
            gust_step(&gu[t], dt, mean_ms, g);
            wind[3 * t] = (float)(mean_ms + g[0]);
            wind[3 * t + 1] = (float)g[1];
            wind[3 * t + 2] = (float)g[2];
        }
        bool snap_tick = k >= 0 && k % 2 == 0; /* 60 Hz ticks, 30 snapshots/s */
        int16_t *cur = snap[(seq + 1) % 3];
        modal_tick(m, wind, snap_tick ? cur : NULL);
        if (k >= -RING) {
            float *rq = ring + (size_t)((k + warm) % RING) * (size_t)n_trees * stride;
            for (int t = 0; t < n_trees; t++) {
                modal_get(m, (uint32_t)t, rq + (size_t)t * stride, NULL);
            }
        }
        if (k >= 0) {
            for (int t = 0; t < n_trees; t++) {
                const float *v = &wind[3 * t];
                double sp_ms = sqrt((double)(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
                leaf_shed(&ld, (uint32_t)t, slots, sp_ms, (uint32_t)(k + warm), dt, shed,
                          LEAF_CAP, &n_shed);
            }
        }
        /* what the client displays at this tick: 0.1 s behind, interpolated; graded on
           the ticks of the graded snapshots and the ticks between them */
        if (k >= 2 * DELAY_TICKS && jitter_count(jit) >= 2 &&
            ((k / 2) % error_every) == 0) {
            double t_render = (double)k * 16667e-6 - (double)DELAY_TICKS / 60.0;
            jitter_sample(jit, t_render, shown, NULL);
            const float *truth =
                ring + (size_t)((k + warm - DELAY_TICKS) % RING) * (size_t)n_trees * stride;
            for (int t = 0; t < n_trees; t++) {
                const asset *a = &sp[tree_sp[t]];
                asset_reconstruct(a, truth + (size_t)t * stride, (uint32_t)n_modes, pa);
                asset_reconstruct(a, shown + (size_t)t * stride, (uint32_t)n_modes, pb);
                for (uint32_t i = 0; i < a->n_nodes; i++) {
                    double dx = (double)pa[3 * i] - (double)pb[3 * i];
                    double dy = (double)pa[3 * i + 1] - (double)pb[3 * i + 1];
                    double dz = (double)pa[3 * i + 2] - (double)pb[3 * i + 2];
                    double e = sqrt(dx * dx + dy * dy + dz * dz) / (double)a->height_m;
                    int bin = (int)(e / HMAX * HBINS);
                    hist_shown[bin < HBINS ? bin : HBINS - 1]++;
                    n_shown++;
                    shown_max = e > shown_max ? e : shown_max;
                }
            }
        }
        if (!snap_tick) {
            continue;
        }
        seq++;
        wire_state sc = { (uint32_t)n_trees, (uint32_t)stride, nm, cur };
        wire_state sp1 = { (uint32_t)n_trees, (uint32_t)stride, nm, snap[(seq + 2) % 3] };
        wire_state sp2 = { (uint32_t)n_trees, (uint32_t)stride, nm, snap[(seq + 1) % 3] };
        wire_header h = { .tick = (uint32_t)(k + warm), .server_time_us = (uint64_t)k * 16667 };
        size_t len = 0;
        double t0 = mono_s();
        int since_key = (int)((seq - 1) % (uint32_t)key_every);
        int rc;
        if (since_key == 0) {
            rc = wire_encode_keyframe(&h, seq, &scene, &sc, frame, cap, &len, &err);
        } else {
            rc = wire_encode_delta(&h, seq, &scene, &sc, &sp1, since_key >= 2 ? &sp2 : NULL,
                                   frame, cap, &len, &err);
        }
        double t1 = mono_s();
        if (rc) {
            fprintf(stderr, "gale-bench wire: encode: %s\n", err.msg);
            return 1;
        }
        wire_frame f;
        if (wire_decode(dec, frame, len, &f, &err) != 0) {
            decode_errors++;
        } else {
            for (int t = 0; t < n_trees; t++) {
                wire_decoder_q(dec, (uint32_t)t, csnap + (size_t)t * stride, (uint32_t)n_modes);
            }
            jitter_insert(jit, h.tick, (double)h.server_time_us * 1e-6, csnap, NULL);
        }
        type_bytes[frame[WIRE_TYPE_BYTE]] += len;
        type_frames[frame[WIRE_TYPE_BYTE]]++;
        ws_bytes += ws_header_bytes(len);
        /* the other frames a viewer gets with this snapshot (srv_publish.c's cadence) */
        if (seq % 15 == 1) { /* SRV_WIND_EVERY */
            for (int c = 0; c < 3 * WNX * WNY; c++) {
                /* a slice as gusty as the trees' wind: cell c/3 takes a tree's */
                float v = wind[3 * ((c / 3) % n_trees) + c % 3];
                slice[c] = wire_wind_quantize(v, (float)(mean_ms * 2.0 / 127.0 + 0.05));
            }
            wire_wind ww = { .x0_m = -60, .y0_m = -60, .z_m = 5, .cell_m = 10,
                             .scale_ms = (float)(mean_ms * 2.0 / 127.0 + 0.05), .nx = WNX,
                             .ny = WNY, .v = slice };
            size_t wlen = 0;
            h.type = WIRE_MSG_WIND;
            uint8_t *xw = xbuf + X_WIND * xcap;
            if (wire_encode_wind(&h, &ww, xw, xcap, &wlen, &err) == 0) {
                type_bytes[xw[WIRE_TYPE_BYTE]] += wlen;
                type_frames[xw[WIRE_TYPE_BYTE]]++;
                ws_bytes += ws_header_bytes(wlen);
                xlen[X_WIND] = wlen;
            }
        }
        if (n_shed && seq % 3 == 0) { /* SRV_LEAF_EVERY */
            uint32_t nl = (uint32_t)n_shed < WIRE_MAX_LEAVES ? (uint32_t)n_shed : WIRE_MAX_LEAVES;
            for (uint32_t i = 0; i < nl; i++) {
                wl[i] = (wire_leaf){ .instance = shed[i].instance, .slot = (uint16_t)shed[i].slot,
                                     .spawn_tick = shed[i].spawn_tick, .seed = shed[i].variation };
            }
            size_t llen = 0;
            h.type = WIRE_MSG_LEAVES;
            uint8_t *xl = xbuf + X_LEAVES * xcap;
            if (wire_encode_leaves(&h, wl, nl, xl, xcap, &llen, &err) == 0) {
                type_bytes[xl[WIRE_TYPE_BYTE]] += llen;
                type_frames[xl[WIRE_TYPE_BYTE]]++;
                ws_bytes += ws_header_bytes(llen);
                xlen[X_LEAVES] = llen;
            }
            n_shed = 0;
        }
        /* WEATHER: in every keyframe's bundle and every SRV_WEATHER_EVERY-th delta's; the
           whole damage state (no damage in a calm: no events) in every keyframe's */
        {
            wire_weather wx = { .sustained_ms = (float)mean_ms, .gust_ms = (float)(mean_ms * 1.4),
                                .dir_from_deg = 270.0f, .ss_class = 0, .beaufort = 3,
                                .storm_class = 255, .pressure_hpa = 1013.0f,
                                .distance_km = -1.0f, .name = "calm" };
            const bool key = since_key == 0;
            h.type = WIRE_MSG_WEATHER;
            if ((key || seq % 10 == 1) &&
                wire_encode_weather(&h, &wx, xbuf + X_WEATHER * xcap, xcap, &xlen[X_WEATHER],
                                    &err) != 0) {
                fprintf(stderr, "gale-bench wire: weather: %s\n", err.msg);
                return 1;
            }
            if (key && wire_encode_damage(&h, true, NULL, 0, xbuf + X_DAMAGE * xcap, xcap,
                                          &xlen[X_DAMAGE], &err) != 0) {
                fprintf(stderr, "gale-bench wire: damage: %s\n", err.msg);
                return 1;
            }
            const uint8_t *more[N_X];
            size_t more_len[N_X];
            uint32_t nx = 0;
            for (int x = 0; x < N_X; x++) {
                if (xlen[x]) {
                    more[nx] = xbuf + x * xcap;
                    more_len[nx++] = xlen[x];
                    x_bytes[x] += xlen[x];
                }
                xlen[x] = 0;
            }
            size_t blen = len;
            memcpy(bundle, frame, len);
            if (nx && wire_bundle_wrap(bundle, cap + N_X * xcap + 256, &blen, more, more_len, nx,
                                       &err) != 0) {
                fprintf(stderr, "gale-bench wire: bundle: %s\n", err.msg);
                return 1;
            }
            bundle_bytes += blen;
            bundle_key_bytes += key ? blen : 0;
        }
        if (seq % 15 == 0) { /* a pong for each ping (cli_net: every 0.5 s) */
            char pong[256];
            size_t plen = 0;
            ctl_msg pm = { .type = CTL_PONG, .u.pong = { .id = seq, .client_us = h.server_time_us,
                                                          .server_us = h.server_time_us,
                                                          .tick = h.tick } };
            if (ctl_encode_into(&pm, pong, sizeof pong, &plen, &err) == 0) {
                text_bytes += plen;
                text_frames++;
                ws_bytes += ws_header_bytes(plen);
            }
        }
        dec_s += mono_s() - t1;
        enc_s += t1 - t0;
        if (since_key == 0) {
            bytes_key += len;
            n_key++;
        } else {
            bytes_delta += len;
            n_delta++;
        }
        wire_state ds = wire_decoder_state(dec);
        if (memcmp(ds.q, cur, sizeof(int16_t) * (size_t)n_trees * stride) != 0) {
            mismatches++;
        }
        if ((seq % (uint32_t)error_every) != 0) {
            continue;
        }
        for (int t = 0; t < n_trees; t++) {
            const asset *a = &sp[tree_sp[t]];
            modal_get(m, (uint32_t)t, qf, NULL);
            wire_decoder_q(dec, (uint32_t)t, qd, (uint32_t)n_modes);
            asset_reconstruct(a, qf, (uint32_t)n_modes, pa);
            asset_reconstruct(a, qd, (uint32_t)n_modes, pb);
            for (uint32_t i = 0; i < a->n_nodes; i++) {
                double dx = (double)pa[3 * i] - (double)pb[3 * i];
                double dy = (double)pa[3 * i + 1] - (double)pb[3 * i + 1];
                double dz = (double)pa[3 * i + 2] - (double)pb[3 * i + 2];
                double e = sqrt(dx * dx + dy * dy + dz * dz) / (double)a->height_m;
                int bin = (int)(e / HMAX * HBINS);
                hist[bin < HBINS ? bin : HBINS - 1]++;
                n_err++;
                err_max = e > err_max ? e : err_max;
                double ux = (double)pa[3 * i] - (double)a->rest[3 * i];
                double uy = (double)pa[3 * i + 1] - (double)a->rest[3 * i + 1];
                double disp = sqrt(ux * ux + uy * uy) / (double)a->height_m;
                q_disp_max = disp > q_disp_max ? disp : q_disp_max;
                int si = tree_sp[t];
                sp_disp[si] = disp > sp_disp[si] ? disp : sp_disp[si];
            }
        }
        hist_n++;
    }
    uint64_t snaps = n_key + n_delta;
    double per_tree = (double)(bytes_key + bytes_delta) / (double)snaps / n_trees;
    double per_tree_delta = n_delta ? (double)bytes_delta / (double)n_delta / n_trees : 0.0;
    double per_tree_key = n_key ? (double)bytes_key / (double)n_key / n_trees : 0.0;
    double p50 = hist_pct(hist, n_err, 0.50), p99 = hist_pct(hist, n_err, 0.99);
    double kbps = (double)(bytes_key + bytes_delta) / seconds * 8.0 / 1000.0;
    double sp50 = hist_pct(hist_shown, n_shown, 0.50), sp99 = hist_pct(hist_shown, n_shown, 0.99);
    uint64_t all_bytes = ws_bytes + text_bytes;
    for (int t = 0; t < 256; t++) {
        all_bytes += type_bytes[t];
    }
    const char *recon = "asset_reconstruct";
    if (json) {
        printf("{\"bench\":\"wire\",\"seconds\":%.1f,\"trees\":%d,\"modes\":%d,\"species\":%d,"
               "\"species_nodes\":[%u,%u,%u],\"assets\":\"%s\",\"reconstruction\":\"%s\","
               "\"bake_s\":%.2f,"
               "\"wind_mean_ms\":%.1f,\"gust_intensity\":%.2f,\"eps\":%g,\"snapshot_hz\":30,"
               "\"keyframe_every_s\":%.1f,\"snapshots\":%llu,\"keyframes\":%llu,"
               "\"bytes_per_tree_per_snapshot\":%.2f,\"bytes_per_tree_delta\":%.2f,"
               "\"bytes_per_tree_keyframe\":%.2f,\"stream_kbit_s\":%.1f,"
               "\"node_error_p50_of_height\":%.6f,\"node_error_p99_of_height\":%.6f,"
               "\"node_error_max_of_height\":%.6f,\"node_samples\":%llu,"
               "\"max_node_displacement_of_height\":[%.4f,%.4f,%.4f],\"decode_errors\":%d,"
               "\"state_mismatches\":%d,\"encode_us_per_tree\":%.3f,\"decode_us_per_tree\":%.3f,"
               "\"target_bytes\":24,\"target_p99\":0.005,",
               seconds, n_trees, n_modes, NS, sp[0].n_nodes, sp[1].n_nodes, sp[2].n_nodes,
               synthetic ? "synthetic skeletons baked by fem+eigen+basis+pose fields"
                         : "configs/species oak, palm, pine baked by bake_run",
               recon, t_bake,
               mean_ms, intensity, eps, keyframe_s, (unsigned long long)snaps,
               (unsigned long long)n_key, per_tree, per_tree_delta, per_tree_key, kbps, p50, p99,
               err_max, (unsigned long long)n_err, sp_disp[0], sp_disp[1], sp_disp[2], decode_errors, mismatches,
               enc_s / (double)snaps / n_trees * 1e6, dec_s / (double)snaps / n_trees * 1e6);
        printf("\"bundled\":{\"bytes_per_tree_per_snapshot\":%.2f,"
               "\"bytes_per_tree_keyframe\":%.2f,\"extras_bytes_per_tree_per_snapshot\":"
               "{\"wind\":%.3f,\"leaves\":%.3f,\"weather\":%.3f,\"damage_state\":%.3f},"
               "\"of_state_alone\":%.3f},",
               (double)bundle_bytes / (double)snaps / n_trees,
               n_key ? (double)bundle_key_bytes / (double)n_key / n_trees : 0.0,
               (double)x_bytes[X_WIND] / (double)snaps / n_trees,
               (double)x_bytes[X_LEAVES] / (double)snaps / n_trees,
               (double)x_bytes[X_WEATHER] / (double)snaps / n_trees,
               (double)x_bytes[X_DAMAGE] / (double)snaps / n_trees,
               per_tree > 0.0 ? (double)bundle_bytes / (double)snaps / n_trees / per_tree : 0.0);
        printf("\"bytes_per_client_s_by_frame_type\":{");
        for (int t = 0, first = 1; t < 256; t++) {
            if (type_frames[t]) {
                printf("%s\"%d\":{\"frames\":%llu,\"bytes_per_s\":%.0f}", first ? "" : ",", t,
                       (unsigned long long)type_frames[t], (double)type_bytes[t] / seconds);
                first = 0;
            }
        }
        double load[3] = { 0 };
        FILE *lf = fopen("/proc/loadavg", "r");
        if (lf) {
            if (fscanf(lf, "%lf %lf %lf", &load[0], &load[1], &load[2]) != 3) {
                load[0] = -1;
            }
            fclose(lf);
        }
        printf("},\"text_pong_bytes_per_s\":%.0f,\"websocket_header_bytes_per_s\":%.0f,"
               "\"bytes_per_client_s\":%.0f,\"bytes_per_tree_per_client_s\":%.2f,"
               "\"shown_node_error_p50_of_height\":%.6f,\"shown_node_error_p99_of_height\":%.6f,"
               "\"shown_node_error_max_of_height\":%.6f,\"shown_node_samples\":%llu,"
               "\"playout_delay_s\":0.1,\"leaf_slots_per_tree\":%u,\"loadavg\":[%.2f,%.2f,%.2f]}\n",
               (double)text_bytes / seconds, (double)ws_bytes / seconds,
               (double)all_bytes / seconds, (double)all_bytes / seconds / n_trees, sp50, sp99,
               shown_max, (unsigned long long)n_shown, slots, load[0], load[1], load[2]);
    } else {
        printf("wire: %d trees x %d modes, %.0f s gusty (mean %.1f m/s, I %.2f): %.2f bytes/tree/"
               "snapshot (deltas %.2f, keyframes %.2f), node error p99 %.4f%% of H (max %.4f%%), "
               "max sway %.2f%% of H, %d decode errors\n",
               n_trees, n_modes, seconds, mean_ms, intensity, per_tree, per_tree_delta,
               per_tree_key, p99 * 100, err_max * 100, q_disp_max * 100, decode_errors);
    }
    (void)hist_n;
    modal_destroy(m);
    wire_decoder_destroy(dec);
    for (int s = 0; s < NS; s++) {
        if (synthetic) {
            asset_fini(&sp[s]);
        } else {
            asset_fini(&sp[s]);
        }
    }
    for (int k = 0; k < 3; k++) {
        free(snap[k]);
    }
    free(tree_sp);
    free(yaw);
    free(wind);
    free(gu);
    free(nm);
    free(frame);
    free(xbuf);
    free(bundle);
    free(pa);
    free(pb);
    free(qf);
    free(qd);
    free(hist);
    free(hist_shown);
    free(ring);
    free(csnap);
    free(shown);
    free(shed);
    free(wl);
    jitter_destroy(jit);
    return decode_errors || mismatches ? 1 : 0;
}
