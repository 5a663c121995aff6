/* Asset files on disk: write to a temporary file in the same directory, fsync, rename
 * over the target (atomic on POSIX file systems); read whole, then asset_decode. */
#include "asset_file.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* Largest file read: the decoder's own limits keep a valid asset well under this. */
#define ASSET_FILE_MAX_BYTES ((size_t)2 << 30)

int asset_save(const asset *a, const char *path, gale_err *err)
{
    uint8_t *buf = NULL;
    size_t len = 0;
    int rc = asset_encode(a, &buf, &len, err);
    if (rc != 0) {
        return rc;
    }
    char tmp[4096];
    int n = snprintf(tmp, sizeof tmp, "%s.tmp.%ld", path, (long)getpid());
    if (n < 0 || (size_t)n >= sizeof tmp) {
        free(buf);
        return gale_errf(err, GALE_E_ARG, "%s: path too long", path);
    }
    int fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) {
        int e = errno;
        free(buf);
        return gale_errf(err, GALE_E_IO, "%s: cannot create %s: %s", path, tmp, strerror(e));
    }
    size_t done = 0;
    while (done < len) {
        ssize_t w = write(fd, buf + done, len - done);
        if (w < 0 && errno == EINTR) {
            continue;
        }
        if (w <= 0) {
            int e = w < 0 ? errno : ENOSPC;
            close(fd);
            unlink(tmp);
            free(buf);
            return gale_errf(err, GALE_E_IO, "%s: write failed after %zu of %zu bytes: %s", path,
                             done, len, strerror(e));
        }
        done += (size_t)w;
    }
    free(buf);
    if (fsync(fd) != 0 || close(fd) != 0) {
        int e = errno;
        unlink(tmp);
        return gale_errf(err, GALE_E_IO, "%s: cannot flush: %s", path, strerror(e));
    }
    if (rename(tmp, path) != 0) {
        int e = errno;
        unlink(tmp);
        return gale_errf(err, GALE_E_IO, "%s: cannot rename %s into place: %s", path, tmp,
                         strerror(e));
    }
    return GALE_OK;
}

int asset_load(const char *path, asset *a, gale_err *err)
{
    memset(a, 0, sizeof *a);
    FILE *f = fopen(path, "rb");
    if (!f) {
        return gale_errf(err, GALE_E_IO, "%s: cannot open: %s", path, strerror(errno));
    }
    struct stat st;
    if (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode)) {
        fclose(f);
        return gale_errf(err, GALE_E_IO, "%s: not a regular file", path);
    }
    if ((unsigned long long)st.st_size > ASSET_FILE_MAX_BYTES) {
        fclose(f);
        return gale_errf(err, GALE_E_FORMAT, "%s: %lld bytes, over the %zu-byte limit", path,
                         (long long)st.st_size, ASSET_FILE_MAX_BYTES);
    }
    size_t len = (size_t)st.st_size;
    uint8_t *buf = malloc(len ? len : 1);
    if (!buf) {
        fclose(f);
        return gale_errf(err, GALE_E_NOMEM, "%s: out of memory for %zu bytes", path, len);
    }
    size_t got = fread(buf, 1, len, f);
    int rerr = ferror(f);
    fclose(f);
    if (rerr || got != len) {
        free(buf);
        return gale_errf(err, GALE_E_IO, "%s: read %zu of %zu bytes", path, got, len);
    }
    int rc = asset_decode(buf, len, path, a, err);
    free(buf);
    return rc;
}
