/* import_texture.c - see import_texture.h. */
#include "model/import_texture.h"

#include <assimp/material.h>
#include <assimp/scene.h>
#include <assimp/texture.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/fileio.h"

/* An image beside a model may be at most this big (as texture_read). */
#define IMPORT_TEX_FILE_BYTES ((size_t)1 << 30)
/* glTF's sampler filter NEAREST (the OpenGL enum) */
#define GL_NEAREST 9728

static ImportTex *add(ImportTexList *l, const char *key)
{
    if (l->n == IMPORT_TEX_MAX)
        return NULL;
    if (l->n == l->cap) {
        uint32_t cap = l->cap ? 2 * l->cap : 8;
        ImportTex *t = realloc(l->t, cap * sizeof *t);
        if (!t)
            return NULL;
        l->t = t, l->cap = cap;
    }
    ImportTex *t = &l->t[l->n++];
    memset(t, 0, sizeof *t);
    snprintf(t->key, sizeof t->key, "%.500s", key);
    return t;
}

/* An embedded texture ("*N"): compressed (an image file's bytes, mHeight
 * 0) or w x h BGRA texels. */
static void embedded(const struct aiScene *sc, const char *key, ImportTex *t)
{
    char *end;
    errno = 0;
    unsigned long i = strtoul(key + 1, &end, 10);
    if (errno || *end || key[1] == 0 || i >= sc->mNumTextures || !sc->mTextures[i]) {
        t->kind = IMPORT_TEX_MISSING;
        snprintf(t->name, sizeof t->name, "embedded image %.400s: the file has no such image", key);
        return;
    }
    const struct aiTexture *tx = sc->mTextures[i];
    if (tx->mHeight == 0) {
        t->kind = IMPORT_TEX_FILE;
        t->bytes = (const uint8_t *)tx->pcData;
        t->len = tx->mWidth;
        char hint[sizeof tx->achFormatHint + 1];
        memcpy(hint, tx->achFormatHint, sizeof tx->achFormatHint);
        hint[sizeof tx->achFormatHint] = 0;
        snprintf(t->name, sizeof t->name, "embedded image %lu (%s)", i, hint[0] ? hint : "?");
    } else {
        t->kind = IMPORT_TEX_BGRA;
        t->w = tx->mWidth;
        t->h = tx->mHeight;
        t->bytes = (const uint8_t *)tx->pcData;
        t->len = (size_t)tx->mWidth * tx->mHeight * 4;
        snprintf(t->name, sizeof t->name, "embedded image %lu (%ux%u texels)", i, tx->mWidth, tx->mHeight);
    }
}

/* A texture file a path names, beside the model. */
static void beside(const char *model, const char *key, ImportTex *t)
{
    char dir[4096], path[4096];
    if (!model) {
        t->kind = IMPORT_TEX_MISSING;
        snprintf(t->name, sizeof t->name, "'%.400s': a model read from memory has no directory to find it in", key);
        return;
    }
    file_dirname(model, dir, sizeof dir);
    if (file_find_near(dir, key, path, sizeof path) == FILE_NOT_FOUND) {
        t->kind = IMPORT_TEX_MISSING;
        snprintf(t->name, sizeof t->name, "'%.400s': not found beside the model", key);
        return;
    }
    char *data;
    size_t len;
    Err e = {{0}};
    if (file_read_all(path, IMPORT_TEX_FILE_BYTES, &data, &len, &e)) {
        t->kind = IMPORT_TEX_MISSING;
        snprintf(t->name, sizeof t->name, "'%.200s': %.290s", key, e.msg);
        return;
    }
    t->kind = IMPORT_TEX_FILE;
    t->own = (uint8_t *)data;
    t->bytes = t->own;
    t->len = len;
    snprintf(t->name, sizeof t->name, "%.500s", path);
}

/* Assimp's wrap mode along one axis as lanray's: a decal (no texture
 * outside [0, 1]) repeats, as it did before modes were read apart. */
static TextureWrap wrap_of(enum aiTextureMapMode m)
{
    return m == aiTextureMapMode_Clamp ? TEXTURE_CLAMP : m == aiTextureMapMode_Mirror ? TEXTURE_MIRROR : TEXTURE_REPEAT;
}

int32_t import_tex_find(const struct aiScene *sc, const struct aiMaterial *am, ImportTexRole role, const char *model,
                        ImportTexList *l)
{
    /* glTF's base colour is also its diffuse texture in Assimp 5.2; other
     * formats name only the diffuse one.  A normal map (glTF's
     * normalTexture, FBX's NormalMap) is of type NORMALS, an emission
     * texture (glTF's emissiveTexture) EMISSIVE */
    static const enum aiTextureType colour[] = {aiTextureType_DIFFUSE, aiTextureType_BASE_COLOR, aiTextureType_NONE};
    static const enum aiTextureType normals[] = {aiTextureType_NORMALS, aiTextureType_NONE};
    static const enum aiTextureType emission[] = {aiTextureType_EMISSIVE, aiTextureType_NONE};
    /* glTF's metallicRoughnessTexture: UNKNOWN in Assimp 5.2 (and METALNESS) */
    static const enum aiTextureType metal[] = {aiTextureType_UNKNOWN, aiTextureType_METALNESS, aiTextureType_NONE};
    /* glTF's occlusionTexture: LIGHTMAP in Assimp 5.2 */
    static const enum aiTextureType occlusion[] = {aiTextureType_LIGHTMAP, aiTextureType_AMBIENT_OCCLUSION,
                                                   aiTextureType_NONE};
    const enum aiTextureType *types = role == IMPORT_TEX_NORMALS     ? normals
                                      : role == IMPORT_TEX_EMISSION  ? emission
                                      : role == IMPORT_TEX_METAL     ? metal
                                      : role == IMPORT_TEX_OCCLUSION ? occlusion
                                                                     : colour;
    struct aiString path;
    enum aiTextureType type = aiTextureType_NONE;
    enum aiTextureMapMode mode[2] = {aiTextureMapMode_Wrap, aiTextureMapMode_Wrap};
    unsigned uv = 0; /* the texture coordinates' set: the first is the only one read (a colour
                      * texture on another is read on it, as before; the others are not) */
    for (size_t k = 0; types[k] != aiTextureType_NONE && type == aiTextureType_NONE; k++)
        if (aiGetMaterialTextureCount(am, types[k]) > 0 &&
            aiGetMaterialTexture(am, types[k], 0, &path, NULL, &uv, NULL, NULL, mode, NULL) == aiReturn_SUCCESS &&
            path.length > 0 && (uv == 0 || role == IMPORT_TEX_COLOUR))
            type = types[k];
    if (type == aiTextureType_NONE)
        return -1;
    uint32_t flags = (uint32_t)wrap_of(mode[0]) << IMPORT_TEX_WRAP_U | (uint32_t)wrap_of(mode[1]) << IMPORT_TEX_WRAP_V;
    int mag = 0;
    if (aiGetMaterialIntegerArray(am, "$tex.mappingfiltermag", (unsigned)type, 0, &mag, NULL) == aiReturn_SUCCESS &&
        mag == GL_NEAREST)
        flags |= IMPORT_TEX_CLOSEST;
    /* one texture an image and sampler: glTF materials may share an image
     * and read it with samplers of their own */
    const char *key = path.data;
    for (uint32_t i = 0; i < l->n; i++)
        if (strcmp(l->t[i].key, key) == 0 && l->t[i].flags == flags)
            return (int32_t)i;
    ImportTex *t = add(l, key);
    if (!t)
        return -1;
    if (key[0] == '*')
        embedded(sc, key, t);
    else
        beside(model, key, t);
    t->flags = flags;
    return (int32_t)(l->n - 1);
}

int32_t import_tex_white(ImportTexList *l)
{
    static const uint8_t white[4] = {255, 255, 255, 255};
    for (uint32_t i = 0; i < l->n; i++)
        if (l->t[i].key[0] == 0) /* a material's path is never empty (import_tex_find) */
            return (int32_t)i;
    ImportTex *t = add(l, "");
    if (!t)
        return -1;
    t->kind = IMPORT_TEX_BGRA;
    t->w = t->h = 1;
    t->bytes = white;
    t->len = sizeof white;
    snprintf(t->name, sizeof t->name, "a metal's uniform factors (one white texel)");
    return (int32_t)(l->n - 1);
}

void import_tex_free(ImportTexList *l)
{
    for (uint32_t i = 0; i < l->n; i++)
        free(l->t[i].own);
    free(l->t);
    memset(l, 0, sizeof *l);
}

/* The answer's form: u32 count, then each: u32 kind, w, h, flags, name
 * length, byte count; the name; the bytes. */
void import_tex_send(Sink *o, const ImportTexList *l)
{
    sink_u32(o, l->n);
    for (uint32_t i = 0; i < l->n; i++) {
        const ImportTex *t = &l->t[i];
        size_t nl = strlen(t->name), len = t->kind == IMPORT_TEX_MISSING ? 0 : t->len;
        if (len > UINT32_MAX)
            len = 0;
        uint32_t head[6] = {t->kind, t->w, t->h, t->flags, (uint32_t)nl, (uint32_t)len};
        sink_put(o, head, sizeof head);
        sink_put(o, t->name, nl);
        sink_put(o, t->bytes, len);
    }
}

/* w x h BGRA texels as a texture, its alphas kept for cutouts. */
static Texture *from_bgra(uint32_t w, uint32_t h, const uint8_t *bgra)
{
    uint8_t *rgb = malloc((size_t)w * h * 4), *a = rgb + (size_t)w * h * 3;
    if (!rgb)
        return NULL;
    for (size_t i = 0; i < (size_t)w * h; i++) {
        rgb[3 * i] = bgra[4 * i + 2];
        rgb[3 * i + 1] = bgra[4 * i + 1];
        rgb[3 * i + 2] = bgra[4 * i];
        a[i] = bgra[4 * i + 3];
    }
    Texture *t = texture_with_alpha(texture_from_rgb8(w, h, rgb), a);
    free(rgb);
    return t;
}

/* Whether a texture's flags are ones import_tex_find writes. */
static int flags_ok(uint32_t f)
{
    return f >> 5 == 0 && (f >> IMPORT_TEX_WRAP_U & 3) < TEXTURE_WRAP_COUNT && (f >> IMPORT_TEX_WRAP_V & 3) < TEXTURE_WRAP_COUNT;
}

int import_tex_receive(Cursor *c, const char *name, const ObjOptions *opt, unsigned long *warnings,
                       unsigned long *missing, Mesh *out, int32_t *map, uint32_t *count, Err *err)
{
    uint32_t n = cursor_u32(c);
    if (c->failed || n > IMPORT_TEX_MAX)
        return err_set(err, "%s: the importer's answer is implausible (textures)", name);
    *count = n;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t head[6];
        map[i] = -1;
        if (cursor_get(c, head, sizeof head) || head[0] > IMPORT_TEX_MISSING || head[4] >= IMPORT_TEX_NAME ||
            !flags_ok(head[3]) || (size_t)head[4] + head[5] > c->left)
            return err_set(err, "%s: the importer's answer is implausible (texture %u)", name, i);
        char what[IMPORT_TEX_NAME];
        cursor_get(c, what, head[4]);
        what[head[4]] = 0;
        const uint8_t *bytes = c->p;
        c->p += head[5], c->left -= head[5];
        char label[IMPORT_TEX_NAME + 1100];
        snprintf(label, sizeof label, "%.1000s: %s", name, what);
        Texture *t = NULL;
        Err terr = {{0}};
        if (head[0] == IMPORT_TEX_MISSING)
            err_set(&terr, "%s: texture %s", name, what);
        else if (head[0] == IMPORT_TEX_FILE)
            texture_read_memory(bytes, head[5], label, &t, &terr);
        else if (!texture_size_ok(head[1], head[2]) || (uint64_t)head[1] * head[2] * 4 != head[5])
            err_set(&terr, "%s: a %ux%u bitmap of %u bytes", label, head[1], head[2], head[5]);
        else if (!(t = from_bgra(head[1], head[2], bytes)))
            err_set(&terr, "%s: out of memory", label);
        if (!t) {
            (*missing)++;
            char msg[sizeof terr.msg + 64];
            snprintf(msg, sizeof msg, "%s: the material is untextured", terr.msg);
            if (obj_warning(opt, warnings, err, msg))
                return -1;
            continue;
        }
        t->wrap[0] = (uint8_t)(head[3] >> IMPORT_TEX_WRAP_U & 3), t->wrap[1] = (uint8_t)(head[3] >> IMPORT_TEX_WRAP_V & 3);
        t->closest = (head[3] & IMPORT_TEX_CLOSEST) != 0;
        uint32_t id;
        if (mesh_add_texture(out, t, &id, err))
            return -1;
        map[i] = (int32_t)id;
    }
    return 0;
}
