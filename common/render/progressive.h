/* progressive.h - a path-traced view's N x N samples a pixel taken in
 * batches that add up (N a power of two, a regular grid).
 *
 * The samples of a pixel go in the order of base/sample.h's
 * sample_grid_cell, whose first 4^k are spread like a 2^k x 2^k grid (and
 * the first 2 x 4^k like 2^k x 2^(k+1)); they are summed in batches that
 * double the samples: 1 the first, 2 the second, 3 the next 2, b those
 * from 2^(b-2) to 2^(b-1), up to N x N in 2 log2 N + 1 batches, and a
 * pixel's sum is its batches' sums added in order.  So a farm's still
 * frames can each render one batch (settings batch: each pixel's sums
 * travel, not its colour), the server adds them to what it holds and
 * shows the mean of all so far, and the last is lanray-render's picture
 * at N x N bit for bit: the same numbers added in the same order.
 * lanray-render's --still-frame K is the picture of the first K batches
 * (what the farm shows on its way). */
#ifndef LANRAY_PROGRESSIVE_H
#define LANRAY_PROGRESSIVE_H

#include <stddef.h>
#include <stdint.h>

#include "render/pixel.h"
#include "scene/shade.h"

/* A pixel's sums: its light (3), then where guided its guide's (9: albedo,
 * the squared luminances, normal, distance, the samples that met a
 * surface; scene/shade.h's Guide). */
#define PROG_COLOUR 3u
#define PROG_GUIDE 9u
#define PROG_MAX (PROG_COLOUR + PROG_GUIDE)

/* The batches of rs's frames: 2 log2 N + 1 where the path integrator
 * takes N x N samples a pixel on a regular grid, N a power of two of 2 or
 * more; 0 where its samples do not go in batches. */
int progressive_batches(const RenderSettings *rs);

/* The batches a frame of rs renders: the first rs->batches (lanray-render
 * --still-frame), else all of them. */
static inline int progressive_upto(const RenderSettings *rs)
{
    return rs->batches ? rs->batches : progressive_batches(rs);
}

/* A jittered moving frame's sample (settings jitter) is one of a pixel's
 * 2^m x 2^m in their progressive order, m this. */
#define PROG_JITTER_M 5

/* The settings jitter of moving frame k (1, 2 ...) of a view of settings
 * rs whose frames a history adds up (render/temporal.h): sample k - 1 of
 * its pixels' (mod their 4^m), so that each frame takes another; 0 where
 * its frames take more than one sample a pixel (not jittered).  One rule
 * for a server's frames and lanray-render --server-frame's. */
static inline int progressive_jitter(const RenderSettings *rs, uint32_t frame)
{
    return rs->aa == 1 && !rs->adaptive ? (int)((frame - 1) % (1u << 2 * PROG_JITTER_M)) + 1 : 0;
}

/* The most batches (N = AA_MAX, 32: 1024 samples). */
#define PROG_MAX_BATCHES 11
/* Batch b's samples (1 <= b <= PROG_MAX_BATCHES): [progressive_start(b), progressive_end(b)). */
static inline uint32_t progressive_end(int b) { return 1u << (b - 1); }
static inline uint32_t progressive_start(int b) { return b <= 1 ? 0u : progressive_end(b - 1); }
/* Whether sample s is the last of its batch. */
static inline int progressive_last(uint32_t s) { return ((s + 1) & s) == 0; }

/* The reals of a pixel's sums with rs's settings. */
static inline uint32_t progressive_reals(const RenderSettings *rs)
{
    return PROG_COLOUR + (render_guided(rs) ? PROG_GUIDE : 0);
}

/* sums plus one sample's light c and (where guided, g not NULL) its guide */
void progressive_add_sample(real *sums, vec3 c, const Guide *g);
/* total plus a batch's sums, n reals */
void progressive_fold(real *total, const real *batch, uint32_t n);

/* The pixel as rendered (render.h: colour, then its guide where rs says
 * denoise) of the sums of its first `samples` samples, exposed by gain
 * (2^exposure). */
void progressive_encode(const RenderSettings *rs, real gain, const real *sums, uint32_t samples, uint8_t *dst);

/* A frame of n pixels' batch sums as they came (settings batch rs->batch,
 * progressive_reals reals a pixel, unaligned) added to acc, the sums of
 * the batches before (zeros before the first), and the pixels they now
 * make written to out (render_pixel_bytes of the frame without batch). */
void progressive_frame_add(const RenderSettings *rs, real *acc, const uint8_t *sums, size_t n, uint8_t *out);
/* The pixels progressive_frame_add would write, acc left as it is (NULL:
 * zeros, the first batch's): a batch's part shown before the frame is
 * whole, its sums added only then, in order. */
void progressive_frame_peek(const RenderSettings *rs, const real *acc, const uint8_t *sums, size_t n, uint8_t *out);

#endif
