/* gale-bake end to end: bad arguments and bad files give a non-zero exit and a message
 * naming the fault, and create no output; good input writes an asset that loads back, a
 * report with the promised fields, and a mode-shape PNG; a CSV's node ids come back
 * from the asset's SRID map, an L-system species has none. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cjson/cJSON.h>

#include "asset_file.h"
#include "bake.h"
#include "skeleton.h"
#include "species.h"
#include "check.h"

static char dir[256];
static char out[64 * 1024];

/* Runs gale-bake with args (a shell word list), stdout+stderr into `out`; exit status. */
static int bake(const char *args)
{
    char cmd[4096], log[512];
    snprintf(log, sizeof log, "%s/log.txt", dir);
    snprintf(cmd, sizeof cmd, "cd %s && %s %s > %s 2>&1", dir, GALE_BAKE_EXE, args, log);
    const int st = system(cmd);
    out[0] = '\0';
    FILE *f = fopen(log, "rb");
    if (f) {
        size_t n = fread(out, 1, sizeof out - 1, f);
        out[n] = '\0';
        fclose(f);
    }
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

static int exists(const char *name)
{
    char p[512];
    struct stat st;
    snprintf(p, sizeof p, "%s/%s", dir, name);
    return stat(p, &st) == 0;
}

static void put(const char *name, const char *text)
{
    char p[512];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    FILE *f = fopen(p, "wb");
    CHECK(f != NULL);
    if (f) {
        fputs(text, f);
        fclose(f);
    }
}

/* Only the files a run is allowed to leave: no temporaries. */
static int count_files(void)
{
    char cmd[512];
    snprintf(cmd, sizeof cmd, "ls -A %s | grep -v -e '^log.txt$' -e '\\.csv$' -e '\\.json$' | wc -l", dir);
    FILE *p = popen(cmd, "r");
    int n = -1;
    if (p) {
        if (fscanf(p, "%d", &n) != 1) {
            n = -1;
        }
        pclose(p);
    }
    return n;
}

static void test_bad_arguments(void)
{
    CHECK(bake("") == 2);
    CHECK_STR_HAS(out, "exactly one of --skeleton");
    CHECK(bake("--skeleton a.csv --species b.json --out x.gasset") == 2);
    CHECK(bake("--skeleton a.csv") == 2);
    CHECK_STR_HAS(out, "--out FILE is required");
    CHECK(bake("--skeleton a.csv --out x.gasset --modes 0") == 2);
    CHECK_STR_HAS(out, "--modes: expected an integer in 1..256, got '0'");
    CHECK(bake("--skeleton a.csv --out x.gasset --modes 3x") == 2);
    CHECK(bake("--skeleton a.csv --out x.gasset --frobnicate") == 2);
    CHECK_STR_HAS(out, "unknown argument --frobnicate");
    CHECK(bake("--skeleton") == 2);
    CHECK_STR_HAS(out, "missing value after --skeleton");
    CHECK(!exists("x.gasset"));
    CHECK(bake("--help") == 0);
    const char *flags[] = { "--skeleton", "--species", "--modes", "--out", "--report",
                            "--modes-png", "--help" };
    for (size_t i = 0; i < sizeof flags / sizeof flags[0]; i++) {
        CHECK_STR_HAS(out, flags[i]);
    }
}

static void test_bad_files(void)
{
    CHECK(bake("--skeleton missing.csv --out x.gasset") == 1);
    CHECK_STR_HAS(out, "missing.csv");
    put("dup.csv", "id,parent,x,y,z,radius\n0,-1,0,0,0,0.1\n1,0,0,0,1,0.05\n1,0,0,1,1,0.05\n");
    CHECK(bake("--skeleton dup.csv --out x.gasset --report r.json") == 1);
    CHECK_STR_HAS(out, "dup.csv:4");
    put("bad.json", "{ \"name\": \"oak\", \"E_pa\": -5 }\n");
    CHECK(bake("--species bad.json --out x.gasset") == 1);
    CHECK_STR_HAS(out, "bad.json");
    /* more modes than the skeleton has degrees of freedom */
    put("tiny.csv", "id,parent,x,y,z,radius\n0,-1,0,0,0,0.1\n1,0,0,0,1,0.05\n");
    CHECK(bake("--skeleton tiny.csv --modes 8 --out x.gasset") == 1);
    CHECK_STR_HAS(out, "degrees of freedom");
    /* an output that cannot be written leaves nothing behind */
    put("ok.csv", "id,parent,x,y,z,radius\n0,-1,0,0,0,0.1\n1,0,0,0,1,0.08\n2,1,0,0,2,0.06\n"
                  "3,2,0.5,0,2.5,0.03\n4,2,-0.5,0,2.5,0.03\n5,1,0.4,0.3,1.3,0.03\n");
    CHECK(bake("--skeleton ok.csv --modes 4 --out no/such/dir/x.gasset --report r.json") == 1);
    CHECK_STR_HAS(out, "no/such/dir/x.gasset");
    CHECK(!exists("x.gasset"));
    CHECK(!exists("r.json"));
    CHECK(count_files() == 0);
}

/* A file of exactly `size` bytes: text, then spaces (sparse zeros when text is NULL). */
static void put_sized(const char *name, const char *text, long size)
{
    char p[512];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    FILE *f = fopen(p, "wb");
    CHECK(f != NULL);
    if (!f) {
        return;
    }
    long n = 0;
    if (text) {
        fputs(text, f);
        n = (long)strlen(text);
        for (; n < size; n++) {
            fputc(' ', f);
        }
    }
    fclose(f);
    CHECK(truncate(p, size) == 0);
}

/* Inputs are capped before they are read: a species file at 1 MiB (what gale-server
 * reads), a skeleton CSV at 64 MiB (1 000 000 rows); a pipe is cut at the cap. */
static void test_input_caps(void)
{
    put_sized("big.json", NULL, (1L << 20) + 1);
    CHECK(bake("--species big.json --out x.gasset") == 1);
    CHECK_STR_HAS(out, "gale-bake: big.json: 1048577 bytes: expected at most 1048576 (a species "
                       "file: what gale-server reads)");
    put_sized("big.csv", NULL, (64L << 20) + 1);
    CHECK(bake("--skeleton big.csv --out x.gasset") == 1);
    CHECK_STR_HAS(out, "gale-bake: big.csv: 67108865 bytes: expected at most 67108864 (a "
                       "skeleton CSV: 1000000 rows of about 60 bytes)");
    CHECK(bake("--species /dev/stdin --out x.gasset < big.json") == 1);
    CHECK_STR_HAS(out, "/dev/stdin: 1048577 bytes: expected at most 1048576");
    CHECK(bake("--species /dev/stdin --out x.gasset < /dev/zero") == 1);
    CHECK_STR_HAS(out, "gale-bake: /dev/stdin: more than 1048576 bytes: expected at most "
                       "1048576 (a species file: what gale-server reads)");
    /* exactly at the cap the file is read and parsed: the parse names the key */
    put_sized("edge.json", "{\"name\": \"x\", \"bogus\": 1}", 1L << 20);
    CHECK(bake("--species edge.json --out x.gasset") == 1);
    CHECK_STR_HAS(out, "gale-bake: edge.json: bogus: unknown key");
    /* bytes after the species object: refused at their line:col */
    put("tail.json", "{\"name\": \"x\"}\n}\n");
    CHECK(bake("--species tail.json --out x.gasset") == 1);
    CHECK_STR_HAS(out, "gale-bake: tail.json:2:1: trailing bytes after the JSON object: "
                       "expected the end of the file");
    /* a grammar that explodes names the file and the generator key */
    put("boom.json", "{\"name\": \"x\", \"generator\": {\"depth\": 10, \"branch\": "
                     "{\"tip_children\": 8, \"prune_prob\": 0, \"length_ratio\": 1}}}\n");
    CHECK(bake("--species boom.json --out x.gasset") == 1);
    CHECK_STR_HAS(out, "gale-bake: boom.json: generator.depth: 10 levels grow more than 200000 "
                       "stems");
    CHECK(!exists("x.gasset"));
    char p[512];
    snprintf(p, sizeof p, "%s/big.csv", dir);
    remove(p);
}

static void check_report_file(const char *name, int nodes, int modes)
{
    char p[512];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    FILE *f = fopen(p, "rb");
    CHECK(f != NULL);
    if (!f) {
        return;
    }
    static char text[256 * 1024];
    size_t n = fread(text, 1, sizeof text - 1, f);
    text[n] = '\0';
    fclose(f);
    cJSON *o = cJSON_Parse(text);
    CHECK(o != NULL);
    if (!o) {
        return;
    }
    if (nodes > 0) {
        CHECK(cJSON_GetObjectItem(o, "nodes")->valueint == nodes);
    } else {
        CHECK(cJSON_GetObjectItem(o, "nodes")->valueint > 100);
    }
    CHECK(cJSON_GetObjectItem(o, "modes")->valueint == modes);
    const cJSON *fh = cJSON_GetObjectItem(o, "frequencies_hz");
    const cJSON *dr = cJSON_GetObjectItem(o, "damping_ratios");
    CHECK(cJSON_GetArraySize(fh) == modes && cJSON_GetArraySize(dr) == modes);
    for (int i = 1; i < cJSON_GetArraySize(fh); i++) {
        CHECK(cJSON_GetArrayItem(fh, i)->valuedouble >= cJSON_GetArrayItem(fh, i - 1)->valuedouble);
    }
    CHECK(cJSON_GetArrayItem(dr, 0)->valuedouble > 0.0);
    CHECK(cJSON_GetObjectItem(o, "seconds")->valuedouble > 0.0);
    const cJSON *bl = cJSON_GetObjectItem(o, "branch_length_error");
    CHECK(cJSON_IsString(cJSON_GetObjectItem(bl, "pose")));
    const double lin = cJSON_GetObjectItem(bl, "linear_at_20pct")->valuedouble;
    const double cor = cJSON_GetObjectItem(bl, "pose_at_20pct")->valuedouble;
    /* a finite share, not a division by ~0 (a cantilever's axial mode has no rotation) */
    CHECK(lin > 0.0 && lin < 1.0);
    CHECK(cor < lin && cor < 0.01);
    CHECK(cJSON_GetObjectItem(bl, "small_q_error")->valuedouble < 1e-2);
    const cJSON *df = cJSON_GetObjectItem(o, "deflection");
    CHECK(cJSON_GetArraySize(df) == 4);
    for (int i = 0; i < cJSON_GetArraySize(df); i++) {
        const cJSON *row = cJSON_GetArrayItem(df, i);
        const double r = cJSON_GetObjectItem(row, "rigid_m")->valuedouble;
        const double st = cJSON_GetObjectItem(row, "streamlined_m")->valuedouble;
        CHECK(r > 0.0 && st > 0.0 && st <= r * (1.0 + 1e-9));
    }
    CHECK(cJSON_GetObjectItem(o, "orthonormality_error")->valuedouble < 1e-8);
    CHECK(cJSON_GetObjectItem(o, "eigen_residual")->valuedouble < 1e-6);
    cJSON_Delete(o);
}

/* The parameters a CSV bake records (ASSET.md META): every one that changes the asset's
 * bytes is there, under the keys of a species file, and baking the CSV again from them
 * alone gives the file byte for byte. */
static void check_csv_params(const asset *a, const char *csv, const char *gasset)
{
    static const char *const keys[][2] = {
        { NULL, "name" },          { NULL, "E_pa" },          { NULL, "rho_kg_m3" },           { NULL, "G_pa" },
        { NULL, "rayleigh_alpha" }, { NULL, "rayleigh_beta" },      { NULL, "drag_c" },
        { "damage", "leaf_drag_share" }, { "generator", "seed" },   { "look", "bark_rgb" },
        { "look", "leaf_rgb" },    { "look", "leaf_shape" },        { "look", "leaf_size_m" },
        { "look", "leaves_per_tip" }, { "look", "leaf_spread_deg" },
    };
    cJSON *o = cJSON_Parse(a->params_json);
    CHECK(o != NULL);
    if (!o) {
        return;
    }
    for (size_t k = 0; k < sizeof keys / sizeof keys[0]; k++) {
        const cJSON *sec = keys[k][0] ? cJSON_GetObjectItem(o, keys[k][0]) : o;
        const int has = sec && cJSON_GetObjectItem(sec, keys[k][1]);
        if (!has) {
            fprintf(stderr, "params_json lacks %s%s%s\n", keys[k][0] ? keys[k][0] : "",
                    keys[k][0] ? "." : "", keys[k][1]);
        }
        CHECK(has);
    }
    cJSON_DeleteItemFromObject(o, "skeleton");
    char *sp_text = cJSON_PrintUnformatted(o);
    cJSON_Delete(o);
    species sp;
    gale_err err;
    memset(&err, 0, sizeof err);
    int rc = species_parse(sp_text, strlen(sp_text), "params_json", &sp, &err);
    free(sp_text);
    CHECK(rc == GALE_OK);
    if (rc != GALE_OK) {
        fprintf(stderr, "%s\n", err.msg);
        return;
    }
    char p[512];
    snprintf(p, sizeof p, "%s/%s", dir, csv);
    skeleton s;
    memset(&s, 0, sizeof s);
    asset b;
    memset(&b, 0, sizeof b);
    bake_desc d = { .n_modes = (int)a->n_modes, .params_json = a->params_json,
                    .source_hash = a->source_hash };
    rc = skeleton_load_csv(p, &s, &err);
    rc = rc ? rc : bake_run(&s, &sp, &d, &b, NULL, &err);
    CHECK(rc == GALE_OK);
    uint8_t *buf = NULL;
    size_t len = 0;
    if (rc == GALE_OK && asset_encode(&b, &buf, &len, &err) == GALE_OK) {
        snprintf(p, sizeof p, "%s/%s", dir, gasset);
        FILE *f = fopen(p, "rb");
        uint8_t *file = malloc(len + 1);
        size_t got = f && file ? fread(file, 1, len + 1, f) : 0;
        CHECK(got == len && memcmp(file, buf, len) == 0);
        free(file);
        if (f) {
            fclose(f);
        }
    }
    free(buf);
    asset_fini(&b);
    skeleton_fini(&s);
}

static void test_skeleton_end_to_end(void)
{
    CHECK(bake("--skeleton ok.csv --modes 4 --out ok.gasset --report ok-report.json") == 0);
    CHECK_STR_HAS(out, "branch-length change");
    check_report_file("ok-report.json", 6, 4);
    char p[512];
    snprintf(p, sizeof p, "%s/ok.gasset", dir);
    asset a;
    gale_err err;
    CHECK(asset_load(p, &a, &err) == GALE_OK);
    CHECK(a.n_nodes == 6 && a.n_modes == 4);
    CHECK_STR_HAS(a.species, "ok");
    CHECK_STR_HAS(a.params_json, "rayleigh_alpha");
    check_csv_params(&a, "ok.csv", "ok.gasset");
    asset_fini(&a);
}

/* The first bytes of a file in dir: the asset version is at byte 4. */
static unsigned file_version(const char *name)
{
    char p[512];
    unsigned char h[8] = { 0 };
    snprintf(p, sizeof p, "%s/%s", dir, name);
    FILE *f = fopen(p, "rb");
    if (f) {
        CHECK(fread(h, 1, sizeof h, f) == sizeof h);
        fclose(f);
    }
    return (unsigned)h[4] | (unsigned)h[5] << 8 | (unsigned)h[6] << 16 | (unsigned)h[7] << 24;
}

/* ASSET.md "Node numbering": ids out of order, the root on the third row and off the
 * origin, children listed before their parents. Every asset node's source id names the
 * CSV row with its position (rest + source_origin), radius and parent. */
static void test_source_ids(void)
{
    static const struct {
        unsigned id;
        int parent;
        float x, y, z, r;
    } rows[] = {
        { 57, 12, 10.4f, 20.3f, 11.3f, 0.03f }, { 12, 900, 10.0f, 20.0f, 11.0f, 0.08f },
        { 900, -1, 10.0f, 20.0f, 10.0f, 0.1f }, { 3, 12, 10.0f, 20.0f, 12.0f, 0.06f },
        { 41, 3, 10.5f, 20.0f, 12.5f, 0.03f },  { 8, 3, 9.5f, 20.0f, 12.5f, 0.03f },
    };
    const int n = (int)(sizeof rows / sizeof rows[0]);
    char csv[1024] = "id,parent,x,y,z,radius\n";
    for (int i = 0; i < n; i++) {
        size_t l = strlen(csv);
        snprintf(csv + l, sizeof csv - l, "%u,%d,%g,%g,%g,%g\n", rows[i].id, rows[i].parent,
                 (double)rows[i].x, (double)rows[i].y, (double)rows[i].z, (double)rows[i].r);
    }
    put("ids.csv", csv);
    CHECK(bake("--skeleton ids.csv --modes 4 --out ids.gasset") == 0);
    CHECK(file_version("ids.gasset") == 2);
    char p[512];
    snprintf(p, sizeof p, "%s/ids.gasset", dir);
    asset a;
    gale_err err;
    CHECK(asset_load(p, &a, &err) == GALE_OK);
    CHECK(a.n_nodes == (uint32_t)n && a.source_id != NULL);
    if (a.n_nodes != (uint32_t)n || !a.source_id) {
        asset_fini(&a);
        return;
    }
    CHECK(a.source_origin[0] == 10.0f && a.source_origin[1] == 20.0f &&
          a.source_origin[2] == 10.0f);
    /* node 0 is the root row, though it is the third in the file */
    CHECK(a.source_id[0] == 900 && a.parent[0] == -1);
    int seen[6] = { 0 };
    for (int i = 0; i < n; i++) {
        int row = -1;
        for (int k = 0; k < n; k++) {
            if (rows[k].id == a.source_id[i]) {
                row = k;
            }
        }
        CHECK(row >= 0);
        if (row < 0) {
            continue;
        }
        seen[row]++;
        CHECK_NEAR(a.rest[3 * i + 0] + a.source_origin[0], rows[row].x, 1e-5);
        CHECK_NEAR(a.rest[3 * i + 1] + a.source_origin[1], rows[row].y, 1e-5);
        CHECK_NEAR(a.rest[3 * i + 2] + a.source_origin[2], rows[row].z, 1e-5);
        CHECK(a.radius[i] == rows[row].r);
        if (a.parent[i] < 0) {
            CHECK(rows[row].parent == -1);
        } else {
            CHECK(rows[row].parent == (int)a.source_id[a.parent[i]]);
        }
    }
    for (int k = 0; k < n; k++) {
        CHECK(seen[k] == 1);
    }
    /* breadth-first, children in file order: 900; 12; 57, 3; 41, 8 */
    static const unsigned order[6] = { 900, 12, 57, 3, 41, 8 };
    for (int i = 0; i < n; i++) {
        CHECK(a.source_id[i] == order[i]);
    }
    asset_fini(&a);
}

static void test_species_end_to_end(void)
{
    CHECK(bake("--species " GALE_SOURCE_DIR "/configs/species/oak.json --modes 12 --out oak.gasset "
               "--report oak.json --modes-png oak.png") == 0);
    check_report_file("oak.json", 0, 12);
    CHECK(exists("oak.png"));
    CHECK(count_files() == 4); /* ok.gasset, ids.gasset, oak.gasset, oak.png */
    /* an L-system skeleton has no source ids, but every bake writes the static correction
     * (SRES): a version-2 file */
    CHECK(file_version("oak.gasset") == 2);
    char p[512];
    snprintf(p, sizeof p, "%s/oak.gasset", dir);
    asset a;
    gale_err err;
    CHECK(asset_load(p, &a, &err) == GALE_OK);
    CHECK(a.n_nodes > 100 && a.source_id == NULL);
    asset_fini(&a);
}

int main(void)
{
    snprintf(dir, sizeof dir, "%s/bake-cli-XXXXXX", GALE_TEST_DIR);
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    RUN(test_bad_arguments);
    RUN(test_bad_files);
    RUN(test_input_caps);
    RUN(test_skeleton_end_to_end);
    RUN(test_source_ids);
    RUN(test_species_end_to_end);
    char cmd[512];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir); /* whether the checks passed or not */
    if (system(cmd) != 0) {
        fprintf(stderr, "could not remove %s\n", dir);
    }
    return check_report();
}
