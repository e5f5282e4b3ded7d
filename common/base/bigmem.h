/* bigmem.h - large arrays on transparent huge pages.
 *
 * A BVH of a million triangles spans a hundred megabytes that traversal
 * reads in no order: with 4 KiB pages every few node visits miss the TLB,
 * and building it takes a page fault per 4 KiB touched (costly under a
 * hypervisor).  Arrays of BIGMEM_MIN bytes or more are placed on 2 MiB
 * boundaries and marked MADV_HUGEPAGE (the kernel's default "madvise"
 * mode honours it); smaller ones are ordinary 64-byte aligned blocks.
 * Measured in docs/renderer.md.  Free with free(). */
#ifndef LANRAY_BIGMEM_H
#define LANRAY_BIGMEM_H

#include <stddef.h>

#define BIGMEM_MIN (4u << 20)

/* 64-byte aligned (2 MiB for big arrays), or NULL. */
void *bigmem_alloc(size_t bytes);

#endif
