/* Large streamed arrays on huge pages: see big_alloc.h. */
#define _DEFAULT_SOURCE
#include "big_alloc.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

#define HUGE_PAGE_BYTES ((size_t)2 << 20)

static int small_pages(void)
{
    const char *v = getenv("GALE_SMALL_PAGES");
    return v && strcmp(v, "1") == 0;
}

void *big_alloc(size_t bytes)
{
    bytes = bytes > 0 ? bytes : 1;
    void *p;
    if (bytes >= BIG_ALLOC_MIN_BYTES && !small_pages()) {
        const size_t whole = (bytes + HUGE_PAGE_BYTES - 1) & ~(HUGE_PAGE_BYTES - 1);
        p = aligned_alloc(HUGE_PAGE_BYTES, whole);
        if (p) {
            /* a hint: where the kernel grants none, the array is on small pages */
            (void)madvise(p, whole, MADV_HUGEPAGE);
        }
    } else {
        p = aligned_alloc(64, (bytes + 63) & ~(size_t)63);
    }
    if (p) {
        memset(p, 0, bytes);
    }
    return p;
}

long long big_alloc_huge_bytes(void)
{
    FILE *f = fopen("/proc/self/smaps_rollup", "r");
    if (!f) {
        return -1;
    }
    char line[256];
    long long kib = -1;
    while (fgets(line, sizeof line, f)) {
        if (sscanf(line, "AnonHugePages: %lld kB", &kib) == 1) {
            break;
        }
    }
    fclose(f);
    return kib >= 0 ? kib * 1024 : -1;
}
