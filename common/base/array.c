/* array.c - see array.h. */
#include "base/array.h"

#include <stdlib.h>

int array_reserve(void **p, uint32_t *cap, uint32_t need, size_t elem, uint32_t limit)
{
    if (need <= *cap)
        return 0;
    if (need > limit)
        return -1;
    uint64_t c = *cap ? *cap : 16;
    while (c < need)
        c *= 2;
    if (c > limit)
        c = limit;
    void *q = realloc(*p, (size_t)c * elem);
    if (!q)
        return -1;
    *p = q;
    *cap = (uint32_t)c;
    return 0;
}
