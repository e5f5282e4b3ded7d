/* upscale.c - see upscale.h.
 *
 * Where a frame pixel's ray went: the camera spans a frame's width with
 * its pixels whatever their number (the view plane is 2 wide: camera.h),
 * square, its height centred.  A frame of sw x sh pixels for a full one
 * of W x H therefore has pixels sw / W of the full ones' size, and its
 * lines are centred on the full frame's, which is not where k x k blocks
 * from the top-left corner would put them where W or H is no multiple of
 * k (1024 / 3 = 341.3: 342 pixels, 2.994 full ones each; 768 / 2.5: 308
 * lines for 307.2, reaching 0.6 of a full line past the top and the
 * bottom).  A full pixel t's centre lies at frame position
 *
 *     ((2t + 1) sw - N sw + n W - W) / 2W
 *
 * along an axis of N full and n frame pixels (from the first frame
 * pixel's centre; across, N = W and n = sw: ((2t + 1) sw - W) / 2W), the
 * whole k x k blocks' (t + 1/2) / k - 1/2 where sw k = W and sh k = H.
 * Positions are rounded to the nearest 1/UPSCALE_PLACES of a frame pixel
 * (exact at scales 1, 2, 4 and 8 on whole blocks: the bytes of those are
 * as they were), whose floor is the left frame pixel and whose remainder
 * r the right one's weight (UPSCALE_PLACES - r the left's).  Lines are
 * mixed first (each frame line once, into scratch, at most 255 x 128: 16
 * bits, signed too), then the two mixed lines about each full line, the
 * sum of weights divided out with rounding. */
#include "upscale.h"

#include <string.h>

#include "base/srgb.h"
#ifdef __SSE2__
#include <emmintrin.h>
#endif

#define UPSCALE_PLACES 128

/* Full pixel t's centre on an axis of N full and n frame pixels (sw
 * frame pixels across W full ones), in 1/UPSCALE_PLACES of a frame pixel
 * from the first frame pixel's centre, rounded to the nearest (halves up). */
static int64_t place(uint32_t t, uint32_t N, uint32_t n, uint32_t sw, uint32_t W)
{
    const int64_t num = ((2 * (int64_t)t + 1) * sw - (int64_t)N * sw + (int64_t)n * W - W) * UPSCALE_PLACES;
    const int64_t den = 2 * (int64_t)W;
    const int64_t twice = 2 * num + den; /* floor((2 num + den) / 2 den) */
    return twice >= 0 ? twice / (2 * den) : -((-twice + 2 * den - 1) / (2 * den));
}

/* The frame pixels about full pixel t (of N on an axis of n frame pixels)
 * and the right one's weight in 1/UPSCALE_PLACES. */
static void taps(uint32_t t, uint32_t N, uint32_t n, uint32_t sw, uint32_t W, uint32_t *a, uint32_t *b, uint32_t *r)
{
    const int64_t u = place(t, N, n, sw, W);
    const int64_t i = u >= 0 ? u / UPSCALE_PLACES : -((-u + UPSCALE_PLACES - 1) / UPSCALE_PLACES); /* floor */
    *r = (uint32_t)(u - i * UPSCALE_PLACES);
    const int64_t last = (int64_t)n - 1;
    *a = (uint32_t)(i < 0 ? 0 : i > last ? last : i);
    *b = (uint32_t)(i + 1 < 0 ? 0 : i + 1 > last ? last : i + 1);
}

/* The frame pixel whose area holds full pixel t's centre (the nearest
 * centre), clamped. */
static uint32_t nearest(uint32_t t, uint32_t N, uint32_t n, uint32_t sw, uint32_t W)
{
    const int64_t u = place(t, N, n, sw, W) + UPSCALE_PLACES / 2;
    const int64_t i = u >= 0 ? u / UPSCALE_PLACES : -1, last = (int64_t)n - 1;
    return (uint32_t)(i < 0 ? 0 : i > last ? last : i);
}

const char *const upscale_names[] = {"smooth", "blocks", NULL};

void upscale_blocks(const uint8_t *src, uint8_t *dst, uint32_t w, uint32_t h, uint32_t bpp, uint32_t s)
{
    const uint32_t sw = upscale_side(w, s), sh = upscale_side(h, s);
    const size_t row = (size_t)w * bpp;
    for (uint32_t y = 0; y < h; y++) {
        uint8_t *d = dst + (size_t)y * row;
        const uint32_t j = nearest(y, h, sh, sw, w);
        if (y > 0 && j == nearest(y - 1, h, sh, sw, w)) { /* the line above, again */
            memcpy(d, d - row, row);
            continue;
        }
        const uint8_t *l = src + (size_t)j * sw * bpp;
        for (uint32_t x = 0; x < w; x++)
            memcpy(d + (size_t)x * bpp, l + (size_t)nearest(x, w, sw, sw, w) * bpp, bpp);
    }
}

size_t upscale_scratch(uint32_t w, uint32_t h, uint32_t s)
{
    return (size_t)upscale_side(h, s) * w * 3 + (size_t)w * 3; /* the mixed lines, then each column's taps */
}

/* A full line, n bytes, from the two mixed lines about it (weights wa and
 * wb, summing to UPSCALE_PLACES), rounded: (wa m0 + wb m1 + sum / 2) /
 * sum, the sum UPSCALE_PLACES^2 = 2^14 a shift.  With SSE2 (the products
 * signed 16 by 16 bits, which 255 x 128 allows) eight at a time. */
#define UPSCALE_SHIFT 14
_Static_assert(UPSCALE_PLACES * UPSCALE_PLACES == 1 << UPSCALE_SHIFT, "the sum of weights a power of two");

static void mix_lines(const uint16_t *m0, const uint16_t *m1, uint32_t wa, uint32_t wb, uint8_t *d, size_t n)
{
    const uint32_t half = 1u << (UPSCALE_SHIFT - 1);
    size_t i = 0;
#ifdef __SSE2__
    const __m128i va = _mm_set1_epi32((int)wa), vb = _mm_set1_epi32((int)wb), vhalf = _mm_set1_epi32((int)half);
    const __m128i zero = _mm_setzero_si128();
    for (; i + 8 <= n; i += 8) {
        const __m128i a8 = _mm_loadu_si128((const __m128i *)(const void *)(m0 + i));
        const __m128i b8 = _mm_loadu_si128((const __m128i *)(const void *)(m1 + i));
        __m128i q[2];
        for (int hi = 0; hi < 2; hi++) {
            const __m128i a4 = hi ? _mm_unpackhi_epi16(a8, zero) : _mm_unpacklo_epi16(a8, zero);
            const __m128i b4 = hi ? _mm_unpackhi_epi16(b8, zero) : _mm_unpacklo_epi16(b8, zero);
            const __m128i x = _mm_add_epi32(_mm_add_epi32(_mm_madd_epi16(a4, va), _mm_madd_epi16(b4, vb)), vhalf);
            q[hi] = _mm_srli_epi32(x, UPSCALE_SHIFT);
        }
        const __m128i p16 = _mm_packs_epi32(q[0], q[1]);
        _mm_storel_epi64((__m128i *)(void *)(d + i), _mm_packus_epi16(p16, p16));
    }
#endif
    for (; i < n; i++)
        d[i] = (uint8_t)((wa * m0[i] + wb * m1[i] + half) >> UPSCALE_SHIFT);
}

void upscale_smooth(const uint8_t *src, uint8_t *dst, uint32_t w, uint32_t h, uint32_t s, uint16_t *scratch)
{
    const uint32_t sw = upscale_side(w, s), sh = upscale_side(h, s), k2 = UPSCALE_PLACES;
    uint16_t *col = scratch + (size_t)sh * w * 3; /* each column's taps: left, right, weight */
    for (uint32_t x = 0; x < w; x++) {
        uint32_t a, b, r;
        taps(x, w, sw, sw, w, &a, &b, &r);
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
    for (uint32_t y = 0; y < h; y++) {
        uint32_t a, b, r;
        taps(y, h, sh, sw, w, &a, &b, &r);
        mix_lines(scratch + (size_t)a * w * 3, scratch + (size_t)b * w * 3, k2 - r, r, dst + (size_t)y * w * 3,
                  (size_t)w * 3);
    }
}

size_t upscale_scratch_rgbe(uint32_t w, uint32_t h, uint32_t s)
{
    return (size_t)upscale_side(w, s) * upscale_side(h, s) * 3;
}

void upscale_smooth_rgbe(const uint8_t *src, uint8_t *dst, uint32_t w, uint32_t h, uint32_t s, double *scratch)
{
    const uint32_t sw = upscale_side(w, s), sh = upscale_side(h, s), k2 = UPSCALE_PLACES;
    for (size_t i = 0; i < (size_t)sw * sh; i++)
        rgbe_decode(src + 4 * i, scratch + 3 * i);
    const double sum = (double)k2 * (double)k2;
    for (uint32_t y = 0; y < h; y++) {
        uint32_t j0, j1, t;
        taps(y, h, sh, sw, w, &j0, &j1, &t);
        const double *l0 = scratch + (size_t)j0 * sw * 3, *l1 = scratch + (size_t)j1 * sw * 3;
        for (uint32_t x = 0; x < w; x++) {
            uint32_t i0, i1, r;
            taps(x, w, sw, sw, w, &i0, &i1, &r);
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
