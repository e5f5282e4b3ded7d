/* simd.h - which traversal path this process uses: scalar, SSE or AVX2.
 *
 * Chosen once, before rendering, from the CPU (the widest path it has) or
 * forced by the environment variable LANRAY_SIMD or a tool's --simd flag.
 * Every path gives bit-identical pixels (see wide.h for why), so the choice
 * changes speed only; clients on different CPUs can share a frame. */
#ifndef LANRAY_SIMD_H
#define LANRAY_SIMD_H

#include <stdatomic.h>

typedef enum { SIMD_SCALAR = 0, SIMD_SSE = 1, SIMD_AVX2 = 2, SIMD_AVX512 = 3, SIMD_PATH_COUNT } SimdPath;

/* The path in use: the first call picks it (LANRAY_SIMD, else the CPU's best).
 * Inline once picked: a path-traced bounce asks several times (a call was
 * 12 instructions, 0.7% of the 100 spheres' frame). */
extern atomic_int simd_chosen;
SimdPath simd_path_pick(void);
static inline SimdPath simd_path(void)
{
    const int c = atomic_load_explicit(&simd_chosen, memory_order_relaxed);
    return c >= 0 ? (SimdPath)c : simd_path_pick();
}
/* Forces a path.  Returns 0, or -1 when this build or CPU lacks it. */
int simd_force(SimdPath p);
/* Whether this build was compiled with the path and this CPU can run it. */
int simd_available(SimdPath p);
const char *simd_name(SimdPath p);
/* "scalar", "sse", "avx2" or "auto" (the CPU's best); -1 on anything else. */
int simd_parse(const char *s, SimdPath *out);
/* Applies a name from a flag or LANRAY_SIMD; writes a message to msg on failure. */
int simd_select(const char *name, char *msg, unsigned msg_size);

#endif
