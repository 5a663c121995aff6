/* L-system generator (Oliapuram & Kumar 2010 section 1.4): structure invariants,
 * determinism, node-count targets, and the three shipped species looking like their
 * names (crown spread, palm crown of drooping fronds, conifer whorls). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "lsystem.h"
#include "species.h"

static species load_species(const char *name)
{
    char path[512];
    snprintf(path, sizeof path, "%s/configs/species/%s.json", GALE_SOURCE_DIR, name);
    species sp;
    gale_err err = { 0 };
    int rc = species_load(path, &sp, &err);
    if (rc != 0) {
        fprintf(stderr, "%s\n", err.msg);
    }
    CHECK(rc == 0);
    return sp;
}

static double elem_len(const skeleton *s, int i)
{
    const float *a = &s->pos[3 * i], *b = &s->pos[3 * s->parent[i]];
    double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return sqrt(dx * dx + dy * dy + dz * dz);
}

/* Invariants every generated skeleton keeps. */
static void check_structure(const skeleton *s, double trunk_len)
{
    CHECK(s->n > 1);
    CHECK(s->parent[0] == -1);
    CHECK(s->pos[0] == 0.0f && s->pos[1] == 0.0f && s->pos[2] == 0.0f);
    CHECK(s->order[0] == 0);
    int bad_parent = 0, bad_radius = 0, bad_order = 0, short_elem = 0, bad_pos = 0;
    double min_len = 1e30;
    for (int i = 1; i < s->n; i++) {
        bad_parent += !(s->parent[i] >= 0 && s->parent[i] < i);
        bad_radius += !(s->radius[i] > 0.0f);
        bad_pos += !(isfinite(s->pos[3 * i]) && isfinite(s->pos[3 * i + 1]) &&
                     isfinite(s->pos[3 * i + 2]));
        if (s->parent[i] >= 0 && s->parent[i] < i) {
            bad_order += s->order[i] < s->order[s->parent[i]];
            double l = elem_len(s, i);
            min_len = fmin(min_len, l);
            /* segments are cut to >= 2% of the trunk; chords of curved pieces are a bit
             * shorter than their arcs, hence 0.9 */
            short_elem += l < 0.9 * 0.02 * trunk_len;
        }
    }
    CHECK(bad_parent == 0);
    CHECK(bad_radius == 0);
    CHECK(bad_order == 0);
    CHECK(bad_pos == 0);
    CHECK(short_elem == 0);
    if (short_elem) {
        fprintf(stderr, "  shortest element %.4g m, trunk %.3g m\n", min_len, trunk_len);
    }
}

static void test_default_structure(void)
{
    lsystem_params p = lsystem_params_default();
    skeleton s;
    gale_err err = { 0 };
    CHECK(lsystem_generate(&p, &s, &err) == 0);
    check_structure(&s, p.trunk_length_m);
    skeleton_fini(&s);
}

static void test_deterministic(void)
{
    species sp = load_species("oak");
    skeleton a, b, c;
    gale_err err = { 0 };
    CHECK(lsystem_generate(&sp.gen, &a, &err) == 0);
    CHECK(lsystem_generate(&sp.gen, &b, &err) == 0);
    sp.gen.seed += 1;
    CHECK(lsystem_generate(&sp.gen, &c, &err) == 0);
    CHECK(a.n == b.n);
    if (a.n == b.n) {
        CHECK(memcmp(a.parent, b.parent, (size_t)a.n * sizeof *a.parent) == 0);
        CHECK(memcmp(a.pos, b.pos, (size_t)a.n * 3 * sizeof *a.pos) == 0);
        CHECK(memcmp(a.radius, b.radius, (size_t)a.n * sizeof *a.radius) == 0);
    }
    /* another seed, another tree */
    CHECK(a.n != c.n || memcmp(a.pos, c.pos, (size_t)a.n * 3 * sizeof *a.pos) != 0);
    skeleton_fini(&a);
    skeleton_fini(&b);
    skeleton_fini(&c);
}

static void test_targets(void)
{
    species sp = load_species("oak");
    const int targets[] = { 300, 1000, 3500, 10000 };
    double h_prev = 0.0;
    for (int k = 0; k < 4; k++) {
        sp.gen.target_nodes = targets[k];
        skeleton s;
        gale_err err = { 0 };
        CHECK(lsystem_generate(&sp.gen, &s, &err) == 0);
        /* within 10% of the asked count */
        CHECK_NEAR(s.n, targets[k], 0.1 * targets[k]);
        check_structure(&s, sp.gen.trunk_length_m);
        double h = 0.0;
        for (int i = 0; i < s.n; i++) {
            h = fmax(h, s.pos[3 * i + 2]);
        }
        /* the same tree at another resolution: heights within 20% of each other */
        if (k > 0) {
            CHECK_NEAR(h / h_prev, 1.0, 0.2);
        }
        h_prev = h;
        skeleton_fini(&s);
    }
}

static void test_oak_shape(void)
{
    species sp = load_species("oak");
    skeleton s;
    gale_err err = { 0 };
    CHECK(lsystem_generate(&sp.gen, &s, &err) == 0);
    CHECK(s.n >= 3000 && s.n <= 4000);
    float lo[3] = { 1e9f, 1e9f, 1e9f }, hi[3] = { -1e9f, -1e9f, -1e9f };
    int max_order = 0;
    for (int i = 0; i < s.n; i++) {
        for (int k = 0; k < 3; k++) {
            lo[k] = fminf(lo[k], s.pos[3 * i + k]);
            hi[k] = fmaxf(hi[k], s.pos[3 * i + k]);
        }
        max_order = s.order[i] > max_order ? s.order[i] : max_order;
    }
    /* a spreading broadleaf crown: as wide as about 0.7-1.5 of its height */
    double width = 0.5 * (double)((hi[0] - lo[0]) + (hi[1] - lo[1]));
    CHECK(width > 0.7 * (double)hi[2] && width < 1.5 * (double)hi[2]);
    CHECK(max_order == sp.gen.depth);
    check_structure(&s, sp.gen.trunk_length_m);
    skeleton_fini(&s);
}

static void test_palm_shape(void)
{
    species sp = load_species("palm");
    skeleton s;
    gale_err err = { 0 };
    CHECK(lsystem_generate(&sp.gen, &s, &err) == 0);
    check_structure(&s, sp.gen.trunk_length_m);
    double trunk_top = 0.0;
    int top = 0;
    for (int i = 0; i < s.n; i++) {
        if (s.order[i] == 0 && (double)s.pos[3 * i + 2] > trunk_top) {
            trunk_top = s.pos[3 * i + 2];
            top = i;
        }
    }
    CHECK(trunk_top >= 12.0 && trunk_top <= 20.0);
    /* slight curve: the top is off the root's vertical, but by less than 15% of height */
    double off = hypot(s.pos[3 * top], s.pos[3 * top + 1]);
    CHECK(off > 0.01 * trunk_top && off < 0.15 * trunk_top);
    /* fronds: order-1 chains from the trunk top; each ends lower than where it starts,
     * and reaches out */
    int fronds = 0, drooping = 0, long_chain = 0;
    for (int i = 1; i < s.n; i++) {
        if (s.order[i] != 1 || s.parent[i] != top) {
            continue;
        }
        fronds++;
        int j = i, len = 1;
        for (;;) {
            int next = -1;
            for (int c = j + 1; c < s.n; c++) {
                if (s.parent[c] == j && s.order[c] == 1) {
                    next = c;
                    break;
                }
            }
            if (next < 0) {
                break;
            }
            j = next;
            len++;
        }
        drooping += s.pos[3 * j + 2] < s.pos[3 * i + 2];
        long_chain += len >= 5;
    }
    CHECK(fronds >= 12 && fronds <= 20);
    CHECK(drooping >= fronds * 3 / 4);
    CHECK(long_chain == fronds);
    skeleton_fini(&s);
}

static void test_conifer_shape(void)
{
    species sp = load_species("pine");
    skeleton s;
    gale_err err = { 0 };
    CHECK(lsystem_generate(&sp.gen, &s, &err) == 0);
    check_structure(&s, sp.gen.trunk_length_m);
    double h = 0.0;
    int top = 0;
    for (int i = 0; i < s.n; i++) {
        if (s.order[i] == 0 && (double)s.pos[3 * i + 2] > h) {
            h = s.pos[3 * i + 2];
            top = i;
        }
    }
    /* a straight monopodial trunk */
    CHECK(hypot(s.pos[3 * top], s.pos[3 * top + 1]) < 0.03 * h);
    /* first branches leave near-horizontal, and the ones high up are shorter */
    int steep = 0, n_low = 0, n_high = 0;
    double reach_low = 0.0, reach_high = 0.0;
    for (int i = 1; i < s.n; i++) {
        int p = s.parent[i];
        if (s.order[i] != 1 || s.order[p] != 0) {
            continue;
        }
        double dz = s.pos[3 * i + 2] - s.pos[3 * p + 2];
        double dh = hypot(s.pos[3 * i] - s.pos[3 * p], s.pos[3 * i + 1] - s.pos[3 * p + 1]);
        steep += fabs(atan2(dz, dh)) > 25.0 * 3.14159265 / 180.0;
        /* reach of this branch: farthest order-1 descendant in the chain from i */
        double reach = 0.0;
        for (int j = i; j < s.n; j++) {
            int a = j;
            while (a > i) {
                a = s.parent[a];
            }
            if (a == i && s.order[j] == 1) {
                reach = fmax(
                    reach, hypot(s.pos[3 * j] - s.pos[3 * p], s.pos[3 * j + 1] - s.pos[3 * p + 1]));
            }
        }
        if ((double)s.pos[3 * p + 2] < 0.5 * h) {
            reach_low += reach;
            n_low++;
        } else if ((double)s.pos[3 * p + 2] > 0.75 * h) {
            reach_high += reach;
            n_high++;
        }
    }
    CHECK(steep == 0);
    CHECK(n_low > 10 && n_high > 5);
    if (n_low && n_high) {
        CHECK(reach_high / n_high < 0.6 * reach_low / n_low);
    }
    skeleton_fini(&s);
}

static void test_bad_params(void)
{
    lsystem_params p = lsystem_params_default();
    skeleton s;
    gale_err err = { 0 };
    p.depth = 11;
    CHECK(lsystem_generate(&p, &s, &err) == GALE_E_RANGE);
    CHECK_STR_HAS(err.msg, "depth: expected 0..10, got 11");
    CHECK(s.n == 0 && s.parent == NULL);
    p = lsystem_params_default();
    p.trunk_length_m = 0.0;
    CHECK(lsystem_generate(&p, &s, &err) == GALE_E_RANGE);
    CHECK_STR_HAS(err.msg, "trunk");
    p = lsystem_params_default();
    p.branch.start = 0.9;
    p.branch.end = 0.2;
    CHECK(lsystem_generate(&p, &s, &err) == GALE_E_RANGE);
    CHECK_STR_HAS(err.msg, "branch: expected 0 <= start <= end <= 1");
    /* a grammar that explodes is refused, not allocated, naming the key to change */
    p = lsystem_params_default();
    p.depth = 10;
    p.branch.tip_children = 8;
    p.branch.prune_prob = 0.0;
    p.branch.length_ratio = 1.0;
    CHECK(lsystem_generate(&p, &s, &err) == GALE_E_RANGE);
    CHECK_STR_HAS(err.msg, "lsystem: generator.depth: 10 levels grow more than 200000 stems: "
                           "expected fewer (lower depth, whorls, per_whorl or tip_children)");
    CHECK(s.n == 0 && s.parent == NULL);
    /* with the source named (species_parse names it), the message starts with the file */
    snprintf(p.where, sizeof p.where, "%s", "oak.json");
    CHECK(lsystem_generate(&p, &s, &err) == GALE_E_RANGE);
    CHECK_STR_HAS(err.msg, "oak.json: generator.depth: 10 levels grow more than 200000 stems");
    CHECK(strncmp(err.msg, "oak.json: ", 10) == 0);
    snprintf(p.where, sizeof p.where, "%s", "");
    /* few enough stems (32 767), but 50 elements on each is past the node limit */
    p = lsystem_params_default();
    p.depth = 7;
    p.trunk.length_ratio = p.branch.length_ratio = 1.0;
    p.trunk.length_top = p.branch.length_top = 1.0;
    p.trunk.prune_prob = p.branch.prune_prob = 0.0;
    p.segment_m = 0.12;
    CHECK(lsystem_generate(&p, &s, &err) == GALE_E_RANGE);
    CHECK_STR_HAS(err.msg, "lsystem: generator.segment_m: 1633924 nodes with 0.12 m elements: "
                           "expected at most 1000000 (longer segment_m, or set target_nodes)");
    CHECK(s.n == 0 && s.parent == NULL);
    /* the same grammar with a node target fits */
    p.target_nodes = 5000;
    CHECK(lsystem_generate(&p, &s, &err) == 0);
    CHECK(s.n > 0 && s.n < 200000);
    skeleton_fini(&s);
}

int main(void)
{
    RUN(test_default_structure);
    RUN(test_deterministic);
    RUN(test_targets);
    RUN(test_oak_shape);
    RUN(test_palm_shape);
    RUN(test_conifer_shape);
    RUN(test_bad_params);
    return check_report();
}
