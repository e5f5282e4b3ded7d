/* worlds.h - the world of a test's scene as the scene is now.
 *
 * A test builds a Scene, may change it (its settings, a light) between
 * renders, and traces or renders it.  world_now(s) checks s and builds its
 * world afresh on every call, with the world of the previous call as
 * `previous` (so that the tests also run world_build's reuse), and frees
 * that previous world: what a test traces is always the scene as it is.
 * Call it once outside a loop of rays.  world_now_free() frees the last. */
#ifndef LANRAY_TEST_WORLDS_H
#define LANRAY_TEST_WORLDS_H

#include <stdio.h>
#include <stdlib.h>

#include "scene/world.h"

static World *worlds_last;

static inline const World *world_now(Scene *s)
{
    Err err;
    World *w = NULL;
    if (scene_check(s, &err) == 0)
        w = world_build(s, worlds_last, &err);
    if (!w) {
        fprintf(stderr, "world_now: %s\n", err.msg);
        abort();
    }
    world_destroy(worlds_last);
    worlds_last = w;
    return w;
}

/* A scene of one instance of the model made from *mesh (SAH tree; the
 * mesh freed), turned by `rotate` (degrees about x, y, z), with the
 * model's own materials. */
static inline Scene *worlds_scene_of_mesh(Mesh *mesh, vec3 rotate)
{
    Err err;
    err.msg[0] = 0;
    Model *model;
    BvhOptions opt = bvh_options_default(BVH_SAH);
    Scene *s = scene_create();
    uint32_t id;
    if (model_from_mesh(&model, mesh, &opt, &err) || !s || scene_add_model(s, model, &id, &err) ||
        scene_add_instance(s, (Instance){id, v3(0, 0, 0), rotate, 1, -1}, &err)) {
        fprintf(stderr, "worlds_scene_of_mesh: %s\n", err.msg);
        abort();
    }
    mesh_free(mesh);
    return s;
}

static inline void world_now_free(void)
{
    world_destroy(worlds_last);
    worlds_last = NULL;
}

#endif
