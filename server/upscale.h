/* upscale.h - a moving frame rendered at a render scale k (each of its
 * pixels stands for a k x k block of the full frame) brought to the full
 * size for the window and the frames written: in blocks (the pixels as
 * rendered) or smooth (bilinear between the pixels' centres, the default:
 * at a scale of 4 to 8 on a small farm, blocks are what the eye sees of a
 * moving picture).  Integer arithmetic, so a smooth frame is the same
 * bytes on every machine (tests/cli/path.sh computes it again). */
#ifndef LANRAY_UPSCALE_H
#define LANRAY_UPSCALE_H

#include <stddef.h>
#include <stdint.h>

typedef enum { UPSCALE_SMOOTH, UPSCALE_BLOCKS } UpscaleKind;

/* the words of lanray-server --upscale, in UpscaleKind's order */
extern const char *const upscale_names[];

/* The full frame w x h, bpp bytes a pixel, from src: ceil(w / k) pixels a
 * line and ceil(h / k) lines; each pixel copied into its block. */
void upscale_blocks(const uint8_t *src, uint8_t *dst, uint32_t w, uint32_t h, uint32_t bpp, uint32_t k);

/* The scratch upscale_smooth needs for a w x h frame at scale k, in
 * uint16_t. */
size_t upscale_scratch(uint32_t w, uint32_t h, uint32_t k);

/* The same, RGB8 only, each full pixel the bilinear mix of the four frame
 * pixels whose centres surround its own (clamped at the edges), rounded to
 * the nearest byte: the mix of bytes as they are coded (what a GPU's
 * linear filter does on a texture not marked sRGB). */
void upscale_smooth(const uint8_t *src, uint8_t *dst, uint32_t w, uint32_t h, uint32_t k, uint16_t *scratch);

/* The same for RGBE pixels (lanray-server --hdr), whose shared exponent
 * does not mix byte by byte: the four pixels decoded (rgbe_decode), mixed
 * in double with the same whole-number weights, and coded again.  The
 * scratch: upscale_scratch_rgbe(w, h, k) doubles. */
size_t upscale_scratch_rgbe(uint32_t w, uint32_t h, uint32_t k);
void upscale_smooth_rgbe(const uint8_t *src, uint8_t *dst, uint32_t w, uint32_t h, uint32_t k, double *scratch);

#endif
