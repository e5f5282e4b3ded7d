/* sample_lanes.c - eight lanes of scrambled Sobol points, on the SIMD path in use. */
#include "base/sample_lanes.h"

#include "base/simd.h"

/* sample_sobol_point's integers for one lane. */
static void lane(SampleLanes *s, int k)
{
    const uint32_t i = sample_owen(s->index[k], s->seq_index[k]);
    uint32_t z = i;
    z ^= (z >> 1) & 0x55555555u;
    z ^= (z >> 2) & 0x33333333u;
    z ^= (z >> 4) & 0x0f0f0f0fu;
    z ^= (z >> 8) & 0x00ff00ffu;
    z ^= (z >> 16) & 0x0000ffffu;
    s->u[k] = sample_reverse(sample_laine_karras(i, s->seq_first[k]));
    s->v[k] = sample_reverse(sample_laine_karras(z, s->seq_second[k]));
}

void sample_sobol_lanes(SampleLanes *s)
{
#if defined(__x86_64__)
    if (simd_path() == SIMD_AVX2) {
        sample_sobol_lanes_avx2(s);
        return;
    }
#endif
    for (int k = 0; k < SAMPLE_LANES; k++)
        lane(s, k);
}
