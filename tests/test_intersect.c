/* test_intersect.c - every intersection routine against analytic answers. */
#include "helpers.h"

#include "bvh/bvh.h"
#include "geom/intersect.h"

static const real EPS = R(1e-5);

static void sphere_from_outside(void **state)
{
    (void)state;
    Ray r = ray_make(v3(0, 0, 10), v3(0, 0, -1), 0, REAL_INF);
    real t;
    assert_true(sphere_intersect(&r, v3(0, 0, 0), 2, REAL_INF, &t));
    assert_float_equal(t, 8, EPS);
    /* off-centre: x = 1 hits where z = sqrt(3) */
    r = ray_make(v3(1, 0, 10), v3(0, 0, -1), 0, REAL_INF);
    assert_true(sphere_intersect(&r, v3(0, 0, 0), 2, REAL_INF, &t));
    assert_float_equal(t, 10 - sqrt(R(3)), EPS);
    /* unnormalised direction: t scales inversely */
    r = ray_make(v3(0, 0, 10), v3(0, 0, -2), 0, REAL_INF);
    assert_true(sphere_intersect(&r, v3(0, 0, 0), 2, REAL_INF, &t));
    assert_float_equal(t, 4, EPS);
}

static void sphere_from_inside_and_misses(void **state)
{
    (void)state;
    real t;
    Ray r = ray_make(v3(0, 0, 0), v3(1, 0, 0), 0, REAL_INF);
    assert_true(sphere_intersect(&r, v3(0, 0, 0), 3, REAL_INF, &t));
    assert_float_equal(t, 3, EPS);
    r = ray_make(v3(0, 5, 10), v3(0, 0, -1), 0, REAL_INF); /* passes above */
    assert_false(sphere_intersect(&r, v3(0, 0, 0), 2, REAL_INF, &t));
    r = ray_make(v3(0, 0, 10), v3(0, 0, 1), 0, REAL_INF); /* sphere behind */
    assert_false(sphere_intersect(&r, v3(0, 0, 0), 2, REAL_INF, &t));
    r = ray_make(v3(0, 0, 10), v3(0, 0, -1), 0, 5); /* beyond tmax */
    assert_false(sphere_intersect(&r, v3(0, 0, 0), 2, R(5), &t));
    /* far away, tiny sphere: the careful discriminant still finds it */
    r = ray_make(v3(0, 0, 0), v3(0, 0, -1), 0, REAL_INF);
    assert_true(sphere_intersect(&r, v3(0, 0, -10000), R(0.01), REAL_INF, &t));
    assert_float_equal(t / R(10000), 1, R(1e-5));
}

static void plane_hits_and_parallel(void **state)
{
    (void)state;
    real t;
    Ray r = ray_make(v3(0, 5, 0), v3(0, -1, 0), 0, REAL_INF);
    assert_true(plane_intersect(&r, v3(0, 1, 0), v3(0, 1, 0), REAL_INF, &t));
    assert_float_equal(t, 4, EPS);
    r = ray_make(v3(0, 5, 0), v3(1, -1, 0), 0, REAL_INF);
    assert_true(plane_intersect(&r, v3(0, 0, 0), v3(0, 1, 0), REAL_INF, &t));
    assert_float_equal(t, 5, EPS);
    r = ray_make(v3(0, 5, 0), v3(1, 0, 0), 0, REAL_INF); /* parallel */
    assert_false(plane_intersect(&r, v3(0, 0, 0), v3(0, 1, 0), REAL_INF, &t));
    r = ray_make(v3(0, 0, 0), v3(1, 0, 0), 0, REAL_INF); /* parallel, inside the plane */
    assert_false(plane_intersect(&r, v3(0, 0, 0), v3(0, 1, 0), REAL_INF, &t));
    r = ray_make(v3(0, 5, 0), v3(0, 1, 0), 0, REAL_INF); /* pointing away */
    assert_false(plane_intersect(&r, v3(0, 0, 0), v3(0, 1, 0), REAL_INF, &t));
}

static Tri tri_of(vec3 a, vec3 b, vec3 c)
{
    Tri t;
    for (int k = 0; k < 3; k++) {
        t.v[0][k] = a.e[k];
        t.v[1][k] = b.e[k];
        t.v[2][k] = c.e[k];
    }
    return t;
}

static void triangle_barycentrics(void **state)
{
    (void)state;
    Tri tri = tri_of(v3(0, 0, 0), v3(4, 0, 0), v3(0, 4, 0));
    real t, b1, b2;
    Ray r = ray_make(v3(1, 2, 5), v3(0, 0, -1), 0, REAL_INF);
    assert_true(tri_intersect(&r, &tri, REAL_INF, &t, &b1, &b2));
    assert_float_equal(t, 5, EPS);
    assert_float_equal(b1, R(0.25), EPS); /* weight of (4,0,0) is x/4 */
    assert_float_equal(b2, R(0.5), EPS);  /* weight of (0,4,0) is y/4 */
    /* from behind: triangles are two-sided */
    r = ray_make(v3(1, 1, -5), v3(0, 0, 1), 0, REAL_INF);
    assert_true(tri_intersect(&r, &tri, REAL_INF, &t, &b1, &b2));
    assert_float_equal(t, 5, EPS);
    /* oblique ray in a dominant-x direction */
    r = ray_make(v3(-3, 1, 1), v3(1, 0, R(-0.25)), 0, REAL_INF);
    assert_true(tri_intersect(&r, &tri, REAL_INF, &t, &b1, &b2));
    assert_float_equal(t, 4, EPS);
    assert_float_equal(b1, R(0.25), EPS);
    /* misses: outside the edge, behind the origin, beyond tmax */
    r = ray_make(v3(3, 3, 5), v3(0, 0, -1), 0, REAL_INF);
    assert_false(tri_intersect(&r, &tri, REAL_INF, &t, &b1, &b2));
    r = ray_make(v3(1, 1, 5), v3(0, 0, 1), 0, REAL_INF);
    assert_false(tri_intersect(&r, &tri, REAL_INF, &t, &b1, &b2));
    r = ray_make(v3(1, 1, 5), v3(0, 0, -1), 0, REAL_INF);
    assert_false(tri_intersect(&r, &tri, R(4.9), &t, &b1, &b2));
    /* parallel to the triangle's plane */
    r = ray_make(v3(-1, 1, 0), v3(1, 0, 0), 0, REAL_INF);
    assert_false(tri_intersect(&r, &tri, REAL_INF, &t, &b1, &b2));
}

static int hits_any(const Ray *r, const Tri *tris, int n)
{
    for (int k = 0; k < n; k++) {
        real t, b1, b2;
        if (tri_intersect(r, &tris[k], REAL_INF, &t, &b1, &b2))
            return 1;
    }
    return 0;
}

/* A planar fan: rays from every direction aimed at its shared edges and its
 * centre vertex must hit at least one triangle (the watertightness
 * guarantee).  In the plane z = 0 rounding of the aim point stays in the
 * plane, so a miss can only be a crack between triangles. */
static void triangle_fan_edges_are_watertight(void **state)
{
    (void)state;
    Rng rng = {12345};
    vec3 centre = v3(R(0.3), R(-0.2), 0);
    vec3 rim[8]; /* computed once: neighbours share bit-identical edges, as in a mesh */
    for (int i = 0; i < 8; i++) {
        real a = R(2) * REAL_PI * (real)i / 8;
        rim[i] = v3(cos(a) * R(3), sin(a) * R(3), 0);
    }
    Tri fan[8];
    for (int i = 0; i < 8; i++)
        fan[i] = tri_of(centre, rim[i], rim[(i + 1) % 8]);
    int misses = 0;
    for (int n = 0; n < 50000; n++) {
        int i = (int)(rng_next(&rng) % 8);
        real s = n % 10 == 0 ? 0 : rng_real(&rng, 0, R(0.999)); /* not the rim itself: that is the border */
        vec3 target = v3_lerp(centre, rim[i], s);
        vec3 org = v3_add(target, v3_scale(rng_dir(&rng), 10));
        Ray r = ray_make(org, v3_sub(target, org), 0, REAL_INF);
        misses += !hits_any(&r, fan, 8);
    }
    assert_int_equal(misses, 0);
}

/* A closed, non-planar mesh (octahedron |x|+|y|+|z| = 2): integer ray origins
 * aimed exactly at points of its edges (dyadic fractions, exactly
 * representable) and at its vertices.  A ray that enters the solid there must
 * register a hit: that is what a leak would break.  Rays that only graze (touch
 * an edge or vertex and stay outside) are not leaks and are left out; the
 * entering test is exact, since all numbers involved are dyadic. */
static void octahedron_edges_and_vertices_do_not_leak(void **state)
{
    (void)state;
    const vec3 v[6] = {v3(2, 0, 0), v3(-2, 0, 0), v3(0, 2, 0), v3(0, -2, 0), v3(0, 0, 2), v3(0, 0, -2)};
    Tri oct[8];
    int k = 0;
    for (int a = 0; a < 2; a++)
        for (int b = 2; b < 4; b++)
            for (int c = 4; c < 6; c++)
                oct[k++] = tri_of(v[a], v[b], v[c]);
    Rng rng = {777};
    int misses = 0, rays = 0;
    for (int a = 0; a < 6; a++)
        for (int b = a + 1; b < 6; b++) {
            if ((a ^ b) == 1) /* opposite vertices: not an edge */
                continue;
            for (int step = 0; step <= 16; step++) {
                vec3 target = v3_add(v[a], v3_scale(v3_sub(v[b], v[a]), (real)step / 16));
                for (int n = 0; n < 400; n++) {
                    vec3 org;
                    do
                        org = v3((real)(int)rng_real(&rng, -20, 20), (real)(int)rng_real(&rng, -20, 20),
                                 (real)(int)rng_real(&rng, -20, 20));
                    while (fabs(org.x) + fabs(org.y) + fabs(org.z) <= 2);
                    double q[3], l1 = 0;
                    for (int c = 0; c < 3; c++) {
                        q[c] = (double)target.e[c] + ((double)target.e[c] - (double)org.e[c]) / 1024.0;
                        l1 += fabs(q[c]);
                    }
                    if (!(l1 < 2.0)) /* grazing: the ray does not enter the solid at the target */
                        continue;
                    Ray r = ray_make(org, v3_sub(target, org), 0, REAL_INF);
                    misses += !hits_any(&r, oct, 8);
                    rays++;
                }
            }
        }
    assert_true(rays > 12 * 17 * 400 / 5); /* about 22% enter (18191 here): the test has teeth */
    assert_int_equal(misses, 0);
}

static void slab_test(void **state)
{
    (void)state;
    BvhNode n = {{-1, -1, -1}, 0, {1, 1, 1}, 1};
    real tn;
    Ray r = ray_make(v3(-5, 0, 0), v3(1, 0, 0), 0, REAL_INF);
    assert_true(bvh_node_hit(&n, &r, REAL_INF, &tn));
    assert_float_equal(tn, 4, EPS);
    r = ray_make(v3(-5, 2, 0), v3(1, 0, 0), 0, REAL_INF); /* parallel to x, outside in y */
    assert_false(bvh_node_hit(&n, &r, REAL_INF, &tn));
    r = ray_make(v3(0, 0, 0), v3(0, 1, 0), 0, REAL_INF); /* starting inside */
    assert_true(bvh_node_hit(&n, &r, REAL_INF, &tn));
    assert_float_equal(tn, 0, EPS);
    r = ray_make(v3(-5, 0, 0), v3(-1, 0, 0), 0, REAL_INF); /* pointing away */
    assert_false(bvh_node_hit(&n, &r, REAL_INF, &tn));
    r = ray_make(v3(-5, 0, 0), v3(1, 0, 0), 0, REAL_INF);
    assert_false(bvh_node_hit(&n, &r, R(3), &tn)); /* box starts beyond tmax */
    /* grazing the face y = 1 exactly: conservative, so it counts as a hit */
    r = ray_make(v3(-5, 1, 0), v3(1, 0, 0), 0, REAL_INF);
    assert_true(bvh_node_hit(&n, &r, REAL_INF, &tn));
    /* a flat box (zero thickness) is still hit */
    BvhNode flat = {{-1, 0, -1}, 0, {1, 0, 1}, 1};
    r = ray_make(v3(0, 5, 0), v3(0, -1, 0), 0, REAL_INF);
    assert_true(bvh_node_hit(&flat, &r, REAL_INF, &tn));
    assert_float_equal(tn, 5, EPS);
}

/* real_next_up/down (the shadow rays' origins) are libm's nextafter, bit
 * for bit, at zeros, subnormals, powers of two, the largest values and
 * infinities, and over a sweep of bit patterns of both signs. */
static void next_up_and_down_are_nextafter(void **state)
{
    (void)state;
    const real special[] = {R(0), -R(0), REAL_MAX, -REAL_MAX, REAL_INF, -REAL_INF, R(1), -R(1), REAL_EPS,
                            R(1e-40), -R(1e-40), R(1e30), R(-3.5), R(0.1)};
    int checked = 0;
    for (size_t i = 0; i < sizeof special / sizeof special[0]; i++) {
        real x = special[i], up = nextafter(x, REAL_INF), down = nextafter(x, -REAL_INF);
        real a = real_next_up(x), b = real_next_down(x);
        assert_memory_equal(&a, &up, sizeof a);
        assert_memory_equal(&b, &down, sizeof b);
        checked++;
    }
    for (uint32_t k = 0; k < 200000; k++) {
        uint64_t bits = (uint64_t)k * 0x9E3779B97F4A7C15ull;
        real x;
        memcpy(&x, &bits, sizeof x); /* the low bytes: any pattern, either sign */
        if (isnan(x))
            continue;
        real up = nextafter(x, REAL_INF), down = nextafter(x, -REAL_INF), a = real_next_up(x), b = real_next_down(x);
        assert_memory_equal(&a, &up, sizeof a);
        assert_memory_equal(&b, &down, sizeof b);
        checked++;
    }
    assert_true(checked > 100000);
    real n = NAN;
    assert_true(isnan(real_next_up(n)) && isnan(real_next_down(n)));
}

/* A face normal of any size normalises: the cross product of edges of a
 * model measured in units 1e10 too small has a square past a float's
 * range, of one 1e-12 too large one under it (v3_norm gave infinities and
 * zeros there, and the model's shading went wrong); within the range the
 * very bits of v3_norm. */
static void normals_of_any_size_normalise(void **state)
{
    (void)state;
    const real big[] = {R(1e20), R(1e30), R(1e-20), R(1e-30)};
    for (size_t i = 0; i < sizeof big / sizeof big[0]; i++) {
        const vec3 n = v3_norm_any(v3(big[i], 0, big[i]));
        assert_float_equal(n.x, R(0.70710678), R(1e-6));
        assert_float_equal(n.y, R(0), R(0));
        assert_float_equal(n.z, R(0.70710678), R(1e-6));
    }
    const vec3 a = v3(R(1.5), R(-2.25), R(3.125)), x = v3_norm(a), y = v3_norm_any(a);
    assert_memory_equal(&x, &y, sizeof x);
    const vec3 z = v3_norm_any(v3(0, 0, 0));
    assert_true(z.x == 0 && z.y == 0 && z.z == 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(sphere_from_outside),
        cmocka_unit_test(normals_of_any_size_normalise),
        cmocka_unit_test(sphere_from_inside_and_misses),
        cmocka_unit_test(plane_hits_and_parallel),
        cmocka_unit_test(triangle_barycentrics),
        cmocka_unit_test(triangle_fan_edges_are_watertight),
        cmocka_unit_test(octahedron_edges_and_vertices_do_not_leak),
        cmocka_unit_test(slab_test),
        cmocka_unit_test(next_up_and_down_are_nextafter),
    };
    return cmocka_run_group_tests_name("intersect", tests, NULL, NULL);
}
