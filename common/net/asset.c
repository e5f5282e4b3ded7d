/* asset.c - see asset.h. */
#include "net/asset.h"

#include <stdlib.h>
#include <string.h>

#include "net/auth.h"
#include "model/tmd.h"

typedef AssetDecoded CacheEntry;

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

/* 0 where the payload is the one its hash names. */
static int check_hash(const uint8_t hash[PROTO_HASH], const void *data, size_t len, Err *err)
{
    uint8_t h[PROTO_HASH];
    auth_hash(data, len, h);
    return memcmp(h, hash, PROTO_HASH) ? err_set(err, "asset: payload does not match its hash") : 0;
}

int asset_decode(uint32_t kind, const uint8_t hash[PROTO_HASH], const void *data, size_t len, AssetDecoded *out,
                 Err *err)
{
    memset(out, 0, sizeof *out);
    if (check_hash(hash, data, len, err))
        return -1;
    memcpy(out->hash, hash, PROTO_HASH);
    out->kind = kind;
    if (kind == ASSET_MODEL)
        return tmd_decode(data, len, "model asset", &out->model, err);
    if (kind == ASSET_TEXTURE)
        return texture_decode(data, len, "asset", &out->texture, err);
    return err_set(err, "asset: unknown kind %u", kind);
}

void asset_decoded_free(AssetDecoded *d)
{
    model_destroy(d->model);
    texture_destroy(d->texture);
    memset(d, 0, sizeof *d);
}

int asset_cache_put(AssetCache *c, AssetDecoded *d, Err *err)
{
    if (cache_find(c, d->hash, d->kind)) {
        asset_decoded_free(d);
        return 0;
    }
    if (c->n >= ASSET_CACHE_MAX) {
        asset_decoded_free(d);
        return err_set(err, "asset: more than %u assets", ASSET_CACHE_MAX);
    }
    CacheEntry *p = realloc(c->e, (c->n + 1) * sizeof *p);
    if (!p) {
        asset_decoded_free(d);
        return err_set(err, "asset: out of memory");
    }
    c->e = p;
    c->e[c->n++] = *d;
    memset(d, 0, sizeof *d);
    return 0;
}

int asset_cache_add(AssetCache *c, uint32_t kind, const uint8_t hash[PROTO_HASH], const void *data, size_t len, Err *err)
{
    if (cache_find(c, hash, kind)) /* still checked: a payload that lies is an error either way */
        return check_hash(hash, data, len, err);
    AssetDecoded d;
    if (asset_decode(kind, hash, data, len, &d, err)) {
        asset_decoded_free(&d);
        return -1;
    }
    return asset_cache_put(c, &d, err);
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

void assets_free(Asset *a, uint32_t n)
{
    for (uint32_t i = 0; a && i < n; i++)
        asset_free(&a[i]);
    free(a);
}

int asset_make_scene(const Scene *s, Asset **out, uint32_t *n, Err *err)
{
    *n = s->model_count + s->texture_count;
    *out = calloc(*n + 1, sizeof **out);
    if (!*out)
        return err_set(err, "out of memory");
    int rc = 0;
    for (uint32_t i = 0; i < s->model_count && !rc; i++)
        rc = asset_make_model(s->models[i], &(*out)[i], err);
    for (uint32_t i = 0; i < s->texture_count && !rc; i++)
        rc = asset_make_texture(s->textures[i], &(*out)[s->model_count + i], err);
    for (uint32_t i = 0; i < *n && !rc; i++)
        if ((*out)[i].len > PROTO_ASSET_MAX)
            rc = err_set(err, "%s %u of the scene is %.2f GiB as sent to the clients (%u MiB at most)",
                         i < s->model_count ? "model" : "texture", i < s->model_count ? i + 1 : i - s->model_count + 1,
                         (double)(*out)[i].len / (1u << 30), PROTO_ASSET_MAX >> 20);
    if (rc) {
        assets_free(*out, *n);
        *out = NULL, *n = 0;
    }
    return rc;
}
