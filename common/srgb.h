/* srgb.h - from linear light to the 8-bit codes of an image, and back.
 *
 * lanray shades in linear light: colours in scene files, textures after
 * decoding and every sum of light are linear.  A pixel is written as sRGB
 * (IEC 61966-2-1), what screens and viewers expect, unless the user asks
 * for linear output (--linear).  Both directions go through constant tables
 * (srgb_tables.c, made by tools/srgb-tables), not pow(): maths libraries
 * differ in their last bits, and a client on another machine must write the
 * same codes as lanray-render. */
#ifndef LANRAY_SRGB_H
#define LANRAY_SRGB_H

#include <stdint.h>

#include "real.h"

/* The linear value at which the sRGB code becomes k + 1 (k = 0..254). */
extern const double srgb_threshold[255];
/* The linear value of sRGB code k. */
extern const float srgb_decode8[256];

/* The sRGB code of linear v: round to nearest in sRGB terms, clamped to
 * 0..255; NaN (inf * 0 from extreme scene values) becomes 0.  Eight
 * comparisons of a binary search over the thresholds. */
static inline uint8_t srgb_encode8(real v)
{
    double d = (double)v;
    if (!(d >= srgb_threshold[0])) /* also NaN */
        return 0;
    int lo = 1, hi = 255; /* the code: the number of thresholds <= d, in lo..hi */
    while (lo < hi) {
        int mid = (lo + hi + 1) / 2;
        if (d >= srgb_threshold[mid - 1])
            lo = mid;
        else
            hi = mid - 1;
    }
    return (uint8_t)lo;
}

/* Linear output (--linear): v * 255 rounded, clamped; NaN becomes 0.  In
 * double, where a float's product with 255 is exact: in float, 0.9f * 255
 * rounded up to 229.5 and the code to 230. */
static inline uint8_t linear_encode8(real v)
{
    double d = v > R(0) ? (v < R(1) ? (double)v : 1.0) : 0.0;
    return (uint8_t)(d * 255 + 0.5);
}

/* The linear value of an sRGB-encoded fraction s in [0, 1] (for images that
 * are not 8 bits deep; 8-bit codes use srgb_decode8). */
double srgb_decode(double s);

#endif
