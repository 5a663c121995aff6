/* gale-bake: bakes one species (L-system from a species JSON) or one skeleton CSV into an
 * asset file, printing a readable report; optionally the report as JSON and a PNG of the
 * first mode shapes. Outputs appear whole or not at all. */
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cjson/cJSON.h>

#include "asset_file.h"
#include "bake.h"
#include "damage_table.h"
#include "lsystem.h"
#include "modes_png.h"
#include "skeleton.h"
#include "species.h"

/* Input caps, checked before the input is read. A species file is read by gale-server
 * only up to 1 MiB (serve/species_cache.c), so a larger one would bake here and never
 * serve; the shipped ones are under 2 KiB. A skeleton CSV holds at most 1 000 000 rows
 * (skeleton_csv.c) of about 60 bytes: 64 MiB, the cap of skeleton_load_csv too. */
#define BAKE_MAX_SPECIES_BYTES ((size_t)1 << 20)
#define BAKE_MAX_SKELETON_BYTES ((size_t)64 << 20)

static void usage(FILE *out)
{
    fprintf(out,
            "usage: gale-bake (--skeleton FILE.csv | --species FILE.json) [--modes N] --out FILE\n"
            "                 [--report FILE.json] [--modes-png FILE.png]\n"
            "\n"
            "Bakes a tree into a gale asset: frame-element model, lowest modes, wind basis,\n"
            "length-true pose fields, tube mesh and leaves (Diener 2008).\n"
            "\n"
            "  --skeleton FILE.csv  skeleton to bake: id,parent,x,y,z,radius with a header line,\n"
            "                       parent -1 for the single root, z up, metres; default wood\n"
            "                       (E 1e10 Pa, rho 1000 kg/m^3) and damping; at most %zu MiB\n"
            "  --species FILE.json  species to bake: its L-system generates the skeleton, its\n"
            "                       wood, damping, drag and look constants are used; at most\n"
            "                       %zu MiB (what gale-server reads)\n"
            "  --modes N            modes to keep, 1..%d (default 32)\n"
            "  --out FILE           asset file to write (written atomically)\n"
            "  --report FILE.json   also write the report as JSON: nodes, modes, frequencies_hz,\n"
            "                       damping_ratios, seconds, branch_length_error, eigen figures\n"
            "  --modes-png FILE.png also draw the first six mode shapes (side view, rest in grey)\n"
            "  --help               this text\n"
            "\n"
            "Exit status 0 on success; 2 on bad arguments; 1 when the input is bad or the bake\n"
            "fails (the message names the file, line or key). Nothing is written on failure.\n",
            BAKE_MAX_SKELETON_BYTES >> 20, BAKE_MAX_SPECIES_BYTES >> 20, BAKE_MAX_MODES);
}

/* The parameters a skeleton CSV is baked with, as the keys of a species file (so that the
 * JSON less "skeleton" reads back as one, species_parse): every one that changes the
 * asset's bytes besides the CSV itself and the mode count: the name (META), the wood and
 * damping (frame,
 * modes), the drag constant and the leaves' share of the drag (wind basis, static
 * correction), the look and the leaves (mesh, leaf slots; the seed places the leaves).
 * NULL when out of memory. */
static char *csv_params(const char *skeleton_name, const species *sp)
{
    static const char *const shapes[] = { "broad", "palm", "needle" };
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "skeleton", skeleton_name);
    cJSON_AddStringToObject(o, "name", sp->name);
    cJSON_AddNumberToObject(o, "E_pa", sp->E_pa);
    cJSON_AddNumberToObject(o, "rho_kg_m3", sp->rho_kg_m3);
    cJSON_AddNumberToObject(o, "G_pa", sp->G_pa);
    cJSON_AddNumberToObject(o, "rayleigh_alpha", sp->rayleigh_alpha);
    cJSON_AddNumberToObject(o, "rayleigh_beta", sp->rayleigh_beta);
    cJSON_AddNumberToObject(o, "drag_c", sp->drag_c);
    cJSON *dm = cJSON_AddObjectToObject(o, "damage");
    cJSON_AddNumberToObject(dm, "leaf_drag_share", sp->damage.leaf_drag_share);
    cJSON *gen = cJSON_AddObjectToObject(o, "generator");
    cJSON_AddNumberToObject(gen, "seed", (double)sp->gen.seed);
    cJSON *lk = cJSON_AddObjectToObject(o, "look");
    const double bark[3] = { sp->bark_rgb[0], sp->bark_rgb[1], sp->bark_rgb[2] };
    const double leaf[3] = { sp->leaf_rgb[0], sp->leaf_rgb[1], sp->leaf_rgb[2] };
    cJSON_AddItemToObject(lk, "bark_rgb", cJSON_CreateDoubleArray(bark, 3));
    cJSON_AddItemToObject(lk, "leaf_rgb", cJSON_CreateDoubleArray(leaf, 3));
    cJSON_AddStringToObject(lk, "leaf_shape", shapes[sp->leaf_shape >= 0 && sp->leaf_shape < 3
                                                     ? sp->leaf_shape
                                                     : 0]);
    cJSON_AddNumberToObject(lk, "leaf_size_m", sp->leaf_size_m);
    cJSON_AddNumberToObject(lk, "leaves_per_tip", sp->leaves_per_tip);
    cJSON_AddNumberToObject(lk, "leaf_spread_deg", sp->leaf_spread_deg);
    char *text = cJSON_PrintUnformatted(o);
    cJSON_Delete(o);
    return text;
}

/* Reads path whole into *out (NUL-terminated, caller frees) when it holds at most max
 * bytes; a larger file is refused naming it, its size when known, the cap and `what`. */
static int read_file(const char *path, size_t max, const char *what, char **out, size_t *len,
                     gale_err *err)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        return gale_errf(err, GALE_E_IO, "%s: cannot open: %s", path, strerror(errno));
    }
    struct stat st;
    if (fstat(fileno(f), &st) == 0 && S_ISREG(st.st_mode) && (uintmax_t)st.st_size > max) {
        fclose(f);
        return gale_errf(err, GALE_E_RANGE, "%s: %jd bytes: expected at most %zu (%s)", path,
                         (intmax_t)st.st_size, max, what);
    }
    size_t cap = 65536, n = 0;
    char *buf = malloc(cap + 1);
    while (buf) {
        n += fread(buf + n, 1, cap - n, f);
        if (n < cap || n > max) {
            break;
        }
        cap *= 2; /* at most max + 1 bytes are read: enough to tell it is too large */
        if (cap > max + 1) {
            cap = max + 1;
        }
        char *nb = realloc(buf, cap + 1);
        if (!nb) {
            free(buf);
            buf = NULL;
        } else {
            buf = nb;
        }
    }
    const int bad = ferror(f);
    fclose(f);
    if (!buf) {
        return gale_errf(err, GALE_E_NOMEM, "%s: out of memory reading", path);
    }
    if (bad) {
        free(buf);
        return gale_errf(err, GALE_E_IO, "%s: read error", path);
    }
    if (n > max) {
        free(buf);
        return gale_errf(err, GALE_E_RANGE, "%s: more than %zu bytes: expected at most %zu (%s)",
                         path, max, max, what);
    }
    buf[n] = '\0';
    *out = buf;
    *len = n;
    return GALE_OK;
}

/* Writes len bytes to tmp (created fresh); the caller renames it into place. */
static int write_file(const char *tmp, const char *data, size_t len, gale_err *err)
{
    FILE *f = fopen(tmp, "wb");
    if (!f) {
        return gale_errf(err, GALE_E_IO, "%s: cannot create: %s", tmp, strerror(errno));
    }
    const size_t w = fwrite(data, 1, len, f);
    const int fl = fflush(f);
    const int sy = fsync(fileno(f));
    if (fclose(f) != 0 || w != len || fl != 0 || sy != 0) {
        unlink(tmp);
        return gale_errf(err, GALE_E_IO, "%s: write failed", tmp);
    }
    return GALE_OK;
}

/* The bake report's JSON with a "damage" object added (PHYSICS.md "Storm damage"): the
 * critical moments and the steady crown wind at which the reference tree snaps and
 * uproots. Takes json (malloc'd, freed here); returns a new text or NULL. */
static char *report_with_damage(char *json, const damage_table *t, double snap_ms,
                                double uproot_ms, double branch_ms)
{
    cJSON *o = json ? cJSON_Parse(json) : NULL;
    free(json);
    if (!o) {
        return NULL;
    }
    cJSON *d = cJSON_AddObjectToObject(o, "damage");
    cJSON_AddNumberToObject(d, "branches", t->n_branches);
    cJSON_AddNumberToObject(d, "stem_d_m", t->stem_d_m);
    cJSON_AddNumberToObject(d, "stem_mass_kg", t->stem_mass_kg);
    cJSON_AddNumberToObject(d, "m_break_nm", t->m_break_nm);
    cJSON_AddNumberToObject(d, "m_over_nm", t->m_over_nm);
    cJSON_AddNumberToObject(d, "snap_ms", snap_ms);
    cJSON_AddNumberToObject(d, "uproot_ms", uproot_ms);
    cJSON_AddNumberToObject(d, "first_branch_ms", branch_ms);
    char *out = cJSON_Print(o);
    cJSON_Delete(o);
    return out;
}

static int arg_fail(const char *msg, const char *what)
{
    fprintf(stderr, "gale-bake: %s%s\n(see gale-bake --help)\n", msg, what ? what : "");
    return 2;
}

int main(int argc, char **argv)
{
    const char *skel_path = NULL, *species_path = NULL, *out = NULL, *report = NULL, *png = NULL;
    int n_modes = 32;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            usage(stdout);
            return 0;
        }
        const int has_val = i + 1 < argc;
        if (strcmp(a, "--skeleton") == 0 || strcmp(a, "--species") == 0 ||
            strcmp(a, "--modes") == 0 || strcmp(a, "--out") == 0 || strcmp(a, "--report") == 0 ||
            strcmp(a, "--modes-png") == 0) {
            if (!has_val) {
                return arg_fail("missing value after ", a);
            }
            const char *v = argv[++i];
            if (strcmp(a, "--skeleton") == 0) {
                skel_path = v;
            } else if (strcmp(a, "--species") == 0) {
                species_path = v;
            } else if (strcmp(a, "--out") == 0) {
                out = v;
            } else if (strcmp(a, "--report") == 0) {
                report = v;
            } else if (strcmp(a, "--modes-png") == 0) {
                png = v;
            } else {
                char *end = NULL;
                errno = 0;
                long m = strtol(v, &end, 10);
                if (errno || end == v || *end != '\0' || m < 1 || m > BAKE_MAX_MODES) {
                    fprintf(stderr, "gale-bake: --modes: expected an integer in 1..%d, got '%s'\n",
                            BAKE_MAX_MODES, v);
                    return 2;
                }
                n_modes = (int)m;
            }
        } else {
            return arg_fail("unknown argument ", a);
        }
    }
    if (!skel_path == !species_path) {
        return arg_fail("give exactly one of --skeleton FILE.csv or --species FILE.json", NULL);
    }
    if (!out) {
        return arg_fail("--out FILE is required", NULL);
    }

    gale_err err;
    gale_err_clear(&err);
    const char *in_path = skel_path ? skel_path : species_path;
    char *text = NULL, *params = NULL, *report_text = NULL;
    size_t len = 0;
    species sp;
    skeleton s;
    asset a;
    bake_report rep;
    damage_table dt;
    memset(&dt, 0, sizeof dt);
    memset(&s, 0, sizeof s);
    memset(&a, 0, sizeof a);
    char tmp_report[4096] = "", tmp_png[4096] = "";
    int status = 1;
    if (read_file(in_path, skel_path ? BAKE_MAX_SKELETON_BYTES : BAKE_MAX_SPECIES_BYTES,
                  skel_path ? "a skeleton CSV: 1000000 rows of about 60 bytes"
                            : "a species file: what gale-server reads",
                  &text, &len, &err) != GALE_OK) {
        goto fail;
    }
    if (species_path) {
        if (species_parse(text, len, species_path, &sp, &err) != GALE_OK ||
            lsystem_generate(&sp.gen, &s, &err) != GALE_OK) {
            goto fail;
        }
        params = strdup(text);
    } else {
        if (skeleton_parse_csv(text, len, skel_path, &s, &err) != GALE_OK) {
            goto fail;
        }
        species_default(&sp);
        const char *base = strrchr(skel_path, '/');
        base = base ? base + 1 : skel_path;
        snprintf(sp.name, sizeof sp.name, "%.*s", (int)strcspn(base, "."), base);
        params = csv_params(base, &sp);
    }
    if (!params) {
        gale_errf(&err, GALE_E_NOMEM, "out of memory");
        goto fail;
    }
    uint64_t h = bake_hash(BAKE_HASH_SEED, text, len);
    const int ver = BAKE_VERSION;
    h = bake_hash(h, &n_modes, sizeof n_modes);
    h = bake_hash(h, &ver, sizeof ver);
    bake_desc d = { .n_modes = n_modes, .params_json = params, .source_hash = h };
    if (bake_run(&s, &sp, &d, &a, &rep, &err) != GALE_OK) {
        goto fail;
    }
    if (png) {
        snprintf(tmp_png, sizeof tmp_png, "%s.tmp-%ld.png", png, (long)getpid());
        if (modes_png_write(&a, tmp_png, &err) != GALE_OK) {
            unlink(tmp_png);
            tmp_png[0] = '\0';
            goto fail;
        }
    }
    double snap_ms = 0.0, uproot_ms = 0.0, branch_ms = 0.0;
    if (damage_table_build(&a, sp.E_pa, sp.drag_c, &sp.damage, &dt, &err) != GALE_OK) {
        goto fail;
    }
    damage_critical_speeds(&a, &dt, &sp.drag, &snap_ms, &uproot_ms, &branch_ms);
    if (report) {
        report_text = report_with_damage(bake_report_json(&a, &rep), &dt, snap_ms, uproot_ms, branch_ms);
        if (!report_text) {
            gale_errf(&err, GALE_E_NOMEM, "out of memory writing the report");
            goto fail;
        }
        snprintf(tmp_report, sizeof tmp_report, "%s.tmp-%ld", report, (long)getpid());
        if (write_file(tmp_report, report_text, strlen(report_text), &err) != GALE_OK) {
            tmp_report[0] = '\0';
            goto fail;
        }
    }
    if (asset_save(&a, out, &err) != GALE_OK) {
        goto fail;
    }
    if ((tmp_report[0] && rename(tmp_report, report) != 0) ||
        (tmp_png[0] && rename(tmp_png, png) != 0)) {
        gale_errf(&err, GALE_E_IO, "cannot rename %s into place: %s",
                  tmp_report[0] ? report : png, strerror(errno));
        unlink(out);
        goto fail;
    }
    tmp_report[0] = '\0';
    tmp_png[0] = '\0';
    bake_report_print(stdout, &a, &rep);
    printf("damage (PHYSICS.md \"Storm damage\"): %u branches; stem d %.3f m, %.0f kg; "
           "M_break %.3g N m, M_over %.3g N m; steady wind at the crown (streamlined drag) to snap %.1f m/s, to "
           "uproot %.1f m/s, to break the first branch %.1f m/s\n",
           dt.n_branches, dt.stem_d_m, dt.stem_mass_kg, dt.m_break_nm, dt.m_over_nm, snap_ms,
           uproot_ms, branch_ms);
    printf("wrote %s%s%s%s%s\n", out, report ? ", " : "", report ? report : "", png ? ", " : "",
           png ? png : "");
    status = 0;
    goto done;
fail:
    fprintf(stderr, "gale-bake: %s\n", err.msg[0] ? err.msg : "failed");
done:
    if (tmp_report[0]) {
        unlink(tmp_report);
    }
    if (tmp_png[0]) {
        unlink(tmp_png);
    }
    free(text), free(params), free(report_text);
    damage_table_fini(&dt);
    asset_fini(&a);
    skeleton_fini(&s);
    return status;
}
