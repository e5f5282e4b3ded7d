/* wide_sse.c - 4-wide BVH traversal with SSE (the x86-64 baseline). */
#if defined(__x86_64__) && !defined(LANRAY_DOUBLE)
#define NW 4
#define VN __m128
#define VN_SET1 _mm_set1_ps
#define VN_LOAD _mm_load_ps
#define VN_STORE _mm_storeu_ps
#define VN_MIN _mm_min_ps
#define VN_MAX _mm_max_ps
#define VN_LE_MASK(a, b) _mm_movemask_ps(_mm_cmple_ps(a, b))
#define KERNEL_CLOSEST wide4_closest_sse
#define KERNEL_ANY wide4_any_sse
#define KERNEL_CLOSEST_PAIRS wide4_closest_pairs_sse
#define KERNEL_CLOSEST_PACKET wide4_closest_packet_sse
#define KERNEL_ANY_PACKET wide4_any_packet_sse
#include "bvh/wide_kernel.h"
#else
typedef int wide_sse_unused; /* no SSE kernel in double or non-x86 builds */
#endif
