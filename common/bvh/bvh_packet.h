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

#if defined(__x86_64__) && !defined(LANRAY_DOUBLE)
#include <emmintrin.h>
#define BVH_PACKET_SSE 1
#endif

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

/* The packet's rays as columns, four lanes a group, for bvh_node_rays_soa. */
typedef struct {
    real org[3][32] __attribute__((aligned(16)));
    real inv[3][32] __attribute__((aligned(16)));
    real tmin[32] __attribute__((aligned(16)));
    int groups; /* of four rays; 0: the scalar test (LANRAY_SIMD=scalar, double builds) */
} BvhPacketSoa;

#ifdef BVH_PACKET_SSE
/* The rays of `mask` whose slab test enters a box, four rays a step: on
 * axis a each ray's entry and exit distances from the planes near[a] and
 * far[a] (splatted), where bit a of `choose` is clear; where it is set,
 * near is bmin and far bmax and each ray takes its own entry plane (bmin
 * where its reciprocal is >= 0, ray_set's choice).  bvh_node_hit's
 * operations on the same numbers (no fused multiply-add), max and min
 * keeping lo and hi where a distance is NaN as the comparisons do, so the
 * same rays enter (the wide kernels' argument, wide.h).  far (the rays'
 * limits): a multiple of four readable. */
static inline __attribute__((always_inline)) uint32_t bvh_rows_rays_soa(const __m128 near[3], const __m128 far_plane[3],
                                                                        int choose, const BvhPacketSoa *s,
                                                                        uint32_t mask, const real *far)
{
    uint32_t in = 0;
    const __m128 zero = _mm_setzero_ps(), fudge = _mm_set1_ps(BVH_FUDGE);
    for (int g = 0; g < s->groups; g++) {
        const uint32_t m = mask >> (4 * g) & 15u;
        if (!m)
            continue;
        __m128 lo = _mm_load_ps(&s->tmin[4 * g]), hi = _mm_loadu_ps(&far[4 * g]);
#pragma GCC unroll 3
        for (int a = 0; a < 3; a++) {
            const __m128 o = _mm_load_ps(&s->org[a][4 * g]), iv = _mm_load_ps(&s->inv[a][4 * g]);
            __m128 tn = _mm_mul_ps(_mm_sub_ps(near[a], o), iv), tf = _mm_mul_ps(_mm_sub_ps(far_plane[a], o), iv);
            if (choose >> a & 1) { /* near is bmin, far bmax: each ray's own choice */
                const __m128 pos = _mm_cmpge_ps(iv, zero), t0 = tn;
                tn = _mm_or_ps(_mm_and_ps(pos, t0), _mm_andnot_ps(pos, tf));
                tf = _mm_or_ps(_mm_and_ps(pos, tf), _mm_andnot_ps(pos, t0));
            }
            lo = _mm_max_ps(tn, lo); /* tn > lo ? tn : lo */
            hi = _mm_min_ps(tf, hi); /* tf < hi ? tf : hi */
        }
        in |= ((uint32_t)_mm_movemask_ps(_mm_cmple_ps(lo, _mm_mul_ps(hi, fudge))) & m) << (4 * g);
    }
    return in;
}

/* The rays of `mask` whose slab test enters the box bmin..bmax (each ray
 * its own entry plane: bvh_rows_rays_soa). */
static inline __attribute__((always_inline)) uint32_t bvh_box_rays_soa(const real *bmin, const real *bmax,
                                                                       const BvhPacketSoa *s, uint32_t mask,
                                                                       const real *far)
{
    const __m128 lo[3] = {_mm_set1_ps(bmin[0]), _mm_set1_ps(bmin[1]), _mm_set1_ps(bmin[2])};
    const __m128 hi[3] = {_mm_set1_ps(bmax[0]), _mm_set1_ps(bmax[1]), _mm_set1_ps(bmax[2])};
    return bvh_rows_rays_soa(lo, hi, 7, s, mask, far);
}

/* bvh_node_rays with four rays a step. */
static inline __attribute__((always_inline)) uint32_t bvh_node_rays_soa(const BvhNode *n, const BvhPacketSoa *s, uint32_t mask, const real *far)
{
    return bvh_box_rays_soa(n->bmin, n->bmax, s, mask, far);
}

/* Fills s with the n rays, four lanes a group. */
static inline __attribute__((always_inline)) void bvh_packet_soa(BvhPacketSoa *s, const Ray *rays, int n)
{
    s->groups = (n + 3) / 4;
    for (int i = 0; i < 4 * s->groups; i++) {
        const Ray *r = &rays[i < n ? i : 0]; /* the lanes past n: a copy, masked out */
        for (int a = 0; a < 3; a++)
            s->org[a][i] = r->org.e[a], s->inv[a][i] = r->inv.e[a];
        s->tmin[i] = r->tmin;
    }
}
#endif

/* The rays of `mask` whose slab test enters node n, by s's groups where it has them. */
static inline __attribute__((always_inline)) uint32_t bvh_packet_node(const BvhNode *n, const BvhPacketSoa *s, const Ray *rays, uint32_t mask,
                                       const real *far)
{
#ifdef BVH_PACKET_SSE
    if (s->groups)
        return bvh_node_rays_soa(n, s, mask, far);
#else
    (void)s;
#endif
    return bvh_node_rays(n, rays, mask, far);
}

/* n <= 32 rays through b, far[i] each ray's limit (lowered by the leaves);
 * returns the rays blocked.  simd: test the boxes four rays at a time, for
 * which far must have a multiple of four readable. */
static inline __attribute__((always_inline)) uint32_t bvh_packet(const Bvh *b, const Ray *rays, int n, real *far,
                                                                 BvhPacketLeaf leaf, void *ctx, int simd)
{
    uint32_t done = 0; /* occlusion: the rays already blocked */
    const uint32_t all = n >= 32 ? ~0u : (1u << n) - 1;
    if (b->node_count == 0)
        return 0;
    /* a root that is a leaf (one model instance, say) is neither box-tested
     * nor walked: its primitives' own tests (a model's root node) do that
     * work, and the walk's set-up would be all its cost */
    if (BVH_LONE_LEAF(b->nodes)) /* called directly, the leaf's updates of far, dead after it, go (through
                                  * the loop below they cost a bunny camera packet 3% more instructions) */
        return leaf(ctx, b->prims[b->nodes[0].first], all, far);
    if (b->nodes[0].count) {
        uint32_t rs = all;
        for (uint32_t k = 0; k < b->nodes[0].count && rs; k++) {
            done |= leaf(ctx, b->prims[b->nodes[0].first + k], rs, far);
            rs &= ~done;
        }
        return done;
    }
    struct {
        uint32_t node, rays;
    } stack[BVH_MAX_DEPTH + 1];
    int sp = 0;
    BvhPacketSoa soa;
    soa.groups = 0;
#ifdef BVH_PACKET_SSE
    if (simd)
        bvh_packet_soa(&soa, rays, n);
#else
    (void)simd;
#endif
    uint32_t idx = 0, rs = bvh_packet_node(&b->nodes[0], &soa, rays, all, far);
    for (;;) {
        const BvhNode *nd = &b->nodes[idx];
        if (rs && nd->count == 0) {
            uint32_t r0 = bvh_packet_node(&b->nodes[nd->first], &soa, rays, rs, far);
            uint32_t r1 = bvh_packet_node(&b->nodes[nd->first + 1], &soa, rays, rs, far);
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
            rs = bvh_packet_node(&b->nodes[idx], &soa, rays, stack[sp].rays & ~done, far);
        } while (!rs);
    }
}

#endif
