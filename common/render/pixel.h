/* pixel.h - a rendered pixel's bytes: its colour as 8-bit codes (sRGB or
 * linear, after the exposure) or RGBE, then with settings denoise its
 * guide.  One for the pixels render.c writes and for those a path-traced
 * still's batches make (progressive.c), so that both are the same bytes. */
#ifndef LANRAY_PIXEL_H
#define LANRAY_PIXEL_H

#include <math.h>
#include <stdint.h>

#include "base/dmath.h"
#include "base/srgb.h"
#include "render/denoise.h"
#include "render/tonemap.h"

/* Bytes of a pixel's colour: 3 (RGB8 codes), or 4 (RGBE) with settings hdr. */
static inline uint32_t render_colour_bytes(const RenderSettings *rs) { return rs->hdr ? 4u : 3u; }
/* Whether a pixel carries its guide: settings denoise (the filter's), or
 * guides (a Whitted moving frame's, for the server's history). */
static inline int render_guided(const RenderSettings *rs) { return rs->denoise || rs->guides; }
/* ... and of a pixel as shown and filtered: its colour, then where
 * guided its guide (render/denoise.h). */
static inline uint32_t render_shown_bytes(const RenderSettings *rs)
{
    return render_colour_bytes(rs) + (render_guided(rs) ? DENOISE_GUIDE_BYTES : 0u);
}

/* The codes' gain: 2^exposure. */
static inline real pixel_gain(const RenderSettings *rs) { return dmath_powr(R(2), rs->exposure); }

/* Linear light to 8-bit codes: sRGB unless linear (srgb.h: both clamp,
 * and NaN becomes 0), after the gain and the view transform (tonemap.h). */
static inline __attribute__((always_inline)) void pixel_put_codes(uint8_t *dst, vec3 c, real gain, Tonemap tm,
                                                                  int linear)
{
    if (gain != R(1)) /* an exposure: apart, so that a frame without pays nothing */
        c = v3_scale(c, gain);
    if (tm != TONEMAP_NONE)
        c = tonemap_apply(c, tm);
    for (int k = 0; k < 3; k++)
        dst[k] = linear ? linear_encode8(c.e[k]) : srgb_encode8(c.e[k]);
}

/* A pixel's colour: its codes, or its RGBE where hdr (high dynamic range:
 * the light itself, no exposure, no view transform). */
static inline __attribute__((always_inline)) void pixel_put_colour(uint8_t *dst, vec3 c, int hdr, real gain,
                                                                   Tonemap tm, int linear)
{
    if (hdr)
        rgbe_encode(c.x, c.y, c.z, dst);
    else
        pixel_put_codes(dst, c, gain, tm, linear);
}

/* ... and back: a pixel's colour bytes (4: RGBE, else 8-bit codes, sRGB
 * unless linear) as the light they hold, for the filters that read a
 * frame's pixels (denoise.c, temporal.c). */
static inline void pixel_read_colour(const uint8_t *p, uint32_t colour_bytes, int linear, float c[3])
{
    if (colour_bytes == 4) {
        double v[3];
        rgbe_decode(p, v);
        for (int k = 0; k < 3; k++)
            c[k] = (float)v[k];
        return;
    }
    for (int k = 0; k < 3; k++)
        c[k] = linear ? (float)p[k] / 255.0f : srgb_decode8[p[k]];
}

#endif
