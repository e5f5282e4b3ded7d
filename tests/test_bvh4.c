/* test_bvh4.c - the four-wide top-level tree: every leaf once, and the
 * binary walks' answers from its walks, ray by ray and in packets. */
#include "helpers.h"

#include "bvh/bvh4_walk.h"
#include "geom/intersect.h"

#include <stdlib.h>

typedef struct {
    vec3 c[400];
    real r[400];
    const uint32_t *prims;
} Balls;

static void balls_make(Balls *b, Rng *rng, uint32_t n, Bvh *tree)
{
    Aabb boxes[400];
    for (uint32_t i = 0; i < n; i++) {
        /* clusters and loners, some touching, a few large */
        b->c[i] = i % 3 ? v3_add(rng_vec(rng, -1, 1), v3((real)(i % 4) * 3, 0, 0)) : rng_vec(rng, -20, 20);
        b->r[i] = i % 17 == 0 ? rng_real(rng, 2, 5) : rng_real(rng, R(0.05), R(0.6));
        boxes[i] = (Aabb){v3_sub(b->c[i], v3_splat(b->r[i])), v3_add(b->c[i], v3_splat(b->r[i]))};
    }
    BvhOptions opt = bvh_options_default(BVH_SAH);
    opt.max_leaf = 2; /* as the scene's top level */
    assert_int_equal(bvh_build(tree, boxes, n, &opt, NULL), 0);
    b->prims = tree->prims;
}

typedef struct {
    Balls *b;
    real t;
    uint32_t hit; /* the sphere, UINT32_MAX: none */
} Near;

/* The nearest sphere, of equal distances the lowest index: the answer
 * does not depend on the order the leaves come in. */
static int near_take(Near *n, uint32_t p, real t)
{
    if (!(t < n->t || (t == n->t && p < n->hit)))
        return 0;
    n->t = t, n->hit = p;
    return 1;
}

static int leaf_closest(void *ctx, uint32_t first, uint32_t count, const Ray *r, real *tmax)
{
    Near *n = ctx;
    int found = 0;
    for (uint32_t i = 0; i < count; i++) {
        const uint32_t p = n->b->prims[first + i];
        real t;
        if (sphere_intersect(r, n->b->c[p], n->b->r[p], REAL_INF, &t) && near_take(n, p, t)) {
            *tmax = n->t;
            found = 1;
        }
    }
    return found;
}

static int leaf_any(const void *ctx, uint32_t first, uint32_t count, const Ray *r, real tmax)
{
    Balls *b = ((const Near *)ctx)->b;
    for (uint32_t i = 0; i < count; i++) {
        const uint32_t p = b->prims[first + i];
        real t;
        if (sphere_intersect(r, b->c[p], b->r[p], tmax, &t))
            return 1;
    }
    return 0;
}

typedef struct {
    Balls *b;
    const Ray *rays;
    Near *near; /* closest: one a ray; NULL: occlusion */
} PacketCtx;

static uint32_t leaf_packet(void *ctx, uint32_t prim, uint32_t rays, real *far)
{
    PacketCtx *c = ctx;
    uint32_t blocked = 0;
    for (; rays; rays &= rays - 1) {
        const int i = __builtin_ctz(rays);
        real t;
        if (!sphere_intersect(&c->rays[i], c->b->c[prim], c->b->r[prim], c->near ? REAL_INF : far[i], &t))
            continue;
        if (!c->near)
            blocked |= 1u << i;
        else if (near_take(&c->near[i], prim, t))
            far[i] = c->near[i].t;
    }
    return blocked;
}

/* Every leaf of the binary tree is a lane of exactly one node, and each
 * interior lane's box is its node's children's hull. */
static void check_structure(const Bvh *tree, const Bvh4 *t)
{
    uint32_t leaves = 0, seen = 0;
    for (uint32_t i = 0; i < tree->node_count; i++)
        leaves += tree->nodes[i].count != 0;
    char *mark = calloc(tree->prim_count, 1);
    for (uint32_t i = 0; i < t->node_count; i++) {
        const Bvh4Node *n = &t->nodes[i];
        assert_true(n->lanes != 0 && n->lanes < 16);
        for (int c = 0; c < 4; c++) {
            if (!(n->lanes >> c & 1))
                continue;
            if (n->count[c]) {
                seen++;
                for (uint32_t k = 0; k < n->count[c]; k++) {
                    assert_true(n->child[c] + k < tree->prim_count);
                    assert_int_equal(mark[n->child[c] + k], 0);
                    mark[n->child[c] + k] = 1;
                }
                continue;
            }
            assert_true(n->child[c] > i && n->child[c] < t->node_count); /* children after parents: no cycle */
            const Bvh4Node *k = &t->nodes[n->child[c]];
            for (int a = 0; a < 3; a++)
                for (int l = 0; l < 4; l++)
                    if (k->lanes >> l & 1) {
                        assert_true(k->box[a][l] >= n->box[a][c]);
                        assert_true(k->box[a + 3][l] <= n->box[a + 3][c]);
                    }
        }
    }
    assert_int_equal(seen, leaves);
    for (uint32_t p = 0; p < tree->prim_count; p++)
        assert_int_equal(mark[p], 1);
    free(mark);
}

static Ray random_ray(Rng *rng, int k)
{
    vec3 o = rng_vec(rng, -25, 25), d = rng_dir(rng);
    if (k % 7 == 0)
        d.e[k % 3] = 0; /* along a slab's plane */
    if (k % 11 == 0)
        o = rng_vec(rng, -1, 1); /* from inside the clusters */
    return ray_make(o, d, R(1e-4), REAL_INF);
}

static void walks_agree(void **state)
{
    (void)state;
    Rng rng = {0x9e3779b97f4a7c15ull};
    for (uint32_t n = 3; n <= 400; n = n * 3 + 1) {
        static Balls b;
        Bvh tree;
        balls_make(&b, &rng, n, &tree);
        Bvh4 t;
        assert_int_equal(bvh4_build(&t, &tree, NULL), 0);
        if (!BVH4_COMPILED) {
            assert_int_equal(t.node_count, 0);
            bvh_destroy(&tree);
            continue;
        }
        assert_true(t.node_count > 0); /* the root has two children at least */
        check_structure(&tree, &t);
        uint32_t hits = 0;
        for (int k = 0; k < 2000; k++) {
            Ray rays[8];
            real far_b[8], far_w[8];
            Near nb[8], nw[8];
            const int axis = k % 3;
            const vec3 from = rng_vec(&rng, -25, 25);
            for (int i = 0; i < 8; i++) {
                /* packets of neighbours (one origin, directions close), of
                 * strangers, and of rays from points near each other towards
                 * a point along an axis, the other axes' directions either
                 * side of 0 (or 0): the four-wide walk leaves those axes out */
                if (k % 4 == 3) {
                    vec3 d = v3_scale(rng_vec(&rng, -1, 1), R(0.05));
                    d.e[axis] = k % 8 == 3 ? 1 : -1;
                    if (i == 5)
                        d.e[(axis + 1) % 3] = 0;
                    rays[i] = ray_make(v3_add(from, rng_vec(&rng, -1, 1)), v3_norm(d), R(1e-4), REAL_INF);
                } else {
                    rays[i] = k % 2 ? random_ray(&rng, k + i)
                                    : ray_make(i ? rays[0].org : from,
                                               v3_norm(v3_add(i ? rays[0].dir : rng_dir(&rng), v3_scale(rng_dir(&rng), R(0.02)))),
                                               R(1e-4), REAL_INF);
                }
                far_b[i] = far_w[i] = i % 3 == 2 ? rng_real(&rng, 1, 40) : REAL_INF;
                nb[i] = nw[i] = (Near){&b, far_b[i], UINT32_MAX};
            }
            for (int i = 0; i < 8; i++) { /* one ray */
                Near x = {&b, far_b[i], UINT32_MAX}, y = x;
                real tb = far_b[i], tw = far_b[i];
                bvh_closest(&tree, &rays[i], &tb, leaf_closest, &x);
                bvh4_closest(&t, &rays[i], &tw, leaf_closest, &y);
                assert_int_equal(x.hit, y.hit);
                assert_true(x.t == y.t || x.hit == UINT32_MAX);
                hits += x.hit != UINT32_MAX;
                assert_int_equal(bvh_any(&tree, &rays[i], far_b[i], leaf_any, &x),
                                 bvh4_any(&t, &rays[i], far_b[i], leaf_any, &y));
            }
            /* a packet: the same hits as one by one, the same blocked rays */
            PacketCtx cb = {&b, rays, nb}, cw = {&b, rays, nw};
            bvh_packet(&tree, rays, 8, far_b, leaf_packet, &cb, 1);
            bvh4_packet(&t, &tree, rays, 8, far_w, k % 4 ? INFINITY : 0.0f, 0, leaf_packet, &cw);
            for (int i = 0; i < 8; i++) {
                assert_int_equal(nb[i].hit, nw[i].hit);
                assert_true(nb[i].t == nw[i].t || nb[i].hit == UINT32_MAX);
            }
            for (int i = 0; i < 8; i++)
                far_b[i] = far_w[i] = i % 2 ? rng_real(&rng, 1, 40) : REAL_INF;
            PacketCtx ob = {&b, rays, NULL}, ow = {&b, rays, NULL};
            assert_int_equal(bvh_packet(&tree, rays, 8, far_b, leaf_packet, &ob, 1),
                             bvh4_packet(&t, &tree, rays, 8, far_w, INFINITY, 1, leaf_packet, &ow));
        }
        assert_true(hits > 0);
        bvh4_destroy(&t);
        bvh_destroy(&tree);
    }
}

/* A root that is a leaf makes no four-wide tree: the binary walks serve. */
static void a_lone_leaf_makes_none(void **state)
{
    (void)state;
    Aabb box = {v3(0, 0, 0), v3(1, 1, 1)};
    BvhOptions opt = bvh_options_default(BVH_SAH);
    Bvh tree;
    assert_int_equal(bvh_build(&tree, &box, 1, &opt, NULL), 0);
    Bvh4 t;
    assert_int_equal(bvh4_build(&t, &tree, NULL), 0);
    assert_int_equal(t.node_count, 0);
    bvh4_destroy(&t);
    bvh_destroy(&tree);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(walks_agree),
        cmocka_unit_test(a_lone_leaf_makes_none),
    };
    return cmocka_run_group_tests_name("bvh4", tests, NULL, NULL);
}
