/* bvh_packet.h - a packet of rays through a binary BVH: the scene's top
 * level, where a leaf may be a whole model that takes the packet on to its
 * own (wide) tree.
 *
 * Depth first, each node with the rays (a bit mask, at most 32) whose slab
 * test enters it; a node popped from the stack is tested again against
 * the rays left, so rays blocked since (occlusion) or with a hit nearer
 * than the node (closest) drop out.  Leaves go to a callback primitive by
 * primitive with the rays that reached them.  Like bvh_traverse.h, the
 * function is always inlined and its callback is a static function known
 * at the call site: no indirect call in the loop.  The wide kernels
 * (wide_kernel.h) are the same walk for a model's four- and eight-wide
 * tree, in SIMD. */
#ifndef LANRAY_BVH_PACKET_H
#define LANRAY_BVH_PACKET_H

#include "bvh/bvh.h"

/* Primitive `prim` (a leaf's entry of bvh->prims) against the rays of
 * `rays`: returns those it blocks (occlusion; 0 for closest hits), and
 * lowers far[i] of a ray it finds a nearer hit for. */
typedef uint32_t (*BvhPacketLeaf)(void *ctx, uint32_t prim, uint32_t rays, real *far);

/* The rays of `mask` whose slab test enters node n (each with its own far limit). */
static inline uint32_t bvh_node_rays(const BvhNode *n, const Ray *rays, uint32_t mask, const real *far)
{
    uint32_t in = 0;
    while (mask) {
        int i = __builtin_ctz(mask);
        mask &= mask - 1;
        real tn;
        if (bvh_node_hit(n, &rays[i], far[i], &tn))
            in |= 1u << i;
    }
    return in;
}

/* n <= 32 rays through b, far[i] each ray's limit (lowered by the leaves);
 * returns the rays blocked. */
static inline __attribute__((always_inline)) uint32_t bvh_packet(const Bvh *b, const Ray *rays, int n, real *far,
                                                                 BvhPacketLeaf leaf, void *ctx)
{
    uint32_t done = 0; /* occlusion: the rays already blocked */
    const uint32_t all = n >= 32 ? ~0u : (1u << n) - 1;
    if (b->node_count == 0)
        return 0;
    struct {
        uint32_t node, rays;
    } stack[BVH_MAX_DEPTH + 1];
    int sp = 0;
    /* a root that is a leaf (one model instance, say) is not box-tested:
     * its primitives' own tests (a model's root node) do that work */
    uint32_t idx = 0, rs = b->nodes[0].count ? all : bvh_node_rays(&b->nodes[0], rays, all, far);
    for (;;) {
        const BvhNode *nd = &b->nodes[idx];
        if (rs && nd->count == 0) {
            uint32_t r0 = bvh_node_rays(&b->nodes[nd->first], rays, rs, far);
            uint32_t r1 = bvh_node_rays(&b->nodes[nd->first + 1], rays, rs, far);
            if (r0 && r1)
                stack[sp].node = nd->first + 1, stack[sp++].rays = r1;
            idx = r0 ? nd->first : nd->first + 1;
            rs = r0 ? r0 : r1;
            if (rs)
                continue;
        } else if (rs) {
            for (uint32_t k = 0; k < nd->count && rs; k++) {
                done |= leaf(ctx, b->prims[nd->first + k], rs, far);
                rs &= ~done;
            }
        }
        do {
            if (sp == 0)
                return done;
            --sp;
            idx = stack[sp].node;
            rs = bvh_node_rays(&b->nodes[idx], rays, stack[sp].rays & ~done, far);
        } while (!rs);
    }
}

#endif
