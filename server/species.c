/* Species files (configs/species/NAME.json): generator parameters for the L-system of
 * Oliapuram & Kumar 2010 section 1.4, wood and damping constants for the bake (Diener
 * 2008 section 3, eq. 9), the look of bark and leaves. Validated through cfg.h. */
#include "species.h"

#include <stdio.h>
#include <string.h>

#include "cfg.h"

void species_default(species *sp)
{
    memset(sp, 0, sizeof *sp);
    snprintf(sp->name, sizeof sp->name, "%s", "tree");
    sp->E_pa = 1e10;
    sp->rho_kg_m3 = 1000.0;
    sp->G_pa = sp->E_pa / 2.6;
    sp->rayleigh_alpha = 0.2;
    sp->rayleigh_beta = 0.004;
    /* ½ ρ_air C_D with ρ_air = 1.2 kg/m^3 and C_D = 1 for a cylinder in cross flow */
    sp->drag_c = 0.6;
    sp->gen = lsystem_params_default();
    sp->bark_rgb[0] = 0.36f;
    sp->bark_rgb[1] = 0.27f;
    sp->bark_rgb[2] = 0.20f;
    sp->leaf_rgb[0] = 0.25f;
    sp->leaf_rgb[1] = 0.45f;
    sp->leaf_rgb[2] = 0.15f;
    sp->leaf_shape = 0;
    sp->leaf_size_m = 0.12f;
    sp->leaves_per_tip = 4;
    sp->leaf_spread_deg = 40.0f;
}

static int sp_int(const cfg_doc *d, const cJSON *o, const char *path, const char *key,
                  long long min, long long max, int *out, gale_err *err)
{
    long long v;
    int rc = cfg_int(d, o, path, key, false, *out, min, max, &v, err);
    if (rc == 0) {
        *out = (int)v;
    }
    return rc;
}

static int sp_num(const cfg_doc *d, const cJSON *o, const char *path, const char *key,
                  double min, double max, double *out, gale_err *err)
{
    return cfg_number(d, o, path, key, false, *out, min, max, out, err);
}

/* obj[key] as an optional object: *o NULL when absent; a wrong type is an error. */
static int sp_section(const cfg_doc *d, const cJSON *parent, const char *path, const char *key,
                      const cJSON **o, gale_err *err)
{
    gale_err e = { 0 };
    bool found;
    *o = cfg_child(d, parent, path, key, cJSON_Object, false, &found, &e);
    if (!*o && e.code != 0) {
        if (err) {
            *err = e;
        }
        return e.code;
    }
    return GALE_OK;
}

static int sp_rule(const cfg_doc *d, const cJSON *parent, const char *path, const char *key,
                   lsystem_rule *r, gale_err *err)
{
    static const char *const keys[] = { "whorls", "per_whorl", "start", "end", "angle_deg",
                                        "tip_children", "tip_angle_deg", "tip_continue",
                                        "continue_ratio", "angle_jitter_deg", "length_ratio",
                                        "length_top", "length_jitter", "radius_ratio", "taper",
                                        "bend_deg", "prune_prob", NULL };
    const cJSON *o;
    int src = sp_section(d, parent, path, key, &o, err);
    if (src != 0 || !o) {
        return src;
    }
    char p[256];
    cfg_path(p, sizeof p, path, key);
    int rc = cfg_check_keys(d, o, p, keys, err);
    bool cont = r->tip_continue != 0;
    if (rc == 0) rc = sp_int(d, o, p, "whorls", 0, 64, &r->whorls, err);
    if (rc == 0) rc = sp_int(d, o, p, "per_whorl", 0, 16, &r->per_whorl, err);
    if (rc == 0) rc = sp_num(d, o, p, "start", 0.0, 1.0, &r->start, err);
    if (rc == 0) rc = sp_num(d, o, p, "end", 0.0, 1.0, &r->end, err);
    if (rc == 0) rc = sp_num(d, o, p, "angle_deg", 0.0, 180.0, &r->angle_deg, err);
    if (rc == 0) rc = sp_int(d, o, p, "tip_children", 0, 32, &r->tip_children, err);
    if (rc == 0) rc = sp_num(d, o, p, "tip_angle_deg", 0.0, 180.0, &r->tip_angle_deg, err);
    if (rc == 0) rc = cfg_bool(d, o, p, "tip_continue", false, cont, &cont, err);
    if (rc == 0) rc = sp_num(d, o, p, "continue_ratio", 0.0, 2.0, &r->continue_ratio, err);
    if (rc == 0) rc = sp_num(d, o, p, "angle_jitter_deg", 0.0, 90.0, &r->angle_jitter_deg, err);
    if (rc == 0) rc = sp_num(d, o, p, "length_ratio", 0.01, 2.0, &r->length_ratio, err);
    if (rc == 0) rc = sp_num(d, o, p, "length_top", 0.01, 4.0, &r->length_top, err);
    if (rc == 0) rc = sp_num(d, o, p, "length_jitter", 0.0, 0.9, &r->length_jitter, err);
    if (rc == 0) rc = sp_num(d, o, p, "radius_ratio", 0.01, 1.0, &r->radius_ratio, err);
    if (rc == 0) rc = sp_num(d, o, p, "taper", 0.01, 1.0, &r->taper, err);
    if (rc == 0) rc = sp_num(d, o, p, "bend_deg", -180.0, 180.0, &r->bend_deg, err);
    if (rc == 0) rc = sp_num(d, o, p, "prune_prob", 0.0, 1.0, &r->prune_prob, err);
    if (rc != 0) {
        return rc;
    }
    r->tip_continue = cont ? 1 : 0;
    if (r->start > r->end) {
        return gale_errf(err, GALE_E_RANGE, "%s: %s.start: expected <= end (%g), got %g", d->name,
                         p, r->end, r->start);
    }
    if (r->tip_continue && !(r->continue_ratio > 0.0)) {
        return gale_errf(err, GALE_E_RANGE, "%s: %s.continue_ratio: expected > 0 with tip_continue",
                         d->name, p);
    }
    return GALE_OK;
}

static int sp_generator(const cfg_doc *d, const cJSON *root, lsystem_params *g, gale_err *err)
{
    static const char *const keys[] = { "seed", "target_nodes", "depth", "trunk_length_m",
                                        "trunk_radius_m", "trunk_taper", "trunk_bend_deg",
                                        "segment_m", "twist_deg", "twist_jitter_deg",
                                        "wobble_deg", "trunk", "branch", NULL };
    const cJSON *o;
    int src = sp_section(d, root, "", "generator", &o, err);
    if (src != 0 || !o) {
        return src;
    }
    const char *p = "generator";
    int rc = cfg_check_keys(d, o, p, keys, err);
    long long seed = (long long)(g->seed & 0x7fffffffffffffffull);
    /* 2^53: every integer below it is exact in a JSON number */
    if (rc == 0) rc = cfg_int(d, o, p, "seed", false, seed, 0, 9007199254740992LL, &seed, err);
    if (rc == 0) rc = sp_int(d, o, p, "target_nodes", 0, 1000000, &g->target_nodes, err);
    if (rc == 0) rc = sp_int(d, o, p, "depth", 0, 10, &g->depth, err);
    if (rc == 0) rc = sp_num(d, o, p, "trunk_length_m", 0.1, 200.0, &g->trunk_length_m, err);
    if (rc == 0) rc = sp_num(d, o, p, "trunk_radius_m", 0.001, 10.0, &g->trunk_radius_m, err);
    if (rc == 0) rc = sp_num(d, o, p, "trunk_taper", 0.01, 1.0, &g->trunk_taper, err);
    if (rc == 0) rc = sp_num(d, o, p, "trunk_bend_deg", -180.0, 180.0, &g->trunk_bend_deg, err);
    if (rc == 0) rc = sp_num(d, o, p, "segment_m", 0.0, 100.0, &g->segment_m, err);
    if (rc == 0) rc = sp_num(d, o, p, "twist_deg", -360.0, 360.0, &g->twist_deg, err);
    if (rc == 0) rc = sp_num(d, o, p, "twist_jitter_deg", 0.0, 180.0, &g->twist_jitter_deg, err);
    if (rc == 0) rc = sp_num(d, o, p, "wobble_deg", 0.0, 90.0, &g->wobble_deg, err);
    if (rc == 0) rc = sp_rule(d, o, p, "trunk", &g->trunk, err);
    if (rc == 0) rc = sp_rule(d, o, p, "branch", &g->branch, err);
    if (rc == 0) {
        g->seed = (uint64_t)seed;
    }
    return rc;
}

static int sp_rgb(const cfg_doc *d, const cJSON *o, const char *path, const char *key,
                  float rgb[3], gale_err *err)
{
    double v[3] = { rgb[0], rgb[1], rgb[2] };
    int rc = cfg_vec(d, o, path, key, false, 3, v, 0.0, 1.0, v, err);
    if (rc == 0) {
        for (int i = 0; i < 3; i++) {
            rgb[i] = (float)v[i];
        }
    }
    return rc;
}

static int sp_look(const cfg_doc *d, const cJSON *root, species *sp, gale_err *err)
{
    static const char *const keys[] = { "bark_rgb", "leaf_rgb", "leaf_shape", "leaf_size_m",
                                        "leaves_per_tip", "leaf_spread_deg", NULL };
    static const char *const shapes[] = { "broad", "palm", "needle" };
    const cJSON *o;
    int src = sp_section(d, root, "", "look", &o, err);
    if (src != 0 || !o) {
        return src;
    }
    const char *p = "look";
    int rc = cfg_check_keys(d, o, p, keys, err);
    char shape[16];
    double size = sp->leaf_size_m, spread = sp->leaf_spread_deg;
    if (rc == 0) rc = sp_rgb(d, o, p, "bark_rgb", sp->bark_rgb, err);
    if (rc == 0) rc = sp_rgb(d, o, p, "leaf_rgb", sp->leaf_rgb, err);
    if (rc == 0) {
        rc = cfg_string(d, o, p, "leaf_shape", false, shapes[sp->leaf_shape], shape, sizeof shape, err);
    }
    if (rc == 0) rc = cfg_number(d, o, p, "leaf_size_m", false, size, 0.005, 10.0, &size, err);
    if (rc == 0) rc = sp_int(d, o, p, "leaves_per_tip", 0, 64, &sp->leaves_per_tip, err);
    if (rc == 0) rc = cfg_number(d, o, p, "leaf_spread_deg", false, spread, 0.0, 180.0, &spread, err);
    if (rc != 0) {
        return rc;
    }
    sp->leaf_size_m = (float)size;
    sp->leaf_spread_deg = (float)spread;
    for (int i = 0; i < 3; i++) {
        if (strcmp(shape, shapes[i]) == 0) {
            sp->leaf_shape = i;
            return GALE_OK;
        }
    }
    return gale_errf(err, GALE_E_RANGE,
                     "%s: look.leaf_shape: expected \"broad\", \"palm\" or \"needle\", got \"%s\"",
                     d->name, shape);
}

static int sp_from_doc(const cfg_doc *d, species *sp, gale_err *err)
{
    static const char *const keys[] = { "name", "E_pa", "rho_kg_m3", "G_pa", "rayleigh_alpha",
                                        "rayleigh_beta", "drag_c", "generator", "look", NULL };
    const cJSON *r = d->root;
    int rc = cfg_check_keys(d, r, "", keys, err);
    double G = -1.0;
    if (rc == 0) rc = cfg_string(d, r, "", "name", true, NULL, sp->name, sizeof sp->name, err);
    /* wood: E of green timber is 5-15 GPa; palm stems ~2-8 GPa; the bounds allow model tests */
    if (rc == 0) rc = sp_num(d, r, "", "E_pa", 1e6, 1e12, &sp->E_pa, err);
    if (rc == 0) rc = sp_num(d, r, "", "rho_kg_m3", 10.0, 20000.0, &sp->rho_kg_m3, err);
    if (rc == 0) rc = cfg_number(d, r, "", "G_pa", false, -1.0, 1e5, 1e12, &G, err);
    if (rc == 0) rc = sp_num(d, r, "", "rayleigh_alpha", 0.0, 100.0, &sp->rayleigh_alpha, err);
    if (rc == 0) rc = sp_num(d, r, "", "rayleigh_beta", 0.0, 1.0, &sp->rayleigh_beta, err);
    if (rc == 0) rc = sp_num(d, r, "", "drag_c", 0.0, 100.0, &sp->drag_c, err);
    if (rc == 0) rc = sp_generator(d, r, &sp->gen, err);
    if (rc == 0) rc = sp_look(d, r, sp, err);
    if (rc != 0) {
        return rc;
    }
    if (sp->name[0] == '\0') {
        return gale_errf(err, GALE_E_RANGE, "%s: name: expected a non-empty string", d->name);
    }
    /* ν ≈ 0.3: G = E / (2 (1 + ν)) = E / 2.6 unless given */
    sp->G_pa = G > 0.0 ? G : sp->E_pa / 2.6;
    return GALE_OK;
}

int species_parse(const char *text, size_t len, const char *name, species *sp, gale_err *err)
{
    cfg_doc d;
    species_default(sp);
    int rc = cfg_parse(&d, name ? name : "<species>", text, len, err);
    if (rc != 0) {
        return rc;
    }
    rc = sp_from_doc(&d, sp, err);
    cfg_fini(&d);
    if (rc != 0) {
        species_default(sp);
    }
    return rc;
}

int species_load(const char *path, species *sp, gale_err *err)
{
    cfg_doc d;
    species_default(sp);
    int rc = cfg_load(&d, path, err);
    if (rc != 0) {
        return rc;
    }
    rc = sp_from_doc(&d, sp, err);
    cfg_fini(&d);
    if (rc != 0) {
        species_default(sp);
    }
    return rc;
}
