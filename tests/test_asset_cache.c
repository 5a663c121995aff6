/* Asset cache: round trip, default directory, atomic replace, corruption detected and the
 * entry dropped, hostile keys refused. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "asset_cache.h"
#include "check.h"

static char root[256];

static void test_round_trip(void)
{
    gale_err err = { 0 };
    char dir[512];
    snprintf(dir, sizeof dir, "%s/a/b/c", root); /* parents created */
    asset_cache *c = asset_cache_create(&(asset_cache_desc){ .dir = dir }, &err);
    CHECK(c != NULL);
    if (!c) {
        return;
    }
    uint8_t buf[5000];
    for (int i = 0; i < 5000; i++) {
        buf[i] = (uint8_t)(i * 7 + 3);
    }
    uint8_t *out = NULL;
    size_t len = 0;
    CHECK(asset_cache_load(c, "0123abcd", &out, &len, &err) == GALE_E_IO);
    CHECK_STR_HAS(err.msg, "a/b/c/0123abcd: No such file");
    CHECK(asset_cache_store(c, "0123abcd", buf, sizeof buf, &err) == 0);
    CHECK(asset_cache_load(c, "0123abcd", &out, &len, &err) == 0);
    CHECK(len == sizeof buf && out && memcmp(out, buf, len) == 0);
    free(out);
    /* replace: the new content wins, no temporary files left behind */
    buf[10] ^= 0xff;
    CHECK(asset_cache_store(c, "0123abcd", buf, 100, &err) == 0);
    CHECK(asset_cache_load(c, "0123abcd", &out, &len, &err) == 0);
    CHECK(len == 100 && memcmp(out, buf, 100) == 0);
    free(out);
    char tmp[600];
    snprintf(tmp, sizeof tmp, "%s/0123abcd.tmp.%ld", dir, (long)getpid());
    CHECK(access(tmp, F_OK) != 0);
    /* empty payload is a valid entry */
    CHECK(asset_cache_store(c, "empty", buf, 0, &err) == 0);
    CHECK(asset_cache_load(c, "empty", &out, &len, &err) == 0 && len == 0);
    free(out);
    asset_cache_destroy(c);
}

static void corrupt_byte(const char *path, long off)
{
    FILE *f = fopen(path, "r+b");
    CHECK(f != NULL);
    if (!f) {
        return;
    }
    fseek(f, off, SEEK_SET);
    int ch = fgetc(f);
    fseek(f, off, SEEK_SET);
    fputc(ch ^ 0x01, f);
    fclose(f);
}

static void test_corruption(void)
{
    gale_err err = { 0 };
    asset_cache *c = asset_cache_create(&(asset_cache_desc){ .dir = root }, &err);
    uint8_t buf[300];
    for (int i = 0; i < 300; i++) {
        buf[i] = (uint8_t)i;
    }
    char path[600];
    snprintf(path, sizeof path, "%s/k1", root);
    uint8_t *out;
    size_t len;
    /* one flipped payload bit */
    asset_cache_store(c, "k1", buf, sizeof buf, &err);
    corrupt_byte(path, 24 + 150);
    CHECK(asset_cache_load(c, "k1", &out, &len, &err) == GALE_E_CHECKSUM);
    CHECK_STR_HAS(err.msg, "k1: checksum expected");
    CHECK(out == NULL && access(path, F_OK) != 0); /* dropped */
    /* truncated */
    asset_cache_store(c, "k1", buf, sizeof buf, &err);
    CHECK(truncate(path, 200) == 0);
    CHECK(asset_cache_load(c, "k1", &out, &len, &err) == GALE_E_FORMAT);
    CHECK_STR_HAS(err.msg, "length expected 300 bytes, got 176");
    /* trailing garbage */
    asset_cache_store(c, "k1", buf, sizeof buf, &err);
    FILE *f = fopen(path, "ab");
    fputc('x', f);
    fclose(f);
    CHECK(asset_cache_load(c, "k1", &out, &len, &err) == GALE_E_FORMAT);
    CHECK_STR_HAS(err.msg, "got more than 300");
    /* not an entry at all */
    f = fopen(path, "wb");
    fputs("hello", f);
    fclose(f);
    CHECK(asset_cache_load(c, "k1", &out, &len, &err) == GALE_E_FORMAT);
    CHECK_STR_HAS(err.msg, "not a cache entry");
    /* huge length field */
    asset_cache_store(c, "k1", buf, sizeof buf, &err);
    corrupt_byte(path, 15);
    CHECK(asset_cache_load(c, "k1", &out, &len, &err) == GALE_E_FORMAT);
    CHECK_STR_HAS(err.msg, "offset 8: length expected <=");
    asset_cache_destroy(c);
}

static void test_keys(void)
{
    gale_err err = { 0 };
    CHECK(asset_cache_key_ok("9f86d081884c7d65-oak.asset"));
    CHECK(!asset_cache_key_ok(""));
    CHECK(!asset_cache_key_ok(NULL));
    CHECK(!asset_cache_key_ok("../etc/passwd"));
    CHECK(!asset_cache_key_ok("a/b"));
    CHECK(!asset_cache_key_ok(".hidden"));
    CHECK(!asset_cache_key_ok("sp ace"));
    char longkey[200];
    memset(longkey, 'a', sizeof longkey - 1);
    longkey[sizeof longkey - 1] = '\0';
    CHECK(!asset_cache_key_ok(longkey));
    asset_cache *c = asset_cache_create(&(asset_cache_desc){ .dir = root }, &err);
    uint8_t b = 1, *out;
    size_t len;
    CHECK(asset_cache_store(c, "../x", &b, 1, &err) == GALE_E_ARG);
    CHECK_STR_HAS(err.msg, "bad key \"../x\"");
    CHECK(asset_cache_load(c, "a/../../x", &out, &len, &err) == GALE_E_ARG);
    asset_cache_destroy(c);
    asset_cache_destroy(NULL);
}

static void test_default_dir(void)
{
    gale_err err = { 0 };
    char xdg[512], want[600];
    snprintf(xdg, sizeof xdg, "%s/xdg", root);
    setenv("XDG_CACHE_HOME", xdg, 1);
    asset_cache *c = asset_cache_create(NULL, &err);
    snprintf(want, sizeof want, "%s/gale", xdg);
    CHECK(c && strcmp(asset_cache_dir(c), want) == 0);
    asset_cache_destroy(c);
    unsetenv("XDG_CACHE_HOME");
    setenv("HOME", root, 1);
    c = asset_cache_create(&(asset_cache_desc){ 0 }, &err);
    snprintf(want, sizeof want, "%s/.cache/gale", root);
    CHECK(c && strcmp(asset_cache_dir(c), want) == 0);
    struct stat st;
    CHECK(stat(want, &st) == 0 && S_ISDIR(st.st_mode));
    asset_cache_destroy(c);
    /* a file where the directory should be */
    char file[600];
    snprintf(file, sizeof file, "%s/plainfile", root);
    FILE *f = fopen(file, "w");
    fclose(f);
    snprintf(want, sizeof want, "%s/plainfile/sub", root);
    CHECK(asset_cache_create(&(asset_cache_desc){ .dir = want }, &err) == NULL);
    CHECK_STR_HAS(err.msg, "cannot create cache directory");
}

static void test_hash(void)
{
    /* FNV-1a 64 published vectors */
    CHECK(asset_cache_hash((const uint8_t *)"", 0) == 0xcbf29ce484222325ull);
    CHECK(asset_cache_hash((const uint8_t *)"a", 1) == 0xaf63dc4c8601ec8cull);
    CHECK(asset_cache_hash((const uint8_t *)"foobar", 6) == 0x85944171f73967e8ull);
}

/* The welcome's hash check (ASSET.md "Content hash" test vectors). */
static void test_verify(void)
{
    gale_err e = { 0 };
    const uint8_t g[4] = { 'g', 'a', 'l', 'e' };
    CHECK(asset_cache_verify("5e643f92003bf3a8", g, 4, "x", &e) == 0);
    CHECK(asset_cache_verify("5e643f92003bf3a9", g, 4, "/assets/x.gasset", &e) == GALE_E_CHECKSUM);
    CHECK_STR_HAS(e.msg, "/assets/x.gasset: content hash 5e643f92003bf3a8, expected "
                         "5e643f92003bf3a9 (the welcome's): refused");
    CHECK(asset_cache_verify("5E643F92003BF3A8", g, 4, "x", &e) == GALE_E_ARG);
    CHECK(asset_cache_verify("f52a15e9a9b5e89b", g, 0, "x", &e) == 0);
}

int main(void)
{
    snprintf(root, sizeof root, "%s/asset_cache_%ld", GALE_TEST_DIR, (long)getpid());
    RUN(test_round_trip);
    RUN(test_corruption);
    RUN(test_keys);
    RUN(test_default_dir);
    RUN(test_hash);
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", root);
    CHECK(system(cmd) == 0);
    RUN(test_verify);
    return check_report();
}
