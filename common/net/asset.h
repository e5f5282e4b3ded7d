/* asset.h - the models and textures a scene names, as they travel: each
 * an ASSET payload (a model's .tmd image, a texture's byte form) named by
 * its SHA-256.  The server makes them once per scene; a client checks,
 * decodes and keeps them by hash for the rest of its connection, so an
 * UPDATE only names them (wire.h). */
#ifndef LANRAY_ASSET_H
#define LANRAY_ASSET_H

#include "model/model.h"
#include "net/msg.h"
#include "model/texture.h"
#include "scene/scene.h"

typedef struct {
    uint32_t kind; /* ASSET_MODEL or ASSET_TEXTURE */
    uint8_t hash[PROTO_HASH];
    uint8_t *data;
    size_t len;
} Asset;

/* Encodes one model (as a .tmd image) or texture and hashes it. */
int asset_make_model(const Model *m, Asset *out, Err *err);
int asset_make_texture(const Texture *t, Asset *out, Err *err);
void asset_free(Asset *a);
/* A scene's assets, its models then its textures (*n of them, an array
 * assets_free frees): made where the scene is read, off the loop that
 * serves frames (a million triangles' .tmd image and its hash take some
 * 0.4 s). */
int asset_make_scene(const Scene *s, Asset **out, uint32_t *n, Err *err);
void assets_free(Asset *a, uint32_t n);

/* Client side: decoded assets by hash. */
typedef struct AssetCache AssetCache;
AssetCache *asset_cache_create(void);
void asset_cache_destroy(AssetCache *c);
/* Checks the payload against its hash, decodes it and keeps it
 * (asset_decode then asset_cache_put). */
int asset_cache_add(AssetCache *c, uint32_t kind, const uint8_t hash[PROTO_HASH], const void *data, size_t len, Err *err);
int asset_cache_has(const AssetCache *c, const uint8_t hash[PROTO_HASH]);
/* An asset checked against its hash and decoded, not yet in a cache: the
 * slow half of asset_cache_add, which any thread may run (the client
 * decodes on a thread of its own while it renders). */
typedef struct {
    uint8_t hash[PROTO_HASH];
    uint32_t kind;
    Model *model;
    Texture *texture;
} AssetDecoded;
int asset_decode(uint32_t kind, const uint8_t hash[PROTO_HASH], const void *data, size_t len, AssetDecoded *out,
                 Err *err);
/* Keeps d in c, which owns it from then on (freed at once where c holds
 * that hash already); d is cleared either way. */
int asset_cache_put(AssetCache *c, AssetDecoded *d, Err *err);
void asset_decoded_free(AssetDecoded *d);
/* The decoded model or texture of that hash, or NULL. */
Model *asset_cache_model(const AssetCache *c, const uint8_t hash[PROTO_HASH]);
Texture *asset_cache_texture(const AssetCache *c, const uint8_t hash[PROTO_HASH]);

#endif
