/* sample_lanes.c - eight lanes of scrambled Sobol points, on the SIMD path in use. */
#include "base/sample_lanes.h"

#include "base/simd.h"

void sample_sobol_lanes(SampleLanes *s)
{
#if defined(__x86_64__)
    if (simd_path() == SIMD_AVX2) {
        sample_sobol_lanes_avx2(s);
        return;
    }
#endif
    for (int k = 0; k < SAMPLE_LANES; k++)
        sample_sobol_bits(s->seq_index[k], s->seq_first[k], s->seq_second[k], s->index[k], &s->u[k], &s->v[k]);
}
