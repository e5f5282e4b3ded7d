/* view_bench.c - what a camera move costs a client, before and after the
 * frame's view travelled apart from the scene (protocol 8).
 *
 *     view_bench [SCENE...] [--rounds N]   (no scene: the default scene)
 *
 * For each scene, N rounds of one camera move, the three ways a client has
 * met it, side by side in each round (best time of each kept):
 *   resent, alone:    the UPDATE carries the whole scene; the client decodes
 *                     and checks it and builds its world from nothing
 *                     (protocol 7, before the description/world split);
 *   resent, previous: the same, the world built with the previous frame's
 *                     (its top-level tree taken where the boxes are the same);
 *   view only:        the UPDATE carries the view; the client decodes it and
 *                     makes the frame's world from the one it holds
 *                     (world_with_view: no decode of the scene, no check, no tree).
 * Prints the UPDATE's bytes each way and the times, and the top-level trees
 * built in the view-only rounds (0).  Timing only: it never fails on it. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/timer.h"
#include "net/wire.h"
#include "scene/scene_default.h"
#include "scene/scene_parse.h"

typedef struct {
    Asset *assets;
    uint32_t n;
    AssetCache *cache;
} Assets;

/* The scene's assets as the server sends them, and a client's cache of them. */
static int assets_make(const Scene *s, Assets *a, Err *err)
{
    if (asset_make_scene(s, &a->assets, &a->n, err))
        return -1;
    if (!(a->cache = asset_cache_create()))
        return err_set(err, "out of memory");
    for (uint32_t i = 0; i < a->n; i++)
        if (asset_cache_add(a->cache, a->assets[i].kind, a->assets[i].hash, a->assets[i].data, a->assets[i].len, err))
            return -1;
    return 0;
}

static void assets_drop(Assets *a)
{
    assets_free(a->assets, a->n);
    asset_cache_destroy(a->cache);
}

/* The UPDATE's size: header, its fixed part with two segments, the view,
 * and the scene where it is sent. */
static size_t update_bytes(size_t view, size_t scene) { return PROTO_HEADER + 24 + 16 + view + scene; }

typedef struct {
    double alone, previous, view;
    uint64_t view_trees;
} Times;

/* One round: the camera moved, the three ways. */
static int round_one(Scene *s, const Sink *scene_blob, const AssetCache *cache, World **held, Times *t, Err *err)
{
    s->camera.pos.x += R(0.01);
    View v = scene_view(s);
    Sink vb = {0};
    if (wire_encode_view(&v, &vb, err))
        return -1;
    Scene *d;
    double t0 = timer_now();
    if (wire_decode_scene(scene_blob->data, scene_blob->len, cache, &d, err))
        return -1;
    World *a = world_build(d, NULL, err);
    double t1 = timer_now();
    scene_destroy(d);
    world_destroy(a);
    double t2 = timer_now();
    if (wire_decode_scene(scene_blob->data, scene_blob->len, cache, &d, err))
        return -1;
    World *b = world_build(d, *held, err);
    double t3 = timer_now();
    world_destroy(b);
    scene_destroy(d);
    uint64_t trees = world_tree_builds();
    double t4 = timer_now();
    View got;
    World *c = wire_decode_view(vb.data, vb.len, &got, err) ? NULL : world_with_view(*held, &got, err);
    double t5 = timer_now();
    t->view_trees += world_tree_builds() - trees;
    sink_free(&vb);
    if (!a || !b || !c)
        return -1;
    world_destroy(*held);
    *held = c;
    t->alone = t1 - t0 < t->alone ? t1 - t0 : t->alone;
    t->previous = t3 - t2 < t->previous ? t3 - t2 : t->previous;
    t->view = t5 - t4 < t->view ? t5 - t4 : t->view;
    return 0;
}

static int bench_scene(const char *path, int rounds, Err *err)
{
    BvhOptions opt = bvh_options_default(BVH_SAH);
    Scene *s;
    if (path ? scene_load(path, &opt, 0, &s, err) : scene_default(&s, &opt, err))
        return -1;
    Assets as = {0};
    Sink blob = {0}, vb = {0};
    World *held = NULL;
    Times t = {1e30, 1e30, 1e30, 0};
    View v = scene_view(s);
    int rc = assets_make(s, &as, err) || wire_encode_scene(s, as.assets, as.assets + s->model_count, &blob, err) ||
             wire_encode_view(&v, &vb, err) || !(held = world_build(s, NULL, err));
    for (int r = 0; rc == 0 && r < rounds; r++)
        rc = round_one(s, &blob, as.cache, &held, &t, err);
    if (rc == 0) {
        printf("view_bench: %s: %u spheres, %u triangles, %u instances\n", path ? path : "default scene",
               s->sphere_count, s->tri_count, s->instance_count);
        printf("  UPDATE bytes: scene resent %zu, view only %zu (ratio %.3g)\n", update_bytes(vb.len, blob.len),
               update_bytes(vb.len, 0), (double)update_bytes(vb.len, 0) / (double)update_bytes(vb.len, blob.len));
        printf("  client time a camera move, best of %d: resent, built alone %.1f us; resent, with the previous "
               "world %.1f us; view only %.2f us (ratio to alone %.3g); trees built in the view-only rounds: %llu\n",
               rounds, t.alone * 1e6, t.previous * 1e6, t.view * 1e6, t.view / t.alone, (unsigned long long)t.view_trees);
    }
    world_destroy(held);
    sink_free(&blob);
    sink_free(&vb);
    assets_drop(&as);
    scene_destroy(s);
    return rc ? -1 : 0;
}

int main(int argc, char **argv)
{
    int rounds = 20, nscenes = 0;
    const char *scenes[64];
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--rounds") && i + 1 < argc)
            rounds = atoi(argv[++i]);
        else if (nscenes < 64)
            scenes[nscenes++] = argv[i];
    }
    if (rounds < 1)
        rounds = 1;
    Err err;
    for (int i = 0; i < (nscenes ? nscenes : 1); i++)
        if (bench_scene(nscenes ? scenes[i] : NULL, rounds, &err)) {
            fprintf(stderr, "view_bench: %s\n", err.msg);
            return 1;
        }
    return 0;
}
