/* test_srgb.c - the sRGB tables against the standard's formulas
 * (IEC 61966-2-1), computed here in double precision. */
#include "helpers.h"

#include <math.h>

#include "base/srgb.h"

static double encode_formula(double v) { return v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1 / 2.4) - 0.055; }
static double decode_formula(double s) { return s <= 0.04045 ? s / 12.92 : pow((s + 0.055) / 1.055, 2.4); }

/* Every linear value gets the code nearest its sRGB value: checked on a
 * million values spread over 0..1 (dense in the dark end, where the curve
 * is steep) and on values just either side of each threshold. */
static void encoding_rounds_to_the_nearest_code(void **state)
{
    (void)state;
    Rng rng = {3};
    for (int i = 0; i < 1000000; i++) {
        double v = rng_real(&rng, 0, 1);
        v = i % 2 ? v * v * v : v;
        real r = (real)v;
        double exact = encode_formula((double)r) * 255;
        if (fabs(exact - floor(exact) - 0.5) < 1e-6) /* a tie to the last bits: either code is right */
            continue;
        assert_int_equal(srgb_encode8(r), (int)floor(exact + 0.5));
    }
    for (int k = 1; k < 256; k++) {
        real t = (real)srgb_threshold[k - 1];
        assert_int_equal(srgb_encode8(nextafter(t, R(0))), k - 1 + ((double)nextafter(t, R(0)) >= srgb_threshold[k - 1]));
        assert_int_equal(srgb_encode8(nextafter(t, R(2))), k);
        assert_float_equal(srgb_threshold[k - 1], decode_formula((k - 0.5) / 255), 1e-12);
    }
    /* out of range and not a number */
    assert_int_equal(srgb_encode8(R(-1)), 0);
    assert_int_equal(srgb_encode8(R(7)), 255);
    assert_int_equal(srgb_encode8(REAL_INF), 255);
    assert_int_equal(srgb_encode8((real)NAN), 0);
    assert_int_equal(srgb_encode8(R(0.5)), 188); /* the mid-grey every viewer shows as 188 */
    assert_int_equal(linear_encode8(R(0.5)), 128);
}

/* The code of v by the thresholds alone: the count of thresholds at or
 * below it (a binary search), what srgb_encode8 must give. */
static int code_by_search(double v)
{
    int lo = 0, hi = 255; /* the answer is in [lo, hi] */
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (v >= srgb_threshold[mid])
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* The table's guess and the two steps after it give the exact code for
 * every float from the first threshold to the last (all 109 million), and
 * for the doubles between floats where a guess could fall furthest short:
 * just below each bucket's first float, and just below each threshold. */
static void encoding_matches_the_thresholds_everywhere(void **state)
{
    (void)state;
    float f = (float)srgb_threshold[0];
    uint32_t bits, last;
    memcpy(&bits, &f, sizeof bits);
    f = (float)srgb_threshold[254];
    memcpy(&last, &f, sizeof last);
    uint64_t checked = 0;
    /* every float between the first and last threshold; every 7th under a
     * sanitizer (each bucket of 0x8000 floats still seen, 10 s of ASan's pass) */
    const uint32_t stride = TEST_SANITIZED ? 7 : 1;
    for (uint32_t b = bits - 1; b <= last + 1; b += stride) {
        float x;
        memcpy(&x, &b, sizeof x);
        if (srgb_encode8((real)x) != code_by_search((double)x))
            fail_msg("%.9g: code %d, thresholds say %d", (double)x, srgb_encode8((real)x), code_by_search((double)x));
        checked++;
    }
    assert_true(checked > 100000000 / stride);
    for (uint32_t b = bits & ~0x7fffu; b <= last; b += 0x8000u) { /* each bucket's first float */
        float x;
        memcpy(&x, &b, sizeof x);
        double below = nextafter((double)x, 0.0);
        if ((double)(real)below == below) /* a double build: the value between two floats */
            assert_int_equal(srgb_encode8((real)below), code_by_search(below));
    }
    for (int k = 0; k < 255; k++) {
        double t = srgb_threshold[k], below = nextafter(t, 0.0);
        if ((double)(real)below == below)
            assert_int_equal(srgb_encode8((real)below), code_by_search(below));
        if ((double)(real)t == t)
            assert_int_equal(srgb_encode8((real)t), code_by_search(t));
    }
}

/* Decoding a code and encoding it again gives the code back: a texture
 * drawn at full light comes out as stored. */
static void decoding_is_exact_and_round_trips(void **state)
{
    (void)state;
    for (int k = 0; k < 256; k++) {
        assert_float_equal(srgb_decode8[k], decode_formula(k / 255.0), 1e-7);
        assert_int_equal(srgb_encode8((real)srgb_decode8[k]), k);
        assert_float_equal(srgb_decode(k / 255.0), decode_formula(k / 255.0), 1e-15);
    }
    assert_float_equal(srgb_decode(-1), 0, 0);
    assert_float_equal(srgb_decode(2), 1, 0);
}

/* An RGBE pixel read back (rgbe_decode, as a window or viewer reads a
 * .hdr) and written again gives the same four bytes, for every normalised
 * pixel (largest mantissa 128..255) across the exponents; the window's
 * codes are sRGB of the light times the gain. */
static void rgbe_round_trips(void **state)
{
    (void)state;
    int kept = 0;
    for (int e = 1; e < 256; e += 3)
        for (int m = 128; m < 256; m += 5) {
            const uint8_t in[4] = {(uint8_t)m, (uint8_t)(m / 3), (uint8_t)(m * 7 % 256 < m ? m * 7 % 256 : m / 2), (uint8_t)e};
            double c[3];
            rgbe_decode(in, c);
            uint8_t out[4];
            rgbe_encode((real)c[0], (real)c[1], (real)c[2], out);
            if (c[0] < 1e-32) /* rgbe_encode writes black below 1e-32 */
                continue;
            assert_memory_equal(in, out, 4);
            kept++;
        }
    assert_true(kept > 60 * 26); /* exponents from 2^-106 up: most of them */
    const uint8_t black[4] = {200, 100, 50, 0};
    double c[3];
    rgbe_decode(black, c);
    assert_true(c[0] == 0 && c[1] == 0 && c[2] == 0);
    const uint8_t px[8] = {128, 64, 0, 128, 255, 255, 255, 129}; /* 0.50195 0.252 0.00195; 1.99 (clamps) */
    uint8_t rgb[6];
    srgb_from_rgbe(px, 2, 1.0, rgb);
    double l[3];
    rgbe_decode(px, l);
    for (int k = 0; k < 3; k++)
        assert_int_equal(rgb[k], srgb_encode8((real)l[k]));
    assert_true(rgb[3] == 255 && rgb[4] == 255 && rgb[5] == 255);
    srgb_from_rgbe(px, 1, 0.25, rgb); /* two stops down */
    for (int k = 0; k < 3; k++)
        assert_int_equal(rgb[k], srgb_encode8((real)(l[k] * 0.25)));
    assert_true(rgb[0] < 128);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(encoding_rounds_to_the_nearest_code),
        cmocka_unit_test(encoding_matches_the_thresholds_everywhere),
        cmocka_unit_test(decoding_is_exact_and_round_trips),
        cmocka_unit_test(rgbe_round_trips),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
