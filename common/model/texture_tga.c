/* texture_tga.c - Truevision TGA textures, as game models and older
 * modellers ship them: true colour (15/16, 24 or 32 bits), grey (8 bits,
 * or 16 with alpha) and colour-mapped (8- or 16-bit indices into a map of
 * 15/16-, 24- or 32-bit entries), each raw or run-length coded; rows
 * bottom-up or top-down, left to right or right to left.  Alpha, where
 * the descriptor gives texels alpha bits (32-bit BGRA, 16-bit grey and
 * alpha, 5-5-5-1, a map's 32-bit entries), is kept for cutouts; a file
 * that says none has none, whatever its fourth bytes hold.  Every read is
 * bounds-checked (Cursor);
 * the size is checked before the texels are allocated, and a run-length
 * file must hold at least a byte for every 128 texels it claims. */
#include <stdlib.h>

#include "base/cursor.h"
#include "model/texture.h"

/* One texel of `bytes` bytes (little-endian) to RGBA: grey, 5-5-5(-1), BGR
 * or BGRA; alpha 255 unless `abits` (the descriptor's alpha bits) says the
 * texel has one. */
static void texel_rgba(const uint8_t *b, int bytes, int grey, int abits, uint8_t rgba[4])
{
    rgba[3] = 255;
    if (grey) {
        rgba[0] = rgba[1] = rgba[2] = b[0]; /* a 16-bit grey texel is grey then alpha */
        if (bytes == 2 && abits)
            rgba[3] = b[1];
    } else if (bytes == 2) {
        const uint32_t v = bytes_le(b, 2); /* A RRRRR GGGGG BBBBB: 5 bits widened as (x << 3) | (x >> 2) */
        const uint32_t r = v >> 10 & 31, g = v >> 5 & 31, bl = v & 31;
        rgba[0] = (uint8_t)(r << 3 | r >> 2), rgba[1] = (uint8_t)(g << 3 | g >> 2), rgba[2] = (uint8_t)(bl << 3 | bl >> 2);
        if (abits)
            rgba[3] = v >> 15 ? 255 : 0;
    } else {
        rgba[0] = b[2], rgba[1] = b[1], rgba[2] = b[0];
        if (bytes == 4 && abits)
            rgba[3] = b[3];
    }
}

typedef struct {
    uint8_t h[18];
    uint32_t w, hgt;
    int type, px_bytes, rle, grey, mapped;
    uint32_t map_first, map_len;
    int map_bytes;
    const uint8_t *map;
} TgaHead;

static int tga_head(Cursor *c, TgaHead *t, const char *name, Err *err)
{
    if (cursor_get(c, t->h, sizeof t->h))
        return err_set(err, "%s: a TGA image cut short in its header", name);
    const uint8_t *h = t->h;
    t->type = h[2];
    t->w = bytes_le(h + 12, 2), t->hgt = bytes_le(h + 14, 2);
    t->rle = t->type >= 9;
    const int base = t->rle ? t->type - 8 : t->type, bpp = h[16];
    t->mapped = base == 1, t->grey = base == 3;
    if (base < 1 || base > 3 || (t->type > 3 && t->type < 9) || t->type > 11)
        return err_set(err, "%s: a TGA image of type %d: lanray reads types 1-3 and 9-11 (convert it to PNG)", name, t->type);
    if (!texture_size_ok(t->w, t->hgt))
        return err_set(err, "%s: a %ux%u TGA image: a texture is 1 to %u texels a side", name, t->w, t->hgt,
                       TEXTURE_MAX_SIDE);
    const int ok_bpp = t->mapped ? (bpp == 8 || bpp == 16) : t->grey ? (bpp == 8 || bpp == 16)
                                                                     : (bpp == 15 || bpp == 16 || bpp == 24 || bpp == 32);
    if (!ok_bpp)
        return err_set(err, "%s: a TGA image of type %d with %d bits a texel", name, t->type, bpp);
    t->px_bytes = (bpp + 7) / 8;
    /* the image ID, then the colour map (whatever the type: skipped where unused) */
    uint8_t skip[256];
    if (cursor_get(c, skip, h[0]))
        return err_set(err, "%s: a TGA image cut short in its ID", name);
    t->map_first = bytes_le(h + 3, 2), t->map_len = bytes_le(h + 5, 2);
    const int map_bits = h[7];
    t->map_bytes = (map_bits + 7) / 8;
    if (h[1] == 1 || t->mapped) {
        if (t->mapped && (h[1] != 1 || !(map_bits == 15 || map_bits == 16 || map_bits == 24 || map_bits == 32)))
            return err_set(err, "%s: a colour-mapped TGA image without a map of 15, 16, 24 or 32 bits", name);
        const size_t map_size = (size_t)t->map_len * (size_t)t->map_bytes;
        if (map_size > c->left)
            return err_set(err, "%s: a TGA image cut short in its colour map", name);
        t->map = c->p;
        c->p += map_size, c->left -= map_size;
    }
    return 0;
}

/* A texel's bytes as RGBA, through the map where there is one. */
static int tga_texel(const TgaHead *t, const uint8_t *b, uint8_t rgba[4])
{
    const int abits = t->h[17] & 15;
    if (!t->mapped) {
        texel_rgba(b, t->px_bytes, t->grey, abits, rgba);
        return 0;
    }
    const uint32_t i = bytes_le(b, t->px_bytes);
    if (i < t->map_first || i - t->map_first >= t->map_len)
        return -1;
    texel_rgba(t->map + (size_t)(i - t->map_first) * (size_t)t->map_bytes, t->map_bytes, 0, abits, rgba);
    return 0;
}

/* The texels in file order (rows as stored), RGBA. */
static int tga_texels(Cursor *c, const TgaHead *t, uint8_t *out, const char *name, Err *err)
{
    const size_t n = (size_t)t->w * t->hgt;
    uint8_t b[4];
    for (size_t i = 0; i < n;) {
        size_t count = 1;
        int run = 0;
        if (t->rle) {
            uint8_t p;
            if (cursor_get(c, &p, 1))
                return err_set(err, "%s: a TGA image cut short after %zu of %zu texels", name, i, n);
            count = (size_t)(p & 0x7f) + 1, run = p >> 7;
            if (count > n - i) /* a packet past the last texel: the rest is lost */
                count = n - i;
        }
        for (size_t k = 0; k < count; k++, i++) {
            if ((k == 0 || !run) && cursor_get(c, b, (size_t)t->px_bytes))
                return err_set(err, "%s: a TGA image cut short after %zu of %zu texels", name, i, n);
            if ((k == 0 || !run) && tga_texel(t, b, &out[4 * i]))
                return err_set(err, "%s: a TGA texel's colour index past the colour map", name);
            if (k > 0 && run)
                memcpy(&out[4 * i], &out[4 * (i - 1)], 4);
        }
    }
    return 0;
}

int texture_read_tga(const void *data, size_t len, const char *name, Texture **out, Err *err)
{
    *out = NULL;
    Cursor c = cursor_make(data, len);
    TgaHead t = {0};
    if (tga_head(&c, &t, name, err))
        return -1;
    const size_t n = (size_t)t.w * t.hgt;
    /* raw texels must all be there; a run packet of 1 + bytes a texel holds 128 */
    if ((!t.rle && n * (size_t)t.px_bytes > c.left) || (t.rle && n > 128 * c.left))
        return err_set(err, "%s: %zu bytes cannot hold a %ux%u TGA image: the file is cut short", name, len, t.w, t.hgt);
    uint8_t *raw = malloc(n * 4), *rgb = malloc(n * 4), *alpha = rgb ? rgb + n * 3 : NULL;
    if (!raw || !rgb) {
        free(raw), free(rgb);
        return err_set(err, "%s: out of memory for a %ux%u texture", name, t.w, t.hgt);
    }
    int rc = tga_texels(&c, &t, raw, name, err);
    if (rc == 0) { /* rows top first, left to right: descriptor bit 5 top-down, bit 4 right-to-left */
        const int top = t.h[17] >> 5 & 1, right = t.h[17] >> 4 & 1;
        for (uint32_t y = 0; y < t.hgt; y++)
            for (uint32_t x = 0; x < t.w; x++) {
                const uint32_t sy = top ? y : t.hgt - 1 - y, sx = right ? t.w - 1 - x : x;
                const uint8_t *s = &raw[4 * ((size_t)sy * t.w + sx)];
                memcpy(&rgb[3 * ((size_t)y * t.w + x)], s, 3);
                alpha[(size_t)y * t.w + x] = s[3];
            }
        *out = texture_with_alpha(texture_from_rgb8(t.w, t.hgt, rgb), alpha);
        rc = *out ? 0 : err_set(err, "%s: out of memory for a %ux%u texture", name, t.w, t.hgt);
    }
    free(raw), free(rgb);
    return rc;
}
