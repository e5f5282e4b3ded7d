/* wide_kernel.h - the wide-BVH traversal, written once for every node width.
 *
 * Included by wide_sse.c (4-wide nodes, SSE) and wide_avx2.c (8-wide nodes,
 * AVX2) after they define:
 *   NW                   children per node
 *   VN                   a vector of NW floats, and VN_SET1, VN_LOAD, VN_STORE,
 *                        VN_MIN, VN_MAX, VN_LE_MASK (a <= b as a bit mask)
 *   KERNEL_CLOSEST, KERNEL_ANY   the names of the single-ray entry points
 *   KERNEL_CLOSEST_PAIRS the name of the entry point for rays alone by pairs
 *   KERNEL_CLOSEST_PACKET, KERNEL_ANY_PACKET   and of the packet ones
 * The triangle blocks are always 4 wide (SSE; VEX-encoded in the AVX2 file).
 *
 * Every operation of the triangle test is the scalar tri_intersect's, in
 * the same order, so every lane gives the scalar path's t, b1 and b2 to the
 * bit; see wide.h for why the visiting order does not matter. */
#include <assert.h>
#include <immintrin.h>
#include <stddef.h>
#include <string.h>

#include "bvh/wide.h"

#ifndef WIDE_KERNEL_COMMON
#define WIDE_KERNEL_COMMON

typedef struct {
    uint32_t id, blocks;
    float t;
    uint32_t rays; /* packets: the rays that may hit it (a leaf's rays are tested one by one) */
} WideEntry;

/* The single-ray walks' enlarging of exit distances (WIDE_NODE_TEST), the
 * role of BVH_FUDGE.  A computed entry distance is at most its true value
 * times 1 + gamma(3) (Ize); an exit distance taken as (bound - o) x
 * fl(inv x WIDE_FAR) passes four roundings, so it is at least its true
 * value times WIDE_FAR x (1 - gamma(4)), which is above 1 + gamma(3) for
 * any WIDE_FAR above 1 + 7u.  1 + 4 gamma(3) (1 + 12u) leaves a margin;
 * the tmax it is compared with is enlarged by the same factor. */
#define WIDE_FAR ((float)(1.0 + 4.0 * (3.0 * 0x1p-24 / (1.0 - 3.0 * 0x1p-24))))

/* A ray's constants for the triangle test, splatted. */
typedef struct {
    int kx, ky, kz;
    int ahead; /* tmin >= 0: only hits ahead of the origin count (WIDE_BEHIND) */
    __m128 ox, oy, oz; /* origin in the sheared frame's axis order */
    __m128 sx, sy, sz, tmin;
} WideRay;

/* A ray with a NaN in its origin or direction (from a degenerate camera)
 * passes every slab test (a NaN leaves a bound as it was), unused children
 * included, whose child 0 is the root: it would walk in circles.  It hits
 * nothing.  (The packets' set-up already refuses such rays.) */
static inline __attribute__((always_inline)) int wide_ray_nan(const Ray *r)
{
    /* one sum, NaN where any term is (or where infinities of both signs
     * meet, a ray from nowhere that hits nothing either) */
    const real s = r->dir.x + r->dir.y + r->dir.z + r->org.x + r->org.y + r->org.z;
    return s != s;
}

/* Which of the inverse direction's components are negative, as bits
 * x, y, z (a component >= 0 is positive, as the scalar walk's rows have
 * it; NaN rays never get here: wide_ray_nan).  One load reads inv and the
 * tmin after it. */
_Static_assert(offsetof(Ray, inv) + 4 * sizeof(float) <= sizeof(Ray), "wide_ray_octant reads 16 bytes at inv");
static inline __attribute__((always_inline)) int wide_ray_octant(const Ray *r)
{
    return _mm_movemask_ps(_mm_cmplt_ps(_mm_loadu_ps(&r->inv.x), _mm_setzero_ps())) & 7;
}

static inline __attribute__((always_inline)) void wide_ray_setup(WideRay *k, const Ray *r)
{
    k->kx = r->kx, k->ky = r->ky, k->kz = r->kz;
    k->ahead = r->tmin >= 0;
    k->ox = _mm_set1_ps(r->org.e[r->kx]);
    k->oy = _mm_set1_ps(r->org.e[r->ky]);
    k->oz = _mm_set1_ps(r->org.e[r->kz]);
    k->sx = _mm_set1_ps(r->sx);
    k->sy = _mm_set1_ps(r->sy);
    k->sz = _mm_set1_ps(r->sz);
    k->tmin = _mm_set1_ps(r->tmin);
}

/* The lanes of z whose U, V or W came out exactly zero (an edge through
 * the ray) computed again in double from the sheared coordinates, as the
 * scalar tri_intersect does: fa holds the rows Ax, Ay, Bx, By, Cx, Cy, fu
 * the rows U, V, W, rewritten in those lanes.  One for the four- and the
 * eight-lane test, so both stay the scalar test's arithmetic. */
static inline void wide_edges_in_double(int z, const float fa[6][8], float fu[3][8])
{
    for (int l = 0; l < 8; l++)
        if (z >> l & 1) {
            double xa = fa[0][l], ya = fa[1][l], xb = fa[2][l], yb = fa[3][l], xc = fa[4][l], yc = fa[5][l];
            fu[0][l] = (float)(xc * yb - yc * xb);
            fu[1][l] = (float)(xa * yc - ya * xc);
            fu[2][l] = (float)(xb * ya - yb * xa);
        }
}

/* WIDE_SIGNS_DIFFER: a lane misses where U, V and W have mixed signs.
 * Where none of them is zero (z, tested first; -0 included), that is where
 * the sign bits differ: their OR has it and their AND has not, three
 * logical operations instead of six compares; only the sign bit of the
 * result counts (a movemask reads it, or an arithmetic shift spreads it).
 * A NaN lane may come out either way, and never hits: its det is NaN. */

/* WIDE_BEHIND: t = T x (1 / det) has the sign of T times det's (or is
 * zero, or NaN), so a lane whose T and det differ in sign has t <= 0 and
 * cannot pass tmin < t where tmin >= 0: where every lane is outside or so,
 * the test ends before its division.  Taken from a ray's surface (the
 * diffuse bounces, mirrored and shadow rays), the triangles about the
 * origin lie behind it: measured (tools/bench/rayclass, the bunny's diffuse
 * bounces), half the blocks that reached the division hit nothing, and
 * all but 0.1% of those had every lane behind or outside. */

/* Four triangles at once: the lanes that hit with tmin < t and t < tmax
 * (t <= tmax when `upto`), as a bit mask; their t, V, W and 1/det. */
static inline __attribute__((always_inline)) int wide_tris_hit(const WideTris *b, const WideRay *k, float tmax, int upto,
                                                               __m128 *t_out, __m128 *v_out, __m128 *w_out,
                                                               __m128 *inv_out)
{
    const __m128 ax = _mm_load_ps(b->v[0][k->kx]) - k->ox, ay = _mm_load_ps(b->v[0][k->ky]) - k->oy,
                 az = _mm_load_ps(b->v[0][k->kz]) - k->oz;
    const __m128 bx = _mm_load_ps(b->v[1][k->kx]) - k->ox, by = _mm_load_ps(b->v[1][k->ky]) - k->oy,
                 bz = _mm_load_ps(b->v[1][k->kz]) - k->oz;
    const __m128 cx = _mm_load_ps(b->v[2][k->kx]) - k->ox, cy = _mm_load_ps(b->v[2][k->ky]) - k->oy,
                 cz = _mm_load_ps(b->v[2][k->kz]) - k->oz;
    const __m128 Ax = ax - k->sx * az, Ay = ay - k->sy * az;
    const __m128 Bx = bx - k->sx * bz, By = by - k->sy * bz;
    const __m128 Cx = cx - k->sx * cz, Cy = cy - k->sy * cz;
    __m128 U = Cx * By - Cy * Bx;
    __m128 V = Ax * Cy - Ay * Cx;
    __m128 W = Bx * Ay - By * Ax;
    const __m128 zero = _mm_setzero_ps();
    int z = _mm_movemask_ps(_mm_or_ps(_mm_or_ps(_mm_cmpeq_ps(U, zero), _mm_cmpeq_ps(V, zero)), _mm_cmpeq_ps(W, zero)));
    if (__builtin_expect(z != 0, 0)) { /* an edge through the ray: redo those lanes in double, as the scalar test does */
        float fa[6][8], fu[3][8];
        _mm_storeu_ps(fa[0], Ax), _mm_storeu_ps(fa[1], Ay), _mm_storeu_ps(fa[2], Bx);
        _mm_storeu_ps(fa[3], By), _mm_storeu_ps(fa[4], Cx), _mm_storeu_ps(fa[5], Cy);
        _mm_storeu_ps(fu[0], U), _mm_storeu_ps(fu[1], V), _mm_storeu_ps(fu[2], W);
        wide_edges_in_double(z, (const float(*)[8])fa, fu); /* z has lanes 0-3 only */
        U = _mm_loadu_ps(fu[0]), V = _mm_loadu_ps(fu[1]), W = _mm_loadu_ps(fu[2]);
    }
    __m128 outside;
    if (__builtin_expect(z == 0, 1)) { /* no zero: a lane is outside where the signs differ (WIDE_SIGNS_DIFFER) */
        outside = _mm_andnot_ps(_mm_and_ps(_mm_and_ps(U, V), W), _mm_or_ps(_mm_or_ps(U, V), W));
    } else {
        const __m128 neg = _mm_or_ps(_mm_or_ps(_mm_cmplt_ps(U, zero), _mm_cmplt_ps(V, zero)), _mm_cmplt_ps(W, zero));
        const __m128 pos = _mm_or_ps(_mm_or_ps(_mm_cmpgt_ps(U, zero), _mm_cmpgt_ps(V, zero)), _mm_cmpgt_ps(W, zero));
        outside = _mm_and_ps(neg, pos);
    }
    /* most blocks a ray reaches it passes by: stop before the division */
    if (_mm_movemask_ps(outside) == 0xf)
        return 0;
    const __m128 det = U + V + W;
    const __m128 T = U * (k->sz * az) + V * (k->sz * bz) + W * (k->sz * cz);
    if (k->ahead && _mm_movemask_ps(_mm_or_ps(outside, _mm_xor_ps(T, det))) == 0xf) /* WIDE_BEHIND */
        return 0;
    const __m128 inv = _mm_set1_ps(1.0f) / det;
    const __m128 t = T * inv;
    const __m128 vt = _mm_set1_ps(tmax);
    __m128 ok = _mm_and_ps(_mm_cmpgt_ps(t, k->tmin), upto ? _mm_cmple_ps(t, vt) : _mm_cmplt_ps(t, vt));
    ok = _mm_andnot_ps(_mm_or_ps(outside, _mm_cmpeq_ps(det, zero)), ok);
    *t_out = t, *v_out = V, *w_out = W, *inv_out = inv;
    return _mm_movemask_ps(ok);
}

/* The lanes of mask, in lane order, against the hit so far: the smaller t,
 * and of equal t the smaller triangle index (wide.h), so the order leaves
 * come in does not matter.  Returns 1 when one was taken. */
static inline __attribute__((always_inline)) int wide_take_lanes(const uint32_t *ids, int mask, const float *ts,
                                                                 const float *vs, const float *ws, const float *is,
                                                                 float *best, uint32_t *best_idx, WideHit *hit)
{
    int took = 0;
    while (mask) {
        int l = __builtin_ctz((unsigned)mask);
        mask &= mask - 1;
        uint32_t id = ids[l];
        if (ts[l] < *best || (ts[l] == *best && id < *best_idx)) {
            *best = ts[l];
            *best_idx = id;
            *hit = (WideHit){ts[l], vs[l] * is[l], ws[l] * is[l], id};
            took = 1;
        }
    }
    return took;
}

static inline __attribute__((always_inline)) int wide_take(const WideTris *blk, int mask, __m128 t, __m128 v, __m128 w,
                                                           __m128 inv, float *best, uint32_t *best_idx, WideHit *hit)
{
    float ts[4], vs[4], ws[4], is[4];
    _mm_storeu_ps(ts, t), _mm_storeu_ps(vs, v), _mm_storeu_ps(ws, w), _mm_storeu_ps(is, inv);
    return wide_take_lanes(blk->idx, mask, ts, vs, ws, is, best, best_idx, hit);
}

#endif

#if NW == 8
/* Two blocks, eight triangles, in one AVX test: wide_tris_hit's arithmetic
 * lane for lane (rows of the second block in the upper half), so every
 * lane gives what the four-wide test gives it.  A leaf's blocks go by
 * pairs here; on these CPUs a 256-bit operation costs about what a 128-bit
 * one does. */
static inline __attribute__((always_inline)) int wide_tris_hit8(const WideTris *b0, const WideTris *b1, const WideRay *k,
                                                                float tmax, int upto, float *t_out, float *v_out,
                                                                float *w_out, float *inv_out)
{
#define ROW(vx, ax_) _mm256_set_m128(_mm_load_ps(b1->v[vx][ax_]), _mm_load_ps(b0->v[vx][ax_]))
    const __m256 ox = _mm256_broadcast_ps(&k->ox), oy = _mm256_broadcast_ps(&k->oy), oz = _mm256_broadcast_ps(&k->oz);
    const __m256 sx = _mm256_broadcast_ps(&k->sx), sy = _mm256_broadcast_ps(&k->sy), sz = _mm256_broadcast_ps(&k->sz);
    const __m256 ax = ROW(0, k->kx) - ox, ay = ROW(0, k->ky) - oy, az = ROW(0, k->kz) - oz;
    const __m256 bx = ROW(1, k->kx) - ox, by = ROW(1, k->ky) - oy, bz = ROW(1, k->kz) - oz;
    const __m256 cx = ROW(2, k->kx) - ox, cy = ROW(2, k->ky) - oy, cz = ROW(2, k->kz) - oz;
#undef ROW
    const __m256 Ax = ax - sx * az, Ay = ay - sy * az;
    const __m256 Bx = bx - sx * bz, By = by - sy * bz;
    const __m256 Cx = cx - sx * cz, Cy = cy - sy * cz;
    __m256 U = Cx * By - Cy * Bx;
    __m256 V = Ax * Cy - Ay * Cx;
    __m256 W = Bx * Ay - By * Ax;
    const __m256 zero = _mm256_setzero_ps();
    int z = _mm256_movemask_ps(_mm256_or_ps(_mm256_or_ps(_mm256_cmp_ps(U, zero, _CMP_EQ_OQ), _mm256_cmp_ps(V, zero, _CMP_EQ_OQ)),
                                            _mm256_cmp_ps(W, zero, _CMP_EQ_OQ)));
    if (__builtin_expect(z != 0, 0)) { /* an edge through the ray: those lanes in double, as the scalar test does */
        float fa[6][8], fu[3][8];
        _mm256_storeu_ps(fa[0], Ax), _mm256_storeu_ps(fa[1], Ay), _mm256_storeu_ps(fa[2], Bx);
        _mm256_storeu_ps(fa[3], By), _mm256_storeu_ps(fa[4], Cx), _mm256_storeu_ps(fa[5], Cy);
        _mm256_storeu_ps(fu[0], U), _mm256_storeu_ps(fu[1], V), _mm256_storeu_ps(fu[2], W);
        wide_edges_in_double(z, (const float(*)[8])fa, fu);
        U = _mm256_loadu_ps(fu[0]), V = _mm256_loadu_ps(fu[1]), W = _mm256_loadu_ps(fu[2]);
    }
    __m256 outside;
    if (__builtin_expect(z == 0, 1)) { /* WIDE_SIGNS_DIFFER */
        outside = _mm256_andnot_ps(_mm256_and_ps(_mm256_and_ps(U, V), W), _mm256_or_ps(_mm256_or_ps(U, V), W));
    } else {
        const __m256 neg = _mm256_or_ps(
            _mm256_or_ps(_mm256_cmp_ps(U, zero, _CMP_LT_OQ), _mm256_cmp_ps(V, zero, _CMP_LT_OQ)),
            _mm256_cmp_ps(W, zero, _CMP_LT_OQ));
        const __m256 pos = _mm256_or_ps(
            _mm256_or_ps(_mm256_cmp_ps(U, zero, _CMP_GT_OQ), _mm256_cmp_ps(V, zero, _CMP_GT_OQ)),
            _mm256_cmp_ps(W, zero, _CMP_GT_OQ));
        outside = _mm256_and_ps(neg, pos);
    }
    if (_mm256_movemask_ps(outside) == 0xff)
        return 0;
    const __m256 det = U + V + W;
    const __m256 T = U * (sz * az) + V * (sz * bz) + W * (sz * cz);
    if (k->ahead && _mm256_movemask_ps(_mm256_or_ps(outside, _mm256_xor_ps(T, det))) == 0xff) /* WIDE_BEHIND */
        return 0;
    const __m256 inv = _mm256_set1_ps(1.0f) / det;
    const __m256 t = T * inv;
    const __m256 vt = _mm256_set1_ps(tmax);
    __m256 ok = _mm256_and_ps(_mm256_cmp_ps(t, _mm256_broadcast_ps(&k->tmin), _CMP_GT_OQ),
                              upto ? _mm256_cmp_ps(t, vt, _CMP_LE_OQ) : _mm256_cmp_ps(t, vt, _CMP_LT_OQ));
    ok = _mm256_andnot_ps(_mm256_or_ps(outside, _mm256_cmp_ps(det, zero, _CMP_EQ_OQ)), ok);
    const int mask = _mm256_movemask_ps(ok);
    if (mask && t_out) {
        _mm256_storeu_ps(t_out, t), _mm256_storeu_ps(v_out, V), _mm256_storeu_ps(w_out, W);
        _mm256_storeu_ps(inv_out, inv);
    }
    return mask;
}
#endif

/* One block against one ray, the hits taken by the rule (wide_take). */
static inline __attribute__((always_inline)) int wide_block_closest(const WideTris *blk, const WideRay *k, float *best,
                                                                   uint32_t *best_idx, WideHit *hit)
{
    __m128 t, v, ww, inv;
    const int m = wide_tris_hit(blk, k, *best, 1, &t, &v, &ww, &inv);
    return m ? wide_take(blk, m, t, v, ww, inv, best, best_idx, hit) : 0;
}

#if NW == 8
/* Blocks blk[0] and blk[1] in one eight-lane test. */
static inline __attribute__((always_inline)) int wide_pair_closest(const WideTris *blk, const WideRay *k, float *best,
                                                                  uint32_t *best_idx, WideHit *hit)
{
    float ts[8], vs[8], ws[8], is[8];
    const int m = wide_tris_hit8(&blk[0], &blk[1], k, *best, 1, ts, vs, ws, is);
    if (!m)
        return 0;
    uint32_t ids[8];
    memcpy(ids, blk[0].idx, sizeof blk[0].idx), memcpy(ids + 4, blk[1].idx, sizeof blk[1].idx);
    return wide_take_lanes(ids, m, ts, vs, ws, is, best, best_idx, hit);
}
#endif

/* A leaf's blocks against one ray, the hits taken by the rule: by pairs
 * in one eight-lane test where the nodes are eight wide (AVX2). */
static inline __attribute__((always_inline)) int wide_leaf_closest(const WideTris *blk, uint32_t blocks, const WideRay *k,
                                                                  float *best, uint32_t *best_idx, WideHit *hit)
{
    int found = 0;
    uint32_t b = 0;
#if NW == 8
    for (; b + 1 < blocks; b += 2)
        found |= wide_pair_closest(&blk[b], k, best, best_idx, hit);
#endif
    for (; b < blocks; b++)
        found |= wide_block_closest(&blk[b], k, best, best_idx, hit);
    return found;
}

/* The same for the single-ray walk, out of line: there the node constants
 * fill the vector registers, and the leaf test inlined spilled and copied
 * them on every leaf visit.  noipa: the caller must not learn that the ray
 * survives the call, so that it loads its node constants from the ray again
 * after it rather than keep them across it. */
static __attribute__((noipa)) int wide_leaf_closest_many(const WideTris *blk, uint32_t blocks, const WideRay *k,
                                                         float *best, uint32_t *best_idx, WideHit *hit)
{
    return wide_leaf_closest(blk, blocks, k, best, best_idx, hit);
}

static __attribute__((noipa)) int wide_leaf_closest_call(const WideTris *blk, uint32_t blocks, const WideRay *k,
                                                         float *best, uint32_t *best_idx, WideHit *hit)
{
    /* most leaves: one block or two, without the loops' set-up, and
     * without the registers and frame the loops' function saves and
     * makes (wide_leaf_closest_many: 22 instructions a call here) */
    if (blocks == 1)
        return wide_block_closest(blk, k, best, best_idx, hit);
#if NW == 8
    if (blocks == 2)
        return wide_pair_closest(blk, k, best, best_idx, hit);
#endif
    return wide_leaf_closest_many(blk, blocks, k, best, best_idx, hit);
}

/* Whether any of a leaf's triangles blocks the ray before tmax. */
static inline __attribute__((always_inline)) int wide_leaf_any(const WideTris *blk, uint32_t blocks, const WideRay *k,
                                                              float tmax)
{
    uint32_t b = 0;
#if NW == 8
    for (; b + 1 < blocks; b += 2)
        if (wide_tris_hit8(&blk[b], &blk[b + 1], k, tmax, 0, NULL, NULL, NULL, NULL))
            return 1;
#endif
    for (; b < blocks; b++) {
        __m128 t, v, ww, inv;
        if (wide_tris_hit(&blk[b], k, tmax, 0, &t, &v, &ww, &inv))
            return 1;
    }
    return 0;
}

/* wide_leaf_any out of line for the single-ray walk, as wide_leaf_closest_call. */
static __attribute__((noipa)) int wide_leaf_any_call(const WideTris *blk, uint32_t blocks, const WideRay *k, float tmax)
{
    if (blocks == 1) {
        __m128 t, v, ww, inv;
        return wide_tris_hit(blk, k, tmax, 0, &t, &v, &ww, &inv) != 0;
    }
#if NW == 8
    if (blocks == 2)
        return wide_tris_hit8(&blk[0], &blk[1], k, tmax, 0, NULL, NULL, NULL, NULL) != 0;
#endif
    return wide_leaf_any(blk, blocks, k, tmax);
}

/* Per-ray node constants: the ray's vectors (made again after each leaf
 * call), and the row of each axis's entry and exit bound. */
#define WIDE_NODE_VECTORS()                                                                                       \
    const VN ox = VN_SET1(r->org.x), oy = VN_SET1(r->org.y), oz = VN_SET1(r->org.z);                              \
    const VN ix = VN_SET1(r->inv.x), iy = VN_SET1(r->inv.y), iz = VN_SET1(r->inv.z);                              \
    const VN fx = VN_SET1(r->inv.x * WIDE_FAR), fy = VN_SET1(r->inv.y * WIDE_FAR), fz = VN_SET1(r->inv.z * WIDE_FAR); \
    const VN vtmin = VN_SET1(r->tmin)
#define WIDE_NODE_ROWS()                                                                                          \
    const int *const rows_ = wide_rows[wide_ray_octant(r)];                                                      \
    const int n0 = rows_[0], n1 = rows_[1], n2 = rows_[2], f0 = rows_[3], f1 = rows_[4], f2 = rows_[5]

/* The entry and exit rows (n0, n1, n2, f0, f1, f2) of each octant of
 * directions (wide_ray_octant): a table, not six compares a ray. */
#define WIDE_ROWS_OF(o)                                                                                           \
    {((o)&1 ? 3 : 0) * NW, ((o)&2 ? 4 : 1) * NW, ((o)&4 ? 5 : 2) * NW,                                            \
     ((o)&1 ? 0 : 3) * NW, ((o)&2 ? 1 : 4) * NW, ((o)&4 ? 2 : 5) * NW}
static const int wide_rows[8][6] = {WIDE_ROWS_OF(0), WIDE_ROWS_OF(1), WIDE_ROWS_OF(2), WIDE_ROWS_OF(3),
                                    WIDE_ROWS_OF(4), WIDE_ROWS_OF(5), WIDE_ROWS_OF(6), WIDE_ROWS_OF(7)};
#undef WIDE_ROWS_OF

/* Slab test of a node's children against (tmin, tmax]; the mask of those
 * hit and their entry distances.  Conservative as bvh_node_hit: a NaN
 * (0 * inf) leaves the bound as it was, and far distances are enlarged,
 * here by exit distances taken with the inverse direction enlarged
 * (fx, fy, fz: inv x WIDE_FAR) against a limit enlarged alike (vlim:
 * tmax x WIDE_FAR), so that the enlarging multiply is not a step of every
 * node's test (it was the last before the compare: four cycles on the
 * walk's chain of dependent steps, node after node).  The bounds are
 * taken in two rounds of max (min), not three: a NaN (the second operand
 * of a max wins it) may then drop a second axis's bound with its own, a
 * test looser still, never one that rejects more; an unused child's
 * bounds are infinities, never NaN, so it still fails. */
#define WIDE_NODE_TEST(box, vlim, lo_out, mask_out)                                                               \
    do {                                                                                                          \
        const VN t0x = (VN_LOAD((box) + n0) - ox) * ix, t1x = (VN_LOAD((box) + f0) - ox) * fx;                    \
        const VN t0y = (VN_LOAD((box) + n1) - oy) * iy, t1y = (VN_LOAD((box) + f1) - oy) * fy;                    \
        const VN t0z = (VN_LOAD((box) + n2) - oz) * iz, t1z = (VN_LOAD((box) + f2) - oz) * fz;                    \
        lo_out = VN_MAX(VN_MAX(t0x, t0y), VN_MAX(t0z, vtmin));                                                    \
        const VN hi_ = VN_MIN(VN_MIN(t1x, t1y), VN_MIN(t1z, vlim));                                               \
        mask_out = VN_LE_MASK(lo_out, hi_);                                                                       \
    } while (0)

/* nodes are NW * 32 bytes (wide_build): a shift, not the stored stride */
#define WIDE_NODE(w, i) ((const float *)(const void *)((const char *)(w)->nodes + (size_t)(i) * (NW * 32)))
#define WIDE_STACK (BVH_MAX_DEPTH * (NW - 1) + NW)

/* The start of a child's memory, fetched while its siblings are tested:
 * a big model's nodes and leaves miss the cache.  A node is NW / 2 cache
 * lines (128 or 256 bytes, aligned); a leaf's first block of 160 bytes
 * spans at most three. */
static inline __attribute__((always_inline)) void wide_prefetch(const Wide *w, uint32_t id, uint32_t blocks)
{
    if (blocks) {
        const char *m = (const char *)&w->tris[id];
        _mm_prefetch(m, _MM_HINT_T0), _mm_prefetch(m + 64, _MM_HINT_T0), _mm_prefetch(m + 128, _MM_HINT_T0);
    } else {
        const char *m = (const char *)WIDE_NODE(w, id);
        for (int i = 0; i < NW / 2; i++) /* unrolled: NW is a constant */
            _mm_prefetch(m + 64 * i, _MM_HINT_T0);
    }
}

/* The next node of a single ray: the only child hit; of two, the nearer,
 * the other pushed; of more, all pushed, sorted in place (farthest
 * deepest) and the nearest popped.  Pushed children are prefetched. */
static inline __attribute__((always_inline)) void wide_descend(const Wide *w, const float *box, int mask, VN lo, WideEntry *stack,
                                                              uint32_t *sp, uint32_t *cur, uint32_t *cur_blocks)
{
    const uint32_t *child = (const uint32_t *)(const void *)(box + WIDE_BOX_FLOATS(NW));
    const uint8_t *blocks = (const uint8_t *)box + WIDE_BLOCKS_OFFSET(NW);
    const int i = __builtin_ctz((unsigned)mask);
    mask &= mask - 1;
    if (!mask) {
        *cur = child[i], *cur_blocks = blocks[i];
        return;
    }
    float tn[NW];
    VN_STORE(tn, lo);
    const int j = __builtin_ctz((unsigned)mask);
    mask &= mask - 1;
    if (!mask) {
        const int near = tn[j] < tn[i] ? j : i, far = i + j - near;
        wide_prefetch(w, child[far], blocks[far]);
        stack[(*sp)++] = (WideEntry){child[far], blocks[far], tn[far], 0};
        *cur = child[near], *cur_blocks = blocks[near];
        return;
    }
    /* a tree of depth <= BVH_MAX_DEPTH (bvh_validate) pushes at most NW - 1 a level */
    assert(*sp + NW <= WIDE_STACK + 1);
    WideEntry *const base = &stack[*sp];
    uint32_t n = 0;
    base[n++] = (WideEntry){child[i], blocks[i], tn[i], 0};
    for (int k = j;; k = __builtin_ctz((unsigned)mask), mask &= mask - 1) {
        WideEntry x = {child[k], blocks[k], tn[k], 0};
        wide_prefetch(w, x.id, x.blocks);
        uint32_t m = n++;
        while (m > 0 && base[m - 1].t < x.t) { /* farthest first */
            base[m] = base[m - 1];
            m--;
        }
        base[m] = x;
        if (!mask)
            break;
    }
    *sp += n - 1;
    *cur = base[n - 1].id, *cur_blocks = base[n - 1].blocks;
}

/* Pops the next entry into cur; 0 when the stack runs out.  With `cull`
 * (closest hits), entries farther than `limit` (the hit so far) are
 * dropped; an any-hit walk's entries carry no distance. */
static inline __attribute__((always_inline)) int wide_pop(const WideEntry *stack, uint32_t *sp, int cull, float limit,
                                                         uint32_t *cur, uint32_t *cur_blocks)
{
    do {
        if (*sp == 0)
            return 0;
        --*sp;
    } while (cull && stack[*sp].t > limit);
    *cur = stack[*sp].id, *cur_blocks = stack[*sp].blocks;
    return 1;
}

int KERNEL_CLOSEST(const Wide *w, const Ray *r, real tmax, uint32_t tie, WideHit *hit)
{
    if (wide_ray_nan(r))
        return 0;
    WideEntry stack[WIDE_STACK];
    uint32_t sp = 0, cur = w->root, cur_blocks = w->root_blocks;
    float best = tmax;
    uint32_t best_idx = tie; /* a hit exactly at tmax is taken if its index is below tie */
    int found = 0;
    WideRay k;
    wide_ray_setup(&k, r);
    WIDE_NODE_ROWS();
    for (;;) {
        /* made again after every leaf (wide_leaf_closest_call) */
        WIDE_NODE_VECTORS();
        const VN vlim = VN_SET1(best * WIDE_FAR);
        while (cur_blocks == 0) {
            const float *box = WIDE_NODE(w, cur);
            VN lo;
            int mask;
            WIDE_NODE_TEST(box, vlim, lo, mask);
            if (mask) {
                wide_descend(w, box, mask, lo, stack, &sp, &cur, &cur_blocks);
                continue;
            }
            if (!wide_pop(stack, &sp, 1, best * BVH_FUDGE, &cur, &cur_blocks))
                return found;
        }
        found |= wide_leaf_closest_call(&w->tris[cur], cur_blocks, &k, &best, &best_idx, hit);
        if (!wide_pop(stack, &sp, 1, best * BVH_FUDGE, &cur, &cur_blocks))
            return found;
    }
}

/* ---- single rays by pairs: two walks interleaved ----
 *
 * A ray alone through a big model waits on a chain of dependent steps: a
 * node's load, its slab test, the push and the next pop.  Two rays walked
 * a step (a node or a leaf) each in turn give the CPU two independent
 * chains to overlap.  Each walk is KERNEL_CLOSEST's, so each ray gets the
 * hit it gets alone.  Measured (tools/bench/rayclass, 1 thread, the 1M
 * sphere and the bunny, mirrored and refracted rays that go ray by ray):
 * by pairs, 7-13% more rays a second than one after another; four at a
 * time no more than pairs; a loop over any number of walks (an index of
 * the live ones) lost what the pairs gained.  KERNEL_CLOSEST stays a loop
 * of its own, not these steps: there a run of nodes keeps the ray's
 * vectors in registers, and a single ray walked by these steps was 10%
 * slower (bunny diffuse bounces 7.1-7.3 -> 6.3-6.6 Mrays/s, the 1M
 * sphere's mirrored rays 6.0-6.4 -> 5.4-5.7). */
/* A walk's state in two parts.  What its steps read on every node (the
 * ray's vectors, the rows, the stack's depth and the entry being walked)
 * has no array and no pointer taken past the inlined steps, so GCC keeps
 * it in registers (as much as fit: with AVX-512's 32 both walks' vectors
 * nearly do); with one struct holding the stack as well, all of it lived
 * in memory and each step's next node went through a store and a load.
 * Measured (tools/bench/rayclass, the 1M sphere, one thread, three
 * alternating runs): mirrored rays 5.31-5.43 -> 5.52-5.62 Mrays/s,
 * refracted 2.54-2.68 -> 2.72-2.77, diffuse bounces 4.93-5.10 ->
 * 5.04-5.16. */
typedef struct {
    VN ox, oy, oz, ix, iy, iz, fx, fy, fz, vtmin;
    VN vlim; /* best x WIDE_FAR, made again when a leaf moves best */
    uint32_t sp, cur, cur_blocks;
    int n0, n1, n2, f0, f1, f2;
} WideWalk;

/* What a walk keeps in memory: what its leaf calls read or write through
 * pointers, and its stack. */
typedef struct {
    WideRay k;
    float best;
    uint32_t best_idx;
    int found;
    WideHit *hit;
    WideEntry stack[WIDE_STACK];
} WideWalkMem;

/* A walk's start; 0 for a ray that hits nothing (wide_ray_nan). */
static inline __attribute__((always_inline)) int wide_walk_start(WideWalk *s, WideWalkMem *m, const Wide *w,
                                                                const Ray *r, real tmax, uint32_t tie, WideHit *hit)
{
    m->found = 0;
    s->sp = 0, s->cur = w->root, s->cur_blocks = w->root_blocks;
    m->best = tmax, m->best_idx = tie, m->hit = hit;
    s->vlim = VN_SET1(m->best * WIDE_FAR);
    wide_ray_setup(&m->k, r);
    WIDE_NODE_ROWS();
    s->n0 = n0, s->n1 = n1, s->n2 = n2, s->f0 = f0, s->f1 = f1, s->f2 = f2;
    s->ox = VN_SET1(r->org.x), s->oy = VN_SET1(r->org.y), s->oz = VN_SET1(r->org.z);
    s->ix = VN_SET1(r->inv.x), s->iy = VN_SET1(r->inv.y), s->iz = VN_SET1(r->inv.z);
    s->fx = VN_SET1(r->inv.x * WIDE_FAR), s->fy = VN_SET1(r->inv.y * WIDE_FAR), s->fz = VN_SET1(r->inv.z * WIDE_FAR);
    s->vtmin = VN_SET1(r->tmin);
    /* tested last, every field set either way: the fields are registers
     * now, and GCC cannot tell that a walk that never started is never
     * stepped (-Wmaybe-uninitialized) */
    return !wide_ray_nan(r);
}

/* One step of KERNEL_CLOSEST's loop: a node tested and descended, or a
 * leaf tested, then the next entry popped.  0 when the walk is over. */
static inline __attribute__((always_inline)) int wide_walk_step(WideWalk *s, WideWalkMem *m, const Wide *w)
{
    if (s->cur_blocks == 0) {
        const float *box = WIDE_NODE(w, s->cur);
        /* the node's last line (child indices and block counts), read only
         * after the test: fetched with the boxes' lines, not after them.
         * Measured as above: mirrored rays 5.39-5.53 -> 5.58-5.66, diffuse
         * 5.03-5.13 -> 5.09-5.22, refracted the same; the single walks
         * (KERNEL_CLOSEST, KERNEL_ANY) gained nothing from it. */
        _mm_prefetch((const char *)box + WIDE_CHILD_OFFSET(NW), _MM_HINT_T0);
        const int n0 = s->n0, n1 = s->n1, n2 = s->n2, f0 = s->f0, f1 = s->f1, f2 = s->f2;
        const VN ox = s->ox, oy = s->oy, oz = s->oz, ix = s->ix, iy = s->iy, iz = s->iz, vtmin = s->vtmin;
        const VN fx = s->fx, fy = s->fy, fz = s->fz, vlim = s->vlim;
        VN lo;
        int mask;
        WIDE_NODE_TEST(box, vlim, lo, mask);
        if (mask) {
            wide_descend(w, box, mask, lo, m->stack, &s->sp, &s->cur, &s->cur_blocks);
            return 1;
        }
    } else {
        const WideTris *blk = &w->tris[s->cur];
        if (s->cur_blocks == 1)
            m->found |= wide_block_closest(blk, &m->k, &m->best, &m->best_idx, m->hit);
        else
            m->found |= wide_leaf_closest_call(blk, s->cur_blocks, &m->k, &m->best, &m->best_idx, m->hit);
        s->vlim = VN_SET1(m->best * WIDE_FAR);
    }
    return wide_pop(m->stack, &s->sp, 1, m->best * BVH_FUDGE, &s->cur, &s->cur_blocks);
}

uint32_t KERNEL_CLOSEST_PAIRS(const Wide *w, const Ray *const *rays, int n, const real *tmax, const uint32_t *tie,
                             WideHit *hits)
{
    uint32_t found = 0;
    int i = 0;
    for (; i + 1 < n; i += 2) {
        WideWalk a, b;
        WideWalkMem am, bm;
        int ra = wide_walk_start(&a, &am, w, rays[i], tmax[i], tie[i], &hits[i]);
        int rb = wide_walk_start(&b, &bm, w, rays[i + 1], tmax[i + 1], tie[i + 1], &hits[i + 1]);
        while (ra && rb) {
            ra = wide_walk_step(&a, &am, w);
            rb = wide_walk_step(&b, &bm, w);
        }
        while (ra)
            ra = wide_walk_step(&a, &am, w);
        while (rb)
            rb = wide_walk_step(&b, &bm, w);
        found |= ((uint32_t)am.found | (uint32_t)bm.found << 1) << i;
    }
    if (i < n)
        found |= (uint32_t)KERNEL_CLOSEST(w, rays[i], tmax[i], tie[i], &hits[i]) << i;
    return found;
}

/* The next node of an any-hit ray: the first child hit in the node's
 * order, the others pushed as they come, neither sorted by distance nor
 * prefetched (any blocker ends the walk, and which one does not change the
 * answer).  Measured against wide_descend's nearest-first order with its
 * prefetches (tools/bench/rayclass, 1 thread, best of 4, three rounds
 * each): shadow rays on the 1M sphere 2.43-2.49 to 2.70-2.81 Mrays/s to a
 * point light, 2.42-3.23 to 2.84-3.29 to an area light; the bunny 3.85-4.77
 * to 4.43-4.55 and 3.93-4.60 to 5.11-5.47. */
static inline __attribute__((always_inline)) void wide_descend_any(const float *box, int mask, WideEntry *stack,
                                                                  uint32_t *sp, uint32_t *cur, uint32_t *cur_blocks)
{
    const uint32_t *child = (const uint32_t *)(const void *)(box + WIDE_BOX_FLOATS(NW));
    const uint8_t *blocks = (const uint8_t *)box + WIDE_BLOCKS_OFFSET(NW);
    int i = __builtin_ctz((unsigned)mask);
    mask &= mask - 1;
    *cur = child[i], *cur_blocks = blocks[i];
    while (mask) {
        int j = __builtin_ctz((unsigned)mask);
        mask &= mask - 1;
        assert(*sp < WIDE_STACK);
        stack[(*sp)++] = (WideEntry){child[j], blocks[j], 0, 0};
    }
}

int KERNEL_ANY(const Wide *w, const Ray *r, real tmax)
{
    if (wide_ray_nan(r))
        return 0;
    WideRay k;
    wide_ray_setup(&k, r);
    WIDE_NODE_ROWS();
    WideEntry stack[WIDE_STACK];
    uint32_t sp = 0, cur = w->root, cur_blocks = w->root_blocks;
    for (;;) {
        /* made again after every leaf (wide_leaf_any_call) */
        WIDE_NODE_VECTORS();
        const VN vlim = VN_SET1(tmax * WIDE_FAR);
        while (cur_blocks == 0) {
            const float *box = WIDE_NODE(w, cur);
            VN lo;
            int mask;
            WIDE_NODE_TEST(box, vlim, lo, mask);
            (void)lo;
            if (mask) {
                wide_descend_any(box, mask, stack, &sp, &cur, &cur_blocks);
                continue;
            }
            if (!wide_pop(stack, &sp, 0, 0, &cur, &cur_blocks))
                return 0;
        }
        if (wide_leaf_any_call(&w->tris[cur], cur_blocks, &k, tmax))
            return 1;
        if (!wide_pop(stack, &sp, 0, 0, &cur, &cur_blocks))
            return 0;
    }
}

/* ---- packets: up to WIDE_PACKET rays down the tree together ----
 *
 * A node is tested once for the whole packet, with interval arithmetic: a
 * lower bound of every ray's entry distance and an upper bound of every
 * ray's exit distance, from the least and greatest origin and inverse
 * direction on each axis.  Rounding is monotonic, so the bounds enclose
 * each ray's own computed distances and the test is at least as
 * conservative as each ray's: it never drops a box a ray would enter.  This
 * needs every ray's direction to have the same signs and no zero component;
 * other packets (and packets of one ray) go ray by ray.  A leaf is tested
 * ray by ray, each ray with the single-ray triangle test, so each ray ends
 * with the hit it would have found alone. */

/* The packet's rays side by side, one lane each (lanes past n repeat ray
 * 0), for the test of a leaf child against every ray at once.  A vector of
 * WIDE_PACKET floats: one AVX register in the AVX2 kernel, two SSE ones in
 * the SSE kernel (GCC's vector extension splits it). */
#ifndef WIDE_LANES_COMMON
#define WIDE_LANES_COMMON
typedef float WideLanes __attribute__((vector_size(4 * WIDE_PACKET)));
typedef int32_t WideLaneBits __attribute__((vector_size(4 * WIDE_PACKET)));

typedef struct {
    WideLanes o[3], inv[3], tmin;
} WideRays;

_Static_assert(WIDE_PACKET == 8, "the packet set-up reads a packet as two SSE registers");

/* The least and the greatest of WIDE_PACKET floats (origins, inverse
 * directions: finite or infinite, never NaN in a packet that is kept) */
static inline __attribute__((always_inline)) float wide_hmin(const float *v)
{
    __m128 m = _mm_min_ps(_mm_loadu_ps(v), _mm_loadu_ps(v + 4));
    m = _mm_min_ps(m, _mm_movehl_ps(m, m));
    return _mm_cvtss_f32(_mm_min_ss(m, _mm_shuffle_ps(m, m, 1)));
}

static inline __attribute__((always_inline)) float wide_hmax(const float *v)
{
    __m128 m = _mm_max_ps(_mm_loadu_ps(v), _mm_loadu_ps(v + 4));
    m = _mm_max_ps(m, _mm_movehl_ps(m, m));
    return _mm_cvtss_f32(_mm_max_ss(m, _mm_shuffle_ps(m, m, 1)));
}

#endif

typedef struct {
    VN o_near[3], o_far[3]; /* the origin bound giving the least entry / greatest exit, per axis */
    VN ilo[3], ihi[3];
    VN tmin;
    int n[3], f[3];         /* rows of the entry and exit bounds */
} WidePacket;

/* A packet's rays read side by side: eight floats of each Ray, from float
 * `first` on, as eight lane vectors (one per field, one lane per ray;
 * lanes past n repeat ray 0).  With AVX, eight loads and a transpose, not
 * a store per field and ray. */
typedef struct {
    WideLanes a[8]; /* floats 0-7: org x y z, dir x y z, inv x y */
    WideLanes b[8]; /* floats 8-15: inv z, tmin, tmax, kx, ky, kz (int bits), near[0..1] */
    WideLanes c[8]; /* floats 15-22: near[1..2], far[0..2], sx, sy, sz */
} WideRayRows;

_Static_assert(sizeof(real) == 4 && offsetof(Ray, inv) == 24 && offsetof(Ray, tmin) == 36 &&
                   offsetof(Ray, kx) == 44 && offsetof(Ray, sx) == 80 && sizeof(Ray) == 92,
               "wide_ray_rows reads a Ray as 23 floats in this order");

static inline __attribute__((always_inline)) void wide_ray_rows8(const float *const *f, int first, WideLanes out[8])
{
#if NW == 8
#define ROW(i) _mm256_loadu_ps(f[i] + first)
    const __m256 r[8] = {ROW(0), ROW(1), ROW(2), ROW(3), ROW(4), ROW(5), ROW(6), ROW(7)};
#undef ROW
    const __m256 t0 = _mm256_unpacklo_ps(r[0], r[1]), t1 = _mm256_unpackhi_ps(r[0], r[1]);
    const __m256 t2 = _mm256_unpacklo_ps(r[2], r[3]), t3 = _mm256_unpackhi_ps(r[2], r[3]);
    const __m256 t4 = _mm256_unpacklo_ps(r[4], r[5]), t5 = _mm256_unpackhi_ps(r[4], r[5]);
    const __m256 t6 = _mm256_unpacklo_ps(r[6], r[7]), t7 = _mm256_unpackhi_ps(r[6], r[7]);
    const __m256 s0 = _mm256_shuffle_ps(t0, t2, 0x44), s1 = _mm256_shuffle_ps(t0, t2, 0xee);
    const __m256 s2 = _mm256_shuffle_ps(t1, t3, 0x44), s3 = _mm256_shuffle_ps(t1, t3, 0xee);
    const __m256 s4 = _mm256_shuffle_ps(t4, t6, 0x44), s5 = _mm256_shuffle_ps(t4, t6, 0xee);
    const __m256 s6 = _mm256_shuffle_ps(t5, t7, 0x44), s7 = _mm256_shuffle_ps(t5, t7, 0xee);
    const __m256 o[8] = {_mm256_permute2f128_ps(s0, s4, 0x20), _mm256_permute2f128_ps(s1, s5, 0x20),
                         _mm256_permute2f128_ps(s2, s6, 0x20), _mm256_permute2f128_ps(s3, s7, 0x20),
                         _mm256_permute2f128_ps(s0, s4, 0x31), _mm256_permute2f128_ps(s1, s5, 0x31),
                         _mm256_permute2f128_ps(s2, s6, 0x31), _mm256_permute2f128_ps(s3, s7, 0x31)};
    memcpy(out, o, sizeof o);
#else
    float v[8][WIDE_PACKET];
    for (int i = 0; i < WIDE_PACKET; i++)
        for (int j = 0; j < 8; j++)
            v[j][i] = f[i][first + j];
    memcpy(out, v, sizeof v);
#endif
}

static inline __attribute__((always_inline)) void wide_ray_rows(WideRayRows *R, const Ray *const *rays, int n)
{
    const float *f[WIDE_PACKET];
    for (int i = 0; i < WIDE_PACKET; i++)
        f[i] = (const float *)(const void *)rays[i < n ? i : 0];
    wide_ray_rows8(f, 0, R->a);
    wide_ray_rows8(f, 8, R->b);
    wide_ray_rows8(f, 15, R->c);
}

/* Fills the packet bounds and the rays' lanes; 0 when the rays are not
 * coherent enough: a direction component zero, not finite or of another
 * sign than the others' (0 < |1/d| < inf holds exactly when d is finite,
 * nonzero and its reciprocal does not overflow), origins spread wider
 * than `spread` on an axis, or unit directions wider than `dspread`. */
static inline __attribute__((always_inline)) int wide_packet_setup(WidePacket *p, WideRays *q, const WideRayRows *R,
                                                                   float spread, float dspread)
{
    float o[3][WIDE_PACKET], inv[3][WIDE_PACKET], tmin[WIDE_PACKET], d[3][WIDE_PACKET];
    for (int a = 0; a < 3; a++) {
        memcpy(o[a], &R->a[a], sizeof o[a]);
        memcpy(d[a], &R->a[3 + a], sizeof d[a]);
    }
    memcpy(inv[0], &R->a[6], sizeof inv[0]), memcpy(inv[1], &R->a[7], sizeof inv[1]);
    memcpy(inv[2], &R->b[0], sizeof inv[2]), memcpy(tmin, &R->b[1], sizeof tmin);
    for (int a = 0; a < 3; a++)
        if (!(wide_hmax(d[a]) - wide_hmin(d[a]) <= dspread))
            return 0;
    const __m128 inf = _mm_set1_ps(INFINITY), ninf = _mm_set1_ps(-INFINITY), zero = _mm_setzero_ps();
    for (int a = 0; a < 3; a++) {
        const __m128 v0 = _mm_loadu_ps(inv[a]), v1 = _mm_loadu_ps(inv[a] + 4);
        const int pos = _mm_movemask_ps(_mm_and_ps(_mm_cmpgt_ps(v0, zero), _mm_cmplt_ps(v0, inf))) |
                        _mm_movemask_ps(_mm_and_ps(_mm_cmpgt_ps(v1, zero), _mm_cmplt_ps(v1, inf))) << 4;
        const int neg = _mm_movemask_ps(_mm_and_ps(_mm_cmplt_ps(v0, zero), _mm_cmpgt_ps(v0, ninf))) |
                        _mm_movemask_ps(_mm_and_ps(_mm_cmplt_ps(v1, zero), _mm_cmpgt_ps(v1, ninf))) << 4;
        const float olo = wide_hmin(o[a]), ohi = wide_hmax(o[a]);
        if ((pos != 0xff && neg != 0xff) || !(ohi - olo <= spread))
            return 0;
        const float ilo = wide_hmin(inv[a]), ihi = wide_hmax(inv[a]);
        /* (bound - o) * inv: with inv > 0 it grows with the bound minus o,
         * so the least entry takes the greatest origin and the greatest exit
         * the least; with inv < 0 the other way round */
        p->o_near[a] = VN_SET1(pos ? ohi : olo);
        p->o_far[a] = VN_SET1(pos ? olo : ohi);
        p->ilo[a] = VN_SET1(ilo);
        p->ihi[a] = VN_SET1(ihi);
        p->n[a] = (pos ? a : a + 3) * NW;
        p->f[a] = (pos ? a + 3 : a) * NW;
        memcpy(&q->o[a], o[a], sizeof q->o[a]);
        memcpy(&q->inv[a], inv[a], sizeof q->inv[a]);
    }
    p->tmin = VN_SET1(wide_hmin(tmin));
    memcpy(&q->tmin, tmin, sizeof q->tmin);
    return 1;
}

static inline __attribute__((always_inline)) int wide_packet_node(const WidePacket *p, const float *box, float tmax,
                                                                  VN *lo_out)
{
    VN lo = p->tmin, hi = VN_SET1(tmax);
    for (int a = 0; a < 3; a++) {
        const VN dn = VN_LOAD(box + p->n[a]) - p->o_near[a];
        const VN df = VN_LOAD(box + p->f[a]) - p->o_far[a];
        lo = VN_MAX(VN_MIN(dn * p->ilo[a], dn * p->ihi[a]), lo);
        hi = VN_MIN(VN_MAX(df * p->ilo[a], df * p->ihi[a]), hi);
    }
    *lo_out = lo;
    return VN_LE_MASK(lo, hi * VN_SET1(BVH_FUDGE));
}

/* The rays of `active` whose own slab test enters child k of a node, all
 * rays at once.  Every ray of a packet has the signs of p's directions
 * (wide_packet_setup), so its entry and exit rows are p's; each lane is
 * the single-ray test's arithmetic (WIDE_NODE_TEST).  tmax: WIDE_PACKET
 * limits (lanes past the packet's rays are masked off). */
static inline __attribute__((always_inline)) uint32_t wide_packet_rays(const float *box, int k, const WidePacket *p,
                                                                       const WideRays *q, uint32_t active,
                                                                       const float *tmax)
{
    WideLanes lo = q->tmin, hi;
    memcpy(&hi, tmax, sizeof hi);
    for (int a = 0; a < 3; a++) {
        const WideLanes t0 = (box[p->n[a] + k] - q->o[a]) * q->inv[a];
        const WideLanes t1 = (box[p->f[a] + k] - q->o[a]) * q->inv[a];
        /* t0 > lo ? t0 : lo and t1 < hi ? t1 : hi: a NaN keeps the bound, as VN_MAX and VN_MIN do */
        const WideLaneBits up = t0 > lo, down = t1 < hi;
        lo = (WideLanes)(((WideLaneBits)t0 & up) | ((WideLaneBits)lo & ~up));
        hi = (WideLanes)(((WideLaneBits)t1 & down) | ((WideLaneBits)hi & ~down));
    }
    const WideLaneBits in = lo <= hi * BVH_FUDGE;
#if NW == 8
    const uint32_t bits = (uint32_t)_mm256_movemask_ps((__m256)in);
#else
    __m128 half[2];
    memcpy(half, &in, sizeof half);
    const uint32_t bits = (uint32_t)(_mm_movemask_ps(half[0]) | _mm_movemask_ps(half[1]) << 4);
#endif
    return bits & active;
}

/* ---- a leaf against a packet's rays side by side ----
 *
 * Coherent rays (camera rays, shadow rays to one light) mostly enter the
 * same leaves: there each triangle is tested against the packet's rays at
 * once, one ray to a lane, instead of each ray against four triangles.
 * Every lane does wide_tris_hit's arithmetic, operation for operation, for
 * its ray and the triangle, and the hits are taken by the same rule
 * (wide_take_lanes), so each ray ends with the hit it finds alone.  The
 * sheared frame's axis order is the ray's: rays of one packet share it or
 * the packet's leaves go ray by ray. */
typedef uint32_t WideLaneIds __attribute__((vector_size(4 * WIDE_PACKET)));

/* Leaves that fewer of a packet's rays enter go ray by ray. */
#ifndef WIDE_LANES_MIN
#define WIDE_LANES_MIN 3
#endif

typedef struct {
    int kx, ky, kz;
    WideLanes ox, oy, oz, sx, sy, sz, tmin;
} WideRayLanes;

/* A lane mask's bits. */
static inline __attribute__((always_inline)) uint32_t wide_lane_bits(WideLaneBits m)
{
#if NW == 8
    return (uint32_t)_mm256_movemask_ps((__m256)m);
#else
    __m128 half[2];
    memcpy(half, &m, sizeof half);
    return (uint32_t)(_mm_movemask_ps(half[0]) | _mm_movemask_ps(half[1]) << 4);
#endif
}

/* The rays' constants (wide_ray_setup's) as lanes; 0 when their axis
 * orders differ.  Lanes past n repeat ray 0 (masked off by the callers). */
static inline __attribute__((always_inline)) int wide_ray_lanes(WideRayLanes *L, const WideRayRows *R)
{
    const WideLaneBits kx = (WideLaneBits)R->b[3], ky = (WideLaneBits)R->b[4], kz = (WideLaneBits)R->b[5];
    L->kx = kx[0], L->ky = ky[0], L->kz = kz[0];
    if (wide_lane_bits((kx != L->kx) | (ky != L->ky) | (kz != L->kz)))
        return 0;
    L->ox = R->a[L->kx], L->oy = R->a[L->ky], L->oz = R->a[L->kz];
    L->sx = R->c[5], L->sy = R->c[6], L->sz = R->c[7];
    L->tmin = R->b[1];
    return 1;
}

/* Triangle l of block b against the lanes `active`: the mask of lanes that
 * hit with tmin < t and t < lim (t <= lim when `upto`), their t, V, W and
 * 1/det (wide_tris_hit's arithmetic, a lane per ray). */
static inline __attribute__((always_inline)) uint32_t wide_tri_lanes(const WideTris *b, int l, const WideRayLanes *L,
                                                                      uint32_t active, WideLanes lim, int upto,
                                                                      WideLaneBits *ok_out, WideLanes *t_out,
                                                                      WideLanes *v_out, WideLanes *w_out,
                                                                      WideLanes *inv_out)
{
    const WideLanes ax = b->v[0][L->kx][l] - L->ox, ay = b->v[0][L->ky][l] - L->oy, az = b->v[0][L->kz][l] - L->oz;
    const WideLanes bx = b->v[1][L->kx][l] - L->ox, by = b->v[1][L->ky][l] - L->oy, bz = b->v[1][L->kz][l] - L->oz;
    const WideLanes cx = b->v[2][L->kx][l] - L->ox, cy = b->v[2][L->ky][l] - L->oy, cz = b->v[2][L->kz][l] - L->oz;
    const WideLanes Ax = ax - L->sx * az, Ay = ay - L->sy * az;
    const WideLanes Bx = bx - L->sx * bz, By = by - L->sy * bz;
    const WideLanes Cx = cx - L->sx * cz, Cy = cy - L->sy * cz;
    WideLanes U = Cx * By - Cy * Bx;
    WideLanes V = Ax * Cy - Ay * Cx;
    WideLanes W = Bx * Ay - By * Ax;
    const uint32_t z = wide_lane_bits((U == 0) | (V == 0) | (W == 0)) & active;
    if (__builtin_expect(z != 0, 0)) { /* an edge through a ray: those lanes in double, as the scalar test does */
        float fa[6][8], fu[3][8];
        memcpy(fa[0], &Ax, sizeof Ax), memcpy(fa[1], &Ay, sizeof Ay), memcpy(fa[2], &Bx, sizeof Bx);
        memcpy(fa[3], &By, sizeof By), memcpy(fa[4], &Cx, sizeof Cx), memcpy(fa[5], &Cy, sizeof Cy);
        memcpy(fu[0], &U, sizeof U), memcpy(fu[1], &V, sizeof V), memcpy(fu[2], &W, sizeof W);
        wide_edges_in_double((int)z, (const float(*)[8])fa, fu);
        memcpy(&U, fu[0], sizeof U), memcpy(&V, fu[1], sizeof V), memcpy(&W, fu[2], sizeof W);
    }
    WideLaneBits outside;
    if (__builtin_expect(z == 0, 1)) { /* WIDE_SIGNS_DIFFER; the sign spread over the lane */
        const WideLaneBits u = (WideLaneBits)U, v = (WideLaneBits)V, w = (WideLaneBits)W;
        outside = ((u | v | w) & ~(u & v & w)) >> 31;
    } else {
        outside = ((U < 0) | (V < 0) | (W < 0)) & ((U > 0) | (V > 0) | (W > 0));
    }
    if ((wide_lane_bits(outside) & active) == active)
        return 0;
    const WideLanes det = U + V + W;
    const WideLanes T = U * (L->sz * az) + V * (L->sz * bz) + W * (L->sz * cz);
    const WideLanes inv = 1.0f / det;
    const WideLanes t = T * inv;
    const WideLaneBits ok = (t > L->tmin) & (upto ? t <= lim : t < lim) & ~outside & ~(det == 0);
    *ok_out = ok, *t_out = t, *v_out = V, *w_out = W, *inv_out = inv;
    return wide_lane_bits(ok) & active;
}

/* A leaf against the rays of `active`, each ray's closest hit so far in
 * best, best_idx and hits (wide_leaf_closest's rule); the mask of rays
 * that took a hit. */
static inline __attribute__((always_inline)) uint32_t wide_leaf_closest_lanes(const WideTris *blk, uint32_t blocks,
                                                                               const WideRayLanes *L, uint32_t active,
                                                                               float *best, uint32_t *best_idx,
                                                                               WideHit *hits)
{
    WideLanes vbest;
    WideLaneIds vidx;
    memcpy(&vbest, best, sizeof vbest), memcpy(&vidx, best_idx, sizeof vidx);
    const WideLaneBits on = ((WideLaneBits){1, 2, 4, 8, 16, 32, 64, 128} & (int32_t)active) != 0;
    uint32_t found = 0;
    for (uint32_t b = 0; b < blocks; b++)
        for (int l = 0; l < WIDE_TRIS; l++) {
            const uint32_t id = blk[b].idx[l];
            if (l > 0 && id == blk[b].idx[l - 1]) /* the leaf's last triangle, repeated */
                break;
            WideLanes t, v, ww, inv;
            WideLaneBits ok;
            uint32_t m = wide_tri_lanes(&blk[b], l, L, active, vbest, 1, &ok, &t, &v, &ww, &inv);
            if (!m)
                continue;
            const WideLaneBits take = ok & on & ((t < vbest) | ((t == vbest) & (WideLaneBits)(id < vidx)));
            m &= wide_lane_bits(take);
            if (!m)
                continue;
            vbest = (WideLanes)(((WideLaneBits)t & take) | ((WideLaneBits)vbest & ~take));
            vidx = (WideLaneIds)(((WideLaneBits)((WideLaneIds){0} + id) & take) | ((WideLaneBits)vidx & ~take));
            const WideLanes b1 = v * inv, b2 = ww * inv;
            for (uint32_t k = m; k; k &= k - 1) {
                const int i = __builtin_ctz(k);
                hits[i] = (WideHit){t[i], b1[i], b2[i], id};
            }
            found |= m;
        }
    memcpy(best, &vbest, sizeof vbest), memcpy(best_idx, &vidx, sizeof vidx);
    return found;
}

/* The rays of `active` that a leaf's triangles block before their tmax. */
static inline __attribute__((always_inline)) uint32_t wide_leaf_any_lanes(const WideTris *blk, uint32_t blocks,
                                                                           const WideRayLanes *L, uint32_t active,
                                                                           WideLanes lim)
{
    uint32_t hit = 0;
    for (uint32_t b = 0; b < blocks; b++)
        for (int l = 0; l < WIDE_TRIS; l++) {
            const uint32_t id = blk[b].idx[l];
            if (l > 0 && id == blk[b].idx[l - 1])
                break;
            WideLanes t, v, ww, inv;
            WideLaneBits ok;
            hit |= wide_tri_lanes(&blk[b], l, L, active & ~hit, lim, 0, &ok, &t, &v, &ww, &inv);
            if ((hit & active) == active)
                return hit;
        }
    return hit;
}

/* Pushes the children hit (farthest first) and returns the nearest; leaf
 * children carry the rays that enter them.  sorted: nearest child first
 * (closest hits); else in the node's order,
 * without prefetches, for an any-hit packet as for a single any-hit ray
 * (wide_descend_any; the bunny's shadow packets 5.6-6.2 to 5.9-8.9
 * Mrays/s to a point light, 5.7-6.3 to 5.9-6.4 to an area light, the 1M
 * sphere's within noise either way). */
static inline __attribute__((always_inline)) WideEntry wide_packet_push(const Wide *w, const float *box, int mask, VN lo,
                                                                       const WidePacket *p, const WideRays *q,
                                                                       uint32_t active,
                                                                       const float *tmax, WideEntry *stack,
                                                                       uint32_t *sp, const int sorted)
{
    const uint32_t *child = (const uint32_t *)(const void *)(box + WIDE_BOX_FLOATS(NW));
    const uint8_t *blocks = (const uint8_t *)box + WIDE_BLOCKS_OFFSET(NW);
    float tn[NW];
    VN_STORE(tn, lo);
    WideEntry e[NW];
    int n = 0;
    while (mask) {
        int i = __builtin_ctz((unsigned)mask);
        mask &= mask - 1;
        uint32_t rs = blocks[i] ? wide_packet_rays(box, i, p, q, active, tmax) : active;
        if (!rs)
            continue;
        WideEntry x = {child[i], blocks[i], tn[i], rs};
        if (!sorted) {
            e[n++] = x;
            continue;
        }
        wide_prefetch(w, x.id, x.blocks);
        int j = n++;
        while (j > 0 && e[j - 1].t < x.t) {
            e[j] = e[j - 1];
            j--;
        }
        e[j] = x;
    }
    if (n == 0)
        return (WideEntry){0, 0, 0, 0};
    assert(*sp + (uint32_t)n <= WIDE_STACK + 1);
    for (int j = 0; j < n - 1; j++)
        stack[(*sp)++] = e[j];
    return e[n - 1];
}

static inline float wide_max_of(const float *v, uint32_t mask)
{
    float m = -INFINITY;
    while (mask) {
        int i = __builtin_ctz(mask);
        mask &= mask - 1;
        m = v[i] > m ? v[i] : m;
    }
    return m;
}

/* A packet that misses the root node's children altogether (a scene's
 * top level sends every packet that reaches the model's instance): one node
 * test, before the rays' own set-up. */
static inline __attribute__((always_inline)) int wide_packet_misses(const Wide *w, const WidePacket *p, float far)
{
    VN lo;
    return w->root_blocks == 0 && !wide_packet_node(p, WIDE_NODE(w, w->root), far, &lo);
}

uint32_t KERNEL_CLOSEST_PACKET(const Wide *w, const Ray *const *rays, int n, const real *tmax, const uint32_t *tie,
                               WideHit *hits)
{
    WidePacket p;
    uint32_t found = 0;
    WideRays q;
    WideRayRows R;
    if (n >= 2)
        wide_ray_rows(&R, rays, n);
    if (n < 2 || !wide_packet_setup(&p, &q, &R, INFINITY, WIDE_DIR_SPREAD))
        return KERNEL_CLOSEST_PAIRS(w, rays, n, tmax, tie, hits);
    const uint32_t all = n == 32 ? ~0u : (1u << n) - 1;
    float far = wide_max_of(tmax, all);
    if (wide_packet_misses(w, &p, far))
        return 0;
    WideRay k[WIDE_PACKET]; /* set up when a ray first meets a leaf alone (kset) */
    uint32_t kset = 0;
    float best[WIDE_PACKET] = {0};
    uint32_t best_idx[WIDE_PACKET] = {0};
    for (int i = 0; i < n; i++) {
        best[i] = tmax[i];
        best_idx[i] = tie[i];
    }
    WideRayLanes L;
    const int lanes = wide_ray_lanes(&L, &R);
    WideEntry stack[WIDE_STACK];
    uint32_t sp = 0;
    WideEntry cur = {w->root, w->root_blocks, 0, all};
    for (;;) {
        if (cur.blocks == 0) {
            const float *box = WIDE_NODE(w, cur.id);
            VN lo;
            int mask = wide_packet_node(&p, box, far, &lo);
            if (mask) {
                cur = wide_packet_push(w, box, mask, lo, &p, &q, all, best, stack, &sp, 1);
                if (cur.rays)
                    continue;
            }
        } else {
            uint32_t rs = cur.rays, took = 0;
            if (lanes && __builtin_popcount(rs) >= WIDE_LANES_MIN)
                took = wide_leaf_closest_lanes(&w->tris[cur.id], cur.blocks, &L, rs, best, best_idx, hits);
            else
                while (rs) {
                    int i = __builtin_ctz(rs);
                    rs &= rs - 1;
                    if (!(kset >> i & 1))
                        wide_ray_setup(&k[i], rays[i]), kset |= 1u << i;
                    if (wide_leaf_closest(&w->tris[cur.id], cur.blocks, &k[i], &best[i], &best_idx[i], &hits[i]))
                        took |= 1u << i;
                }
            if (took) { /* a ray's limit came nearer */
                found |= took;
                far = wide_max_of(best, all);
            }
        }
        do {
            if (sp == 0)
                return found;
            --sp;
        } while (stack[sp].t > far * BVH_FUDGE);
        cur = stack[sp];
    }
}

/* Shadow rays from hit points spread over many leaves share little of
 * their walk; one interval box for all of them then enters nodes that no
 * ray does.  Measured (make bench's scenes, 1 thread, ratio to Embree):
 * always packets: 1M-triangle sphere 0.86, scanned meshes 1.13-1.22; never:
 * 0.94 and 1.00-1.05; packets while the origins spread less than 1, 2, 3,
 * 4 or 8 mean leaf sizes: 0.95, 0.98, 0.97, 0.98, 0.94 on the sphere and
 * 1.17-1.24 on the bunny and the elephant for all five. */
#ifndef WIDE_SPREAD_LEAVES
#define WIDE_SPREAD_LEAVES 3
#endif

uint32_t KERNEL_ANY_PACKET(const Wide *w, const Ray *const *rays, int n, const real *tmax)
{
    WidePacket p;
    uint32_t hit = 0;
    WideRays q;
    WideRayRows R;
    if (n >= 2)
        wide_ray_rows(&R, rays, n);
    if (n < 2 || !wide_packet_setup(&p, &q, &R, WIDE_SPREAD_LEAVES * w->leaf_size, INFINITY)) {
        for (int i = 0; i < n; i++)
            hit |= (uint32_t)KERNEL_ANY(w, rays[i], tmax[i]) << i;
        return hit;
    }
    const uint32_t all = n == 32 ? ~0u : (1u << n) - 1;
    float far = wide_max_of(tmax, all);
    if (wide_packet_misses(w, &p, far))
        return 0;
    WideRay k[WIDE_PACKET]; /* set up when a ray first meets a leaf alone (kset) */
    uint32_t kset = 0;
    float tm[WIDE_PACKET] = {0};
    for (int i = 0; i < n; i++)
        tm[i] = tmax[i];
    WideRayLanes L;
    const int lanes = wide_ray_lanes(&L, &R);
    WideLanes lim;
    memcpy(&lim, tm, sizeof lim);
    WideEntry stack[WIDE_STACK];
    uint32_t sp = 0;
    WideEntry cur = {w->root, w->root_blocks, 0, all};
    for (;;) {
        const uint32_t active = all & ~hit;
        if (cur.blocks == 0) {
            const float *box = WIDE_NODE(w, cur.id);
            VN lo;
            int mask = wide_packet_node(&p, box, far, &lo);
            if (mask) {
                cur = wide_packet_push(w, box, mask, lo, &p, &q, active, tm, stack, &sp, 0);
                if (cur.rays)
                    continue;
            }
        } else {
            uint32_t rs = cur.rays & active;
            const uint32_t before = hit;
            if (lanes && __builtin_popcount(rs) >= WIDE_LANES_MIN)
                hit |= wide_leaf_any_lanes(&w->tris[cur.id], cur.blocks, &L, rs, lim);
            else
                while (rs) {
                    int i = __builtin_ctz(rs);
                    rs &= rs - 1;
                    if (!(kset >> i & 1))
                        wide_ray_setup(&k[i], rays[i]), kset |= 1u << i;
                    if (wide_leaf_any(&w->tris[cur.id], cur.blocks, &k[i], tm[i]))
                        hit |= 1u << i;
                }
            if (hit == all)
                return hit;
            if (hit != before) /* a ray left: the farthest limit may come nearer */
                far = wide_max_of(tm, all & ~hit);
        }
        if (sp == 0)
            return hit;
        cur = stack[--sp];
    }
}
