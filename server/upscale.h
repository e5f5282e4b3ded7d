/* upscale.h - a moving frame rendered at a render scale k (each of its
 * pixels stands for a k x k block of the full frame) brought to the full
 * size for the window and the frames written: in blocks (the pixels as
 * rendered) or smooth (bilinear between the pixels' centres, the default:
 * at a scale of 4 to 8 on a small farm, blocks are what the eye sees of a
 * moving picture).  Integer arithmetic, so a smooth frame is the same
 * bytes on every machine (tests/cli/path.sh computes it again).
 *
 * A render scale is counted in quarter steps, s = 4k (UPSCALE_ONE, 4:
 * every pixel; 6: 1.5; 10: 2.5; 11: 2.75; 32: 8), so that a frame rate can
 * be held between the whole scales, whose frames' pixels differ by 1.8 to
 * 4 times from one to the next (half steps still 1.3 to 1.6 times: the
 * demo's flight held 19-20 fps where 15 was asked). */
#ifndef LANRAY_UPSCALE_H
#define LANRAY_UPSCALE_H

#include <stddef.h>
#include <stdint.h>

typedef enum { UPSCALE_SMOOTH, UPSCALE_BLOCKS } UpscaleKind;

/* the words of lanray-server --upscale, in UpscaleKind's order */
extern const char *const upscale_names[];

#define UPSCALE_ONE 4
/* The largest render scale, in quarter steps (8). */
#define UPSCALE_MAX 32

/* A side of `full` pixels at render scale s (quarter steps): ceil(4 full / s). */
static inline uint32_t upscale_side(uint32_t full, uint32_t s)
{
    return (uint32_t)(((uint64_t)full * UPSCALE_ONE + s - 1) / s);
}

/* The full frame w x h, bpp bytes a pixel, from src, a frame at scale s
 * (quarter steps): upscale_side(w, s) pixels a line and upscale_side(h, s)
 * lines, each where its camera ray went (upscale.c: a frame spans the
 * full frame's width, its lines centred on the full frame's); each full
 * pixel shows the frame pixel whose centre is nearest its own (a block of
 * k x k where k divides the sides; at 2.5, of 2 and 3 pixels a side). */
void upscale_blocks(const uint8_t *src, uint8_t *dst, uint32_t w, uint32_t h, uint32_t bpp, uint32_t s);

/* The scratch upscale_smooth needs for a w x h frame at scale s, in
 * uint16_t. */
size_t upscale_scratch(uint32_t w, uint32_t h, uint32_t s);

/* The same, RGB8 only, each full pixel the bilinear mix of the four frame
 * pixels whose centres surround its own (clamped at the edges), its place
 * among them to 1/128 of a frame pixel, rounded to the nearest byte: the
 * mix of bytes as they are coded (what a GPU's linear filter does on a
 * texture not marked sRGB). */
void upscale_smooth(const uint8_t *src, uint8_t *dst, uint32_t w, uint32_t h, uint32_t s, uint16_t *scratch);

/* The same for RGBE pixels (lanray-server --hdr), whose shared exponent
 * does not mix byte by byte: the four pixels decoded (rgbe_decode), mixed
 * in double with the same whole-number weights, and coded again.  The
 * scratch: upscale_scratch_rgbe(w, h, s) doubles. */
size_t upscale_scratch_rgbe(uint32_t w, uint32_t h, uint32_t s);
void upscale_smooth_rgbe(const uint8_t *src, uint8_t *dst, uint32_t w, uint32_t h, uint32_t s, double *scratch);

#endif
