/* gale-client asset fetch: a species' baked asset from the disk cache by content hash,
 * else downloaded from the server over HTTP and cached; either way its bytes must hash
 * to the welcome's hash (protocol/ASSET.md "Content hash"). */
#include <stdio.h>
#include <stdlib.h>

#include "client.h"

/* The asset of one species: from the disk cache, else over HTTP (then cached). */
int client_assets_load(client *c, const ctl_species *s, asset *a, gale_err *err)
{
    uint8_t *buf = NULL;
    size_t len = 0;
    gale_err cerr = { 0 };
    char key[64];
    snprintf(key, sizeof key, "%s.gasset", s->hash);
    bool cached = c->cache && asset_cache_load(c->cache, key, &buf, &len, &cerr) == 0;
    if (cached && asset_cache_verify(s->hash, buf, len, key, &cerr) != 0) {
        /* an entry stored under this hash holding other bytes is never drawn */
        free(buf);
        buf = NULL;
        cached = false;
    }
    if (!cached) {
        if (cerr.code != GALE_E_IO && cerr.code != 0) {
            fprintf(stderr, "gale-client: cache: %s (fetching again)\n", cerr.msg);
        }
        /* the download must hash to the welcome's hash, else it is refused and not cached
         * (PROTOCOL.md "Handshake", ASSET.md "Content hash") */
        int rc = cli_net_fetch_asset(c->net, s->url, s->hash, ASSET_CACHE_MAX_BYTES, 60.0, &buf,
                                     &len, err);
        if (rc != 0) {
            return rc;
        }
    }
    int rc = asset_decode(buf, len, s->url, a, err);
    if (rc == 0 && !cached && c->cache) {
        gale_err serr = { 0 };
        if (asset_cache_store(c->cache, key, buf, len, &serr) != 0) {
            fprintf(stderr, "gale-client: cache: %s\n", serr.msg);
        }
    }
    fprintf(stderr, "gale-client: species %s: %zu bytes %s\n", s->name, len,
            cached ? "from the cache" : "downloaded");
    free(buf);
    return rc;
}
