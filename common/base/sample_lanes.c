/* sample_lanes.c - eight lanes of scrambled Sobol points, on the SIMD path in use. */
#include "base/sample_lanes.h"

#include "base/simd.h"

void sample_sobol_lanes(SampleLanes *s)
{
#if defined(__x86_64__)
    if (simd_path() >= SIMD_AVX2) {
        sample_sobol_lanes_avx2(s);
        return;
    }
#endif
    for (int k = 0; k < SAMPLE_LANES; k++)
        sample_sobol_bits(s->seq_index[k], s->seq_first[k], s->seq_second[k], s->index[k], &s->u[k], &s->v[k]);
}

void sample_draw_lanes(uint32_t key, uint32_t index, const uint32_t dim[SAMPLE_LANES], uint32_t u[SAMPLE_LANES],
                       uint32_t v[SAMPLE_LANES])
{
#if defined(__x86_64__)
    if (simd_path() >= SIMD_AVX2) {
        sample_draw_lanes_avx2(key, index, dim, u, v);
        return;
    }
#endif
    for (int k = 0; k < SAMPLE_LANES; k++) {
        const SampleSobol q = sample_sobol_seq(sample_mix(key, dim[k]));
        sample_sobol_bits(q.index, q.first, q.second, index, &u[k], &v[k]);
    }
}

void sample_grid_cells(const SampleSobol *q, uint32_t first, uint32_t count, int m, uint32_t *i, uint32_t *j)
{
#if defined(__x86_64__)
    if (count >= 3 && simd_path() >= SIMD_AVX2) { /* fewer cost alone what eight lanes cost */
        for (uint32_t at = 0; at < count; at += SAMPLE_LANES) /* past count to the lanes' end */
            sample_grid_cells_avx2(q, first + at, m, &i[at], &j[at]);
        return;
    }
#endif
    for (uint32_t k = 0; k < count; k++)
        sample_grid_cell(q, first + k, m, &i[k], &j[k]);
}

int sample_lanes_wide(void)
{
#if defined(__x86_64__)
    return simd_path() >= SIMD_AVX2;
#else
    return 0;
#endif
}
