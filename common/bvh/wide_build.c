/* wide_build.c - collapsing a binary BVH into W-wide nodes with triangle blocks.
 *
 * Top down: a wide node starts with the binary node's two children and
 * repeatedly opens the child with the largest surface area (the one a ray
 * most likely enters) until it has W children or only leaves are left.
 * The binary tree's leaves stay leaves, each as ceil(count/4) blocks, so
 * every builder's choice of leaves carries over unchanged. */
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

/* Appends the blocks of binary leaf n; returns the first block. */
static uint32_t add_leaf(Collapse *c, const BvhNode *n, uint8_t *blocks)
{
    Wide *w = c->w;
    uint32_t first = w->block_count, nb = (n->count + WIDE_TRIS - 1) / WIDE_TRIS;
    real ext = 0;
    for (int a = 0; a < 3; a++)
        ext = real_max(ext, n->bmax[a] - n->bmin[a]);
    c->leaf_size_sum += (double)ext;
    c->leaves++;
    for (uint32_t b = 0; b < nb; b++) {
        WideTris *blk = &w->tris[w->block_count++];
        for (uint32_t l = 0; l < WIDE_TRIS; l++) {
            uint32_t k = b * WIDE_TRIS + l;
            uint32_t t = n->first + (k < n->count ? k : n->count - 1);
            for (int v = 0; v < 3; v++)
                for (int a = 0; a < 3; a++)
                    blk->v[v][a][l] = (float)c->tris[t].v[v][a];
            blk->idx[l] = t;
        }
    }
    *blocks = (uint8_t)nb;
    return first;
}

int wide_build(Wide **out, const Bvh *bvh, const Tri *tris, int path, Err *err)
{
    *out = NULL;
    if (!WIDE_COMPILED || bvh->node_count == 0)
        return 0;
    int width = path == SIMD_AVX2 ? 8 : 4;
    Wide *w = calloc(1, sizeof *w);
    uint32_t blocks_cap = 0;
    for (uint32_t i = 0; i < bvh->node_count; i++)
        blocks_cap += (bvh->nodes[i].count + WIDE_TRIS - 1) / WIDE_TRIS;
    uint32_t *work = malloc(bvh->node_count * 2 * sizeof *work); /* (binary node, wide node) pairs */
    if (!w || !work) {
        free(w);
        free(work);
        return err_set(err, "wide bvh: out of memory");
    }
    w->width = width;
    w->node_bytes = width == 8 ? 256 : 128;
    size_t node_cap = bvh->node_count / 2 + 1;
    w->nodes = bigmem_alloc(node_cap * w->node_bytes);
    w->tris = bigmem_alloc((size_t)blocks_cap * sizeof(WideTris));
    if (!w->nodes || !w->tris) {
        free(work);
        wide_destroy(w);
        return err_set(err, "wide bvh: out of memory for %u nodes", bvh->node_count);
    }
#if WIDE_COMPILED
    if (path == SIMD_AVX2) {
        w->closest = wide8_closest_avx2;
        w->any = wide8_any_avx2;
        w->closest_packet = wide8_closest_packet_avx2;
        w->any_packet = wide8_any_packet_avx2;
    } else {
        w->closest = wide4_closest_sse;
        w->any = wide4_any_sse;
        w->closest_packet = wide4_closest_packet_sse;
        w->any_packet = wide4_any_packet_sse;
    }
#endif
    Collapse c = {w, bvh, tris, 0, 0};
    const BvhNode *bn = bvh->nodes;
    if (bn[0].count) {
        uint8_t nb;
        w->root = add_leaf(&c, &bn[0], &nb);
        w->root_blocks = nb;
        w->depth = 1;
        w->leaf_size = (float)(c.leaf_size_sum / c.leaves);
        free(work);
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
            if (kn->count) {
                child[k] = add_leaf(&c, kn, &blocks[k]);
            } else {
                child[k] = w->node_count++;
                blocks[k] = 0;
                work[wp++] = kids[k], work[wp++] = child[k];
            }
        }
    }
    free(work);
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
