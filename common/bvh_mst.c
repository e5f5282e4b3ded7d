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

#include "bvh_build.h"

typedef struct {
    uint32_t n_slots; /* power of two */
    real (*lo)[3];    /* per tree node: max over clusters of box.min */
    real (*hi)[3];    /* per tree node: min over clusters of box.max */
    uint32_t *count;  /* live clusters below the node */
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

static void mst_refit(Mst *m, uint32_t slot)
{
    uint32_t k = m->n_slots + slot;
    int32_t c = m->slot_cluster[slot];
    for (int a = 0; a < 3; a++) {
        m->lo[k][a] = c >= 0 ? m->cbox[c].min.e[a] : -REAL_INF;
        m->hi[k][a] = c >= 0 ? m->cbox[c].max.e[a] : REAL_INF;
    }
    m->count[k] = c >= 0;
    for (k >>= 1; k >= 1; k >>= 1) {
        uint32_t l = 2 * k, r = l + 1;
        for (int a = 0; a < 3; a++) {
            m->lo[k][a] = real_max(m->lo[l][a], m->lo[r][a]);
            m->hi[k][a] = real_min(m->hi[l][a], m->hi[r][a]);
        }
        m->count[k] = m->count[l] + m->count[r];
    }
}

static real union_area(Aabb a, Aabb b) { return aabb_half_area(aabb_union(a, b)); }

static real node_bound(const Mst *m, uint32_t k, Aabb q)
{
    real e[3];
    for (int a = 0; a < 3; a++)
        e[a] = real_max(q.max.e[a], m->hi[k][a]) - real_min(q.min.e[a], m->lo[k][a]);
    return e[0] * e[1] + e[1] * e[2] + e[2] * e[0];
}

/* Nearest live cluster to q (excluding q); ties go to the smaller id. */
static int32_t mst_nearest(const Mst *m, int32_t q, real *dist)
{
    Aabb qb = m->cbox[q];
    real best = REAL_INF;
    int32_t best_id = -1;
    uint32_t stack[2 * 32 + 2], sp = 0;
    stack[sp++] = 1;
    while (sp) {
        uint32_t k = stack[--sp];
        if (m->count[k] == 0 || node_bound(m, k, qb) > best)
            continue;
        if (k >= m->n_slots) {
            int32_t c = m->slot_cluster[k - m->n_slots];
            if (c == q)
                continue;
            real d = union_area(qb, m->cbox[c]);
            if (d < best || (d == best && c < best_id)) {
                best = d;
                best_id = c;
            }
            continue;
        }
        uint32_t l = 2 * k, r = l + 1;
        real bl = m->count[l] ? node_bound(m, l, qb) : REAL_INF;
        real br = m->count[r] ? node_bound(m, r, qb) : REAL_INF;
        /* visit the more promising child first: push it last */
        if (bl <= br) {
            stack[sp++] = r;
            stack[sp++] = l;
        } else {
            stack[sp++] = l;
            stack[sp++] = r;
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
    m.lo = malloc(2 * m.n_slots * sizeof *m.lo);
    m.hi = malloc(2 * m.n_slots * sizeof *m.hi);
    m.count = calloc(2 * m.n_slots, sizeof *m.count);
    m.slot_cluster = malloc(m.n_slots * sizeof *m.slot_cluster);
    m.cluster_slot = malloc(total * sizeof *m.cluster_slot);
    m.cbox = malloc(total * sizeof *m.cbox);
    Keyed *keys = malloc(n * sizeof *keys);
    int32_t *chain = malloc(n * sizeof *chain);
    int rc = -1;
    if (!m.lo || !m.hi || !m.count || !m.slot_cluster || !m.cluster_slot || !m.cbox || !keys || !chain) {
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
        uint32_t k = m.n_slots + s;
        for (int a = 0; a < 3; a++) {
            m.lo[k][a] = c >= 0 ? m.cbox[c].min.e[a] : -REAL_INF;
            m.hi[k][a] = c >= 0 ? m.cbox[c].max.e[a] : REAL_INF;
        }
        m.count[k] = c >= 0;
    }
    for (uint32_t k = m.n_slots - 1; k >= 1; k--) {
        uint32_t l = 2 * k, r = l + 1;
        for (int a = 0; a < 3; a++) {
            m.lo[k][a] = real_max(m.lo[l][a], m.lo[r][a]);
            m.hi[k][a] = real_min(m.hi[l][a], m.hi[r][a]);
        }
        m.count[k] = m.count[l] + m.count[r];
    }
    uint32_t next_id = n, seed = 0, len = 0;
    while (next_id < total) {
        if (len == 0) {
            while (m.slot_cluster[seed] < 0)
                seed++;
            chain[len++] = m.slot_cluster[seed];
        }
        int32_t c = chain[len - 1];
        real d;
        int32_t nn = mst_nearest(&m, c, &d);
        if (len >= 2) {
            int32_t prev = chain[len - 2];
            if (union_area(m.cbox[c], m.cbox[prev]) <= d)
                nn = prev; /* on a tie keep the chain's previous link: no cycles */
        }
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
    free(m.lo);
    free(m.hi);
    free(m.count);
    free(m.slot_cluster);
    free(m.cluster_slot);
    free(m.cbox);
    free(keys);
    free(chain);
    return rc;
}
