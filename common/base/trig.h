/* trig.h - atan2, sine and cosine for what runs every sample (a
 * panorama's directions): in the float build by polynomials of lanray's
 * own, in the double build the C library's atan2 and dmath.h's sine and
 * cosine.
 *
 * The C library's sinf, cosf and atan2f were a tenth of a sky-lit
 * path-traced frame (environment_uv's two atan2f a lookup, the draws' four
 * sines and cosines), and they are the C library's: a machine with
 * another libm, or one that picks another variant by its CPU, may round
 * them otherwise, and a farm's frame must be the same bits from every
 * client (glibc 2.36 takes sincosf's FMA variant where the CPU has FMA).
 * These are plain arithmetic (no contraction: -ffp-contract=off), the
 * same bits everywhere: atan2 within 3e-7 of the true value, relative,
 * the sine and cosine within 2e-7 (tests/test_trig.c); the double build's
 * sine and cosine are dmath.h's, its atan2 the library's (which glibc
 * does not vary by the CPU). */
#ifndef LANRAY_TRIG_H
#define LANRAY_TRIG_H

#include <math.h>

#include "base/dmath.h"
#include "base/real.h"
#include "base/sample.h"

/* atan2(y, x) in (-pi, pi], as the C library's: the signs of zeros kept,
 * atan2(+-0, x < 0) = +-pi, (0, 0) 0, a NaN for a NaN.  Cephes' atanf on
 * the smaller over the larger magnitude (relative error 1.9e-7), then
 * the octant. */
static inline real trig_atan2(real y, real x)
{
#ifdef LANRAY_DOUBLE
    return atan2(y, x);
#else
    const float ax = fabsf(x), ay = fabsf(y), hi = ax > ay ? ax : ay, lo = ax > ay ? ay : ax;
    if (!(hi > 0.0f) || hi == INFINITY) /* zeros, NaNs, infinities: rare, the library's rules */
        return atan2f(y, x);
    float t = lo / hi, a = 0.0f;
    if (t > 0.4142135623730950f) { /* past tan(pi/8): about pi/4 */
        t = (t - 1.0f) / (t + 1.0f);
        a = 0.7853981633974483f;
    }
    const float z = t * t;
    a += (((8.05374449538e-2f * z - 1.38776856032e-1f) * z + 1.99777106478e-1f) * z - 3.33329491539e-1f) * z * t + t;
    if (ay > ax)
        a = 1.5707963267948966f - a;
    if (signbit(x))
        a = 3.1415926535897932f - a;
    return copysignf(a, y);
#endif
}

/* sin(a) and cos(a) for |a| under 8192: the quadrant's
 * multiple of pi/2 taken off in two steps (Cody and Waite: pi/2's first
 * eight bits, exact in any product with it, then the rest), then
 * sample_sincos_quarter's polynomials. */
static inline void trig_sincos(real a, real *s, real *c)
{
#ifdef LANRAY_DOUBLE
    dmath_sincosr(a, s, c);
#else
    if (!(fabsf(a) < 8192.0f)) { /* NaNs, infinities, far turns: in double (dmath.h) */
        dmath_sincosr(a, s, c);
        return;
    }
    const int ki = (int)lrintf(a * 0.6366197723675814f); /* the nearest quadrant: one conversion */
    const float k = (float)ki;
    const float r = (a - k * 1.5703125f) - k * 4.8382679489661923e-4f;
    float sr, cr;
    sample_sincos_quarter(r, &sr, &cr);
    /* the quadrant q turns (sr, cr) by q x 90 degrees: selects, not branches */
    const int q = ki & 3;
    const float ss = q & 1 ? cr : sr, cc = q & 1 ? sr : cr;
    *s = q & 2 ? -ss : ss;
    *c = (q + 1) & 2 ? -cc : cc;
#endif
}

#endif
