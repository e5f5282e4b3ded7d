/* texture_bmp.c - Windows BMP textures, as older models ship them: 1, 4
 * and 8 bits a texel through a palette, 16 and 32 bits with the default
 * masks or their own (BI_BITFIELDS), 24 bits; every header from
 * BITMAPCOREHEADER (OS/2, 12 bytes) to BITMAPV5HEADER; rows bottom-up or,
 * with a negative height, top-down.  Run-length coded BMPs are refused with
 * their name.  Alpha, where an alpha mask says there is one (a V3 header
 * or later, BI_ALPHABITFIELDS), is kept for cutouts.  Every read is
 * bounds-checked: the rows the header claims must lie inside the file
 * before the texels are allocated. */
#include <stdlib.h>

#include "base/cursor.h"
#include "model/texture.h"

/* A mask's channel out of a texel, widened to 8 bits. */
static uint8_t channel(uint32_t v, uint32_t mask)
{
    if (!mask)
        return 0;
    int shift = __builtin_ctz(mask), bits = 0;
    for (uint32_t m = mask >> shift; m & 1; m >>= 1)
        bits++;
    uint32_t x = (v & mask) >> shift;
    if (bits >= 8)
        return (uint8_t)(x >> (bits - 8));
    uint32_t out = 0; /* repeat the bits: 5 bits 10110 -> 10110101 */
    for (int have = 0; have < 8; have += bits)
        out = out << bits | x;
    return (uint8_t)(out >> ((8 + bits - 1) / bits * bits - 8));
}

typedef struct {
    uint32_t w, h, off, head;
    int top_down, bpp, compression;
    uint32_t mask[4]; /* red, green, blue, alpha (0: none) */
    const uint8_t *pal;
    uint32_t pal_n;
    int pal_bytes;
} BmpHead;

static int bmp_head(const uint8_t *p, size_t len, BmpHead *b, const char *name, Err *err)
{
    if (len < 26 || p[0] != 'B' || p[1] != 'M')
        return err_set(err, "%s: not a BMP image, or one cut short in its header", name);
    b->off = bytes_le(p + 10, 4);
    b->head = bytes_le(p + 14, 4);
    if (b->head != 12 && (b->head < 40 || b->head > 124 || 14 + (size_t)b->head > len))
        return err_set(err, "%s: a BMP header of %u bytes: not one lanray knows", name, b->head);
    int32_t hh;
    if (b->head == 12) { /* BITMAPCOREHEADER: 16-bit sizes, 3-byte palette entries */
        b->w = bytes_le(p + 18, 2), hh = (int16_t)bytes_le(p + 20, 2), b->bpp = (int)bytes_le(p + 24, 2), b->compression = 0;
        b->pal_bytes = 3;
    } else {
        b->w = bytes_le(p + 18, 4), hh = (int32_t)bytes_le(p + 22, 4), b->bpp = (int)bytes_le(p + 28, 2);
        b->compression = (int)bytes_le(p + 30, 4);
        b->pal_bytes = 4;
    }
    b->top_down = hh < 0;
    b->h = hh < 0 ? (uint32_t)0 - (uint32_t)hh : (uint32_t)hh;
    if ((int32_t)b->w <= 0 || !texture_size_ok(b->w, b->h))
        return err_set(err, "%s: a %dx%d BMP image: a texture is 1 to %u texels a side", name, (int32_t)b->w, hh,
                       TEXTURE_MAX_SIDE);
    if (b->compression == 1 || b->compression == 2)
        return err_set(err, "%s: a run-length coded BMP: lanray reads uncoded ones (convert it to PNG)", name);
    if (!(b->compression == 0 || b->compression == 3 || b->compression == 6))
        return err_set(err, "%s: a BMP of compression %d: lanray reads uncoded ones (convert it to PNG)", name,
                       b->compression);
    if (!(b->bpp == 1 || b->bpp == 4 || b->bpp == 8 || b->bpp == 16 || b->bpp == 24 || b->bpp == 32))
        return err_set(err, "%s: a BMP of %d bits a texel", name, b->bpp);
    /* masks: the default ones, or the three after a 40-byte header (BI_BITFIELDS), or in a V2+ header */
    b->mask[0] = b->bpp == 16 ? 0x7c00u : 0xff0000u, b->mask[1] = b->bpp == 16 ? 0x3e0u : 0xff00u;
    b->mask[2] = b->bpp == 16 ? 0x1fu : 0xffu;
    const size_t masks = 14 + (size_t)b->head;
    if (b->compression != 0 && (b->bpp == 16 || b->bpp == 32)) {
        const size_t at = b->head >= 52 ? 14 + 40 : masks;
        if (at + 12 > len)
            return err_set(err, "%s: a BMP cut short in its colour masks", name);
        for (int k = 0; k < 3; k++)
            b->mask[k] = bytes_le(p + at + 4 * k, 4);
        /* an alpha mask: in a V3 header or later, or the fourth after a
         * 40-byte one with BI_ALPHABITFIELDS */
        if ((b->head >= 56 || b->compression == 6) && at + 16 <= len)
            b->mask[3] = bytes_le(p + at + 12, 4);
    }
    if (b->bpp <= 8) { /* the palette follows the header (and a BI_BITFIELDS header's masks) */
        const size_t at = masks + (b->head == 40 && b->compression == 3 ? 12 : 0);
        uint32_t n = b->head >= 40 ? bytes_le(p + 46, 4) : 0;
        if (n == 0 || n > (1u << b->bpp))
            n = 1u << b->bpp;
        if (at > len || (len - at) / (size_t)b->pal_bytes < n)
            return err_set(err, "%s: a BMP cut short in its palette", name);
        b->pal = p + at, b->pal_n = n;
    }
    return 0;
}

/* Texel x of a row as RGB, and its alpha (255 without an alpha mask). */
static int bmp_texel(const BmpHead *b, const uint8_t *row, uint32_t x, uint8_t rgb[3], uint8_t *alpha)
{
    *alpha = 255;
    if (b->bpp <= 8) {
        const size_t bit = (size_t)x * (size_t)b->bpp;
        const uint32_t i = (uint32_t)(row[bit / 8] >> (8 - b->bpp - (int)(bit % 8))) & ((1u << b->bpp) - 1);
        if (i >= b->pal_n)
            return -1;
        const uint8_t *e = b->pal + (size_t)i * (size_t)b->pal_bytes;
        rgb[0] = e[2], rgb[1] = e[1], rgb[2] = e[0];
    } else if (b->bpp == 24) {
        const uint8_t *e = row + 3 * (size_t)x;
        rgb[0] = e[2], rgb[1] = e[1], rgb[2] = e[0];
    } else {
        const uint32_t v = bytes_le(row + (size_t)x * (size_t)(b->bpp / 8), b->bpp / 8);
        for (int k = 0; k < 3; k++)
            rgb[k] = channel(v, b->mask[k]);
        if (b->mask[3])
            *alpha = channel(v, b->mask[3]);
    }
    return 0;
}

int texture_read_bmp(const void *data, size_t len, const char *name, Texture **out, Err *err)
{
    *out = NULL;
    const uint8_t *p = data;
    BmpHead b = {0};
    if (bmp_head(p, len, &b, name, err))
        return -1;
    const size_t stride = ((size_t)b.w * (size_t)b.bpp + 31) / 32 * 4; /* rows padded to 4 bytes */
    if (b.off > len || (len - b.off) / stride < b.h)
        return err_set(err, "%s: %zu bytes cannot hold a %ux%u BMP image: the file is cut short", name, len, b.w, b.h);
    const size_t n = (size_t)b.w * b.h;
    uint8_t *rgb = malloc(n * 4), *alpha = rgb + n * 3;
    if (!rgb)
        return err_set(err, "%s: out of memory for a %ux%u texture", name, b.w, b.h);
    for (uint32_t y = 0; y < b.h; y++) { /* rows top first */
        const uint8_t *row = p + b.off + (size_t)(b.top_down ? y : b.h - 1 - y) * stride;
        for (uint32_t x = 0; x < b.w; x++)
            if (bmp_texel(&b, row, x, &rgb[3 * ((size_t)y * b.w + x)], &alpha[(size_t)y * b.w + x])) {
                free(rgb);
                return err_set(err, "%s: a BMP texel's colour index past the palette", name);
            }
    }
    *out = texture_with_alpha(texture_from_rgb8(b.w, b.h, rgb), alpha);
    free(rgb);
    return *out ? 0 : err_set(err, "%s: out of memory for a %ux%u texture", name, b.w, b.h);
}
