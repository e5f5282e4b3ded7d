/* avx512_begin.h - the code from here to avx512_end.h is compiled for
 * AVX-512 (F, VL, BW, DQ): AVX2's 256-bit vectors with 32 registers
 * instead of 16 and compares into mask registers.  Never FMA-contracted
 * (the build's -ffp-contract=off), so its arithmetic rounds as the other
 * paths' does.  Included by bvh/wide_avx512.c, whose functions run only
 * where the CPU reports those extensions (simd.c).  No include guard. */
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2,avx512f,avx512vl,avx512bw,avx512dq"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2,avx512f,avx512vl,avx512bw,avx512dq")
#endif
