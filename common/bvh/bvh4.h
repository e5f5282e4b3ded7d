/* bvh4.h - the scene's top level as a four-wide tree.
 *
 * The top level is a binary SAH tree over spheres, scene triangles and
 * model instances (bvh_traverse.h walks it for one ray, bvh_packet.h for a
 * packet).  Collapsed to four children a node (bvh4_build: the binary
 * tree's boxes and leaves, each node opening its largest children), one
 * ray tests a node's four boxes in one SSE slab test, and a coherent
 * packet tests them as one interval (bvh4_walk.h): a hundred spheres
 * path-traced took a fifth fewer instructions (docs/renderer.md).  The
 * slab test is bvh_node_hit's, lane for lane (max and min
 * keep the bound where a distance is NaN, as its comparisons do), and the
 * leaves and their callbacks are the binary walks', so both trees give
 * every ray the same primitives to test and the same hits (trace.c's
 * order-free rule).  x86-64 float builds; elsewhere bvh4_build makes no
 * tree and the binary walks serve.  The walks are in bvh4_walk.h. */
#ifndef LANRAY_BVH4_H
#define LANRAY_BVH4_H

#include "bvh/bvh.h"

#if defined(__x86_64__) && !defined(LANRAY_DOUBLE) /* as bvh_packet.h's SSE */
#define BVH4_COMPILED 1
#else
#define BVH4_COMPILED 0
#endif

/* 128 bytes: two cache lines. */
typedef struct __attribute__((aligned(64))) {
    float box[6][4];   /* bmin x, y, z, then bmax x, y, z: a child a lane */
    uint32_t child[4]; /* an interior child: its node; a leaf: its first entry of the binary tree's prims */
    uint16_t count[4]; /* 0: an interior child; else the leaf's primitives */
    uint8_t lanes;     /* the lanes in use: a NaN ray passes every box, empty lanes too */
} Bvh4Node;

typedef struct {
    Bvh4Node *nodes;       /* node 0 is the root */
    uint32_t node_count;   /* 0: no tree (a root that is a leaf, or a build without SSE) */
    const uint32_t *prims; /* the binary tree's, borrowed */
} Bvh4;

/* Collapses b (its prims borrowed: b outlives the result). */
int bvh4_build(Bvh4 *out, const Bvh *b, Err *err);
void bvh4_destroy(Bvh4 *t);

#endif
