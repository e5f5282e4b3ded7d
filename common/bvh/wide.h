/* wide.h - a model's BVH collapsed into 4- or 8-wide nodes for SIMD traversal.
 *
 * Built from the model's binary tree (any builder, or a .tmd file's tree)
 * when a scene is prepared, for the SIMD path in use (simd.h): 4-wide nodes
 * for SSE, 8-wide for AVX2.  A node holds its children's boxes in
 * structure-of-arrays form (one row of W floats per bound), so one vector
 * compare tests all children; leaves are blocks of 4 triangles, vertex
 * coordinates again in rows of 4, tested at once.
 *
 * Why every path gives the same pixels: the closest hit is defined without
 * reference to the visiting order.  Among all triangles with tmin < t < tmax
 * it is the smallest t, and of equal t the smallest triangle index (the
 * binary traversal applies the same rule).  The triangle test is the same
 * arithmetic, operation for operation, in every path (no contraction into
 * FMA), and the box tests are conservative, so they never drop the hit;
 * whatever order a path visits leaves in, it ends with the same hit. */
#ifndef LANRAY_WIDE_H
#define LANRAY_WIDE_H

#include <stddef.h>
#include <stdint.h>

#include "bvh/bvh.h"
#include "base/err.h"
#include "geom/intersect.h"

#define WIDE_TRIS 4   /* triangles per leaf block */
#define WIDE_PACKET 8 /* most rays in a packet */
/* Closest-hit packets of rays whose directions spread wider than this on
 * an axis go ray by ray: the mirrored, refracted and bounced rays of
 * neighbouring pixels off a bumpy surface enter, as one interval box,
 * nodes that no ray does.  Measured (tools/bench/rayclass, the
 * 1M-triangle sphere, 1 thread, Mrays/s packets/single, best of 6):
 * refracted rays with no limit 0.54-0.59 / 1.49-1.68, directions within
 * 0.1 on every axis 1.15-1.38, 0.03 1.59-1.62, 0.01 1.53-1.83; camera rays
 * (8 neighbours spread 0.007) keep their packets. */
#ifndef WIDE_DIR_SPREAD
#define WIDE_DIR_SPREAD 0.03f
#endif

/* Mirrored and refracted packets in a world of one model whose first and
 * last origins lie more than this many mean leaf sizes apart go ray by ray
 * (trace.c trace_closest_bounced): over a fine mesh, where each ray's walk
 * is its own, the packet's interval walk cost more than it shared.
 * Measured (tools/bench/rayclass, 1 thread, packets over Embree's best,
 * two runs): no limit, the 1M sphere's mirrored rays 0.90-0.94 and
 * refracted 0.86-0.93 (rays one by one 3-5% faster than the packets), the
 * bunny's 0.99-1.02 and 1.11-1.17; 1 leaf, 0.91-0.96, 0.89-0.91 (as one by
 * one) and 0.99, 1.11-1.13; a quarter, the bunny's refracted rays lose
 * their packets (0.96-0.97). */
#ifndef WIDE_BOUNCE_LEAVES
#define WIDE_BOUNCE_LEAVES 1
#endif

/* The SIMD kernels exist in float builds on x86-64 only. */
#if defined(__x86_64__) && !defined(LANRAY_DOUBLE)
#define WIDE_COMPILED 1
#else
#define WIDE_COMPILED 0
#endif

/* Four triangles, coordinates by vertex, axis, lane.  Lanes past a leaf's
 * last triangle repeat it (same index: a repeat never changes a result). */
typedef struct __attribute__((aligned(16))) {
    float v[3][3][WIDE_TRIS];
    uint32_t idx[WIDE_TRIS]; /* index into the model's tris[] */
} WideTris;

typedef struct Wide Wide;

typedef struct {
    real t, b1, b2;
    uint32_t tri;
} WideHit;

struct Wide {
    int width;          /* children per node: 4 or 8 */
    size_t node_bytes;  /* bytes per node */
    void *nodes;        /* node_count nodes of node_bytes, 64-byte aligned */
    uint32_t node_count;
    WideTris *tris;     /* leaf blocks */
    uint32_t block_count;
    uint32_t root;      /* root: a node, or a leaf when root_blocks > 0 */
    uint32_t root_blocks;
    uint32_t depth;     /* nodes on the longest path (for the stack bound) */
    float leaf_size;    /* mean largest extent of a leaf's box: packets of shadow rays
                         * whose origins spread wider go ray by ray (wide_kernel.h) */
    /* tie: a hit at exactly tmax is taken when its triangle index is below
     * tie (0: never; UINT32_MAX: always) */
    int (*closest)(const Wide *w, const Ray *r, real tmax, uint32_t tie, WideHit *hit);
    int (*any)(const Wide *w, const Ray *r, real tmax);
    /* n rays each alone, as closest gives them (their walks interleaved
     * by pairs: wide_kernel.h); the mask of the rays hit */
    uint32_t (*closest_pairs)(const Wide *w, const Ray *const *rays, int n, const real *tmax, const uint32_t *tie,
                              WideHit *hits);
    /* n <= WIDE_PACKET rays at once; the mask of rays hit */
    uint32_t (*closest_packet)(const Wide *w, const Ray *const *rays, int n, const real *tmax, const uint32_t *tie,
                               WideHit *hits);
    uint32_t (*any_packet)(const Wide *w, const Ray *const *rays, int n, const real *tmax);
};

/* Node layout for width W, at byte 0 of a node:
 *   float box[6][W]    rows min x, min y, min z, max x, max y, max z;
 *                      an unused child has min +inf, max -inf (never hit)
 *   uint32_t child[W]  a node index, or a leaf's first block
 *   uint8_t blocks[W]  0 for a node, else the leaf's number of blocks */
#define WIDE_BOX_FLOATS(W) (6 * (W))
#define WIDE_CHILD_OFFSET(W) (WIDE_BOX_FLOATS(W) * 4)
#define WIDE_BLOCKS_OFFSET(W) (WIDE_CHILD_OFFSET(W) + 4 * (W))

/* Collapses `bvh` (over `tris`, in leaf order) into a wide tree for `path`
 * (SIMD_SSE, SIMD_AVX2 or SIMD_AVX512).  *out is NULL for an empty tree. */
int wide_build(Wide **out, const Bvh *bvh, const Tri *tris, int path, Err *err);
void wide_destroy(Wide *w);
/* Bytes held: nodes and triangle blocks. */
size_t wide_bytes(const Wide *w);

/* The traversal kernels (wide_sse.c, wide_avx2.c). */
int wide4_closest_sse(const Wide *w, const Ray *r, real tmax, uint32_t tie, WideHit *hit);
int wide4_any_sse(const Wide *w, const Ray *r, real tmax);
uint32_t wide4_closest_pairs_sse(const Wide *w, const Ray *const *rays, int n, const real *tmax, const uint32_t *tie,
                                 WideHit *hits);
uint32_t wide8_closest_pairs_avx2(const Wide *w, const Ray *const *rays, int n, const real *tmax, const uint32_t *tie,
                                  WideHit *hits);
uint32_t wide4_closest_packet_sse(const Wide *w, const Ray *const *rays, int n, const real *tmax, const uint32_t *tie,
                                  WideHit *hits);
uint32_t wide4_any_packet_sse(const Wide *w, const Ray *const *rays, int n, const real *tmax);
int wide8_closest_avx2(const Wide *w, const Ray *r, real tmax, uint32_t tie, WideHit *hit);
int wide8_any_avx2(const Wide *w, const Ray *r, real tmax);
uint32_t wide8_closest_packet_avx2(const Wide *w, const Ray *const *rays, int n, const real *tmax, const uint32_t *tie,
                                   WideHit *hits);
uint32_t wide8_any_packet_avx2(const Wide *w, const Ray *const *rays, int n, const real *tmax);
int wide8_closest_avx512(const Wide *w, const Ray *r, real tmax, uint32_t tie, WideHit *hit);
int wide8_any_avx512(const Wide *w, const Ray *r, real tmax);
uint32_t wide8_closest_pairs_avx512(const Wide *w, const Ray *const *rays, int n, const real *tmax,
                                    const uint32_t *tie, WideHit *hits);
uint32_t wide8_closest_packet_avx512(const Wide *w, const Ray *const *rays, int n, const real *tmax,
                                     const uint32_t *tie, WideHit *hits);
uint32_t wide8_any_packet_avx512(const Wide *w, const Ray *const *rays, int n, const real *tmax);

#endif
