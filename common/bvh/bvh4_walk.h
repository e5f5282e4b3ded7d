/* bvh4_walk.h - one ray and a packet through the four-wide top-level tree
 * (bvh4.h): bvh_closest, bvh_any and bvh_packet on it, with their leaf
 * callbacks.  Always inlined, as the binary walks are. */
#ifndef LANRAY_BVH4_WALK_H
#define LANRAY_BVH4_WALK_H

#include <assert.h>

#include "bvh/bvh4.h"
#include "bvh/bvh_packet.h"
#include "bvh/bvh_traverse.h"

#if BVH4_COMPILED
#include <emmintrin.h>

/* Pushes at most 3 entries a level over a depth of BVH_MAX_DEPTH, and the last node's 4. */
#define BVH4_STACK (3 * BVH_MAX_DEPTH + 4)

typedef struct {
    __m128 o[3], inv[3], tmin;
    int near[3], far[3]; /* rows of Bvh4Node.box */
} Bvh4Ray;

static inline __attribute__((always_inline)) void bvh4_ray(Bvh4Ray *k, const Ray *r)
{
    for (int a = 0; a < 3; a++) {
        k->o[a] = _mm_set1_ps(r->org.e[a]);
        k->inv[a] = _mm_set1_ps(r->inv.e[a]);
        /* ray_set's choice: the entry plane is bmin where inv >= 0 */
        k->near[a] = r->inv.e[a] >= 0 ? a : a + 3;
        k->far[a] = r->inv.e[a] >= 0 ? a + 3 : a;
    }
    k->tmin = _mm_set1_ps(r->tmin);
}

/* bvh_node_hit on the node's four boxes: the mask of those entered before
 * tmax, their entry distances in *lo_out. */
static inline __attribute__((always_inline)) int bvh4_node_hit(const Bvh4Node *n, const Bvh4Ray *k, float tmax,
                                                               __m128 *lo_out)
{
    __m128 lo = k->tmin, hi = _mm_set1_ps(tmax);
    for (int a = 0; a < 3; a++) {
        const __m128 t0 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n->box[k->near[a]]), k->o[a]), k->inv[a]);
        const __m128 t1 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n->box[k->far[a]]), k->o[a]), k->inv[a]);
        lo = _mm_max_ps(t0, lo); /* t0 > lo ? t0 : lo */
        hi = _mm_min_ps(t1, hi); /* t1 < hi ? t1 : hi */
    }
    *lo_out = lo;
    return _mm_movemask_ps(_mm_cmple_ps(lo, _mm_mul_ps(hi, _mm_set1_ps(BVH_FUDGE)))) & n->lanes;
}

typedef struct {
    uint32_t child, count;
    float t;
} Bvh4Entry;

/* Pushes the children of `mask`, the farthest deepest: closest hits pop
 * the nearest first and drop what lies beyond their hit, any-hit rays
 * meet the nearer, likelier occluder first. */
static inline __attribute__((always_inline)) void bvh4_push(const Bvh4Node *n, int mask, __m128 lo, Bvh4Entry *stack,
                                                            uint32_t *sp)
{
    float tn[4];
    _mm_storeu_ps(tn, lo);
    Bvh4Entry *base = &stack[*sp];
    uint32_t m = 0;
    while (mask) {
        const int i = __builtin_ctz((unsigned)mask);
        mask &= mask - 1;
        const Bvh4Entry x = {n->child[i], n->count[i], tn[i]};
        uint32_t j = m++;
        while (j > 0 && base[j - 1].t < x.t) {
            base[j] = base[j - 1];
            j--;
        }
        base[j] = x;
    }
    *sp += m;
}

/* A node's one or two children hit (mask): the nearer entered at once
 * (*e), the farther pushed, where bvh4_push pushed them all and the walk
 * popped the nearest again; 0 (nothing done) for none or more than two.
 * The 100 spheres path-traced at 2 x 2 (callgrind): 364.6M -> 350.3M
 * instructions, the same hits (the order leaves come in does not matter). */
static inline __attribute__((always_inline)) int bvh4_enter(const Bvh4Node *n, int mask, __m128 lo, Bvh4Entry *stack,
                                                            uint32_t *sp, Bvh4Entry *e)
{
    const int rest = mask & (mask - 1);
    if (!mask || (rest & (rest - 1)))
        return 0;
    const int i = __builtin_ctz((unsigned)mask);
    if (!rest) {
        *e = (Bvh4Entry){n->child[i], n->count[i], 0};
        return 1;
    }
    const int j = __builtin_ctz((unsigned)rest);
    float tn[4];
    _mm_storeu_ps(tn, lo);
    const int near = tn[j] <= tn[i] ? j : i, far = i + j - near;
    stack[(*sp)++] = (Bvh4Entry){n->child[far], n->count[far], tn[far]};
    *e = (Bvh4Entry){n->child[near], n->count[near], 0};
    return 1;
}

/* A closest-hit walk of the four-wide tree, by steps (a node or a leaf),
 * so that two rays' walks can be interleaved (bvh4_closest_pair). */
typedef struct {
    Bvh4Ray k;
    Bvh4Entry e;
    uint32_t sp;
    int found;
    const Ray *r;
    real *tmax;
    void *ctx;
    Bvh4Entry stack[BVH4_STACK];
} Bvh4Walk;

static inline __attribute__((always_inline)) void bvh4_walk_start(Bvh4Walk *s, const Ray *r, real *tmax, void *ctx)
{
    bvh4_ray(&s->k, r);
    s->e = (Bvh4Entry){0, 0, 0};
    s->sp = 0, s->found = 0, s->r = r, s->tmax = tmax, s->ctx = ctx;
}

/* One pass of bvh4_closest's loop; 0 when the walk is over. */
static inline __attribute__((always_inline)) int bvh4_walk_step(Bvh4Walk *s, const Bvh4 *t, BvhLeafClosest leaf)
{
    if (s->e.count) {
        s->found |= leaf(s->ctx, s->e.child, s->e.count, s->r, s->tmax);
    } else {
        const Bvh4Node *n = &t->nodes[s->e.child];
        __m128 lo;
        const int mask = bvh4_node_hit(n, &s->k, *s->tmax, &lo);
        if (bvh4_enter(n, mask, lo, s->stack, &s->sp, &s->e))
            return 1;
        assert(s->sp + 4 <= BVH4_STACK);
        bvh4_push(n, mask, lo, s->stack, &s->sp);
    }
    do {
        if (s->sp == 0)
            return 0;
        s->e = s->stack[--s->sp];
    } while (s->e.t > *s->tmax * BVH_FUDGE);
    return 1;
}

/* bvh_closest on the four-wide tree: the same leaves, the same callback. */
static inline __attribute__((always_inline)) int bvh4_closest(const Bvh4 *t, const Ray *r, real *tmax,
                                                              BvhLeafClosest leaf, void *ctx)
{
    Bvh4Walk x;
    bvh4_walk_start(&x, r, tmax, ctx);
    while (bvh4_walk_step(&x, t, leaf))
        ;
    return x.found;
}

/* bvh4_closest for rays a and b, a step of each in turn: each ray gets
 * the hits it gets alone, and the two chains of dependent loads, tests
 * and divisions (a sphere's) overlap.  A path tracer's bounces
 * (scene/path.c) go by such pairs.  Bit 0 and bit 1: whether each found a
 * hit. */
static inline __attribute__((always_inline)) uint32_t bvh4_closest_pair(const Bvh4 *t, const Ray *a, const Ray *b,
                                                                       real *tmax_a, real *tmax_b,
                                                                       BvhLeafClosest leaf, void *ctx_a, void *ctx_b)
{
    Bvh4Walk x, y;
    bvh4_walk_start(&x, a, tmax_a, ctx_a);
    bvh4_walk_start(&y, b, tmax_b, ctx_b);
    int rx = 1, ry = 1;
    while (rx && ry) {
        rx = bvh4_walk_step(&x, t, leaf);
        ry = bvh4_walk_step(&y, t, leaf);
    }
    while (rx)
        rx = bvh4_walk_step(&x, t, leaf);
    while (ry)
        ry = bvh4_walk_step(&y, t, leaf);
    return (uint32_t)x.found | (uint32_t)y.found << 1;
}

/* bvh_any on the four-wide tree. */
static inline __attribute__((always_inline)) int bvh4_any(const Bvh4 *t, const Ray *r, real tmax, BvhLeafAny leaf,
                                                          const void *ctx)
{
    Bvh4Ray k;
    bvh4_ray(&k, r);
    Bvh4Entry stack[BVH4_STACK];
    uint32_t sp = 0;
    Bvh4Entry e = {0, 0, 0};
    for (;;) {
        if (e.count) {
            if (leaf(ctx, e.child, e.count, r, tmax))
                return 1;
        } else {
            const Bvh4Node *n = &t->nodes[e.child];
            __m128 lo;
            const int mask = bvh4_node_hit(n, &k, tmax, &lo);
            if (bvh4_enter(n, mask, lo, stack, &sp, &e))
                continue;
            assert(sp + 4 <= BVH4_STACK);
            bvh4_push(n, mask, lo, stack, &sp);
        }
        if (sp == 0)
            return 0;
        e = stack[--sp];
    }
}

/* A packet's rays as one interval: per axis the least and greatest origin
 * and reciprocal direction, where every ray's reciprocal has one sign and
 * is finite and nonzero, and the origins lie within ospread of each other
 * on every axis (INFINITY: any).  Its slab test of a node's four boxes admits
 * every box that any of the rays' own tests enters (rounding is monotone:
 * the interval's entry is at most each ray's, its exit at least).  An axis
 * whose reciprocals differ in sign or are infinite (rays towards a light
 * straight above, whose x and z straddle 0) is left out of the interval
 * (`loose`): its reciprocals span [-inf, inf], which bvh4_span_hit's
 * products make -inf (or NaN) at entry and inf (or NaN) at exit, which the
 * max and min pass over; the interval then bounds by the other axes, still
 * never rejecting a box a ray enters, and the leaves' own tests (each ray's,
 * bvh4_child_rays_span) decide.  Such packets had gone ray by ray down the
 * binary tree: a quarter of the shadow packets of the demo's still frame,
 * with a third of the top level's instructions. */
typedef struct {
    __m128 o_near[3], o_far[3], ilo[3], ihi[3], tmin;
    int near[3], far[3]; /* rows of Bvh4Node.box */
    int loose;           /* the axes left out, a bit each */
} Bvh4Span;

/* The least (greatest) of a vector's lanes, in every lane. */
static inline __attribute__((always_inline)) __m128 bvh4_lanes_min(__m128 v)
{
    v = _mm_min_ps(v, _mm_shuffle_ps(v, v, _MM_SHUFFLE(1, 0, 3, 2)));
    return _mm_min_ps(v, _mm_shuffle_ps(v, v, _MM_SHUFFLE(2, 3, 0, 1)));
}

static inline __attribute__((always_inline)) __m128 bvh4_lanes_max(__m128 v)
{
    v = _mm_max_ps(v, _mm_shuffle_ps(v, v, _MM_SHUFFLE(1, 0, 3, 2)));
    return _mm_max_ps(v, _mm_shuffle_ps(v, v, _MM_SHUFFLE(2, 3, 0, 1)));
}

/* The interval from the packet's columns (bvh_packet_soa), all columns in
 * one pass over the groups of four (lanes past n repeat ray 0, so they
 * change no bound): 0 where a ray's origin or reciprocal is NaN (its own
 * tests, which the binary walk keeps) or where the origins spread wider
 * than ospread (0 for closest hits: a caller tests first that they are one
 * point); an axis whose reciprocals differ in sign or are infinite is left
 * out.  Any interval that encloses the rays' own serves (the leaves test
 * each ray), so the order of the min and max does not matter. */
static inline __attribute__((always_inline)) int bvh4_span(Bvh4Span *p, const BvhPacketSoa *s, float ospread)
{
    __m128 tl = _mm_load_ps(s->tmin), bad = _mm_setzero_ps();
    __m128 ol[3], oh[3], il[3], ih[3];
#pragma GCC unroll 3
    for (int a = 0; a < 3; a++) {
        ol[a] = oh[a] = _mm_load_ps(s->org[a]), il[a] = ih[a] = _mm_load_ps(s->inv[a]);
        bad = _mm_or_ps(bad, _mm_cmpunord_ps(ol[a], il[a])); /* either NaN */
    }
    for (int g = 1; g < s->groups; g++) {
        tl = _mm_min_ps(tl, _mm_load_ps(&s->tmin[4 * g]));
#pragma GCC unroll 3
        for (int a = 0; a < 3; a++) {
            const __m128 o = _mm_load_ps(&s->org[a][4 * g]), iv = _mm_load_ps(&s->inv[a][4 * g]);
            ol[a] = _mm_min_ps(ol[a], o), oh[a] = _mm_max_ps(oh[a], o);
            il[a] = _mm_min_ps(il[a], iv), ih[a] = _mm_max_ps(ih[a], iv);
            bad = _mm_or_ps(bad, _mm_cmpunord_ps(o, iv));
        }
    }
    if (_mm_movemask_ps(bad))
        return 0;
    p->tmin = bvh4_lanes_min(tl);
    p->loose = 0;
#pragma GCC unroll 3
    for (int a = 0; a < 3; a++) {
        const __m128 olo = bvh4_lanes_min(ol[a]), ohi = bvh4_lanes_max(oh[a]);
        const __m128 ilo = bvh4_lanes_min(il[a]), ihi = bvh4_lanes_max(ih[a]);
        const float il0 = _mm_cvtss_f32(ilo), ih0 = _mm_cvtss_f32(ihi);
        if (!(_mm_cvtss_f32(ohi) - _mm_cvtss_f32(olo) <= ospread))
            return 0;
        const int pos = il0 > 0 && ih0 < INFINITY, neg = ih0 < 0 && il0 > -INFINITY;
        if (!pos && !neg) { /* left out: a product of +-inf, never a bound */
            p->o_near[a] = p->o_far[a] = _mm_setzero_ps();
            p->ilo[a] = _mm_set1_ps(-INFINITY), p->ihi[a] = _mm_set1_ps(INFINITY);
            p->near[a] = a, p->far[a] = a + 3;
            p->loose |= 1 << a;
            continue;
        }
        p->o_near[a] = pos ? ohi : olo;
        p->o_far[a] = pos ? olo : ohi;
        p->ilo[a] = ilo, p->ihi[a] = ihi;
        p->near[a] = pos ? a : a + 3;
        p->far[a] = pos ? a + 3 : a;
    }
    return 1;
}

/* Whether the packet's rays start at one point (closest-hit packets take
 * the interval only then: a pinhole camera's). */
static inline __attribute__((always_inline)) int bvh4_one_origin(const Ray *rays, int n)
{
    for (int i = 1; i < n; i++)
        if (rays[i].org.x != rays[0].org.x || rays[i].org.y != rays[0].org.y || rays[i].org.z != rays[0].org.z)
            return 0;
    return 1;
}

static inline __attribute__((always_inline)) int bvh4_span_hit(const Bvh4Node *nd, const Bvh4Span *p, float far,
                                                               __m128 *lo_out)
{
    __m128 lo = p->tmin, hi = _mm_set1_ps(far);
    for (int a = 0; a < 3; a++) {
        const __m128 dn = _mm_sub_ps(_mm_load_ps(nd->box[p->near[a]]), p->o_near[a]);
        const __m128 df = _mm_sub_ps(_mm_load_ps(nd->box[p->far[a]]), p->o_far[a]);
        lo = _mm_max_ps(_mm_min_ps(_mm_mul_ps(dn, p->ilo[a]), _mm_mul_ps(dn, p->ihi[a])), lo);
        hi = _mm_min_ps(_mm_max_ps(_mm_mul_ps(df, p->ilo[a]), _mm_mul_ps(df, p->ihi[a])), hi);
    }
    *lo_out = lo;
    return _mm_movemask_ps(_mm_cmple_ps(lo, _mm_mul_ps(hi, _mm_set1_ps(BVH_FUDGE)))) & nd->lanes;
}

/* The rays of `mask` whose own slab test enters child c of node n, for a
 * packet with its interval (bvh4_span): on an axis whose reciprocals share
 * one sign each ray's entry and exit planes are the interval's rows
 * (ray_set's choice, the same for all), so no choice lane by lane; a loose
 * axis keeps it (bvh_rows_rays_soa: the same operations on the same
 * numbers as bvh_box_rays_soa, so the same rays enter).  far: a multiple
 * of four readable. */
static inline __attribute__((always_inline)) uint32_t bvh4_child_rays_span(const Bvh4Node *n, int c, const Bvh4Span *p,
                                                                           const BvhPacketSoa *s, uint32_t mask,
                                                                           const real *far)
{
    __m128 bn[3], bf[3];
    for (int a = 0; a < 3; a++)
        bn[a] = _mm_set1_ps(n->box[p->near[a]][c]), bf[a] = _mm_set1_ps(n->box[p->far[a]][c]);
    return bvh_rows_rays_soa(bn, bf, p->loose, s, mask, far);
}

static inline float bvh4_far_max(const real *far, uint32_t mask)
{
    float m = -INFINITY;
    for (; mask; mask &= mask - 1) {
        const float f = far[__builtin_ctz(mask)];
        m = f > m ? f : m;
    }
    return m;
}

/* bvh_packet on the four-wide tree: n <= 32 rays, far[i] each ray's limit
 * (lowered by the leaves); returns the rays blocked.  Rays whose
 * reciprocal directions share their signs and whose origins lie within
 * ospread of each other test a node's four boxes at once as one interval
 * (bvh4_span), nearest first, and take an interior child together; a leaf
 * child, when it comes off the stack, takes the rays whose own slab test
 * enters it with their limits then (bvh4_child_rays_span, four rays a step).
 * A leaf hands its primitives one by one to the callback with its rays
 * less those blocked since.  Other packets go through the binary tree
 * (bvh_packet): ray by ray their masks part, and its pairs of boxes,
 * tested again as it pops them, cost them less.  far: a multiple of four
 * readable.  any: an occlusion walk, whose leaves block rays and lower no
 * ray's far. */
static inline __attribute__((always_inline)) uint32_t bvh4_packet(const Bvh4 *t, const Bvh *binary, const Ray *rays,
                                                                  int n, real *far, float ospread, int any,
                                                                  BvhPacketLeaf leaf, void *ctx)
{
    struct {
        uint32_t child, count, rays;
        uint32_t parent, lane; /* a leaf's box: lane `lane` of node `parent` */
    } stack[BVH4_STACK];
    if (n <= 0)
        return 0;
    Bvh4Span span;
    BvhPacketSoa soa;
    if (ospread == 0 && !bvh4_one_origin(rays, n)) /* out before the columns are made */
        return bvh_packet(binary, rays, n, far, leaf, ctx, 1);
    bvh_packet_soa(&soa, rays, n);
    if (!bvh4_span(&span, &soa, ospread))
        return bvh_packet(binary, rays, n, far, leaf, ctx, 1);
    const uint32_t all = n >= 32 ? ~0u : (1u << n) - 1;
    uint32_t done = 0, sp = 0;
    uint32_t child = 0, count = 0, rs = all;
    float fmax = bvh4_far_max(far, all);
    for (;;) {
        rs &= ~done;
        if (rs && count) {
            const uint32_t was = done;
            for (uint32_t j = 0; j < count && rs; j++) {
                done |= leaf(ctx, t->prims[child + j], rs, far);
                rs &= ~done;
            }
            if (!any || done != was) /* a hit or a blocker brings it nearer */
                fmax = bvh4_far_max(far, all & ~done);
        } else if (rs) {
            const Bvh4Node *nd = &t->nodes[child];
            __m128 lo;
            int mask = bvh4_span_hit(nd, &span, fmax, &lo);
            if (mask && !(mask & (mask - 1))) { /* one child: entered at once (bvh4_enter) */
                const int c = __builtin_ctz((unsigned)mask);
                const uint32_t parent = child;
                child = nd->child[c], count = nd->count[c];
                if (count) /* a leaf's rays: as when it comes off the stack */
                    rs = bvh4_child_rays_span(&t->nodes[parent], c, &span, &soa, rs, far);
                if (rs)
                    continue;
                mask = 0;
            }
            float tn[4];
            _mm_storeu_ps(tn, lo);
            assert(sp + 4 <= BVH4_STACK);
            const uint32_t base = sp;
            while (mask) { /* the nearest entry popped first: its hits cut the others' rays */
                const int c = __builtin_ctz((unsigned)mask);
                mask &= mask - 1;
                uint32_t j = sp++;
                for (; j > base && tn[stack[j - 1].lane] < tn[c]; j--)
                    stack[j] = stack[j - 1];
                stack[j].child = nd->child[c], stack[j].count = nd->count[c], stack[j].rays = rs;
                stack[j].parent = child, stack[j].lane = (uint32_t)c;
            }
        }
        do {
            if (sp == 0)
                return done;
            --sp;
            child = stack[sp].child, count = stack[sp].count, rs = stack[sp].rays & ~done;
            /* which rays enter a leaf: each ray's own test, when it comes up (a
             * nearer hit since may keep a ray out) */
            if (rs && count)
                rs = bvh4_child_rays_span(&t->nodes[stack[sp].parent], (int)stack[sp].lane, &span, &soa, rs, far);
        } while (!rs);
    }
}
#endif

#endif
