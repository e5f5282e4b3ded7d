/* wide_build.c - collapsing a binary BVH into W-wide nodes with triangle blocks.
 *
 * Top down: a wide node starts with the binary node's two children and
 * repeatedly opens the child with the largest surface area (the one a ray
 * most likely enters) until it has W children or only leaves are left.
 * The binary tree's leaves stay leaves, each as ceil(count/4) blocks, so
 * every builder's choice of leaves carries over; only a small subtree
 * left over where a node is full becomes one leaf (WIDE_MERGE_TRIS). */
#include "bvh/wide.h"

#include <stdlib.h>
#include <string.h>

#include "base/bigmem.h"
#include "base/simd.h"

static real node_area(const BvhNode *n)
{
    real ex = n->bmax[0] - n->bmin[0], ey = n->bmax[1] - n->bmin[1], ez = n->bmax[2] - n->bmin[2];
    return ex * ey + ey * ez + ez * ex;
}

typedef struct {
    Wide *w;
    const Bvh *bvh;
    const Tri *tris;
    double leaf_size_sum;
    uint32_t leaves;
} Collapse;

static float *node_box(const Wide *w, uint32_t i) { return (float *)((char *)w->nodes + (size_t)i * w->node_bytes); }
static uint32_t *node_child(const Wide *w, uint32_t i) { return (uint32_t *)((char *)node_box(w, i) + WIDE_CHILD_OFFSET(w->width)); }
static uint8_t *node_blocks(const Wide *w, uint32_t i) { return (uint8_t *)node_box(w, i) + WIDE_BLOCKS_OFFSET(w->width); }

/* Appends the blocks of the leaf `run` (first triangle, count) that binary
 * node n (a leaf, or a merged subtree) makes; returns the first block. */
static uint32_t add_leaf(Collapse *c, const BvhNode *n, const uint32_t *run, uint8_t *blocks)
{
    Wide *w = c->w;
    const uint32_t count = run[1];
    uint32_t first = w->block_count, nb = (count + WIDE_TRIS - 1) / WIDE_TRIS;
    real ext = 0;
    for (int a = 0; a < 3; a++)
        ext = real_max(ext, n->bmax[a] - n->bmin[a]);
    c->leaf_size_sum += (double)ext;
    c->leaves++;
    for (uint32_t b = 0; b < nb; b++) {
        WideTris *blk = &w->tris[w->block_count++];
        for (uint32_t l = 0; l < WIDE_TRIS; l++) {
            uint32_t k = b * WIDE_TRIS + l;
            uint32_t t = run[0] + (k < count ? k : count - 1);
            for (int v = 0; v < 3; v++)
                for (int a = 0; a < 3; a++)
                    blk->v[v][a][l] = (float)c->tris[t].v[v][a];
            blk->idx[l] = t;
        }
    }
    *blocks = (uint8_t)nb;
    return first;
}

/* Subtrees of at most this many triangles, met where a wide node has no
 * slot left to open them, become one leaf of their triangles instead of a
 * wide node of their own.  Two binary leaves under one node otherwise made
 * a wide node of two children: 36% of the 1M-triangle sphere's 8-wide
 * nodes.  Measured (docs/renderer.md): 12 takes the sphere from 55467 nodes
 * (4.3 children each) to 37749 (5.3), 4 bytes a triangle less; frame times
 * of 0, 8, 12, 16 and 24 were within the machine's noise, and 12 costs 0.8%
 * more instructions than 0 (larger leaves), 16 1.9%. */
#ifndef WIDE_MERGE_TRIS
#define WIDE_MERGE_TRIS 12
#endif

/* Per binary node i, the leaf a subtree of at most `merge` triangles makes:
 * first triangle at sub[2i], count at sub[2i + 1]; count 0 for an interior
 * node that is not merged (larger, or its triangles not one contiguous
 * run).  Children sit after their parents, so one pass backwards sees
 * children first. */
static uint32_t *merged_leaves(const Bvh *bvh, uint32_t merge)
{
    uint32_t *sub = malloc((size_t)bvh->node_count * 2 * sizeof *sub);
    if (!sub)
        return NULL;
    for (uint32_t i = bvh->node_count; i-- > 0;) {
        const BvhNode *n = &bvh->nodes[i];
        uint32_t *me = &sub[2 * (size_t)i];
        if (n->count) {
            me[0] = n->first, me[1] = n->count;
            continue;
        }
        const uint32_t *a = &sub[2 * (size_t)n->first], *b = a + 2;
        if (a[1] && b[1] && a[1] + b[1] <= merge && (a[0] + a[1] == b[0] || b[0] + b[1] == a[0]))
            me[0] = a[0] < b[0] ? a[0] : b[0], me[1] = a[1] + b[1];
        else
            me[0] = me[1] = 0;
    }
    return sub;
}

int wide_build(Wide **out, const Bvh *bvh, const Tri *tris, int path, Err *err)
{
    *out = NULL;
    if (!WIDE_COMPILED || bvh->node_count == 0)
        return 0;
    int width = path >= SIMD_AVX2 ? 8 : 4;
    Wide *w = calloc(1, sizeof *w);
    uint32_t blocks_cap = 0;
    for (uint32_t i = 0; i < bvh->node_count; i++)
        blocks_cap += (bvh->nodes[i].count + WIDE_TRIS - 1) / WIDE_TRIS;
    uint32_t *work = malloc(bvh->node_count * 2 * sizeof *work); /* (binary node, wide node) pairs */
    uint32_t *sub = merged_leaves(bvh, WIDE_MERGE_TRIS);
    if (!w || !work || !sub) {
        free(w);
        free(work);
        free(sub);
        return err_set(err, "wide bvh: out of memory");
    }
    w->width = width;
    w->node_bytes = width == 8 ? 256 : 128;
    size_t node_cap = bvh->node_count / 2 + 1;
    w->nodes = bigmem_alloc(node_cap * w->node_bytes);
    w->tris = bigmem_alloc((size_t)blocks_cap * sizeof(WideTris));
    if (!w->nodes || !w->tris) {
        free(work);
        free(sub);
        wide_destroy(w);
        return err_set(err, "wide bvh: out of memory for %u nodes", bvh->node_count);
    }
#if WIDE_COMPILED
    if (path == SIMD_AVX512) {
        w->closest = wide8_closest_avx512;
        w->closest_pairs = wide8_closest_pairs_avx512;
        w->any = wide8_any_avx512;
        w->closest_packet = wide8_closest_packet_avx512;
        w->any_packet = wide8_any_packet_avx512;
    } else if (path == SIMD_AVX2) {
        w->closest = wide8_closest_avx2;
        w->closest_pairs = wide8_closest_pairs_avx2;
        w->any = wide8_any_avx2;
        w->closest_packet = wide8_closest_packet_avx2;
        w->any_packet = wide8_any_packet_avx2;
    } else {
        w->closest = wide4_closest_sse;
        w->closest_pairs = wide4_closest_pairs_sse;
        w->any = wide4_any_sse;
        w->closest_packet = wide4_closest_packet_sse;
        w->any_packet = wide4_any_packet_sse;
    }
#endif
    Collapse c = {w, bvh, tris, 0, 0};
    const BvhNode *bn = bvh->nodes;
    if (sub[1]) {
        uint8_t nb;
        w->root = add_leaf(&c, &bn[0], sub, &nb);
        w->root_blocks = nb;
        w->depth = 1;
        w->leaf_size = (float)(c.leaf_size_sum / c.leaves);
        free(work);
        free(sub);
        *out = w;
        return 0;
    }
    uint32_t wp = 0;
    w->node_count = 1;
    work[wp++] = 0, work[wp++] = 0;
    w->depth = bvh->depth; /* a wide path is never longer than the binary one */
    while (wp) {
        uint32_t wi = work[--wp], bi = work[--wp];
        uint32_t kids[8], n = 2;
        kids[0] = bn[bi].first, kids[1] = bn[bi].first + 1;
        while (n < (uint32_t)width) {
            int best = -1;
            real best_area = -R(1);
            for (uint32_t k = 0; k < n; k++)
                if (bn[kids[k]].count == 0 && node_area(&bn[kids[k]]) > best_area) {
                    best = (int)k;
                    best_area = node_area(&bn[kids[k]]);
                }
            if (best < 0)
                break;
            uint32_t open = kids[best];
            kids[best] = bn[open].first;
            kids[n++] = bn[open].first + 1;
        }
        float *box = node_box(w, wi);
        uint32_t *child = node_child(w, wi);
        uint8_t *blocks = node_blocks(w, wi);
        memset(box, 0, w->node_bytes);
        for (int k = 0; k < width; k++) {
            if ((uint32_t)k >= n) {
                for (int a = 0; a < 3; a++) {
                    box[a * width + k] = INFINITY;
                    box[(a + 3) * width + k] = -INFINITY;
                }
                continue;
            }
            const BvhNode *kn = &bn[kids[k]];
            for (int a = 0; a < 3; a++) {
                box[a * width + k] = (float)kn->bmin[a];
                box[(a + 3) * width + k] = (float)kn->bmax[a];
            }
            if (sub[2 * (size_t)kids[k] + 1]) {
                child[k] = add_leaf(&c, kn, &sub[2 * (size_t)kids[k]], &blocks[k]);
            } else {
                child[k] = w->node_count++;
                blocks[k] = 0;
                work[wp++] = kids[k], work[wp++] = child[k];
            }
        }
    }
    free(work);
    free(sub);
    w->leaf_size = c.leaves ? (float)(c.leaf_size_sum / c.leaves) : 0;
    *out = w;
    return 0;
}

void wide_destroy(Wide *w)
{
    if (!w)
        return;
    free(w->nodes);
    free(w->tris);
    free(w);
}

size_t wide_bytes(const Wide *w)
{
    return w ? sizeof *w + (size_t)w->node_count * w->node_bytes + (size_t)w->block_count * sizeof(WideTris) : 0;
}
