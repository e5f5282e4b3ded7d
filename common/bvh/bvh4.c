/* bvh4.c - collapsing the top level's binary tree into four-wide nodes.
 *
 * Top down, as wide_build.c does for a model: a node starts with the
 * binary node's two children and opens the interior child of the largest
 * surface area (the one a ray most likely enters) until it has four or
 * only leaves are left.  Leaves stay the binary tree's. */
#include "bvh/bvh4.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#if BVH4_COMPILED
static real node_area(const BvhNode *n)
{
    const real ex = n->bmax[0] - n->bmin[0], ey = n->bmax[1] - n->bmin[1], ez = n->bmax[2] - n->bmin[2];
    return ex * ey + ey * ez + ez * ex;
}

/* Fills wide node `at` from binary interior node `bi`; its interior
 * children get the nodes from *count on and go on the work list. */
static void collapse(Bvh4 *t, const Bvh *b, uint32_t bi, uint32_t at, uint32_t *work, uint32_t *nwork)
{
    uint32_t slot[4] = {b->nodes[bi].first, b->nodes[bi].first + 1};
    int used = 2;
    while (used < 4) {
        int best = -1;
        for (int s = 0; s < used; s++)
            if (b->nodes[slot[s]].count == 0 && (best < 0 || node_area(&b->nodes[slot[s]]) > node_area(&b->nodes[slot[best]])))
                best = s;
        if (best < 0)
            break;
        const uint32_t first = b->nodes[slot[best]].first;
        slot[best] = first;
        slot[used++] = first + 1;
    }
    Bvh4Node *n = &t->nodes[at];
    memset(n, 0, sizeof *n);
    for (int s = 0; s < 4; s++) {
        if (s >= used) { /* never entered: an empty box (and no lane bit) */
            for (int a = 0; a < 3; a++)
                n->box[a][s] = INFINITY, n->box[a + 3][s] = -INFINITY;
            continue;
        }
        const BvhNode *c = &b->nodes[slot[s]];
        for (int a = 0; a < 3; a++)
            n->box[a][s] = c->bmin[a], n->box[a + 3][s] = c->bmax[a];
        n->lanes |= (uint8_t)(1u << s);
        if (c->count) {
            n->child[s] = c->first;
            n->count[s] = (uint16_t)c->count;
        } else {
            n->child[s] = t->node_count++;
            work[2 * *nwork] = slot[s], work[2 * *nwork + 1] = n->child[s];
            ++*nwork;
        }
    }
}
#endif

int bvh4_build(Bvh4 *out, const Bvh *b, Err *err)
{
    memset(out, 0, sizeof *out);
#if BVH4_COMPILED
    if (b->node_count == 0 || b->nodes[0].count)
        return 0;
    uint32_t interior = 0;
    for (uint32_t i = 0; i < b->node_count; i++) {
        if (b->nodes[i].count > UINT16_MAX)
            return 0; /* a leaf too large for a lane's count: the binary walks serve */
        interior += b->nodes[i].count == 0;
    }
    uint32_t *work = malloc((size_t)interior * 2 * sizeof *work);
    out->nodes = aligned_alloc(64, (size_t)interior * sizeof *out->nodes);
    if (!work || !out->nodes) {
        free(work);
        free(out->nodes);
        out->nodes = NULL;
        return err_set(err, "top-level tree: out of memory for %u nodes", interior);
    }
    out->prims = b->prims;
    out->node_count = 1;
    uint32_t nwork = 1;
    work[0] = 0, work[1] = 0;
    while (nwork) { /* each binary interior node starts at most one wide node */
        --nwork;
        collapse(out, b, work[2 * nwork], work[2 * nwork + 1], work, &nwork);
    }
    free(work);
#else
    (void)b;
    (void)err;
#endif
    return 0;
}

void bvh4_destroy(Bvh4 *t)
{
    free(t->nodes);
    memset(t, 0, sizeof *t);
}
