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

/* A plain tree (nothing to collapse, shallow enough to need no repair)
 * is laid out by flat_subtree, in the general loop's order: children in
 * adjacent slots, depth first, left first.  Its leaves keep their
 * builder's ranges: a top-down builder splits a range left before right,
 * so a range is also the leaf's place in leaf order, and the leaf order
 * is perm itself.
 *
 * The subtree of build node `root` goes to flat slot `slot`, its
 * descendants to the slots from *next on (2 for each interior node);
 * returns its deepest level. */
static uint32_t flat_subtree(const Builder *b, BvhNode *nodes, uint32_t root, uint32_t slot, uint32_t depth,
                             uint32_t *next)
{
    uint32_t work[BVH_MAX_DEPTH + 2][3], wp = 0, deepest = depth, c = *next; /* build node, slot, depth */
    work[wp][0] = root, work[wp][1] = slot, work[wp][2] = depth, wp++;
    while (wp) {
        wp--;
        const uint32_t i = work[wp][0], s = work[wp][1], d = work[wp][2];
        const BuildNode *bn = &b->nodes[i];
        BvhNode *node = &nodes[s];
        flat_set_box(node, bn->box);
        deepest = d > deepest ? d : deepest;
        if (bn->left < 0) {
            node->first = bn->first;
            node->count = bn->count;
            continue;
        }
        node->first = c;
        node->count = 0;
        /* a pop takes one entry and pushes two: one more a level */
        work[wp][0] = (uint32_t)bn->right, work[wp][1] = c + 1, work[wp][2] = d + 1, wp++;
        work[wp][0] = (uint32_t)bn->left, work[wp][1] = c, work[wp][2] = d + 1, wp++;
        c += 2;
    }
    *next = c;
    return deepest;
}

/* On a pool, a plain tree is cut into subtrees of at most cut_max
 * primitives, which are laid out at once: a subtree's slots follow from
 * the number of interior nodes before it in depth-first order, which a
 * pass over each subtree counts first (on the pool too).  Serial, the
 * layout was a tenth of the 1M-triangle sphere's two-thread build. */
#define CUTS_PER_THREAD 8

typedef struct {
    uint32_t node, slot, depth, next, interior, deepest;
} Cut;

typedef struct {
    const Builder *b;
    BvhNode *nodes;
    Cut *cuts;
} CutJob;

static int cut_is(const BuildNode *bn, uint32_t cut_max) { return bn->left < 0 || bn->count <= cut_max; }

static void cut_count(void *ctx, uint64_t lo, uint64_t hi, int thread)
{
    (void)thread;
    const CutJob *j = ctx;
    for (uint64_t k = lo; k < hi; k++) {
        uint32_t stack[BVH_MAX_DEPTH + 2], sp = 0, interior = 0;
        stack[sp++] = j->cuts[k].node;
        while (sp) {
            const BuildNode *bn = &j->b->nodes[stack[--sp]];
            if (bn->left >= 0) {
                interior++;
                stack[sp++] = (uint32_t)bn->right;
                stack[sp++] = (uint32_t)bn->left;
            }
        }
        j->cuts[k].interior = interior;
    }
}

static void cut_lay(void *ctx, uint64_t lo, uint64_t hi, int thread)
{
    (void)thread;
    const CutJob *j = ctx;
    for (uint64_t k = lo; k < hi; k++) {
        Cut *c = &j->cuts[k];
        uint32_t next = c->next;
        c->deepest = flat_subtree(j->b, j->nodes, c->node, c->slot, c->depth, &next);
    }
}

/* The top above the cuts, depth first as flat_subtree goes; returns the
 * number of cuts.  With `cuts` it notes each cut's build node, and with
 * `nodes` as well it lays out the top's nodes and gives each cut (whose
 * interior nodes are counted by then) its slot, its depth and the first
 * slot of its descendants. */
static uint32_t cut_top(const Builder *b, BvhNode *nodes, uint32_t cut_max, Cut *cuts, uint32_t *next)
{
    uint32_t work[BVH_MAX_DEPTH + 2][3], wp = 0, nc = 0, c = 1;
    work[wp][0] = b->root, work[wp][1] = 0, work[wp][2] = 1, wp++;
    while (wp) {
        wp--;
        const uint32_t i = work[wp][0], s = work[wp][1], d = work[wp][2];
        const BuildNode *bn = &b->nodes[i];
        if (cut_is(bn, cut_max)) {
            if (cuts && nodes) {
                cuts[nc].slot = s, cuts[nc].depth = d, cuts[nc].next = c;
                c += 2 * cuts[nc].interior;
            } else if (cuts) {
                cuts[nc].node = i;
            }
            nc++;
            continue;
        }
        if (nodes) {
            flat_set_box(&nodes[s], bn->box);
            nodes[s].first = c;
            nodes[s].count = 0;
        }
        work[wp][0] = (uint32_t)bn->right, work[wp][1] = c + 1, work[wp][2] = d + 1, wp++;
        work[wp][0] = (uint32_t)bn->left, work[wp][1] = c, work[wp][2] = d + 1, wp++;
        c += 2;
    }
    *next = c;
    return nc;
}

/* Lays out a plain tree into f, whose nodes and prims are allocated;
 * 0, or -1 when out of memory. */
static int flat_plain(const Builder *b, Flat *f)
{
    uint32_t next = 1;
    memcpy(f->prims, b->perm, b->n * sizeof *f->prims);
    f->prim_count = b->n;
    const int threads = b->pool ? pool_threads(b->pool) : 1;
    if (threads < 2) {
        f->depth = flat_subtree(b, f->nodes, b->root, 0, 1, &next);
        f->node_count = next;
        return 0;
    }
    const uint32_t cut_max = b->n / (CUTS_PER_THREAD * (uint32_t)threads);
    const uint32_t nc = cut_top(b, NULL, cut_max, NULL, &next);
    Cut *cuts = calloc(nc, sizeof *cuts);
    if (!cuts)
        return -1;
    CutJob job = {b, f->nodes, cuts};
    cut_top(b, NULL, cut_max, cuts, &next);
    pool_for(b->pool, nc, 1, cut_count, &job);
    cut_top(b, f->nodes, cut_max, cuts, &next);
    pool_for(b->pool, nc, 1, cut_lay, &job);
    f->node_count = next;
    f->depth = 1;
    for (uint32_t k = 0; k < nc; k++) /* the top's nodes lie above every cut */
        f->depth = cuts[k].deepest > f->depth ? cuts[k].deepest : f->depth;
    free(cuts);
    return 0;
}

/* The general layout's scratch arrays, by build node (and a primitive list). */
typedef struct {
    uint32_t *order, *stack, *height, *nprims, *tmp;
    double *cost;
    uint32_t (*work)[3]; /* build node, flat slot, depth */
} Scratch;

static void scratch_free(Scratch *s)
{
    free(s->order);
    free(s->stack);
    free(s->height);
    free(s->nprims);
    free(s->cost);
    free(s->tmp);
    free(s->work);
}

static int scratch_alloc(Scratch *s, uint32_t nodes, uint32_t prims)
{
    s->order = bigmem_alloc(nodes * sizeof *s->order); /* pre-order */
    s->stack = bigmem_alloc(nodes * sizeof *s->stack);
    s->height = bigmem_alloc(nodes * sizeof *s->height);
    s->nprims = bigmem_alloc(nodes * sizeof *s->nprims);
    s->cost = bigmem_alloc(nodes * sizeof *s->cost);
    s->tmp = bigmem_alloc(prims * sizeof *s->tmp);
    s->work = bigmem_alloc(nodes * sizeof *s->work);
    return s->order && s->stack && s->height && s->nprims && s->cost && s->tmp && s->work ? 0 : -1;
}

/* Every build node's height, primitives and SAH cost, children before
 * parents (pre-order, then a reverse sweep); with collapsing, a subtree
 * cheaper as one leaf becomes one (height 1). */
static void subtree_costs(const Builder *b, Scratch *s)
{
    uint32_t sp = 0, no = 0;
    s->stack[sp++] = b->root;
    while (sp) {
        uint32_t i = s->stack[--sp];
        s->order[no++] = i;
        if (b->nodes[i].left >= 0) {
            s->stack[sp++] = (uint32_t)b->nodes[i].right;
            s->stack[sp++] = (uint32_t)b->nodes[i].left;
        }
    }
    for (uint32_t k = no; k-- > 0;) {
        uint32_t i = s->order[k];
        const BuildNode *bn = &b->nodes[i];
        double area = aabb_half_area(bn->box);
        if (bn->left < 0) {
            s->height[i] = 1;
            s->nprims[i] = bn->count;
            s->cost[i] = area * bvh_leaf_blocks(bn->count);
            continue;
        }
        uint32_t l = (uint32_t)bn->left, r = (uint32_t)bn->right;
        s->height[i] = 1 + (s->height[l] > s->height[r] ? s->height[l] : s->height[r]);
        s->nprims[i] = s->nprims[l] + s->nprims[r];
        s->cost[i] = area + s->cost[l] + s->cost[r];
        if (b->collapse && s->nprims[i] <= b->opt->max_leaf && area * bvh_leaf_blocks(s->nprims[i]) <= s->cost[i]) {
            s->cost[i] = area * bvh_leaf_blocks(s->nprims[i]);
            s->height[i] = 1;
        }
    }
}

/* The general layout: depth first, each node's children side by side, a
 * subtree that would pass BVH_MAX_DEPTH rebuilt by medians below
 * REPAIR_DEPTH. */
static int flat_general(const Builder *b, Flat *f, vec3 **own_centres, Err *err)
{
    Scratch s = {0};
    int rc = -1;
    if (scratch_alloc(&s, b->node_count, b->n)) {
        err_set(err, "bvh: out of memory flattening %u nodes", b->node_count);
        goto done;
    }
    subtree_costs(b, &s);
    uint32_t wp = 0;
    f->node_count = 1;
    s.work[wp][0] = b->root, s.work[wp][1] = 0, s.work[wp][2] = 1, wp++;
    while (wp) {
        wp--;
        uint32_t i = s.work[wp][0], slot = s.work[wp][1], depth = s.work[wp][2];
        const BuildNode *bn = &b->nodes[i];
        BvhNode *node = &f->nodes[slot];
        int leaf = bn->left < 0 || (b->collapse && s.height[i] == 1);
        if (!leaf && depth + s.height[i] - 1 > BVH_MAX_DEPTH && depth >= REPAIR_DEPTH) {
            if (flat_centres(f, own_centres)) {
                err_set(err, "bvh: out of memory repairing the depth of %u primitives", b->n);
                goto done;
            }
            uint32_t n = collect_prims(b, i, s.tmp, s.stack);
            flat_median(f, s.tmp, n, slot, depth);
            continue;
        }
        flat_set_box(node, bn->box);
        flat_note_depth(f, depth);
        if (bn->left < 0) {
            node->first = f->prim_count;
            node->count = bn->count;
            memcpy(f->prims + f->prim_count, b->perm + bn->first, bn->count * sizeof *f->prims);
            f->prim_count += node->count;
            continue;
        }
        if (leaf) { /* a collapsed subtree */
            node->first = f->prim_count;
            node->count = collect_prims(b, i, f->prims + f->prim_count, s.stack);
            f->prim_count += node->count;
            continue;
        }
        uint32_t c = f->node_count;
        f->node_count += 2;
        node->first = c;
        node->count = 0;
        /* push right first so the left subtree is laid out right after its parent */
        s.work[wp][0] = (uint32_t)bn->right, s.work[wp][1] = c + 1, s.work[wp][2] = depth + 1, wp++;
        s.work[wp][0] = (uint32_t)bn->left, s.work[wp][1] = c, s.work[wp][2] = depth + 1, wp++;
    }
    rc = 0;
done:
    scratch_free(&s);
    return rc;
}

int bvh_flatten(const Builder *b, Bvh *out, Err *err)
{
    /* a tree its builder knows to be shallow enough, with nothing to
     * collapse, is laid out as it is (flat_plain): no pass for heights and
     * costs (on the 1M-triangle sphere, a tenth of the SAH build on two
     * threads), and none of their arrays */
    const int plain = !b->collapse && b->max_depth && b->max_depth <= BVH_MAX_DEPTH;
    vec3 *own_centres = NULL;
    Flat f = {b, b->centres, NULL, 0, 2 * b->n, NULL, 0, 0};
    Bvh nodes_owner = {0};
    if (bvh_alloc_nodes(&nodes_owner, f.node_cap) == 0)
        f.nodes = nodes_owner.nodes;
    f.prims = bigmem_alloc(b->n * sizeof *f.prims);
    int rc = -1;
    if (!f.nodes || !f.prims || (plain && flat_plain(b, &f)))
        err_set(err, "bvh: out of memory flattening %u nodes", b->node_count);
    else
        rc = plain ? 0 : flat_general(b, &f, &own_centres, err);
    if (rc == 0) {
        out->nodes = f.nodes;
        out->nodes_mem = nodes_owner.nodes_mem;
        out->node_count = f.node_count;
        out->prims = f.prims;
        out->prim_count = f.prim_count;
        out->depth = f.depth;
        f.nodes = NULL;
        f.prims = NULL;
    }
    free(own_centres);
    if (f.nodes)
        free(nodes_owner.nodes_mem);
    free(f.prims);
    return rc;
}
