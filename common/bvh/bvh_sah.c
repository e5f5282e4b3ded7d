/* bvh_sah.c - top-down builder that minimises the surface area heuristic.
 *
 * Binned SAH (Wald, "On fast construction of SAH-based bounding volume
 * hierarchies", 2007): centres are dropped into BINS buckets per axis and
 * every bucket boundary is costed with one sweep from each side.  A node
 * becomes a leaf when splitting would cost more than intersecting all its
 * primitives and it holds at most max_leaf of them; primitives cost by the
 * block of four (bvh.h, BVH_LEAF_BLOCK).
 *
 * One pass over a node's primitives bins all three axes and keeps, per bin,
 * the box of the boxes and of the centres, so the chosen split's two
 * children get their boxes from the bins: no pass just for bounds.  Nodes
 * run as tasks on opt->threads workers (bvh_tasks.c). */
#include <stdlib.h>
#include <string.h>
#if defined(__x86_64__) && !defined(LANRAY_DOUBLE)
#include <immintrin.h>
#endif

#include "base/bigmem.h"

#include "bvh/bvh_build.h"

#define BINS 32
#define TWO_SETS_MIN 1024 /* primitives: below, one set of bins (bin_prims) */
#define COST_TRAVERSE R(1)
#define COST_INTERSECT R(1)

/* Boxes as two rows of four, so that growing one is a vector min and max.
 * A primitive's own box (its "reference") carries its index in the fourth
 * lane of hi, which bin boxes never read: the builder moves references
 * rather than indices into other arrays, so each level reads its nodes'
 * primitives in order instead of at random. */
typedef struct {
    _Alignas(4 * sizeof(real)) real lo[4];
    real hi[4];
} Box4;

/* The index in lane 3 is a normal number, which the arithmetic on whole
 * rows (centres: lo + hi, halved) passes over at full speed.  Its bits as
 * they were, a denormal for any index below 2^23, made every one of those
 * adds and multiplies take a microcode assist: three times as slow, a
 * third of the build (docs/renderer.md).  A float row holds the bits
 * offset by those of 1.0 (indices below BVH_MAX_PRIMS = 2^26 read as 1 to
 * 256), a double row the index's value, exact. */
#define REF_ID_BIAS 0x3f800000u
_Static_assert(BVH_MAX_PRIMS <= (1u << 26), "ref_id: the biased index must stay a normal float");
static real ref_id_lane(uint32_t i)
{
#ifdef LANRAY_DOUBLE
    return (real)i;
#else
    const uint32_t bits = i + REF_ID_BIAS;
    float f;
    memcpy(&f, &bits, sizeof f);
    return f;
#endif
}
static uint32_t ref_id(const Box4 *r)
{
#ifdef LANRAY_DOUBLE
    return (uint32_t)r->hi[3];
#else
    uint32_t bits;
    memcpy(&bits, &r->hi[3], sizeof bits);
    return bits - REF_ID_BIAS;
#endif
}
/* A reference's centre: aabb_centre's arithmetic, which binning and
 * partitioning must share to agree on every reference's bin.  On x86-64
 * float builds in a row, from the reference's rows lo and hi (lane 3
 * carries the index, halved). */
#if defined(__x86_64__) && !defined(LANRAY_DOUBLE)
static inline __attribute__((always_inline)) __m128 centre4(__m128 lo, __m128 hi)
{
    return _mm_mul_ps(_mm_add_ps(lo, hi), _mm_set1_ps(0.5f));
}
#else
static vec3 ref_centre(const Box4 *r)
{
    return v3((r->lo[0] + r->hi[0]) * R(0.5), (r->lo[1] + r->hi[1]) * R(0.5), (r->lo[2] + r->hi[2]) * R(0.5));
}
#endif

typedef struct {
    Box4 box;
    uint32_t count;
} Bin;

static inline int bin_of(real c, real lo, real scale, int nb)
{
    /* extreme coordinates can make this inf * 0 = NaN: clamp before converting */
    real f = (c - lo) * scale;
    if (!(f >= R(0)))
        return 0;
    return f >= (real)nb ? nb - 1 : (int)f;
}

static inline void box4_grow(Box4 *b, const Box4 *x)
{
    for (int k = 0; k < 4; k++) { /* lane 3 too: one vector op; bins never read it */
        b->lo[k] = x->lo[k] < b->lo[k] ? x->lo[k] : b->lo[k];
        b->hi[k] = x->hi[k] > b->hi[k] ? x->hi[k] : b->hi[k];
    }
}

static const Box4 box4_empty = {{REAL_INF, REAL_INF, REAL_INF, 0}, {-REAL_INF, -REAL_INF, -REAL_INF, 0}};

static Aabb box4_aabb(const Box4 *b)
{
    return (Aabb){v3(b->lo[0], b->lo[1], b->lo[2]), v3(b->hi[0], b->hi[1], b->hi[2])};
}

/* aabb_half_area of a box that is not empty (the sweeps only ever add
 * primitives and non-empty bins), without the emptiness test */
static inline real box4_half_area(const Box4 *b)
{
    real ex = b->hi[0] - b->lo[0], ey = b->hi[1] - b->lo[1], ez = b->hi[2] - b->lo[2];
    return ex * ey + ey * ez + ez * ex;
}

/* The box of the centres of refs[first, first + count). */
static Aabb refs_cbox(const Box4 *refs, uint32_t first, uint32_t count)
{
#if defined(__x86_64__) && !defined(LANRAY_DOUBLE)
    __m128 lo = _mm_set1_ps(INFINITY), hi = _mm_set1_ps(-INFINITY);
    for (uint32_t i = first; i < first + count; i++) {
        const __m128 c = centre4(_mm_load_ps(refs[i].lo), _mm_load_ps(refs[i].hi));
        lo = _mm_min_ps(lo, c), hi = _mm_max_ps(hi, c);
    }
    Box4 b;
    _mm_store_ps(b.lo, lo), _mm_store_ps(b.hi, hi);
    return box4_aabb(&b);
#else
    Aabb cbox = aabb_empty();
    for (uint32_t i = first; i < first + count; i++)
        aabb_grow(&cbox, ref_centre(&refs[i]));
    return cbox;
#endif
}

static void refs_bounds(const Box4 *refs, uint32_t first, uint32_t count, BuildTask *kid)
{
    Box4 box = box4_empty;
    for (uint32_t i = first; i < first + count; i++)
        box4_grow(&box, &refs[i]);
    kid->box = box4_aabb(&box);
    kid->cbox = refs_cbox(refs, first, count);
}

static inline __attribute__((always_inline)) void bins_clear(Bin bins[3][BINS], int nb)
{
    for (int a = 0; a < 3; a++)
        for (int i = 0; i < nb; i++)
            bins[a][i] = (Bin){box4_empty, 0};
}

/* Adds the primitives binned in `from` to `into`: boxes by minimum and
 * maximum, counts by sum, so the same bins in any order. */
static inline __attribute__((always_inline)) void bins_merge(Bin into[3][BINS], Bin from[3][BINS], int nb)
{
    for (int a = 0; a < 3; a++)
        for (int i = 0; i < nb; i++) {
            box4_grow(&into[a][i].box, &from[a][i].box);
            into[a][i].count += from[a][i].count;
        }
}

#if defined(__x86_64__) && !defined(LANRAY_DOUBLE)
/* One reference into its bin on each axis of a set of bins (bin_prims). */
static inline __attribute__((always_inline)) void bin_one(const Box4 *x, char *set, __m128 lov, __m128 scv, __m128 last,
                                                          __m128i size, __m128i axis_at)
{
    const __m128 l = _mm_load_ps(x->lo), h = _mm_load_ps(x->hi);
    __m128 f = _mm_mul_ps(_mm_sub_ps(centre4(l, h), lov), scv);
    /* bin_of: NaN or below 0 -> 0; nb - 1 or more -> nb - 1 (truncating min(f, nb - 1) is the same) */
    f = _mm_min_ps(_mm_and_ps(f, _mm_cmpge_ps(f, _mm_setzero_ps())), last);
    const __m128i at = _mm_add_epi32(_mm_mullo_epi16(_mm_cvttps_epi32(f), size), axis_at);
    Bin *b0 = (Bin *)(set + (uint32_t)_mm_cvtsi128_si32(at));
    Bin *b1 = (Bin *)(set + (uint32_t)_mm_cvtsi128_si32(_mm_shuffle_epi32(at, 1)));
    Bin *b2 = (Bin *)(set + (uint32_t)_mm_cvtsi128_si32(_mm_shuffle_epi32(at, 2)));
    _mm_store_ps(b0->box.lo, _mm_min_ps(l, _mm_load_ps(b0->box.lo)));
    _mm_store_ps(b0->box.hi, _mm_max_ps(h, _mm_load_ps(b0->box.hi)));
    b0->count++;
    _mm_store_ps(b1->box.lo, _mm_min_ps(l, _mm_load_ps(b1->box.lo)));
    _mm_store_ps(b1->box.hi, _mm_max_ps(h, _mm_load_ps(b1->box.hi)));
    b1->count++;
    _mm_store_ps(b2->box.lo, _mm_min_ps(l, _mm_load_ps(b2->box.lo)));
    _mm_store_ps(b2->box.hi, _mm_max_ps(h, _mm_load_ps(b2->box.hi)));
    b2->count++;
}
#endif

/* Drops each primitive's centre into a bin per axis (bin_of), growing the
 * bins' boxes.  The hot loop of the build: on x86-64 float builds the three
 * axes go at once in SSE, with the same arithmetic, so the same bins, and
 * the three bins' byte offsets are made in the same vector (one 16-bit
 * multiply and an add, where extending, scaling and offsetting each index
 * in scalar registers took 16 instructions of the 62 a reference), two
 * references a turn, one to each set.  Inlined into each caller, whose bins are its own array, which the
 * compiler then knows the references do not alias. */
static inline __attribute__((always_inline)) void bin_prims(const Box4 *refs, uint32_t first, uint32_t count,
                                                            const real lo[3], const real scale[3], int nb,
                                                            Bin bins[3][BINS])
{
#if defined(__x86_64__) && !defined(LANRAY_DOUBLE)
    const __m128 lov = _mm_setr_ps(lo[0], lo[1], lo[2], 0), scv = _mm_setr_ps(scale[0], scale[1], scale[2], 0);
    const __m128 last = _mm_set1_ps((float)(nb - 1));
    /* a bin's byte offset from the axis's first bin, (k * sizeof(Bin))
     * in 16 bits (k < BINS), and the axes' first bins from bins[0] */
    const __m128i size = _mm_set1_epi32((int)sizeof(Bin));
    const __m128i axis_at = _mm_setr_epi32(0, (int)(BINS * sizeof(Bin)), (int)(2 * BINS * sizeof(Bin)), 0);
    /* two sets of bins, for even and odd primitives, merged at the end:
     * neighbours (sorted by the partitions above) often share a bin, and
     * one set makes every update wait for the last one's store; a small
     * node keeps one, where clearing and merging the second cost more */
    Bin odd[3][BINS];
    const int two = count >= TWO_SETS_MIN;
    if (two)
        bins_clear(odd, nb);
    char *const even_set = (char *)bins, *const odd_set = two ? (char *)odd : (char *)bins;
    const Box4 *x = refs + first, *const end = refs + first + count;
    for (; end - x >= 2; x += 2) {
        bin_one(x, even_set, lov, scv, last, size, axis_at);
        bin_one(x + 1, odd_set, lov, scv, last, size, axis_at);
    }
    if (x < end)
        bin_one(x, even_set, lov, scv, last, size, axis_at);
    if (two)
        bins_merge(bins, odd, nb);
#else
    for (uint32_t i = first; i < first + count; i++) {
        const vec3 c = ref_centre(&refs[i]);
        for (int a = 0; a < 3; a++) {
            Bin *bin = &bins[a][bin_of(c.e[a], lo[a], scale[a], nb)];
            box4_grow(&bin->box, &refs[i]);
            bin->count++;
        }
    }
#endif
}

/* Moves the references of [first, first + count) whose centre falls in a
 * bin up to `split` of `axis` before the others; returns where the second
 * side starts.
 *
 * A centre is in a bin up to `split` exactly when (c - lo) * scale <
 * split + 1: bin_of's arithmetic, with its clamps (NaN and negatives go to
 * bin 0, on the left; split + 1 <= nb - 1 leaves the upper clamp out of
 * it).
 *
 * By blocks from both ends (Edelkamp and Weiss's BlockQuicksort): a block
 * of PART_BLOCK references at the front notes, without a branch, the ones
 * that belong at the back (a bit each in a mask: a byte each in an array
 * made every note a store), a block at the back the ones that belong at
 * the front, and as many pairs as both have are swapped.  Each reference is
 * read once and only the misplaced ones written, where the scheme before
 * (Lomuto's: every reference swapped with the first one not yet known to
 * go left) read and wrote every one twice; the upper levels stream the
 * whole array from memory, so that traffic was their time.  What is left
 * between the last blocks goes by Lomuto's scheme. */
#define PART_BLOCK 64

/* Where each reference goes: bin_of's arithmetic, per lane on x86-64
 * float builds, on the split's axis otherwise. */
typedef struct {
#if defined(__x86_64__) && !defined(LANRAY_DOUBLE)
    __m128 lo, scale, limit;
#else
    real lo, scale, limit;
#endif
} Side;

/* Whether x goes right (1) or left (0).  `axis` is a constant in each
 * caller (partition), so that picking its lane is one shift. */
static inline __attribute__((always_inline)) int side_right(const Side *s, const Box4 *x, int axis)
{
#if defined(__x86_64__) && !defined(LANRAY_DOUBLE)
    const __m128 c = centre4(_mm_load_ps(x->lo), _mm_load_ps(x->hi));
    return (_mm_movemask_ps(_mm_cmpge_ps(_mm_mul_ps(_mm_sub_ps(c, s->lo), s->scale), s->limit)) >> axis) & 1;
#else
    return (((x->lo[axis] + x->hi[axis]) * R(0.5)) - s->lo) * s->scale >= s->limit;
#endif
}

static inline __attribute__((always_inline)) void ref_swap(Box4 *a, Box4 *b)
{
    Box4 t = *a;
    *a = *b;
    *b = t;
}

static inline __attribute__((always_inline)) uint32_t partition_on(Box4 *refs, uint32_t first, uint32_t count,
                                                                    const int axis, const Side *s)
{
    uint32_t l = first, r = first + count; /* [l, r) not yet in place */
    /* bit k: the front block's reference l + k goes right, the back
     * block's r - 1 - k goes left; set bits are paired in order */
    uint64_t ml = 0, mr = 0;
    int have_l = 0, have_r = 0;
    while (r - l >= 2 * PART_BLOCK) {
        if (!have_l) {
            for (uint32_t k = 0; k < PART_BLOCK; k++)
                ml |= (uint64_t)side_right(s, &refs[l + k], axis) << k;
            have_l = 1;
        }
        if (!have_r) {
            for (uint32_t k = 0; k < PART_BLOCK; k++)
                mr |= (uint64_t)!side_right(s, &refs[r - 1 - k], axis) << k;
            have_r = 1;
        }
        for (; ml && mr; ml &= ml - 1, mr &= mr - 1)
            ref_swap(&refs[l + (uint32_t)__builtin_ctzll(ml)], &refs[r - 1 - (uint32_t)__builtin_ctzll(mr)]);
        if (!ml)
            l += PART_BLOCK, have_l = 0;
        if (!mr)
            r -= PART_BLOCK, have_r = 0;
    }
    uint32_t j = l; /* the rest, Lomuto's way */
    for (uint32_t i = l; i < r; i++) {
        const int right = side_right(s, &refs[i], axis);
        ref_swap(&refs[i], &refs[j]);
        j += (uint32_t)!right;
    }
    return j;
}

static uint32_t partition(Box4 *refs, uint32_t first, uint32_t count, int axis, const real lo[3], const real scale[3],
                          int split)
{
    const real limit = (real)(split + 1);
    Side s;
#if defined(__x86_64__) && !defined(LANRAY_DOUBLE)
    s.lo = _mm_setr_ps(lo[0], lo[1], lo[2], 0), s.scale = _mm_setr_ps(scale[0], scale[1], scale[2], 0);
    s.limit = _mm_set1_ps(limit);
#else
    s.lo = lo[axis], s.scale = scale[axis], s.limit = limit;
#endif
    switch (axis) { /* a constant axis in each */
    case 0: return partition_on(refs, first, count, 0, &s);
    case 1: return partition_on(refs, first, count, 1, &s);
    default: return partition_on(refs, first, count, 2, &s);
    }
}

/* Small nodes: the exact SAH over every split position of the centres
 * sorted on each axis.  Cheaper than filling 96 bins for a handful of
 * primitives (clearing the bins was a fifth of the build), and better:
 * binning can only approximate these splits. */
#define SWEEP_MAX 8

/* For each axis, the order of the n centres along it (order[a][r]: the
 * r-th smallest, equal ones keeping their order: the key is twice each
 * centre) and the SAH cost of each split of that order (cost[a][j]: the
 * first j + 1 on the left).
 *
 * On x86-64 float builds the three axes go at once, one to a lane: a
 * reference's keys are its lo + hi, each one's rank is counted against all
 * the others without a branch, and the sweeps grow three boxes at once
 * from the references transposed into a vector per coordinate.  The same
 * arithmetic per lane as the scalar sweep below, so the same costs; three
 * axes one by one, with their shuffles and scalar areas, were a seventh of
 * the build (callgrind: 3200 instructions a node, 2000 now). */
static void sweep_costs(const Box4 *refs, uint32_t n, uint8_t order[3][SWEEP_MAX], real cost[3][SWEEP_MAX])
{
#if defined(__x86_64__) && !defined(LANRAY_DOUBLE)
    __m128 key[SWEEP_MAX];
    for (uint32_t i = 0; i < n; i++)
        key[i] = _mm_add_ps(_mm_load_ps(refs[i].lo), _mm_load_ps(refs[i].hi));
    for (uint32_t i = 0; i < n; i++) {
        __m128i rank = _mm_setzero_si128();
        for (uint32_t j = 0; j < i; j++) /* before i: ties count */
            rank = _mm_sub_epi32(rank, _mm_castps_si128(_mm_cmple_ps(key[j], key[i])));
        for (uint32_t j = i + 1; j < n; j++)
            rank = _mm_sub_epi32(rank, _mm_castps_si128(_mm_cmplt_ps(key[j], key[i])));
        order[0][_mm_cvtsi128_si32(rank)] = (uint8_t)i;
        order[1][_mm_cvtsi128_si32(_mm_shuffle_epi32(rank, 1))] = (uint8_t)i;
        order[2][_mm_cvtsi128_si32(_mm_shuffle_epi32(rank, 2))] = (uint8_t)i;
    }
    /* lane a: the box of the references taken so far in axis a's order */
    const __m128 inf = _mm_set1_ps(INFINITY), ninf = _mm_set1_ps(-INFINITY);
    __m128 right_area[SWEEP_MAX];
    for (int side = 0; side < 2; side++) {
        __m128 lx = inf, ly = inf, lz = inf, hx = ninf, hy = ninf, hz = ninf;
        for (uint32_t s = 0; s + 1 < n; s++) {
            const uint32_t j = side ? s : n - 1 - s; /* the right side from the back */
            const Box4 *r0 = &refs[order[0][j]], *r1 = &refs[order[1][j]], *r2 = &refs[order[2][j]];
            __m128 l0 = _mm_load_ps(r0->lo), l1 = _mm_load_ps(r1->lo), l2 = _mm_load_ps(r2->lo), l3 = inf;
            __m128 h0 = _mm_load_ps(r0->hi), h1 = _mm_load_ps(r1->hi), h2 = _mm_load_ps(r2->hi), h3 = ninf;
            _MM_TRANSPOSE4_PS(l0, l1, l2, l3);
            _MM_TRANSPOSE4_PS(h0, h1, h2, h3);
            lx = _mm_min_ps(l0, lx), ly = _mm_min_ps(l1, ly), lz = _mm_min_ps(l2, lz);
            hx = _mm_max_ps(h0, hx), hy = _mm_max_ps(h1, hy), hz = _mm_max_ps(h2, hz);
            /* box4_half_area's arithmetic */
            const __m128 ex = _mm_sub_ps(hx, lx), ey = _mm_sub_ps(hy, ly), ez = _mm_sub_ps(hz, lz);
            const __m128 area = _mm_add_ps(_mm_add_ps(_mm_mul_ps(ex, ey), _mm_mul_ps(ey, ez)), _mm_mul_ps(ez, ex));
            if (!side) {
                right_area[j] = area;
                continue;
            }
            _Alignas(16) real c[4];
            _mm_store_ps(c, _mm_add_ps(_mm_mul_ps(area, _mm_set1_ps((real)bvh_leaf_blocks(j + 1))),
                                       _mm_mul_ps(right_area[j + 1], _mm_set1_ps((real)bvh_leaf_blocks(n - j - 1)))));
            cost[0][j] = c[0], cost[1][j] = c[1], cost[2][j] = c[2];
        }
    }
#else
    for (int a = 0; a < 3; a++) {
        real key[SWEEP_MAX], sorted[SWEEP_MAX];
        for (uint32_t i = 0; i < n; i++)
            key[i] = refs[i].lo[a] + refs[i].hi[a];
        for (uint32_t i = 0; i < n; i++) { /* insertion sort */
            uint32_t j = i;
            while (j > 0 && sorted[j - 1] > key[i]) {
                sorted[j] = sorted[j - 1];
                order[a][j] = order[a][j - 1];
                j--;
            }
            sorted[j] = key[i];
            order[a][j] = (uint8_t)i;
        }
        real right_area[SWEEP_MAX];
        Box4 acc = box4_empty;
        for (uint32_t j = n - 1; j > 0; j--) {
            box4_grow(&acc, &refs[order[a][j]]);
            right_area[j] = box4_half_area(&acc);
        }
        acc = box4_empty;
        for (uint32_t j = 0; j + 1 < n; j++) {
            box4_grow(&acc, &refs[order[a][j]]);
            cost[a][j] = box4_half_area(&acc) * (real)bvh_leaf_blocks(j + 1) +
                         right_area[j + 1] * (real)bvh_leaf_blocks(n - j - 1);
        }
    }
#endif
}

static int sah_sweep(const Builder *b, const BuildTask *t, BuildTask kids[2])
{
    Box4 *refs = (Box4 *)b->aux + t->first;
    const uint32_t n = t->count;
    uint8_t order[3][SWEEP_MAX];
    real cost[3][SWEEP_MAX];
    sweep_costs(refs, n, order, cost);
    real best = REAL_INF;
    int axis = -1;
    uint32_t split = 0;
    for (int a = 0; a < 3; a++)
        for (uint32_t j = 0; j + 1 < n; j++)
            if (cost[a][j] < best) {
                best = cost[a][j];
                axis = a;
                split = j + 1;
            }
    real area = aabb_half_area(t->box);
    real split_cost = area > R(0) ? COST_TRAVERSE + COST_INTERSECT * best / area : COST_TRAVERSE;
    if (!(split_cost < COST_INTERSECT * (real)bvh_leaf_blocks(n)) && n <= b->opt->max_leaf)
        return 0;
    if (axis < 0) { /* every cost overflowed (boxes past 1e19 in a float build): the median of the widest axis */
        axis = v3_max_axis(aabb_extent(t->cbox));
        split = n / 2;
    }
    Box4 sorted[SWEEP_MAX];
    for (uint32_t j = 0; j < n; j++)
        sorted[j] = refs[order[axis][j]];
    memcpy(refs, sorted, n * sizeof *refs);
    kids[0].first = t->first, kids[0].count = split;
    kids[1].first = t->first + split, kids[1].count = n - split;
    refs_bounds(b->aux, kids[0].first, kids[0].count, &kids[0]);
    refs_bounds(b->aux, kids[1].first, kids[1].count, &kids[1]);
    return 2;
}

/* Bins for a node of n primitives: fewer for small nodes, whose binning
 * cost is mostly clearing and sweeping the bins.  Embree's rule, 4 + n/20,
 * at most BINS, with the exact sweep up to 8 primitives.  Measured against
 * 8 + n/8 with the sweep up to 32 (docs/renderer.md): a quarter fewer
 * build instructions (the 1M sphere 4.02 G -> 3.03 G a build, Embree's
 * 2.62 G), and traversal instructions within 0.2% (bunny +0.02%, sphere
 * +0.2%, 512x384).  Under the kernels of 2026-11-23 the same rules had
 * cost the bunny's traversal 1.1%; the per-ray leaf test in lanes made the
 * extra leaf visits cheap. */
static int bin_count(uint32_t n) { return n >= 20 * (BINS - 4) ? BINS : 4 + (int)(n / 20); }

/* Binning at the top of the tree (sah_step_top: no other task runs), by
 * ranges on the pool, each thread into its own bins, which are then
 * merged (bins_merge): the same bins whichever thread took which range. */
typedef struct {
    const Box4 *refs;
    uint32_t first;
    const real *lo, *scale;
    int nb;
    Bin (*bins)[3][BINS]; /* one set per pool thread */
} BinJob;

static void bin_range(void *ctx, uint64_t lo, uint64_t hi, int thread)
{
    const BinJob *j = ctx;
    bin_prims(j->refs, j->first + (uint32_t)lo, (uint32_t)(hi - lo), j->lo, j->scale, j->nb, j->bins[thread]);
}

typedef Bin BinSet[3][BINS];

/* The merged bins in a block the caller frees, or NULL (out of memory:
 * the caller bins alone, to the same bins). */
static BinSet *bin_on_pool(const Builder *b, const BuildTask *t, const real lo[3], const real scale[3], int nb)
{
    const int threads = pool_threads(b->pool);
    BinSet *sets = malloc((size_t)threads * sizeof *sets);
    if (!sets)
        return NULL;
    for (int k = 0; k < threads; k++)
        bins_clear(sets[k], nb);
    BinJob job = {b->aux, t->first, lo, scale, nb, sets};
    pool_for(b->pool, t->count, BVH_POOL_GRAIN, bin_range, &job);
    for (int k = 1; k < threads; k++)
        bins_merge(sets[0], sets[k], nb);
    return sets;
}

/* sah_step and sah_step_top in one body: `top` is a constant in each, so
 * sah_step has no trace of the pool.  With the pool's branch in the one
 * step every node took, the one-thread build, which never takes it, was
 * 15% slower (interleaved, 1M sphere). */
static inline __attribute__((always_inline)) int sah_split(const Builder *b, const BuildTask *t, BuildTask kids[2],
                                                           int top)
{
    /* One block of primitives is a leaf: it costs COST_INTERSECT, and any
     * split costs COST_TRAVERSE (no less) plus its children's share, so
     * neither sweep could choose to split.  Most leaves are such nodes,
     * and their sweeps were a twentieth of the build. */
    if (t->count <= BVH_LEAF_BLOCK && t->count <= b->opt->max_leaf)
        return 0;
    if (t->count <= SWEEP_MAX)
        return sah_sweep(b, t, kids);
    Box4 *refs = (Box4 *)b->aux;
    Bin bins[3][BINS];
    real lo[3], scale[3];
    vec3 ext = aabb_extent(t->cbox);
    const int nb = bin_count(t->count);
    for (int a = 0; a < 3; a++) {
        lo[a] = t->cbox.min.e[a];
        scale[a] = ext.e[a] > R(0) ? (real)nb / ext.e[a] : R(0);
    }
    BinSet *pooled = top && b->pool ? bin_on_pool(b, t, lo, scale, nb) : NULL;
    if (pooled) {
        for (int a = 0; a < 3; a++)
            for (int i = 0; i < nb; i++)
                bins[a][i] = pooled[0][a][i];
        free(pooled);
    } else {
        bins_clear(bins, nb);
        bin_prims(refs, t->first, t->count, lo, scale, nb, bins);
    }
    real best = REAL_INF;
    int axis = -1, split = 0;
    for (int a = 0; a < 3; a++) {
        if (ext.e[a] <= R(0))
            continue;
        /* only the bins that hold something: a boundary inside a run of
         * empty bins cuts the same way and costs the same as the first
         * boundary of the run, which is the one a sweep over every bin
         * keeps (strictly smaller wins) */
        int used[BINS], m = 0;
        for (int i = 0; i < nb; i++)
            if (bins[a][i].count)
                used[m++] = i;
        real right_area[BINS];
        uint32_t right_count[BINS];
        Box4 acc = box4_empty;
        uint32_t cnt = 0;
        for (int j = m - 1; j > 0; j--) {
            box4_grow(&acc, &bins[a][used[j]].box);
            cnt += bins[a][used[j]].count;
            right_area[j] = box4_half_area(&acc);
            right_count[j] = cnt;
        }
        acc = box4_empty;
        cnt = 0;
        for (int j = 0; j < m - 1; j++) {
            box4_grow(&acc, &bins[a][used[j]].box);
            cnt += bins[a][used[j]].count;
            real c = box4_half_area(&acc) * (real)bvh_leaf_blocks(cnt) +
                     right_area[j + 1] * (real)bvh_leaf_blocks(right_count[j + 1]);
            if (c < best) {
                best = c;
                axis = a;
                split = used[j];
            }
        }
    }
    real area = aabb_half_area(t->box);
    real split_cost = area > R(0) ? COST_TRAVERSE + COST_INTERSECT * best / area : (best < REAL_INF ? COST_TRAVERSE : REAL_INF);
    real leaf_cost = COST_INTERSECT * (real)bvh_leaf_blocks(t->count);
    uint32_t nl;
    if (split_cost < REAL_INF && (split_cost < leaf_cost || t->count > b->opt->max_leaf)) {
        nl = partition(refs, t->first, t->count, axis, lo, scale, split) - t->first;
        Box4 bl = box4_empty, br = box4_empty;
        for (int k = 0; k < nb; k++)
            box4_grow(k > split ? &br : &bl, &bins[axis][k].box);
        kids[0].box = box4_aabb(&bl), kids[0].cbox = refs_cbox(refs, t->first, nl);
        kids[1].box = box4_aabb(&br), kids[1].cbox = refs_cbox(refs, t->first + nl, t->count - nl);
    } else if (t->count > b->opt->max_leaf) {
        nl = t->count / 2; /* coincident centres: split by count */
        refs_bounds(refs, t->first, nl, &kids[0]);
        refs_bounds(refs, t->first + nl, t->count - nl, &kids[1]);
    } else {
        return 0;
    }
    kids[0].first = t->first, kids[0].count = nl;
    kids[1].first = t->first + nl, kids[1].count = t->count - nl;
    return 2;
}

static int sah_step(const Builder *b, const BuildTask *t, BuildTask kids[2]) { return sah_split(b, t, kids, 0); }
static int sah_step_top(const Builder *b, const BuildTask *t, BuildTask kids[2]) { return sah_split(b, t, kids, 1); }

/* The references, from the boxes, in one pass that also checks each box
 * (the first bad one per range) and bounds the boxes and their centres
 * for the root: where three passes over the boxes did it. */
typedef struct {
    Builder *b;
    uint32_t bad[BVH_POOL_MAX];
    Box4 box[BVH_POOL_MAX], cbox[BVH_POOL_MAX];
} Fill;

static void refs_fill(void *ctx, uint64_t lo, uint64_t hi, int thread)
{
    Fill *w = ctx;
    const Builder *b = w->b;
    Box4 *refs = (Box4 *)b->aux;
    uint32_t i;
#if defined(__x86_64__) && !defined(LANRAY_DOUBLE)
    /* in registers: built in memory lane by lane and read back as vectors,
     * each read waited for stores it could not forward from */
    __m128 blo = _mm_load_ps(w->box[thread].lo), bhi = _mm_load_ps(w->box[thread].hi);
    __m128 clo = _mm_load_ps(w->cbox[thread].lo), chi = _mm_load_ps(w->cbox[thread].hi);
    for (i = (uint32_t)lo; i < hi; i++) {
        const Aabb x = b->boxes[i];
        if (!builder_box_ok(x))
            break;
        const __m128 l = _mm_setr_ps(x.min.x, x.min.y, x.min.z, 0), h = _mm_setr_ps(x.max.x, x.max.y, x.max.z, 0);
        const __m128 c = centre4(l, h);
        blo = _mm_min_ps(blo, l), bhi = _mm_max_ps(bhi, h);
        clo = _mm_min_ps(clo, c), chi = _mm_max_ps(chi, c);
        _mm_store_ps(refs[i].lo, l);
        _mm_store_ps(refs[i].hi, _mm_setr_ps(x.max.x, x.max.y, x.max.z, ref_id_lane(i)));
    }
    _mm_store_ps(w->box[thread].lo, blo), _mm_store_ps(w->box[thread].hi, bhi);
    _mm_store_ps(w->cbox[thread].lo, clo), _mm_store_ps(w->cbox[thread].hi, chi);
#else
    Box4 box = w->box[thread], cbox = w->cbox[thread];
    for (i = (uint32_t)lo; i < hi; i++) {
        if (!builder_box_ok(b->boxes[i]))
            break;
        Box4 r, c;
        for (int k = 0; k < 4; k++) {
            r.lo[k] = k < 3 ? b->boxes[i].min.e[k] : R(0);
            r.hi[k] = k < 3 ? b->boxes[i].max.e[k] : R(0);
            c.lo[k] = c.hi[k] = (r.lo[k] + r.hi[k]) * R(0.5); /* aabb_centre's arithmetic */
        }
        box4_grow(&box, &r);
        box4_grow(&cbox, &c);
        r.hi[3] = ref_id_lane(i);
        refs[i] = r;
    }
    w->box[thread] = box, w->cbox[thread] = cbox;
#endif
    if (i < hi && i < w->bad[thread]) /* the range's first bad box */
        w->bad[thread] = i;
}

static void refs_perm(void *ctx, uint64_t lo, uint64_t hi, int thread)
{
    (void)thread;
    const Builder *b = ctx;
    const Box4 *refs = b->aux;
    for (uint64_t i = lo; i < hi; i++)
        b->perm[i] = ref_id(&refs[i]);
}

int bvh_build_sah(Builder *b, Err *err)
{
    Box4 *refs = bigmem_alloc((size_t)b->n * sizeof *refs);
    if (!refs)
        return err_set(err, "bvh: out of memory for %u primitives", b->n);
    b->aux = refs;
    Fill w;
    w.b = b;
    for (int k = 0; k < BVH_POOL_MAX; k++)
        w.bad[k] = b->n, w.box[k] = w.cbox[k] = box4_empty;
    pool_for(b->pool, b->n, BVH_POOL_GRAIN, refs_fill, &w);
    /* minima and maxima: the same bounds in any order and cut */
    uint32_t bad = b->n;
    Box4 box = box4_empty, cbox = box4_empty;
    for (int k = 0; k < BVH_POOL_MAX; k++) {
        bad = w.bad[k] < bad ? w.bad[k] : bad;
        box4_grow(&box, &w.box[k]);
        box4_grow(&cbox, &w.cbox[k]);
    }
    if (bad < b->n) {
        free(refs);
        b->aux = NULL;
        return builder_bad_box(bad, err);
    }
    b->root_known = 1;
    b->root_box = box4_aabb(&box), b->root_cbox = box4_aabb(&cbox);
    int rc = builder_run(b, sah_step, sah_step_top, err);
    if (rc == 0)
        pool_for(b->pool, b->n, BVH_POOL_GRAIN, refs_perm, b);
    free(refs);
    b->aux = NULL;
    return rc;
}
