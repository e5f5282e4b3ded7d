/* test_shadow.c - shadow rays that glass lets through: trace_shadow and
 * trace_shadow_packet against worlds holding the opaque or the glass
 * items alone, on every SIMD path and every packet size. */
#include "helpers.h"
#include "sah_model.h"
#include "worlds.h"

#include "base/simd.h"
#include "scene/trace.h"

enum { OPAQUE = 1, GLASS = 2 };

static Model *box_model(void)
{
    Mesh m;
    assert_int_equal(mesh_init(&m, 0, NULL), 0);
    const vec3 c[8] = {v3(-1, -1, -1), v3(1, -1, -1), v3(1, 1, -1), v3(-1, 1, -1),
                       v3(-1, -1, 1),  v3(1, -1, 1),  v3(1, 1, 1),  v3(-1, 1, 1)};
    const int f[12][3] = {{0, 1, 2}, {0, 2, 3}, {4, 6, 5}, {4, 7, 6}, {0, 4, 5}, {0, 5, 1},
                          {3, 2, 6}, {3, 6, 7}, {0, 3, 7}, {0, 7, 4}, {1, 5, 6}, {1, 6, 2}};
    for (int i = 0; i < 12; i++) {
        const vec3 t[3] = {c[f[i][0]], c[f[i][1]], c[f[i][2]]};
        assert_int_equal(mesh_add(&m, t, NULL, NULL, NULL, 0, NULL), 0);
    }
    Model *model = sah_model(&m);
    return model;
}

/* A scene of the items `which` asks for (OPAQUE, GLASS or both), the same
 * materials (0 opaque, 1 glass) in every one. */
static Scene *shadow_scene(int which, int glass_plane)
{
    Scene *s = scene_create();
    assert_non_null(s);
    Material clay = {.kd = v3(R(0.8), R(0.7), R(0.6)), .shininess = 1, .texture = -1};
    Material glass = {.kd = v3_splat(0), .kt = v3(R(0.9), R(0.95), 1), .ior = R(1.5), .shininess = 1, .texture = -1};
    assert_int_equal(scene_add_material(s, clay, NULL, NULL), 0);
    assert_int_equal(scene_add_material(s, glass, NULL, NULL), 0);
    uint32_t box;
    assert_int_equal(scene_add_model(s, box_model(), &box, NULL), 0);
    if (which & OPAQUE) {
        assert_int_equal(scene_add_sphere(s, (Sphere){v3(R(0.7), R(0.3), 0), R(0.5), 0}, NULL), 0);
        const vec3 tri[3] = {v3(-2, R(-0.5), -2), v3(2, R(-0.5), -2), v3(0, R(-0.5), 2)};
        assert_int_equal(scene_add_triangle(s, tri, NULL, NULL, 0, NULL), 0);
        Instance in = instance_make(box, v3(R(-1.5), 0, -1), v3(10, 20, 30), R(0.4));
        in.material = 0;
        assert_int_equal(scene_add_instance(s, in, NULL), 0);
    }
    if (which & GLASS) {
        assert_int_equal(scene_add_sphere(s, (Sphere){v3(R(-0.4), R(0.2), R(0.6)), R(0.6), 1}, NULL), 0);
        Instance in = instance_make(box, v3(R(1.4), R(0.2), -1), v3(0, 45, 0), R(0.5));
        in.material = 1;
        assert_int_equal(scene_add_instance(s, in, NULL), 0);
        if (glass_plane)
            assert_int_equal(scene_add_plane(s, plane_make(v3(0, R(1.6), 0), v3(0, -1, 0), 1), NULL), 0);
    }
    assert_int_equal(scene_add_light(s, light_point(v3(0, 5, 0), v3(1, 1, 1), 1, 0), NULL), 0);
    return s;
}

/* A world of its own for each scene (world_now keeps one at a time). */
static World *build(Scene *s)
{
    Err err;
    assert_int_equal(scene_check(s, &err), 0);
    World *w = world_build(s, NULL, &err);
    assert_non_null(w);
    return w;
}

/* Ray k of a fan from points under and among the items up towards the
 * light's side, each to a point at its own distance. */
static Ray fan_ray(int k, real *tmax)
{
    vec3 o = v3(R(-2.5) + R(0.19) * (real)(k % 27), R(-1.2) + R(0.05) * (real)(k % 7), R(-1.8) + R(0.13) * (real)(k % 29));
    vec3 to = v3(R(-1) + R(0.37) * (real)(k % 5), R(2.5), R(-0.5) + R(0.23) * (real)(k % 3));
    vec3 d = v3_sub(to, o);
    *tmax = v3_len(d) * (R(0.3) + R(0.1) * (real)(k % 7));
    return ray_make(o, v3_norm(d), 0, REAL_INF);
}

/* Blocked (by the opaque items alone), through glass (met by the glass
 * items, not blocked) or clear, on every SIMD path and packet size, and
 * the walk's closest glass hit the glass-only world's closest hit. */
static void glass_passes_and_opaque_blocks(void **state)
{
    (void)state;
    for (int plane = 0; plane < 2; plane++) {
        Scene *sf = shadow_scene(OPAQUE | GLASS, plane), *so = shadow_scene(OPAQUE, plane),
              *sg = shadow_scene(GLASS, plane);
        World *full = build(sf), *opaque = build(so), *glass = build(sg);
        assert_non_null(full->glassy);
        assert_null(opaque->glassy);
        int counts[3] = {0, 0, 0};
        for (int path = -1; simd_next(&path);) {
            for (int k0 = 0; k0 < 4000; k0 += TRACE_PACKET) {
                const int n = 1 + (k0 / TRACE_PACKET) % TRACE_PACKET;
                Ray rays[TRACE_PACKET];
                real tm[TRACE_PACKET];
                for (int i = 0; i < n; i++)
                    rays[i] = fan_ray(k0 + i, &tm[i]);
                uint32_t through;
                const uint32_t blocked = trace_shadow_packet(full, rays, n, tm, NULL, &through);
                assert_int_equal(blocked & through, 0);
                for (int i = 0; i < n; i++) {
                    const int op = trace_occluded(opaque, &rays[i], tm[i], NULL);
                    const int gl = !op && trace_occluded(glass, &rays[i], tm[i], NULL);
                    int g1;
                    const int b1 = trace_shadow(full, &rays[i], tm[i], NULL, &g1);
                    if (b1 != op || g1 != gl || (int)(blocked >> i & 1) != op || (int)(through >> i & 1) != gl)
                        fail_msg("%s, plane %d, ray %d: alone blocked %d glass %d, packet %d %d; expected %d %d",
                                 simd_name((SimdPath)path), plane, k0 + i, b1, g1, (int)(blocked >> i & 1),
                                 (int)(through >> i & 1), op, gl);
                    assert_int_equal(trace_occluded(full, &rays[i], tm[i], NULL), op || gl);
                    counts[op ? 0 : gl ? 1 : 2]++;
                    Hit a, b;
                    Ray r = rays[i];
                    r.tmax = tm[i];
                    const int ga = trace_closest_glass(full, &r, &a), gb = trace_closest(glass, &r, &b);
                    assert_int_equal(ga, gb);
                    if (ga && (a.t != b.t || a.kind != b.kind))
                        fail_msg("ray %d: the walk's glass hit t %.9g kind %d, the glass world's %.9g %d", k0 + i,
                                 (double)a.t, a.kind, (double)b.t, b.kind);
                }
            }
        }
        /* every case is met often */
        for (int c = 0; c < 3; c++)
            if (counts[c] < 200)
                fail_msg("plane %d: only %d rays %s", plane, counts[c], c == 0 ? "blocked" : c == 1 ? "through glass" : "clear");
        world_destroy(full), world_destroy(opaque), world_destroy(glass);
        scene_destroy(sf), scene_destroy(so), scene_destroy(sg);
    }
}

/* Without dielectrics a shadow ray is trace_occluded's, and nothing is glass. */
static void no_glass_is_plain_occlusion(void **state)
{
    (void)state;
    Scene *s = shadow_scene(OPAQUE, 0);
    World *w = build(s);
    for (int k0 = 0; k0 < 800; k0 += TRACE_PACKET) {
        Ray rays[TRACE_PACKET];
        real tm[TRACE_PACKET];
        for (int i = 0; i < TRACE_PACKET; i++)
            rays[i] = fan_ray(k0 + i, &tm[i]);
        uint32_t through = 123;
        assert_int_equal(trace_shadow_packet(w, rays, TRACE_PACKET, tm, NULL, &through),
                         trace_occluded_packet(w, rays, TRACE_PACKET, tm, NULL));
        assert_int_equal(through, 0);
    }
    world_destroy(w);
    scene_destroy(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(glass_passes_and_opaque_blocks),
        cmocka_unit_test(no_glass_is_plain_occlusion),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
