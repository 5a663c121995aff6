/* Skeleton CSV import: a good file is reordered parents-first with the root at the
 * origin and sensible branch orders; every fault of the format is rejected with the
 * exact message naming the file and line, and leaves the skeleton empty. */
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "skeleton.h"

static int parse(const char *csv, skeleton *s, gale_err *err)
{
    return skeleton_parse_csv(csv, strlen(csv), "t.csv", s, err);
}

static void test_good(void)
{
    /* children listed before parents, ids not contiguous, root off the origin */
    const char *csv = "id,parent,x,y,z,radius\n"
                      "# a comment\n"
                      "30,20,1,1,3,0.05\n"
                      "10,-1,1,1,0,0.3\r\n"
                      "\n"
                      "20,10,1,1,2,0.2\n"
                      " 40 , 20 , 2 , 1 , 2.5 , 0.04 \n";
    skeleton s;
    gale_err err = { 0 };
    int rc = parse(csv, &s, &err);
    if (rc) {
        fprintf(stderr, "%s\n", err.msg);
    }
    CHECK(rc == 0);
    CHECK(s.n == 4);
    if (rc == 0 && s.n == 4) {
        CHECK(s.src_id[0] == 10 && s.parent[0] == -1);
        CHECK(s.pos[0] == 0.0f && s.pos[1] == 0.0f && s.pos[2] == 0.0f);
        /* the root's own position, kept so pos + src_origin is the file's */
        CHECK(s.src_origin[0] == 1.0f && s.src_origin[1] == 1.0f && s.src_origin[2] == 0.0f);
        CHECK(s.src_id[1] == 20 && s.parent[1] == 0);
        CHECK_NEAR(s.pos[3 * 1 + 2], 2.0, 1e-6);
        /* 30 and 40 both hang on 20, in file order */
        CHECK(s.src_id[2] == 30 && s.parent[2] == 1);
        CHECK(s.src_id[3] == 40 && s.parent[3] == 1);
        CHECK_NEAR(s.pos[3 * 3 + 0], 1.0, 1e-6); /* 2 - root's 1 */
        CHECK_NEAR(s.radius[3], 0.04, 1e-7);
        /* 30 continues straight up: trunk; 40 leans out: first-order branch */
        CHECK(s.order[0] == 0 && s.order[1] == 0 && s.order[2] == 0 && s.order[3] == 1);
        for (int i = 1; i < s.n; i++) {
            CHECK(s.parent[i] >= 0 && s.parent[i] < i);
        }
    }
    skeleton_fini(&s);
    /* header in capitals, no final newline */
    CHECK(parse("ID,Parent,X,Y,Z,Radius\n0,-1,0,0,0,0.1\n1,0,0,0,1,0.1", &s, &err) == 0);
    CHECK(s.n == 2);
    skeleton_fini(&s);
}

static void expect(const char *csv, int code, const char *msg)
{
    skeleton s;
    gale_err err = { 0 };
    int rc = parse(csv, &s, &err);
    CHECK(rc == code);
    CHECK_STR_HAS(err.msg, msg);
    CHECK(s.n == 0 && s.parent == NULL && s.pos == NULL);
}

#define H "id,parent,x,y,z,radius\n"

static void test_faults(void)
{
    expect("", GALE_E_PARSE,
           "t.csv: empty file: expected a header line \"id,parent,x,y,z,radius\" and nodes");
    expect("\n\n  \n", GALE_E_PARSE, "t.csv: empty file");
    expect(H, GALE_E_PARSE, "t.csv: no nodes after the header");
    expect(
        "0,-1,0,0,0,0.1\n", GALE_E_PARSE,
        "t.csv:1: header missing: expected \"id,parent,x,y,z,radius\" as the first line, got data \"0...\"");
    expect("id,parent,x,y,radius\n", GALE_E_PARSE, "t.csv:1: header missing");
    expect(H "0,-1,0,0,0\n", GALE_E_PARSE,
           "t.csv:2: expected 6 columns (id,parent,x,y,z,radius), got 5");
    expect(H "0,-1,0,0,0,0.1,7\n", GALE_E_PARSE,
           "t.csv:2: expected 6 columns (id,parent,x,y,z,radius), got 7");
    expect(H "0,-1,0,0,0,0.1\n,0,0,0,1,0.1\n", GALE_E_PARSE, "t.csv:3: id: missing");
    expect(H "0,-1,0,0,0,0.1\n1,,0,0,1,0.1\n", GALE_E_PARSE, "t.csv:3: parent: missing");
    expect(H "0,-1,0,0,0,0.1\nseven,0,0,0,1,0.1\n", GALE_E_PARSE,
           "t.csv:3: id: expected an integer, got \"seven\"");
    expect(H "0,-1,0,0,0,0.1\n1,0.5,0,0,1,0.1\n", GALE_E_PARSE,
           "t.csv:3: parent: expected an integer, got \"0.5\"");
    expect(H "0,-1,0,0,0,0.1\n1,0,0,0,1e,0.1\n", GALE_E_PARSE,
           "t.csv:3: z: expected a number, got \"1e\"");
    expect(H "0,-1,0,0,0,0.1\n1,0,abc,0,1,0.1\n", GALE_E_PARSE,
           "t.csv:3: x: expected a number, got \"abc\"");
    expect(H "0,-1,0,0,0,0.1\n1,0,0,nan,1,0.1\n", GALE_E_PARSE,
           "t.csv:3: y: expected a finite number, got \"nan\"");
    expect(H "0,-1,0,0,0,0.1\n1,0,0,0,inf,0.1\n", GALE_E_PARSE,
           "t.csv:3: z: expected a finite number, got \"inf\"");
    expect(H "0,-1,0,0,0,0.1\n1,0,0,0,1,NaN\n", GALE_E_PARSE,
           "t.csv:3: radius: expected a finite number, got \"NaN\"");
    expect(H "0,-1,0,0,0,0.1\n1,0,0,0,1,\n", GALE_E_PARSE, "t.csv:3: radius: missing");
    expect(H "0,-1,0,0,0,0.1\n1,0,0,0,1,0\n", GALE_E_RANGE, "t.csv:3: radius: expected > 0, got 0");
    expect(H "0,-1,0,0,0,0.1\n1,0,0,0,1,-0.2\n", GALE_E_RANGE,
           "t.csv:3: radius: expected > 0, got -0.2");
    /* a radius that would underflow float32 to 0 (found by fuzz_skeleton_csv) */
    expect(H "0,-1,0,0,0,0.1\n1,0,0,0,1,5e-48\n", GALE_E_RANGE,
           "t.csv:3: radius: expected at least 1e-06 m, got 5e-48");
    expect(H "0,-1,0,0,0,0.1\n1,0,0,0,1e9,0.1\n", GALE_E_RANGE,
           "t.csv:3: z: expected |z| <= 1000 m, got 1e+09");
    expect(H "-3,-1,0,0,0,0.1\n", GALE_E_RANGE, "t.csv:2: id: expected 0..2147483647, got -3");
    expect(H "0,-1,0,0,0,0.1\n1,-7,0,0,1,0.1\n", GALE_E_RANGE,
           "t.csv:3: parent: expected -1 (root) or a node id, got -7");
    expect(H "0,-1,0,0,0,0.1\n1,0,0,0,1,0.1\n2,1,0,0,2,0.1\n1,0,1,0,1,0.1\n", GALE_E_PARSE,
           "t.csv:5: duplicate id 1 (first on line 3)");
    expect(H "0,-1,0,0,0,0.1\n1,0,0,0,1,0.1\n2,9,0,0,2,0.1\n", GALE_E_PARSE,
           "t.csv:4: unknown parent 9 of node 2");
    expect(H "0,-1,0,0,0,0.1\n1,0,0,0,1,0.1\n5,-1,3,0,0,0.1\n", GALE_E_PARSE,
           "t.csv:4: several roots: node 5 has parent -1, as has node 0 on line 2");
    expect(H "0,1,0,0,0,0.1\n1,0,0,0,1,0.1\n", GALE_E_PARSE,
           "t.csv: no root: expected one node with parent -1");
    expect(H "0,-1,0,0,0,0.1\n1,1,0,0,1,0.1\n", GALE_E_PARSE,
           "t.csv:3: cycle: node 1 is its own parent");
    expect(H "0,-1,0,0,0,0.1\n1,0,0,0,1,0.1\n2,3,0,0,2,0.1\n3,4,0,0,3,0.1\n4,2,0,0,4,0.1\n"
             "5,4,0,0,5,0.1\n",
           GALE_E_PARSE, "t.csv:4: cycle: node 2 (parent 3) never reaches the root");
    expect(H "0,-1,0,0,0,0.1\n1,0,0,0,1,0.1\n2,1,0,0,1,0.1\n", GALE_E_RANGE,
           "t.csv:4: zero-length edge: node 2 sits at the position of its parent 1 (line 3)");
    char big[200];
    memset(big, '1', sizeof big);
    big[sizeof big - 1] = '\0';
    char csv[400];
    snprintf(csv, sizeof csv, H "0,-1,0,0,0,0.1\n1,0,0,0,%s,0.1\n", big);
    expect(csv, GALE_E_PARSE, "t.csv:3: z: field longer than 63 characters");
    /* a NUL byte inside a field */
    const char nul[] = H "0,-1,0,0,0,0.1\n1,0,0,0,1\0,0.1\n";
    skeleton s;
    gale_err err = { 0 };
    CHECK(skeleton_parse_csv(nul, sizeof nul - 1, "t.csv", &s, &err) == GALE_E_PARSE);
    CHECK_STR_HAS(err.msg, "t.csv:3: z: expected a number, got \"1?\"");
}

static void test_load(void)
{
    skeleton s;
    gale_err err = { 0 };
    CHECK(skeleton_load_csv("/nonexistent/tree.csv", &s, &err) == GALE_E_IO);
    CHECK_STR_HAS(err.msg, "/nonexistent/tree.csv: cannot open");
    char path[] = "test_skeleton_csv.tmp.csv";
    FILE *f = fopen(path, "w");
    CHECK(f != NULL);
    if (f) {
        fputs(H "0,-1,0,0,0,0.2\n1,0,0,0,1.5,0.1\n2,1,0.5,0,2,0.05\n", f);
        fclose(f);
    }
    CHECK(skeleton_load_csv(path, &s, &err) == 0);
    CHECK(s.n == 3);
    skeleton_fini(&s);
    f = fopen(path, "w");
    if (f) {
        fputs(H "0,-1,0,0,0,0.2\n1,0,0,0,1.5,-1\n", f);
        fclose(f);
    }
    CHECK(skeleton_load_csv(path, &s, &err) == GALE_E_RANGE);
    CHECK_STR_HAS(err.msg, "test_skeleton_csv.tmp.csv:3: radius: expected > 0, got -1");
    remove(path);
}

int main(void)
{
    RUN(test_good);
    RUN(test_faults);
    RUN(test_load);
    return check_report();
}
