/* denoise.h - a path-traced frame's noise filtered out (settings denoise),
 * guided by what each pixel's camera rays saw first.
 *
 * With settings denoise on, every pixel carries, after its colour, its
 * guide (scene/shade.h's Guide of its samples, DENOISE_GUIDE_BYTES): the
 * mean colour of the surfaces its rays met first (albedo), their normal
 * and their distance.  The frame, once whole, is filtered: the light
 * divided by the albedo (so that a texture's detail is not blurred with
 * the noise) goes through an edge-avoiding a-trous wavelet filter
 * (Dammertz et al. 2010: five passes of a 5 x 5 B3-spline kernel, its taps
 * 1, 2, 4, 8, 16 pixels apart), each tap weighed by how alike the two
 * pixels' normals, distances and albedos are and by how far their light
 * differs against the noise's own spread (the variance of the light about
 * the pixel, as SVGF estimates it where it has no frames before: Schied et
 * al. 2017), then multiplied by the albedo again.  Pixels that saw only
 * the background or an emitter (no noise of their own) pass as they are.
 *
 * The filter is a function of the frame's bytes alone (float arithmetic in
 * a fixed order, its exponential its own), so that a frame assembled from
 * any clients' segments and lanray-render's are filtered into one picture;
 * rows go to the threads of a pool, each pixel computed alone. */
#ifndef LANRAY_DENOISE_H
#define LANRAY_DENOISE_H

#include <stdint.h>

#include "base/err.h"
#include "base/pool.h"
#include "scene/shade.h"

/* A guide's bytes: the albedo (3 linear codes), the normal (2 bytes of its
 * octahedral projection), the distance (3 bytes: the top 24 bits of its
 * float; 0 where no sample met a surface), the noise (1 byte: the
 * standard error of the pixel's mean luminance relative to it, in
 * sixteenths of an octave from 2^-12; 0 for a pixel of one sample, whose
 * noise the filter estimates from its neighbours), the instance (2 bytes,
 * little-endian: Guide.instance, 0 past 65535 instances). */
#define DENOISE_GUIDE_BYTES 11u

/* The guide of a pixel of n samples whose guides sum to *sum and whose
 * light is mean, as bytes. */
void denoise_guide_pack(const Guide *sum, int n, vec3 mean, uint8_t out[DENOISE_GUIDE_BYTES]);
/* A normal (any length but 0) as the guide's two bytes (octahedral). */
void denoise_normal_pack(vec3 m, uint8_t out[2]);
/* The noise byte of a relative standard error (0 and below: none). */
uint8_t denoise_noise_code(float rel);
/* A guide's instance bytes (Guide.instance: index + 1; 0 none, and past 65535). */
static inline void denoise_guide_put_instance(uint8_t out[DENOISE_GUIDE_BYTES], uint32_t instance)
{
    const uint32_t i = instance <= 0xffffu ? instance : 0;
    out[9] = (uint8_t)i, out[10] = (uint8_t)(i >> 8);
}
/* Its instance (Guide.instance: index + 1, 0 none). */
static inline uint32_t denoise_guide_instance(const uint8_t in[DENOISE_GUIDE_BYTES])
{
    return (uint32_t)in[9] | (uint32_t)in[10] << 8;
}
/* Its albedo, unit normal, distance (0: no surface) and relative noise
 * (negative: not known), as the filter reads them. */
void denoise_guide_unpack(const uint8_t in[DENOISE_GUIDE_BYTES], float albedo[3], float normal[3], float *depth,
                          float *noise);

typedef struct Denoiser Denoiser;

/* A denoiser for frames of up to max_w x max_h pixels, its scratch made
 * once (NULL where memory ran out); pool (may be NULL: the caller alone)
 * runs its passes' rows. */
Denoiser *denoiser_create(Pool *pool, uint32_t max_w, uint32_t max_h);
/* The bytes of that scratch (its planes of floats, with their margins). */
uint64_t denoiser_bytes(uint32_t max_w, uint32_t max_h);
void denoiser_destroy(Denoiser *d);

/* Filters a w x h frame of guided pixels (colour_bytes of colour, 3 codes
 * or 4 of RGBE, then the guide) into out (colour_bytes a pixel); codes are
 * sRGB unless linear.  0, or -1 with err where the frame is larger than
 * the denoiser was made for. */
int denoise_frame(Denoiser *d, const uint8_t *px, uint32_t w, uint32_t h, uint32_t colour_bytes, int linear,
                  uint8_t *out, Err *err);

#endif
