/* test_wire.c - scenes through the wire format and the asset cache. */
#include "helpers.h"
#include "worlds.h"

#include "net/auth.h"
#include "render/render.h"
#include "scene/scene_default.h"
#include "scene/scene_parse.h"
#include "model/tmd.h"
#include "net/wire.h"

/* A scene's assets as the server makes them (asset_make_scene: models,
 * then textures) and its serialised description. */
typedef struct {
    Asset *models, *textures; /* one array: textures = models + model_count */
    uint32_t n;
    uint8_t *blob;
    size_t len;
} Encoded;

static Encoded encode(const Scene *s)
{
    Encoded e;
    assert_int_equal(asset_make_scene(s, &e.models, &e.n, NULL), 0);
    e.textures = e.models + s->model_count;
    Sink sink = {0};
    assert_int_equal(wire_encode_scene(s, e.models, e.textures, &sink, NULL), 0);
    e.blob = sink.data;
    e.len = sink.len;
    return e;
}

static AssetCache *cache_of(const Encoded *e)
{
    AssetCache *c = asset_cache_create();
    for (uint32_t i = 0; i < e->n; i++)
        assert_int_equal(asset_cache_add(c, e->models[i].kind, e->models[i].hash, e->models[i].data, e->models[i].len, NULL), 0);
    return c;
}

static void free_encoded(Encoded *e)
{
    assets_free(e->models, e->n);
    free(e->blob);
}

static void assert_same_pixels(Scene *a, Scene *b)
{
    RenderPool *p = render_pool_create(2, NULL);
    enum { W = 64, H = 48 };
    uint8_t pa[W * H * 3], pb[W * H * 3];
    assert_int_equal(render_lines(p, world_now(a), W, H, 0, H, pa, NULL, NULL), 0);
    assert_int_equal(render_lines(p, world_now(b), W, H, 0, H, pb, NULL, NULL), 0);
    assert_memory_equal(pa, pb, sizeof pa);
    render_pool_destroy(p);
}

#define SAME(a, b) assert_memory_equal(&(a), &(b), sizeof(a))

/* What a world derives from its description, bit for bit. */
static void assert_worlds_identical(const World *a, const World *b)
{
    assert_int_equal(a->features, b->features);
    assert_int_equal(a->plane_count, b->plane_count);
    for (uint32_t i = 0; i < a->plane_count; i++) {
        const WorldPlane *x = &a->planes[i], *y = &b->planes[i];
        SAME(x->point, y->point);
        SAME(x->unit, y->unit);
        SAME(x->tu, y->tu);
        SAME(x->tv, y->tv);
        assert_int_equal(x->material, y->material);
    }
    assert_int_equal(a->instance_count, b->instance_count);
    for (uint32_t i = 0; i < a->instance_count; i++) {
        const WorldInstance *x = &a->instances[i], *y = &b->instances[i];
        SAME(x->rot, y->rot);
        SAME(x->translate, y->translate);
        SAME(x->scale, y->scale);
        assert_int_equal(x->identity, y->identity);
        assert_int_equal(x->material, y->material);
    }
    assert_int_equal(a->light_count, b->light_count);
    for (uint32_t i = 0; i < a->light_count; i++) {
        const WorldLight *x = &a->lights[i], *y = &b->lights[i];
        SAME(x->axis, y->axis);
        SAME(x->cos_outer, y->cos_outer);
        SAME(x->cos_inner, y->cos_inner);
        assert_int_equal(x->lamp_first, y->lamp_first);
        assert_int_equal(x->lamp_count, y->lamp_count);
    }
    assert_int_equal(a->lamp_total, b->lamp_total);
    if (a->lamp_total)
        assert_memory_equal(a->lamps, b->lamps, a->lamp_total * sizeof *a->lamps);
    assert_int_equal(a->tree->node_count, b->tree->node_count);
    for (uint32_t i = 0; i < a->tree->node_count; i++) {
        SAME(a->tree->nodes[i].bmin, b->tree->nodes[i].bmin);
        SAME(a->tree->nodes[i].bmax, b->tree->nodes[i].bmax);
    }
}

/* The worlds of a and b, built alone, are the same bits; so is b's built
 * with a's as the previous world (which gives it a's top-level BVH). */
static void assert_same_worlds(const Scene *a, const Scene *b)
{
    World *wa = world_build(a, NULL, NULL), *wb = world_build(b, NULL, NULL), *wr = world_build(b, wa, NULL);
    assert_non_null(wa);
    assert_non_null(wb);
    assert_non_null(wr);
    assert_worlds_identical(wa, wb);
    assert_worlds_identical(wa, wr);
    assert_true(world_shares_top(wr, wa) || wa->top == NULL);
    world_destroy(wa);
    world_destroy(wb);
    world_destroy(wr);
}

/* Every number rendering reads, given and derived, bit for bit: a client
 * must render from exactly what lanray-render does (a difference of one ulp
 * shows as a pixel one level off somewhere in a large frame). */
static void assert_scenes_identical(const Scene *a, const Scene *b)
{
    SAME(a->camera, b->camera);
    SAME(a->ambient, b->ambient);
    SAME(a->background, b->background);
    SAME(a->environment, b->environment);
    assert_int_equal(a->settings.linear, b->settings.linear);
    assert_int_equal(a->material_count, b->material_count);
    for (uint32_t i = 0; i < a->material_count; i++) {
        SAME(a->materials[i].kd, b->materials[i].kd);
        SAME(a->materials[i].ks, b->materials[i].ks);
        SAME(a->materials[i].shininess, b->materials[i].shininess);
        assert_int_equal(a->materials[i].texture, b->materials[i].texture);
    }
    assert_int_equal(a->plane_count, b->plane_count);
    for (uint32_t i = 0; i < a->plane_count; i++) {
        SAME(a->planes[i].point, b->planes[i].point);
        SAME(a->planes[i].normal, b->planes[i].normal);
        SAME(a->planes[i].uv_scale, b->planes[i].uv_scale);
        SAME(a->planes[i].uv_rotate, b->planes[i].uv_rotate);
    }
    assert_int_equal(a->sphere_count, b->sphere_count);
    for (uint32_t i = 0; i < a->sphere_count; i++) {
        SAME(a->spheres[i].centre, b->spheres[i].centre);
        SAME(a->spheres[i].radius, b->spheres[i].radius);
    }
    assert_int_equal(a->tri_count, b->tri_count);
    if (a->tri_count)
        assert_memory_equal(a->tris, b->tris, a->tri_count * sizeof *a->tris);
    for (uint32_t i = 0; i < a->tri_count; i++) {
        const TriAttr *x = &a->tri_attrs[i], *y = &b->tri_attrs[i];
        assert_int_equal(x->smooth, y->smooth);
        assert_int_equal(x->textured, y->textured);
        if (x->smooth)
            SAME(x->n, y->n);
        if (x->textured)
            SAME(x->uv, y->uv);
    }
    assert_int_equal(a->instance_count, b->instance_count);
    for (uint32_t i = 0; i < a->instance_count; i++) {
        const Instance *x = &a->instances[i], *y = &b->instances[i];
        SAME(x->translate, y->translate);
        SAME(x->rotate, y->rotate);
        SAME(x->scale, y->scale);
        assert_int_equal(x->material, y->material);
    }
    assert_int_equal(a->model_count, b->model_count);
    for (uint32_t i = 0; i < a->model_count; i++) { /* the models' own numbers: their encodings */
        void *x, *y;
        size_t xl, yl;
        assert_int_equal(tmd_encode(a->models[i], 1, &x, &xl, NULL), 0);
        assert_int_equal(tmd_encode(b->models[i], 1, &y, &yl, NULL), 0);
        assert_int_equal(xl, yl);
        assert_memory_equal(x, y, xl);
        free(x);
        free(y);
    }
    assert_int_equal(a->light_count, b->light_count);
    for (uint32_t i = 0; i < a->light_count; i++) {
        const Light *x = &a->lights[i], *y = &b->lights[i];
        assert_int_equal(x->kind, y->kind);
        SAME(x->pos, y->pos);
        SAME(x->dir, y->dir);
        SAME(x->color, y->color);
        SAME(x->intensity, y->intensity);
        SAME(x->angle, y->angle);
        SAME(x->soft, y->soft);
        assert_int_equal(x->attenuate, y->attenuate);
    }
    assert_same_worlds(a, b);
}

static void scenes_round_trip(void **state)
{
    (void)state;
    Scene *scenes[2];
    BvhOptions opt = bvh_options_default(BVH_SAH);
    Err err;
    assert_int_equal(scene_default(&scenes[0], &opt, NULL), 0);
    if (scene_load("models/example.scene", &opt, 0, &scenes[1], &err))
        fail_msg("%s", err.msg);
    for (int k = 0; k < 2; k++) {
        Scene *s = scenes[k];
        Encoded e = encode(s);
        AssetCache *c = cache_of(&e);
        Scene *back;
        if (wire_decode_scene(e.blob, e.len, c, &back, &err))
            fail_msg("%s", err.msg);
        assert_true(back->borrowed_assets);
        assert_int_equal(back->light_count, s->light_count);
        assert_scenes_identical(s, back);
        /* checking again (a server does after every change) changes
         * nothing either (directions normalised in place once drifted by an
         * ulp every time) */
        assert_int_equal(scene_check(back, NULL), 0);
        assert_scenes_identical(s, back);
        assert_same_pixels(s, back);
        /* models travel as assets: the scene itself stays small */
        assert_true(e.len < 4096);
        scene_destroy(back);
        asset_cache_destroy(c);
        free_encoded(&e);
        scene_destroy(s);
    }
}

static void only_used_parts_travel(void **state)
{
    (void)state;
    /* a spot light costs more bytes than a point light; an untextured triangle carries no uvs */
    Scene *a = scene_create(), *b = scene_create();
    Material m = material_default();
    scene_add_material(a, m, NULL, NULL);
    scene_add_material(b, m, NULL, NULL);
    const vec3 p[3] = {v3(0, 0, 0), v3(1, 0, 0), v3(0, 1, 0)};
    const real uv[6] = {0, 0, 1, 0, 0, 1};
    scene_add_triangle(a, p, NULL, NULL, 0, NULL);
    scene_add_triangle(b, p, NULL, uv, 0, NULL);
    scene_add_light(a, light_point(v3(0, 5, 0), v3(1, 1, 1), 1, 0), NULL);
    scene_add_light(b, light_spot(v3(0, 5, 0), v3(0, -1, 0), 30, 0, v3(1, 1, 1), 1, 0), NULL);
    assert_int_equal(scene_check(a, NULL), 0);
    assert_int_equal(scene_check(b, NULL), 0);
    Sink sa = {0}, sb = {0};
    assert_int_equal(wire_encode_scene(a, NULL, NULL, &sa, NULL), 0);
    assert_int_equal(wire_encode_scene(b, NULL, NULL, &sb, NULL), 0);
    assert_int_equal(sb.len - sa.len, 6 * 8 + 5 * 8); /* uv: 6 f64; spot: dir (3) + angle + soft */
    sink_free(&sa);
    sink_free(&sb);
    scene_destroy(a);
    scene_destroy(b);
}

/* An environment travels with its .hdr as a texture asset: the client's
 * scene has it, its light the server's to the bit (the same pixels), and
 * a scene without one pays its group bits alone. */
static void an_environment_travels(void **state)
{
    (void)state;
    /* a 4 x 2 .hdr, flat scanlines, one texel 12 times white */
    uint8_t hdr[128];
    const char *head = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 4\n";
    size_t n = strlen(head);
    memcpy(hdr, head, n);
    for (int i = 0; i < 8; i++) {
        const uint8_t px[4] = {(uint8_t)(40 + 20 * i), 120, i == 1 ? 191 : 200, (uint8_t)(i == 1 ? 132 : 127)};
        memcpy(hdr + n, px, 4);
        n += 4;
    }
    Scene *a = scene_create(), *b = scene_create();
    Err err;
    for (int k = 0; k < 2; k++) {
        Scene *s = k ? b : a;
        scene_add_material(s, material_default(), NULL, NULL);
        scene_add_sphere(s, (Sphere){.centre = v3(0, 1, 0), .radius = R(0.8), .material = 0}, NULL);
        s->camera.pos = v3(0, 1, 4);
    }
    Texture *t;
    if (texture_read_memory(hdr, n, "sky.hdr", &t, &err))
        fail_msg("%s", err.msg);
    uint32_t id;
    assert_int_equal(scene_add_texture(b, t, &id, NULL), 0);
    b->environment = (SceneEnvironment){.texture = (int32_t)id, .strength = R(2), .rotate = R(33)};
    assert_int_equal(scene_check(a, NULL), 0);
    assert_int_equal(scene_check(b, NULL), 0);
    Encoded ea = encode(a), eb = encode(b);
    /* the group (texture i32, strength and rotate f64) and the texture's hash */
    assert_int_equal(eb.len - ea.len, 4 + 2 * 8 + PROTO_HASH);
    AssetCache *c = cache_of(&eb);
    Scene *back;
    if (wire_decode_scene(eb.blob, eb.len, c, &back, &err))
        fail_msg("%s", err.msg);
    assert_scenes_identical(b, back);
    assert_non_null(back->textures[0]->hdr);
    assert_same_pixels(b, back);
    b->settings.integrator = back->settings.integrator = INTEGRATOR_PATH;
    assert_same_pixels(b, back);
    scene_destroy(back);
    asset_cache_destroy(c);
    free_encoded(&ea);
    free_encoded(&eb);
    scene_destroy(a);
    scene_destroy(b);
}

/* A model's own materials (an MTL's illum 3, carried in its .tmd) bring
 * the settings of secondary rays onto the wire as a scene material does:
 * without them a client traced with its defaults (found by randscene.sh). */
static void a_models_optics_carry_the_settings(void **state)
{
    (void)state;
    char obj[512], mtl[512], text[256];
    snprintf(obj, sizeof obj, "%s/mirror.obj", test_tmpdir());
    snprintf(mtl, sizeof mtl, "%s/mirror.mtl", test_tmpdir());
    test_write_file(obj, "mtllib mirror.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl chrome\nf 1 2 3\n");
    test_write_file(mtl, "newmtl chrome\nKd 0 0 0\nKs 0.9 0.9 0.9\nillum 3\n");
    int n = snprintf(text, sizeof text,
                     "settings depth 2 rough_samples 3 fresnel schlick\nmodel m mirror.obj\ninstance m\n"
                     "sphere centre 0 0 2 radius 0.5\nlight point position 0 0 5\n");
    Scene *s, *back;
    Err err;
    BvhOptions opt = bvh_options_default(BVH_SAH);
    if (scene_parse(text, (size_t)n, "t.scene", test_tmpdir(), &opt, 0, &s, &err))
        fail_msg("%s", err.msg);
    assert_true(world_has(world_now(s), FEAT_REFLECT) && s->material_count == 1 && !material_reflects(&s->materials[0]));
    Encoded e = encode(s);
    AssetCache *c = cache_of(&e);
    assert_int_equal(wire_decode_scene(e.blob, e.len, c, &back, &err), 0);
    assert_int_equal(back->settings.depth, 2);
    assert_int_equal(back->settings.rough_samples, 3);
    assert_int_equal(back->settings.fresnel, FRESNEL_SCHLICK);
    scene_destroy(back);
    asset_cache_destroy(c);
    free_encoded(&e);
    scene_destroy(s);
}

/* A high dynamic range frame costs the scene no bytes (a flag of the
 * extras word) and the client renders the same RGBE as lanray-render. */
/* A 40x30 frame of the server's scene a and of the client's decoded b:
 * the same bytes (RGB8 or RGBE). */
static void assert_renders_alike(Scene *a, Scene *b)
{
    enum { W = 40, H = 30 };
    static uint8_t pa[W * H * 4], pb[W * H * 4];
    RenderPool *p = render_pool_create(2, NULL);
    assert_int_equal(render_lines(p, world_now(a), W, H, 0, H, pa, NULL, NULL), 0);
    assert_int_equal(render_span(p, world_now(b), W, H, 0, W * H, pb, NULL, NULL, NULL), 0);
    assert_memory_equal(pa, pb, (size_t)W * H * render_pixel_bytes(&a->settings));
    render_pool_destroy(p);
}

/* The sampling, what the depth limit returns and the texture filter
 * travel, and the client renders the server's pixels with them. */
static void sampling_limit_and_filter_travel(void **state)
{
    (void)state;
    Scene *s, *back;
    BvhOptions opt = bvh_options_default(BVH_SAH);
    Err err;
    assert_int_equal(scene_default(&s, &opt, NULL), 0);
    const struct {
        Sampling sampling;
        DepthLimit limit;
        TextureFilter filter;
    } cases[] = {{SAMPLING_PRODUCT, LIMIT_LOCAL, FILTER_TRILINEAR}, {SAMPLING_BUDGET, LIMIT_BACKGROUND, FILTER_NEAREST}};
    for (int i = 0; i < 2; i++) {
        s->settings.sampling = cases[i].sampling;
        s->settings.depth_limit = cases[i].limit;
        s->settings.filter = cases[i].filter;
        s->settings.depth = 1;
        assert_int_equal(scene_check(s, NULL), 0);
        Encoded e = encode(s);
        AssetCache *c = cache_of(&e);
        if (wire_decode_scene(e.blob, e.len, c, &back, &err))
            fail_msg("%s", err.msg);
        assert_int_equal(back->settings.sampling, cases[i].sampling);
        assert_int_equal(back->settings.depth_limit, cases[i].limit);
        assert_int_equal(back->settings.filter, cases[i].filter);
        assert_renders_alike(s, back);
        scene_destroy(back);
        asset_cache_destroy(c);
        free_encoded(&e);
    }
    scene_destroy(s);
}

static void hdr_travels_as_a_flag(void **state)
{
    (void)state;
    Scene *s, *back;
    BvhOptions opt = bvh_options_default(BVH_SAH);
    Err err;
    assert_int_equal(scene_default(&s, &opt, NULL), 0);
    Encoded plain = encode(s);
    s->settings.hdr = 1;
    Encoded e = encode(s);
    assert_int_equal(e.len, plain.len);
    AssetCache *c = cache_of(&e);
    if (wire_decode_scene(e.blob, e.len, c, &back, &err))
        fail_msg("%s", err.msg);
    assert_int_equal(back->settings.hdr, 1);
    assert_int_equal(render_pixel_bytes(&back->settings), 4);
    assert_renders_alike(s, back);
    scene_destroy(back);
    asset_cache_destroy(c);
    free_encoded(&e);
    /* and without it, the client's pixels are RGB8 again */
    s->settings.hdr = 0;
    c = cache_of(&plain);
    assert_int_equal(wire_decode_scene(plain.blob, plain.len, c, &back, NULL), 0);
    assert_int_equal(render_pixel_bytes(&back->settings), 3);
    scene_destroy(back);
    asset_cache_destroy(c);
    free_encoded(&plain);
    scene_destroy(s);
}

/* A word of a serialised scene replaced: the scene is refused, saying why. */
typedef struct {
    size_t at;
    uint32_t word;
    const char *why;
} BadWord;

/* Each bad word in turn in the scene sk, refused; sk as it was after. */
static void refused(Sink *sk, AssetCache *c, const BadWord *bad, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        Scene *back;
        Err err;
        uint32_t was;
        memcpy(&was, sk->data + bad[i].at, 4);
        memcpy(sk->data + bad[i].at, &bad[i].word, 4);
        assert_int_equal(wire_decode_scene(sk->data, sk->len, c, &back, &err), -1);
        assert_contains(err.msg, bad[i].why);
        memcpy(sk->data + bad[i].at, &was, 4);
    }
}

static void malformed_scenes_and_assets_are_rejected(void **state)
{
    (void)state;
    Scene *s;
    BvhOptions opt = bvh_options_default(BVH_SAH);
    assert_int_equal(scene_default(&s, &opt, NULL), 0);
    Encoded e = encode(s);
    AssetCache *c = cache_of(&e);
    Scene *back;
    for (size_t n = 0; n < e.len; n++) { /* every truncation */
        Err err = {{0}};
        assert_int_equal(wire_decode_scene(e.blob, n, c, &back, &err), -1);
        assert_contains(err.msg, "scene");
    }
    Err err = {{0}};
    uint8_t *bad = malloc(e.len + 1);
    memcpy(bad, e.blob, e.len);
    bad[e.len] = 0;
    assert_int_equal(wire_decode_scene(bad, e.len + 1, c, &back, &err), -1);
    assert_contains(err.msg, "trailing bytes");
    uint32_t v = 0x04030201;
    memcpy(bad + 8, &v, 4);
    assert_int_equal(wire_decode_scene(bad, e.len, c, &back, &err), -1);
    assert_contains(err.msg, "other byte order");
    /* an empty cache: the assets were never sent */
    AssetCache *empty = asset_cache_create();
    assert_int_equal(wire_decode_scene(e.blob, e.len, empty, &back, &err), -1);
    assert_contains(err.msg, "asset not received");
    /* a payload that does not match its hash, and a malformed texture */
    e.models[0].data[100] ^= 1;
    assert_int_equal(asset_cache_add(empty, ASSET_MODEL, e.models[0].hash, e.models[0].data, e.models[0].len, &err), -1);
    assert_contains(err.msg, "does not match its hash");
    uint8_t tex[12] = {2, 0, 0, 0, 2, 0, 0, 0, 0, 0, 0, 0}, h[PROTO_HASH];
    auth_hash(tex, sizeof tex, h);
    assert_int_equal(asset_cache_add(empty, ASSET_TEXTURE, h, tex, sizeof tex, &err), -1);
    assert_contains(err.msg, "the texture's header is cut short");
    asset_cache_destroy(empty);
    free(bad);
    asset_cache_destroy(c);
    free_encoded(&e);
    scene_destroy(s);
    /* Every item travels by its field table (docs/protocol.md): a 12-byte
     * header; the camera, a group word (at 12) and position, yaw, pitch,
     * roll, zoom (60 bytes); the colours (48); the environment's group
     * word (at 120: none); the settings, a group word at 124, then aa,
     * adaptive, shading, shadows, filter (at 144), linear and hdr; the
     * counts (32, at 156); a material, its group word (188), diffuse,
     * specular, shininess and texture (64); a plane, its group word (252),
     * point, normal and material: 308 bytes. */
    Scene *one = scene_create();
    assert_int_equal(scene_add_material(one, material_default(), NULL, NULL), 0);
    assert_int_equal(scene_add_plane(one, plane_make(v3(0, 0, 0), v3(0, 1, 0), 0), NULL), 0);
    Sink sk = {0};
    /* only a scene whose checks have passed is sent */
    assert_int_equal(wire_encode_scene(one, NULL, NULL, &sk, &err), -1);
    assert_contains(err.msg, "not checked");
    sink_free(&sk);
    sk = (Sink){0};
    assert_int_equal(scene_check(one, NULL), 0);
    assert_int_equal(wire_encode_scene(one, NULL, NULL, &sk, NULL), 0);
    assert_int_equal(sk.len, 308);
    assert_int_equal(wire_decode_scene(sk.data, sk.len, c = asset_cache_create(), &back, &err), 0);
    scene_destroy(back);
    const BadWord bad_words[] = {{124, 1u << 5, "bad settings"},
                     {120, 1u << 2, "bad environment"}, /* a group it does not have */
                     {120, 1u << 0, "bad environment"},
                     {144, FILTER_COUNT, "settings: 'filter' is not one of its words"},
                     {140, 2, "settings: 'shadows' is not one of its words"},
                     {148, 2, "settings: 'linear' is not 0 or 1"},
                     {188, 1u << 14, "bad material"},
                     {252, 1u << 2, "bad plane"},
                     {252, 1u << 1, "truncated"}, /* a plane mapped, its two numbers missing */
                     {12, 1u << 3, "bad camera"}};
    refused(&sk, c, bad_words, sizeof bad_words / sizeof bad_words[0]);
    sink_free(&sk);
    /* a mirror pays for its reflectance and roughness (32 bytes after the
     * material's texture, at 252); settings of secondary rays away from
     * their defaults travel in the settings' first group (28 bytes after
     * hdr, at 156: depth, depth limit, cutoff, Fresnel, glass shadows,
     * rough samples), moving the rest along */
    one->materials[0].kr = v3_splat(R(0.5));
    assert_int_equal(scene_check(one, NULL), 0);
    sk = (Sink){0};
    assert_int_equal(wire_encode_scene(one, NULL, NULL, &sk, NULL), 0);
    assert_int_equal(sk.len, 308 + 32);
    assert_int_equal(wire_decode_scene(sk.data, sk.len, c, &back, &err), 0);
    assert_true(back->materials[0].kr.y == R(0.5));
    scene_destroy(back);
    /* a mirror's reflectance must not be negative: the scene's own checks */
    double neg = -1;
    memcpy(sk.data + 252, &neg, 8);
    assert_int_equal(wire_decode_scene(sk.data, sk.len, c, &back, &err), -1);
    assert_contains(err.msg, "'reflect' must not be negative");
    sink_free(&sk);
    one->settings.depth = 8;
    assert_int_equal(scene_check(one, NULL), 0);
    sk = (Sink){0};
    assert_int_equal(wire_encode_scene(one, NULL, NULL, &sk, NULL), 0);
    assert_int_equal(sk.len, 308 + 32 + 28);
    assert_int_equal(wire_decode_scene(sk.data, sk.len, c, &back, &err), 0);
    assert_true(back->settings.depth == 8 && back->settings.cutoff == one->settings.cutoff);
    scene_destroy(back);
    const BadWord bad_optics[] = {{156, SCENE_MAX_DEPTH + 1, "'depth' must be a whole number from 0 to 64"},
                      {160, LIMIT_COUNT, "'depth_limit' is not one of its words"},
                      {172, 2, "'fresnel' is not one of its words"},
                      {176, 2, "'glass_shadows' is not one of its words"},
                      {180, SCENE_MAX_SAMPLES + 1, "'rough_samples' must be 0 or from 1 to 16"}};
    refused(&sk, c, bad_optics, sizeof bad_optics / sizeof bad_optics[0]);
    sink_free(&sk);
    one->settings.depth = 5;
    /* a fisheye camera: its projection group (the orthographic width, the
     * fisheye's field of view at 80, the kind at 88) follows the zoom */
    one->camera.kind = CAMERA_FISHEYE;
    one->camera.fov = 200;
    assert_int_equal(scene_check(one, NULL), 0);
    sk = (Sink){0};
    assert_int_equal(wire_encode_scene(one, NULL, NULL, &sk, NULL), 0);
    assert_int_equal(sk.len, 308 + 32 + 20);
    assert_int_equal(wire_decode_scene(sk.data, sk.len, c, &back, &err), 0);
    assert_true(back->camera.kind == CAMERA_FISHEYE && back->camera.fov == R(200));
    scene_destroy(back);
    uint32_t word = CAMERA_FISHEYE + 1;
    memcpy(sk.data + 88, &word, 4);
    assert_int_equal(wire_decode_scene(sk.data, sk.len, c, &back, &err), -1);
    assert_contains(err.msg, "camera: 'kind' is not one of its words");
    word = CAMERA_FISHEYE;
    memcpy(sk.data + 88, &word, 4);
    double wide = 400; /* past 360 degrees */
    memcpy(sk.data + 80, &wide, 8);
    assert_int_equal(wire_decode_scene(sk.data, sk.len, c, &back, &err), -1);
    assert_contains(err.msg, "'fisheye' must be from 0 to 360");
    asset_cache_destroy(c);
    sink_free(&sk);
    scene_destroy(one);
}

/* A frame's view travels alone: decoded, it gives the world of the
 * description a client holds (world_with_view) the pixels of a world built
 * from a scene with that camera and settings, with no tree built; a view
 * the checks refuse, a short one and one with a byte more are errors. */
static void a_view_travels_alone(void **state)
{
    (void)state;
    BvhOptions opt = bvh_options_default(BVH_SAH);
    Scene *s;
    assert_int_equal(scene_default(&s, &opt, NULL), 0);
    World *held = world_build(s, NULL, NULL);
    assert_non_null(held);
    View v = scene_view(s);
    v.camera.pos = v3_add(v.camera.pos, v3(R(0.4), R(-0.2), R(0.3)));
    v.settings.aa = 2;
    v.settings.adaptive = 0;
    v.settings.shadows = 0;
    Sink sink = {0};
    assert_int_equal(wire_encode_view(&v, &sink, NULL), 0);
    assert_true(sink.len < 256); /* a view is small: the camera and the settings */
    View got;
    Err err;
    assert_int_equal(wire_decode_view(sink.data, sink.len, &got, &err), 0);
    uint64_t trees = world_tree_builds();
    World *moved = world_with_view(held, &got, &err);
    assert_non_null(moved);
    assert_int_equal(world_tree_builds(), trees); /* a camera move builds no tree */
    assert_true(world_shares_top(moved, held));
    world_destroy(held); /* the moved world keeps what it shares */
    s->camera = v.camera;
    s->settings = v.settings;
    enum { W = 40, H = 30 };
    static uint8_t pa[W * H * 3], pb[W * H * 3];
    RenderPool *p = render_pool_create(2, NULL);
    assert_int_equal(render_lines(p, moved, W, H, 0, H, pa, NULL, NULL), 0);
    assert_int_equal(render_lines(p, world_now(s), W, H, 0, H, pb, NULL, NULL), 0);
    assert_memory_equal(pa, pb, sizeof pa);
    render_pool_destroy(p);
    assert_int_equal(wire_decode_view(sink.data, sink.len - 1, &got, &err), -1);
    assert_contains(err.msg, "view: truncated");
    sink_u32(&sink, 0);
    assert_int_equal(wire_decode_view(sink.data, sink.len, &got, &err), -1);
    assert_contains(err.msg, "trailing");
    View bad = v;
    bad.settings.depth = SCENE_MAX_DEPTH + 1;
    sink.len = 0;
    assert_int_equal(wire_encode_view(&bad, &sink, NULL), 0);
    assert_int_equal(wire_decode_view(sink.data, sink.len, &got, &err), -1);
    assert_contains(err.msg, "depth");
    sink_free(&sink);
    world_destroy(moved);
    scene_destroy(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(scenes_round_trip),
        cmocka_unit_test(a_view_travels_alone),
        cmocka_unit_test(only_used_parts_travel),
        cmocka_unit_test(an_environment_travels),
        cmocka_unit_test(a_models_optics_carry_the_settings),
        cmocka_unit_test(hdr_travels_as_a_flag),
        cmocka_unit_test(sampling_limit_and_filter_travel),
        cmocka_unit_test(malformed_scenes_and_assets_are_rejected),
    };
    int rc = cmocka_run_group_tests_name("wire", tests, NULL, NULL);
    world_now_free();
    return rc;
}
