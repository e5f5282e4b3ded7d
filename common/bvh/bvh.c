/* bvh.c - BVH entry point, validation and cost; the builders live in
 * bvh_sbt.c, bvh_mst.c and bvh_sah.c, what they share in bvh_builder.c and
 * bvh_tasks.c. */
#include "bvh/bvh.h"

#include <stdlib.h>

#include "base/bigmem.h"
#include <string.h>

#include "base/opt.h"
#include "bvh/bvh_build.h"

const char *const bvh_kind_names[BVH_KIND_COUNT + 1] = {"sbt", "mst", "sah", NULL};

const char *bvh_kind_name(BvhKind k) { return (unsigned)k < BVH_KIND_COUNT ? bvh_kind_names[k] : "?"; }

int bvh_kind_parse(const char *s, BvhKind *out)
{
    int i = opt_word_index(bvh_kind_names, BVH_KIND_COUNT, s);
    if (i >= 0)
        *out = (BvhKind)i;
    return i >= 0 ? 0 : -1;
}

BvhOptions bvh_options_default(BvhKind kind)
{
    BvhOptions o = {kind, 8, 0, 1}; /* leaves: two blocks of four (bvh.h), measured in docs/renderer.md */
    return o;
}

/* Checks every box, fills the centres (where the builder keeps them) and
 * the identity permutation; a range notes its first bad box. */
typedef struct {
    Builder *b;
    uint32_t bad[BVH_POOL_MAX];
} Prep;

static void prep_range(void *ctx, uint64_t lo, uint64_t hi, int thread)
{
    Prep *w = ctx;
    Builder *b = w->b;
    for (uint32_t i = (uint32_t)lo; i < hi; i++) {
        if (!builder_box_ok(b->boxes[i])) {
            if (i < w->bad[thread])
                w->bad[thread] = i;
            return;
        }
        if (b->centres)
            b->centres[i] = aabb_centre(b->boxes[i]);
        b->perm[i] = i;
    }
}

Pool *bvh_pool_create(uint32_t n, const BvhOptions *opt)
{
    if (opt->threads <= 1 || n < BVH_POOL_MIN)
        return NULL;
    return pool_create(opt->threads < BVH_POOL_MAX ? (int)opt->threads : BVH_POOL_MAX, NULL);
}

int bvh_build(Bvh *out, const Aabb *boxes, uint32_t n, const BvhOptions *opt, Err *err)
{
    Pool *pool = bvh_pool_create(n, opt);
    int rc = bvh_build_on(out, boxes, n, opt, pool, err);
    pool_destroy(pool);
    return rc;
}

int bvh_build_on(Bvh *out, const Aabb *boxes, uint32_t n, const BvhOptions *opt, Pool *pool, Err *err)
{
    memset(out, 0, sizeof *out);
    out->kind = opt->kind;
    if (n == 0)
        return 0;
    if (n > BVH_MAX_PRIMS)
        return err_set(err, "bvh: %u primitives exceed the limit of %u", n, BVH_MAX_PRIMS);
    if (opt->max_leaf < 1 || opt->max_leaf > 255)
        return err_set(err, "bvh: leaf size %u out of range 1..255", opt->max_leaf);
    Builder b = {0};
    b.boxes = boxes;
    b.n = n;
    b.opt = opt;
    b.pool = pool;
    const int centres = opt->kind != BVH_SAH; /* SAH keeps them in its references */
    b.centres = centres ? bigmem_alloc(n * sizeof *b.centres) : NULL;
    b.perm = bigmem_alloc(n * sizeof *b.perm);
    int rc = -1;
    if ((centres && !b.centres) || !b.perm) {
        err_set(err, "bvh: out of memory for %u primitives", n);
        goto done;
    }
    if (opt->kind != BVH_SAH) { /* SAH checks the boxes in its own first pass (bvh_sah.c) */
        Prep prep;
        prep.b = &b;
        for (int k = 0; k < BVH_POOL_MAX; k++)
            prep.bad[k] = n;
        pool_for(b.pool, n, BVH_POOL_GRAIN, prep_range, &prep);
        uint32_t bad = n;
        for (int k = 0; k < BVH_POOL_MAX; k++)
            bad = prep.bad[k] < bad ? prep.bad[k] : bad;
        if (bad < n) {
            rc = builder_bad_box(bad, err);
            goto done;
        }
    }
    switch (opt->kind) {
    case BVH_SBT: rc = bvh_build_sbt(&b, err); break;
    case BVH_SAH: rc = bvh_build_sah(&b, err); break;
    case BVH_MST: rc = bvh_build_mst(&b, err); break;
    default: rc = err_set(err, "bvh: unknown kind %d", (int)opt->kind);
    }
    if (rc == 0)
        rc = bvh_flatten(&b, out, err);
    out->kind = opt->kind;
done:
    free(b.centres);
    free(b.perm);
    free(b.nodes);
    return rc;
}

int bvh_alloc_nodes(Bvh *b, uint32_t count)
{
    size_t bytes = ((size_t)count * sizeof(BvhNode) + 64 + 63) / 64 * 64;
    uint8_t *mem = aligned_alloc(64, bytes);
    if (!mem)
        return -1;
    b->nodes_mem = mem;
    b->nodes = (BvhNode *)(mem + (sizeof(BvhNode) == 32 ? 32 : 0));
    return 0;
}

void bvh_destroy(Bvh *b)
{
    free(b->nodes_mem);
    free(b->prims);
    memset(b, 0, sizeof *b);
}

int bvh_validate(const Bvh *b, uint32_t *depth_out, Err *err)
{
    if (depth_out)
        *depth_out = 0;
    if (b->node_count == 0)
        return b->prim_count == 0 ? 0 : err_set(err, "bvh: %u primitives but no nodes", b->prim_count);
    /* children strictly after the parent and referenced once: the node graph is a tree */
    uint8_t *seen = calloc(b->node_count, 1);
    uint8_t *depth = calloc(b->node_count, 1);
    uint8_t *covered = calloc(b->prim_count ? b->prim_count : 1, 1);
    int rc = -1;
    if (!seen || !depth || !covered) {
        err_set(err, "bvh: out of memory validating %u nodes", b->node_count);
        goto done;
    }
    depth[0] = 1;
    seen[0] = 1;
    uint32_t max_depth = 1, leaf_prims = 0;
    for (uint32_t i = 0; i < b->node_count; i++) {
        const BvhNode *n = &b->nodes[i];
        if (!seen[i]) {
            err_set(err, "bvh: node %u is not reachable from the root", i);
            goto done;
        }
        for (int a = 0; a < 3; a++)
            if (!isfinite(n->bmin[a]) || !isfinite(n->bmax[a]) || !(n->bmin[a] <= n->bmax[a])) {
                err_set(err, "bvh: node %u has an invalid box", i);
                goto done;
            }
        if (n->count == 0) {
            if (n->first <= i || n->first >= b->node_count - 1) {
                err_set(err, "bvh: node %u has child index %u out of range", i, n->first);
                goto done;
            }
            for (uint32_t c = n->first; c <= n->first + 1; c++) {
                if (seen[c]) {
                    err_set(err, "bvh: node %u is the child of two parents", c);
                    goto done;
                }
                seen[c] = 1;
                if (depth[i] >= BVH_MAX_DEPTH) {
                    err_set(err, "bvh: tree deeper than %d levels", BVH_MAX_DEPTH);
                    goto done;
                }
                depth[c] = depth[i] + 1;
                if (depth[c] > max_depth)
                    max_depth = depth[c];
            }
        } else {
            if (n->first > b->prim_count || n->count > b->prim_count - n->first) {
                err_set(err, "bvh: leaf %u covers primitives %u..%u beyond %u", i, n->first,
                        n->first + n->count, b->prim_count);
                goto done;
            }
            for (uint32_t p = n->first; p < n->first + n->count; p++) {
                if (covered[p]) {
                    err_set(err, "bvh: primitive %u is in two leaves", p);
                    goto done;
                }
                covered[p] = 1;
            }
            leaf_prims += n->count;
        }
    }
    if (leaf_prims != b->prim_count) {
        err_set(err, "bvh: leaves cover %u of %u primitives", leaf_prims, b->prim_count);
        goto done;
    }
    if (b->prims)
        for (uint32_t i = 0; i < b->prim_count; i++)
            if (b->prims[i] >= b->prim_count) {
                err_set(err, "bvh: primitive reference %u out of range", b->prims[i]);
                goto done;
            }
    rc = 0;
    if (depth_out)
        *depth_out = max_depth;
done:
    free(seen);
    free(depth);
    free(covered);
    return rc;
}

double bvh_sah_cost(const Bvh *b)
{
    if (b->node_count == 0)
        return 0;
    double root = aabb_half_area(bvh_node_box(&b->nodes[0]));
    if (root <= 0)
        return 0;
    double cost = 0;
    for (uint32_t i = 0; i < b->node_count; i++) {
        double a = aabb_half_area(bvh_node_box(&b->nodes[i]));
        cost += b->nodes[i].count ? a * b->nodes[i].count : a;
    }
    return cost / root;
}
