/* array.h - growing a malloc'd array by doubling. */
#ifndef LANRAY_ARRAY_H
#define LANRAY_ARRAY_H

#include <stddef.h>
#include <stdint.h>

/* Makes room for `need` elements of `elem` bytes; fails past `limit` elements or on OOM. */
int array_reserve(void **p, uint32_t *cap, uint32_t need, size_t elem, uint32_t limit);

#endif
