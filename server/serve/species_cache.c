/* Species assets baked on start or loaded from the cache: see species_cache.h. */
#include "species_cache.h"
#include "mono.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "bake.h"
#include "hash.h"
#include "quant_steps.h"
#include "lsystem.h"
#include "species.h"

/* Reads a whole file (at most max bytes) into a malloc'd buffer. */
static int read_all(const char *path, size_t max, uint8_t **out, size_t *len, gale_err *err)
{
    *out = NULL;
    *len = 0;
    FILE *f = fopen(path, "rb");
    if (!f) {
        return gale_errf(err, GALE_E_IO, "%s: cannot open: %s", path, strerror(errno));
    }
    long n = -1;
    if (fseek(f, 0, SEEK_END) == 0) {
        n = ftell(f);
    }
    uint8_t *b = NULL;
    if (n < 0 || (size_t)n > max || fseek(f, 0, SEEK_SET) != 0 ||
        !(b = malloc((size_t)n + 1)) || fread(b, 1, (size_t)n, f) != (size_t)n) {
        fclose(f);
        free(b);
        return gale_errf(err, GALE_E_IO, "%s: cannot read (or larger than %zu bytes)", path, max);
    }
    fclose(f);
    b[n] = 0;
    *out = b;
    *len = (size_t)n;
    return GALE_OK;
}

/* mkdir -p */
static int make_dirs(const char *dir, gale_err *err)
{
    char p[512];
    snprintf(p, sizeof p, "%s", dir);
    for (char *s = p + 1; *s; s++) {
        if (*s == '/') {
            *s = 0;
            mkdir(p, 0755);
            *s = '/';
        }
    }
    if (mkdir(p, 0755) != 0 && errno != EEXIST) {
        return gale_errf(err, GALE_E_IO, "%s: cannot create the cache folder: %s", dir,
                         strerror(errno));
    }
    return GALE_OK;
}

static int write_atomic(const char *path, const uint8_t *b, size_t n, gale_err *err)
{
    char tmp[600];
    snprintf(tmp, sizeof tmp, "%s.tmp-%ld", path, (long)getpid());
    FILE *f = fopen(tmp, "wb");
    if (!f) {
        return gale_errf(err, GALE_E_IO, "%s: cannot create: %s", tmp, strerror(errno));
    }
    bool ok = fwrite(b, 1, n, f) == n;
    ok = fflush(f) == 0 && ok;
    ok = fsync(fileno(f)) == 0 && ok;
    ok = fclose(f) == 0 && ok;
    if (!ok || rename(tmp, path) != 0) {
        unlink(tmp);
        return gale_errf(err, GALE_E_IO, "%s: cannot write: %s", path, strerror(errno));
    }
    return GALE_OK;
}

int species_cache_get(const char *species_file, int n_modes, const char *cache_dir,
                      species_entry *e, gale_err *err)
{
    memset(e, 0, sizeof *e);
    double t0 = mono_s();
    uint8_t *text = NULL;
    size_t len = 0;
    species sp;
    skeleton sk;
    memset(&sk, 0, sizeof sk);
    int rc = read_all(species_file, 1 << 20, &text, &len, err);
    if (rc || (rc = species_parse((const char *)text, len, species_file, &sp, err))) {
        goto fail;
    }
    /* the key gale-bake uses: species bytes, mode count, bake version */
    const int ver = BAKE_VERSION;
    uint64_t key = bake_hash(BAKE_HASH_SEED, text, len);
    key = bake_hash(key, &n_modes, sizeof n_modes);
    key = bake_hash(key, &ver, sizeof ver);
    e->source_hash = key;
    e->drag = sp.drag;
    if ((rc = make_dirs(cache_dir, err))) {
        goto fail;
    }
    snprintf(e->path, sizeof e->path, "%s/%s-%016llx.gasset", cache_dir, sp.name,
             (unsigned long long)key);
    gale_err le;
    if (read_all(e->path, 512u << 20, &e->bytes, &e->len, &le) == GALE_OK) {
        if (asset_decode(e->bytes, e->len, e->path, &e->a, &le) == GALE_OK &&
            e->a.source_hash == key && (int)e->a.n_modes == n_modes) {
            goto done;
        }
        /* damaged or stale: bake again and replace it */
        fprintf(stderr, "gale-server: %s: not usable (%s): baking again\n", e->path,
                le.msg[0] ? le.msg : "source hash differs");
        asset_fini(&e->a);
        free(e->bytes);
        e->bytes = NULL;
    }
    if ((rc = lsystem_generate(&sp.gen, &sk, err))) {
        goto fail;
    }
    bake_desc d = { .n_modes = n_modes, .params_json = (const char *)text, .source_hash = key };
    if ((rc = bake_run(&sk, &sp, &d, &e->a, NULL, err)) ||
        (rc = asset_encode(&e->a, &e->bytes, &e->len, err)) ||
        (rc = write_atomic(e->path, e->bytes, e->len, err))) {
        goto fail;
    }
    e->baked = true;
done:
    if ((rc = quant_steps_derive(&e->a, 0, e->qstep, err)) ||
        (rc = damage_table_build(&e->a, sp.E_pa, sp.drag_c, &sp.damage, &e->damage, err))) {
        goto fail;
    }
    snprintf(e->hash, sizeof e->hash, "%016llx", (unsigned long long)hash64(e->bytes, e->len));
    e->seconds = mono_s() - t0;
    free(text);
    skeleton_fini(&sk);
    return GALE_OK;
fail:
    free(text);
    skeleton_fini(&sk);
    species_entry_fini(e);
    return rc;
}

void species_entry_fini(species_entry *e)
{
    if (!e) {
        return;
    }
    damage_table_fini(&e->damage);
    asset_fini(&e->a);
    free(e->bytes);
    memset(e, 0, sizeof *e);
}
