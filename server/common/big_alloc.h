/* Memory for the large arrays a tick streams through (the trees' modal state and damage
 * records, the snapshots): on the kernel's transparent huge pages where it grants them to
 * a process that asks (madvise mode, Debian's default). A tick walks such an array from
 * end to end, and some of its passes stride a kilobyte or more a tree; on 4 KiB pages
 * every few trees cost a page walk (server/SERVER.md "The tick at 100 000 trees: huge
 * pages for the streamed arrays"). */
#ifndef GALE_BIG_ALLOC_H
#define GALE_BIG_ALLOC_H

#include <stddef.h>

/* Arrays from this size on are asked for on huge pages, in whole pages: a smaller one
 * would leave most of its last page unused. */
#define BIG_ALLOC_MIN_BYTES ((size_t)4 << 20)

/* bytes of zeroed memory, aligned to 64 bytes at least (from BIG_ALLOC_MIN_BYTES on, to a
 * huge page, and asked for on huge pages: a hint the kernel may not take); NULL when out
 * of memory. Written through now, not left to lazy zero pages, so the first ticks do not
 * fault it in. Freed with free(). With GALE_SMALL_PAGES=1 in the environment every array
 * is on small pages, for comparisons. */
void *big_alloc(size_t bytes);

/* Bytes of this process on transparent huge pages now (AnonHugePages of
 * /proc/self/smaps_rollup); -1 where the system does not say. */
long long big_alloc_huge_bytes(void);

#endif
