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

static inline void world_now_free(void)
{
    world_destroy(worlds_last);
    worlds_last = NULL;
}

#endif
