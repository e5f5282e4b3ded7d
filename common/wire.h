/* wire.h - the scene on the wire, and the assets it refers to.
 *
 * A scene is serialised once per frame (docs/protocol.md): header with magic,
 * version and byte-order mark, then only what the scene has.  Models and
 * textures are not inside: the scene names them by the SHA-256 of their
 * ASSET payload, which a client receives once per connection and caches, so
 * an UPDATE for a scene with millions of triangles stays small. */
#ifndef LANRAY_WIRE_H
#define LANRAY_WIRE_H

#include "cursor.h"
#include "msg.h"
#include "scene.h"

#define WIRE_MAGIC 0x4353524cu /* "LRSC" */
#define WIRE_VERSION 2u /* 2: the output encoding (linear or sRGB), a plane's texture mapping */

typedef struct {
    uint32_t kind; /* ASSET_MODEL or ASSET_TEXTURE */
    uint8_t hash[PROTO_HASH];
    uint8_t *data;
    size_t len;
} Asset;

/* Encodes one model (as a .tmd image) or texture and hashes it. */
int wire_asset_model(const Model *m, Asset *out, Err *err);
int wire_asset_texture(const Texture *t, Asset *out, Err *err);
void wire_asset_free(Asset *a);

/* Serialises s; model_assets[i] / texture_assets[i] are the assets of
 * s->models[i] / s->textures[i]. */
int wire_encode_scene(const Scene *s, const Asset *model_assets, const Asset *texture_assets, Sink *out, Err *err);

/* Client side: decoded assets by hash. */
typedef struct AssetCache AssetCache;
AssetCache *asset_cache_create(void);
void asset_cache_destroy(AssetCache *c);
/* Checks the payload against its hash, decodes it and keeps it. */
int asset_cache_add(AssetCache *c, uint32_t kind, const uint8_t hash[PROTO_HASH], const void *data, size_t len, Err *err);
int asset_cache_has(const AssetCache *c, const uint8_t hash[PROTO_HASH]);

/* Decodes a scene whose models and textures are in the cache; the scene
 * borrows them and comes back prepared. */
int wire_decode_scene(const void *data, size_t len, const AssetCache *cache, Scene **out, Err *err);

#endif
