/* bvh.h - bounding volume hierarchies: flat layout, builders, slab test.
 *
 * Invariants of a built or loaded Bvh (checked by bvh_validate):
 *  - node 0 is the root; an interior node's two children sit side by side at
 *    `first` and `first + 1`, always after their parent;
 *  - a leaf (count > 0) covers primitives [first, first + count) of `prims`
 *    (or of the caller's reordered arrays when prims is NULL);
 *  - depth <= BVH_MAX_DEPTH, so traversal needs a fixed stack of that size. */
#ifndef LANRAY_BVH_H
#define LANRAY_BVH_H

#include <stddef.h>
#include <stdint.h>

#include "geom/aabb.h"
#include "base/err.h"
#include "base/pool.h"
#include "geom/ray.h"

#define BVH_MAX_DEPTH 64
#define BVH_MAX_PRIMS (1u << 26)

/* Builds of at least BVH_POOL_MIN primitives run their passes over every
 * primitive (boxes, references, the triangles' reordering) on a pool of
 * opt->threads threads, at most BVH_POOL_MAX; smaller ones on the caller. */
#define BVH_POOL_MIN 65536u
#define BVH_POOL_MAX 64
#define BVH_POOL_GRAIN (BVH_POOL_MIN / 4) /* primitives a pool_for range holds at least */

/* 32 bytes in the float build: two nodes per 64-byte cache line. */
typedef struct __attribute__((aligned(32))) {
    real bmin[3];
    uint32_t first; /* interior: index of the first child; leaf: first primitive */
    real bmax[3];
    uint32_t count; /* 0 for an interior node, else the number of primitives */
} BvhNode;

typedef enum { BVH_SBT = 0, BVH_MST = 1, BVH_SAH = 2, BVH_KIND_COUNT } BvhKind;

/* The traversal tests a leaf's triangles four at a time (wide.h), so a leaf
 * of 1 to 4 costs about what one triangle does: the SAH builder and the
 * MST's collapse count a leaf's cost in blocks of 4, not in triangles.
 * Measured against the triangle count (make bench, 1 thread, AVX2): leaves
 * grow from 1.7 triangles on average to 5, and Embree's ratio from 0.91 to
 * 1.13 (elephant), 1.09 to 1.24 (bunny). */
#define BVH_LEAF_BLOCK 4
static inline uint32_t bvh_leaf_blocks(uint32_t n) { return (n + BVH_LEAF_BLOCK - 1) / BVH_LEAF_BLOCK; }

typedef struct {
    BvhKind kind;
    uint32_t max_leaf;     /* most primitives per leaf (the MST and SAH may use fewer) */
    int sbt_alternate;     /* SBT: split axes in turn x, y, z instead of the longest */
    int threads;           /* builder threads (1 by default; obj2tmd: one per core) */
} BvhOptions;

typedef struct {
    BvhNode *nodes;   /* see bvh_alloc_nodes for the alignment */
    void *nodes_mem;  /* what to free */
    uint32_t node_count;
    uint32_t *prims; /* leaf order -> caller's primitive index; NULL once the caller reordered */
    uint32_t prim_count;
    uint32_t depth; /* nodes on the longest root-to-leaf path */
    BvhKind kind;
} Bvh;

BvhOptions bvh_options_default(BvhKind kind);
/* Builds over n boxes. Empty boxes are not allowed (callers drop degenerate input). */
int bvh_build(Bvh *out, const Aabb *boxes, uint32_t n, const BvhOptions *opt, Err *err);
/* The pool for a build of n primitives: NULL (the caller alone) for one
 * thread or fewer than BVH_POOL_MIN primitives, or when no thread starts. */
Pool *bvh_pool_create(uint32_t n, const BvhOptions *opt);
/* bvh_build on the caller's pool (from bvh_pool_create, or NULL), so that
 * a model's passes around the tree and the tree's own share one set of
 * threads. */
int bvh_build_on(Bvh *out, const Aabb *boxes, uint32_t n, const BvhOptions *opt, Pool *pool, Err *err);
void bvh_destroy(Bvh *b);
/* Allocates b->nodes for count nodes.  Sibling pairs always start at odd
 * indices (the root is 0, then pairs follow), so the array is placed 32 bytes
 * past a 64-byte boundary: each pair then shares one cache line and a visit
 * to an interior node touches a single line for both child boxes. */
int bvh_alloc_nodes(Bvh *b, uint32_t count);
/* Structural check of a tree that came from outside (a .tmd file); writes
 * the measured depth to *depth (may be NULL). */
int bvh_validate(const Bvh *b, uint32_t *depth, Err *err);
/* SAH cost with traversal cost 1 and intersection cost 1, relative to the root area. */
double bvh_sah_cost(const Bvh *b);
/* The builders' names in BvhKind order, NULL-terminated (scene files, command lines). */
extern const char *const bvh_kind_names[];
const char *bvh_kind_name(BvhKind k);
int bvh_kind_parse(const char *s, BvhKind *out);
static inline Aabb bvh_node_box(const BvhNode *n)
{
    Aabb b = {v3(n->bmin[0], n->bmin[1], n->bmin[2]), v3(n->bmax[0], n->bmax[1], n->bmax[2])};
    return b;
}

/* Ize's conservative factor ("Robust BVH Ray Traversal", JCGT 2013): the
 * computed slab distances are off by at most gamma(3) relative, so far
 * distances and the current closest hit are enlarged by 1 + 2*gamma(3)
 * before comparing with an entry distance. */
#define BVH_FUDGE (R(1) + R(2) * real_gamma(3))

/* A tree that is one leaf of one primitive (a scene of one model: its top
 * level) goes straight to the primitive, single rays and packets alike:
 * the box around it would test what the primitive's own test does (a
 * model's wide tree starts with its children's boxes), and cost the ray a
 * slab test and the walk's set-up. */
#define BVH_LONE_LEAF(nodes) ((nodes)[0].count == 1)

/* The slab test reads a node as reals: bmin at 0..2, bmax at 4..6. */
_Static_assert(offsetof(BvhNode, bmax) == 4 * sizeof(real), "BvhNode layout: bmax must start at real 4");

/* Slab test: a box grazed by the ray, or holding a hit exactly as far as the
 * current closest one, is never lost to rounding.  The entry and exit planes
 * are chosen by the sign of the direction (precomputed in the Ray), so no
 * min/max per axis.  A NaN (ray parallel to and exactly in a slab's plane:
 * 0 * inf) is ignored, i.e. treated as inside that slab: conservative.
 * Writes the entry distance. */
static inline __attribute__((always_inline)) int bvh_node_hit(const BvhNode *n, const Ray *r, real tmax, real *tnear)
{
    const real *f = (const real *)(const void *)n;
    real lo = r->tmin, hi = tmax;
    for (int a = 0; a < 3; a++) {
        real t0 = (f[r->near[a]] - r->org.e[a]) * r->inv.e[a];
        real t1 = (f[r->far[a]] - r->org.e[a]) * r->inv.e[a];
        lo = t0 > lo ? t0 : lo; /* NaN compares false: keeps lo */
        hi = t1 < hi ? t1 : hi;
    }
    *tnear = lo;
    return lo <= hi * BVH_FUDGE;
}

#endif
