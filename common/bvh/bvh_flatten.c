/* bvh_flatten.c - turns a builder's binary tree into the flat traversal layout.
 *
 * Children are given adjacent slots in depth-first order (good locality for
 * the near-child-first traversal).  Two extra duties live here so that every
 * builder gets them:
 *  - collapse (MST): a subtree of at most max_leaf primitives becomes one
 *    leaf when the SAH says a leaf is cheaper than the subtree;
 *  - depth repair: a subtree that would reach below BVH_MAX_DEPTH is rebuilt
 *    by object median, which is balanced, so the traversal stack never
 *    overflows whatever the input (spatial medians and agglomerative trees
 *    can both degenerate into long chains). */
#include <stdlib.h>

#include "base/bigmem.h"
#include <string.h>

#include "bvh/bvh_build.h"

#define REPAIR_DEPTH (BVH_MAX_DEPTH - 32) /* leaves room for a balanced tree of 2^31 leaves */

typedef struct {
    const Builder *b;
    const vec3 *centres; /* the builder's, or made for a repair (SAH keeps none) */
    BvhNode *nodes;
    uint32_t node_count, node_cap;
    uint32_t *prims;
    uint32_t prim_count;
    uint32_t depth;
} Flat;

static void flat_set_box(BvhNode *n, Aabb box)
{
    for (int a = 0; a < 3; a++) {
        n->bmin[a] = box.min.e[a];
        n->bmax[a] = box.max.e[a];
    }
}

static void flat_note_depth(Flat *f, uint32_t d)
{
    if (d > f->depth)
        f->depth = d;
}

/* Quickselect: reorder p[0..n) so that p[k] has the k-th smallest centre on axis. */
static void select_kth(uint32_t *p, uint32_t n, uint32_t k, const vec3 *centres, int axis)
{
    uint32_t lo = 0, hi = n - 1;
    while (lo < hi) {
        real pivot = centres[p[lo + (hi - lo) / 2]].e[axis];
        uint32_t i = lo, j = hi;
        while (i <= j) {
            while (centres[p[i]].e[axis] < pivot)
                i++;
            while (centres[p[j]].e[axis] > pivot)
                j--;
            if (i <= j) {
                uint32_t t = p[i];
                p[i] = p[j];
                p[j] = t;
                i++;
                if (j == 0)
                    break;
                j--;
            }
        }
        if (k <= j)
            hi = j;
        else if (k >= i)
            lo = i;
        else
            return;
    }
}

/* Balanced object-median tree over p[0..n) written at flat slot idx. Recursion depth is log2(n). */
static void flat_median(Flat *f, uint32_t *p, uint32_t n, uint32_t idx, uint32_t depth)
{
    Aabb box = aabb_empty(), cbox = aabb_empty();
    for (uint32_t i = 0; i < n; i++) {
        box = aabb_union(box, f->b->boxes[p[i]]);
        aabb_grow(&cbox, f->centres[p[i]]);
    }
    BvhNode *node = &f->nodes[idx];
    flat_set_box(node, box);
    flat_note_depth(f, depth);
    if (n <= f->b->opt->max_leaf) {
        node->first = f->prim_count;
        node->count = n;
        memcpy(f->prims + f->prim_count, p, n * sizeof *p);
        f->prim_count += n;
        return;
    }
    int axis = v3_max_axis(aabb_extent(cbox));
    uint32_t half = n / 2;
    select_kth(p, n, half, f->centres, axis);
    uint32_t c = f->node_count;
    f->node_count += 2;
    node->first = c;
    node->count = 0;
    flat_median(f, p, half, c, depth + 1);
    flat_median(f, p + half, n - half, c + 1, depth + 1);
}

/* Appends the primitives under build node `root` to out[], returns how many. */
static uint32_t collect_prims(const Builder *b, uint32_t root, uint32_t *out, uint32_t *stack)
{
    uint32_t sp = 0, n = 0;
    stack[sp++] = root;
    while (sp) {
        const BuildNode *bn = &b->nodes[stack[--sp]];
        if (bn->left < 0) {
            memcpy(out + n, b->perm + bn->first, bn->count * sizeof *out);
            n += bn->count;
        } else {
            stack[sp++] = (uint32_t)bn->right;
            stack[sp++] = (uint32_t)bn->left;
        }
    }
    return n;
}

/* Centres for a depth repair, where the builder kept none (SAH). */
static int flat_centres(Flat *f, vec3 **own)
{
    if (f->centres)
        return 0;
    if (!(*own = bigmem_alloc(f->b->n * sizeof **own)))
        return -1;
    for (uint32_t i = 0; i < f->b->n; i++)
        (*own)[i] = aabb_centre(f->b->boxes[i]);
    f->centres = *own;
    return 0;
}

int bvh_flatten(const Builder *b, Bvh *out, Err *err)
{
    /* a tree its builder knows to be shallow enough, with nothing to
     * collapse, is laid out as it is: no pass for heights and costs (on
     * the 1M-triangle sphere, a tenth of the SAH build on two threads) */
    const int plain = !b->collapse && b->max_depth && b->max_depth <= BVH_MAX_DEPTH;
    uint32_t bn_count = b->node_count, pass = plain ? 1 : bn_count;
    uint32_t *order = bigmem_alloc(pass * sizeof *order);   /* pre-order */
    uint32_t *stack = bigmem_alloc(pass * sizeof *stack);
    uint32_t *height = bigmem_alloc(pass * sizeof *height);
    uint32_t *nprims = bigmem_alloc(pass * sizeof *nprims);
    double *cost = bigmem_alloc(pass * sizeof *cost);
    uint32_t *tmp = bigmem_alloc((plain ? 1 : b->n) * sizeof *tmp);
    uint32_t (*work)[3] = bigmem_alloc(bn_count * sizeof *work); /* build node, flat slot, depth */
    vec3 *own_centres = NULL;
    Flat f = {b, b->centres, NULL, 0, 2 * b->n, NULL, 0, 0};
    Bvh nodes_owner = {0};
    if (bvh_alloc_nodes(&nodes_owner, f.node_cap) == 0)
        f.nodes = nodes_owner.nodes;
    f.prims = bigmem_alloc(b->n * sizeof *f.prims);
    int rc = -1;
    if (!order || !stack || !height || !nprims || !cost || !tmp || !work || !f.nodes || !f.prims) {
        err_set(err, "bvh: out of memory flattening %u nodes", bn_count);
        goto done;
    }
    /* pre-order, then a reverse sweep gives children before parents */
    uint32_t sp = 0, no = 0;
    if (!plain)
        stack[sp++] = b->root;
    while (sp) {
        uint32_t i = stack[--sp];
        order[no++] = i;
        if (b->nodes[i].left >= 0) {
            stack[sp++] = (uint32_t)b->nodes[i].right;
            stack[sp++] = (uint32_t)b->nodes[i].left;
        }
    }
    for (uint32_t k = no; !plain && k-- > 0;) {
        uint32_t i = order[k];
        const BuildNode *bn = &b->nodes[i];
        double area = aabb_half_area(bn->box);
        if (bn->left < 0) {
            height[i] = 1;
            nprims[i] = bn->count;
            cost[i] = area * bvh_leaf_blocks(bn->count);
        } else {
            uint32_t l = (uint32_t)bn->left, r = (uint32_t)bn->right;
            height[i] = 1 + (height[l] > height[r] ? height[l] : height[r]);
            nprims[i] = nprims[l] + nprims[r];
            cost[i] = area + cost[l] + cost[r];
            if (b->collapse && nprims[i] <= b->opt->max_leaf && area * bvh_leaf_blocks(nprims[i]) <= cost[i]) {
                cost[i] = area * bvh_leaf_blocks(nprims[i]);
                height[i] = 1;
            }
        }
    }
    uint32_t wp = 0;
    f.node_count = 1;
    work[wp][0] = b->root, work[wp][1] = 0, work[wp][2] = 1, wp++;
    while (wp) {
        wp--;
        uint32_t i = work[wp][0], slot = work[wp][1], depth = work[wp][2];
        const BuildNode *bn = &b->nodes[i];
        BvhNode *node = &f.nodes[slot];
        int leaf = bn->left < 0 || (b->collapse && height[i] == 1);
        if (!plain && !leaf && depth + height[i] - 1 > BVH_MAX_DEPTH && depth >= REPAIR_DEPTH) {
            if (flat_centres(&f, &own_centres)) {
                err_set(err, "bvh: out of memory repairing the depth of %u primitives", b->n);
                goto done;
            }
            uint32_t n = collect_prims(b, i, tmp, stack);
            flat_median(&f, tmp, n, slot, depth);
            continue;
        }
        flat_set_box(node, bn->box);
        flat_note_depth(&f, depth);
        if (bn->left < 0) {
            node->first = f.prim_count;
            node->count = bn->count;
            memcpy(f.prims + f.prim_count, b->perm + bn->first, bn->count * sizeof *f.prims);
            f.prim_count += node->count;
            continue;
        }
        if (leaf) { /* a collapsed subtree */
            node->first = f.prim_count;
            node->count = collect_prims(b, i, f.prims + f.prim_count, stack);
            f.prim_count += node->count;
            continue;
        }
        uint32_t c = f.node_count;
        f.node_count += 2;
        node->first = c;
        node->count = 0;
        /* push right first so the left subtree is laid out right after its parent */
        work[wp][0] = (uint32_t)bn->right, work[wp][1] = c + 1, work[wp][2] = depth + 1, wp++;
        work[wp][0] = (uint32_t)bn->left, work[wp][1] = c, work[wp][2] = depth + 1, wp++;
    }
    out->nodes = f.nodes;
    out->nodes_mem = nodes_owner.nodes_mem;
    out->node_count = f.node_count;
    out->prims = f.prims;
    out->prim_count = f.prim_count;
    out->depth = f.depth;
    f.nodes = NULL;
    f.prims = NULL;
    rc = 0;
done:
    free(order);
    free(stack);
    free(height);
    free(nprims);
    free(cost);
    free(tmp);
    free(work);
    free(own_centres);
    if (f.nodes)
        free(nodes_owner.nodes_mem);
    free(f.prims);
    return rc;
}
