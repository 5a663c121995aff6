/* Client disk cache of assets by content hash. Entry file `<dir>/<key>`: magic "GALECAC1",
 * u64 payload length, u64 FNV-1a of the payload (both little-endian), then the payload.
 * Written to `<key>.tmp.<pid>`, fsync'd, renamed over the entry. */
#include "asset_cache.h"
#include "hash.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define CACHE_MAGIC  "GALECAC1"
#define CACHE_HEADER 24

struct asset_cache {
    char dir[1024];
};

uint64_t asset_cache_hash(const uint8_t *buf, size_t len)
{
    return hash64_update(HASH64_INIT, buf, len); /* plain FNV-1a 64, no final mix */
}

int asset_cache_verify(const char *want_hex, const uint8_t *buf, size_t len, const char *what,
                       gale_err *err)
{
    if (!want_hex || strlen(want_hex) != 16 || strspn(want_hex, "0123456789abcdef") != 16) {
        return gale_errf(err, GALE_E_ARG, "%s: content hash: expected 16 lowercase hex digits, "
                         "got \"%.20s\"", what, want_hex ? want_hex : "");
    }
    char got[17];
    snprintf(got, sizeof got, "%016llx", (unsigned long long)hash64(buf, len));
    if (strcmp(got, want_hex) != 0) {
        return gale_errf(err, GALE_E_CHECKSUM,
                         "%s: content hash %s, expected %s (the welcome's): refused", what, got,
                         want_hex);
    }
    return 0;
}

int asset_cache_key_ok(const char *key)
{
    size_t n = key ? strlen(key) : 0;
    if (n == 0 || n > ASSET_CACHE_MAX_KEY || key[0] == '.') {
        return 0;
    }
    for (size_t i = 0; i < n; i++) {
        char ch = key[i];
        int ok = (ch >= '0' && ch <= '9') || (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') ||
                 ch == '_' || ch == '.' || ch == '-';
        if (!ok) {
            return 0;
        }
    }
    return 1;
}

/* mkdir -p */
static int make_dirs(char *path, gale_err *err)
{
    for (char *p = path + 1;; p++) {
        if (*p == '/' || *p == '\0') {
            char saved = *p;
            *p = '\0';
            if (mkdir(path, 0755) != 0 && errno != EEXIST) {
                int e = errno;
                *p = saved;
                return gale_errf(err, GALE_E_IO, "%s: cannot create cache directory: %s", path,
                                 strerror(e));
            }
            *p = saved;
            if (saved == '\0') {
                break;
            }
        }
    }
    struct stat st;
    if (stat(path, &st) != 0 || !S_ISDIR(st.st_mode)) {
        return gale_errf(err, GALE_E_IO, "%s: not a directory", path);
    }
    return 0;
}

asset_cache *asset_cache_create(const asset_cache_desc *d, gale_err *err)
{
    char dir[1024];
    int n;
    const char *xdg = getenv("XDG_CACHE_HOME"), *home = getenv("HOME");
    if (d && d->dir) {
        n = snprintf(dir, sizeof dir, "%s", d->dir);
    } else if (xdg && xdg[0] == '/') {
        n = snprintf(dir, sizeof dir, "%s/gale", xdg);
    } else if (home && home[0]) {
        n = snprintf(dir, sizeof dir, "%s/.cache/gale", home);
    } else {
        gale_errf(err, GALE_E_ARG, "asset cache: neither XDG_CACHE_HOME nor HOME is set");
        return NULL;
    }
    if (n <= 0 || (size_t)n >= sizeof dir - ASSET_CACHE_MAX_KEY - 32) {
        gale_errf(err, GALE_E_ARG, "asset cache: directory path too long (%d bytes)", n);
        return NULL;
    }
    if (make_dirs(dir, err) != 0) {
        return NULL;
    }
    asset_cache *c = calloc(1, sizeof *c);
    if (!c) {
        gale_errf(err, GALE_E_NOMEM, "asset cache: no memory");
        return NULL;
    }
    memcpy(c->dir, dir, (size_t)n + 1);
    return c;
}

void asset_cache_destroy(asset_cache *c)
{
    free(c);
}

const char *asset_cache_dir(const asset_cache *c)
{
    return c->dir;
}

static void put_u64(uint8_t *p, uint64_t v)
{
    for (int i = 0; i < 8; i++) {
        p[i] = (uint8_t)(v >> (8 * i));
    }
}

static uint64_t get_u64(const uint8_t *p)
{
    uint64_t v = 0;
    for (int i = 0; i < 8; i++) {
        v |= (uint64_t)p[i] << (8 * i);
    }
    return v;
}

static int write_all(int fd, const uint8_t *p, size_t n)
{
    while (n > 0) {
        ssize_t w = write(fd, p, n);
        if (w < 0) {
            if (errno == EINTR) {
                continue;
            }
            return -1;
        }
        p += w;
        n -= (size_t)w;
    }
    return 0;
}

int asset_cache_store(asset_cache *c, const char *key, const uint8_t *buf, size_t len,
                      gale_err *err)
{
    if (!asset_cache_key_ok(key)) {
        return gale_errf(err, GALE_E_ARG, "asset cache: bad key \"%.40s\"", key ? key : "");
    }
    if (len > ASSET_CACHE_MAX_BYTES) {
        return gale_errf(err, GALE_E_RANGE, "asset cache %s: expected <= %u bytes, got %zu", key,
                         ASSET_CACHE_MAX_BYTES, len);
    }
    char path[1200], tmp[1300];
    snprintf(path, sizeof path, "%s/%s", c->dir, key);
    snprintf(tmp, sizeof tmp, "%s.tmp.%ld", path, (long)getpid());
    uint8_t hdr[CACHE_HEADER];
    memcpy(hdr, CACHE_MAGIC, 8);
    put_u64(hdr + 8, len);
    put_u64(hdr + 16, asset_cache_hash(buf, len));
    int fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) {
        return gale_errf(err, GALE_E_IO, "%s: %s", tmp, strerror(errno));
    }
    if (write_all(fd, hdr, sizeof hdr) != 0 || write_all(fd, buf, len) != 0 || fsync(fd) != 0) {
        int e = errno;
        close(fd);
        unlink(tmp);
        return gale_errf(err, GALE_E_IO, "%s: write: %s", tmp, strerror(e));
    }
    if (close(fd) != 0 || rename(tmp, path) != 0) {
        int e = errno;
        unlink(tmp);
        return gale_errf(err, GALE_E_IO, "%s: %s", path, strerror(e));
    }
    return 0;
}

int asset_cache_load(asset_cache *c, const char *key, uint8_t **out, size_t *len, gale_err *err)
{
    *out = NULL;
    *len = 0;
    if (!asset_cache_key_ok(key)) {
        return gale_errf(err, GALE_E_ARG, "asset cache: bad key \"%.40s\"", key ? key : "");
    }
    char path[1200];
    snprintf(path, sizeof path, "%s/%s", c->dir, key);
    FILE *f = fopen(path, "rb");
    if (!f) {
        return gale_errf(err, GALE_E_IO, "%s: %s", path, strerror(errno));
    }
    uint8_t hdr[CACHE_HEADER];
    uint8_t *data = NULL;
    int rc;
    if (fread(hdr, 1, sizeof hdr, f) != sizeof hdr || memcmp(hdr, CACHE_MAGIC, 8) != 0) {
        rc = gale_errf(err, GALE_E_FORMAT, "%s: not a cache entry (short or bad magic)", path);
        goto bad;
    }
    uint64_t n = get_u64(hdr + 8), want = get_u64(hdr + 16);
    if (n > ASSET_CACHE_MAX_BYTES) {
        rc = gale_errf(err, GALE_E_FORMAT, "%s: offset 8: length expected <= %u, got %llu", path,
                       ASSET_CACHE_MAX_BYTES, (unsigned long long)n);
        goto bad;
    }
    data = malloc(n ? (size_t)n : 1);
    if (!data) {
        fclose(f);
        return gale_errf(err, GALE_E_NOMEM, "%s: no memory for %llu bytes", path,
                         (unsigned long long)n);
    }
    size_t got = fread(data, 1, (size_t)n, f);
    int extra = fgetc(f);
    if (got != n || extra != EOF) {
        rc = gale_errf(err, GALE_E_FORMAT, "%s: length expected %llu bytes, got %s%zu", path,
                       (unsigned long long)n, extra != EOF ? "more than " : "", got);
        goto bad;
    }
    uint64_t h = asset_cache_hash(data, (size_t)n);
    if (h != want) {
        rc = gale_errf(err, GALE_E_CHECKSUM, "%s: checksum expected %016llx, got %016llx", path,
                       (unsigned long long)want, (unsigned long long)h);
        goto bad;
    }
    fclose(f);
    *out = data;
    *len = (size_t)n;
    return 0;
bad:
    free(data);
    fclose(f);
    unlink(path); /* damaged: forget it so the next fetch replaces it */
    return rc;
}
