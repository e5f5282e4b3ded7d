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

#endif
