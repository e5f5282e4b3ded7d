/* bvh_sah.c - top-down builder that minimises the surface area heuristic.
 *
 * Binned SAH (Wald, "On fast construction of SAH-based bounding volume
 * hierarchies", 2007): centres are dropped into BINS buckets per axis and
 * every bucket boundary is costed with one sweep from each side.  A node
 * becomes a leaf when splitting would cost more than intersecting all its
 * primitives and it holds at most max_leaf of them; primitives cost by the
 * block of four (bvh.h, BVH_LEAF_BLOCK). */
#include <stdlib.h>

#include "bvh_build.h"

#define BINS 32
#define COST_TRAVERSE R(1)
#define COST_INTERSECT R(1)

typedef struct {
    Aabb box;
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

/* Finds the cheapest bucket boundary; returns its cost (inf if none). */
static real best_split(const Builder *b, const BuildNode *node, Aabb cbox, int *axis_out, int *bin_out)
{
    real best = REAL_INF;
    vec3 ext = aabb_extent(cbox);
    for (int axis = 0; axis < 3; axis++) {
        if (ext.e[axis] <= R(0))
            continue;
        Bin bins[BINS];
        for (int i = 0; i < BINS; i++)
            bins[i] = (Bin){aabb_empty(), 0};
        real lo = cbox.min.e[axis], scale = (real)BINS / ext.e[axis];
        for (uint32_t i = node->first; i < node->first + node->count; i++) {
            uint32_t p = b->perm[i];
            Bin *bin = &bins[bin_of(b->centres[p].e[axis], lo, scale)];
            bin->box = aabb_union(bin->box, b->boxes[p]);
            bin->count++;
        }
        real right_area[BINS];
        uint32_t right_count[BINS];
        Aabb acc = aabb_empty();
        uint32_t cnt = 0;
        for (int i = BINS - 1; i > 0; i--) {
            acc = aabb_union(acc, bins[i].box);
            cnt += bins[i].count;
            right_area[i] = aabb_half_area(acc);
            right_count[i] = cnt;
        }
        acc = aabb_empty();
        cnt = 0;
        for (int i = 0; i < BINS - 1; i++) {
            acc = aabb_union(acc, bins[i].box);
            cnt += bins[i].count;
            if (cnt == 0 || right_count[i + 1] == 0)
                continue;
            real c = aabb_half_area(acc) * (real)bvh_leaf_blocks(cnt) +
                     right_area[i + 1] * (real)bvh_leaf_blocks(right_count[i + 1]);
            if (c < best) {
                best = c;
                *axis_out = axis;
                *bin_out = i;
            }
        }
    }
    real area = aabb_half_area(node->box);
    return area > R(0) ? COST_TRAVERSE + COST_INTERSECT * best / area : (best < REAL_INF ? COST_TRAVERSE : REAL_INF);
}

int bvh_build_sah(Builder *b, Err *err)
{
    int32_t *tasks = malloc((b->n + 1) * sizeof *tasks);
    if (!tasks)
        return err_set(err, "bvh: out of memory");
    Aabb box, cbox;
    builder_bounds(b, 0, b->n, &box, &cbox);
    int32_t r = builder_add(b, (BuildNode){box, -1, -1, 0, b->n});
    uint32_t nt = 0;
    tasks[nt++] = r;
    while (nt && r >= 0) {
        int32_t ni = tasks[--nt];
        BuildNode node = b->nodes[ni];
        if (node.count == 1)
            continue;
        builder_bounds(b, node.first, node.count, &box, &cbox);
        int axis = 0, bin = 0;
        real split_cost = best_split(b, &node, cbox, &axis, &bin);
        real leaf_cost = COST_INTERSECT * (real)bvh_leaf_blocks(node.count);
        uint32_t nl;
        if (split_cost < REAL_INF && (split_cost < leaf_cost || node.count > b->opt->max_leaf)) {
            real lo = cbox.min.e[axis], scale = (real)BINS / aabb_extent(cbox).e[axis];
            uint32_t i = node.first, j = node.first + node.count;
            while (i < j) {
                if (bin_of(b->centres[b->perm[i]].e[axis], lo, scale) <= bin)
                    i++;
                else {
                    uint32_t t = b->perm[i];
                    b->perm[i] = b->perm[--j];
                    b->perm[j] = t;
                }
            }
            nl = i - node.first;
        } else if (node.count > b->opt->max_leaf) {
            nl = node.count / 2; /* coincident centres: split by count */
        } else {
            continue;
        }
        Aabb lb, rb;
        builder_bounds(b, node.first, nl, &lb, NULL);
        builder_bounds(b, node.first + nl, node.count - nl, &rb, NULL);
        int32_t l = builder_add(b, (BuildNode){lb, -1, -1, node.first, nl});
        r = l < 0 ? -1 : builder_add(b, (BuildNode){rb, -1, -1, node.first + nl, node.count - nl});
        if (r < 0)
            break;
        b->nodes[ni].left = l;
        b->nodes[ni].right = r;
        tasks[nt++] = l;
        tasks[nt++] = r;
    }
    free(tasks);
    if (r < 0)
        return err_set(err, "bvh: out of memory");
    b->root = 0;
    return 0;
}
