/* test_normalmap.c - a model's normal map: the shading normal its texels
 * give in the tangent frame of the surface's texture coordinates. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include "helpers.h"
#include "model/obj.h"
#include "scene/path.h"
#include "scene/shade.h"
#include "scene/trace.h"
#include "worlds.h"

typedef struct {
    uint8_t rgb[3];  /* the map's one texel */
    real scale;      /* normal_scale; 0: no map */
    int mirror_u;    /* u runs from 1 at x = 0 to 0 at x = 1 */
    int flat_uv;     /* every corner at the same texture coordinates */
    vec3 rotate;     /* the instance's rotation, degrees */
    real height;     /* > 0: the map is the grey ramp below, a height map of this height (bump_height) */
    int ramp_v;      /* the ramp rises along v, not u */
    int level;       /* with height: the map is one grey texel, level */
    real lean;       /* the vertex normals lean to +x by this much: (lean, 0, 1), normalised */
} Quad;

/* A height map: a ramp of 64 grey texels, code 4 i at the i-th from u = 0
 * (or, ramp_v, from v = 0: the bottom row, v growing up the image). */
static Texture *ramp(int along_v)
{
    uint8_t g[64 * 3];
    for (int i = 0; i < 64; i++)
        g[3 * (along_v ? 63 - i : i)] = g[3 * (along_v ? 63 - i : i) + 1] = g[3 * (along_v ? 63 - i : i) + 2] =
            (uint8_t)(4 * i);
    return along_v ? texture_from_rgb8(1, 64, g) : texture_from_rgb8(64, 1, g);
}

/* The unit quad x, y in [0, 1] at z = 0, normals +z, u along x (or back),
 * v along y, its material's normal map one texel, as one instance. */
static Scene *quad_scene(const Quad *q)
{
    Mesh mesh;
    Err err;
    assert_int_equal(mesh_init(&mesh, MESH_NORMALS | MESH_UVS | MESH_MATERIALS, &err), 0);
    uint32_t tex;
    const uint8_t grey[3] = {128, 128, 128};
    Texture *map = q->height > 0 && q->level ? texture_from_rgb8(1, 1, grey)
                   : q->height > 0           ? ramp(q->ramp_v)
                                             : texture_from_rgb8(1, 1, q->rgb);
    assert_int_equal(mesh_add_texture(&mesh, map, &tex, &err), 0);
    Material m = material_default();
    if (q->scale > 0)
        m.normal_map = (int32_t)tex, m.normal_scale = q->scale;
    if (q->height > 0)
        m.normal_map = (int32_t)tex, m.normal_scale = 1, m.bump_height = q->height;
    assert_int_equal(mesh_add_material(&mesh, m, &err), 0);
    const vec3 a[3] = {v3(0, 0, 0), v3(1, 0, 0), v3(1, 1, 0)}, b[3] = {v3(0, 0, 0), v3(1, 1, 0), v3(0, 1, 0)};
    const vec3 up = v3_norm(v3(q->lean, 0, 1)), n[3] = {up, up, up};
    real ua[6] = {0, 0, 1, 0, 1, 1}, ub[6] = {0, 0, 1, 1, 0, 1};
    for (int i = 0; i < 6; i += 2) {
        if (q->mirror_u)
            ua[i] = 1 - ua[i], ub[i] = 1 - ub[i];
        if (q->flat_uv)
            ua[i] = ub[i] = R(0.25), ua[i + 1] = ub[i + 1] = R(0.5);
    }
    assert_int_equal(mesh_add(&mesh, a, n, ua, NULL, 0, &err), 0);
    assert_int_equal(mesh_add(&mesh, b, n, ub, NULL, 0, &err), 0);
    return worlds_scene_of_mesh(&mesh, q->rotate);
}

/* The shading normal where a ray from `from` towards `to` meets the quad. */
static Surface surface_seen(const Quad *q, vec3 from, vec3 to)
{
    Scene *s = quad_scene(q);
    const World *w = world_now(s);
    Ray r = ray_make(from, v3_norm(v3_sub(to, from)), 0, REAL_MAX);
    Hit h;
    assert_true(trace_closest(w, &r, &h));
    Surface sf;
    trace_surface(w, &r, &h, &sf);
    trace_surface_bump(&sf, NULL);
    world_now_free();
    scene_destroy(s);
    return sf;
}

/* A code as the map's number, as glTF defines it. */
static double code(uint8_t c) { return c / 255.0 * 2 - 1; }

/* normalise(t x sx + b y sy + n z) for the texel's numbers. */
static vec3 mapped(const uint8_t rgb[3], real scale, vec3 t, vec3 b, vec3 n)
{
    vec3 p = v3_add(v3_add(v3_scale(t, (real)code(rgb[0]) * scale), v3_scale(b, (real)code(rgb[1]) * scale)),
                    v3_scale(n, (real)code(rgb[2])));
    return v3_norm(p);
}

static void assert_near(vec3 got, vec3 want, double tol)
{
    for (int a = 0; a < 3; a++)
        if (fabs((double)got.e[a] - (double)want.e[a]) > tol)
            fail_msg("normal (%.5f %.5f %.5f), expected (%.5f %.5f %.5f)", (double)got.x, (double)got.y, (double)got.z,
                     (double)want.x, (double)want.y, (double)want.z);
}

static const vec3 X = {{1, 0, 0}}, Y = {{0, 1, 0}}, Z = {{0, 0, 1}};

static void red_tilts_the_normal_towards_u_and_green_towards_v(void **state)
{
    (void)state;
    Quad q = {.rgb = {218, 128, 218}, .scale = 1};
    Surface sf = surface_seen(&q, v3(0.3f, 0.6f, 1), v3(0.3f, 0.6f, 0));
    assert_near(sf.ns, mapped(q.rgb, 1, X, Y, Z), 1e-5);
    assert_true(sf.ns.x > R(0.6));
    Quad g = {.rgb = {128, 218, 218}, .scale = 1};
    sf = surface_seen(&g, v3(0.7f, 0.2f, 1), v3(0.7f, 0.2f, 0));
    assert_near(sf.ns, mapped(g.rgb, 1, X, Y, Z), 1e-5);
    assert_true(sf.ns.y > R(0.6));
    /* the geometric normal stays the triangle's */
    assert_near(sf.ng, Z, 0);
}

static void the_scale_tilts_x_and_y_only(void **state)
{
    (void)state;
    Quad q = {.rgb = {218, 80, 218}, .scale = R(0.5)};
    Surface sf = surface_seen(&q, v3(0.3f, 0.6f, 1), v3(0.3f, 0.6f, 0));
    assert_near(sf.ns, mapped(q.rgb, R(0.5), X, Y, Z), 1e-5);
    Quad none = q;
    none.scale = 0; /* no map: the vertex normals' */
    sf = surface_seen(&none, v3(0.3f, 0.6f, 1), v3(0.3f, 0.6f, 0));
    assert_near(sf.ns, Z, 0);
}

/* A grey height map (MTL bump) bumps the surface as a displacement would
 * (Blinn): the ramp rises 4/255 of bump_height a texel, 64 texels to the
 * unit quad, so the surface climbs 0.5 x 1.0039 a unit along u and the
 * normal leans back from the climb: (-0.502, 0, 1), normalised.  Mirrored
 * coordinates climb along -x; a ramp along v leans it to -y; a rotated
 * instance turns it with the quad; no height: the vertex normal. */
static void a_height_map_leans_the_normal_down_its_slope(void **state)
{
    (void)state;
    const real slope = R(0.5) * R(4) / R(255) * R(64);
    Quad q = {.height = R(0.5)};
    Surface sf = surface_seen(&q, v3(0.3f, 0.6f, 1), v3(0.3f, 0.6f, 0));
    assert_near(sf.ns, v3_norm(v3(-slope, 0, 1)), 1e-5);
    Quad m = {.height = R(0.5), .mirror_u = 1};
    sf = surface_seen(&m, v3(0.3f, 0.6f, 1), v3(0.3f, 0.6f, 0));
    assert_near(sf.ns, v3_norm(v3(slope, 0, 1)), 1e-5);
    Quad v = {.height = R(0.5), .ramp_v = 1};
    sf = surface_seen(&v, v3(0.3f, 0.6f, 1), v3(0.3f, 0.6f, 0));
    assert_near(sf.ns, v3_norm(v3(0, -slope, 1)), 1e-5);
    Quad r = {.height = R(0.5), .rotate = {{0, 0, 90}}}; /* u along +y now */
    sf = surface_seen(&r, v3(-0.6f, 0.3f, 1), v3(-0.6f, 0.3f, 0));
    assert_near(sf.ns, v3_norm(v3(0, -slope, 1)), 1e-5);
    Quad low = {.height = R(0.05)}; /* a tenth the height: a tenth the lean */
    sf = surface_seen(&low, v3(0.3f, 0.6f, 1), v3(0.3f, 0.6f, 0));
    assert_near(sf.ns, v3_norm(v3(-slope / 10, 0, 1)), 1e-5);
}

/* A height map bumps the smooth surface the vertex normals describe, not
 * the triangle's flat one: a level map leaves the interpolated normal (the
 * renderer before gave the face's, and a smooth low-poly model under a
 * height map showed its facets), and a ramp leans that normal back from
 * its climb. */
static void a_height_map_bumps_the_smooth_surface(void **state)
{
    (void)state;
    const vec3 lean = v3_norm(v3(R(0.4), 0, 1));
    Quad q = {.height = R(0.5), .level = 1, .lean = R(0.4)};
    Surface sf = surface_seen(&q, v3(0.3f, 0.6f, 1), v3(0.3f, 0.6f, 0));
    assert_near(sf.ns, lean, 1e-6);
    Quad r = {.height = R(0.5), .lean = R(0.4)};
    sf = surface_seen(&r, v3(0.3f, 0.6f, 1), v3(0.3f, 0.6f, 0));
    /* u's direction in the plane of the leaning normal, climbing 0.502 a unit of it */
    const vec3 t = v3_norm(v3_sub(X, v3_scale(lean, v3_dot(lean, X))));
    const real slope = R(0.5) * R(4) / R(255) * R(64) / v3_dot(t, X);
    assert_near(sf.ns, v3_norm(v3_sub(lean, v3_scale(t, slope))), 1e-5);
}

/* A normal map's tilt towards a light that the smooth surface meets at a
 * grazing angle takes a share of it that falls to 0 at the smooth
 * surface's horizon (lobes_bump_shadowing; Chiang et al.'s term, as
 * Cycles applies it): the quad's map leans 45 degrees to +u, the lamp
 * stands 10 degrees over the quad towards +x, so the tilted normal faces
 * it at cos 35 degrees but the quad's relief would shadow most of it: g =
 * sin 10 / (cos 35 cos 45) = 0.300, the share g + g^2 - g^3 = 0.363.
 * Under both integrators' direct light; a lamp high above (g >= 1) lights
 * it fully. */
static void a_tilt_towards_a_grazing_light_takes_a_share_of_it(void **state)
{
    (void)state;
    const double el = 10 * 3.14159265358979 / 180, g = sin(el) / (cos(35 * 3.14159265358979 / 180) * sqrt(0.5));
    const double share = g + g * g - g * g * g;
    Quad q = {.rgb = {218, 128, 218}, .scale = 1};
    for (int path = 0; path < 2; path++)
        for (int high = 0; high < 2; high++) {
            Scene *s = quad_scene(&q);
            s->ambient = v3_splat(R(0));
            s->settings.shading = SHADE_DIFFUSE;
            s->settings.shadows = 0;
            s->settings.integrator = path ? INTEGRATOR_PATH : INTEGRATOR_WHITTED;
            s->settings.depth = 0;
            const vec3 to_light = high ? v3_norm(v3(1, 0, 1)) : v3((real)cos(el), 0, (real)sin(el));
            assert_int_equal(scene_add_light(s, light_directional(v3_neg(to_light), v3_splat(1), 1), NULL), 0);
            const World *w = world_now(s);
            Ray r = ray_make(v3(0.3f, 0.6f, 1), v3(0, 0, -1), 0, REAL_MAX);
            Hit h;
            assert_true(trace_closest(w, &r, &h));
            Surface sf;
            trace_surface(w, &r, &h, &sf);
            trace_surface_bump(&sf, NULL);
            const double cosine = (double)v3_dot(sf.ns, to_light);
            RayStats st = {0, 0, 0};
            vec3 c;
            if (path) {
                const SampleId id = {.key = 1, .index = 0, .count = 1};
                path_radiance_packet(w, &r, 1, &id, &c, &st, NULL, NULL);
            } else {
                c = shade_ray(w, &r, &st, NULL);
            }
            const double want = 0.8 * cosine * (high ? 1 : share); /* the default diffuse colour 0.8 */
            if (fabs((double)c.x - want) > 1e-4)
                fail_msg("%s, lamp %s: %.5f, expected %.5f (cos %.4f)", path ? "path" : "Whitted", high ? "high" : "grazing",
                         (double)c.x, want, cosine);
            world_now_free();
            scene_destroy(s);
        }
}

/* Texture coordinates that run against x turn the tangent: the normal
 * leans to -x, and still to +v. */
static void mirrored_coordinates_mirror_the_frame(void **state)
{
    (void)state;
    Quad q = {.rgb = {218, 170, 218}, .scale = 1, .mirror_u = 1};
    Surface sf = surface_seen(&q, v3(0.3f, 0.6f, 1), v3(0.3f, 0.6f, 0));
    assert_near(sf.ns, mapped(q.rgb, 1, v3(-1, 0, 0), Y, Z), 1e-5);
    assert_true(sf.ns.x < R(-0.5) && sf.ns.y > R(0.1));
}

/* Seen from behind, the surface's normal is the front's turned round:
 * the same tilted surface. */
static void from_behind_the_normal_is_the_fronts_reversed(void **state)
{
    (void)state;
    Quad q = {.rgb = {218, 170, 218}, .scale = 1};
    Surface sf = surface_seen(&q, v3(0.3f, 0.6f, -1), v3(0.3f, 0.6f, 0));
    assert_near(sf.ns, v3_neg(mapped(q.rgb, 1, X, Y, Z)), 1e-5);
    assert_near(sf.ng, v3(0, 0, -1), 0);
}

/* An instance's rotation turns the mapped normal with the surface. */
static void the_instance_turns_the_frame(void **state)
{
    (void)state;
    Quad q = {.rgb = {218, 170, 218}, .scale = 1, .rotate = v3(0, 90, 0)};
    /* rotated 90 degrees about y: x -> -z, z -> x; the quad at x = 0 faces +x */
    Surface sf = surface_seen(&q, v3(1, 0.6f, -0.3f), v3(0, 0.6f, -0.3f));
    assert_near(sf.ng, X, 1e-6);
    assert_near(sf.ns, mapped(q.rgb, 1, v3(0, 0, -1), Y, X), 1e-5);
}

/* Where the map's normal would face away from the viewer, or the texture
 * coordinates give no frame, the vertex normals' stays. */
static void no_frame_or_a_normal_below_keeps_the_vertex_normal(void **state)
{
    (void)state;
    Quad below = {.rgb = {255, 128, 0}, .scale = 1};
    Surface sf = surface_seen(&below, v3(0.3f, 0.6f, 1), v3(0.3f, 0.6f, 0));
    assert_near(sf.ns, Z, 0);
    Quad flat = {.rgb = {218, 170, 218}, .scale = 1, .flat_uv = 1};
    sf = surface_seen(&flat, v3(0.3f, 0.6f, 1), v3(0.3f, 0.6f, 0));
    assert_near(sf.ns, Z, 0);
}

/* A texel read as data: 128 128 255 is (almost) the normal itself, not
 * sRGB-decoded (which would read 128 as 0.22, a tilt of 56 degrees). */
static void the_map_is_read_as_data(void **state)
{
    (void)state;
    const uint8_t rgb[3] = {0, 128, 255};
    Texture *t = texture_from_rgb8(1, 1, rgb);
    vec3 c = texture_normal(t, R(0.5), R(0.5), NULL);
    assert_near(c, v3(-1, (real)code(128), 1), 1e-6);
    texture_destroy(t);
}

/* A normal map seen from afar reads its levels, which average its codes
 * as numbers: a checker of tilts to +u and -u is, four texels to a sample,
 * the untilted normal (the colour levels, averaged as light, would lean to
 * +u: code 161, not 128); without the levels, or at a point, one texel. */
static void far_off_a_normal_map_reads_the_mean_of_its_normals(void **state)
{
    (void)state;
    const uint8_t rgb[12] = {218, 128, 218, 38, 128, 218, 38, 128, 218, 218, 128, 218};
    Texture *t = texture_from_rgb8(2, 2, rgb);
    const TexFootprint wide = {R(1), 0, 0, R(1)}; /* a sample spans the image */
    vec3 c = texture_normal(t, R(0.25), R(0.75), &wide);
    assert_true(c.x > R(0.6)); /* no levels yet: the texel */
    assert_int_equal(texture_make_data_levels(t), 0);
    assert_int_equal(t->data_level[1].rgb[0], 128);
    assert_int_equal(t->data_level[1].rgb[2], 218);
    assert_true(t->level[1].rgb[0] > 150); /* the colour level: light, not numbers */
    c = texture_normal(t, R(0.25), R(0.75), &wide);
    assert_near(c, v3((real)code(128), (real)code(128), (real)code(218)), 1e-6);
    c = texture_normal(t, R(0.25), R(0.75), NULL);
    assert_true(c.x > R(0.6));
    /* a footprint of half a texel: the image itself */
    const TexFootprint near = {R(0.25), 0, 0, R(0.25)};
    c = texture_normal(t, R(0.25), R(0.75), &near);
    assert_true(c.x > R(0.6));
    texture_destroy(t);
}

/* The normal a map baked by Blender stands for (tests/data/mikk/make-ball.py's
 * wavy(): the unit sphere's, leaning in waves, 6 round and 5 down). */
static vec3 wavy(vec3 p)
{
    const vec3 q = v3_norm(p);
    const double th = acos(fmax(-1, fmin(1, (double)q.y))), ph = atan2(-(double)q.z, (double)q.x);
    const double a = 0.6 * sin(th) * sin(6 * ph), b = 0.6 * sin(th) * cos(5 * th);
    const double e[3] = {(double)q.x + a * -sin(ph) + b * cos(th) * cos(ph), (double)q.y + b * -sin(th),
                         (double)q.z + a * -cos(ph) + b * -cos(th) * sin(ph)};
    return v3_norm(v3((real)e[0], (real)e[1], (real)e[2]));
}

/* A low-poly sphere (12 x 6) whose normal map was baked in Blender's
 * tangent frames (MikkTSpace, smooth across each vertex's triangles):
 * read in the frames lanray makes (model_tangents.c; its corners' tangents
 * are Blender's within 1e-4 degrees here), the normals are the ones baked,
 * within the 8-bit codes' and the bilinear reading's error: 0.14 degrees
 * off on average, 2.4 at most (at the seam of u, where the reading wraps).
 * Read in each triangle's own frame (the renderer before), they were 1.46
 * degrees off on average and 7.3 at most: the triangles showed through
 * the map made to hide them. */
static void a_map_baked_in_smooth_frames_reads_its_normals_back(void **state)
{
    (void)state;
    Mesh mesh;
    Err err;
    ObjStats st;
    if (obj_read("tests/data/mikk/ball.obj", NULL, &mesh, &st, &err))
        fail_msg("%s", err.msg);
    Scene *s = worlds_scene_of_mesh(&mesh, v3(0, 0, 0));
    const World *w = world_now(s);
    double sum = 0, worst = 0;
    const int n = 2000;
    for (int i = 0; i < n; i++) { /* a Fibonacci lattice of directions, rays from outside to the centre */
        const double y = 1 - (2 * i + 1.0) / n, r = sqrt(1 - y * y), ph = 2.399963229728653 * i;
        const vec3 d = v3((real)(r * cos(ph)), (real)y, (real)(r * sin(ph)));
        Ray ray = ray_make(v3_scale(d, 3), v3_neg(d), 0, REAL_MAX);
        Hit h;
        assert_true(trace_closest(w, &ray, &h));
        Surface sf;
        trace_surface(w, &ray, &h, &sf);
        trace_surface_bump(&sf, NULL);
        const vec3 want = wavy(ray_at(&ray, h.t));
        const double deg = acos(fmin(1, (double)v3_dot(sf.ns, want))) * 57.29577951308232;
        sum += deg;
        worst = fmax(worst, deg);
    }
    print_message("baked normals read back: mean %.3f, worst %.3f degrees off\n", sum / n, worst);
    assert_true(sum / n < 0.5);
    assert_true(worst < 3);
    world_now_free();
    scene_destroy(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(red_tilts_the_normal_towards_u_and_green_towards_v),
        cmocka_unit_test(a_map_baked_in_smooth_frames_reads_its_normals_back),
        cmocka_unit_test(a_height_map_bumps_the_smooth_surface),
        cmocka_unit_test(a_tilt_towards_a_grazing_light_takes_a_share_of_it),
        cmocka_unit_test(a_height_map_leans_the_normal_down_its_slope),
        cmocka_unit_test(the_scale_tilts_x_and_y_only),
        cmocka_unit_test(mirrored_coordinates_mirror_the_frame),
        cmocka_unit_test(from_behind_the_normal_is_the_fronts_reversed),
        cmocka_unit_test(the_instance_turns_the_frame),
        cmocka_unit_test(no_frame_or_a_normal_below_keeps_the_vertex_normal),
        cmocka_unit_test(the_map_is_read_as_data),
        cmocka_unit_test(far_off_a_normal_map_reads_the_mean_of_its_normals),
    };
    return cmocka_run_group_tests_name("normalmap", tests, NULL, NULL);
}
