/* bvh_traverse.h - the one BVH traversal, used for model triangles and for
 * the scene's top level alike.
 *
 * Flat node array, explicit stack, both children tested with the slab test
 * and the nearer visited first; the farther is pushed with its entry
 * distance so that it is skipped on pop once a closer hit exists.  Leaves are
 * handed to a callback; both functions are always inlined and the callbacks
 * are static functions known at the call site, so the compiler inlines them
 * too: no indirect call in the loop. */
#ifndef LANRAY_BVH_TRAVERSE_H
#define LANRAY_BVH_TRAVERSE_H

#include <assert.h>

#include "bvh/bvh.h"

/* Tests primitives [first, first+count); on a hit nearer than *tmax, lowers
 * *tmax, records the hit in ctx and returns 1. */
typedef int (*BvhLeafClosest)(void *ctx, uint32_t first, uint32_t count, const Ray *r, real *tmax);
/* Returns 1 if any primitive of [first, first+count) is hit before tmax. */
typedef int (*BvhLeafAny)(const void *ctx, uint32_t first, uint32_t count, const Ray *r, real tmax);

typedef struct {
    uint32_t node;
    real tnear;
} BvhStackEntry;

static inline __attribute__((always_inline)) int bvh_closest(const Bvh *b, const Ray *r, real *tmax,
                                                             BvhLeafClosest leaf, void *ctx)
{
    const BvhNode *nodes = b->nodes;
    real tn;
    if (b->node_count == 0)
        return 0;
    if (BVH_LONE_LEAF(nodes))
        return leaf(ctx, nodes[0].first, 1, r, tmax);
    if (!bvh_node_hit(&nodes[0], r, *tmax, &tn))
        return 0;
    BvhStackEntry stack[BVH_MAX_DEPTH];
    uint32_t sp = 0, idx = 0;
    int found = 0;
    for (;;) {
        const BvhNode *n = &nodes[idx];
        if (n->count) {
            found |= leaf(ctx, n->first, n->count, r, tmax);
        } else {
            real t0, t1;
            const uint32_t c = n->first;
            int h0 = bvh_node_hit(&nodes[c], r, *tmax, &t0);
            int h1 = bvh_node_hit(&nodes[c + 1], r, *tmax, &t1);
            if (h0 && h1) {
                idx = t1 < t0 ? c + 1 : c;
                assert(sp < BVH_MAX_DEPTH); /* bvh_validate keeps trees to this depth */
                stack[sp++] = t1 < t0 ? (BvhStackEntry){c, t0} : (BvhStackEntry){c + 1, t1};
                continue;
            }
            if (h0 | h1) {
                idx = h0 ? c : c + 1;
                continue;
            }
        }
        do {
            if (sp == 0)
                return found;
            --sp;
        } while (stack[sp].tnear > *tmax * BVH_FUDGE);
        idx = stack[sp].node;
    }
}

static inline __attribute__((always_inline)) int bvh_any(const Bvh *b, const Ray *r, real tmax, BvhLeafAny leaf,
                                                         const void *ctx)
{
    const BvhNode *nodes = b->nodes;
    real tn;
    if (b->node_count == 0)
        return 0;
    if (BVH_LONE_LEAF(nodes))
        return leaf(ctx, nodes[0].first, 1, r, tmax);
    if (!bvh_node_hit(&nodes[0], r, tmax, &tn))
        return 0;
    uint32_t stack[BVH_MAX_DEPTH];
    uint32_t sp = 0, idx = 0;
    for (;;) {
        const BvhNode *n = &nodes[idx];
        if (n->count) {
            if (leaf(ctx, n->first, n->count, r, tmax))
                return 1;
        } else {
            real t0, t1;
            const uint32_t c = n->first;
            int h0 = bvh_node_hit(&nodes[c], r, tmax, &t0);
            int h1 = bvh_node_hit(&nodes[c + 1], r, tmax, &t1);
            if (h0 && h1) { /* order still pays: the nearer child more likely occludes */
                idx = t1 < t0 ? c + 1 : c;
                assert(sp < BVH_MAX_DEPTH);
                stack[sp++] = t1 < t0 ? c : c + 1;
                continue;
            }
            if (h0 | h1) {
                idx = h0 ? c : c + 1;
                continue;
            }
        }
        if (sp == 0)
            return 0;
        idx = stack[--sp];
    }
}

#endif
