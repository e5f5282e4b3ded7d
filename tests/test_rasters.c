/* test_rasters.c - TGA and BMP textures (texture_tga.c, texture_bmp.c):
 * one small picture written in each layout those formats allow, read back
 * texel for texel; damaged and unsupported files refused with the reason;
 * alpha kept where the file says its texels have it. */
#include "helpers.h"

#include "model/texture.h"

/* The picture: 3 x 2, top row red, green, blue; bottom row three others. */
#define W 3
#define H 2
static const uint8_t pic[H][W][3] = {{{255, 0, 0}, {0, 255, 0}, {0, 0, 255}},
                                     {{10, 20, 30}, {128, 128, 128}, {250, 200, 100}}};

typedef struct {
    uint8_t b[1024];
    size_t n;
} Buf;

static void put(Buf *o, const void *p, size_t n)
{
    assert_true(o->n + n <= sizeof o->b);
    memcpy(o->b + o->n, p, n);
    o->n += n;
}
static void put8(Buf *o, uint32_t v) { put(o, &(uint8_t){(uint8_t)v}, 1); }
static void put16(Buf *o, uint32_t v) { put8(o, v & 255), put8(o, v >> 8 & 255); }
static void put32(Buf *o, uint32_t v) { put16(o, v & 0xffff), put16(o, v >> 16); }

/* Reads `o` as `name` and compares it with the picture (or with `want`,
 * rows top first, where given). */
static void reads_as(const Buf *o, const char *name, const uint8_t *want, uint32_t w, uint32_t h)
{
    Texture *t = NULL;
    Err err = {{0}};
    if (texture_read_memory(o->b, o->n, name, &t, &err))
        fail_msg("%s: %s", name, err.msg);
    assert_int_equal(t->w, w);
    assert_int_equal(t->h, h);
    for (uint32_t i = 0; i < w * h * 3; i++)
        if (t->level[0].rgb[i] != (want ? want[i] : (&pic[0][0][0])[i]))
            fail_msg("%s: byte %u is %u, not %u", name, i, t->level[0].rgb[i], want ? want[i] : (&pic[0][0][0])[i]);
    texture_destroy(t);
}

static void refused(const Buf *o, const char *name, const char *what)
{
    Texture *t = NULL;
    Err err = {{0}};
    assert_int_equal(texture_read_memory(o->b, o->n, name, &t, &err), -1);
    assert_null(t);
    assert_contains(err.msg, name);
    assert_contains(err.msg, what);
}

static void tga_head(Buf *o, int type, int cmap, uint32_t map_len, int map_bits, int bpp, int desc)
{
    *o = (Buf){.n = 0};
    put8(o, 2), put8(o, cmap), put8(o, type); /* an image ID of 2 bytes, skipped */
    put16(o, 0), put16(o, map_len), put8(o, map_bits);
    put16(o, 0), put16(o, 0), put16(o, W), put16(o, H), put8(o, bpp), put8(o, desc);
    put8(o, 'i'), put8(o, 'd');
}

/* The picture's rows in TGA order: bottom first unless top, left to right unless right. */
static const uint8_t *tga_px(int i, int top, int right)
{
    const int y = top ? i / W : H - 1 - i / W, x = right ? W - 1 - i % W : i % W;
    return pic[y][x];
}

static void tga_layouts(void **state)
{
    (void)state;
    Buf o;
    for (int desc = 0; desc < 4; desc++) { /* 24 bits, every origin */
        const int top = desc & 2, right = desc & 1;
        tga_head(&o, 2, 0, 0, 0, 24, (top ? 0x20 : 0) | (right ? 0x10 : 0));
        for (int i = 0; i < W * H; i++)
            put8(&o, tga_px(i, top, right)[2]), put8(&o, tga_px(i, top, right)[1]), put8(&o, tga_px(i, top, right)[0]);
        reads_as(&o, "a.tga", NULL, W, H);
    }
    tga_head(&o, 2, 0, 0, 0, 32, 0x28); /* 32 bits, alpha dropped, top first */
    for (int i = 0; i < W * H; i++)
        put8(&o, tga_px(i, 1, 0)[2]), put8(&o, tga_px(i, 1, 0)[1]), put8(&o, tga_px(i, 1, 0)[0]), put8(&o, 7);
    reads_as(&o, "b.tga", NULL, W, H);
    /* run-length coded: each texel a run of one, then a flat picture as one
     * run of six that crosses a row */
    tga_head(&o, 10, 0, 0, 0, 24, 0);
    for (int i = 0; i < W * H; i++)
        put8(&o, 0x80), put8(&o, tga_px(i, 0, 0)[2]), put8(&o, tga_px(i, 0, 0)[1]), put8(&o, tga_px(i, 0, 0)[0]);
    reads_as(&o, "c.tga", NULL, W, H);
    tga_head(&o, 10, 0, 0, 0, 24, 0);
    put8(&o, 0x85), put8(&o, 3), put8(&o, 2), put8(&o, 1);
    uint8_t flat[W * H * 3];
    for (int i = 0; i < W * H; i++)
        flat[3 * i] = 1, flat[3 * i + 1] = 2, flat[3 * i + 2] = 3;
    reads_as(&o, "d.tga", flat, W, H);
    /* a raw packet of all six */
    tga_head(&o, 10, 0, 0, 0, 24, 0);
    put8(&o, 0x05);
    for (int i = 0; i < W * H; i++)
        put8(&o, tga_px(i, 0, 0)[2]), put8(&o, tga_px(i, 0, 0)[1]), put8(&o, tga_px(i, 0, 0)[0]);
    reads_as(&o, "e.tga", NULL, W, H);
    /* colour-mapped: 8-bit indices into a 24-bit map, reversed order */
    tga_head(&o, 1, 1, W * H, 24, 8, 0);
    for (int i = W * H - 1; i >= 0; i--)
        put8(&o, tga_px(i, 0, 0)[2]), put8(&o, tga_px(i, 0, 0)[1]), put8(&o, tga_px(i, 0, 0)[0]);
    for (int i = 0; i < W * H; i++)
        put8(&o, W * H - 1 - i);
    reads_as(&o, "f.tga", NULL, W, H);
    /* 16 bits, 5-5-5: 31 widens to 255, 16 to 132 */
    tga_head(&o, 2, 0, 0, 0, 16, 0x20);
    const uint32_t r = 31u << 10, g = 16u << 5;
    for (int i = 0; i < W * H; i++)
        put16(&o, i % 2 ? g : r);
    uint8_t rg[W * H * 3] = {0};
    for (int i = 0; i < W * H; i++)
        rg[3 * i] = i % 2 ? 0 : 255, rg[3 * i + 1] = i % 2 ? 132 : 0;
    reads_as(&o, "g.tga", rg, W, H);
    /* grey */
    tga_head(&o, 3, 0, 0, 0, 8, 0x20);
    uint8_t grey[W * H * 3];
    for (int i = 0; i < W * H; i++) {
        put8(&o, 40 * i);
        grey[3 * i] = grey[3 * i + 1] = grey[3 * i + 2] = (uint8_t)(40 * i);
    }
    reads_as(&o, "h.tga", grey, W, H);
    /* an embedded image named by its format hint */
    reads_as(&o, "embedded image 0 (tga)", grey, W, H);
}

static void tga_damage(void **state)
{
    (void)state;
    Buf o;
    tga_head(&o, 2, 0, 0, 0, 24, 0);
    put8(&o, 1), put8(&o, 2);
    refused(&o, "cut.tga", "cut short");
    tga_head(&o, 10, 0, 0, 0, 24, 0);
    put8(&o, 0x81), put8(&o, 1), put8(&o, 2), put8(&o, 3); /* two of six texels */
    refused(&o, "rle.tga", "cut short after 2 of 6 texels");
    tga_head(&o, 32, 0, 0, 0, 24, 0);
    refused(&o, "huffman.tga", "type 32");
    tga_head(&o, 1, 1, 2, 24, 8, 0);
    for (int i = 0; i < 6; i++)
        put8(&o, 0);
    for (int i = 0; i < W * H; i++)
        put8(&o, i);
    refused(&o, "index.tga", "past the colour map");
    tga_head(&o, 2, 0, 0, 0, 24, 0);
    o.b[12] = 0; /* width 0 */
    refused(&o, "zero.tga", "1 to 16384 texels a side");
    tga_head(&o, 2, 0, 0, 0, 7, 0);
    refused(&o, "bits.tga", "7 bits a texel");
    o.n = 10;
    refused(&o, "head.tga", "cut short in its header");
}

/* A BMP of the picture: `head` bytes of header, `bpp` bits, rows bottom
 * first (or top first with a negative height), the texels by `px`. */
static void bmp_file(Buf *o, uint32_t head, int bpp, int top, int compression, uint32_t pal_n)
{
    *o = (Buf){.n = 0};
    const uint32_t pal_bytes = head == 12 ? 3 : 4, masks = compression == 3 && head == 40 ? 12 : 0;
    const uint32_t off = 14 + head + masks + pal_n * pal_bytes;
    put8(o, 'B'), put8(o, 'M'), put32(o, 0), put32(o, 0), put32(o, off);
    put32(o, head);
    if (head == 12) {
        put16(o, W), put16(o, H), put16(o, 1), put16(o, (uint32_t)bpp);
        return;
    }
    put32(o, W), put32(o, top ? (uint32_t)-H : H), put16(o, 1), put16(o, (uint32_t)bpp);
    put32(o, (uint32_t)compression), put32(o, 0), put32(o, 2835), put32(o, 2835), put32(o, pal_n), put32(o, 0);
    for (uint32_t k = 40; k < head; k++)
        put8(o, 0);
}

static void pad_row(Buf *o, size_t row_bytes)
{
    for (size_t k = row_bytes; k % 4; k++)
        put8(o, 0);
}

static void bmp_layouts(void **state)
{
    (void)state;
    Buf o;
    for (int top = 0; top < 2; top++) /* 24 bits, rows padded from 9 to 12 bytes */
        for (int v = 0; v < 3; v++) {
            const uint32_t head = v == 0 ? 40 : v == 1 ? 124 : 12;
            if (head == 12 && top)
                continue; /* the core header has no top-down rows */
            bmp_file(&o, head, 24, top, 0, 0);
            for (int y = 0; y < H; y++) {
                const int sy = top ? y : H - 1 - y;
                for (int x = 0; x < W; x++)
                    put8(&o, pic[sy][x][2]), put8(&o, pic[sy][x][1]), put8(&o, pic[sy][x][0]);
                pad_row(&o, 3 * W);
            }
            reads_as(&o, "a.bmp", NULL, W, H);
        }
    bmp_file(&o, 40, 32, 1, 0, 0); /* BGRX, top first */
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            put8(&o, pic[y][x][2]), put8(&o, pic[y][x][1]), put8(&o, pic[y][x][0]), put8(&o, 0xee);
    reads_as(&o, "b.bmp", NULL, W, H);
    /* 8 bits through a palette of the six colours */
    bmp_file(&o, 40, 8, 0, 0, W * H);
    for (int i = 0; i < W * H; i++)
        put8(&o, pic[i / W][i % W][2]), put8(&o, pic[i / W][i % W][1]), put8(&o, pic[i / W][i % W][0]), put8(&o, 0);
    for (int y = H - 1; y >= 0; y--) {
        for (int x = 0; x < W; x++)
            put8(&o, (uint32_t)(y * W + x));
        pad_row(&o, W);
    }
    reads_as(&o, "c.bmp", NULL, W, H);
    /* 4 and 1 bits: indices packed from the high bits */
    bmp_file(&o, 40, 4, 1, 0, W * H);
    for (int i = 0; i < W * H; i++)
        put8(&o, pic[i / W][i % W][2]), put8(&o, pic[i / W][i % W][1]), put8(&o, pic[i / W][i % W][0]), put8(&o, 0);
    for (int y = 0; y < H; y++)
        put8(&o, (uint32_t)(y * W) << 4 | (uint32_t)(y * W + 1)), put8(&o, (uint32_t)(y * W + 2) << 4), pad_row(&o, 2);
    reads_as(&o, "d.bmp", NULL, W, H);
    bmp_file(&o, 40, 1, 1, 0, 2);
    put32(&o, 0), put32(&o, 0x00ffffff); /* black, white */
    put8(&o, 0xa0), pad_row(&o, 1), put8(&o, 0x40), pad_row(&o, 1); /* 101 / 010 */
    const uint8_t bw[W * H * 3] = {255, 255, 255, 0, 0, 0, 255, 255, 255, 0, 0, 0, 255, 255, 255, 0, 0, 0};
    reads_as(&o, "e.bmp", bw, W, H);
    /* 16 bits, BI_BITFIELDS 5-6-5 after the header */
    bmp_file(&o, 40, 16, 1, 3, 0);
    put32(&o, 0xf800), put32(&o, 0x07e0), put32(&o, 0x001f);
    for (int y = 0; y < H; y++) {
        put16(&o, 31u << 11), put16(&o, 63u << 5), put16(&o, 16);
        pad_row(&o, 6);
    }
    const uint8_t rgb565[W * H * 3] = {255, 0, 0, 0, 255, 0, 0, 0, 132, 255, 0, 0, 0, 255, 0, 0, 0, 132};
    reads_as(&o, "f.bmp", rgb565, W, H);
}

/* The alpha of a texel i (rows top first) that the alpha tests write. */
static uint8_t alpha_of(int i) { return (uint8_t)(40 * i + 5); }

/* Alpha, kept for cutouts, where the file says its texels have it: a TGA
 * with alpha bits in its descriptor (32-bit BGRA, 5-5-5-1), a BMP with an
 * alpha mask (a V4 header); none where it says none, whatever the fourth
 * bytes hold. */
static void alpha_where_the_file_says(void **state)
{
    (void)state;
    Buf o;
    Texture *t;
    Err err = {{0}};
    for (int abits = 0; abits <= 8; abits += 8) { /* 32 bits, top first */
        tga_head(&o, 2, 0, 0, 0, 32, 0x20 | abits);
        for (int i = 0; i < W * H; i++)
            put8(&o, tga_px(i, 1, 0)[2]), put8(&o, tga_px(i, 1, 0)[1]), put8(&o, tga_px(i, 1, 0)[0]), put8(&o, alpha_of(i));
        if (texture_read_memory(o.b, o.n, "a.tga", &t, &err))
            fail_msg("%s", err.msg);
        if (!abits) {
            assert_null(t->alpha);
        } else {
            assert_non_null(t->alpha);
            for (int i = 0; i < W * H; i++)
                assert_int_equal(t->alpha[i], alpha_of(i));
        }
        texture_destroy(t);
    }
    tga_head(&o, 2, 0, 0, 0, 16, 0x01); /* 5-5-5-1: the top bit, bottom row first */
    for (int i = 0; i < W * H; i++)
        put16(&o, (i % 2 ? 0x8000u : 0) | 31u);
    if (texture_read_memory(o.b, o.n, "b.tga", &t, &err))
        fail_msg("%s", err.msg);
    assert_non_null(t->alpha);
    for (int i = 0; i < W * H; i++) /* file texel (H - 1 - y) * W + x is texel y * W + x */
        assert_int_equal(t->alpha[i], ((H - 1 - i / W) * W + i % W) % 2 ? 255 : 0);
    texture_destroy(t);
    bmp_file(&o, 108, 32, 1, 3, 0); /* V4: masks in the header, alpha the high byte */
    const uint32_t masks[4] = {0xff0000u, 0xff00u, 0xffu, 0xff000000u};
    for (int k = 0; k < 4; k++)
        memcpy(o.b + 14 + 40 + 4 * k, &masks[k], 4);
    for (int i = 0; i < W * H; i++)
        put8(&o, pic[i / W][i % W][2]), put8(&o, pic[i / W][i % W][1]), put8(&o, pic[i / W][i % W][0]), put8(&o, alpha_of(i));
    if (texture_read_memory(o.b, o.n, "c.bmp", &t, &err))
        fail_msg("%s", err.msg);
    assert_memory_equal(t->level[0].rgb, &pic[0][0][0], W * H * 3);
    assert_non_null(t->alpha);
    for (int i = 0; i < W * H; i++)
        assert_int_equal(t->alpha[i], alpha_of(i));
    texture_destroy(t);
}

static void bmp_damage(void **state)
{
    (void)state;
    Buf o;
    bmp_file(&o, 40, 24, 0, 0, 0);
    put8(&o, 1);
    refused(&o, "cut.bmp", "cut short");
    bmp_file(&o, 40, 8, 0, 1, 2);
    refused(&o, "rle.bmp", "run-length coded BMP");
    bmp_file(&o, 40, 8, 0, 0, 2);
    put32(&o, 0), put32(&o, 0);
    for (int y = 0; y < H; y++)
        put8(&o, 0), put8(&o, 1), put8(&o, 5), pad_row(&o, W); /* index 5 of a palette of 2 */
    refused(&o, "index.bmp", "past the palette");
    bmp_file(&o, 40, 8, 0, 0, 200);
    refused(&o, "palette.bmp", "cut short in its palette");
    bmp_file(&o, 40, 24, 0, 0, 0);
    o.b[18] = 0; /* width 0 */
    refused(&o, "zero.bmp", "1 to 16384 texels a side");
    bmp_file(&o, 40, 12, 0, 0, 0);
    refused(&o, "bits.bmp", "12 bits a texel");
    bmp_file(&o, 40, 24, 0, 0, 0);
    o.b[14] = 30; /* a header of 30 bytes */
    refused(&o, "head.bmp", "header of 30 bytes");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(tga_layouts),
        cmocka_unit_test(tga_damage),
        cmocka_unit_test(bmp_layouts),
        cmocka_unit_test(bmp_damage),
        cmocka_unit_test(alpha_where_the_file_says),
    };
    return cmocka_run_group_tests_name("rasters", tests, NULL, NULL);
}
