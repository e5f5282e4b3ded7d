/* texture.h - RGB images for texture mapping, read from PNG, JPEG, PPM or PGM.
 *
 * Texels are stored as float RGB in [0,1], linear light: images store
 * sRGB-encoded values, which are decoded on load (srgb.h), so that filtering
 * and shading work on light.  Texture coordinates wrap (repeat);
 * v = 0 is the bottom row, as in OBJ. */
#ifndef LANRAY_TEXTURE_H
#define LANRAY_TEXTURE_H

#include <stdint.h>
#include <stdio.h>

#include "base/cursor.h"
#include "base/err.h"
#include "base/vec.h"

#define TEXTURE_MAX_SIDE 16384u

typedef struct {
    uint32_t w, h;
    float *rgb; /* 3 per texel, row-major, top row first */
    int clamp;  /* coordinates clamp to the edge instead of wrapping (MTL -clamp on) */
} Texture;

typedef enum { FILTER_NEAREST = 0, FILTER_BILINEAR = 1 } TextureFilter;

/* Reads a PPM (P3/P6) or PGM (P2/P5, replicated to grey RGB); `name` labels errors. */
int texture_read_stream(FILE *f, const char *name, Texture **out, Err *err);
/* Reads a texture file by its extension: .png, .jpg/.jpeg, else PPM/PGM (texture_file.c). */
int texture_read(const char *path, Texture **out, Err *err);
/* A JPEG from an open stream (not closed) of `bytes` bytes; `name` labels errors. */
int texture_read_jpeg_stream(FILE *f, const char *name, size_t bytes, Texture **out, Err *err);
/* A w x h texture whose texels the caller fills, or NULL. */
Texture *texture_alloc(uint32_t w, uint32_t h);
/* The texture's byte form, what an ASSET carries (docs/protocol.md): u32
 * w, u32 h, f32 rgb[3 w h] as stored (linear light, top row first). */
int texture_encode(const Texture *t, Sink *out);
/* Reads that form with every size and value checked; `name` labels errors. */
int texture_decode(const void *data, size_t len, const char *name, Texture **out, Err *err);
/* Whether w x h is a size a texture may have (1..TEXTURE_MAX_SIDE a side). */
static inline int texture_size_ok(uint32_t w, uint32_t h)
{
    return w >= 1 && h >= 1 && w <= TEXTURE_MAX_SIDE && h <= TEXTURE_MAX_SIDE;
}
/* The texels of a w x h texture as stored in both byte forms (the ASSET's
 * and the .tmd's): f32 rgb, linear light, each in [0, 1]; the caller has
 * checked the size and that the cursor holds them. */
int texture_read_texels(Cursor *c, uint32_t w, uint32_t h, const char *name, Texture **out, Err *err);
/* A texture of w x h from 8-bit RGB pixels (copied). */
Texture *texture_from_rgb8(uint32_t w, uint32_t h, const uint8_t *rgb);
void texture_destroy(Texture *t);
Texture *texture_copy(const Texture *t);

static inline vec3 texture_texel(const Texture *t, uint32_t x, uint32_t y)
{
    const float *p = &t->rgb[3 * ((size_t)y * t->w + x)];
    return v3(p[0], p[1], p[2]);
}

/* Wraps a coordinate into [0,1); NaN and inf map to 0. */
static inline real texture_wrap(real u)
{
    if (!isfinite(u))
        return R(0);
    u -= floor(u);
    return u >= R(1) ? R(0) : u;
}

/* Clamps a coordinate into [0,1]; NaN maps to 0. */
static inline real texture_clamp01(real u) { return u > R(0) ? (u < R(1) ? u : R(1)) : R(0); }

static inline vec3 texture_sample(const Texture *t, real u, real v, TextureFilter filter)
{
    u = t->clamp ? texture_clamp01(u) : texture_wrap(u);
    v = R(1) - (t->clamp ? texture_clamp01(v) : texture_wrap(v)); /* v = 0 at the bottom */
    if (filter == FILTER_NEAREST) {
        uint32_t x = (uint32_t)(u * (real)t->w), y = (uint32_t)(v * (real)t->h);
        return texture_texel(t, x < t->w ? x : t->w - 1, y < t->h ? y : t->h - 1);
    }
    /* bilinear between the four texel centres around (u, v), wrapping at the edges */
    real fx = u * (real)t->w - R(0.5), fy = v * (real)t->h - R(0.5);
    real x0f = floor(fx), y0f = floor(fy);
    real ax = fx - x0f, ay = fy - y0f;
    int64_t x0 = (int64_t)x0f, y0 = (int64_t)y0f;
    uint32_t xa = (uint32_t)((x0 % t->w + t->w) % t->w), xb = (xa + 1) % t->w;
    uint32_t ya = (uint32_t)((y0 % t->h + t->h) % t->h), yb = (ya + 1) % t->h;
    vec3 top = v3_lerp(texture_texel(t, xa, ya), texture_texel(t, xb, ya), ax);
    vec3 bot = v3_lerp(texture_texel(t, xa, yb), texture_texel(t, xb, yb), ax);
    return v3_lerp(top, bot, ay);
}

#endif
