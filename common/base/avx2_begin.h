/* avx2_begin.h - the code from here to avx2_end.h is compiled for AVX2:
 * the target pragmas of GCC and of Clang (which the fuzz build uses), and
 * never FMA, whose contracted multiply-adds would round differently from
 * the other paths.  Included once by each file that has an AVX2 path
 * (bvh/wide_avx2.c, base/sample_lanes_avx2.c), whose functions run only
 * where the CPU reports AVX2 (simd.c).  No include guard: a pair a file. */
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2")
#endif
