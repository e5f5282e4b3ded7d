/* real.h - the renderer's scalar type.
 *
 * Geometry and shading use `real`: float by default, double when built with
 * `make PRECISION=double` (which defines LANRAY_DOUBLE).  tgmath.h makes
 * sqrt/fabs/pow/... pick the right width for `real` arguments, so the same
 * source serves both builds; write constants as R(0.5) so that float builds
 * do not silently promote to double. */
#ifndef LANRAY_REAL_H
#define LANRAY_REAL_H

#include <float.h>
#include <stdint.h>
#include <string.h>
#include <tgmath.h>

#ifdef LANRAY_DOUBLE
typedef double real;
#define REAL_EPS DBL_EPSILON
#define REAL_MAX DBL_MAX
#define REAL_NAME "double"
#define REAL_DIGITS 17 /* significant digits that print a real so that it reads back the same */
#else
typedef float real;
#define REAL_EPS FLT_EPSILON
#define REAL_MAX FLT_MAX
#define REAL_NAME "float"
#define REAL_DIGITS 9
#endif

#define R(x) ((real)(x))
#define REAL_INF ((real)INFINITY)
#define REAL_PI R(3.14159265358979323846)

/* gamma(n) of Pharr, Jakob & Humphreys (PBRT 3.9): a bound on the relative
 * rounding error of n chained floating-point operations. */
static inline real real_gamma(int n)
{
    real ne = (real)n * (REAL_EPS * R(0.5));
    return ne / (R(1) - ne);
}

static inline real real_min(real a, real b) { return a < b ? a : b; }
static inline real real_max(real a, real b) { return a > b ? a : b; }
static inline real real_clamp(real x, real lo, real hi) { return x < lo ? lo : (x > hi ? hi : x); }
static inline int real_is_finite(real x) { return isfinite(x); }

/* nextafter(x, +inf), inline: the next representable value above x (the
 * least subnormal above a zero; infinity and NaN stay).  libm's is a call
 * per coordinate of every shadow ray's origin. */
static inline real real_next_up(real x)
{
#ifdef LANRAY_DOUBLE
    uint64_t b;
#else
    uint32_t b;
#endif
    if (!(x < REAL_INF)) /* +inf, NaN */
        return x;
    if (x == R(0))
        b = 1;
    else {
        memcpy(&b, &x, sizeof b);
        b = x > R(0) ? b + 1 : b - 1; /* the magnitude's bits count up from zero on either sign */
    }
    memcpy(&x, &b, sizeof b);
    return x;
}

/* nextafter(x, -inf) */
static inline real real_next_down(real x) { return -real_next_up(-x); }

#endif
