/* The browser client's files by URL (net_web.h): the three pages by their short paths,
 * the rest by the path they were embedded at, each with the Content-Type its name ends
 * in (a browser runs an ES module only when it is served as JavaScript). */
#include "net_web.h"

#include <stdbool.h>
#include <string.h>

static const struct {
    const char *path; /* what the visitor types */
    const char *file; /* the embedded page */
} pages[] = {
    { "/", "/web/index.html" },
    { "/kiosk", "/web/kiosk.html" },
    { "/wall", "/web/wall.html" },
    { "/status.html", "/web/status.html" },
};

static const struct {
    const char *ext;
    const char *type;
} types[] = {
    { ".html", "text/html; charset=utf-8" },
    { ".js", "text/javascript; charset=utf-8" },
    { ".css", "text/css; charset=utf-8" },
    { ".json", "application/json" },
    { ".glsl", "text/plain; charset=utf-8" },
    { ".vert", "text/plain; charset=utf-8" },
    { ".frag", "text/plain; charset=utf-8" },
};

static bool ends_with(const char *s, const char *tail)
{
    size_t n = strlen(s), t = strlen(tail);
    return n >= t && !memcmp(s + n - t, tail, t);
}

const net_web_file *net_web_find(const char *uri, const char **type)
{
    for (size_t i = 0; i < sizeof pages / sizeof pages[0]; i++) {
        if (!strcmp(uri, pages[i].path)) {
            uri = pages[i].file;
            break;
        }
    }
    for (int i = 0; i < net_web_n_files; i++) {
        if (strcmp(uri, net_web_files[i].url)) {
            continue;
        }
        *type = "application/octet-stream";
        for (size_t k = 0; k < sizeof types / sizeof types[0]; k++) {
            if (ends_with(uri, types[k].ext)) {
                *type = types[k].type;
                break;
            }
        }
        return &net_web_files[i];
    }
    return NULL;
}
