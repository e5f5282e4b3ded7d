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

#include "base/real.h"

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

/* (u, v) in the unit square to the unit disc, area-preserving (Shirley and
 * Chiu's concentric map: strata stay compact). */
static inline void sample_disc(real u, real v, real *x, real *y)
{
    real a = R(2) * u - R(1), b = R(2) * v - R(1);
    if (a == R(0) && b == R(0)) {
        *x = *y = R(0);
        return;
    }
    real r, phi;
    if (a * a > b * b) {
        r = a;
        phi = (REAL_PI / R(4)) * (b / a);
    } else {
        r = b;
        phi = (REAL_PI / R(2)) - (REAL_PI / R(4)) * (a / b);
    }
    *x = r * cos(phi);
    *y = r * sin(phi);
}

#endif
