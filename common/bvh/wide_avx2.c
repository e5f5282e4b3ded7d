/* wide_avx2.c - 8-wide BVH traversal with AVX2 (base/avx2_begin.h: the
 * kernel compiled for AVX2, never FMA; only called when the CPU reports
 * AVX2). */
#if defined(__x86_64__) && !defined(LANRAY_DOUBLE)
#include "base/avx2_begin.h"
#include "bvh/wide8.h"
#define VN_LE_MASK(a, b) _mm256_movemask_ps(_mm256_cmp_ps(a, b, _CMP_LE_OQ))
#define KERNEL_CLOSEST wide8_closest_avx2
#define KERNEL_ANY wide8_any_avx2
#define KERNEL_CLOSEST_PAIRS wide8_closest_pairs_avx2
#define KERNEL_CLOSEST_PACKET wide8_closest_packet_avx2
#define KERNEL_ANY_PACKET wide8_any_packet_avx2
#include "bvh/wide_kernel.h"
#include "base/avx2_end.h"
#else
typedef int wide_avx2_unused; /* no AVX2 kernel in double or non-x86 builds */
#endif
