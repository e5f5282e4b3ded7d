/* test_upload.c - a scene's assets from the server's uploads
 * (server/upload.c) to a client's cache (client/assetload.c): slices paced
 * onto the connection, gathered whole, decoded on the client's thread with
 * their trees built, a HAVE for each in the order they came; slices that
 * do not follow one another, and a payload that is not its hash, refused. */
#include "helpers.h"
#include "worlds.h"

#include <fcntl.h>
#include <sys/socket.h>
#include <unistd.h>

#include "assetload.h"
#include "base/simd.h"
#include "bvh/wide.h"
#include "net/net.h"
#include "scene/scene_default.h"
#include "upload.h"

/* A wavy grid of 2 n^2 triangles: its .tmd image is megabytes, many slices. */
static Scene *grid_scene(uint32_t n)
{
    Mesh mesh;
    assert_int_equal(mesh_init(&mesh, 0, NULL), 0);
    for (uint32_t j = 0; j < n; j++)
        for (uint32_t i = 0; i < n; i++) {
            vec3 p[4];
            for (int k = 0; k < 4; k++) {
                const real x = (real)(i + (k & 1)) / (real)n, z = (real)(j + (k >> 1)) / (real)n;
                p[k] = v3(x, R(0.05) * (real)sin(20 * x) * (real)cos(20 * z), z);
            }
            const vec3 a[3] = {p[0], p[2], p[1]}, b[3] = {p[1], p[2], p[3]};
            assert_int_equal(mesh_add(&mesh, a, NULL, NULL, NULL, 0, NULL), 0);
            assert_int_equal(mesh_add(&mesh, b, NULL, NULL, NULL, 0, NULL), 0);
        }
    return worlds_scene_of_mesh(&mesh, v3(0, 0, 0));
}

typedef struct {
    uint8_t hash[16][PROTO_HASH];
    int n;
} Haves;

static void on_have(void *ctx, const uint8_t *hash)
{
    Haves *h = ctx;
    assert_true(h->n < 16);
    memcpy(h->hash[h->n++], hash, PROTO_HASH);
}

/* Every ASSET the client's end has whole, into l. */
static void read_slices(Conn *in, AssetLoad *l, uint32_t *slices)
{
    Err err;
    int got;
    while ((got = conn_read(in, &err)) == 1) {
        assert_int_equal(in->type, PKT_ASSET);
        MsgAsset a;
        assert_int_equal(msg_decode_asset(in->body, in->body_size, &a, &err), 0);
        assert_true(a.len <= PROTO_ASSET_SLICE);
        if (assetload_slice(l, &a, &err))
            fail_msg("%s", err.msg);
        (*slices)++;
    }
    assert_int_equal(got, 0);
}

static void socket_pair(Conn *out, Conn *in)
{
    int sv[2];
    assert_int_equal(socketpair(AF_UNIX, SOCK_STREAM, 0, sv), 0);
    assert_int_equal(net_setup(sv[0]), 0);
    assert_int_equal(net_setup(sv[1]), 0);
    conn_init(out, sv[0]);
    conn_init(in, sv[1]);
}

static void slices_bring_every_asset_whole(void **state)
{
    (void)state;
    Scene *grid = grid_scene(160), *def;
    BvhOptions opt = bvh_options_default(BVH_SAH);
    assert_int_equal(scene_default(&def, &opt, NULL), 0);
    Asset *ga, *da;
    uint32_t gn, dn;
    assert_int_equal(asset_make_scene(grid, &ga, &gn, NULL), 0);
    assert_int_equal(asset_make_scene(def, &da, &dn, NULL), 0);
    assert_true(gn == 1 && dn >= 2);
    assert_true(ga[0].len > 4 * (UPLOAD_LOW_MIN + UPLOAD_SLICE));
    AssetSet *gs = assetset_make(ga, gn), *ds = assetset_make(da, dn);
    Upload up = {0};
    assert_int_equal(upload_push(&up, gs, 0), 0);
    for (uint32_t i = 0; i < dn; i++)
        assert_int_equal(upload_push(&up, ds, i), 0);
    Conn out, in;
    socket_pair(&out, &in);
    int wake[2];
    assert_int_equal(pipe(wake), 0);
    assert_int_equal(net_setup(wake[1]), 0);
    Err err;
    AssetLoad *l = assetload_create(wake[1], &err);
    assert_non_null(l);
    /* paced: what waits to go (queued, and in the socket) stays under
     * UPLOAD_LOW_MIN (no pace measured yet) but for the slice that crossed it */
    long first = upload_pump(&up, &out, 0, &err);
    assert_true(first > 0 && first <= (long)(UPLOAD_LOW_MIN + UPLOAD_SLICE + PROTO_HEADER + 44));
    assert_int_equal(upload_pump(&up, &out, 0, &err), 0); /* nothing drained: nothing more */
    assert_true(upload_pending(&up));
    uint32_t slices = 0, rounds = 0;
    for (;;) {
        assert_true(conn_flush(&out, &err) >= 0);
        read_slices(&in, l, &slices);
        if (!upload_pending(&up) && !conn_pending(&out) && !conn_buffered(&in))
            break;
        assert_true(upload_pump(&up, &out, 0, &err) >= 0);
        assert_true(++rounds < 100000);
    }
    read_slices(&in, l, &slices);
    uint64_t want = 0;
    for (uint32_t i = 0; i < gn; i++)
        want += (ga[i].len + UPLOAD_SLICE - 1) / UPLOAD_SLICE;
    for (uint32_t i = 0; i < dn; i++)
        want += da[i].len ? (da[i].len + UPLOAD_SLICE - 1) / UPLOAD_SLICE : 1;
    assert_int_equal(slices, want); /* every slice full but each asset's last */
    assetload_wait(l);
    AssetCache *cache = asset_cache_create();
    Haves h = {.n = 0};
    assert_int_equal(assetload_take(l, cache, on_have, &h, &err), 0);
    assert_int_equal(h.n, (int)(gn + dn)); /* a HAVE each, in the order sent */
    assert_memory_equal(h.hash[0], ga[0].hash, PROTO_HASH);
    for (uint32_t i = 0; i < dn; i++)
        assert_memory_equal(h.hash[1 + i], da[i].hash, PROTO_HASH);
    const Model *m = asset_cache_model(cache, ga[0].hash);
    assert_non_null(m);
    assert_int_equal(m->tri_count, 2 * 160 * 160);
    /* decoded on the thread with its tree for this CPU's SIMD path */
    if (WIDE_COMPILED && simd_path() != SIMD_SCALAR)
        assert_non_null(m->wide);
    for (uint32_t i = 0; i < def->texture_count; i++)
        assert_non_null(asset_cache_texture(cache, da[def->model_count + i].hash));
    /* all at once: a client whose next UPDATE needs it */
    assert_int_equal(upload_push(&up, gs, 0), 0);
    assert_true(upload_pump(&up, &out, 1, &err) > (long)ga[0].len);
    assert_false(upload_pending(&up));
    upload_free(&up);
    assetset_drop(gs);
    assetset_drop(ds);
    asset_cache_destroy(cache);
    assetload_destroy(l);
    conn_close(&out);
    conn_close(&in);
    close(wake[0]), close(wake[1]);
    scene_destroy(grid);
    scene_destroy(def);
}

static void slices_that_do_not_follow_are_refused(void **state)
{
    (void)state;
    int wake[2];
    assert_int_equal(pipe(wake), 0);
    assert_int_equal(net_setup(wake[1]), 0);
    Err err;
    AssetLoad *l = assetload_create(wake[1], &err);
    uint8_t payload[100];
    memset(payload, 7, sizeof payload);
    MsgAsset a = {ASSET_TEXTURE, {1}, sizeof payload, 40, payload, 20};
    assert_int_equal(assetload_slice(l, &a, &err), -1);
    assert_non_null(strstr(err.msg, "ASSET slice at byte 40 of an asset whose start never came"));
    a.offset = 0;
    assert_int_equal(assetload_slice(l, &a, &err), 0);
    a.offset = 30; /* a gap: 20 .. 30 never came */
    assert_int_equal(assetload_slice(l, &a, &err), -1);
    assert_non_null(strstr(err.msg, "does not follow the one before (byte 20 of 100"));
    a.offset = 20, a.hash[0] = 2; /* another asset before this one was whole */
    assert_int_equal(assetload_slice(l, &a, &err), -1);
    assert_non_null(strstr(err.msg, "its hash another"));
    a.hash[0] = 1, a.len = 80;
    assert_int_equal(assetload_slice(l, &a, &err), 0); /* whole: its hash is checked on the thread */
    assetload_wait(l);
    AssetCache *cache = asset_cache_create();
    Haves h = {.n = 0};
    assert_int_equal(assetload_take(l, cache, on_have, &h, &err), -1);
    assert_non_null(strstr(err.msg, "payload does not match its hash"));
    assert_int_equal(h.n, 0);
    asset_cache_destroy(cache);
    assetload_destroy(l);
    close(wake[0]), close(wake[1]);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(slices_bring_every_asset_whole),
        cmocka_unit_test(slices_that_do_not_follow_are_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
