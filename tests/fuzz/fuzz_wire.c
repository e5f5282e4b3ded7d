/* fuzz_wire.c - what a client decodes from the server: ASSET payloads,
 * serialised scenes and frames' views.  The first byte picks: an asset
 * (model or texture, below 32) added to a cache that already holds the
 * default scene's assets; a view ('V') decoded and, when accepted, the
 * default scene rendered with it; or a scene decoded against that cache
 * and, when accepted, rendered. */
#include <assert.h>
#include <stdlib.h>

#include "fuzz.h"
#include "net/auth.h"
#include "render/render.h"
#include "scene/scene_default.h"
#include "net/wire.h"

static AssetCache *cache;
static RenderPool *pool;
static Scene *base;        /* the default scene */
static World *base_world;  /* and its world, which a view is set on */

static void setup(void)
{
    Scene *s;
    BvhOptions opt = bvh_options_default(BVH_SAH);
    cache = asset_cache_create();
    pool = render_pool_create(1, NULL);
    if (!cache || !pool || scene_default(&s, &opt, NULL))
        abort();
    for (uint32_t i = 0; i < s->model_count; i++) {
        Asset a;
        asset_make_model(s->models[i], &a, NULL);
        asset_cache_add(cache, ASSET_MODEL, a.hash, a.data, a.len, NULL);
        asset_free(&a);
    }
    for (uint32_t i = 0; i < s->texture_count; i++) {
        Asset a;
        asset_make_texture(s->textures[i], &a, NULL);
        asset_cache_add(cache, ASSET_TEXTURE, a.hash, a.data, a.len, NULL);
        asset_free(&a);
    }
    base = s;
    base_world = world_build(base, NULL, NULL);
    if (!base_world)
        abort();
}

/* The most bytes a pixel: a batch's sums with guides (render/progressive.h). */
#define PIXEL_MOST (PROG_MAX * sizeof(real))

/* A frame's view: decoded, then the default scene rendered with it. */
static void view_one(const uint8_t *data, size_t size)
{
    View v;
    if (wire_decode_view(data, size, &v, NULL))
        return;
    /* bounded work per input (a batch of a path-traced still's samples: of 2x2) */
    v.settings.aa = v.settings.batch ? 2 : 1;
    World *w = world_with_view(base_world, &v, NULL);
    uint8_t px[8 * 6 * PIXEL_MOST]; /* as render_pixel_bytes says */
    if (w)
        render_lines(pool, w, 8, 6, 0, 6, px, NULL, NULL);
    world_destroy(w);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (!cache)
        setup();
    if (size < 1)
        return 0;
    if (data[0] == 'V') {
        view_one(data + 1, size - 1);
        return 0;
    }
    if (data[0] < 32) {
        /* an asset: the hash is computed, so the payload itself gets decoded */
        AssetCache *c = asset_cache_create();
        uint8_t hash[PROTO_HASH];
        auth_hash(data + 1, size - 1, hash);
        asset_cache_add(c, data[0] & 1 ? ASSET_MODEL : ASSET_TEXTURE, hash, data + 1, size - 1, NULL);
        asset_cache_destroy(c);
        return 0;
    }
    Scene *s;
    if (wire_decode_scene(data + 1, size - 1, cache, &s, NULL) == 0) {
        uint8_t px[8 * 6 * PIXEL_MOST]; /* RGB8, RGBE, with guides, or a batch's sums */
        assert(render_pixel_bytes(&s->settings) * 8 * 6 <= sizeof px);
        s->settings.aa = s->settings.batch ? 2 : 1; /* bounded work per input */
        World *w = world_build(s, NULL, NULL);
        if (w)
            render_lines(pool, w, 8, 6, 0, 6, px, NULL, NULL);
        world_destroy(w);
        scene_destroy(s);
    }
    return 0;
}
