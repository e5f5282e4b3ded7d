/* asset.c - see asset.h. */
#include "net/asset.h"

#include <stdlib.h>
#include <string.h>

#include "net/auth.h"
#include "model/tmd.h"

typedef struct {
    uint8_t hash[PROTO_HASH];
    uint32_t kind;
    Model *model;
    Texture *texture;
} CacheEntry;

struct AssetCache {
    CacheEntry *e;
    uint32_t n, cap;
};

AssetCache *asset_cache_create(void) { return calloc(1, sizeof(AssetCache)); }

void asset_cache_destroy(AssetCache *c)
{
    if (!c)
        return;
    for (uint32_t i = 0; i < c->n; i++) {
        model_destroy(c->e[i].model);
        texture_destroy(c->e[i].texture);
    }
    free(c->e);
    free(c);
}

static const CacheEntry *cache_find(const AssetCache *c, const uint8_t hash[PROTO_HASH], uint32_t kind)
{
    for (uint32_t i = 0; i < c->n; i++)
        if (memcmp(c->e[i].hash, hash, PROTO_HASH) == 0 && (kind == 0 || c->e[i].kind == kind))
            return &c->e[i];
    return NULL;
}

int asset_cache_has(const AssetCache *c, const uint8_t hash[PROTO_HASH]) { return cache_find(c, hash, 0) != NULL; }

Model *asset_cache_model(const AssetCache *c, const uint8_t hash[PROTO_HASH])
{
    const CacheEntry *e = cache_find(c, hash, ASSET_MODEL);
    return e ? e->model : NULL;
}

Texture *asset_cache_texture(const AssetCache *c, const uint8_t hash[PROTO_HASH])
{
    const CacheEntry *e = cache_find(c, hash, ASSET_TEXTURE);
    return e ? e->texture : NULL;
}

#define ASSET_CACHE_MAX 4096u

int asset_cache_add(AssetCache *c, uint32_t kind, const uint8_t hash[PROTO_HASH], const void *data, size_t len, Err *err)
{
    uint8_t h[PROTO_HASH];
    auth_hash(data, len, h);
    if (memcmp(h, hash, PROTO_HASH) != 0)
        return err_set(err, "asset: payload does not match its hash");
    if (cache_find(c, hash, kind))
        return 0;
    if (c->n >= ASSET_CACHE_MAX)
        return err_set(err, "asset: more than %u assets", ASSET_CACHE_MAX);
    CacheEntry e;
    memset(&e, 0, sizeof e);
    memcpy(e.hash, hash, PROTO_HASH);
    e.kind = kind;
    if (kind == ASSET_MODEL) {
        if (tmd_decode(data, len, "model asset", &e.model, err))
            return -1;
    } else if (kind == ASSET_TEXTURE) {
        if (texture_decode(data, len, "asset", &e.texture, err))
            return -1;
    } else {
        return err_set(err, "asset: unknown kind %u", kind);
    }
    CacheEntry *p = realloc(c->e, (c->n + 1) * sizeof *p);
    if (!p) {
        model_destroy(e.model);
        texture_destroy(e.texture);
        return err_set(err, "asset: out of memory");
    }
    c->e = p;
    c->e[c->n++] = e;
    return 0;
}

int asset_make_model(const Model *m, Asset *out, Err *err)
{
    memset(out, 0, sizeof *out);
    out->kind = ASSET_MODEL;
    void *data;
    /* the model's own numbers: float64 in a double build, which float32 would round */
    if (tmd_encode(m, sizeof(real) > sizeof(float), &data, &out->len, err))
        return -1;
    out->data = data;
    auth_hash(out->data, out->len, out->hash);
    return 0;
}

int asset_make_texture(const Texture *t, Asset *out, Err *err)
{
    memset(out, 0, sizeof *out);
    out->kind = ASSET_TEXTURE;
    Sink s = {0};
    if (texture_encode(t, &s) || s.failed) {
        sink_free(&s);
        return err_set(err, "asset: out of memory");
    }
    out->data = s.data;
    out->len = s.len;
    auth_hash(out->data, out->len, out->hash);
    return 0;
}

void asset_free(Asset *a)
{
    free(a->data);
    memset(a, 0, sizeof *a);
}
