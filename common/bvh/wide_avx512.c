/* wide_avx512.c - the 8-wide traversal of wide_avx2.c compiled for
 * AVX-512 (base/avx512_begin.h): the same 256-bit arithmetic, with 32
 * vector registers, so two interleaved walks keep their rays' vectors in
 * registers, and compares into mask registers.  Only called when the CPU
 * reports AVX-512 F, VL, BW and DQ. */
#if defined(__x86_64__) && !defined(LANRAY_DOUBLE)
#include "base/avx512_begin.h"
#include "bvh/wide8.h"
#define VN_LE_MASK(a, b) ((int)_mm256_cmp_ps_mask(a, b, _CMP_LE_OQ))
#define KERNEL_CLOSEST wide8_closest_avx512
#define KERNEL_ANY wide8_any_avx512
#define KERNEL_CLOSEST_PAIRS wide8_closest_pairs_avx512
#define KERNEL_CLOSEST_PACKET wide8_closest_packet_avx512
#define KERNEL_ANY_PACKET wide8_any_packet_avx512
#include "bvh/wide_kernel.h"
#include "base/avx512_end.h"
#else
typedef int wide_avx512_unused; /* no AVX-512 kernel in double or non-x86 builds */
#endif
