/* bigmem.c - see bigmem.h. */
#define _DEFAULT_SOURCE /* madvise */
#include "base/bigmem.h"

#include <stdlib.h>
#include <sys/mman.h>

#define HUGE_PAGE ((size_t)2 << 20)

void *bigmem_alloc(size_t bytes)
{
    if (bytes < BIGMEM_MIN)
        return aligned_alloc(64, (bytes + 63) / 64 * 64 + (bytes == 0) * 64);
    size_t size = (bytes + HUGE_PAGE - 1) / HUGE_PAGE * HUGE_PAGE;
    void *p = aligned_alloc(HUGE_PAGE, size);
#ifdef MADV_HUGEPAGE
    if (p)
        madvise(p, size, MADV_HUGEPAGE); /* advice only: without it the pages are small */
#endif
    return p;
}
