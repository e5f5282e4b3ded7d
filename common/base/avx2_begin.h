/* avx2_begin.h - the code from here to avx2_end.h is compiled for AVX2:
 * the target pragmas of GCC and of Clang (which the fuzz build uses).  No
 * multiply-add is ever contracted (the build's -ffp-contract=off), so its
 * arithmetic rounds as the other paths' does; a file that defines
 * LANRAY_TARGET_FMA first may also call fused multiply-adds by name (the
 * wide kernels' slab test, bvh/wide8.h).  Included once by each file that
 * has an AVX2 path (bvh/wide_avx2.c, base/sample_lanes_avx2.c), whose
 * functions run only where the CPU reports AVX2 and FMA (simd.c).  No
 * include guard: a pair a file. */
#if defined(LANRAY_TARGET_FMA) /* for explicit fused multiply-adds alone (bvh/wide8.h) */
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2,fma"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2,fma")
#endif
#else
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2")
#endif
#endif
