/* sample_lanes_avx2.c - sample_sobol_lanes' eight chains in AVX2 registers:
 * the bytes of each lane reversed by one shuffle and their bits by two
 * nibble tables, the hashes' multiplies eight at once.  Compiled for AVX2
 * (base/avx2_begin.h); called only where the CPU has it. */
#include "base/sample_lanes.h"

#if defined(__x86_64__)
#include <immintrin.h>

#include "base/avx2_begin.h"

static inline __m256i reverse8(__m256i x)
{
    /* bytes reversed within each 32-bit lane, then each byte's bits by its nibbles */
    const __m256i bytes = _mm256_setr_epi8(3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12, 3, 2, 1, 0, 7, 6, 5,
                                           4, 11, 10, 9, 8, 15, 14, 13, 12);
    const __m256i nib = _mm256_setr_epi8(0x0, 0x8, 0x4, 0xc, 0x2, 0xa, 0x6, 0xe, 0x1, 0x9, 0x5, 0xd, 0x3, 0xb, 0x7, 0xf,
                                         0x0, 0x8, 0x4, 0xc, 0x2, 0xa, 0x6, 0xe, 0x1, 0x9, 0x5, 0xd, 0x3, 0xb, 0x7, 0xf);
    const __m256i low = _mm256_set1_epi8(0x0f);
    x = _mm256_shuffle_epi8(x, bytes);
    const __m256i lo = _mm256_shuffle_epi8(nib, _mm256_and_si256(x, low));
    const __m256i hi = _mm256_shuffle_epi8(nib, _mm256_and_si256(_mm256_srli_epi16(x, 4), low));
    return _mm256_or_si256(_mm256_slli_epi16(lo, 4), hi);
}

static inline __m256i laine_karras8(__m256i x, __m256i seed)
{
    x = _mm256_add_epi32(x, seed);
    x = _mm256_xor_si256(x, _mm256_mullo_epi32(x, _mm256_set1_epi32((int)0x6c50b47cu)));
    x = _mm256_xor_si256(x, _mm256_mullo_epi32(x, _mm256_set1_epi32((int)0xb82f1e52u)));
    x = _mm256_xor_si256(x, _mm256_mullo_epi32(x, _mm256_set1_epi32((int)0xc7afe638u)));
    x = _mm256_xor_si256(x, _mm256_mullo_epi32(x, _mm256_set1_epi32((int)0x8d22f6e6u)));
    return x;
}

static inline __m256i shift_xor(__m256i z, int by, uint32_t mask)
{
    return _mm256_xor_si256(z, _mm256_and_si256(_mm256_srli_epi32(z, by), _mm256_set1_epi32((int)mask)));
}

#define LOAD(a) _mm256_loadu_si256((const __m256i *)(const void *)(a))
#define STORE(a, x) _mm256_storeu_si256((__m256i *)(void *)(a), x)

/* sample_sobol_bits on eight lanes: the scrambles and the index in, u and v out. */
static inline void sobol_bits8(__m256i index, __m256i seq_index, __m256i seq_first, __m256i seq_second, __m256i *u,
                               __m256i *v)
{
    const __m256i i = reverse8(laine_karras8(reverse8(index), seq_index));
    __m256i z = i;
    z = shift_xor(z, 1, 0x55555555u);
    z = shift_xor(z, 2, 0x33333333u);
    z = shift_xor(z, 4, 0x0f0f0f0fu);
    z = shift_xor(z, 8, 0x00ff00ffu);
    z = shift_xor(z, 16, 0x0000ffffu);
    *u = reverse8(laine_karras8(i, seq_first));
    *v = reverse8(laine_karras8(z, seq_second));
}

void sample_sobol_lanes_avx2(SampleLanes *s)
{
    __m256i u, v;
    sobol_bits8(LOAD(s->index), LOAD(s->seq_index), LOAD(s->seq_first), LOAD(s->seq_second), &u, &v);
    STORE(s->u, u);
    STORE(s->v, v);
}

void sample_grid_cells_avx2(const SampleSobol *q, uint32_t first, int m, uint32_t i[SAMPLE_LANES],
                            uint32_t j[SAMPLE_LANES])
{
    __m256i u, v;
    const __m256i index = _mm256_add_epi32(_mm256_set1_epi32((int)first), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
    sobol_bits8(index, _mm256_set1_epi32((int)q->index), _mm256_set1_epi32((int)q->first),
                _mm256_set1_epi32((int)q->second), &u, &v);
    const __m128i by = _mm_cvtsi32_si128(m > 0 ? 32 - m : 32); /* a shift by 32 or more gives 0 */
    STORE(i, _mm256_srl_epi32(u, by));
    STORE(j, _mm256_srl_epi32(v, by));
}

/* sample_hash on eight lanes. */
static inline __m256i hash8(__m256i x)
{
    x = _mm256_xor_si256(x, _mm256_srli_epi32(x, 16));
    x = _mm256_mullo_epi32(x, _mm256_set1_epi32(0x7feb352d));
    x = _mm256_xor_si256(x, _mm256_srli_epi32(x, 15));
    x = _mm256_mullo_epi32(x, _mm256_set1_epi32((int)0x846ca68bu));
    return _mm256_xor_si256(x, _mm256_srli_epi32(x, 16));
}

void sample_draw_lanes_avx2(uint32_t key, uint32_t index, const uint32_t dim[SAMPLE_LANES], uint32_t u[SAMPLE_LANES],
                            uint32_t v[SAMPLE_LANES])
{
    /* sample_mix(key, dim), then sample_sobol_seq's three hashes */
    const __m256i mixed = hash8(_mm256_add_epi32(LOAD(dim), _mm256_set1_epi32((int)0x9e3779b9u)));
    const __m256i seed = hash8(_mm256_xor_si256(_mm256_set1_epi32((int)key), mixed));
    const __m256i si = hash8(_mm256_xor_si256(seed, _mm256_set1_epi32(0x5bd1e995)));
    const __m256i sf = hash8(_mm256_xor_si256(seed, _mm256_set1_epi32(0x68e31da4)));
    const __m256i ss = hash8(_mm256_xor_si256(seed, _mm256_set1_epi32((int)0xb5297a4du)));
    __m256i uu, vv;
    sobol_bits8(_mm256_set1_epi32((int)index), si, sf, ss, &uu, &vv);
    STORE(u, uu);
    STORE(v, vv);
}
#undef LOAD
#undef STORE

#include "base/avx2_end.h"
#else
typedef int sample_lanes_avx2_unused; /* no AVX2 path off x86-64 */
#endif
