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

#include "bigmem.h"

#include "bvh_build.h"

#define BINS 32
#define COST_TRAVERSE R(1)
#define COST_INTERSECT R(1)

/* Boxes as two rows of four (the fourth unused), so that growing one is a
 * vector min and max. */
typedef struct {
    real lo[4], hi[4];
} Box4;

typedef struct {
    Box4 box;
    uint32_t count;
} Bin;

static int bin_of(real c, real lo, real scale)
{
    /* extreme coordinates can make this inf * 0 = NaN: clamp before converting */
    real f = (c - lo) * scale;
    if (!(f >= R(0)))
        return 0;
    return f >= (real)BINS ? BINS - 1 : (int)f;
}

static inline void box4_grow(Box4 *b, const Box4 *x)
{
    for (int k = 0; k < 4; k++) {
        b->lo[k] = x->lo[k] < b->lo[k] ? x->lo[k] : b->lo[k];
        b->hi[k] = x->hi[k] > b->hi[k] ? x->hi[k] : b->hi[k];
    }
}

static const Box4 box4_empty = {{REAL_INF, REAL_INF, REAL_INF, 0}, {-REAL_INF, -REAL_INF, -REAL_INF, 0}};

static Aabb box4_aabb(const Box4 *b)
{
    return (Aabb){v3(b->lo[0], b->lo[1], b->lo[2]), v3(b->hi[0], b->hi[1], b->hi[2])};
}

static real box4_half_area(const Box4 *b) { return aabb_half_area(box4_aabb(b)); }

static int sah_step(const Builder *b, const BuildTask *t, BuildTask kids[2])
{
    if (t->count == 1)
        return 0;
    const Box4 *boxes = b->aux;
    Bin bins[3][BINS];
    real lo[3], scale[3];
    vec3 ext = aabb_extent(t->cbox);
    for (int a = 0; a < 3; a++) {
        lo[a] = t->cbox.min.e[a];
        scale[a] = ext.e[a] > R(0) ? (real)BINS / ext.e[a] : R(0);
        for (int i = 0; i < BINS; i++)
            bins[a][i] = (Bin){box4_empty, 0};
    }
    for (uint32_t i = t->first; i < t->first + t->count; i++) {
        uint32_t p = b->perm[i];
        const vec3 c = b->centres[p];
        for (int a = 0; a < 3; a++) {
            Bin *bin = &bins[a][bin_of(c.e[a], lo[a], scale[a])];
            box4_grow(&bin->box, &boxes[p]);
            bin->count++;
        }
    }
    real best = REAL_INF;
    int axis = -1, split = 0;
    for (int a = 0; a < 3; a++) {
        if (ext.e[a] <= R(0))
            continue;
        real right_area[BINS];
        uint32_t right_count[BINS];
        Box4 acc = box4_empty;
        uint32_t cnt = 0;
        for (int i = BINS - 1; i > 0; i--) {
            box4_grow(&acc, &bins[a][i].box);
            cnt += bins[a][i].count;
            right_area[i] = box4_half_area(&acc);
            right_count[i] = cnt;
        }
        acc = box4_empty;
        cnt = 0;
        for (int i = 0; i < BINS - 1; i++) {
            box4_grow(&acc, &bins[a][i].box);
            cnt += bins[a][i].count;
            if (cnt == 0 || right_count[i + 1] == 0)
                continue;
            real c = box4_half_area(&acc) * (real)bvh_leaf_blocks(cnt) +
                     right_area[i + 1] * (real)bvh_leaf_blocks(right_count[i + 1]);
            if (c < best) {
                best = c;
                axis = a;
                split = i;
            }
        }
    }
    real area = aabb_half_area(t->box);
    real split_cost = area > R(0) ? COST_TRAVERSE + COST_INTERSECT * best / area : (best < REAL_INF ? COST_TRAVERSE : REAL_INF);
    real leaf_cost = COST_INTERSECT * (real)bvh_leaf_blocks(t->count);
    uint32_t nl;
    if (split_cost < REAL_INF && (split_cost < leaf_cost || t->count > b->opt->max_leaf)) {
        /* partition, growing each side's centre box on the way */
        Aabb cl = aabb_empty(), cr = aabb_empty();
        uint32_t i = t->first, j = t->first + t->count;
        while (i < j) {
            uint32_t p = b->perm[i];
            vec3 c = b->centres[p];
            if (bin_of(c.e[axis], lo[axis], scale[axis]) <= split) {
                aabb_grow(&cl, c);
                i++;
            } else {
                aabb_grow(&cr, c);
                b->perm[i] = b->perm[--j];
                b->perm[j] = p;
            }
        }
        nl = i - t->first;
        Box4 bl = box4_empty, br = box4_empty;
        for (int k = 0; k < BINS; k++)
            box4_grow(k > split ? &br : &bl, &bins[axis][k].box);
        kids[0].box = box4_aabb(&bl), kids[0].cbox = cl;
        kids[1].box = box4_aabb(&br), kids[1].cbox = cr;
    } else if (t->count > b->opt->max_leaf) {
        nl = t->count / 2; /* coincident centres: split by count */
        builder_bounds(b, t->first, nl, &kids[0].box, &kids[0].cbox);
        builder_bounds(b, t->first + nl, t->count - nl, &kids[1].box, &kids[1].cbox);
    } else {
        return 0;
    }
    kids[0].first = t->first, kids[0].count = nl;
    kids[1].first = t->first + nl, kids[1].count = t->count - nl;
    return 2;
}

int bvh_build_sah(Builder *b, Err *err)
{
    Box4 *boxes = bigmem_alloc((size_t)b->n * sizeof *boxes);
    if (!boxes)
        return err_set(err, "bvh: out of memory for %u primitives", b->n);
    for (uint32_t i = 0; i < b->n; i++)
        for (int k = 0; k < 4; k++) {
            boxes[i].lo[k] = k < 3 ? b->boxes[i].min.e[k] : R(0);
            boxes[i].hi[k] = k < 3 ? b->boxes[i].max.e[k] : R(0);
        }
    b->aux = boxes;
    int rc = builder_run(b, sah_step, err);
    free(boxes);
    b->aux = NULL;
    return rc;
}
