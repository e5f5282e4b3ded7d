/* texture.h - RGB images for texture mapping, with their mip-maps.
 *
 * Texels are kept as the 8-bit sRGB codes image files store (3 bytes a
 * texel, a quarter of float RGB), decoded to linear light by a table when
 * sampled (srgb.h), so that filtering and shading work on light.  Below the
 * image are its mip-map levels, each half the size of the one above (a box
 * filter in linear light, rounded to sRGB codes), down to 1 x 1: a ray
 * whose footprint covers many texels reads a level where it covers about
 * one (texture_sample.c).  Texture coordinates repeat, clamp to the edge
 * or repeat mirrored, each axis its own way (glTF's samplers set them
 * apart); v = 0 is the bottom row, as in OBJ.
 *
 * A texture read from a PNG or JPEG file keeps the file's own bytes: a
 * .tmd and an ASSET carry those (texture_encode), so that a model with a
 * 78 KB image is not stored, or sent to every client, as 12 MB of floats;
 * the reader decodes them again into the same texels. */
#ifndef LANRAY_TEXTURE_H
#define LANRAY_TEXTURE_H

#include <stdint.h>
#include <stdio.h>

#include "base/cursor.h"
#include "base/err.h"
#include "base/vec.h"

#define TEXTURE_MAX_SIDE 16384u
#define TEXTURE_MAX_LEVELS 15 /* 16384 = 2^14: 15 levels down to 1 x 1 */

typedef enum { TEXTURE_RAW = 0, TEXTURE_PNG = 1, TEXTURE_JPEG = 2, TEXTURE_HDR = 3 } TextureCodec;

typedef struct {
    uint32_t w, h;
    uint8_t *rgb; /* 3 sRGB codes a texel, row-major, top row first */
} TextureLevel;

/* How a coordinate outside [0, 1] reads the image, along one axis:
 * tiles (OBJ's default, glTF's REPEAT), the edge's texels (MTL -clamp on,
 * glTF's CLAMP_TO_EDGE), or tiles flipped every other time (glTF's
 * MIRRORED_REPEAT).  The values are the byte form's (texture_encode). */
typedef enum { TEXTURE_REPEAT = 0, TEXTURE_CLAMP = 1, TEXTURE_MIRROR = 2 } TextureWrap;
#define TEXTURE_WRAP_COUNT 3

typedef struct {
    uint32_t w, h;   /* the image's size: level 0 */
    uint8_t wrap[2]; /* TextureWrap along u and along v */
    int closest;     /* magnified, texels are squares with sharp edges (pixel art, a
                      * checkerboard); else they blend bilinearly */
    uint8_t *alpha;  /* w x h opacities of the image (a PNG's alpha channel or tRNS, an
                      * embedded BGRA bitmap's), top row first; NULL: opaque (none, or
                      * all 255).  Read only by cutouts (texture_coverage) */
    uint32_t levels; /* 1 + the mip-map levels below the image */
    TextureLevel level[TEXTURE_MAX_LEVELS];
    uint8_t *texels; /* every level's texels, one block */
    /* a normal map's levels (texture_make_data_levels): level 0 the image,
     * those below averaging its codes as numbers; data_texels NULL: none */
    TextureLevel data_level[TEXTURE_MAX_LEVELS];
    uint8_t *data_texels;
    /* the image file's own bytes, kept for the byte form; NULL where the
     * texture came from elsewhere (PPM, generated, an embedded bitmap):
     * texture_encode then writes a PNG of the texels */
    uint8_t *file;
    size_t file_len;
    TextureCodec codec;
    /* a Radiance .hdr's light, 3 floats a texel, top row first (its sRGB
     * codes above are clipped to white); NULL for any other image */
    float *hdr;
} Texture;

/* How a lookup reads the texels: one texel of the image (nearest), the
 * bilinear blend of four (bilinear), the blend of two mip-map levels
 * chosen by the ray's footprint (trilinear: aliasing gone, detail blurred
 * along a floor seen edge-on), or several trilinear probes along the
 * footprint's long axis (anisotropic). */
typedef enum { FILTER_NEAREST = 0, FILTER_BILINEAR = 1, FILTER_TRILINEAR = 2, FILTER_ANISOTROPIC = 3 } TextureFilter;
#define FILTER_COUNT 4
/* The filters' names in TextureFilter order, NULL-terminated. */
extern const char *const texture_filter_names[];
const char *texture_filter_name(TextureFilter f);
int texture_filter_parse(const char *s, TextureFilter *out);

/* The footprint of a ray's sample on the texture: how u and v change from
 * one sample to the next across the image (x) and down it (y). */
typedef struct {
    real dudx, dvdx, dudy, dvdy;
} TexFootprint;

/* A texture of w x h from 8-bit sRGB RGB texels (copied), with its
 * mip-maps; NULL when out of memory. */
Texture *texture_from_rgb8(uint32_t w, uint32_t h, const uint8_t *rgb);
/* The same taking ownership of `file` (the image's own bytes, freed on
 * failure too). */
Texture *texture_from_file_rgb8(uint32_t w, uint32_t h, const uint8_t *rgb, uint8_t *file, size_t file_len,
                                TextureCodec codec);
void texture_destroy(Texture *t);
Texture *texture_copy(const Texture *t);
/* Gives t the w x h opacities a (copied; none kept where all are 255);
 * -1 when out of memory. */
int texture_keep_alpha(Texture *t, const uint8_t *a);
/* t (just made, or NULL) with the opacities a (none when NULL): t, or
 * NULL with t destroyed when out of memory.  What every reader with alpha
 * ends with: *out = texture_with_alpha(texture_from_rgb8(...), a). */
Texture *texture_with_alpha(Texture *t, const uint8_t *a);
/* How opaque the texel at (u, v) is, for a cutout's test (material.h):
 * the image's alpha, or, where it has none (a grey mask: MTL map_d), the
 * mean of the texel's codes; 0 to 1.  The nearest texel of the image
 * itself, with the texture's wrap modes: the same answer on every path
 * and at every distance, whatever the filter. */
real texture_coverage(const Texture *t, real u, real v);
/* Whether every texel of the image has equal red, green and blue (a grey
 * height map, not a normal map). */
int texture_grey(const Texture *t);
/* Whether w x h is a size a texture may have (1..TEXTURE_MAX_SIDE a side). */
static inline int texture_size_ok(uint32_t w, uint32_t h)
{
    return w >= 1 && h >= 1 && w <= TEXTURE_MAX_SIDE && h <= TEXTURE_MAX_SIDE;
}
/* Bytes the texels of all levels take. */
size_t texture_bytes(const Texture *t);

/* Reads an image file, by its first bytes (not its name): PNG, JPEG,
 * PPM/PGM, BMP, or TGA (which has no magic: by its name or its footer)
 * Radiance HDR (texture_hdr.c) (texture_file.c); another format is named in the error. */
int texture_read(const char *path, Texture **out, Err *err);
/* The same from bytes in memory (an image embedded in a glTF, say); `name`
 * labels errors.  The bytes are copied where they are kept. */
int texture_read_memory(const void *data, size_t len, const char *name, Texture **out, Err *err);
/* Reads a PPM (P3/P6) or PGM (P2/P5, replicated to grey RGB); `name` labels errors. */
int texture_read_stream(FILE *f, const char *name, Texture **out, Err *err);
/* A JPEG from an open stream (not closed) of `bytes` bytes; `name` labels errors. */
int texture_read_jpeg_stream(FILE *f, const char *name, size_t bytes, Texture **out, Err *err);
/* A TGA image (texture_tga.c) and a BMP one (texture_bmp.c) from bytes in
 * memory, as RGB texels; `name` labels errors. */
int texture_read_tga(const void *data, size_t len, const char *name, Texture **out, Err *err);
int texture_read_bmp(const void *data, size_t len, const char *name, Texture **out, Err *err);
/* A Radiance .hdr (texture_hdr.c): its light in Texture.hdr, its file's
 * bytes kept (codec TEXTURE_HDR). */
int texture_read_hdr(const void *data, size_t len, const char *name, Texture **out, Err *err);

/* The texture's byte form, what an ASSET and a .tmd carry (docs/tmd.md):
 * u32 w, h, flags (1: clamp both axes, 2: closest; bits 2-3 and 4-5, where
 * bit 0 is clear: u's and v's TextureWrap), codec (1 PNG, 2 JPEG, 3 Radiance HDR), byte
 * count, then the image's bytes, padded with zeros to a multiple of 4. */
int texture_encode(const Texture *t, Sink *out);
/* Reads one byte form from a cursor: the image is decoded and must be w x
 * h; `name` labels errors. */
int texture_read_form(Cursor *c, const char *name, Texture **out, Err *err);
/* A whole payload that is one byte form and nothing else (an ASSET). */
int texture_decode(const void *data, size_t len, const char *name, Texture **out, Err *err);
/* The texels of a w x h texture as .tmd versions 2 to 4 stored them: f32
 * rgb, linear light, each in [0, 1]; the caller has checked the size and
 * that the cursor holds them.  They are kept as the nearest sRGB codes. */
int texture_read_texels(Cursor *c, uint32_t w, uint32_t h, const char *name, Texture **out, Err *err);

/* The linear colour of texel (x, y) of level l. */
vec3 texture_texel(const Texture *t, uint32_t l, uint32_t x, uint32_t y);
/* The colour at (u, v): with `fp` NULL, one lookup in the image (nearest
 * or bilinear, as for a trilinear or anisotropic filter); else filtered
 * over the footprint (texture_sample.c).  Non-finite coordinates read
 * texel (0, 0). */
vec3 texture_sample(const Texture *t, real u, real v, const TexFootprint *fp, TextureFilter filter);
/* Gives t the mip-map levels a data texture reads (texture_normal,
 * texture_fractions): the codes averaged as numbers, not as light (the
 * sRGB levels would bend an average of normals towards the brighter
 * codes, and a metal share or an occlusion towards the larger).  Made
 * once, when a scene is prepared (model_prepare_simd), for the textures
 * that are normal maps, metal-roughness or occlusion textures; -1 when out
 * of memory. */
int texture_make_data_levels(Texture *t);
/* A normal map's vector at (u, v): the texels read as data, each code c
 * as c / 255 x 2 - 1 (not as sRGB); over the footprint fp (NULL: at the
 * point) trilinearly in the data levels where t has them, else blended
 * bilinearly in the image itself; the nearest texel of a `closest`
 * texture.  Not normalised (an average of normals is shorter).
 * Non-finite coordinates read texel (0, 0). */
vec3 texture_normal(const Texture *t, real u, real v, const TexFootprint *fp);
/* A data texture's channels at (u, v) as fractions, each code c as
 * c / 255 (not as sRGB: a metal-roughness or occlusion texture's), read
 * as texture_normal reads its codes: over the footprint fp in the data
 * levels where t has them, else at the point. */
vec3 texture_fractions(const Texture *t, real u, real v, const TexFootprint *fp);

#endif
