/* sample.h - deterministic random numbers for sampling (area lights, rough
 * reflections, lens apertures).
 *
 * Every number comes from the pixel sample (the bits of its image
 * position), the bounce and what it is drawn for, through an integer hash,
 * never from a thread, a clock or a sequence consumed in order: a pixel
 * rendered by any client, in any segment, any number of times, draws the
 * same numbers, so distributed frames stay bit-identical.  A number in
 * [0, 1) has 24 random bits, exact in float and double. */
#ifndef LANRAY_SAMPLE_H
#define LANRAY_SAMPLE_H

#include <stdint.h>
#include <string.h>

#include "base/dmath.h"
#include "base/real.h"
#include "base/vec.h"

/* An integer hash with good avalanche (Wellons' "lowbias32"). */
static inline uint32_t sample_hash(uint32_t x)
{
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    x ^= x >> 16;
    return x;
}

/* A new key from a key and a number: the bounce, the light, the sample index. */
static inline uint32_t sample_mix(uint32_t key, uint32_t n) { return sample_hash(key ^ sample_hash(n + 0x9e3779b9U)); }

static inline uint32_t real_bits32(real v)
{
#ifdef LANRAY_DOUBLE
    uint64_t b;
    memcpy(&b, &v, sizeof b);
    return (uint32_t)b ^ (uint32_t)(b >> 32);
#else
    uint32_t b;
    memcpy(&b, &v, sizeof b);
    return b;
#endif
}

/* The key of the sample at image position (x, y). */
static inline uint32_t sample_seed(real x, real y) { return sample_mix(sample_hash(real_bits32(x)), real_bits32(y)); }

/* The key's number in [0, 1). */
static inline real sample_unit(uint32_t key) { return (real)(key >> 8) * R(5.9604644775390625e-8); /* 2^-24 */ }

/* Sample j of a k x k stratified pattern in the unit square: its cell,
 * jittered by two numbers from key. */
static inline void sample_stratum(uint32_t key, uint32_t j, uint32_t k, real *u, real *v)
{
    uint32_t h = sample_mix(key, j);
    real inv = R(1) / (real)k;
    *u = ((real)(j % k) + sample_unit(h)) * inv;
    *v = ((real)(j / k) + sample_unit(sample_hash(h))) * inv;
}

/* One sample budget per pixel: an effect that asks for K points a pixel
 * (an area light's K = samples^2, a lens's, a rough mirror's) spreads
 * them over the pixel's rays: ray `index` of the `count` rays its pixel
 * traces at its depth takes ceil(K / count) of them, points index * m ..
 * index * m + m - 1 of one sequence of count * m for the whole pixel, so
 * that the points of a pixel are stratified together and costs add (K +
 * rays) instead of multiplying (K x rays).  key: the pixel's, mixed with
 * the path (sample_mix); a ray's children (a rough mirror's) are rays
 * index * m + j of count * m. */
typedef struct {
    uint32_t key;
    uint32_t index, count; /* ray index of count, 0 <= index < count */
    /* Adaptive light sampling's first pass (settings light_sampling): 1
     * where this camera ray takes one point of each area light, the point
     * of stratum (px mod k, py mod k) of its k x k, so that every 3 x 3
     * block of pixels probes every stratum of a light of 3 x 3 (interleaved
     * sampling); 0 otherwise, and for every ray after a bounce. */
    uint32_t probe;
    uint16_t px, py;
} SampleId;

/* Points per ray when an effect wants k a pixel over `count` rays: ceil(k / count), at least 1. */
static inline uint32_t sample_share(uint32_t k, uint32_t count) { return count >= k ? 1u : (k + count - 1) / count; }

static inline uint32_t sample_reverse(uint32_t x)
{
    x = __builtin_bswap32(x); /* the halves and the bytes swapped in one instruction */
    x = ((x & 0x0f0f0f0fu) << 4) | ((x & 0xf0f0f0f0u) >> 4);
    x = ((x & 0x33333333u) << 2) | ((x & 0xccccccccu) >> 2);
    return ((x & 0x55555555u) << 1) | ((x & 0xaaaaaaaau) >> 1);
}

/* The Laine-Karras permutation of a 32-bit integer: each bit flipped by a
 * hash of the bits below it. */
static inline uint32_t sample_laine_karras(uint32_t x, uint32_t seed)
{
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

/* Owen scrambling of a 32-bit fraction (nested uniform: each bit flipped by
 * a hash of the bits above it), by the Laine-Karras permutation on the
 * bits reversed (Burley, "Practical Hash-based Owen Scrambling", JCGT 2020). */
static inline uint32_t sample_owen(uint32_t x, uint32_t seed) { return sample_reverse(sample_laine_karras(sample_reverse(x), seed)); }

/* One seed's sequence for sample_sobol_point: its three scrambles, hashed
 * once for all its points (an area light's nine points of a pixel hashed
 * them nine times; a sixth of the default scene's frame was sampling). */
typedef struct {
    uint32_t index, first, second;
} SampleSobol;

static inline SampleSobol sample_sobol_seq(uint32_t seed)
{
    return (SampleSobol){sample_hash(seed ^ 0x5bd1e995u), sample_hash(seed ^ 0x68e31da4u), sample_hash(seed ^ 0xb5297a4du)};
}

/* The first number alone of point `index` of q's sequence
 * (sample_sobol_point's u), for a dimension that needs one. */
static inline real sample_sobol_first(const SampleSobol *q, uint32_t index)
{
    return sample_unit(sample_reverse(sample_laine_karras(sample_owen(index, q->index), q->first)));
}

/* sample_sobol_point's two numbers (below) as the 32-bit integers
 * sample_unit turns into u and v (base/sample_lanes.c makes eight at once). */
static inline void sample_sobol_bits(uint32_t seq_index, uint32_t seq_first, uint32_t seq_second, uint32_t index,
                                     uint32_t *u, uint32_t *v)
{
    uint32_t i = sample_owen(index, seq_index);
    /* the second Sobol dimension: bit 31 - j of y is the parity of the bits
     * k of i with C(k, j) odd, that is (Lucas) with j's bits a subset of
     * k's: a superset sum over the five bits of a bit's position, five
     * shifts where a loop over i's bits took up to 32 steps */
    uint32_t z = i;
    z ^= (z >> 1) & 0x55555555u;
    z ^= (z >> 2) & 0x33333333u;
    z ^= (z >> 4) & 0x0f0f0f0fu;
    z ^= (z >> 8) & 0x00ff00ffu;
    z ^= (z >> 16) & 0x0000ffffu;
    /* sample_owen(sample_reverse(i)) with the two reversals that cancel left out */
    *v = sample_reverse(sample_laine_karras(z, seq_second));
    *u = sample_reverse(sample_laine_karras(i, seq_first));
}

/* Point `index` of an Owen-scrambled Sobol (0,2)-sequence in the unit
 * square, its index shuffled too (Burley's shuffled scrambled Sobol), for
 * one sequence per seed (sample_sobol_seq): any 2^k consecutive aligned
 * points are a (0,k,2)-net (one point in every 2^-a x 2^-(k-a) box), the
 * first n of a sequence are well spread for any n, and two seeds'
 * sequences are independent. */
static inline void sample_sobol_point(const SampleSobol *q, uint32_t index, real *u, real *v)
{
    uint32_t a, b;
    sample_sobol_bits(q->index, q->first, q->second, index, &a, &b);
    *u = sample_unit(a);
    *v = sample_unit(b);
}

/* Point `index` of seed's sequence (sample_sobol_point). */
static inline void sample_sobol2(uint32_t index, uint32_t seed, real *u, real *v)
{
    const SampleSobol q = sample_sobol_seq(seed);
    sample_sobol_point(&q, index, u, v);
}

/* The sequence of a pixel of this key for sample_grid_cell: the cell of
 * sample `index` of its 2^m x 2^m grid of sample positions (the path
 * integrator's N x N, N a power of two), in an order whose every prefix is
 * spread: the cell the Sobol point of index `index` of the pixel's own
 * sequence falls in.  The first 4^m indices are
 * an aligned block of the shuffled sequence, a (0,2m,2)-net, so they take
 * every cell once; the first 4^k (k < m) take one cell in each 2^(m-k) x
 * 2^(m-k) block, at a place that differs from pixel to pixel, so that a
 * picture of the first 4^k samples of N x N is as even as one of 2^k x 2^k
 * and the samples after them add to it (render/progressive.h). */
static inline SampleSobol sample_grid_seq(uint32_t key) { return sample_sobol_seq(sample_mix(key, 0x43454c4cu)); /* "CELL" */ }

/* ... of the pixel whose sequence is q (sample_grid_seq of its key). */
static inline void sample_grid_cell(const SampleSobol *q, uint32_t index, int m, uint32_t *i, uint32_t *j)
{
    uint32_t u, v;
    sample_sobol_bits(q->index, q->first, q->second, index, &u, &v);
    *i = m > 0 ? u >> (32 - m) : 0;
    *j = m > 0 ? v >> (32 - m) : 0;
}

/* (u, v) in the unit square to a unit vector, uniform over the sphere
 * (z uniform in [-1, 1], the longitude by v). */
static inline vec3 sample_sphere(real u, real v)
{
    real z = R(1) - R(2) * u, phi = R(2) * REAL_PI * v, rr = sqrt(real_max(R(0), R(1) - z * z));
    real sp, cp;
    dmath_sincosr(phi, &sp, &cp);
    return v3(rr * cp, rr * sp, z);
}

/* sin and cos of |a| <= pi/4 by Cephes' minimax polynomials of sinf and
 * cosf (within 1e-7 there): the concentric map's angle, where the C
 * library's sincos took a sixth of the time of an area light's point, and
 * the same bits on every machine.  Short: a dependent chain of a point. */
static inline void sample_sincos_quarter(real a, real *s, real *c)
{
    const real a2 = a * a;
    *s = a + a * a2 * (R(-1.6666654611e-1) + a2 * (R(8.3321608736e-3) + a2 * R(-1.9515295891e-4)));
    *c = R(1) - R(0.5) * a2 + a2 * a2 * (R(4.166664568298827e-2) + a2 * (R(-1.388731625493765e-3) + a2 * R(2.443315711809948e-5)));
}

/* (u, v) in the unit square to the unit disc, area-preserving (Shirley and
 * Chiu's concentric map: strata stay compact). */
static inline void sample_disc(real u, real v, real *x, real *y)
{
    real a = R(2) * u - R(1), b = R(2) * v - R(1);
    if (a == R(0) && b == R(0)) {
        *x = *y = R(0);
        return;
    }
    /* the angle (pi/4)(b/a) where |a| > |b|, else pi/2 - (pi/4)(a/b),
     * whose cos is the sine of (pi/4)(a/b): chosen without a branch (it
     * goes either way at random) */
    const int wide = a * a > b * b;
    const real r = wide ? a : b, q = wide ? b : a;
    real s, c;
    sample_sincos_quarter((REAL_PI / R(4)) * (q / r), &s, &c);
    *x = r * (wide ? c : s);
    *y = r * (wide ? s : c);
}

#endif
