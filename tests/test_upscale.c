/* test_upscale.c - a frame at a render scale brought to the full size
 * (server/upscale.c): in blocks, each full pixel is its block's pixel; smooth,
 * each byte the exact rounded mix of its four (the vector loop's float
 * division included), a flat frame stays flat, a ramp stays the ramp sampled at each full
 * pixel's centre (clamped beyond the first and last centres), every pixel
 * lies within the four it mixes, and a mirrored frame comes out mirrored
 * (the centres are where they belong, not half a pixel off); RGBE frames
 * mix their light, decoded.  Every render scale in quarter steps, 1.25
 * to 8 (s = 5..32, k = s / 4: upscale.h), on sides that k divides and sides
 * it does not, where a frame pixel is where its camera ray went (the
 * frame spans the full width, its lines centred): not k x k blocks from
 * the corner, which would move the picture by up to 2 full pixels. */
#include "helpers.h"

#include <math.h>
#include <stdlib.h>

#include "base/srgb.h"
#include "upscale.h"

static uint8_t *frame_of(uint32_t sw, uint32_t sh, uint32_t bpp, uint32_t seed)
{
    uint8_t *f = malloc((size_t)sw * sh * bpp);
    assert_non_null(f);
    for (size_t i = 0; i < (size_t)sw * sh * bpp; i++)
        f[i] = (uint8_t)((i * 2654435761u + seed * 40503u) >> 13);
    return f;
}

/* upscale_smooth of src (a frame at scale s, quarter steps) to w x h, in a fresh buffer */
static uint8_t *smooth(const uint8_t *src, uint32_t w, uint32_t h, uint32_t s)
{
    uint8_t *dst = malloc((size_t)w * h * 3);
    uint16_t *scratch = malloc(upscale_scratch(w, h, s) * sizeof *scratch);
    assert_non_null(dst);
    assert_non_null(scratch);
    upscale_smooth(src, dst, w, h, s, scratch);
    free(scratch);
    return dst;
}

/* A side of n full pixels at scale s: ceil(n / k), k = s / UPSCALE_ONE. */
static uint32_t side(uint32_t n, uint32_t s) { return (uint32_t)ceil(n / ((double)s / UPSCALE_ONE) - 1e-9); }

/* Where full pixel t's centre lies among the frame pixels' (0: the first
 * one's centre) on an axis of N full and n frame pixels, the frame sw
 * pixels across W full ones: a frame pixel is sw / W full ones wide (the
 * camera spans the width with whatever pixels it has) and the lines are
 * centred, worked here in floating point from that geometry. */
static double place_of(uint32_t t, uint32_t N, uint32_t n, uint32_t sw, uint32_t W)
{
    const double size = (double)W / sw, off = (N - n * size) / 2; /* a frame pixel in full ones; the first's edge */
    return (t + 0.5 - off) / size - 0.5;
}

/* Each full pixel is the frame pixel whose centre is nearest its own. */
static void blocks_copy_each_pixel(void **state)
{
    (void)state;
    for (uint32_t bpp = 3; bpp <= 4; bpp++)
        for (uint32_t s = UPSCALE_ONE + 1; s <= UPSCALE_MAX; s++) {
            const uint32_t w = 13, h = 7, sw = side(w, s), sh = side(h, s);
            assert_int_equal(sw, upscale_side(w, s));
            assert_int_equal(sh, upscale_side(h, s));
            uint8_t *src = frame_of(sw, sh, bpp, s), *dst = malloc((size_t)w * h * bpp);
            assert_non_null(dst);
            upscale_blocks(src, dst, w, h, bpp, s);
            for (uint32_t y = 0; y < h; y++)
                for (uint32_t x = 0; x < w; x++) {
                    const double u = floor(place_of(x, w, sw, sw, w) + 0.5), v = floor(place_of(y, h, sh, sw, w) + 0.5);
                    const size_t i = u < 0 ? 0 : u > sw - 1 ? sw - 1 : (size_t)u;
                    const size_t j = v < 0 ? 0 : v > sh - 1 ? sh - 1 : (size_t)v;
                    assert_memory_equal(dst + ((size_t)y * w + x) * bpp, src + (j * sw + i) * bpp, bpp);
                }
            free(src), free(dst);
        }
}

/* The frame pixels about full pixel (x, y) and the right and lower ones'
 * weights in 1/128: the place rounded to the nearest 1/128 (halves up),
 * its floor and remainder, clamped at the edges. */
typedef struct {
    int i0, i1, j0, j1, r, q, k2;
} Taps;

static Taps taps_of(uint32_t x, uint32_t y, uint32_t w, uint32_t h, uint32_t sw, uint32_t sh)
{
    const double u = floor(place_of(x, w, sw, sw, w) * 128 + 0.5), v = floor(place_of(y, h, sh, sw, w) * 128 + 0.5);
    const int i = (int)floor(u / 128), j = (int)floor(v / 128);
    return (Taps){i < 0 ? 0 : i, i + 1 >= (int)sw ? (int)sw - 1 : i + 1, j < 0 ? 0 : j,
                  j + 1 >= (int)sh ? (int)sh - 1 : j + 1, (int)u - i * 128, (int)v - j * 128, 128};
}

/* A frame whose sides k divides is k x k blocks from the corner: full
 * pixel t at (t + 1/2) / k - 1/2 (1.5: 12 x 9 for 18 x 13.5 ... a side of
 * 3 x 6 = 18 full pixels). */
static void whole_blocks_where_k_divides(void **state)
{
    (void)state;
    for (uint32_t s = UPSCALE_ONE + 1; s <= UPSCALE_MAX; s++) {
        const uint32_t sw = 12, sh = 8, w = sw * s / UPSCALE_ONE, h = sh * s / UPSCALE_ONE;
        if (sw * s % UPSCALE_ONE || sh * s % UPSCALE_ONE)
            continue;
        for (uint32_t t = 0; t < w; t++)
            assert_true(fabs(place_of(t, w, sw, sw, w) - ((t + 0.5) / ((double)s / UPSCALE_ONE) - 0.5)) < 1e-12);
        for (uint32_t t = 0; t < h; t++)
            assert_true(fabs(place_of(t, h, sh, sw, w) - ((t + 0.5) / ((double)s / UPSCALE_ONE) - 0.5)) < 1e-12);
    }
}

/* Every byte the exact rounded mix, (sum of weights x pixels + sum / 2) /
 * sum in integers, on sizes whose lines end in the vector loop's tail. */
static void smooth_is_the_rounded_mix(void **state)
{
    (void)state;
    for (uint32_t s = UPSCALE_ONE + 1; s <= UPSCALE_MAX; s++) {
        const uint32_t w = 41 + s, h = 17, sw = side(w, s), sh = side(h, s);
        uint8_t *src = frame_of(sw, sh, 3, 7 * s), *dst = smooth(src, w, h, s);
        for (uint32_t y = 0; y < h; y++)
            for (uint32_t x = 0; x < w; x++) {
                const Taps t = taps_of(x, y, w, h, sw, sh);
                const int r = t.r, q = t.q, i0 = t.i0, i1 = t.i1, j0 = t.j0, j1 = t.j1, k2 = t.k2;
                for (int c = 0; c < 3; c++) {
#define PX(a, b) (int)src[3 * ((size_t)(b) * sw + (size_t)(a)) + (size_t)c]
                    const int top = (k2 - r) * PX(i0, j0) + r * PX(i1, j0);
                    const int bottom = (k2 - r) * PX(i0, j1) + r * PX(i1, j1);
#undef PX
                    const int sum = k2 * k2, want = ((k2 - q) * top + q * bottom + sum / 2) / sum;
                    assert_int_equal(dst[3 * ((size_t)y * w + x) + (size_t)c], want);
                }
            }
        free(src), free(dst);
    }
}

static void smooth_keeps_a_flat_frame(void **state)
{
    (void)state;
    for (uint32_t s = UPSCALE_ONE + 1; s <= UPSCALE_MAX; s++) {
        const uint32_t w = 21, h = 11, sw = side(w, s), sh = side(h, s);
        uint8_t *src = malloc((size_t)sw * sh * 3);
        assert_non_null(src);
        for (size_t i = 0; i < (size_t)sw * sh; i++)
            src[3 * i] = 255, src[3 * i + 1] = 7, src[3 * i + 2] = 128;
        uint8_t *dst = smooth(src, w, h, s);
        for (size_t i = 0; i < (size_t)w * h; i++) {
            assert_int_equal(dst[3 * i], 255);
            assert_int_equal(dst[3 * i + 1], 7);
            assert_int_equal(dst[3 * i + 2], 128);
        }
        free(src), free(dst);
    }
}

/* A ramp across (or down) the frame: each full pixel is the ramp at its
 * centre's place among the frame's centres (place_of), held at the ends,
 * within the rounding to a byte and the place's to 1/128 (a step of 18
 * a frame pixel at most). */
static void smooth_follows_a_ramp(void **state)
{
    (void)state;
    for (int down = 0; down <= 1; down++)
        for (uint32_t s = UPSCALE_ONE + 1; s <= UPSCALE_MAX; s++) {
            const uint32_t w = down ? 5 : 2 * s + 3, h = down ? 2 * s + 3 : 5;
            const uint32_t sw = side(w, s), sh = side(h, s), n = down ? sh : sw;
            uint8_t *src = malloc((size_t)sw * sh * 3);
            assert_non_null(src);
            for (uint32_t j = 0; j < sh; j++)
                for (uint32_t i = 0; i < sw; i++)
                    for (int c = 0; c < 3; c++)
                        src[3 * ((size_t)j * sw + i) + c] = (uint8_t)(10 + (c + 1) * 6 * (down ? j : i));
            uint8_t *dst = smooth(src, w, h, s);
            for (uint32_t y = 0; y < h; y++)
                for (uint32_t x = 0; x < w; x++) {
                    double u = down ? place_of(y, h, sh, sw, w) : place_of(x, w, sw, sw, w);
                    u = u < 0 ? 0 : u > n - 1 ? n - 1 : u;
                    for (int c = 0; c < 3; c++) {
                        const double want = 10 + (c + 1) * 6 * u;
                        assert_true(fabs(dst[3 * ((size_t)y * w + x) + c] - want) <= 0.5 + 18.0 / 256 + 1e-9);
                    }
                }
            free(src), free(dst);
        }
}

static void smooth_stays_within_its_taps(void **state)
{
    (void)state;
    for (uint32_t s = UPSCALE_ONE + 1; s <= UPSCALE_MAX; s++) {
        const uint32_t w = 37, h = 29, sw = side(w, s), sh = side(h, s);
        uint8_t *src = frame_of(sw, sh, 3, s), *dst = smooth(src, w, h, s);
        for (uint32_t y = 0; y < h; y++)
            for (uint32_t x = 0; x < w; x++) {
                /* the frame pixels whose centres surround this one's */
                const double u = place_of(x, w, sw, sw, w), v = place_of(y, h, sh, sw, w);
                int i0 = (int)floor(u), j0 = (int)floor(v);
                for (int c = 0; c < 3; c++) {
                    int lo = 255, hi = 0;
                    for (int j = j0; j <= j0 + 1; j++)
                        for (int i = i0; i <= i0 + 1; i++) {
                            const int ci = i < 0 ? 0 : i >= (int)sw ? (int)sw - 1 : i;
                            const int cj = j < 0 ? 0 : j >= (int)sh ? (int)sh - 1 : j;
                            const int p = src[3 * ((size_t)cj * sw + (size_t)ci) + (size_t)c];
                            lo = p < lo ? p : lo, hi = p > hi ? p : hi;
                        }
                    const int got = dst[3 * ((size_t)y * w + x) + (size_t)c];
                    assert_true(got >= lo && got <= hi);
                }
            }
        free(src), free(dst);
    }
}

/* A frame mirrored both ways comes out mirrored, at w x h full pixels
 * from a frame at scale s. */
static void mirrors(uint32_t w, uint32_t h, uint32_t s)
{
    const uint32_t sw = upscale_side(w, s), sh = upscale_side(h, s);
    uint8_t *src = frame_of(sw, sh, 3, 3 * s), *mir = malloc((size_t)sw * sh * 3);
    assert_non_null(mir);
    for (uint32_t j = 0; j < sh; j++)
        for (uint32_t i = 0; i < sw; i++)
            memcpy(mir + 3 * ((size_t)(sh - 1 - j) * sw + (sw - 1 - i)), src + 3 * ((size_t)j * sw + i), 3);
    uint8_t *a = smooth(src, w, h, s), *b = smooth(mir, w, h, s);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++)
            assert_memory_equal(a + 3 * ((size_t)y * w + x), b + 3 * ((size_t)(h - 1 - y) * w + (w - 1 - x)), 3);
    free(src), free(mir), free(a), free(b);
}

/* On sides that k divides (k x 10, k x 6) and sides it does not (41 x
 * 23: the frame's lines centred, not k x k blocks from the corner, which
 * would not mirror). */
static void smooth_mirrors_a_mirrored_frame(void **state)
{
    (void)state;
    for (uint32_t s = UPSCALE_ONE + 1; s <= UPSCALE_MAX; s++) {
        mirrors(5 * s, 3 * s, s);
        mirrors(41, 23, s);
    }
}

/* RGBE (--hdr): a frame of random light over four decades, brought up
 * smooth: each pixel the decoded four mixed in double with the same
 * weights and coded again (byte for byte); a flat frame stays the same
 * bytes; and each pixel's light lies within its four's, but for the code's
 * own step (1/256 of the largest channel). */
static void smooth_rgbe_mixes_the_light(void **state)
{
    (void)state;
    for (uint32_t s = UPSCALE_ONE + 1; s <= UPSCALE_MAX; s++) {
        const uint32_t w = 23 + s, h = 19, sw = side(w, s), sh = side(h, s);
        uint8_t *src = malloc((size_t)sw * sh * 4), *dst = malloc((size_t)w * h * 4);
        double *scratch = malloc(upscale_scratch_rgbe(w, h, s) * sizeof *scratch);
        assert_true(src && dst && scratch);
        for (size_t i = 0; i < (size_t)sw * sh; i++) {
            const double l = pow(10.0, (double)((i * 7919u) % 400) / 100.0 - 2.0); /* 0.01 .. 100 */
            rgbe_encode((real)(l * 0.9), (real)(l * (double)(i % 5) / 4.0), (real)(l * 0.3), src + 4 * i);
        }
        upscale_smooth_rgbe(src, dst, w, h, s, scratch);
        for (uint32_t y = 0; y < h; y++)
            for (uint32_t x = 0; x < w; x++) {
                const Taps t = taps_of(x, y, w, h, sw, sh);
                const int r = t.r, q = t.q, i0 = t.i0, i1 = t.i1, j0 = t.j0, j1 = t.j1, k2 = t.k2;
                double c00[3], c10[3], c01[3], c11[3], mix[3], got[3];
                rgbe_decode(src + 4 * ((size_t)j0 * sw + (size_t)i0), c00);
                rgbe_decode(src + 4 * ((size_t)j0 * sw + (size_t)i1), c10);
                rgbe_decode(src + 4 * ((size_t)j1 * sw + (size_t)i0), c01);
                rgbe_decode(src + 4 * ((size_t)j1 * sw + (size_t)i1), c11);
                const double w00 = (double)((k2 - r) * (k2 - q)), w10 = (double)(r * (k2 - q));
                const double w01 = (double)((k2 - r) * q), w11 = (double)(r * q), sum = (double)(k2 * k2);
                double top = 0;
                for (int c = 0; c < 3; c++) {
                    mix[c] = (w00 * c00[c] + w10 * c10[c] + w01 * c01[c] + w11 * c11[c]) / sum;
                    top = mix[c] > top ? mix[c] : top;
                }
                uint8_t want[4];
                rgbe_encode((real)mix[0], (real)mix[1], (real)mix[2], want);
                const uint8_t *at = dst + 4 * ((size_t)y * w + x);
                assert_memory_equal(at, want, 4);
                rgbe_decode(at, got);
                for (int c = 0; c < 3; c++) {
                    double lo = c00[c], hi = c00[c];
                    const double o[3] = {c10[c], c01[c], c11[c]};
                    for (int n = 0; n < 3; n++)
                        lo = o[n] < lo ? o[n] : lo, hi = o[n] > hi ? o[n] : hi;
                    assert_true(got[c] >= lo - top / 128 && got[c] <= hi + top / 128);
                }
            }
        /* flat: the same bytes everywhere */
        for (size_t i = 0; i < (size_t)sw * sh; i++)
            rgbe_encode(R(0.7), R(0.2), R(0.05), src + 4 * i);
        upscale_smooth_rgbe(src, dst, w, h, s, scratch);
        for (size_t i = 0; i < (size_t)w * h; i++)
            assert_memory_equal(dst + 4 * i, src, 4);
        free(src), free(dst), free(scratch);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(blocks_copy_each_pixel),
        cmocka_unit_test(whole_blocks_where_k_divides),
        cmocka_unit_test(smooth_is_the_rounded_mix),
        cmocka_unit_test(smooth_keeps_a_flat_frame),
        cmocka_unit_test(smooth_follows_a_ramp),
        cmocka_unit_test(smooth_stays_within_its_taps),
        cmocka_unit_test(smooth_mirrors_a_mirrored_frame),
        cmocka_unit_test(smooth_rgbe_mixes_the_light),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
