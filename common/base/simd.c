/* simd.c - picking the traversal path at run time. */
#include "base/simd.h"

#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const names[SIMD_PATH_COUNT] = {"scalar", "sse", "avx2", "avx512"};
/* set by --simd before the render threads start; else by the first call,
 * which may come from several render threads at once (the path
 * integrator's first draws): each finds the same path, and the atomic
 * makes that no data race (ThreadSanitizer found one, 2026-11-29) */
atomic_int simd_chosen = -1;

int simd_available(SimdPath p)
{
    switch (p) {
    case SIMD_SCALAR:
        return 1;
#if defined(__x86_64__) && !defined(LANRAY_DOUBLE)
    case SIMD_SSE:
        return 1; /* SSE2 is part of x86-64 */
    case SIMD_AVX2:
        __builtin_cpu_init();
        return __builtin_cpu_supports("avx2");
    case SIMD_AVX512:
        __builtin_cpu_init();
        return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("avx512f") &&
               __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512bw") &&
               __builtin_cpu_supports("avx512dq");
#endif
    default:
        return 0;
    }
}

static SimdPath simd_best(void)
{
    for (int p = SIMD_PATH_COUNT - 1; p > 0; p--)
        if (simd_available((SimdPath)p))
            return (SimdPath)p;
    return SIMD_SCALAR;
}

const char *simd_name(SimdPath p) { return (unsigned)p < SIMD_PATH_COUNT ? names[p] : "?"; }

int simd_parse(const char *s, SimdPath *out)
{
    if (strcmp(s, "auto") == 0) {
        *out = simd_best();
        return 0;
    }
    for (int i = 0; i < SIMD_PATH_COUNT; i++)
        if (strcmp(s, names[i]) == 0) {
            *out = (SimdPath)i;
            return 0;
        }
    return -1;
}

int simd_force(SimdPath p)
{
    if (!simd_available(p))
        return -1;
    atomic_store_explicit(&simd_chosen, (int)p, memory_order_relaxed);
    return 0;
}

int simd_select(const char *name, char *msg, unsigned msg_size)
{
    SimdPath p;
    if (simd_parse(name, &p)) {
        snprintf(msg, msg_size, "unknown SIMD path '%s' (scalar, sse, avx2, avx512 or auto)", name);
        return -1;
    }
    if (simd_force(p)) {
        snprintf(msg, msg_size, "SIMD path '%s' is not available on this %s", name,
                 p >= SIMD_AVX2 ? "CPU or build" : "build");
        return -1;
    }
    return 0;
}

SimdPath simd_path_pick(void)
{
    int c = atomic_load_explicit(&simd_chosen, memory_order_relaxed);
    if (c < 0) {
        /* an unusable LANRAY_SIMD falls back to the best path: the tools
         * check the variable themselves and say so (cli_simd) */
        const char *env = getenv("LANRAY_SIMD");
        SimdPath p;
        c = env && simd_parse(env, &p) == 0 && simd_available(p) ? (int)p : (int)simd_best();
        atomic_store_explicit(&simd_chosen, c, memory_order_relaxed);
    }
    return (SimdPath)c;
}
