/* upscale.c - see upscale.h.
 *
 * The scale k = p / q in lowest terms (s / 2: q is 1 where s is even, 2
 * where it is odd).  A full pixel x's centre, x + 1/2, lies at (x + 1/2) q
 * / p - 1/2 in frame pixels (a frame pixel i's centre is the middle of its
 * block, (i + 1/2) p / q).  In units of 1/(2p): (2x + 1) q - p, whose floor
 * division by 2p is the left frame pixel and whose remainder r the right
 * one's weight (2p - r the left's).  Lines are mixed first (each frame
 * line once, into scratch, at most 255 x 2p: 16 bits), then the two mixed
 * lines about each full line, the sum of weights (2p)^2 divided out with
 * rounding.  A whole scale (q 1) is the arithmetic of whole scales alone,
 * as it was before the half steps: the same bytes. */
#include "upscale.h"

#include <assert.h>
#include <string.h>

#include "base/srgb.h"
#ifdef __SSE2__
#include <emmintrin.h>
#endif

const char *const upscale_names[] = {"smooth", "blocks", NULL};

void upscale_blocks(const uint8_t *src, uint8_t *dst, uint32_t w, uint32_t h, uint32_t bpp, uint32_t s)
{
    const uint32_t sw = upscale_side(w, s);
    const size_t row = (size_t)w * bpp;
    for (uint32_t y = 0; y < h; y++) {
        uint8_t *d = dst + (size_t)y * row;
        /* the frame pixel a full pixel's centre falls in: (2y + 1) / 2k */
        const uint32_t j = (uint32_t)((2ull * y + 1) / s);
        if (y > 0 && j == (uint32_t)((2ull * y - 1) / s)) { /* the line above, again */
            memcpy(d, d - row, row);
            continue;
        }
        const uint8_t *l = src + (size_t)j * sw * bpp;
        for (uint32_t x = 0; x < w; x++)
            memcpy(d + (size_t)x * bpp, l + (size_t)((2ull * x + 1) / s) * bpp, bpp);
    }
}

size_t upscale_scratch(uint32_t w, uint32_t h, uint32_t s)
{
    return (size_t)upscale_side(h, s) * w * 3 + (size_t)w * 3; /* the mixed lines, then each column's taps */
}

/* Scale s (half steps) as p / q in lowest terms. */
static void ratio(uint32_t s, uint32_t *p, uint32_t *q)
{
    *p = s % 2 ? s : s / 2;
    *q = s % 2 ? 2 : 1;
}

/* The frame pixels about full pixel x (or line) and the right one's
 * weight in 1/(2p), for a frame n pixels across at scale p / q. */
static void taps(uint32_t x, uint32_t p, uint32_t q, uint32_t n, uint32_t *a, uint32_t *b, uint32_t *r)
{
    const int64_t u = (2 * (int64_t)x + 1) * (int64_t)q - (int64_t)p, k2 = 2 * (int64_t)p;
    const int64_t i = u >= 0 ? u / k2 : -((-u + k2 - 1) / k2); /* floor */
    *r = (uint32_t)(u - i * k2);
    const int64_t last = (int64_t)n - 1;
    *a = (uint32_t)(i < 0 ? 0 : i > last ? last : i);
    *b = (uint32_t)(i + 1 < 0 ? 0 : i + 1 > last ? last : i + 1);
}

/* A full line, n bytes, from the two mixed lines about it (weights wa
 * and wb), rounded: (wa m0 + wb m1 + sum / 2) / sum.  The division is done
 * in float, which vectorises: the dividend is an integer below 2^24, exact
 * in a float, and its quotient either whole or at least 1/sum below the
 * next whole number; its product with the rounded 1/sum is within a few
 * 2^-24 of the quotient (at most 256), so with 2^-10 added its truncation
 * is the exact quotient's floor either way.  With SSE2 (`wide`: the
 * products signed 16 by 16 bits, which p <= 64 allows) eight at a time,
 * by the same operations. */
static void mix_lines(const uint16_t *m0, const uint16_t *m1, uint32_t wa, uint32_t wb, uint32_t sum, int wide,
                      uint8_t *d, size_t n)
{
    const float inv = 1.0f / (float)sum, nudge = 1.0f / 1024.0f;
    size_t i = 0;
#ifdef __SSE2__
    const __m128i va = _mm_set1_epi32((int)wa), vb = _mm_set1_epi32((int)wb), half = _mm_set1_epi32((int)(sum / 2));
    const __m128 vinv = _mm_set1_ps(inv), vnudge = _mm_set1_ps(nudge);
    const __m128i zero = _mm_setzero_si128();
    for (; wide && i + 8 <= n; i += 8) {
        const __m128i a8 = _mm_loadu_si128((const __m128i *)(const void *)(m0 + i));
        const __m128i b8 = _mm_loadu_si128((const __m128i *)(const void *)(m1 + i));
        __m128i q[2];
        for (int hi = 0; hi < 2; hi++) {
            const __m128i a4 = hi ? _mm_unpackhi_epi16(a8, zero) : _mm_unpacklo_epi16(a8, zero);
            const __m128i b4 = hi ? _mm_unpackhi_epi16(b8, zero) : _mm_unpacklo_epi16(b8, zero);
            const __m128i x = _mm_add_epi32(_mm_add_epi32(_mm_madd_epi16(a4, va), _mm_madd_epi16(b4, vb)), half);
            q[hi] = _mm_cvttps_epi32(_mm_add_ps(_mm_mul_ps(_mm_cvtepi32_ps(x), vinv), vnudge));
        }
        const __m128i p16 = _mm_packs_epi32(q[0], q[1]);
        _mm_storel_epi64((__m128i *)(void *)(d + i), _mm_packus_epi16(p16, p16));
    }
#else
    (void)wide;
#endif
    for (; i < n; i++)
        d[i] = (uint8_t)(int32_t)((float)(wa * m0[i] + wb * m1[i] + sum / 2) * inv + nudge);
}

void upscale_smooth(const uint8_t *src, uint8_t *dst, uint32_t w, uint32_t h, uint32_t s, uint16_t *scratch)
{
    uint32_t k, q;
    ratio(s, &k, &q);
    assert(k >= 1 && k <= 128); /* 255 x 2k fits 16 bits */
    const uint32_t sw = upscale_side(w, s), sh = upscale_side(h, s), k2 = 2 * k;
    uint16_t *col = scratch + (size_t)sh * w * 3; /* each column's taps: left, right, weight */
    for (uint32_t x = 0; x < w; x++) {
        uint32_t a, b, r;
        taps(x, k, q, sw, &a, &b, &r);
        col[3 * x] = (uint16_t)(3 * a), col[3 * x + 1] = (uint16_t)(3 * b), col[3 * x + 2] = (uint16_t)r;
    }
    for (uint32_t j = 0; j < sh; j++) {
        const uint8_t *l = src + (size_t)j * sw * 3;
        uint16_t *m = scratch + (size_t)j * w * 3;
        for (uint32_t x = 0; x < w; x++) {
            const uint32_t a = col[3 * x], b = col[3 * x + 1], r = col[3 * x + 2];
            for (int c = 0; c < 3; c++)
                m[3 * x + c] = (uint16_t)((k2 - r) * l[a + c] + r * l[b + c]);
        }
    }
    const uint32_t sum = k2 * k2;
    for (uint32_t y = 0; y < h; y++) {
        uint32_t a, b, r;
        taps(y, k, q, sh, &a, &b, &r);
        mix_lines(scratch + (size_t)a * w * 3, scratch + (size_t)b * w * 3, k2 - r, r, sum, k <= 64,
                  dst + (size_t)y * w * 3, (size_t)w * 3);
    }
}

size_t upscale_scratch_rgbe(uint32_t w, uint32_t h, uint32_t s)
{
    return (size_t)upscale_side(w, s) * upscale_side(h, s) * 3;
}

void upscale_smooth_rgbe(const uint8_t *src, uint8_t *dst, uint32_t w, uint32_t h, uint32_t s, double *scratch)
{
    uint32_t k, q;
    ratio(s, &k, &q);
    assert(k >= 1);
    const uint32_t sw = upscale_side(w, s), sh = upscale_side(h, s), k2 = 2 * k;
    for (size_t i = 0; i < (size_t)sw * sh; i++)
        rgbe_decode(src + 4 * i, scratch + 3 * i);
    const double sum = (double)k2 * (double)k2;
    for (uint32_t y = 0; y < h; y++) {
        uint32_t j0, j1, t;
        taps(y, k, q, sh, &j0, &j1, &t);
        const double *l0 = scratch + (size_t)j0 * sw * 3, *l1 = scratch + (size_t)j1 * sw * 3;
        for (uint32_t x = 0; x < w; x++) {
            uint32_t i0, i1, r;
            taps(x, k, q, sw, &i0, &i1, &r);
            /* whole-number weights, the products and sums in one order: the same bits everywhere */
            const double w00 = (double)((k2 - r) * (k2 - t)), w10 = (double)(r * (k2 - t));
            const double w01 = (double)((k2 - r) * t), w11 = (double)(r * t);
            double c[3];
            for (int ch = 0; ch < 3; ch++)
                c[ch] = (w00 * l0[3 * i0 + ch] + w10 * l0[3 * i1 + ch] + w01 * l1[3 * i0 + ch] + w11 * l1[3 * i1 + ch]) /
                        sum;
            rgbe_encode((real)c[0], (real)c[1], (real)c[2], dst + 4 * ((size_t)y * w + x));
        }
    }
}
