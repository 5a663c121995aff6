/* What protocol/'s decoders make of a batch of inputs, one canonical line each, for
 * tests/web/fuzz_web_decoders.mjs to hold web/wire.js and web/asset.js to. Input (a file,
 * read twice where a record's frames are sized first): records, each
 *   'W' u32 n, then n frames (u32 length, bytes): fed in order to one fresh wire_decoder,
 *       one line per frame;
 *   'A' u32 length, bytes: one asset file: a line of its hash64 and CRC-32, then a line of
 *       what asset_decode made of it.
 * A rejected input prints "E state" (GALE_E_STATE: the client resyncs) or "E bad", then
 * the error's text (not compared: the fuzzer prints it beside a disagreement). An
 * accepted one prints its values, floats as their bit patterns (u32), in the order the
 * fuzzer prints the JavaScript decoders' (every field the browser reads; a FOREST's also as
 * the DAMAGE events wire_forest_events makes of it). */
#include <inttypes.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "asset.h"
#include "hash.h"
#include "wire.h"

static uint32_t bits(float x)
{
    uint32_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}

static void fbits(const char *tag, const float *v, size_t n)
{
    printf(" %s", tag);
    for (size_t i = 0; i < n; i++) {
        printf("%s%" PRIu32, i ? "," : "", bits(v[i]));
    }
}

static void ubits(const char *tag, const uint32_t *v, size_t n)
{
    printf(" %s", tag);
    for (size_t i = 0; i < n; i++) {
        printf("%s%" PRIu32, i ? "," : "", v[i]);
    }
}

static void hex(const char *tag, const uint8_t *s, size_t n)
{
    printf(" %s", tag);
    for (size_t i = 0; i < n; i++) {
        printf("%02x", s[i]);
    }
}

/* server_time_us as the double a JavaScript Number holds (exact below 2^53 us). */
static void header(const wire_header *h)
{
    printf(" H%u,%" PRIu32 ",%.0f", (unsigned)h->type, h->tick, (double)h->server_time_us);
}

static void state(const wire_decoder *d, const wire_frame *f)
{
    const wire_scene *sc = wire_decoder_scene(d);
    const wire_state st = wire_decoder_state(d);
    printf(" S%" PRIu32 " C%" PRIu32 ",%" PRIu32 ":", f->seq, sc->n_trees, sc->n_species);
    for (uint32_t s = 0; s < sc->n_species; s++) {
        printf("%s%u", s ? "," : "", (unsigned)sc->n_modes[s]);
    }
    for (uint32_t s = 0; s < sc->n_species; s++) {
        fbits(":", sc->step[s], sc->n_modes[s]);
    }
    printf(" T");
    for (uint32_t t = 0; t < sc->n_trees; t++) {
        printf("%s%u", t ? "," : "", (unsigned)sc->species[t]);
    }
    printf(" M");
    for (uint32_t t = 0; t < st.n_trees; t++) {
        printf("%s%u", t ? "," : "", (unsigned)st.n_modes[t]);
    }
    printf(" Q");
    bool first = true;
    for (uint32_t t = 0; t < st.n_trees; t++) {
        for (uint32_t m = 0; m < st.n_modes[t]; m++) {
            printf("%s%d", first ? "" : ",", (int)st.q[(size_t)t * st.stride + m]);
            first = false;
        }
    }
}

static void frame(const wire_decoder *d, const wire_frame *f)
{
    printf("T%" PRIu32, f->types);
    header(&f->hdr);
    if (f->types & ((1u << WIRE_MSG_KEYFRAME) | (1u << WIRE_MSG_DELTA))) {
        state(d, f);
    }
    if (f->types & (1u << WIRE_MSG_LEAVES)) {
        printf(" L");
        for (uint32_t i = 0; i < f->n_leaves; i++) {
            const wire_leaf *l = &f->leaves[i];
            printf("%s%" PRIu32 ",%u,%" PRIu32 ",%" PRIu32, i ? ";" : "", l->instance,
                   (unsigned)l->slot, l->spawn_tick, l->seed);
        }
    }
    if (f->types & (1u << WIRE_MSG_WIND)) {
        const wire_wind *w = &f->wind;
        const float v[5] = { w->x0_m, w->y0_m, w->z_m, w->cell_m, w->scale_ms };
        fbits("W", v, 5);
        printf(",%u,%u:", (unsigned)w->nx, (unsigned)w->ny);
        for (size_t i = 0; i < (size_t)3 * w->nx * w->ny; i++) {
            printf("%s%d", i ? "," : "", (int)w->v[i]);
        }
    }
    if (f->types & (1u << WIRE_MSG_WEATHER)) {
        const wire_weather *w = &f->weather;
        const float v[5] = { w->sustained_ms, w->gust_ms, w->dir_from_deg, w->pressure_hpa,
                             w->central_hpa };
        fbits("X", v, 5);
        const float u[6] = { w->distance_km, w->bearing_deg, w->storm_min, w->replay_pos_s,
                             w->replay_len_s, w->replay_speed };
        fbits("", u, 6);
        printf(" %u,%u,%u,%u,%" PRIu32 ",%d", (unsigned)w->ss_class, (unsigned)w->beaufort,
               (unsigned)w->flags, (unsigned)w->storm_class, w->utc_min, (int)w->utc_offset_min);
        hex("N", (const uint8_t *)w->name, strlen(w->name));
    }
    if (f->types & (1u << WIRE_MSG_DAMAGE)) {
        printf(" D%d:", f->damage_full ? 1 : 0);
        for (uint32_t i = 0; i < f->n_damage; i++) {
            const wire_damage *e = &f->damage[i];
            printf("%s%" PRIu32 ",%" PRIu32 ",%u,%u,%" PRIu32, i ? ";" : "", e->tree, e->node,
                   (unsigned)e->kind, (unsigned)e->value, e->tick);
        }
    }
    if (f->types & (1u << WIRE_MSG_FOREST)) {
        printf(" F%" PRIu32 ",%" PRIu32 ":", f->forest_first, f->forest_count);
        hex("", f->forest_state, f->forest_count);
        printf(" :");
        for (uint32_t i = 0; i < f->n_forest_fall; i++) {
            printf("%s%u,%" PRIu32, i ? ";" : "", (unsigned)f->forest_fall[i].az,
                   f->forest_fall[i].tick);
        }
        /* and as the DAMAGE events it stands for (wire_forest_events) */
        const uint32_t n = wire_forest_events(f, NULL, 0);
        wire_damage *ev = malloc((size_t)n * sizeof *ev + 1);
        if (!ev) {
            printf(" G?");
        } else {
            printf(" G%" PRIu32 ":", wire_forest_events(f, ev, n));
            for (uint32_t i = 0; i < n; i++) {
                printf("%s%" PRIu32 ",%" PRIu32 ",%u,%u,%" PRIu32, i ? ";" : "", ev[i].tree,
                       ev[i].node, (unsigned)ev[i].kind, (unsigned)ev[i].value, ev[i].tick);
            }
            free(ev);
        }
    }
    printf("\n");
}

static void asset_line(const uint8_t *b, size_t n)
{
    printf("H%016" PRIx64 ",%08" PRIx32 "\n", hash64(b, n), hash_crc32(b, n));
    asset a;
    gale_err e;
    if (asset_decode(b, n, "fuzz", &a, &e) != 0) {
        printf("E bad %s\n", e.msg);
        return;
    }
    const size_t nn = a.n_nodes, nm = a.n_modes, nv = a.n_verts, nl = a.n_leaves;
    hex("ok", (const uint8_t *)a.species, strnlen(a.species, sizeof a.species));
    printf(" %zu", nn);
    fbits("h", &a.height_m, 1);
    printf(" p");
    for (size_t i = 0; i < nn; i++) {
        printf("%s%" PRId32, i ? "," : "", a.parent[i]);
    }
    fbits("r", a.rest, 3 * nn);
    fbits("R", a.radius, nn);
    printf(" m%zu", nm);
    if (nm && a.corr_v) {
        fbits("v", a.corr_v, 3 * nm * nn);
        fbits("w", a.corr_w, 3 * nm * nn);
        fbits("a", a.corr_a, nm);
        fbits("b", a.corr_b, nm);
    } else if (nm) {
        printf(" nocorr");
    }
    fbits("P", a.mesh_pos, 3 * nv);
    fbits("n", a.mesh_normal, 3 * nv);
    ubits("B", a.mesh_bone, 2 * nv);
    fbits("g", a.mesh_weight, nv);
    ubits("I", a.mesh_index, a.n_indices);
    printf(" l%" PRIu32, a.n_lods);
    ubits(":", a.lod_first, a.n_lods);
    ubits(":", a.lod_count, a.n_lods);
    ubits("L", a.leaf_node, nl);
    fbits("o", a.leaf_offset, 3 * nl);
    fbits("N", a.leaf_normal, 3 * nl);
    fbits("s", a.leaf_size, nl);
    fbits("k", a.bark_rgb, 3);
    fbits("K", a.leaf_rgb, 3);
    printf(" S%" PRIu32 "\n", a.leaf_shape);
    asset_fini(&a);
}

static bool get32(FILE *f, uint32_t *v)
{
    uint8_t b[4];
    if (fread(b, 1, 4, f) != 4) {
        return false;
    }
    *v = (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
    return true;
}

/* A length-prefixed byte string into *buf (grown as needed); false at a short read. */
static bool get_bytes(FILE *f, uint8_t **buf, size_t *cap, uint32_t *n)
{
    if (!get32(f, n)) {
        return false;
    }
    if (*n > *cap) {
        uint8_t *nb = realloc(*buf, *n);
        if (!nb) {
            return false;
        }
        *buf = nb;
        *cap = *n;
    }
    return fread(*buf, 1, *n, f) == *n;
}

int main(int argc, char **argv)
{
    if (argc != 2 || !strcmp(argv[1], "--help")) {
        bool help = argc == 2;
        fprintf(help ? stdout : stderr,
                "usage: gale-web-decode-dump FILE\n"
                "  decodes each record of FILE ('W' u32 n then n frames of u32 length and bytes;\n"
                "  'A' u32 length and an asset file) with protocol/'s decoders and prints one\n"
                "  canonical line per frame, two per asset (hash64 and CRC-32, then the decode)\n");
        return help ? 0 : 2;
    }
    FILE *f = fopen(argv[1], "rb");
    if (!f) {
        fprintf(stderr, "gale-web-decode-dump: %s: cannot open\n", argv[1]);
        return 1;
    }
    uint8_t *buf = NULL;
    size_t cap = 0;
    long rec = 0;
    int kind, rc = 0;
    while ((kind = fgetc(f)) != EOF) {
        uint32_t n;
        if (kind == 'A') {
            if (!get_bytes(f, &buf, &cap, &n)) {
                rc = 1;
                break;
            }
            asset_line(buf, n);
        } else if (kind == 'W' && get32(f, &n)) {
            /* the decoder is made for as many trees as the longest frame has bytes: a
             * KEYFRAME spends a byte per tree, so none that decodes needs more, and one
             * that claims more is refused either way (the protocol's limit alone would
             * cost 100 MB a record) */
            long start = ftell(f);
            uint32_t most = 1;
            for (uint32_t i = 0; i < n && rc == 0; i++) {
                uint32_t len;
                if (!get32(f, &len) || fseek(f, (long)len, SEEK_CUR) != 0) {
                    rc = 1;
                }
                most = len > most ? len : most;
            }
            if (rc || fseek(f, start, SEEK_SET) != 0) {
                rc = 1;
                break;
            }
            gale_err e;
            wire_decoder *d = wire_decoder_create(
                &(wire_decoder_desc){ .max_trees = most < WIRE_MAX_TREES ? most : WIRE_MAX_TREES }, &e);
            if (!d) {
                fprintf(stderr, "gale-web-decode-dump: %s\n", e.msg);
                rc = 1;
                break;
            }
            for (uint32_t i = 0; i < n && rc == 0; i++) {
                uint32_t len;
                if (!get_bytes(f, &buf, &cap, &len)) {
                    rc = 1;
                    break;
                }
                wire_frame fr;
                if (wire_decode(d, buf, len, &fr, &e) != 0) {
                    printf("E %s %s\n", e.code == GALE_E_STATE ? "state" : "bad", e.msg);
                } else {
                    frame(d, &fr);
                }
            }
            wire_decoder_destroy(d);
        } else {
            rc = 1;
        }
        if (rc) {
            break;
        }
        rec++;
    }
    if (rc) {
        fprintf(stderr, "gale-web-decode-dump: %s: record %ld: truncated or unknown kind\n",
                argv[1], rec);
    }
    free(buf);
    fclose(f);
    return rc;
}
