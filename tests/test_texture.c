/* test_texture.c - PPM/PGM loading through libnetpbm and texture filtering. */
#include "helpers.h"

#include <math.h>

#include "model/texture.h"

static const char *write_bytes(const char *name, const void *data, size_t len)
{
    static char path[256];
    snprintf(path, sizeof path, "%s/%s", test_tmpdir(), name);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fwrite(data, 1, len, f);
    fclose(f);
    return path;
}

static void reads_ppm_and_pgm(void **state)
{
    (void)state;
    /* binary P6, 2x1: red, blue */
    const unsigned char p6[] = "P6\n2 1\n255\n\xff\x00\x00\x00\x00\xff";
    Texture *t;
    Err err;
    if (texture_read(write_bytes("a.ppm", p6, sizeof p6 - 1), &t, &err))
        fail_msg("%s", err.msg);
    assert_int_equal(t->w, 2);
    assert_int_equal(t->h, 1);
    assert_float_equal(t->rgb[0], 1, 0);
    assert_float_equal(t->rgb[5], 1, 0);
    texture_destroy(t);
    /* plain P3 with maxval 4 */
    const char p3[] = "P3\n# comment\n1 2\n4\n4 2 0\n0 0 4\n";
    if (texture_read(write_bytes("b.ppm", p3, strlen(p3)), &t, &err))
        fail_msg("%s", err.msg);
    assert_int_equal(t->h, 2);
    /* stored sRGB-encoded, read as linear light: 2 of 4 is the decoding of 0.5 */
    assert_float_equal(t->rgb[1], pow((0.5 + 0.055) / 1.055, 2.4), R(1e-6));
    texture_destroy(t);
    /* grey PGM becomes grey RGB */
    const unsigned char p5[] = "P5\n1 1\n255\n\x80";
    if (texture_read(write_bytes("c.pgm", p5, sizeof p5 - 1), &t, &err))
        fail_msg("%s", err.msg);
    assert_float_equal(t->rgb[0], t->rgb[2], 0);
    assert_float_equal(t->rgb[0], pow((128.0 / 255 + 0.055) / 1.055, 2.4), R(1e-6));
    texture_destroy(t);
}

static void expect_error(const char *name, const void *data, size_t len, const char *what)
{
    Texture *t = NULL;
    Err err = {{0}};
    assert_int_equal(texture_read(write_bytes(name, data, len), &t, &err), -1);
    assert_null(t);
    assert_contains(err.msg, name);
    assert_contains(err.msg, what);
}

static void rejects_bad_images(void **state)
{
    (void)state;
    expect_error("magic.ppm", "GIF89a", 6, "not a valid PPM/PGM image");
    expect_error("empty.ppm", "", 0, "not a valid PPM/PGM image");
    const char trunc[] = "P6\n4 4\n255\n\x01\x02\x03";
    expect_error("trunc.ppm", trunc, sizeof trunc - 1, "the header promises 4x4 pixels but only 3 bytes follow");
    /* a tiny file claiming a huge image is refused before any pixel memory is allocated (found by fuzzing) */
    const char claim[] = "P4 14060 14060 3\xc3";
    expect_error("claim.pbm", claim, sizeof claim - 1, "the header promises 14060x14060 pixels");
    /* PAM (P7) is not a texture format here */
    const char pam[] = "P7\nWIDTH 1\nHEIGHT 1\nDEPTH 3\nMAXVAL 255\nTUPLTYPE RGB\nENDHDR\n\x01\x02\x03";
    expect_error("img.pam", pam, sizeof pam - 1, "does not start with P1..P6");
    const char huge[] = "P6\n100000 100000\n255\n";
    expect_error("huge.ppm", huge, sizeof huge - 1, "textures must be 1..16384 pixels");
    const char bitmap[] = "P1\n1 1\n1\n";
    /* a PBM has one channel: accepted as grey, so check it loads rather than failing */
    Texture *t;
    assert_int_equal(texture_read(write_bytes("bit.pbm", bitmap, sizeof bitmap - 1), &t, NULL), 0);
    texture_destroy(t);
    Err err = {{0}};
    assert_int_equal(texture_read("/nonexistent/t.ppm", &t, &err), -1);
    assert_contains(err.msg, "cannot open");
}

/* The byte form an ASSET carries (and whose texels a .tmd carries): a
 * texture comes back exactly; a wrong size, a texel out of [0, 1] or NaN
 * is refused with the name and nothing is returned. */
static void byte_form_round_trips_and_refuses_bad_texels(void **state)
{
    (void)state;
    const uint8_t px[2 * 2 * 3] = {0, 64, 128, 255, 1, 2, 3, 4, 5, 250, 251, 252};
    Texture *t = texture_from_rgb8(2, 2, px), *back;
    Sink s = {0};
    assert_int_equal(texture_encode(t, &s), 0);
    assert_int_equal(s.len, 8 + 12 * sizeof(float));
    Err err = {{0}};
    assert_int_equal(texture_decode(s.data, s.len, "asset", &back, &err), 0);
    assert_int_equal(back->w, 2);
    assert_int_equal(back->h, 2);
    assert_memory_equal(back->rgb, t->rgb, 12 * sizeof(float));
    texture_destroy(back);
    assert_int_equal(texture_decode(s.data, s.len - 1, "asset", &back, &err), -1);
    assert_null(back);
    assert_non_null(strstr(err.msg, "asset: texture payload of 55 bytes is malformed"));
    const float bad[] = {NAN, 1.5f, -0.25f};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        memcpy(s.data + 8 + 5 * sizeof(float), &bad[i], sizeof(float));
        assert_int_equal(texture_decode(s.data, s.len, "asset", &back, &err), -1);
        assert_null(back);
        assert_non_null(strstr(err.msg, "asset: a texel value out of range"));
    }
    uint32_t big = TEXTURE_MAX_SIDE + 1;
    memcpy(s.data, &big, 4);
    assert_int_equal(texture_decode(s.data, s.len, "asset", &back, &err), -1);
    sink_free(&s);
    texture_destroy(t);
}

static void nearest_and_bilinear_sampling(void **state)
{
    (void)state;
    /* 2x2: top row black, white; bottom row red, green (v = 0 is the bottom) */
    const uint8_t px[12] = {0, 0, 0, 255, 255, 255, 255, 0, 0, 0, 255, 0};
    Texture *t = texture_from_rgb8(2, 2, px);
    assert_non_null(t);
    vec3 c = texture_sample(t, R(0.25), R(0.25), FILTER_NEAREST); /* bottom-left texel */
    assert_float_equal(c.x, 1, 0);
    assert_float_equal(c.y, 0, 0);
    c = texture_sample(t, R(0.75), R(0.75), FILTER_NEAREST); /* top-right */
    assert_float_equal(c.z, 1, 0);
    /* at a texel centre bilinear equals nearest */
    c = texture_sample(t, R(0.25), R(0.25), FILTER_BILINEAR);
    assert_float_equal(c.x, 1, R(1e-6));
    /* half way between the two bottom texels: mean of red and green */
    c = texture_sample(t, R(0.5), R(0.25), FILTER_BILINEAR);
    assert_float_equal(c.x, R(0.5), R(1e-6));
    assert_float_equal(c.y, R(0.5), R(1e-6));
    /* wrapping: u = 1.25 is u = 0.25; and the corner blends all four texels */
    vec3 a = texture_sample(t, R(1.25), R(-0.75), FILTER_NEAREST), b = texture_sample(t, R(0.25), R(0.25), FILTER_NEAREST);
    assert_memory_equal(&a, &b, sizeof a);
    c = texture_sample(t, 0, 0, FILTER_BILINEAR);
    assert_float_equal(c.x, R(0.5), R(1e-6)); /* (0 + 1 + 1 + 0) / 4 */
    assert_float_equal(c.y, R(0.5), R(1e-6));
    /* non-finite coordinates do not crash */
    c = texture_sample(t, NAN, INFINITY, FILTER_BILINEAR);
    assert_true(isfinite(c.x));
    texture_destroy(t);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(reads_ppm_and_pgm),
        cmocka_unit_test(rejects_bad_images),
        cmocka_unit_test(byte_form_round_trips_and_refuses_bad_texels),
        cmocka_unit_test(nearest_and_bilinear_sampling),
    };
    return cmocka_run_group_tests_name("texture", tests, NULL, NULL);
}
