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
#include <string.h>

#include "base/real.h"

/* The linear value at which the sRGB code becomes k + 1 (k = 0..254). */
extern const double srgb_threshold[255];
/* The smallest float at or above each: a float is at or above one exactly
 * when it is at or above the other. */
extern const float srgb_threshold_f[255];
/* The linear value of sRGB code k. */
extern const float srgb_decode8[256];

/* A first guess of the code by a float's top bits (sign, exponent and 8
 * bits of mantissa, bits >> 15, less SRGB_START_BASE): never above the
 * code of any value with those bits, at most one below. */
#define SRGB_START_BASE (114 << 8) /* 2^-13, below the first threshold */
extern const uint8_t srgb_start[13 * 256];

/* srgb_start's guess for a float in [threshold 0, threshold 254), where
 * its bucket is in range (clamped all the same). */
static inline int srgb_guess(float f)
{
    uint32_t bits;
    memcpy(&bits, &f, sizeof bits);
    uint32_t i = (bits >> 15) - SRGB_START_BASE;
    return srgb_start[i < sizeof srgb_start ? i : sizeof srgb_start - 1];
}

/* The sRGB code of linear v: round to nearest in sRGB terms, clamped to
 * 0..255; NaN (inf * 0 from extreme scene values) becomes 0.  A table
 * lookup by the value's top bits, then one comparison with the exact
 * thresholds (two in a double build): every pixel channel goes through here, and a
 * binary search over the thresholds cost a cheap scene a fifth of its
 * time. */
static inline uint8_t srgb_encode8(real v)
{
#ifndef LANRAY_DOUBLE
    /* a float build compares floats: srgb_threshold_f, and the value is
     * its own bucket's float, at most one code above the guess; the
     * double path below took a sixteenth of a frame of the 1M sphere */
    if (!(v >= srgb_threshold_f[0])) /* also NaN */
        return 0;
    if (v >= srgb_threshold_f[254])
        return 255;
    int code = srgb_guess(v);
    code += v >= srgb_threshold_f[code];
    return (uint8_t)code;
#else
    double d = (double)v;
    if (!(d >= srgb_threshold[0])) /* also NaN */
        return 0;
    if (d >= srgb_threshold[254])
        return 255;
    float f = (float)d;
    if ((double)f > d) /* rounded up: the bucket's guess must not pass d's code */
        f = nextafterf(f, 0.0f);
    int code = srgb_guess(f);
    /* two steps without a branch: the guess is at most one below for a
     * float (test_srgb checks every float in range), and a double between
     * two floats is at most one code past the lower one's.  The loop this
     * replaces guessed its exit wrong about every other channel.  code stays
     * at most 254: d < threshold 254. */
    code += d >= srgb_threshold[code];
    code += d >= srgb_threshold[code];
    return (uint8_t)code;
#endif
}

/* Linear output (--linear): v * 255 rounded, clamped; NaN becomes 0.  In
 * double, where a float's product with 255 is exact: in float, 0.9f * 255
 * rounded up to 229.5 and the code to 230. */
static inline uint8_t linear_encode8(real v)
{
    double d = v > R(0) ? (v < R(1) ? (double)v : 1.0) : 0.0;
    return (uint8_t)(d * 255 + 0.5);
}

/* Linear light as RGBE (Ward's shared exponent, Radiance .hdr): the
 * largest channel's binary exponent e + 128 in the fourth byte, each
 * channel's mantissa in 1/256 steps of 2^e (truncated, as Radiance does);
 * below 1e-32, negative or NaN gives zero.  Integer results of exact
 * operations: the same bytes on every CPU. */
static inline void rgbe_encode(real r, real g, real b, uint8_t out[4])
{
    double c[3] = {r > R(0) ? (double)r : 0.0, g > R(0) ? (double)g : 0.0, b > R(0) ? (double)b : 0.0};
    double v = c[0] > c[1] ? c[0] : c[1];
    v = v > c[2] ? v : c[2];
    if (!(v >= 1e-32) || !isfinite(v)) {
        out[0] = out[1] = out[2] = out[3] = 0;
        return;
    }
    int e;
    double m = frexp(v, &e) * 256.0 / v; /* v * m is just below 256 */
    for (int k = 0; k < 3; k++)
        out[k] = (uint8_t)(c[k] * m);
    out[3] = (uint8_t)(e + 128);
}

/* The light an RGBE pixel stands for, as Radiance reads it: each mantissa
 * taken at the middle of its 1/256 step (rgbe_encode truncates), times
 * 2^(exponent - 136); exponent byte 0 is black. */
static inline void rgbe_decode(const uint8_t in[4], double out[3])
{
    double f = in[3] ? ldexp(1.0, (int)in[3] - 136) : 0.0;
    for (int k = 0; k < 3; k++)
        out[k] = in[3] ? ((double)in[k] + 0.5) * f : 0.0;
}

/* n RGBE pixels as 8-bit sRGB codes after a gain (2^exposure): how a
 * window shows a high dynamic range frame. */
void srgb_from_rgbe(const uint8_t *rgbe, size_t n, double gain, uint8_t *rgb);

/* The linear value of an sRGB-encoded fraction s in [0, 1] (for images that
 * are not 8 bits deep; 8-bit codes use srgb_decode8). */
double srgb_decode(double s);

#endif
