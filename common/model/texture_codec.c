/* texture_codec.c - a texture's byte form, as a .tmd and an ASSET carry it.
 *
 * The form is the image file's own bytes (PNG, JPEG or Radiance HDR) behind a small
 * header that states the size they must decode to; a texture without a
 * file of its own (PPM, generated, an embedded bitmap) is written as a PNG
 * of its texels.  A reader decodes the bytes with the same libraries and
 * so gets the same texels, then builds the same mip-maps (texture.c). */
#include "model/texture.h"

#include <stdlib.h>
#include <string.h>

#include "image/image.h"

#define FORM_CLAMP 1u /* both axes clamp: what every version wrote */
#define FORM_CLOSEST 2u
#define FORM_WRAP_U 2 /* bits 2-3: u's TextureWrap, where FORM_CLAMP is clear */
#define FORM_WRAP_V 4 /* bits 4-5: v's */

/* The flags' wrap bits: the old clamp bit where both axes clamp (so that
 * such a texture's form is what it always was), else each axis's mode. */
static uint32_t form_wrap(const Texture *t)
{
    if (t->wrap[0] == TEXTURE_CLAMP && t->wrap[1] == TEXTURE_CLAMP)
        return FORM_CLAMP;
    return (uint32_t)t->wrap[0] << FORM_WRAP_U | (uint32_t)t->wrap[1] << FORM_WRAP_V;
}

/* The wrap modes of flags; -1 for bits no version writes. */
static int form_unwrap(uint32_t flags, uint8_t wrap[2])
{
    const uint32_t u = flags >> FORM_WRAP_U & 3, v = flags >> FORM_WRAP_V & 3;
    if ((flags >> 6) != 0 || u >= TEXTURE_WRAP_COUNT || v >= TEXTURE_WRAP_COUNT || ((flags & FORM_CLAMP) && (u || v)))
        return -1;
    wrap[0] = (flags & FORM_CLAMP) ? TEXTURE_CLAMP : (uint8_t)u;
    wrap[1] = (flags & FORM_CLAMP) ? TEXTURE_CLAMP : (uint8_t)v;
    return 0;
}

int texture_encode(const Texture *t, Sink *out)
{
    Sink png = {0};
    const uint8_t *bytes = t->file;
    size_t len = t->file_len;
    TextureCodec codec = t->codec;
    if (!bytes) {
        if (image_encode_png_alpha(t->level[0].rgb, t->alpha, (int)t->w, (int)t->h, &png) || png.failed) {
            sink_free(&png);
            out->failed = 1;
            return -1;
        }
        bytes = png.data, len = png.len, codec = TEXTURE_PNG;
    }
    sink_u32(out, t->w);
    sink_u32(out, t->h);
    sink_u32(out, form_wrap(t) | (t->closest ? FORM_CLOSEST : 0));
    sink_u32(out, (uint32_t)codec);
    sink_u32(out, (uint32_t)len);
    sink_put(out, bytes, len);
    const uint8_t zero[4] = {0, 0, 0, 0};
    sink_put(out, zero, (4 - len % 4) % 4);
    sink_free(&png);
    return out->failed ? -1 : 0;
}

int texture_read_form(Cursor *c, const char *name, Texture **out, Err *err)
{
    *out = NULL;
    uint32_t w = cursor_u32(c), h = cursor_u32(c), flags = cursor_u32(c), codec = cursor_u32(c), len = cursor_u32(c);
    if (c->failed)
        return err_set(err, "%s: the texture's header is cut short", name);
    uint8_t wrap[2];
    if (!texture_size_ok(w, h) || form_unwrap(flags, wrap) || (codec != TEXTURE_PNG && codec != TEXTURE_JPEG && codec != TEXTURE_HDR))
        return err_set(err, "%s: a texture of %ux%u, flags %u, codec %u: not a size, flags and codec (1 PNG, 2 JPEG, 3 HDR) "
                       "a texture has", name, w, h, flags, codec);
    size_t padded = (size_t)len + (4 - len % 4) % 4;
    if (padded > c->left)
        return err_set(err, "%s: the texture's %u image bytes are cut short (%zu left)", name, len, c->left);
    const uint8_t *bytes = c->p;
    for (size_t i = len; i < padded; i++)
        if (bytes[i] != 0)
            return err_set(err, "%s: the texture's padding is not zero", name);
    Texture *t;
    if (texture_read_memory(bytes, len, name, &t, err))
        return -1;
    if (t->w != w || t->h != h || t->codec != (TextureCodec)codec) {
        uint32_t tw = t->w, th = t->h;
        texture_destroy(t);
        return err_set(err, "%s: the texture says %ux%u %s, its image is %ux%u", name, w, h,
                       codec == TEXTURE_PNG ? "PNG" : codec == TEXTURE_JPEG ? "JPEG" : "HDR", tw, th);
    }
    c->p += padded;
    c->left -= padded;
    t->wrap[0] = wrap[0], t->wrap[1] = wrap[1];
    t->closest = (flags & FORM_CLOSEST) != 0;
    *out = t;
    return 0;
}

int texture_decode(const void *data, size_t len, const char *name, Texture **out, Err *err)
{
    Cursor c = cursor_make(data, len);
    if (texture_read_form(&c, name, out, err))
        return -1;
    if (c.left != 0) {
        texture_destroy(*out);
        *out = NULL;
        return err_set(err, "%s: %zu bytes after the texture", name, c.left);
    }
    return 0;
}
