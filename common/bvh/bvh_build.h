/* bvh_build.h - what the three BVH builders share (private to common/bvh*.c).
 *
 * Each builder produces a binary tree of BuildNodes over primitive indices;
 * bvh_flatten then turns any such tree into the flat traversal layout. */
#ifndef LANRAY_BVH_BUILD_H
#define LANRAY_BVH_BUILD_H

#include "base/pool.h"
#include "bvh/bvh.h"


typedef struct {
    Aabb box;
    int32_t left, right; /* -1 for a leaf */
    uint32_t first, count; /* leaf: range in the builder's perm[] */
} BuildNode;

/* A task of a top-down builder (builder_run, below). */
typedef struct {
    uint32_t node, first, count, depth;
    Aabb box, cbox;
} BuildTask;
typedef struct Builder Builder;
typedef int (*BuildStep)(const Builder *b, const BuildTask *t, BuildTask kids[2]);

struct Builder {
    const Aabb *boxes;
    vec3 *centres; /* NULL for SAH, which keeps centres in its own references: aabb_centre(boxes[i]) */
    uint32_t n;
    uint32_t *perm; /* primitive indices, grouped by leaf */
    BuildNode *nodes;
    uint32_t node_count, node_cap;
    uint32_t root;
    const BvhOptions *opt;
    int collapse; /* let bvh_flatten merge small subtrees into leaves by SAH */
    uint32_t max_depth; /* the deepest node builder_run made (the root is 1); 0: not known */
    const void *aux; /* a builder's own per-primitive data */
    Pool *pool;      /* for passes over every primitive; NULL: the caller alone */
    int root_known; /* root_box and root_cbox are set (the builder's own pass found them) */
    Aabb root_box, root_cbox;
};

/* Appends a node, returns its index or -1 when out of memory (one thread only). */
int32_t builder_add(Builder *b, BuildNode node);

/* Top-down builders run as tasks: a task is a node whose primitives are
 * perm[first, first+count), with the box of their boxes and of their
 * centres.  `step` makes it a leaf (returns 0) or splits its range in two,
 * fills kids[0..1] (boxes and ranges) and returns 2; builder_run allocates
 * the children's nodes and links them.  Subtrees go to opt->threads
 * workers; each task touches only its own range of perm, so the tree is the
 * same whatever the number of threads and their timing.  A builder may
 * give a second step, top_step (else NULL), for the top of the tree: while
 * there are fewer tasks than workers, builder_run steps the biggest one
 * alone with it, and it may spread its passes over b->pool. */
int builder_run(Builder *b, BuildStep step, BuildStep top_step, Err *err);
/* Bounds of the primitive boxes and of their centres over perm[first, first+count). */
void builder_bounds(const Builder *b, uint32_t first, uint32_t count, Aabb *box, Aabb *cbox);
/* The same over every primitive, on the pool: only where no task runs (a
 * pool takes one loop at a time). */
void builder_bounds_all(const Builder *b, Aabb *box, Aabb *cbox);

/* Every builder's error for the first primitive i whose box is empty or
 * not finite; returns -1. */
int builder_bad_box(uint32_t i, Err *err);
/* Whether a box can be built over: not empty and finite. */
static inline int builder_box_ok(Aabb box)
{
    return !aabb_is_empty(box) && v3_is_finite(box.min) && v3_is_finite(box.max);
}

int bvh_build_sbt(Builder *b, Err *err);
int bvh_build_sah(Builder *b, Err *err);
int bvh_build_mst(Builder *b, Err *err);
int bvh_flatten(const Builder *b, Bvh *out, Err *err);

#endif
