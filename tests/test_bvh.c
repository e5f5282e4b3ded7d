/* test_bvh.c - every builder: structure, enclosure, and the same answers as brute force. */
#include "helpers.h"

#include "bvh/bvh_build.h"
#include "model/model.h"
#include "base/pool.h"
#include "base/simd.h"

static void random_mesh(Mesh *m, Rng *rng, uint32_t n, int clustered)
{
    assert_int_equal(mesh_init(m, 0, NULL), 0);
    for (uint32_t i = 0; i < n; i++) {
        /* clustered: most triangles in a few dense blobs, as in scanned models */
        vec3 c = clustered && i % 10 ? v3_scale(rng_vec(rng, -1, 1), R(0.05)) : rng_vec(rng, -10, 10);
        if (clustered)
            c = v3_add(c, v3((real)(i % 3) * 4, 0, 0));
        real size = rng_real(rng, R(0.01), R(0.6));
        vec3 p[3] = {v3_add(c, v3_scale(rng_dir(rng), size)), v3_add(c, v3_scale(rng_dir(rng), size)),
                     v3_add(c, v3_scale(rng_dir(rng), size))};
        if (mesh_tri_is_degenerate(p)) {
            i--;
            continue;
        }
        assert_int_equal(mesh_add(m, p, NULL, NULL, NULL, 0, NULL), 0);
    }
}

static int box_has(const BvhNode *n, vec3 p)
{
    return p.x >= n->bmin[0] && p.y >= n->bmin[1] && p.z >= n->bmin[2] && p.x <= n->bmax[0] && p.y <= n->bmax[1] &&
           p.z <= n->bmax[2];
}

static void check_structure(const Model *m)
{
    Err err;
    uint32_t depth;
    if (bvh_validate(&m->bvh, &depth, &err))
        fail_msg("%s", err.msg);
    assert_int_equal(depth, m->bvh.depth); /* the builder reports the depth it made */
    assert_true(m->bvh.depth <= BVH_MAX_DEPTH);
    for (uint32_t i = 0; i < m->bvh.node_count; i++) {
        const BvhNode *n = &m->bvh.nodes[i];
        if (n->count) {
            for (uint32_t t = n->first; t < n->first + n->count; t++)
                for (int k = 0; k < 3; k++)
                    assert_true(box_has(n, tri_vertex(&m->tris[t], k)));
        } else {
            for (uint32_t c = n->first; c <= n->first + 1; c++) {
                const BvhNode *ch = &m->bvh.nodes[c];
                assert_true(box_has(n, v3(ch->bmin[0], ch->bmin[1], ch->bmin[2])));
                assert_true(box_has(n, v3(ch->bmax[0], ch->bmax[1], ch->bmax[2])));
            }
        }
    }
}

/* Closest hit and any hit agree with testing every triangle, on the binary
 * tree and on the wide tree of every SIMD path this machine has: the same
 * t, barycentrics and triangle (of equal t, the smallest index: wide.h). */
static SimdPath tested_path; /* the path whose wide tree check_rays walks, for messages */

/* A ray and what testing every triangle finds for it. */
typedef struct {
    Ray r;
    real best, b1, b2;
    uint32_t tri;
} Expected;

/* `rays` rays at the model and each one's brute-force answer, made once
 * for every SIMD path's walk (the model's triangles, in its order, are the
 * same for all: the brute force was most of this test's time). */
static Expected *expected_rays(const Model *m, Rng *rng, int rays)
{
    Aabb b = m->bounds;
    vec3 c = aabb_centre(b);
    real radius = v3_len(aabb_extent(b));
    Expected *ex = calloc((size_t)rays, sizeof *ex);
    assert_non_null(ex);
    for (int i = 0; i < rays; i++) {
        vec3 org = v3_add(c, v3_scale(rng_dir(rng), radius * rng_real(rng, R(0.1), R(1.5))));
        vec3 target = v3_add(c, v3_scale(rng_vec(rng, -1, 1), radius * R(0.3)));
        if (i % 2) { /* half the rays aim near a random triangle's centre */
            const Tri *t = &m->tris[rng_next(rng) % m->tri_count];
            target = v3_scale(v3_add(v3_add(tri_vertex(t, 0), tri_vertex(t, 1)), tri_vertex(t, 2)), R(1) / 3);
        }
        if (i % 7 == 3) /* and some through a vertex, shared by its neighbours */
            target = tri_vertex(&m->tris[rng_next(rng) % m->tri_count], (int)(rng_next(rng) % 3));
        Expected *e = &ex[i];
        e->r = ray_make(org, v3_sub(target, org), 0, REAL_INF);
        e->best = REAL_INF;
        for (uint32_t t = 0; t < m->tri_count; t++) {
            real tt, b1, b2;
            if (tri_solve(&e->r, &m->tris[t], &tt, &b1, &b2) && tt < e->best)
                e->best = tt, e->tri = t, e->b1 = b1, e->b2 = b2; /* ascending t: the first of equal t stays */
        }
    }
    return ex;
}

static void check_rays(const Model *m, const Expected *ex, int rays)
{
    int hits = 0;
    for (int i = 0; i < rays; i++) {
        const Expected *e = &ex[i];
        ModelHit h;
        int got = model_intersect(m, &e->r, REAL_INF, 0, &h);
        assert_int_equal(got, e->best < REAL_INF);
        if (got) {
            if (h.t != e->best || h.tri != e->tri || h.b1 != e->b1 || h.b2 != e->b2)
                fail_msg("%s: closest hit %.9g on %u, brute force %.9g on %u (ray %d)",
                         simd_name(tested_path), (double)h.t, h.tri,
                         (double)e->best, e->tri, i);
            hits++;
        }
        assert_int_equal(model_occluded(m, &e->r, REAL_INF), e->best < REAL_INF);
        assert_int_equal(model_occluded(m, &e->r, e->best * R(0.999)), 0);
    }
    assert_true(hits > rays / 4); /* the rays do reach the geometry */
}

/* Packets of 8 coherent rays (one origin, directions fanned around a
 * triangle, as a line of pixels) and of 8 scattered ones: each ray's answer
 * is the one it gets alone, hit or miss, closest or any, in the packet and
 * walked by pairs (Wide.closest_pairs). */
static void check_packets(const Model *m, Rng *rng, int packets)
{
    Aabb b = m->bounds;
    vec3 c = aabb_centre(b);
    real radius = v3_len(aabb_extent(b));
    for (int pk = 0; pk < packets; pk++) {
        Ray rays[WIDE_PACKET];
        const Ray *rp[WIDE_PACKET];
        real tmax[WIDE_PACKET], shadow[WIDE_PACKET];
        int at[WIDE_PACKET];
        vec3 org = v3_add(c, v3_scale(rng_dir(rng), radius * rng_real(rng, R(0.3), R(1.5))));
        const Tri *t = &m->tris[rng_next(rng) % m->tri_count];
        vec3 target = v3_scale(v3_add(v3_add(tri_vertex(t, 0), tri_vertex(t, 1)), tri_vertex(t, 2)), R(1) / 3);
        real spread = radius * (pk % 3 == 0 ? R(0.001) : pk % 3 == 1 ? R(0.02) : R(0.3));
        int n = 2 + (int)(rng_next(rng) % (WIDE_PACKET - 1));
        for (int i = 0; i < n; i++) {
            vec3 o = pk % 4 == 3 ? v3_add(org, v3_scale(rng_dir(rng), spread)) : org; /* shadow rays: many origins */
            vec3 d = v3_sub(v3_add(target, v3_scale(rng_vec(rng, -1, 1), spread)), o);
            if (pk % 7 == 6 && i == n / 2) /* a packet the interval test must refuse: a zero, a subnormal component */
                d.e[pk % 3] = pk % 2 ? R(0) : R(1e-40) * (d.e[pk % 3] < 0 ? -1 : 1);
            rays[i] = ray_make(o, d, 0, REAL_INF);
            if (pk % 11 == 10 && i == n - 1) /* a degenerate camera's ray: hits nothing, in a packet or a pair */
                rays[i].org.x = (real)NAN;
            rp[i] = &rays[i];
            tmax[i] = pk % 5 == 4 ? radius * rng_real(rng, R(0.2), R(2)) : REAL_INF;
            at[i] = (int)(rng_next(rng) % 2);
        }
        ModelHit hits[WIDE_PACKET], each[WIDE_PACKET];
        uint32_t found = model_intersect_packet(m, rp, n, tmax, at, hits);
        /* the wide tree's rays alone by pairs (the scalar path: alone) */
        uint32_t tie[WIDE_PACKET];
        for (int i = 0; i < n; i++)
            tie[i] = at[i] ? UINT32_MAX : 0;
        uint32_t found_each = m->wide ? m->wide->closest_pairs(m->wide, rp, n, tmax, tie, each)
                                      : model_intersect_each(m, rp, n, tmax, at, each);
        for (int i = 0; i < n; i++) {
            ModelHit h;
            int got = model_intersect(m, &rays[i], tmax[i], at[i], &h);
            assert_int_equal((int)(found >> i & 1), got);
            assert_int_equal((int)(found_each >> i & 1), got);
            if (got && (h.t != hits[i].t || h.tri != hits[i].tri || h.b1 != hits[i].b1 || h.b2 != hits[i].b2))
                fail_msg("packet %d ray %d: %.9g on %u, alone %.9g on %u", pk, i, (double)hits[i].t, hits[i].tri,
                         (double)h.t, h.tri);
            if (got && (h.t != each[i].t || h.tri != each[i].tri || h.b1 != each[i].b1 || h.b2 != each[i].b2))
                fail_msg("pair walk %d ray %d: %.9g on %u, alone %.9g on %u", pk, i, (double)each[i].t, each[i].tri,
                         (double)h.t, h.tri);
            shadow[i] = got && pk % 2 ? h.t * R(0.999) : tmax[i];
        }
        uint32_t blocked = model_occluded_packet(m, rp, n, shadow);
        for (int i = 0; i < n; i++)
            assert_int_equal((int)(blocked >> i & 1), model_occluded(m, &rays[i], shadow[i]));
    }
}

static void check_against_brute_force(Model *m, Rng *rng, int rays)
{
    Expected *ex = expected_rays(m, rng, rays);
    Rng start = *rng;
    for (int p = 0; p < SIMD_PATH_COUNT; p++) {
        if (!simd_available((SimdPath)p))
            continue;
        Err err;
        if (p != SIMD_SCALAR && wide_build(&m->wide, &m->bvh, m->tris, p, &err))
            fail_msg("wide bvh: %s", err.msg);
        if (p != SIMD_SCALAR && WIDE_COMPILED)
            assert_non_null(m->wide);
        *rng = start; /* every path sees the same packets */
        tested_path = (SimdPath)p;
        check_rays(m, ex, rays);
        check_packets(m, rng, rays / 4);
        wide_destroy(m->wide);
        m->wide = NULL;
    }
    free(ex);
}

static void each_builder(Mesh *mesh, Rng *rng, int rays)
{
    for (int k = 0; k < BVH_KIND_COUNT; k++)
        for (int alt = 0; alt < (k == BVH_SBT ? 2 : 1); alt++) {
            BvhOptions opt = bvh_options_default((BvhKind)k);
            opt.sbt_alternate = alt;
            Model *m;
            Err err;
            if (model_from_mesh(&m, mesh, &opt, &err))
                fail_msg("%s: %s", bvh_kind_name((BvhKind)k), err.msg);
            assert_int_equal(m->tri_count, mesh->tri_count);
            check_structure(m);
            check_against_brute_force(m, rng, rays);
            model_destroy(m);
        }
}

static void builders_on_random_triangles(void **state)
{
    (void)state;
    Rng rng = {4242};
    Mesh mesh;
    /* the rays against brute force: a third of them under a sanitizer (17 s of ASan's pass) */
    const int rays = TEST_SANITIZED ? 1000 : 3000;
    random_mesh(&mesh, &rng, 3000, 0);
    each_builder(&mesh, &rng, rays);
    mesh_free(&mesh);
    random_mesh(&mesh, &rng, 3000, 1);
    each_builder(&mesh, &rng, rays);
    mesh_free(&mesh);
}

/* Builders on several threads make the very tree they make on one: the
 * subtrees are handed out by timing, the layout comes from the shape alone. */
static void count_range(void *ctx, uint64_t lo, uint64_t hi, int thread)
{
    uint8_t *seen = ctx;
    assert_true(thread >= 0 && thread < 3);
    for (uint64_t i = lo; i < hi; i++)
        seen[i]++;
}

static void threads_do_not_change_the_tree(void **state)
{
    (void)state;
    Rng rng = {99};
    /* big enough for subtrees to change hands (bvh_tasks.c), and, but for
     * the MST (slow here, and bottom-up: no pool passes of its own), for the
     * passes over every primitive to run on a pool (BVH_POOL_MIN) */
    Mesh small, big;
    random_mesh(&small, &rng, 20000, 1);
    random_mesh(&big, &rng, BVH_POOL_MIN + 4000, 1);
    for (int k = 0; k < BVH_KIND_COUNT; k++) {
        const Mesh *mesh = k == BVH_MST ? &small : &big;
        Model *one = NULL, *many = NULL;
        BvhOptions opt = bvh_options_default((BvhKind)k);
        assert_int_equal(model_from_mesh(&one, mesh, &opt, NULL), 0);
        opt.threads = 4;
        assert_int_equal(model_from_mesh(&many, mesh, &opt, NULL), 0);
        assert_int_equal(one->bvh.node_count, many->bvh.node_count);
        assert_int_equal(one->bvh.depth, many->bvh.depth);
        for (uint32_t i = 0; i < one->bvh.node_count; i++) { /* field by field: a double build's nodes have padding */
            const BvhNode *a = &one->bvh.nodes[i], *c = &many->bvh.nodes[i];
            assert_memory_equal(a->bmin, c->bmin, sizeof a->bmin);
            assert_memory_equal(a->bmax, c->bmax, sizeof a->bmax);
            assert_int_equal(a->first, c->first);
            assert_int_equal(a->count, c->count);
        }
        assert_memory_equal(one->tris, many->tris, one->tri_count * sizeof(Tri));
        assert_memory_equal(one->bounds.min.e, many->bounds.min.e, 3 * sizeof(real));
        assert_memory_equal(one->bounds.max.e, many->bounds.max.e, 3 * sizeof(real));
        model_destroy(one);
        model_destroy(many);
    }
    mesh_free(&small);
    mesh_free(&big);
}

/* The passes over every primitive run on a pool: each index once, on any
 * thread count and grain; a bad box is named by its first index whichever
 * thread finds it. */
static void pool_passes_cover_every_primitive(void **state)
{
    (void)state;
    enum { N = 100003 };
    static uint8_t seen[N];
    for (int threads = 1; threads <= 3; threads++) {
        Pool *p = pool_create(threads, NULL);
        for (uint64_t grain = 1; grain <= 2 * N; grain *= 7) {
            memset(seen, 0, sizeof seen);
            pool_for(p, N, grain, count_range, seen);
            for (uint32_t i = 0; i < N; i++)
                assert_int_equal(seen[i], 1);
        }
        pool_destroy(p);
    }
    pool_for(NULL, 5, 1, count_range, seen); /* no pool: the caller */
    Aabb *boxes = malloc(N * sizeof *boxes);
    for (uint32_t i = 0; i < N; i++)
        boxes[i] = (Aabb){v3((real)i, 0, 0), v3((real)i + 1, 1, 1)};
    boxes[90000].max.y = REAL_INF;
    boxes[70001] = aabb_empty();
    /* every builder: SAH checks the boxes in its own pass, the others before building */
    for (int k = 0; k < BVH_KIND_COUNT; k++)
        for (uint32_t threads = 1; threads <= 4; threads += 3) {
            BvhOptions opt = bvh_options_default((BvhKind)k);
            opt.threads = threads;
            Bvh bvh;
            Err err;
            assert_int_equal(bvh_build(&bvh, boxes, N, &opt, &err), -1);
            assert_string_equal(err.msg, "bvh: primitive 70001 has an empty or non-finite box");
        }
    free(boxes);
}

static void builders_on_tiny_and_coincident_input(void **state)
{
    (void)state;
    Rng rng = {7};
    for (uint32_t n = 1; n <= 9; n++) {
        Mesh mesh;
        random_mesh(&mesh, &rng, n, 0);
        each_builder(&mesh, &rng, 200);
        mesh_free(&mesh);
    }
    /* 500 copies of one triangle: centres coincide, splits must fall back to counts */
    Mesh mesh;
    assert_int_equal(mesh_init(&mesh, 0, NULL), 0);
    vec3 p[3] = {v3(0, 0, 0), v3(1, 0, 0), v3(0, 1, 0)};
    for (int i = 0; i < 500; i++)
        assert_int_equal(mesh_add(&mesh, p, NULL, NULL, NULL, 0, NULL), 0);
    each_builder(&mesh, &rng, 200);
    mesh_free(&mesh);
}

/* Triangles at x = 2^-k: a spatial median peels off one per level, which
 * would make a 2000-deep chain.  The depth repair keeps it within the limit. */
static void depth_is_bounded_on_adversarial_input(void **state)
{
    (void)state;
    Mesh mesh;
    assert_int_equal(mesh_init(&mesh, 0, NULL), 0);
    real x = 1;
    for (int i = 0; i < 120; i++, x *= R(0.5)) {
        vec3 p[3] = {v3(x, 0, 0), v3(x, 1, 0), v3(x, 0, 1)};
        assert_int_equal(mesh_add(&mesh, p, NULL, NULL, NULL, 0, NULL), 0);
    }
    /* nested triangles from 1e17 growing by 3%: a chain for every builder,
     * and areas past the float range (3.7e19 squared), where SAH costs and
     * the MST's merge areas are infinite (the MST took -1 for a cluster and
     * the SAH sweep an axis of -1 before) */
    Mesh nested;
    assert_int_equal(mesh_init(&nested, 0, NULL), 0);
    real s = R(1e17);
    for (int i = 0; i < 200; i++, s *= R(1.03)) {
        vec3 p[3] = {v3(0, 0, 0), v3(s, 0, 0), v3(0, s, R(0.001) * s)};
        assert_int_equal(mesh_add(&nested, p, NULL, NULL, NULL, 0, NULL), 0);
    }
    Rng rng = {5};
    for (int k = 0; k < BVH_KIND_COUNT; k++)
        for (int which = 0; which < 2; which++) {
            BvhOptions opt = bvh_options_default((BvhKind)k);
            opt.max_leaf = 1;
            Model *m;
            assert_int_equal(model_from_mesh(&m, which ? &nested : &mesh, &opt, NULL), 0);
            check_structure(m);
            if (!which) /* past 1e19 a float triangle test overflows: the trees, not the rays */
                check_against_brute_force(m, &rng, 500);
            model_destroy(m);
        }
    mesh_free(&mesh);
    mesh_free(&nested);
}

/* The layout repairs a chain deeper than BVH_MAX_DEPTH by object median
 * (bvh_flatten.c); a SAH build keeps no centres, so the repair makes its
 * own.  SAH trees are hardly ever that deep, so the chain is made here. */
static void a_deep_tree_without_centres_is_repaired(void **state)
{
    (void)state;
    enum { N = 100 };
    Aabb boxes[N];
    uint32_t perm[N];
    BuildNode nodes[2 * N - 1];
    for (uint32_t i = 0; i < N; i++) {
        boxes[i] = (Aabb){v3((real)i, 0, 0), v3((real)i + 1, 1, 1)};
        perm[i] = i;
        nodes[i] = (BuildNode){boxes[i], -1, -1, i, 1};
    }
    for (int k = N - 2; k >= 0; k--) { /* node N + k: leaf k beside the rest of the chain */
        int32_t right = k == N - 2 ? N - 1 : N + k + 1;
        nodes[N + k] = (BuildNode){aabb_union(boxes[k], nodes[right].box), k, right, 0, 0};
    }
    BvhOptions opt = bvh_options_default(BVH_SAH);
    opt.max_leaf = 1;
    Builder b = {.boxes = boxes, .centres = NULL, .n = N, .perm = perm, .nodes = nodes, .node_count = 2 * N - 1,
                 .node_cap = 2 * N - 1, .root = N, .opt = &opt, .collapse = 0, .max_depth = N};
    Bvh bvh;
    Err err;
    if (bvh_flatten(&b, &bvh, &err))
        fail_msg("%s", err.msg);
    uint32_t depth;
    if (bvh_validate(&bvh, &depth, &err))
        fail_msg("%s", err.msg);
    assert_true(bvh.depth <= BVH_MAX_DEPTH && depth == bvh.depth);
    uint8_t seen[N] = {0};
    assert_int_equal(bvh.prim_count, N);
    for (uint32_t i = 0; i < N; i++)
        seen[bvh.prims[i]]++;
    for (uint32_t i = 0; i < N; i++)
        assert_int_equal(seen[i], 1);
    bvh_destroy(&bvh);
}

static int cmp_real(const void *a, const void *b)
{
    real x = *(const real *)a, y = *(const real *)b;
    return x < y ? -1 : x > y;
}

/* The MST must equal the naive greedy algorithm: repeatedly merge the pair
 * whose union box has the smallest area.  Compare the areas of all clusters. */
static void mst_equals_naive_greedy(void **state)
{
    (void)state;
    Rng rng = {31337};
    enum { N = 80 };
    for (int round = 0; round < 5; round++) {
        Aabb box[N];
        int alive[N];
        for (int i = 0; i < N; i++) {
            vec3 c = rng_vec(&rng, -10, 10), e = rng_vec(&rng, R(0.01), 2);
            box[i] = (Aabb){v3_sub(c, e), v3_add(c, e)};
            alive[i] = 1;
        }
        Bvh bvh;
        BvhOptions opt = bvh_options_default(BVH_MST);
        opt.max_leaf = 1;
        assert_int_equal(bvh_build(&bvh, box, N, &opt, NULL), 0);
        real naive[N - 1], ours[N - 1];
        Aabb work[N];
        memcpy(work, box, sizeof work);
        for (int m = 0; m < N - 1; m++) {
            real best = REAL_INF;
            int bi = -1, bj = -1;
            for (int i = 0; i < N; i++)
                for (int j = i + 1; j < N; j++)
                    if (alive[i] && alive[j]) {
                        real a = aabb_half_area(aabb_union(work[i], work[j]));
                        if (a < best)
                            best = a, bi = i, bj = j;
                    }
            work[bi] = aabb_union(work[bi], work[bj]);
            alive[bj] = 0;
            naive[m] = best;
        }
        int k = 0;
        for (uint32_t i = 0; i < bvh.node_count; i++)
            if (bvh.nodes[i].count == 0)
                ours[k++] = aabb_half_area(bvh_node_box(&bvh.nodes[i]));
        assert_int_equal(k, N - 1);
        qsort(naive, N - 1, sizeof *naive, cmp_real);
        qsort(ours, N - 1, sizeof *ours, cmp_real);
        for (int i = 0; i < N - 1; i++)
            assert_float_equal(ours[i], naive[i], (R(1e-4) * naive[i]));
        bvh_destroy(&bvh);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(builders_on_random_triangles),
        cmocka_unit_test(threads_do_not_change_the_tree),
        cmocka_unit_test(pool_passes_cover_every_primitive),
        cmocka_unit_test(builders_on_tiny_and_coincident_input),
        cmocka_unit_test(depth_is_bounded_on_adversarial_input),
        cmocka_unit_test(a_deep_tree_without_centres_is_repaired),
        cmocka_unit_test(mst_equals_naive_greedy),
    };
    return cmocka_run_group_tests_name("bvh", tests, NULL, NULL);
}
