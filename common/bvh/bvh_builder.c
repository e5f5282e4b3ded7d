/* bvh_builder.c - what the three builders share (bvh_build.h): their node
 * list, the bounds of a range of primitives, the error for a bad box. */
#include <stdlib.h>

#include "bvh/bvh_build.h"

int32_t builder_add(Builder *b, BuildNode node)
{
    if (b->node_count == b->node_cap) {
        uint32_t cap = b->node_cap ? b->node_cap * 2 : 64;
        BuildNode *p = realloc(b->nodes, cap * sizeof *p);
        if (!p)
            return -1;
        b->nodes = p;
        b->node_cap = cap;
    }
    b->nodes[b->node_count] = node;
    return (int32_t)b->node_count++;
}

typedef struct {
    const Builder *b;
    uint32_t first;
    Aabb box[BVH_POOL_MAX], cbox[BVH_POOL_MAX];
} Bounds;

static void bounds_range(void *ctx, uint64_t lo, uint64_t hi, int thread)
{
    Bounds *w = ctx;
    const Builder *b = w->b;
    Aabb bb = w->box[thread], cb = w->cbox[thread];
    for (uint64_t i = w->first + lo; i < w->first + hi; i++) {
        uint32_t p = b->perm[i];
        bb = aabb_union(bb, b->boxes[p]);
        aabb_grow(&cb, b->centres ? b->centres[p] : aabb_centre(b->boxes[p]));
    }
    w->box[thread] = bb, w->cbox[thread] = cb;
}

static void bounds_run(const Builder *b, Pool *pool, uint32_t first, uint32_t count, Aabb *box, Aabb *cbox)
{
    Bounds w;
    w.b = b, w.first = first;
    for (int k = 0; k < BVH_POOL_MAX; k++)
        w.box[k] = w.cbox[k] = aabb_empty();
    /* minima and maxima: the same boxes in any order and cut */
    pool_for(pool, count, BVH_POOL_GRAIN, bounds_range, &w);
    Aabb bb = aabb_empty(), cb = aabb_empty();
    for (int k = 0; k < BVH_POOL_MAX; k++)
        bb = aabb_union(bb, w.box[k]), cb = aabb_union(cb, w.cbox[k]);
    *box = bb;
    if (cbox)
        *cbox = cb;
}

void builder_bounds(const Builder *b, uint32_t first, uint32_t count, Aabb *box, Aabb *cbox)
{
    bounds_run(b, NULL, first, count, box, cbox);
}

void builder_bounds_all(const Builder *b, Aabb *box, Aabb *cbox) { bounds_run(b, b->pool, 0, b->n, box, cbox); }

int builder_bad_box(uint32_t i, Err *err) { return err_set(err, "bvh: primitive %u has an empty or non-finite box", i); }
