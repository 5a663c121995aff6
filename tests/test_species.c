/* Species files: the shipped ones load with their values; unknown keys, wrong types and
 * out-of-range values are rejected with the key path in the message. */
#include <string.h>

#include "check.h"
#include "lsystem.h"
#include "species.h"

static int parse(const char *json, species *sp, gale_err *err)
{
    return species_parse(json, strlen(json), "t.json", sp, err);
}

static void test_shipped(void)
{
    const char *names[] = { "oak", "palm", "pine" };
    for (int i = 0; i < 3; i++) {
        char path[512];
        snprintf(path, sizeof path, "%s/configs/species/%s.json", GALE_SOURCE_DIR, names[i]);
        species sp;
        gale_err err = { 0 };
        int rc = species_load(path, &sp, &err);
        if (rc != 0) {
            fprintf(stderr, "%s\n", err.msg);
        }
        CHECK(rc == 0);
        CHECK(strcmp(sp.name, names[i]) == 0);
        CHECK(sp.E_pa > 1e9 && sp.E_pa < 2e10);
        CHECK_NEAR(sp.G_pa, sp.E_pa / 2.6, 1e-6 * sp.E_pa);
        CHECK(sp.leaves_per_tip > 0);
    }
    species palm;
    gale_err err = { 0 };
    char path[512];
    snprintf(path, sizeof path, "%s/configs/species/palm.json", GALE_SOURCE_DIR);
    CHECK(species_load(path, &palm, &err) == 0);
    CHECK_NEAR(palm.E_pa, 4e9, 1.0);
    CHECK(palm.leaf_shape == 1);
}

static void test_values(void)
{
    species sp;
    gale_err err = { 0 };
    const char *j = "{\"name\":\"x\",\"E_pa\":5e9,\"G_pa\":2e9,\"rayleigh_alpha\":0.3,"
                    "\"generator\":{\"seed\":42,\"depth\":3,\"trunk\":{\"whorls\":2,"
                    "\"tip_continue\":true,\"continue_ratio\":0.8}},"
                    "\"look\":{\"leaf_shape\":\"needle\",\"bark_rgb\":[0.1,0.2,0.3]}}";
    CHECK(parse(j, &sp, &err) == 0);
    CHECK(strcmp(sp.name, "x") == 0);
    CHECK_NEAR(sp.E_pa, 5e9, 1.0);
    CHECK_NEAR(sp.G_pa, 2e9, 1.0);
    CHECK_NEAR(sp.rayleigh_alpha, 0.3, 1e-12);
    CHECK(sp.gen.seed == 42);
    CHECK(sp.gen.depth == 3);
    CHECK(sp.gen.trunk.whorls == 2);
    CHECK(sp.gen.trunk.tip_continue == 1);
    CHECK(sp.leaf_shape == 2);
    CHECK_NEAR(sp.bark_rgb[2], 0.3, 1e-6);
    /* absent keys keep the defaults */
    CHECK_NEAR(sp.rho_kg_m3, 1000.0, 1e-9);
    CHECK(sp.leaves_per_tip == 4);
}

static void expect_error(const char *json, int code, const char *msg)
{
    species sp;
    gale_err err = { 0 };
    int rc = parse(json, &sp, &err);
    CHECK(rc == code);
    CHECK_STR_HAS(err.msg, msg);
}

static void test_errors(void)
{
    expect_error("{\"name\":\"x\",\"colour\":1}", GALE_E_PARSE, "t.json: colour: unknown key");
    expect_error("{\"name\":\"x\",\"generator\":{\"trunk\":{\"wirls\":2}}}", GALE_E_PARSE,
                 "t.json: generator.trunk.wirls: unknown key");
    expect_error("{\"name\":\"x\",\"generator\":{\"depth\":11}}", GALE_E_RANGE,
                 "generator.depth: expected an integer in [0, 10], got 11");
    expect_error("{\"name\":\"x\",\"E_pa\":-5}", GALE_E_RANGE,
                 "E_pa: expected a number in [1e+06, 1e+12], got -5");
    expect_error("{\"name\":\"x\",\"E_pa\":\"stiff\"}", GALE_E_PARSE,
                 "E_pa: expected a number, got a string");
    expect_error("{\"E_pa\":1e10}", GALE_E_PARSE, "t.json: name: required key missing");
    expect_error("{\"name\":\"x\",\"generator\":[]}", GALE_E_PARSE,
                 "generator: expected an object, got an array");
    expect_error("{\"name\":\"x\",\"generator\":{\"branch\":{\"start\":0.9,\"end\":0.1}}}",
                 GALE_E_RANGE, "generator.branch.start: expected <= end (0.1), got 0.9");
    expect_error("{\"name\":\"x\",\"look\":{\"leaf_shape\":\"cube\"}}", GALE_E_RANGE,
                 "look.leaf_shape: expected \"broad\", \"palm\" or \"needle\", got \"cube\"");
    expect_error("{\"name\":\"x\",\"look\":{\"leaf_rgb\":[1,2]}}", GALE_E_PARSE,
                 "look.leaf_rgb: expected an array of 3 numbers");
    expect_error("{\"name\":\"x\",\"look\":{\"leaf_rgb\":[0.1,2,0.1]}}", GALE_E_RANGE,
                 "look.leaf_rgb[1]: expected a number in [0, 1], got 2");
    expect_error("{\"name\":\"x\",\n \"E_pa\": }", GALE_E_PARSE, "t.json:2:");
    expect_error("", GALE_E_PARSE, "t.json: empty file");
    expect_error("{\"name\":\"\"}", GALE_E_RANGE, "name: expected a non-empty string");
    /* a wrong-typed boolean is reported, never read uninitialised (found by fuzz_species) */
    expect_error("{\"name\":\"x\",\"generator\":{\"trunk\":{\"tip_continue\":7}}}",
                 GALE_E_PARSE, "generator.trunk.tip_continue: expected a boolean, got a number");
}

/* Bytes after the object are refused at their line:col; whitespace is not. */
static void test_trailing_bytes(void)
{
    expect_error("{\"name\":\"x\"} x", GALE_E_PARSE,
                 "t.json:1:14: trailing bytes after the JSON object: expected the end of the file");
    expect_error("{\"name\":\"x\"}\n{\"name\":\"y\"}\n", GALE_E_PARSE,
                 "t.json:2:1: trailing bytes after the JSON object: expected the end of the file");
    species sp;
    gale_err err = { 0 };
    CHECK(parse("{\"name\":\"x\"}\n\t \r\n", &sp, &err) == 0);
    CHECK(strcmp(sp.name, "x") == 0);
}

/* The generator runs after the parse; its failures still name the species file and the
 * generator key to change. */
static void test_generator_errors_name_the_file(void)
{
    const char *boom = "{\"name\":\"x\",\"generator\":{\"depth\":10,\"branch\":"
                       "{\"tip_children\":8,\"prune_prob\":0,\"length_ratio\":1}}}\n";
    species sp;
    skeleton s;
    gale_err err = { 0 };
    CHECK(species_parse(boom, strlen(boom), "oak.json", &sp, &err) == 0);
    CHECK(strcmp(sp.gen.where, "oak.json") == 0);
    CHECK(lsystem_generate(&sp.gen, &s, &err) == GALE_E_RANGE);
    CHECK_STR_HAS(err.msg, "oak.json: generator.depth: 10 levels grow more than 200000 stems: "
                           "expected fewer (lower depth, whorls, per_whorl or tip_children)");
    /* loaded from a file (in the build directory): the path it was loaded from */
    FILE *f = fopen("species-explode.json", "wb");
    CHECK(f != NULL);
    if (f) {
        fputs(boom, f);
        fclose(f);
    }
    CHECK(species_load("species-explode.json", &sp, &err) == 0);
    CHECK(lsystem_generate(&sp.gen, &s, &err) == GALE_E_RANGE);
    CHECK(strncmp(err.msg, "species-explode.json: generator.depth: 10 levels", 48) == 0);
    remove("species-explode.json");
    /* a failed parse leaves the defaults, which name no file */
    CHECK(parse("{\"name\":1}", &sp, &err) == GALE_E_PARSE);
    CHECK(sp.gen.where[0] == '\0');
}

static void test_load_missing(void)
{
    species sp;
    gale_err err = { 0 };
    CHECK(species_load("/nonexistent/oak.json", &sp, &err) == GALE_E_IO);
    CHECK_STR_HAS(err.msg, "/nonexistent/oak.json");
}

int main(void)
{
    RUN(test_shipped);
    RUN(test_values);
    RUN(test_errors);
    RUN(test_trailing_bytes);
    RUN(test_generator_errors_name_the_file);
    RUN(test_load_missing);
    return check_report();
}
