/* A kiosk token read from a file (gale-server --kiosk-token-file writes one): given on
 * the command line instead, the token shows in the process list to every local user. */
#ifndef GALE_TOKEN_FILE_H
#define GALE_TOKEN_FILE_H

#include <stddef.h>

/* The first line of path (without its line end) into out[cap]; 0, or -1 after a message
 * on stderr naming prog and the file (cannot open, first line empty, longer than cap - 1). */
int token_file_read(const char *prog, const char *path, char *out, size_t cap);

#endif
