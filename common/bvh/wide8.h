/* wide8.h - what wide_kernel.h needs for 8-wide nodes in 256-bit vectors,
 * shared by the AVX2 and AVX-512 kernels (wide_avx2.c, wide_avx512.c),
 * which add their own compare (VN_LE_MASK) and entry points' names.  No
 * include guard: included once by each, inside its target pragmas. */
#define NW 8
#define VN __m256
#define VN_SET1 _mm256_set1_ps
#define VN_LOAD _mm256_load_ps
#define VN_STORE _mm256_storeu_ps
#define VN_MIN _mm256_min_ps
#define VN_MAX _mm256_max_ps
