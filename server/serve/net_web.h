/* The browser client's pages (web/) and the shaders they compile (shaders/), embedded
 * in gale-server (web_embed.cmake) and served over HTTP (server/SERVER.md "Browser
 * client"). */
#ifndef GALE_NET_WEB_H
#define GALE_NET_WEB_H

#include <stddef.h>

typedef struct net_web_file {
    const char *url;            /* the path it is served at, e.g. "/web/app.js" */
    const unsigned char *bytes;
    size_t len;
} net_web_file;

extern const net_web_file net_web_files[];
extern const int net_web_n_files;

/* The embedded file served at uri (its path: lws strips the query string), with its
 * Content-Type in *type; NULL when uri names none. "/", "/kiosk" and "/wall" are the
 * three pages. */
const net_web_file *net_web_find(const char *uri, const char **type);

#endif
