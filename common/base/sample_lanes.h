/* sample_lanes.h - eight rays' points of their scrambled Sobol sequences
 * at once (sample_sobol_point, lane by lane).
 *
 * An area light's points are a packet's hottest integers: per point a
 * chain of bit reversals and Laine-Karras hashes some 80 cycles long (a
 * sixth of the default scene's frame, 3 x 3 points a pixel).  The AVX2
 * path runs eight lanes' chains side by side; the others one after
 * another.  Integer arithmetic is exact, so every path gives the same
 * bits: a pixel is the same on any CPU. */
#ifndef LANRAY_SAMPLE_LANES_H
#define LANRAY_SAMPLE_LANES_H

#include <stdint.h>

#include "base/sample.h"

#define SAMPLE_LANES 8

/* Lane k: point index[k] of the sequence whose scrambles are seq_index[k],
 * seq_first[k] and seq_second[k] (SampleSobol), as the 32-bit numbers u[k]
 * and v[k] that sample_unit turns into sample_sobol_point's u and v. */
typedef struct {
    uint32_t seq_index[SAMPLE_LANES], seq_first[SAMPLE_LANES], seq_second[SAMPLE_LANES], index[SAMPLE_LANES];
    uint32_t u[SAMPLE_LANES], v[SAMPLE_LANES];
} SampleLanes;

void sample_sobol_lanes(SampleLanes *s);
/* The AVX2 path (sample_lanes_avx2.c); only where simd_path says AVX2. */
void sample_sobol_lanes_avx2(SampleLanes *s);

/* Eight dimensions of one ray's numbers at once: lane k, point `index` of
 * the sequence of seed sample_mix(key, dim[k]) (sample_sobol_seq), as the
 * 32-bit numbers sample_sobol_bits gives (u[k] is also what
 * sample_sobol_first gives).  A path's bounce draws four to six such
 * numbers, each some 100 instructions of hashes alone. */
void sample_draw_lanes(uint32_t key, uint32_t index, const uint32_t dim[SAMPLE_LANES], uint32_t u[SAMPLE_LANES],
                       uint32_t v[SAMPLE_LANES]);
void sample_draw_lanes_avx2(uint32_t key, uint32_t index, const uint32_t dim[SAMPLE_LANES], uint32_t u[SAMPLE_LANES],
                            uint32_t v[SAMPLE_LANES]);
/* The cells of samples first .. first + count - 1 of the pixel whose
 * sequence is q, as sample_grid_cell gives them one by one (i[k], j[k] for
 * sample first + k), eight at a time where the lanes run side by side:
 * a path-traced frame's every sample takes its cell this way, some 100
 * instructions of hashes a sample alone.  i and j hold count rounded up
 * to a multiple of SAMPLE_LANES: the last lanes may write past count. */
void sample_grid_cells(const SampleSobol *q, uint32_t first, uint32_t count, int m, uint32_t *i, uint32_t *j);
/* Eight of them, samples first .. first + 7, on the AVX2 path. */
void sample_grid_cells_avx2(const SampleSobol *q, uint32_t first, int m, uint32_t i[SAMPLE_LANES],
                            uint32_t j[SAMPLE_LANES]);
/* Whether the lanes run side by side here (AVX2): elsewhere they go one
 * after another, and a caller that needs only some draws them alone. */
int sample_lanes_wide(void);

#endif
