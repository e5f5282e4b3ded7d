/* dmath.h - sine and cosine, exp, log2 and pow in double by lanray's own
 * arithmetic: the same bits on every machine.
 *
 * A farm's frame must be the same bits from every client, and glibc picks
 * its variant of sinf, cosf, sincosf, expf and powf (and of the double
 * sin, cos, tan, atan and log2) by the CPU: with FMA or without.  The two do not
 * always agree: over all 2^32 floats (2026-12-01, glibc 2.36), expf's
 * differ on 2 inputs, sinf's on 12 and cosf's on 22 (all beyond 17 in
 * size), and powf(x, 20) on one x in (0, 1], powf(x, 1 / 2.2) on three,
 * by one unit in the last place (docs/renderer.md, "Arithmetic the same on
 * every machine").  These use only the operations IEEE 754 rounds one
 * way (+, -, x, /, conversions; no contraction: -ffp-contract=off), so
 * every machine computes them alike.  In double, so that a float rounded
 * from them is nearly always the correctly rounded one: the float build's
 * pictures stay what the library's functions gave them but for such
 * inputs.  Accuracy: sine and cosine within 4e-16 (absolute) for |x|
 * below 10^6 (farther, a deterministic reduction and less accuracy), log2
 * within 4e-16 absolute on [0.5, 2], exp2 and exp within 3 units of the
 * last place, pow within (4 + |y| + |y log2 x|) 3e-16 relative, where the
 * results are normal doubles (tests/test_dmath.c). */
#ifndef LANRAY_DMATH_H
#define LANRAY_DMATH_H

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "base/real.h"

/* sin(x) and cos(x): the quadrant taken off in three steps (Cody and
 * Waite, fdlibm's 33-bit pieces of pi/2, exact in products with any k
 * below 2^20), then fdlibm's kernels on [-pi/4, pi/4]. */
static inline void dmath_sincos(double x, double *s, double *c)
{
    if (!(fabs(x) < 1e6)) {
        if (!(fabs(x) <= 1.79769313486231570815e308)) { /* NaN or infinity */
            *s = *c = x - x;
            return;
        }
        x = fmod(x, 6.28318530717958647692); /* exact (IEEE): far turns, less accurate, the same everywhere */
    }
    const long k = lrint(x * 6.36619772367581382433e-01);
    const double kd = (double)k;
    const double r = ((x - kd * 1.57079632673412561417e+00) - kd * 6.07710050630396597660e-11) -
                     kd * 2.02226624879595063154e-21;
    const double z = r * r;
    double ps = 1.58969099521155010221e-10, pc = -1.13596475577881948265e-11;
    ps = ps * z - 2.50507602534068634195e-08, pc = pc * z + 2.08757232129817482790e-09;
    ps = ps * z + 2.75573137070700676789e-06, pc = pc * z - 2.75573143513906633035e-07;
    ps = ps * z - 1.98412698298579493134e-04, pc = pc * z + 2.48015872894767294178e-05;
    ps = ps * z + 8.33333333332248946124e-03, pc = pc * z - 1.38888888888741095749e-03;
    ps = ps * z - 1.66666666666666324348e-01, pc = pc * z + 4.16666666666666019037e-02;
    const double sr = r + r * z * ps, cr = 1.0 - 0.5 * z + z * z * pc;
    /* quadrant q turns (sr, cr) by q x 90 degrees */
    const int q = (int)(k & 3);
    const double ss = q & 1 ? cr : sr, cc = q & 1 ? sr : cr;
    *s = q & 2 ? -ss : ss;
    *c = (q + 1) & 2 ? -cc : cc;
}

/* e^r 2^(n/32) for |r| <= ln 2 / 64: 2^(j/32) from the table (j = n mod
 * 32) times e^r by its Taylor series to the sixth power (the term after
 * it below 4e-18), times 2^((n - j) / 32) in at most two exact steps
 * (where that is a normal double) and one rounding. */
static inline double dmath_scaled_exp(double r, long n)
{
    /* 2^(j/32), j = 0..31, correctly rounded (made with Python's decimal at
     * 60 digits) */
    static const double exp2_32[32] = {
        1.0, 1.0218971486541166, 1.0442737824274138, 1.0671404006768237, 1.0905077326652577, 1.1143867425958924,
        1.1387886347566916, 1.1637248587775775, 1.189207115002721, 1.215247359980469, 1.241857812073484,
        1.2690509571917332, 1.2968395546510096, 1.3252366431597413, 1.3542555469368927, 1.383909881963832,
        1.4142135623730951, 1.4451808069770467, 1.4768261459394993, 1.5091644275934228, 1.5422108254079407,
        1.5759808451078865, 1.6104903319492543, 1.645755478153965, 1.681792830507429, 1.718619298122478,
        1.7562521603732995, 1.7947090750031072, 1.8340080864093424, 1.8741676341103, 1.9152065613971474,
        1.9571441241754002};
    const long j = n & 31, k = (n - j) / 32;
    const double p =
        1.0 + r * (1.0 + r * (0.5 + r * (1.0 / 6.0 + r * (1.0 / 24.0 + r * (1.0 / 120.0 + r * (1.0 / 720.0))))));
    long k1 = k, k2 = 0;
    if (k1 > 1023)
        k2 = k1 - 1023, k1 = 1023;
    else if (k1 < -1022)
        k2 = k1 + 1022, k1 = -1022;
    uint64_t b1 = (uint64_t)(k1 + 1023) << 52, b2 = (uint64_t)(k2 + 1023) << 52;
    double s1, s2;
    memcpy(&s1, &b1, sizeof s1);
    memcpy(&s2, &b2, sizeof s2);
    const double v = exp2_32[j] * p;
    return k2 ? v * s1 * s2 : v * s1;
}

/* 2^t: the nearest n/32 taken off t (exact), the rest times ln 2. */
static inline double dmath_exp2(double t)
{
    if (!(t < 1024.0))
        return t != t ? t : HUGE_VAL;
    if (t < -1080.0)
        return 0.0;
    const long n = lrint(t * 32.0);
    return dmath_scaled_exp((t - (double)n * 0.03125) * 6.93147180559945286227e-01, n);
}

/* e^x: the nearest multiple n of ln 2 / 32 taken off in two steps (Cody
 * and Waite: ln 2 / 32 in a 21-bit head, exact times any n here, and a
 * tail), so that the rest keeps x's accuracy however large x is. */
static inline double dmath_exp(double x)
{
    if (!(x < 709.8))
        return x != x ? x : HUGE_VAL;
    if (x < -748.0)
        return 0.0;
    const long n = lrint(x * 46.16624130844683);
    const double r = (x - (double)n * 0.021660834550857544) - (double)n * 1.4841640746973977e-08;
    return dmath_scaled_exp(r, n);
}

/* log2(x) for x > 0: x = m 2^e with m in [1, 2), c the centre of m's
 * thirty-second (its first five bits), log2(m) = log2(c) + (2 / ln 2)
 * atanh(z), z = (m - c) / (m + c) (m - c exact) by its series to z^7.
 * 0 gives -inf, a negative or NaN x NaN, infinity infinity. */
static inline double dmath_log2(double x)
{
    /* log2(1 + (i + 1/2) / 32), i = 0..31, correctly rounded (as the table
     * above) */
    static const double log2_32[32] = {
        0.02236781302845451, 0.06608919045777244, 0.10852445677816905, 0.14974711950468206, 0.18982455888001723,
        0.22881869049588088, 0.2667865406949014,  0.30378074817710293, 0.33985000288462475, 0.37503943134692475,
        0.4093909361377018,  0.4429434958487283,  0.47573343096639775, 0.5077946401986962,  0.5391588111080314,
        0.5698556083309478,  0.5999128421871277,  0.6293566200796096,  0.6582114827517948,  0.6865005271832184,
        0.7142455176661227,  0.7414669864011469,  0.7681843247769263,  0.794415866350106,   0.8201789624151877,
        0.8454900509443752,  0.8703647195834046,  0.8948177633079435,  0.9188632372745945,  0.9425145053392399,
        0.965784284662087,   0.9886846867721658};
    if (!(x > 0.0))
        return x == 0.0 ? -HUGE_VAL : (double)NAN;
    if (x == HUGE_VAL)
        return x;
    int e = 0;
    if (x < 2.2250738585072014e-308) /* subnormal: made normal first (exact) */
        x *= 18014398509481984.0, e = -54; /* 2^54 */
    uint64_t b;
    memcpy(&b, &x, sizeof b);
    e += (int)(b >> 52) - 1023;
    const int i = (int)(b >> 47 & 31);
    b = (b & 0x000fffffffffffffull) | 0x3ff0000000000000ull; /* m in [1, 2) */
    double m;
    memcpy(&m, &b, sizeof m);
    const double c = 1.0 + ((double)i + 0.5) * 0.03125;
    const double z = (m - c) / (m + c), w = z * z;
    const double series = 1.0 + w * (1.0 / 3.0 + w * (0.2 + w * (1.0 / 7.0)));
    return (double)e + (log2_32[i] + 2.88539008177792681472 * z * series);
}

/* x^y as the C library's pow has it at the edges (x^0 = 1, 1^y = 1, a
 * negative x to an integer power, zeros and infinities), elsewhere
 * 2^(y log2 x). */
static inline double dmath_pow(double x, double y)
{
    if (x > 0.0 && x < HUGE_VAL) /* the renderer's case: asked first */
        return x == 1.0 ? 1.0 : dmath_exp2(y * dmath_log2(x)); /* y = 0: 2^0, exactly 1 */
    if (y == 0.0)
        return 1.0;
    if (x != x || y != y)
        return x + y;
    /* y an odd integer: a negative base keeps its sign */
    const int odd = fabs(y) < 9007199254740992.0 && y == (double)(int64_t)y && ((int64_t)y & 1);
    if (x == 0.0)
        return y > 0.0 ? (odd ? x : 0.0) : (odd ? copysign(HUGE_VAL, x) : HUGE_VAL);
    if (x == HUGE_VAL)
        return y > 0.0 ? HUGE_VAL : 0.0;
    if (x == -HUGE_VAL)
        return y > 0.0 ? (odd ? -HUGE_VAL : HUGE_VAL) : (odd ? -0.0 : 0.0);
    if (fabs(y) < 9007199254740992.0 && y != (double)(int64_t)y)
        return (double)NAN; /* a negative base to a fraction */
    const double v = dmath_pow(-x, y);
    return odd ? -v : v;
}

/* One of the two, and their quotient. */
static inline double dmath_sin(double x)
{
    double s, c;
    dmath_sincos(x, &s, &c);
    return s;
}

static inline double dmath_cos(double x)
{
    double s, c;
    dmath_sincos(x, &s, &c);
    return c;
}

static inline double dmath_tan(double x)
{
    double s, c;
    dmath_sincos(x, &s, &c);
    return s / c;
}

/* The same in the renderer's precision (real: float, or double in the
 * double build), rounded once from the double.  (trig_sincos, base/trig.h,
 * is the float build's cheaper sine and cosine, within 2e-7, for the
 * panorama's per-sample draws; these round as the C library's float
 * functions nearly always do, so that the pictures kept their bits.) */
static inline void dmath_sincosr(real x, real *s, real *c)
{
    double sd, cd;
    dmath_sincos((double)x, &sd, &cd);
    *s = (real)sd, *c = (real)cd;
}

static inline real dmath_sinr(real x) { return (real)dmath_sin((double)x); }
static inline real dmath_cosr(real x) { return (real)dmath_cos((double)x); }
static inline real dmath_tanr(real x) { return (real)dmath_tan((double)x); }
static inline real dmath_powr(real x, real y) { return (real)dmath_pow((double)x, (double)y); }
static inline real dmath_expr(real x) { return (real)dmath_exp((double)x); }
static inline real dmath_log2r(real x) { return (real)dmath_log2((double)x); }

#endif
