/* A kiosk token read from a file: see token_file.h. */
#include "token_file.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>

int token_file_read(const char *prog, const char *path, char *out, size_t cap)
{
    FILE *f = fopen(path, "r");
    if (!f) {
        fprintf(stderr, "%s: --token-file %s: cannot open (%s)\n", prog, path, strerror(errno));
        return -1;
    }
    if (!fgets(out, (int)cap, f)) {
        out[0] = '\0';
    }
    fclose(f);
    const size_t len = strcspn(out, "\r\n");
    if (len + 1 >= cap && out[len] == '\0') {
        fprintf(stderr, "%s: --token-file %s: the first line is longer than %zu bytes\n", prog,
                path, cap - 1);
        return -1;
    }
    out[len] = '\0';
    if (!out[0]) {
        fprintf(stderr, "%s: --token-file %s: the first line is empty\n", prog, path);
        return -1;
    }
    return 0;
}
