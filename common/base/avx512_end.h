/* avx512_end.h - the end of the code avx512_begin.h compiles for AVX-512. */
#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
