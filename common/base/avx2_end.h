/* avx2_end.h - the end of the code avx2_begin.h compiles for AVX2. */
#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
