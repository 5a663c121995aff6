/* Species files (configs/species/NAME.json): generator parameters for the L-system of
 * Oliapuram & Kumar 2010 section 1.4, wood and damping constants for the bake (Diener
 * 2008 section 3, eq. 9), the look of bark and leaves. Validated through cfg.h from
 * tables of keys with their ranges; JSON keys are the struct field names. */
#include "species.h"

#include <stddef.h>
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
    /* rigid drag unless the file says otherwise; the fits start near 10 m/s and end
     * near 25 m/s, above which C_d holds (PHYSICS.md "Streamlining") */
    sp->drag.vogel_b = 0.0f;
    sp->drag.u0_ms = 10.0f;
    sp->drag.fit_max_ms = 25.0f;
    sp->drag.hold_above_fit = 1;
    sp->damage = damage_params_default();
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

typedef enum sp_kind {
    SP_INT,  /* int */
    SP_BOOL, /* int, 0 or 1, from a JSON boolean */
    SP_DBL,  /* double */
    SP_FLT,  /* float */
    SP_RGB,  /* float[3], each in [min, max] */
    SP_SEED, /* uint64_t, an integer below 2^53 so that JSON holds it exactly */
} sp_kind;

/* One optional key: its kind, allowed range, and where it lands in the struct. */
typedef struct sp_field {
    const char *key;
    sp_kind kind;
    double min, max;
    size_t off;
} sp_field;

/* clang-format off */
#define RULE(k, kind, lo, hi) { #k, kind, lo, hi, offsetof(lsystem_rule, k) }
/* clang-format on */
static const sp_field rule_fields[] = {
    RULE(whorls, SP_INT, 0, 64),
    RULE(per_whorl, SP_INT, 0, 16),
    RULE(start, SP_DBL, 0.0, 1.0),
    RULE(end, SP_DBL, 0.0, 1.0),
    RULE(angle_deg, SP_DBL, 0.0, 180.0),
    RULE(tip_children, SP_INT, 0, 32),
    RULE(tip_angle_deg, SP_DBL, 0.0, 180.0),
    RULE(tip_continue, SP_BOOL, 0, 1),
    RULE(continue_ratio, SP_DBL, 0.0, 2.0),
    RULE(angle_jitter_deg, SP_DBL, 0.0, 90.0),
    RULE(length_ratio, SP_DBL, 0.01, 2.0),
    RULE(length_top, SP_DBL, 0.01, 4.0),
    RULE(length_jitter, SP_DBL, 0.0, 0.9),
    RULE(radius_ratio, SP_DBL, 0.01, 1.0),
    RULE(taper, SP_DBL, 0.01, 1.0),
    RULE(bend_deg, SP_DBL, -180.0, 180.0),
    RULE(prune_prob, SP_DBL, 0.0, 1.0),
};
#undef RULE

/* clang-format off */
#define GEN(k, kind, lo, hi) { #k, kind, lo, hi, offsetof(lsystem_params, k) }
/* clang-format on */
static const sp_field gen_fields[] = {
    GEN(seed, SP_SEED, 0.0, 9007199254740992.0),
    GEN(target_nodes, SP_INT, 0, 1000000),
    GEN(depth, SP_INT, 0, 10),
    GEN(trunk_length_m, SP_DBL, 0.1, 200.0),
    GEN(trunk_radius_m, SP_DBL, 0.001, 10.0),
    GEN(trunk_taper, SP_DBL, 0.01, 1.0),
    GEN(trunk_bend_deg, SP_DBL, -180.0, 180.0),
    GEN(segment_m, SP_DBL, 0.0, 100.0),
    GEN(twist_deg, SP_DBL, -360.0, 360.0),
    GEN(twist_jitter_deg, SP_DBL, 0.0, 180.0),
    GEN(wobble_deg, SP_DBL, 0.0, 90.0),
    GEN(tip_radius_m, SP_DBL, 0.0, 1.0),
    GEN(pipe_exponent, SP_DBL, 0.0, 4.0),
};
#undef GEN

/* clang-format off */
#define SPF(k, kind, lo, hi) { #k, kind, lo, hi, offsetof(species, k) }
/* clang-format on */
/* wood: E of green timber is 5-15 GPa, palm stems 2-8 GPa; the bounds leave room for
 * model tests. G is read separately: absent means E / 2.6. */
static const sp_field top_fields[] = {
    SPF(E_pa, SP_DBL, 1e6, 1e12),
    SPF(rho_kg_m3, SP_DBL, 10.0, 20000.0),
    SPF(rayleigh_alpha, SP_DBL, 0.0, 100.0),
    SPF(rayleigh_beta, SP_DBL, 0.0, 1.0),
    SPF(drag_c, SP_DBL, 0.0, 100.0),
};
static const sp_field look_fields[] = {
    SPF(bark_rgb, SP_RGB, 0.0, 1.0),          SPF(leaf_rgb, SP_RGB, 0.0, 1.0),
    SPF(leaf_size_m, SP_FLT, 0.005, 10.0),    SPF(leaves_per_tip, SP_INT, 0, 64),
    SPF(leaf_spread_deg, SP_FLT, 0.0, 180.0),
};
static const sp_field drag_fields[] = {
    { "vogel_b", SP_FLT, -1.5, 0.0, offsetof(species, drag.vogel_b) },
    { "u0_ms", SP_FLT, 0.1, 100.0, offsetof(species, drag.u0_ms) },
    { "fit_max_ms", SP_FLT, 0.1, 200.0, offsetof(species, drag.fit_max_ms) },
};
#undef SPF

/* clang-format off */
#define DMF(k, lo, hi) { #k, SP_DBL, lo, hi, offsetof(damage_params, k) }
/* clang-format on */
/* storm damage (PHYSICS.md "Storm damage"): green-wood MOR is 20-100 MPa, C_reg of
 * pulling tests 50-400 N m/kg; the bounds leave room for model tests */
static const sp_field damage_fields[] = {
    DMF(mor_pa, 1e6, 1e9),          DMF(f_knot, 0.1, 1.0),
    DMF(stem_density_kg_m3, 10.0, 5000.0), DMF(c_reg_nm_kg, 1.0, 5000.0),
    DMF(strength_sd, 0.0, 2.0),     DMF(leaf_drag_share, 0.0, 1.0),
    DMF(strip_max, 0.0, 1.0),
};
#undef DMF

#define COUNT(a) (sizeof(a) / sizeof((a)[0]))

/* Reads every present key of `fields` from obj (at key path `path`) into base. */
static int sp_read(const cfg_doc *d, const cJSON *obj, const char *path, const sp_field *fields,
                   size_t n, void *base, gale_err *err)
{
    for (size_t i = 0; i < n; i++) {
        const sp_field *f = &fields[i];
        void *dst = (char *)base + f->off;
        int rc = GALE_OK;
        switch (f->kind) {
        case SP_INT: {
            int v;
            memcpy(&v, dst, sizeof v);
            long long ll = v; /* kept as is when the key is bad */
            rc = cfg_int(d, obj, path, f->key, false, v, (long long)f->min, (long long)f->max, &ll,
                         err);
            v = (int)ll;
            memcpy(dst, &v, sizeof v);
            break;
        }
        case SP_BOOL: {
            int v;
            memcpy(&v, dst, sizeof v);
            bool b = v != 0; /* kept as is when the key is bad */
            rc = cfg_bool(d, obj, path, f->key, false, v != 0, &b, err);
            v = b ? 1 : 0;
            memcpy(dst, &v, sizeof v);
            break;
        }
        case SP_DBL: {
            double v;
            memcpy(&v, dst, sizeof v);
            rc = cfg_number(d, obj, path, f->key, false, v, f->min, f->max, &v, err);
            memcpy(dst, &v, sizeof v);
            break;
        }
        case SP_FLT: {
            float fv;
            memcpy(&fv, dst, sizeof fv);
            double v = fv;
            rc = cfg_number(d, obj, path, f->key, false, v, f->min, f->max, &v, err);
            fv = (float)v;
            memcpy(dst, &fv, sizeof fv);
            break;
        }
        case SP_RGB: {
            float fv[3];
            memcpy(fv, dst, sizeof fv);
            double v[3] = { fv[0], fv[1], fv[2] };
            rc = cfg_vec(d, obj, path, f->key, false, 3, v, f->min, f->max, v, err);
            for (int k = 0; k < 3; k++) {
                fv[k] = (float)v[k];
            }
            memcpy(dst, fv, sizeof fv);
            break;
        }
        case SP_SEED: {
            uint64_t v;
            memcpy(&v, dst, sizeof v);
            long long ll = (long long)(v & 0x001fffffffffffffull);
            rc = cfg_int(d, obj, path, f->key, false, ll, (long long)f->min, (long long)f->max, &ll,
                         err);
            v = (uint64_t)ll;
            memcpy(dst, &v, sizeof v);
            break;
        }
        }
        if (rc != 0) {
            return rc;
        }
    }
    return GALE_OK;
}

/* Fails naming the first key of obj that is neither in `fields` nor in `extra`. */
static int sp_keys(const cfg_doc *d, const cJSON *obj, const char *path, const sp_field *fields,
                   size_t n, const char *const *extra, gale_err *err)
{
    const char *keys[32];
    size_t k = 0;
    for (size_t i = 0; i < n && k < COUNT(keys) - 1; i++) {
        keys[k++] = fields[i].key;
    }
    for (; extra && *extra && k < COUNT(keys) - 1; extra++) {
        keys[k++] = *extra;
    }
    keys[k] = NULL;
    return cfg_check_keys(d, obj, path, keys, err);
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

static int sp_rule(const cfg_doc *d, const cJSON *gen, const char *key, lsystem_rule *r,
                   gale_err *err)
{
    const cJSON *o;
    char p[64];
    cfg_path(p, sizeof p, "generator", key);
    int rc = sp_section(d, gen, "generator", key, &o, err);
    if (rc != 0 || !o) {
        return rc;
    }
    rc = sp_keys(d, o, p, rule_fields, COUNT(rule_fields), NULL, err);
    if (rc == 0) {
        rc = sp_read(d, o, p, rule_fields, COUNT(rule_fields), r, err);
    }
    if (rc != 0) {
        return rc;
    }
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
    static const char *const subs[] = { "trunk", "branch", NULL };
    const cJSON *o;
    int rc = sp_section(d, root, "", "generator", &o, err);
    if (rc != 0 || !o) {
        return rc;
    }
    rc = sp_keys(d, o, "generator", gen_fields, COUNT(gen_fields), subs, err);
    if (rc == 0) {
        rc = sp_read(d, o, "generator", gen_fields, COUNT(gen_fields), g, err);
    }
    if (rc == 0) {
        rc = sp_rule(d, o, "trunk", &g->trunk, err);
    }
    if (rc == 0) {
        rc = sp_rule(d, o, "branch", &g->branch, err);
    }
    return rc;
}

static int sp_look(const cfg_doc *d, const cJSON *root, species *sp, gale_err *err)
{
    static const char *const extra[] = { "leaf_shape", NULL };
    static const char *const shapes[] = { "broad", "palm", "needle" };
    const cJSON *o;
    int rc = sp_section(d, root, "", "look", &o, err);
    if (rc != 0 || !o) {
        return rc;
    }
    rc = sp_keys(d, o, "look", look_fields, COUNT(look_fields), extra, err);
    if (rc == 0) {
        rc = sp_read(d, o, "look", look_fields, COUNT(look_fields), sp, err);
    }
    char shape[16];
    if (rc == 0) {
        rc = cfg_string(d, o, "look", "leaf_shape", false, shapes[sp->leaf_shape], shape,
                        sizeof shape, err);
    }
    if (rc != 0) {
        return rc;
    }
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

/* "drag": the streamlining law (drag_law.h); above_fit is "extend" or "hold". */
static int sp_drag(const cfg_doc *d, const cJSON *root, species *sp, gale_err *err)
{
    static const char *const extra[] = { "above_fit", NULL };
    static const char *const modes[] = { "extend", "hold" };
    const cJSON *o;
    int rc = sp_section(d, root, "", "drag", &o, err);
    if (rc != 0 || !o) {
        return rc;
    }
    rc = sp_keys(d, o, "drag", drag_fields, COUNT(drag_fields), extra, err);
    if (rc == 0) {
        rc = sp_read(d, o, "drag", drag_fields, COUNT(drag_fields), sp, err);
    }
    char mode[16];
    if (rc == 0) {
        rc = cfg_string(d, o, "drag", "above_fit", false, modes[sp->drag.hold_above_fit], mode,
                        sizeof mode, err);
    }
    if (rc != 0) {
        return rc;
    }
    if (!(sp->drag.fit_max_ms >= sp->drag.u0_ms)) {
        return gale_errf(err, GALE_E_RANGE, "%s: drag.fit_max_ms: expected >= u0_ms (%g), got %g",
                         d->name, (double)sp->drag.u0_ms, (double)sp->drag.fit_max_ms);
    }
    for (int i = 0; i < 2; i++) {
        if (strcmp(mode, modes[i]) == 0) {
            sp->drag.hold_above_fit = i;
            return GALE_OK;
        }
    }
    return gale_errf(err, GALE_E_RANGE, "%s: drag.above_fit: expected \"extend\" or \"hold\", got \"%s\"",
                     d->name, mode);
}

static int sp_damage(const cfg_doc *d, const cJSON *root, damage_params *p, gale_err *err)
{
    const cJSON *o;
    int rc = sp_section(d, root, "", "damage", &o, err);
    if (rc != 0 || !o) {
        return rc;
    }
    rc = sp_keys(d, o, "damage", damage_fields, COUNT(damage_fields), NULL, err);
    if (rc == 0) {
        rc = sp_read(d, o, "damage", damage_fields, COUNT(damage_fields), p, err);
    }
    return rc;
}

static int sp_from_doc(const cfg_doc *d, species *sp, gale_err *err)
{
    static const char *const extra[] = { "name", "G_pa", "generator", "look", "drag", "damage",
                                         NULL };
    const cJSON *r = d->root;
    double G = -1.0;
    int rc = sp_keys(d, r, "", top_fields, COUNT(top_fields), extra, err);
    if (rc == 0) {
        rc = cfg_string(d, r, "", "name", true, NULL, sp->name, sizeof sp->name, err);
    }
    if (rc == 0) {
        rc = sp_read(d, r, "", top_fields, COUNT(top_fields), sp, err);
    }
    if (rc == 0) {
        rc = cfg_number(d, r, "", "G_pa", false, -1.0, 1e5, 1e12, &G, err);
    }
    if (rc == 0) {
        rc = sp_generator(d, r, &sp->gen, err);
    }
    if (rc == 0) {
        rc = sp_look(d, r, sp, err);
    }
    if (rc == 0) {
        rc = sp_drag(d, r, sp, err);
    }
    if (rc == 0) {
        rc = sp_damage(d, r, &sp->damage, err);
    }
    if (rc != 0) {
        return rc;
    }
    if (sp->name[0] == '\0') {
        return gale_errf(err, GALE_E_RANGE, "%s: name: expected a non-empty string", d->name);
    }
    /* ν ≈ 0.3: G = E / (2 (1 + ν)) = E / 2.6 unless given */
    sp->G_pa = G > 0.0 ? G : sp->E_pa / 2.6;
    /* the generator runs later (bake, server start): its failures name this file too */
    snprintf(sp->gen.where, sizeof sp->gen.where, "%s", d->name);
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
