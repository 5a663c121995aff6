/* Tests of big_alloc: zeroed memory at the alignment it promises, on huge pages where the
 * kernel grants them to a process that asks, and on small pages with GALE_SMALL_PAGES=1. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "big_alloc.h"
#include "check.h"

#define MIB ((size_t)1 << 20)

/* The kernel's transparent huge page mode ("always", "madvise", "never"), or "" where it
 * does not say. */
static const char *thp_mode(char *buf, size_t cap)
{
    buf[0] = '\0';
    FILE *f = fopen("/sys/kernel/mm/transparent_hugepage/enabled", "r");
    if (!f) {
        return buf;
    }
    char line[128] = "";
    if (fgets(line, sizeof line, f)) {
        const char *a = strchr(line, '['), *b = a ? strchr(a, ']') : NULL;
        if (a && b && (size_t)(b - a - 1) < cap) {
            memcpy(buf, a + 1, (size_t)(b - a - 1));
            buf[b - a - 1] = '\0';
        }
    }
    fclose(f);
    return buf;
}

static int all_zero(const unsigned char *p, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        if (p[i]) {
            return 0;
        }
    }
    return 1;
}

/* Zeroed even where the allocator hands back memory just written and freed. */
static void test_zeroed_and_aligned(void)
{
    const size_t sizes[] = { 1, 100, 4096, BIG_ALLOC_MIN_BYTES - 1, BIG_ALLOC_MIN_BYTES,
                             5 * MIB + 3 };
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
        const size_t n = sizes[k];
        for (int round = 0; round < 3; round++) {
            unsigned char *p = big_alloc(n);
            CHECK(p != NULL);
            if (!p) {
                continue;
            }
            CHECK(all_zero(p, n));
            const uintptr_t align = n >= BIG_ALLOC_MIN_BYTES ? 2 * MIB : 64;
            CHECK((uintptr_t)p % align == 0);
            memset(p, 0xab, n);
            free(p);
        }
    }
    unsigned char *z = big_alloc(0);
    CHECK(z != NULL);
    free(z);
}

/* The growth of the process's huge pages over allocating and writing an array of n. */
static long long huge_growth(size_t n)
{
    const long long before = big_alloc_huge_bytes();
    unsigned char *p = big_alloc(n);
    CHECK(p != NULL);
    if (!p) {
        return -1;
    }
    for (size_t i = 0; i < n; i += 4096) {
        p[i] = 1;
    }
    const long long after = big_alloc_huge_bytes();
    free(p);
    return before >= 0 && after >= 0 ? after - before : -1;
}

static void test_huge_pages(void)
{
    char mode[32];
    thp_mode(mode, sizeof mode);
    const long long now = big_alloc_huge_bytes();
    if (now < 0 || (strcmp(mode, "madvise") != 0 && strcmp(mode, "always") != 0)) {
        printf("test_big_alloc: transparent huge pages \"%s\", AnonHugePages %lld: not "
               "checked\n", mode, now);
        return;
    }
    /* 16 MiB: 8 huge pages asked for; a fragmented machine may grant fewer, not none */
    const long long grown = huge_growth(16 * MIB);
    printf("test_big_alloc: mode %s, 16 MiB array: %lld MiB on huge pages\n", mode,
           grown / (long long)MIB);
    CHECK(grown >= (long long)(2 * MIB));
    if (strcmp(mode, "madvise") == 0) {
        /* asked for nothing, granted nothing */
        setenv("GALE_SMALL_PAGES", "1", 1);
        const long long small = huge_growth(16 * MIB);
        printf("test_big_alloc: GALE_SMALL_PAGES=1: %lld MiB on huge pages\n",
               small / (long long)MIB);
        CHECK(small == 0);
        unsetenv("GALE_SMALL_PAGES");
    }
}

int main(void)
{
    test_zeroed_and_aligned();
    test_huge_pages();
    return check_report();
}
