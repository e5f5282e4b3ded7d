/* test_pixcodec.c - DATA's pixel codings (common/net/pixcodec.c): every
 * coding gives back the bytes it was given, for RGB8 and RGBE, and for
 * both with each pixel's denoising guide after them (14 and 15 bytes a
 * pixel: the predictor's byte-by-byte path); what does
 * not shrink goes raw; and the decoder writes exactly the segment's bytes
 * or refuses (a coded size as large as the raw one, a zstd frame that says
 * another size, data cut short or flipped, an unknown coding), never a
 * byte past the segment. */
#include "helpers.h"

#include "net/pixcodec.h"
#include "render/denoise.h"

enum { PIXELS = 2048, GUARD = 64 };

static const uint32_t codings[] = {PIX_ZSTD, PIX_LZ4, PIX_ZSTD | PIX_PREDICT, PIX_LZ4 | PIX_PREDICT};

/* A line of a rendered-looking frame: smooth gradients, a few edges, a bit of
 * noise (in one pixel of four: LZ4 at the acceleration clients use finds
 * no matches in noise at every pixel, and sends such a line raw). */
static void picture(uint8_t *px, size_t n, uint32_t bpp, uint64_t seed)
{
    Rng r = {seed};
    for (size_t i = 0; i < n / bpp; i++)
        for (uint32_t k = 0; k < bpp; k++) {
            unsigned v = (unsigned)(i / 7 + 40 * k + (i % 300 < 40 ? 90 : 0) + (i % 4 ? 0 : rng_next(&r) % 3));
            px[i * bpp + k] = (uint8_t)(bpp == 4 && k == 3 ? 128 + (i / 500) : v);
        }
}

static void every_coding_round_trips(void **state)
{
    (void)state;
    PixCodec *c = pixcodec_create();
    assert_non_null(c);
    static const uint32_t sizes[] = {3, 4, 3 + DENOISE_GUIDE_BYTES, 4 + DENOISE_GUIDE_BYTES};
    for (size_t b = 0; b < sizeof sizes / sizeof *sizes; b++) {
        const uint32_t bpp = sizes[b];
        const size_t n = PIXELS * bpp;
        uint8_t *px = malloc(n), *out = malloc(pixcodec_bound(n)), *back = malloc(n + GUARD);
        picture(px, n, bpp, 7);
        for (size_t k = 0; k < sizeof codings / sizeof *codings; k++) {
            size_t len;
            Err err;
            int used = pixcodec_encode(c, codings[k], px, n, bpp, out, &len, &err);
            assert_int_equal(used, (int)codings[k]); /* a picture shrinks */
            assert_true(len < n);
            memset(back, 0xa5, n + GUARD);
            assert_int_equal(pixcodec_decode(c, (uint32_t)used, out, len, back, n, bpp, &err), 0);
            assert_memory_equal(back, px, n);
            for (size_t g = 0; g < GUARD; g++)
                assert_int_equal(back[n + g], 0xa5);
        }
        /* the predictor pays on a rendered line with zstd */
        size_t plain, predicted;
        Err err;
        pixcodec_encode(c, PIX_ZSTD, px, n, bpp, out, &plain, &err);
        pixcodec_encode(c, PIX_ZSTD | PIX_PREDICT, px, n, bpp, out, &predicted, &err);
        assert_true(predicted < plain);
        free(px), free(out), free(back);
    }
    pixcodec_destroy(c);
}

static void noise_goes_raw(void **state)
{
    (void)state;
    PixCodec *c = pixcodec_create();
    const size_t n = PIXELS * 3;
    uint8_t *px = malloc(n), *out = malloc(pixcodec_bound(n)), *back = malloc(n);
    Rng r = {99};
    for (size_t i = 0; i < n; i++)
        px[i] = (uint8_t)rng_next(&r);
    for (size_t k = 0; k < sizeof codings / sizeof *codings; k++) {
        size_t len;
        Err err;
        assert_int_equal(pixcodec_encode(c, codings[k], px, n, 3, out, &len, &err), PIX_RAW);
        assert_int_equal(len, n);
        assert_int_equal(pixcodec_decode(c, PIX_RAW, out, len, back, n, 3, &err), 0);
        assert_memory_equal(back, px, n);
    }
    free(px), free(out), free(back);
    pixcodec_destroy(c);
}

/* An empty segment (what a hostile server's WORK can ask for) encodes as
 * no bytes, raw, in every coding, from a fresh codec that has no scratch
 * to predict into (the client fuzzer found predict's memcpy into NULL). */
static void an_empty_segment_is_no_bytes(void **state)
{
    (void)state;
    for (size_t k = 0; k < sizeof codings / sizeof *codings; k++) {
        PixCodec *c = pixcodec_create();
        uint8_t px[4] = {1, 2, 3, 4}, out[64], back[4] = {9, 9, 9, 9};
        size_t len = 99;
        Err err;
        assert_int_equal(pixcodec_encode(c, codings[k], px, 0, 3, out, &len, &err), PIX_RAW);
        assert_int_equal(len, 0);
        assert_int_equal(pixcodec_decode(c, PIX_RAW, out, 0, back, 0, 3, &err), 0);
        assert_int_equal(back[0], 9);
        pixcodec_destroy(c);
    }
}

/* decode must fail with a message holding `what`, and leave the guard after the segment alone */
static void refused(PixCodec *c, uint32_t coding, const uint8_t *in, size_t len, size_t n, const char *what)
{
    uint8_t *back = malloc(n + GUARD);
    memset(back, 0xa5, n + GUARD);
    Err err = {{0}};
    assert_int_equal(pixcodec_decode(c, coding, in, len, back, n, 3, &err), -1);
    if (!strstr(err.msg, what))
        fail_msg("expected '%s' in '%s'", what, err.msg);
    for (size_t g = 0; g < GUARD; g++)
        assert_int_equal(back[n + g], 0xa5);
    free(back);
}

static void bad_data_is_refused(void **state)
{
    (void)state;
    PixCodec *c = pixcodec_create();
    const size_t n = PIXELS * 3;
    uint8_t *px = malloc(n), *z = malloc(pixcodec_bound(n)), *l = malloc(pixcodec_bound(n));
    picture(px, n, 3, 3);
    size_t zl, ll;
    Err err;
    assert_int_equal(pixcodec_encode(c, PIX_ZSTD, px, n, 3, z, &zl, &err), PIX_ZSTD);
    assert_int_equal(pixcodec_encode(c, PIX_LZ4, px, n, 3, l, &ll, &err), PIX_LZ4);
    /* a segment's worth of pixels decoded for a smaller segment: more than it holds */
    refused(c, PIX_ZSTD, z, zl, n - 3, "a zstd frame of other bytes");
    refused(c, PIX_LZ4, l, ll, n - 3, "does not decode");
    /* for a larger one: short of it */
    refused(c, PIX_ZSTD, z, zl, n + 3, "a zstd frame of other bytes");
    refused(c, PIX_LZ4, l, ll, n + 3, "short of the segment");
    /* cut short, or with flipped bytes */
    refused(c, PIX_ZSTD, z, zl / 2, n, "zstd");
    refused(c, PIX_LZ4, l, ll / 2, n, "lz4");
    for (size_t i = 0; i < ll; i += 7)
        l[i] ^= 0x5a;
    uint8_t *back = malloc(n + GUARD);
    memset(back, 0xa5, n + GUARD);
    pixcodec_decode(c, PIX_LZ4, l, ll, back, n, 3, &err); /* may decode to garbage, never past n */
    for (size_t g = 0; g < GUARD; g++)
        assert_int_equal(back[n + g], 0xa5);
    /* a coded size not below the raw one, raw of the wrong size, unknown codings */
    refused(c, PIX_ZSTD, px, n, n, "a coded segment is smaller");
    refused(c, PIX_RAW, px, n - 1, n, "bytes for a segment of");
    refused(c, 7, z, zl, n, "unknown coding");
    refused(c, PIX_RAW | PIX_PREDICT, px, n, n, "unknown coding");
    refused(c, PIX_ZSTD | 0x10000, z, zl, n, "unknown coding");
    free(back), free(px), free(z), free(l);
    pixcodec_destroy(c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(every_coding_round_trips),
        cmocka_unit_test(noise_goes_raw),
        cmocka_unit_test(an_empty_segment_is_no_bytes),
        cmocka_unit_test(bad_data_is_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
