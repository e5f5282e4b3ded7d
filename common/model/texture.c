/* texture.c - a texture's texels and its mip-map levels.
 *
 * Each level is the one above box-filtered to half its size (rounded
 * down, at least 1): in linear light, since texels are averaged as light,
 * then rounded to the nearest sRGB code; a normal map's own levels
 * (texture_make_data_levels) average the codes themselves, its numbers.  A side of odd length is shrunk by
 * a box of 2 to 3 texels with fractional weights at its ends, so that every
 * texel of the level above counts by the area it covers (no texel is
 * dropped, none counted twice).  The arithmetic is float in every build and
 * in a fixed order: the same texels on every machine and in both precisions
 * (a float's code is the same in float and double: srgb.h). */
#include "model/texture.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/opt.h"
#include "base/srgb.h"

/* The levels of a w x h image, and the bytes their texels take. */
static uint32_t level_sizes(uint32_t w, uint32_t h, TextureLevel *lv, size_t *bytes)
{
    uint32_t n = 0;
    *bytes = 0;
    for (;;) {
        lv[n].w = w;
        lv[n].h = h;
        *bytes += (size_t)w * h * 3;
        n++;
        if ((w == 1 && h == 1) || n == TEXTURE_MAX_LEVELS)
            return n;
        w = w > 1 ? w / 2 : 1;
        h = h > 1 ? h / 2 : 1;
    }
}

/* Weights of the source texels [*first, *first + *count) that output texel
 * x of `out` covers, when `in` texels shrink to `out` (box filter). */
static void box_weights(uint32_t in, uint32_t out, uint32_t x, uint32_t *first, uint32_t *count, float w[4])
{
    if (in == out) {
        *first = x, *count = 1, w[0] = 1.0f;
        return;
    }
    const float s = (float)in / (float)out;
    const float a = (float)x * s, b = x + 1 == out ? (float)in : (float)(x + 1) * s;
    uint32_t i0 = (uint32_t)a, i1 = (uint32_t)ceilf(b);
    if (i1 > in)
        i1 = in;
    if (i1 - i0 > 4) /* s < 3, so a box meets at most 4 texels */
        i1 = i0 + 4;
    *first = i0;
    *count = i1 - i0;
    for (uint32_t i = i0; i < i1; i++) {
        float lo = (float)i > a ? (float)i : a, hi = (float)(i + 1) < b ? (float)(i + 1) : b;
        w[i - i0] = (hi - lo) / (b - a);
    }
}

/* Level `to` from the level above it, a row at a time (`row`: 3 floats a
 * texel of the level above; `acc`: 3 a texel of this one): colours in
 * linear light, or `data` (a normal map's numbers) code by code. */
static void shrink(const TextureLevel *src, TextureLevel *dst, float *row, float *acc, int data)
{
    for (uint32_t y = 0; y < dst->h; y++) {
        uint32_t r0, rn;
        float wy[4];
        box_weights(src->h, dst->h, y, &r0, &rn, wy);
        memset(row, 0, (size_t)src->w * 3 * sizeof *row);
        for (uint32_t k = 0; k < rn; k++) {
            const uint8_t *p = &src->rgb[(size_t)(r0 + k) * src->w * 3];
            for (size_t i = 0; i < (size_t)src->w * 3; i++)
                row[i] += wy[k] * (data ? (float)p[i] : srgb_decode8[p[i]]);
        }
        for (uint32_t x = 0; x < dst->w; x++) {
            uint32_t c0, cn;
            float wx[4];
            box_weights(src->w, dst->w, x, &c0, &cn, wx);
            float sum[3] = {0, 0, 0};
            for (uint32_t k = 0; k < cn; k++)
                for (int c = 0; c < 3; c++)
                    sum[c] += wx[k] * row[3 * (c0 + k) + c];
            for (int c = 0; c < 3; c++)
                acc[3 * x + c] = sum[c];
        }
        uint8_t *q = &dst->rgb[(size_t)y * dst->w * 3];
        for (size_t i = 0; i < (size_t)dst->w * 3; i++)
            q[i] = data ? (uint8_t)fminf(fmaxf(acc[i] + 0.5f, 0.0f), 255.0f) : srgb_encode8((real)acc[i]);
    }
}

/* A texture with room for the levels of w x h, the image's texels not yet set. */
static Texture *texture_alloc(uint32_t w, uint32_t h)
{
    if (!texture_size_ok(w, h))
        return NULL;
    Texture *t = calloc(1, sizeof *t);
    if (!t)
        return NULL;
    t->w = w;
    t->h = h;
    size_t bytes;
    t->levels = level_sizes(w, h, t->level, &bytes);
    t->texels = malloc(bytes);
    if (!t->texels) {
        free(t);
        return NULL;
    }
    size_t at = 0;
    for (uint32_t l = 0; l < t->levels; l++) {
        t->level[l].rgb = t->texels + at;
        at += (size_t)t->level[l].w * t->level[l].h * 3;
    }
    return t;
}

/* The levels below level 0 of lv (t's own, or its data levels). */
static int build_levels_of(const Texture *t, TextureLevel *lv, int data)
{
    if (t->levels < 2)
        return 0;
    float *row = malloc((size_t)t->w * 3 * sizeof *row), *acc = malloc((size_t)t->w * 3 * sizeof *acc);
    if (!row || !acc) {
        free(row);
        free(acc);
        return -1;
    }
    for (uint32_t l = 1; l < t->levels; l++)
        shrink(&lv[l - 1], &lv[l], row, acc, data);
    free(row);
    free(acc);
    return 0;
}

/* The mip-map levels below level 0. */
static int build_levels(Texture *t) { return build_levels_of(t, t->level, 0); }

int texture_make_data_levels(Texture *t)
{
    if (t->data_texels || t->levels < 2)
        return 0;
    const size_t first = (size_t)t->w * t->h * 3;
    uint8_t *px = malloc(texture_bytes(t) - first);
    if (!px)
        return -1;
    t->data_level[0] = t->level[0]; /* the image itself is the same */
    size_t at = 0;
    for (uint32_t l = 1; l < t->levels; l++) {
        t->data_level[l] = (TextureLevel){t->level[l].w, t->level[l].h, px + at};
        at += (size_t)t->level[l].w * t->level[l].h * 3;
    }
    if (build_levels_of(t, t->data_level, 1)) {
        free(px);
        return -1;
    }
    t->data_texels = px;
    return 0;
}

Texture *texture_from_file_rgb8(uint32_t w, uint32_t h, const uint8_t *rgb, uint8_t *file, size_t file_len,
                                TextureCodec codec)
{
    Texture *t = texture_alloc(w, h);
    if (!t) {
        free(file);
        return NULL;
    }
    memcpy(t->level[0].rgb, rgb, (size_t)w * h * 3);
    if (build_levels(t)) {
        free(file);
        texture_destroy(t);
        return NULL;
    }
    t->file = file;
    t->file_len = file ? file_len : 0;
    t->codec = file ? codec : TEXTURE_RAW;
    return t;
}

Texture *texture_from_rgb8(uint32_t w, uint32_t h, const uint8_t *rgb)
{
    return texture_from_file_rgb8(w, h, rgb, NULL, 0, TEXTURE_RAW);
}

Texture *texture_copy(const Texture *t)
{
    Texture *c = texture_alloc(t->w, t->h);
    if (!c)
        return NULL;
    if (t->file && !(c->file = malloc(t->file_len))) {
        texture_destroy(c);
        return NULL;
    }
    if (t->file)
        memcpy(c->file, t->file, t->file_len);
    c->file_len = t->file_len;
    c->codec = t->codec;
    c->wrap[0] = t->wrap[0], c->wrap[1] = t->wrap[1];
    c->closest = t->closest;
    memcpy(c->texels, t->texels, texture_bytes(t));
    if (t->hdr) {
        const size_t n = (size_t)t->w * t->h * 3 * sizeof *t->hdr;
        if (!(c->hdr = malloc(n))) {
            texture_destroy(c);
            return NULL;
        }
        memcpy(c->hdr, t->hdr, n);
    }
    return texture_with_alpha(c, t->alpha);
}

Texture *texture_with_alpha(Texture *t, const uint8_t *a)
{
    if (t && a && texture_keep_alpha(t, a)) {
        texture_destroy(t);
        return NULL;
    }
    return t;
}

int texture_keep_alpha(Texture *t, const uint8_t *a)
{
    const size_t n = (size_t)t->w * t->h;
    size_t i = 0;
    while (i < n && a[i] == 255)
        i++;
    free(t->alpha);
    t->alpha = NULL;
    if (i == n)
        return 0;
    if (!(t->alpha = malloc(n)))
        return -1;
    memcpy(t->alpha, a, n);
    return 0;
}

size_t texture_bytes(const Texture *t)
{
    size_t n = 0;
    for (uint32_t l = 0; l < t->levels; l++)
        n += (size_t)t->level[l].w * t->level[l].h * 3;
    return n;
}

void texture_destroy(Texture *t)
{
    if (!t)
        return;
    free(t->texels);
    free(t->data_texels);
    free(t->file);
    free(t->alpha);
    free(t->hdr);
    free(t);
}

vec3 texture_texel(const Texture *t, uint32_t l, uint32_t x, uint32_t y)
{
    const uint8_t *p = &t->level[l].rgb[3 * ((size_t)y * t->level[l].w + x)];
    return v3(srgb_decode8[p[0]], srgb_decode8[p[1]], srgb_decode8[p[2]]);
}

int texture_read_texels(Cursor *c, uint32_t w, uint32_t h, const char *name, Texture **out, Err *err)
{
    *out = NULL;
    size_t n = (size_t)w * h * 3;
    uint8_t *rgb = malloc(n);
    if (!rgb)
        return err_set(err, "%s: out of memory for a %ux%u texture", name, w, h);
    for (size_t i = 0; i < n; i++) {
        float v = cursor_f32(c);
        if (c->failed) {
            free(rgb);
            return err_set(err, "%s: the %ux%u texture's texels are cut short", name, w, h);
        }
        if (!(v >= 0.0f && v <= 1.0f)) { /* NaN fails too */
            free(rgb);
            return err_set(err, "%s: a texel value out of range", name);
        }
        rgb[i] = srgb_encode8((real)v);
    }
    *out = texture_from_rgb8(w, h, rgb);
    free(rgb);
    return *out ? 0 : err_set(err, "%s: out of memory for a %ux%u texture", name, w, h);
}

const char *const texture_filter_names[FILTER_COUNT + 1] = {"nearest", "bilinear", "trilinear", "anisotropic", NULL};

const char *texture_filter_name(TextureFilter f) { return (unsigned)f < FILTER_COUNT ? texture_filter_names[f] : "?"; }

int texture_filter_parse(const char *s, TextureFilter *out)
{
    int i = opt_word_index(texture_filter_names, FILTER_COUNT, s);
    if (i >= 0)
        *out = (TextureFilter)i;
    return i >= 0 ? 0 : -1;
}

int texture_grey(const Texture *t)
{
    const uint8_t *p = t->level[0].rgb;
    for (size_t i = 0, n = (size_t)t->w * t->h; i < n; i++, p += 3)
        if (p[0] != p[1] || p[1] != p[2])
            return 0;
    return 1;
}
