/* test_texture.c - texture images (by their bytes, not their names), the
 * byte form a .tmd and an ASSET carry, mip-maps, and filtering. */
#include "helpers.h"

#include <math.h>

#include "base/srgb.h"
#include "image/image.h"
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

static const uint8_t *texel(const Texture *t, uint32_t l, uint32_t x, uint32_t y)
{
    return &t->level[l].rgb[3 * ((size_t)y * t->level[l].w + x)];
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
    assert_int_equal(texel(t, 0, 0, 0)[0], 255);
    assert_int_equal(texel(t, 0, 1, 0)[2], 255);
    assert_float_equal(texture_texel(t, 0, 1, 0).z, 1, 0);
    assert_null(t->file); /* a PPM is not kept: its byte form is a PNG */
    texture_destroy(t);
    /* plain P3 with maxval 4: 2 of 4 is the nearest 8-bit code, 128 */
    const char p3[] = "P3\n# comment\n1 2\n4\n4 2 0\n0 0 4\n";
    if (texture_read(write_bytes("b.ppm", p3, strlen(p3)), &t, &err))
        fail_msg("%s", err.msg);
    assert_int_equal(t->h, 2);
    assert_int_equal(texel(t, 0, 0, 0)[1], 128);
    assert_float_equal(texture_texel(t, 0, 0, 0).y, srgb_decode8[128], 0);
    texture_destroy(t);
    /* grey PGM becomes grey RGB; the name does not decide the format */
    const unsigned char p5[] = "P5\n1 1\n255\n\x80";
    if (texture_read(write_bytes("c.png", p5, sizeof p5 - 1), &t, &err))
        fail_msg("%s", err.msg);
    assert_int_equal(texel(t, 0, 0, 0)[0], 128);
    assert_int_equal(texel(t, 0, 0, 0)[2], 128);
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
    expect_error("magic.ppm", "GIF89a", 6, "a GIF image: lanray reads PNG, JPEG, PPM, PGM, BMP, TGA and Radiance HDR");
    expect_error("empty.ppm", "", 0, "the file is empty");
    expect_error("noise.ppm", "\x01\x02\x03\x04", 4, "not an image lanray reads");
    /* a TGA has no magic: its name says what it is (test_rasters reads them) */
    expect_error("wood.tga", "\x00\x00\x02\x00\x00\x00\x00\x00\x00\x00\x00\x00\x01\x00\x01\x00\x18\x00\x10\x20", 20,
                 "cannot hold a 1x1 TGA image");
    expect_error("pic.bmp", "BM\x36\x00\x00\x00", 6, "not a BMP image, or one cut short");
    const char trunc[] = "P6\n4 4\n255\n\x01\x02\x03";
    expect_error("trunc.ppm", trunc, sizeof trunc - 1, "the header promises 4x4 pixels but only 3 bytes follow");
    /* a tiny file claiming a huge image is refused before any pixel memory is allocated (found by fuzzing) */
    const char claim[] = "P4 14060 14060 3\xc3";
    expect_error("claim.pbm", claim, sizeof claim - 1, "the header promises 14060x14060 pixels");
    /* PAM (P7) is not a texture format here */
    const char pam[] = "P7\nWIDTH 1\nHEIGHT 1\nDEPTH 3\nMAXVAL 255\nTUPLTYPE RGB\nENDHDR\n\x01\x02\x03";
    expect_error("img.pam", pam, sizeof pam - 1, "not an image lanray reads");
    const char huge[] = "P6\n100000 100000\n255\n";
    expect_error("huge.ppm", huge, sizeof huge - 1, "textures must be 1..16384 pixels");
    expect_error("bad.png", "\x89PNG\r\n\x1a\n\0\0\0\0", 12, "bad.png");
    const char bitmap[] = "P1\n1 1\n1\n";
    /* a PBM has one channel: accepted as grey, so check it loads rather than failing */
    Texture *t;
    assert_int_equal(texture_read(write_bytes("bit.pbm", bitmap, sizeof bitmap - 1), &t, NULL), 0);
    texture_destroy(t);
    Err err = {{0}};
    assert_int_equal(texture_read("/nonexistent/t.ppm", &t, &err), -1);
    assert_contains(err.msg, "/nonexistent/t.ppm");
}

/* The byte form: a PNG's or JPEG's own bytes come back as they were (a
 * .tmd is as small as the image); a texture without a file becomes a PNG
 * of its texels; either decodes to the same texels and mip-maps.  A size
 * that does not match the image, a cut, bad padding are refused by name. */
static void byte_form_keeps_the_image_file(void **state)
{
    (void)state;
    const uint8_t px[3 * 3 * 3] = {0, 64, 128, 255, 1, 2, 3, 4, 5, 250, 251, 252, 9, 8, 7, 6, 5, 4, 3, 2, 1, 0, 90, 80};
    Texture *t = texture_from_rgb8(3, 3, px), *back;
    t->closest = 1;
    Sink s = {0};
    assert_int_equal(texture_encode(t, &s), 0);
    assert_int_equal(s.len % 4, 0);
    uint32_t head[5];
    memcpy(head, s.data, sizeof head);
    assert_int_equal(head[0], 3);
    assert_int_equal(head[2], 2); /* closest */
    assert_int_equal(head[3], TEXTURE_PNG);
    Err err = {{0}};
    if (texture_decode(s.data, s.len, "asset", &back, &err))
        fail_msg("%s", err.msg);
    assert_int_equal(back->levels, t->levels);
    assert_int_equal(back->closest, 1);
    assert_memory_equal(back->texels, t->texels, texture_bytes(t));
    /* decoded, it keeps the PNG: encoding it again gives the same bytes */
    Sink again = {0};
    assert_int_equal(texture_encode(back, &again), 0);
    assert_int_equal(again.len, s.len);
    assert_memory_equal(again.data, s.data, s.len);
    sink_free(&again);
    texture_destroy(back);
    assert_int_equal(texture_decode(s.data, s.len - 4, "asset", &back, &err), -1);
    assert_null(back);
    assert_contains(err.msg, "cut short");
    uint32_t wrong = 4;
    memcpy(s.data, &wrong, 4);
    assert_int_equal(texture_decode(s.data, s.len, "asset", &back, &err), -1);
    assert_contains(err.msg, "the texture says 4x3 PNG, its image is 3x3");
    sink_free(&s);
    /* a PNG file's own bytes travel */
    Sink png = {0};
    assert_int_equal(image_encode_png(px, 3, 3, &png), 0);
    const char *path = write_bytes("t.png", png.data, png.len);
    assert_int_equal(texture_read(path, &back, &err), 0);
    assert_int_equal(back->codec, TEXTURE_PNG);
    assert_int_equal(back->file_len, png.len);
    Sink form = {0};
    assert_int_equal(texture_encode(back, &form), 0);
    assert_int_equal(form.len, 20 + (png.len + 3) / 4 * 4);
    assert_memory_equal(form.data + 20, png.data, png.len);
    sink_free(&form);
    sink_free(&png);
    texture_destroy(back);
    texture_destroy(t);
}

/* Mip-maps: each level the box-filtered level above in linear light, half
 * its size rounded down, down to 1 x 1, odd sides included. */
static void mip_maps_average_light(void **state)
{
    (void)state;
    uint8_t px[4 * 4 * 3];
    for (int i = 0; i < 16; i++)
        memset(&px[3 * i], ((i % 4) + (i / 4)) % 2 ? 255 : 0, 3);
    Texture *t = texture_from_rgb8(4, 4, px);
    assert_int_equal(t->levels, 3);
    assert_int_equal(t->level[1].w, 2);
    /* half white, half black: light 0.5, code 188 (not 128, the codes' mean) */
    for (uint32_t l = 1; l < 3; l++)
        assert_int_equal(texel(t, l, 0, 0)[0], srgb_encode8(R(0.5)));
    texture_destroy(t);
    /* 3 x 1: one level of 1 x 1, each texel counted by the area it covers */
    const uint8_t row[9] = {255, 255, 255, 0, 0, 0, 255, 255, 255};
    t = texture_from_rgb8(3, 1, row);
    assert_int_equal(t->levels, 2);
    assert_int_equal(texel(t, 1, 0, 0)[0], srgb_encode8(R(2.0) / R(3.0)));
    texture_destroy(t);
    /* 8 x 2: 4 x 1, 2 x 1, 1 x 1 */
    uint8_t wide[8 * 2 * 3] = {0};
    t = texture_from_rgb8(8, 2, wide);
    assert_int_equal(t->levels, 4);
    assert_int_equal(t->level[3].w, 1);
    assert_int_equal(t->level[3].h, 1);
    texture_destroy(t);
}

static void nearest_and_bilinear_sampling(void **state)
{
    (void)state;
    /* 2x2: top row black, white; bottom row red, green (v = 0 is the bottom) */
    const uint8_t px[12] = {0, 0, 0, 255, 255, 255, 255, 0, 0, 0, 255, 0};
    Texture *t = texture_from_rgb8(2, 2, px);
    assert_non_null(t);
    vec3 c = texture_sample(t, R(0.25), R(0.25), NULL, FILTER_NEAREST); /* bottom-left texel */
    assert_float_equal(c.x, 1, 0);
    assert_float_equal(c.y, 0, 0);
    c = texture_sample(t, R(0.75), R(0.75), NULL, FILTER_NEAREST); /* top-right */
    assert_float_equal(c.z, 1, 0);
    /* at a texel centre bilinear equals nearest */
    c = texture_sample(t, R(0.25), R(0.25), NULL, FILTER_BILINEAR);
    assert_float_equal(c.x, 1, R(1e-6));
    /* half way between the two bottom texels: mean of red and green */
    c = texture_sample(t, R(0.5), R(0.25), NULL, FILTER_BILINEAR);
    assert_float_equal(c.x, R(0.5), R(1e-6));
    assert_float_equal(c.y, R(0.5), R(1e-6));
    /* wrapping: u = 1.25 is u = 0.25; and the corner blends all four texels */
    vec3 a = texture_sample(t, R(1.25), R(-0.75), NULL, FILTER_NEAREST);
    vec3 b = texture_sample(t, R(0.25), R(0.25), NULL, FILTER_NEAREST);
    assert_memory_equal(&a, &b, sizeof a);
    c = texture_sample(t, 0, 0, NULL, FILTER_TRILINEAR);
    assert_float_equal(c.x, R(0.5), R(1e-6)); /* (0 + 1 + 1 + 0) / 4 */
    assert_float_equal(c.y, R(0.5), R(1e-6));
    /* clamped, the corner is the corner texel: the far side does not bleed in */
    t->wrap[0] = t->wrap[1] = TEXTURE_CLAMP;
    c = texture_sample(t, 0, 0, NULL, FILTER_BILINEAR);
    assert_float_equal(c.x, 1, R(1e-6));
    assert_float_equal(c.y, 0, R(1e-6));
    t->wrap[0] = t->wrap[1] = TEXTURE_REPEAT;
    /* non-finite coordinates do not crash */
    c = texture_sample(t, NAN, INFINITY, NULL, FILTER_BILINEAR);
    assert_true(isfinite(c.x));
    TexFootprint inf = {INFINITY, NAN, 0, 1e30f};
    c = texture_sample(t, R(0.3), R(0.3), &inf, FILTER_ANISOTROPIC);
    assert_true(isfinite(c.x));
    texture_destroy(t);
}

/* Each axis wraps its own way (glTF's wrapS and wrapT): repeated, clamped
 * or mirrored, u apart from v. */
static void wrap_modes_by_axis(void **state)
{
    (void)state;
    /* 4 x 1: red, green, blue, white, left to right */
    const uint8_t px[12] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255};
    Texture *t = texture_from_rgb8(4, 1, px);
    assert_non_null(t);
    const real u[] = {R(1.125), R(1.875), R(-0.125), R(2.125), R(-1.875), R(0.625), R(7.375)};
    /* mirrored: [1, 2] runs back (1.125 reads 0.875: white), [2, 3] forward (2.125: red), and
     * [-2, -1] forward too (-1.875 reads 0.125) */
    const int mirrored[] = {3, 0, 0, 0, 0, 2, 2}, repeated[] = {0, 3, 3, 0, 0, 2, 1}, clamped[] = {3, 3, 0, 3, 0, 2, 3};
    const uint8_t modes[] = {TEXTURE_MIRROR, TEXTURE_REPEAT, TEXTURE_CLAMP};
    const int *want[] = {mirrored, repeated, clamped};
    for (int m = 0; m < 3; m++) {
        t->wrap[0] = modes[m];
        t->wrap[1] = TEXTURE_REPEAT;
        for (size_t i = 0; i < sizeof u / sizeof *u; i++) {
            vec3 c = texture_sample(t, u[i], R(0.5), NULL, FILTER_NEAREST);
            const uint8_t *e = &px[3 * want[m][i]];
            if (c.x != srgb_decode8[e[0]] || c.y != srgb_decode8[e[1]] || c.z != srgb_decode8[e[2]])
                fail_msg("wrap %d, u = %g: not texel %d", modes[m], (double)u[i], want[m][i]);
        }
    }
    /* bilinear at the left edge: mirrored and clamped read red alone, repeated blends in the white */
    t->wrap[0] = TEXTURE_MIRROR;
    vec3 c = texture_sample(t, 0, R(0.5), NULL, FILTER_BILINEAR);
    assert_float_equal(c.x, 1, R(1e-6));
    assert_float_equal(c.y, 0, R(1e-6));
    t->wrap[0] = TEXTURE_REPEAT;
    c = texture_sample(t, 0, R(0.5), NULL, FILTER_BILINEAR);
    assert_float_equal(c.y, R(0.5), R(1e-6));
    /* v apart from u: v clamped does not wrap the image's one row, u still repeats */
    t->wrap[1] = TEXTURE_CLAMP;
    vec3 a = texture_sample(t, R(1.375), R(3.75), NULL, FILTER_NEAREST);
    vec3 b = texture_sample(t, R(0.375), R(0.5), NULL, FILTER_NEAREST);
    assert_memory_equal(&a, &b, sizeof a);
    texture_destroy(t);
}

/* The byte form's wrap bits: both axes clamped is the flag every version
 * wrote (1); other pairs go in bits 2-5 and come back; bits no version
 * writes are refused. */
static void byte_form_keeps_the_wrap_modes(void **state)
{
    (void)state;
    const uint8_t px[12] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
    Texture *t = texture_from_rgb8(2, 2, px), *back;
    const uint8_t pairs[][2] = {{TEXTURE_CLAMP, TEXTURE_CLAMP}, {TEXTURE_MIRROR, TEXTURE_CLAMP},
                                {TEXTURE_REPEAT, TEXTURE_MIRROR}, {TEXTURE_REPEAT, TEXTURE_REPEAT}};
    const uint32_t flags[] = {1, 2 << 2 | 1 << 4, 2 << 4, 0};
    Err err = {{0}};
    for (int i = 0; i < 4; i++) {
        t->wrap[0] = pairs[i][0], t->wrap[1] = pairs[i][1];
        Sink s = {0};
        assert_int_equal(texture_encode(t, &s), 0);
        uint32_t head[3];
        memcpy(head, s.data, sizeof head);
        assert_int_equal(head[2], flags[i]);
        if (texture_decode(s.data, s.len, "asset", &back, &err))
            fail_msg("%s", err.msg);
        assert_int_equal(back->wrap[0], pairs[i][0]);
        assert_int_equal(back->wrap[1], pairs[i][1]);
        texture_destroy(back);
        sink_free(&s);
    }
    const uint32_t bad[] = {3 << 2, 3 << 4, 1 | 1 << 2, 1 << 6};
    for (int i = 0; i < 4; i++) {
        Sink s = {0};
        assert_int_equal(texture_encode(t, &s), 0);
        memcpy(s.data + 8, &bad[i], 4);
        assert_int_equal(texture_decode(s.data, s.len, "asset", &back, &err), -1);
        assert_null(back);
        assert_contains(err.msg, "not a size, flags and codec");
        sink_free(&s);
    }
    texture_destroy(t);
}

/* Opacity for cutouts: a PNG's alpha is kept (none where every texel is
 * opaque), travels in the byte form (an RGBA PNG for a texture without a
 * file of its own), and texture_coverage reads it by the nearest texel;
 * an image without alpha reads its grey level (a map_d mask). */
static void alpha_is_kept_for_cutouts(void **state)
{
    (void)state;
    const uint8_t rgb[12] = {255, 255, 255, 0, 0, 0, 90, 90, 90, 30, 60, 90};
    const uint8_t alpha[4] = {0, 255, 128, 255}, opaque[4] = {255, 255, 255, 255};
    Err err = {{0}};
    Texture *t;
    for (int k = 0; k < 2; k++) {
        Sink png = {0};
        assert_int_equal(image_encode_png_alpha(rgb, k ? opaque : alpha, 2, 2, &png), 0);
        const char *path = write_bytes("a.png", png.data, png.len);
        sink_free(&png);
        if (texture_read(path, &t, &err))
            fail_msg("%s", err.msg);
        if (k) {
            assert_null(t->alpha); /* all opaque: nothing kept */
            texture_destroy(t);
            continue;
        }
        assert_non_null(t->alpha);
        assert_memory_equal(t->alpha, alpha, 4);
        assert_memory_equal(t->level[0].rgb, rgb, 12);
        /* top row first: (0.25, 0.75) is the top-left texel, (0.75, 0.25) the bottom-right */
        assert_float_equal(texture_coverage(t, R(0.25), R(0.75)), 0, 0);
        assert_float_equal(texture_coverage(t, R(0.75), R(0.75)), 1, 0);
        assert_float_equal(texture_coverage(t, R(0.25), R(0.25)), R(128) / R(255), R(1e-6));
        assert_float_equal(texture_coverage(t, R(1.25), R(0.75)), 0, 0); /* repeated */
        texture_destroy(t);
    }
    /* no file of its own: the byte form is an RGBA PNG, and the alphas come back */
    t = texture_from_rgb8(2, 2, rgb);
    assert_int_equal(texture_keep_alpha(t, alpha), 0);
    Sink form = {0};
    assert_int_equal(texture_encode(t, &form), 0);
    Texture *back;
    if (texture_decode(form.data, form.len, "asset", &back, &err))
        fail_msg("%s", err.msg);
    assert_non_null(back->alpha);
    assert_memory_equal(back->alpha, alpha, 4);
    sink_free(&form);
    texture_destroy(back);
    /* without alpha, a grey image's level: the mean of the codes */
    free(t->alpha);
    t->alpha = NULL;
    assert_float_equal(texture_coverage(t, R(0.25), R(0.75)), 1, 0);
    assert_float_equal(texture_coverage(t, R(0.75), R(0.25)), R(180) / R(765), R(1e-6));
    texture_destroy(t);
}

/* The footprint picks the level: a sample that covers the whole of a
 * 64 x 64 checker of one-texel squares reads grey (light 0.5), not a
 * texel; one of a tenth of a texel reads the texel.  A closest texture
 * keeps its squares sharp magnified; a smooth one blends across a texel.
 * Anisotropic keeps stripes across a footprint that trilinear blurs. */
static void footprints_choose_the_level(void **state)
{
    (void)state;
    enum { N = 64 };
    static uint8_t px[N * N * 3];
    for (int y = 0; y < N; y++)
        for (int x = 0; x < N; x++)
            memset(&px[3 * (y * N + x)], (x + y) % 2 ? 255 : 0, 3);
    Texture *t = texture_from_rgb8(N, N, px);
    const real u = R(10.5) / N, v = R(1) - R(20.5) / N; /* texel (10, 20): black */
    TexFootprint whole = {1, 0, 0, 1}, tiny = {R(0.1) / N, 0, 0, R(0.1) / N};
    assert_float_equal(texture_sample(t, u, v, &whole, FILTER_TRILINEAR).x, R(0.5), R(0.01));
    assert_float_equal(texture_sample(t, u, v, &whole, FILTER_BILINEAR).x, 0, R(1e-6)); /* no mip-maps: aliased */
    assert_float_equal(texture_sample(t, u, v, &tiny, FILTER_TRILINEAR).x, 0, R(1e-6));
    /* a quarter texel from the edge between texels 10 and 11, magnified 10x */
    const real ue = R(10.75) / N;
    real smooth = texture_sample(t, ue, v, &tiny, FILTER_TRILINEAR).x;
    t->closest = 1;
    real sharp = texture_sample(t, ue, v, &tiny, FILTER_TRILINEAR).x;
    assert_float_equal(smooth, R(0.25), R(1e-6)); /* bilinear: a quarter of the way to white */
    assert_float_equal(sharp, 0, R(1e-6));        /* the square: still black */
    /* on the edge itself, half of each */
    assert_float_equal(texture_sample(t, R(11.0) / N, v, &tiny, FILTER_TRILINEAR).x, R(0.5), R(1e-6));
    texture_destroy(t);
    /* horizontal stripes (v changes), a footprint 32 texels along u and 1 along v */
    for (int y = 0; y < N; y++)
        for (int x = 0; x < N; x++)
            memset(&px[3 * (y * N + x)], (y / 4) % 2 ? 255 : 0, 3);
    t = texture_from_rgb8(N, N, px);
    TexFootprint thin = {R(32.0) / N, 0, 0, R(1.0) / N};
    const real vs = R(1) - R(2.0) / N; /* in a black stripe, two texels from its edges */
    real tri = texture_sample(t, R(0.5), vs, &thin, FILTER_TRILINEAR).x;
    real aniso = texture_sample(t, R(0.5), vs, &thin, FILTER_ANISOTROPIC).x;
    assert_true(tri > R(0.3));   /* blurred towards the mean */
    assert_true(aniso < R(0.05)); /* still the stripe */
    texture_destroy(t);
}

static void filters_have_names(void **state)
{
    (void)state;
    for (int f = 0; f < FILTER_COUNT; f++) {
        TextureFilter back;
        assert_int_equal(texture_filter_parse(texture_filter_name((TextureFilter)f), &back), 0);
        assert_int_equal(back, f);
    }
    TextureFilter x;
    assert_int_equal(texture_filter_parse("cubic", &x), -1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(reads_ppm_and_pgm),
        cmocka_unit_test(rejects_bad_images),
        cmocka_unit_test(byte_form_keeps_the_image_file),
        cmocka_unit_test(mip_maps_average_light),
        cmocka_unit_test(nearest_and_bilinear_sampling),
        cmocka_unit_test(wrap_modes_by_axis),
        cmocka_unit_test(byte_form_keeps_the_wrap_modes),
        cmocka_unit_test(alpha_is_kept_for_cutouts),
        cmocka_unit_test(footprints_choose_the_level),
        cmocka_unit_test(filters_have_names),
    };
    return cmocka_run_group_tests_name("texture", tests, NULL, NULL);
}
