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
#include <tgmath.h>

#ifdef LANRAY_DOUBLE
typedef double real;
#define REAL_EPS DBL_EPSILON
#define REAL_MAX DBL_MAX
#define REAL_NAME "double"
#else
typedef float real;
#define REAL_EPS FLT_EPSILON
#define REAL_MAX FLT_MAX
#define REAL_NAME "float"
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

#endif
