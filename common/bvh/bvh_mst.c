/* bvh_mst.c - the minimal space tree: bottom-up, always merge the pair of
 * clusters whose combined box is smallest (by surface area).
 *
 * The naive algorithm searches all pairs per merge (O(n^3), or O(n^2) with a
 * heap); here the exact same greedy tree comes from two ideas:
 *
 * 1. Nearest-neighbour chains.  d(A,B) = area(box(A u B)) is reducible:
 *    box(A u B u C) contains box(A u C) and box(B u C), so merging A and B
 *    never brings anything closer.  For reducible distances the NN-chain
 *    algorithm (follow nearest neighbours until two are mutual, merge them)
 *    produces the greedy hierarchy with O(n) nearest-neighbour queries, as
 *    Walter et al. note in "Fast Agglomerative Clustering for Rendering"
 *    (2008).  Ties are broken by cluster id so that chains cannot cycle.
 *
 * 2. A search tree for the queries.  Clusters live in slots sorted along a
 *    Morton curve; an implicit binary tree over the slots stores, for every
 *    subtree, the largest box minimum and the smallest box maximum of its
 *    clusters.  Any cluster C below a node has C.max >= that minimum and
 *    C.min <= that maximum per axis, which gives a lower bound on
 *    area(box(Q u C)) for the whole subtree; branch and bound then visits a
 *    handful of subtrees per query.  A merged cluster takes the slot of one of
 *    its halves (spatially close) and the tree is refitted along two paths. */
#include <stdlib.h>

#include "bvh/bvh_build.h"

/* Per search-tree node, in one 32-byte record (one cache line per visit):
 * lo = the largest box minimum of the clusters below, hi = the smallest box
 * maximum, per axis. */
typedef struct {
    _Alignas(4 * sizeof(real)) real lo[4];
    real hi[4];
} Bound;

typedef struct {
    uint32_t n_slots; /* power of two */
    Bound *bd;        /* per tree node */
    int32_t *slot_cluster;
    uint32_t *cluster_slot;
    Aabb *cbox;       /* cluster boxes, id < 2n-1 */
} Mst;

static uint32_t morton_spread(uint32_t x)
{
    x &= 0x3ff;
    x = (x | (x << 16)) & 0x030000ff;
    x = (x | (x << 8)) & 0x0300f00f;
    x = (x | (x << 4)) & 0x030c30c3;
    x = (x | (x << 2)) & 0x09249249;
    return x;
}

typedef struct {
    uint32_t code, id;
} Keyed;

static int keyed_cmp(const void *a, const void *b)
{
    const Keyed *x = a, *y = b;
    if (x->code != y->code)
        return x->code < y->code ? -1 : 1;
    return x->id < y->id ? -1 : (x->id > y->id);
}

static void mst_leaf(Mst *m, uint32_t k, int32_t c)
{
    for (int a = 0; a < 3; a++) {
        m->bd[k].lo[a] = c >= 0 ? m->cbox[c].min.e[a] : -REAL_INF;
        m->bd[k].hi[a] = c >= 0 ? m->cbox[c].max.e[a] : REAL_INF;
    }
    m->bd[k].lo[3] = m->bd[k].hi[3] = 0;
}

static void mst_join(Mst *m, uint32_t k)
{
    const Bound *l = &m->bd[2 * k], *r = &m->bd[2 * k + 1];
    for (int a = 0; a < 4; a++) {
        m->bd[k].lo[a] = real_max(l->lo[a], r->lo[a]);
        m->bd[k].hi[a] = real_min(l->hi[a], r->hi[a]);
    }
}

static void mst_refit(Mst *m, uint32_t slot)
{
    uint32_t k = m->n_slots + slot;
    int32_t c = m->slot_cluster[slot];
    mst_leaf(m, k, c);
    for (k >>= 1; k >= 1; k >>= 1)
        mst_join(m, k);
}

static real union_area(Aabb a, Aabb b) { return aabb_half_area(aabb_union(a, b)); }

/* A lower bound on area(box(q u C)) for every cluster C below node k:
 * C.max >= hi and C.min <= lo on each axis. */
static inline real node_bound(const Bound *n, const Bound *q)
{
    real e[4];
    for (int a = 0; a < 4; a++)
        e[a] = real_max(q->hi[a], n->hi[a]) - real_min(q->lo[a], n->lo[a]);
    return e[0] * e[1] + e[1] * e[2] + e[2] * e[0];
}

/* Nearest live cluster to q (excluding q); ties go to the smaller id.
 * Subtrees wait on the stack with their bound, dropped when a nearer
 * cluster has been found since. */
static int32_t mst_nearest(const Mst *m, int32_t q, real *dist, int32_t known)
{
    Aabb qa = m->cbox[q];
    Bound qb = {{qa.min.x, qa.min.y, qa.min.z, 0}, {qa.max.x, qa.max.y, qa.max.z, 0}};
    /* a cluster already known (the chain's previous link) bounds the search from the start */
    real best = known >= 0 ? union_area(qa, m->cbox[known]) : REAL_INF;
    int32_t best_id = known;
    struct {
        uint32_t k;
        real bound;
    } stack[2 * 32 + 2];
    uint32_t sp = 0;
    stack[sp].k = 1, stack[sp++].bound = 0;
    while (sp) {
        --sp;
        uint32_t k = stack[sp].k;
        if (stack[sp].bound > best)
            continue;
        if (k >= m->n_slots) {
            int32_t c = m->slot_cluster[k - m->n_slots];
            if (c == q || c < 0)
                continue;
            real d = union_area(qa, m->cbox[c]);
            /* best_id < 0: the first cluster found wins even at an infinite
             * area (boxes past 1e19 overflow a float's area): without it no
             * neighbour was found and the chain took -1 for a cluster */
            if (d < best || (d == best && (best_id < 0 || c < best_id))) {
                best = d;
                best_id = c;
            }
            continue;
        }
        /* an empty subtree's bound is infinite (lo -inf, hi +inf): it is
         * only ever entered before any cluster is found, and then only
         * after its live sibling, which ends in a cluster */
        uint32_t l = 2 * k, r = l + 1;
        real bl = node_bound(&m->bd[l], &qb), br = node_bound(&m->bd[r], &qb);
        /* visit the more promising child first: push it last */
        if (bl <= br) {
            if (br <= best)
                stack[sp].k = r, stack[sp++].bound = br;
            if (bl <= best)
                stack[sp].k = l, stack[sp++].bound = bl;
        } else {
            if (bl <= best)
                stack[sp].k = l, stack[sp++].bound = bl;
            if (br <= best)
                stack[sp].k = r, stack[sp++].bound = br;
        }
    }
    *dist = best;
    return best_id;
}

int bvh_build_mst(Builder *b, Err *err)
{
    uint32_t n = b->n, total = 2 * n - 1;
    Mst m = {0};
    m.n_slots = 1;
    while (m.n_slots < n)
        m.n_slots <<= 1;
    m.bd = aligned_alloc(64, 2 * (size_t)m.n_slots * sizeof *m.bd);
    m.slot_cluster = malloc(m.n_slots * sizeof *m.slot_cluster);
    m.cluster_slot = malloc(total * sizeof *m.cluster_slot);
    m.cbox = malloc(total * sizeof *m.cbox);
    Keyed *keys = malloc(n * sizeof *keys);
    int32_t *chain = malloc(n * sizeof *chain);
    int rc = -1;
    if (!m.bd || !m.slot_cluster || !m.cluster_slot || !m.cbox || !keys || !chain) {
        err_set(err, "bvh: out of memory for the MST of %u primitives", n);
        goto done;
    }
    b->nodes = malloc(total * sizeof *b->nodes);
    if (!b->nodes) {
        err_set(err, "bvh: out of memory for the MST of %u primitives", n);
        goto done;
    }
    b->node_cap = b->node_count = total;
    Aabb cb = aabb_empty();
    for (uint32_t i = 0; i < n; i++)
        aabb_grow(&cb, b->centres[i]);
    vec3 ext = aabb_extent(cb);
    for (uint32_t i = 0; i < n; i++) {
        uint32_t q[3];
        for (int a = 0; a < 3; a++) {
            real t = ext.e[a] > R(0) ? (b->centres[i].e[a] - cb.min.e[a]) / ext.e[a] : R(0);
            if (!(t >= R(0))) /* NaN from an overflowing extent */
                t = R(0);
            q[a] = (uint32_t)real_clamp(t * R(1023), R(0), R(1023));
        }
        keys[i] = (Keyed){morton_spread(q[0]) | morton_spread(q[1]) << 1 | morton_spread(q[2]) << 2, i};
        b->nodes[i] = (BuildNode){b->boxes[i], -1, -1, i, 1};
        m.cbox[i] = b->boxes[i];
    }
    qsort(keys, n, sizeof *keys, keyed_cmp);
    for (uint32_t s = 0; s < m.n_slots; s++) {
        int32_t c = s < n ? (int32_t)keys[s].id : -1;
        m.slot_cluster[s] = c;
        if (c >= 0)
            m.cluster_slot[c] = s;
        mst_leaf(&m, m.n_slots + s, c);
    }
    for (uint32_t k = m.n_slots - 1; k >= 1; k--)
        mst_join(&m, k);
    uint32_t next_id = n, seed = 0, len = 0;
    while (next_id < total) {
        if (len == 0) {
            while (m.slot_cluster[seed] < 0)
                seed++;
            chain[len++] = m.slot_cluster[seed];
        }
        int32_t c = chain[len - 1];
        real d;
        int32_t prev = len >= 2 ? chain[len - 2] : -1;
        int32_t nn = mst_nearest(&m, c, &d, prev);
        if (prev >= 0 && union_area(m.cbox[c], m.cbox[prev]) <= d)
            nn = prev; /* on a tie keep the chain's previous link: no cycles */
        if (len < 2 || nn != chain[len - 2]) {
            chain[len++] = nn;
            continue;
        }
        /* c and its predecessor are mutual nearest neighbours: merge */
        int32_t a = chain[len - 2];
        len -= 2;
        uint32_t id = next_id++;
        m.cbox[id] = aabb_union(m.cbox[a], m.cbox[c]);
        b->nodes[id] = (BuildNode){m.cbox[id], a, c, 0, 0};
        uint32_t sa = m.cluster_slot[a], sc = m.cluster_slot[c];
        m.slot_cluster[sa] = (int32_t)id;
        m.cluster_slot[id] = sa;
        m.slot_cluster[sc] = -1;
        mst_refit(&m, sa);
        mst_refit(&m, sc);
    }
    b->root = total - 1;
    b->collapse = 1;
    rc = 0;
done:
    free(m.bd);
    free(m.slot_cluster);
    free(m.cluster_slot);
    free(m.cbox);
    free(keys);
    free(chain);
    return rc;
}
