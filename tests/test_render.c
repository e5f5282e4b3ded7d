/* test_render.c - shading against analytic values, and pixels that do not
 * depend on threads or on how the frame is cut into segments. */
#include "helpers.h"
#include "sah_model.h"
#include "worlds.h"

#include <math.h>

#include "render/render.h"
#include "base/srgb.h"
#include "scene/path.h"
#include "scene/scene_default.h"
#include "base/simd.h"
#include "scene/scene_fields.h"

static Scene *empty_scene(void)
{
    Scene *s = scene_create();
    assert_non_null(s);
    s->ambient = v3_splat(0);
    s->background = v3_splat(0);
    Material white = {.kd = v3(1, 1, 1), .ks = v3(0, 0, 0), .shininess = 1, .texture = -1};
    assert_int_equal(scene_add_material(s, white, NULL, NULL), 0);
    return s;
}

static void prepare(Scene *s)
{
    Err err;
    if (scene_check(s, &err))
        fail_msg("%s", err.msg);
}

/* Colour seen by a ray from eye towards point p. */
static vec3 look(Scene *s, vec3 eye, vec3 p)
{
    Ray r = ray_make(eye, v3_norm(v3_sub(p, eye)), 0, REAL_INF);
    RayStats st = {0, 0, 0};
    return shade_ray(world_now(s), &r, &st, NULL);
}

static void diffuse_and_phong_match_the_formula(void **state)
{
    (void)state;
    Scene *s = empty_scene();
    s->materials[0].ks = v3_splat(R(0.25));
    s->materials[0].shininess = 10;
    assert_int_equal(scene_add_sphere(s, (Sphere){v3(0, 0, 0), 1, 0}, NULL), 0);
    assert_int_equal(scene_add_light(s, light_directional(v3(0, 0, -1), v3(1, 1, 1), R(0.5)), NULL), 0);
    prepare(s);
    /* front of the sphere: N.L = 1 and the mirror direction points at the eye */
    vec3 c = look(s, v3(0, 0, 5), v3(0, 0, 1));
    assert_float_equal(c.x, R(0.5) + R(0.25) * R(0.5), R(1e-5));
    /* 60 degrees off: N.L = cos 60; the highlight is gone (R.V = cos 120 < 0) */
    vec3 p = v3(sin(REAL_PI / 3), 0, cos(REAL_PI / 3));
    c = look(s, v3_scale(p, 5), p);
    assert_float_equal(c.x, R(0.5) * cos(REAL_PI / 3) + R(0.25) * R(0.5) * pow(cos(REAL_PI / 3), R(10)), R(1e-4));
    s->settings.shading = SHADE_DIFFUSE;
    c = look(s, v3(0, 0, 5), v3(0, 0, 1));
    assert_float_equal(c.x, R(0.5), R(1e-5));
    scene_destroy(s);
}

static void shadows_attenuation_and_spot_cone(void **state)
{
    (void)state;
    Scene *s = empty_scene();
    assert_int_equal(scene_add_plane(s, plane_make(v3(0, 0, 0), v3(0, 1, 0), 0), NULL), 0);
    assert_int_equal(scene_add_sphere(s, (Sphere){v3(0, 2, 0), R(0.5), 0}, NULL), 0);
    assert_int_equal(scene_add_light(s, light_point(v3(0, 4, 0), v3(1, 1, 1), 16, 1), NULL), 0);
    prepare(s);
    vec3 eye = v3(0, 3, 6);
    /* under the sphere: shadowed */
    assert_float_equal(look(s, eye, v3(0, 0, 0)).x, 0, 0);
    /* at (3, 0, 0): N.L = 4/5, distance^2 = 25, intensity 16 */
    assert_float_equal(look(s, eye, v3(3, 0, 0)).x, R(16) / 25 * R(0.8), R(1e-4));
    s->settings.shadows = 0;
    prepare(s);
    assert_float_equal(look(s, eye, v3(0, 0, 0)).x, 1, R(1e-4)); /* 16 / 16 * N.L 1 */
    /* a spot light straight down with a 60 degree beam and no soft edge */
    s->settings.shadows = 1;
    s->lights[0] = light_spot(v3(0, 4, 0), v3(0, -1, 0), 60, 0, v3(1, 1, 1), 1, 0);
    s->spheres[0].centre = v3(50, 50, 50); /* out of the way */
    prepare(s);
    real inside = look(s, eye, v3(R(2.2), 0, 0)).x;  /* 28.8 degrees off the axis */
    real outside = look(s, eye, v3(R(2.4), 0, 0)).x; /* 31 degrees */
    assert_float_equal(inside, v3_dot(v3(0, 1, 0), v3_norm(v3(R(-2.2), 4, 0))), R(1e-4));
    assert_float_equal(outside, 0, 0);
    /* with a 10 degree soft edge the rim fades: between 0 and the hard value */
    s->lights[0].soft = 10;
    prepare(s);
    real soft = look(s, eye, v3(R(2.2), 0, 0)).x;
    assert_true(soft > 0 && soft < inside);
    assert_float_equal(look(s, eye, v3(R(0.5), 0, 0)).x, v3_dot(v3(0, 1, 0), v3_norm(v3(R(-0.5), 4, 0))), R(1e-4));
    scene_destroy(s);
}

/* The colour of every pixel of a small frame that shows one surface only. */
static void render_codes(Scene *s, uint8_t out[16 * 3])
{
    RenderPool *pool = render_pool_create(1, NULL);
    assert_int_equal(render_lines(pool, world_now(s), 4, 4, 0, 4, out, NULL, NULL), 0);
    render_pool_destroy(pool);
}

static double srgb_formula(double v) { return v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1 / 2.4) - 0.055; }

/* Shading is linear light, the pixel its sRGB code: a wall whose colour is
 * exactly kd (ambient 1, nothing else) comes out as the standard's encoding
 * of kd, or as kd * 255 with linear output; and a texture's codes, decoded
 * on load, come out as stored. */
static void pixels_are_srgb_unless_linear(void **state)
{
    (void)state;
    Scene *s = empty_scene();
    s->ambient = v3_splat(1);
    assert_int_equal(scene_add_plane(s, plane_make(v3(0, 0, 0), v3(0, 0, 1), 0), NULL), 0);
    const real kd[] = {R(0.001), R(0.0031), R(0.05), R(0.2), R(0.5), R(0.9), R(1)};
    for (size_t i = 0; i < sizeof kd / sizeof kd[0]; i++)
        for (int linear = 0; linear < 2; linear++) {
            s->materials[0].kd = v3(kd[i], kd[i] * R(0.5), R(0));
            s->settings.linear = linear;
            prepare(s);
            uint8_t px[16 * 3];
            render_codes(s, px);
            for (int c = 0; c < 2; c++) {
                double v = (double)s->materials[0].kd.e[c];
                int want = (int)floor((linear ? v : srgb_formula(v)) * 255 + 0.5);
                for (int k = 0; k < 16; k++)
                    assert_int_equal(px[3 * k + c], want);
            }
        }
    /* a 1x1 texture of each code, drawn at full light, comes out as that code */
    uint32_t tex;
    uint8_t code[3] = {0, 0, 0};
    assert_int_equal(scene_add_texture(s, texture_from_rgb8(1, 1, code), &tex, NULL), 0);
    s->materials[0] = (Material){.kd = v3(1, 1, 1), .ks = v3(0, 0, 0), .shininess = 1, .texture = (int32_t)tex};
    s->planes[0].uv_scale = 1;
    s->settings.linear = 0;
    for (int k = 0; k < 256; k++) {
        uint8_t *t = s->textures[tex]->level[0].rgb;
        t[0] = t[1] = t[2] = (uint8_t)k;
        prepare(s);
        uint8_t px[16 * 3];
        render_codes(s, px);
        for (int j = 0; j < 16 * 3; j++)
            assert_int_equal(px[j], k);
    }
    scene_destroy(s);
}

/* Planes and spheres take textures: a plane by planar mapping (u along x
 * laid on the plane, v = n x u, scaled and turned), a sphere by spherical
 * mapping (longitude and latitude). */
static void plane_and_sphere_texture_coordinates(void **state)
{
    (void)state;
    Scene *s = empty_scene();
    const uint8_t px[3] = {255, 255, 255};
    uint32_t tex;
    assert_int_equal(scene_add_texture(s, texture_from_rgb8(1, 1, px), &tex, NULL), 0);
    s->materials[0].texture = (int32_t)tex;
    Plane floor = plane_make(v3(1, 0, 1), v3(0, 2, 0), 0);
    floor.uv_scale = 2;
    floor.uv_rotate = 90;
    assert_int_equal(scene_add_plane(s, floor, NULL), 0);
    assert_int_equal(scene_add_sphere(s, (Sphere){v3(0, 5, 0), 1, 0}, NULL), 0);
    prepare(s);
    Ray r = ray_make(v3(4, 3, -2), v3(0, -1, 0), 0, REAL_INF);
    Hit h;
    Surface sf;
    assert_true(trace_closest(world_now(s), &r, &h));
    trace_surface(world_now(s), &r, &h, &sf);
    assert_true(sf.has_uv);
    /* unturned: u = x / 2, v = -z / 2 from the point (1, 0, 1); turned 90
     * degrees, u takes v's axis and v takes -u's */
    assert_float_equal(sf.u, R(1.5), R(1e-6));
    assert_float_equal(sf.v, R(-1.5), R(1e-6));
    s->planes[0].uv_rotate = 0;
    prepare(s);
    trace_surface(world_now(s), &r, &h, &sf);
    assert_float_equal(sf.u, R(1.5), R(1e-6));
    assert_float_equal(sf.v, R(1.5), R(1e-6));
    /* the sphere: its front (+z) is the middle of the texture, its top v = 1,
     * a quarter turn towards +x is u = 0.75 */
    const vec3 at[3] = {v3(0, 0, 1), v3(0, 1, 0), v3(1, 0, 0)};
    const real want[3][2] = {{R(0.5), R(0.5)}, {-1, 1}, {R(0.75), R(0.5)}};
    for (int k = 0; k < 3; k++) {
        vec3 o = v3_add(v3(0, 5, 0), v3_scale(at[k], 3));
        r = ray_make(o, v3_neg(at[k]), 0, REAL_INF);
        assert_true(trace_closest(world_now(s), &r, &h));
        assert_int_equal(h.kind, HIT_SPHERE);
        trace_surface(world_now(s), &r, &h, &sf);
        assert_true(sf.has_uv);
        if (want[k][0] >= 0)
            assert_float_equal(sf.u, want[k][0], R(1e-5));
        assert_float_equal(sf.v, want[k][1], R(1e-5));
    }
    scene_destroy(s);
}

/* A coarse UV sphere (16 x 8 quads, each two triangles) with the true
 * sphere's normals at its vertices, as a modeller exports a smooth ball. */
/* A unit sphere of seg x rings quads (the poles' triangles left out), of
 * material *mat (or none: the scene's first). */
static Model *sphere_model_of(int SEG, int RINGS, const Material *mat)
{
    Mesh m;
    assert_int_equal(mesh_init(&m, MESH_NORMALS | (mat ? MESH_MATERIALS : 0u), NULL), 0);
    if (mat)
        assert_int_equal(mesh_add_material(&m, *mat, NULL), 0);
    for (int j = 0; j < RINGS; j++)
        for (int i = 0; i < SEG; i++) {
            vec3 v[4];
            for (int k = 0; k < 4; k++) {
                real th = REAL_PI * (real)(j + (k >= 2)) / RINGS, ph = R(2) * REAL_PI * (real)(i + (k == 1 || k == 2)) / SEG;
                v[k] = v3(sin(th) * cos(ph), cos(th), sin(th) * sin(ph));
            }
            const vec3 t1[3] = {v[0], v[1], v[2]}, t2[3] = {v[0], v[2], v[3]};
            if (!mesh_tri_is_degenerate(t1))
                assert_int_equal(mesh_add(&m, t1, t1, NULL, NULL, 0, NULL), 0);
            if (!mesh_tri_is_degenerate(t2))
                assert_int_equal(mesh_add(&m, t2, t2, NULL, NULL, 0, NULL), 0);
        }
    Model *model = sah_model(&m);
    return model;
}

static Model *sphere_model(int SEG, int RINGS) { return sphere_model_of(SEG, RINGS, NULL); }
static Model *coarse_sphere(void) { return sphere_model(16, 8); }

/* The shadow terminator: where smooth normals face a grazing light, the
 * flat triangles of a coarse mesh shade and shadow themselves, and
 * triangle-shaped dark patches appear along the boundary between light and
 * dark.  Seen from the front, lit from three grazing directions, every
 * pixel whose ray hits both the mesh and the true unit sphere is compared
 * with the true sphere's diffuse shading max(0, n.L) at its own hit point.
 * Tolerances: no pixel that the true sphere shows lit at 0.05 or more is
 * black (a dark patch); shadow rays change no pixel at all (a convex body
 * cannot shadow itself, so the image equals the one rendered without
 * shadows); no pixel differs from the true sphere by more than 0.15, the
 * error of interpolating 16 x 8 vertex normals (and of the facets lying
 * inside the sphere), which rendering without shadows shows as well.
 * Before the fix: 123 dark pixels with the first light.  The path
 * integrator's direct light (depth 0) the same: before it decided by the
 * facet too (2026-11-29), 123 dark pixels with the first light. */
static vec3 look_path(Scene *s, vec3 eye, vec3 p)
{
    Ray r = ray_make(eye, v3_norm(v3_sub(p, eye)), 0, REAL_INF);
    RayStats st = {0, 0, 0};
    const SampleId id = {.key = 1, .index = 0, .count = 1};
    vec3 out;
    path_radiance_packet(world_now(s), &r, 1, &id, &out, &st, NULL, NULL);
    return out;
}

static void smooth_mesh_has_no_shadow_terminator(void **state)
{
    (void)state;
    Scene *s = empty_scene();
    s->background = v3_splat(-1); /* a miss is told from black */
    uint32_t id;
    assert_int_equal(scene_add_model(s, coarse_sphere(), &id, NULL), 0);
    assert_int_equal(scene_add_instance(s, instance_make(id, v3_splat(0), v3_splat(0), 1), NULL), 0);
    const vec3 lights[3] = {v3(-1, R(-0.1), R(-0.05)), v3(-1, R(-0.5), R(0.2)), v3(R(-0.3), R(-1), R(0.1))};
    for (int run = 0; run < 6; run++) {
        const int li = run % 3, path = run >= 3;
        s->settings.integrator = path ? INTEGRATOR_PATH : INTEGRATOR_WHITTED;
        s->settings.depth = path ? 0 : s->settings.depth;
        s->light_count = 0;
        assert_int_equal(scene_add_light(s, light_directional(lights[li], v3_splat(1), 1), NULL), 0);
        enum { N = 160 };
        int dark = 0, compared = 0, changed = 0;
        real worst = 0;
        for (int y = 0; y < N; y++)
            for (int x = 0; x < N; x++) {
                vec3 eye = v3(0, 0, 6), target = v3(R(2.4) * ((real)x + R(0.5)) / N - R(1.2), R(1.2) - R(2.4) * ((real)y + R(0.5)) / N, 0);
                vec3 d = v3_norm(v3_sub(target, eye));
                /* the true sphere: |eye + t d| = 1 */
                real b = v3_dot(eye, d), c = v3_dot(eye, eye) - 1, disc = b * b - c;
                if (disc < R(0.02)) /* misses, or grazes its rim where the mesh's outline differs */
                    continue;
                vec3 p = v3_madd(eye, d, -b - sqrt(disc));
                real want = real_max(0, v3_dot(p, v3_neg(v3_norm(lights[li]))));
                s->settings.shadows = 1;
                prepare(s);
                vec3 got = path ? look_path(s, eye, target) : look(s, eye, target);
                s->settings.shadows = 0;
                prepare(s);
                vec3 unshadowed = path ? look_path(s, eye, target) : look(s, eye, target);
                if (got.x < 0)
                    continue; /* the mesh's outline is inside the sphere's */
                compared++;
                dark += want >= R(0.05) && got.x == 0;
                changed += got.x != unshadowed.x;
                worst = real_max(worst, fabs(got.x - want));
            }
        print_message("terminator (%s), light %d: %d pixels compared, %d dark patches, %d changed by shadow rays, "
                      "largest error %.3f\n", path ? "path" : "Whitted", li, compared, dark, changed, (double)worst);
        assert_true(compared > N * N / 2);
        assert_int_equal(dark, 0);
        assert_int_equal(changed, 0);
        assert_true(worst <= R(0.15));
    }
    scene_destroy(s);
}

/* A clear coat (Whitted): a smooth one reflects Fresnel's share for index
 * 1.5 times its strength, 0.04 head on ((1.5 - 1) / (1.5 + 1))^2, more
 * towards the rim, and the surface under it takes the rest (the ambient
 * light on a white one: 0.96); a rough one traces no ray here and
 * reflects the ambient light. */
static void clear_coat_reflects_fresnels_share(void **state)
{
    (void)state;
    Scene *s = empty_scene();
    s->background = v3_splat(1);
    Material varnish = {.kd = v3_splat(0), .coat = 1, .shininess = 1, .texture = -1};
    uint32_t mv;
    assert_int_equal(scene_add_material(s, varnish, &mv, NULL), 0);
    assert_int_equal(scene_add_sphere(s, (Sphere){v3(0, 0, 0), 1, mv}, NULL), 0);
    const vec3 eye = v3(0, 0, 5);
    prepare(s);
    assert_float_equal(look(s, eye, v3(0, 0, 0)).x, R(0.04), R(1e-5));
    const real rim = look(s, eye, v3(R(0.97), 0, 0)).x;
    assert_true(rim > R(0.1) && rim < R(1));
    s->materials[mv].coat = R(0.5);
    prepare(s);
    assert_float_equal(look(s, eye, v3(0, 0, 0)).x, R(0.02), R(1e-5));
    s->materials[mv] = (Material){.kd = v3_splat(1), .coat = 1, .shininess = 1, .texture = -1};
    s->background = v3_splat(0);
    s->ambient = v3_splat(1);
    prepare(s);
    assert_float_equal(look(s, eye, v3(0, 0, 0)).x, R(0.96), R(1e-5));
    /* rough: no ray; the coat reflects the ambient light, so a white one
     * under the ambient light is white, at the rim too (it was dark
     * there, where Fresnel's share nears 1), and no background */
    s->materials[mv].coat_roughness = R(0.5);
    prepare(s);
    assert_float_equal(look(s, eye, v3(0, 0, 0)).x, R(1), R(1e-5));
    assert_float_equal(look(s, eye, v3(R(0.97), 0, 0)).x, R(1), R(1e-5));
    s->background = v3_splat(1);
    s->ambient = v3_splat(0);
    prepare(s);
    assert_float_equal(look(s, eye, v3(0, 0, 0)).x, R(0), R(1e-6));
    scene_destroy(s);
}

/* A model's own glass absorbs per unit of the model (glTF's attenuation
 * distance is the model's): an instance scaled by 2 doubles the world's
 * path through it, not the light it absorbs; a scene material set on the
 * instance absorbs per unit of the world, so there it doubles.  Glass of
 * index 1 (no bend, no Fresnel reflection) before a white background: a
 * ray along one line of the model keeps exp(-absorb x length).  Before the
 * fix the model's glass absorbed per unit of the world (ratio 2). */
static void scaled_instance_absorbs_in_model_units(void **state)
{
    (void)state;
    const Material glass = {.kd = v3_splat(0), .kt = v3_splat(1), .ior = 1, .absorb = v3_splat(R(0.3)),
                            .shininess = 1, .texture = -1};
    real logt[2][2]; /* [override][scale 1, 2] */
    for (int over = 0; over < 2; over++)
        for (int k = 0; k < 2; k++) {
            Scene *s = empty_scene();
            s->background = v3_splat(1);
            s->ambient = v3_splat(0);
            uint32_t id, gm;
            Model *ball = sphere_model_of(16, 8, &glass);
            assert_int_equal(scene_add_model(s, ball, &id, NULL), 0);
            assert_int_equal(scene_add_material(s, glass, &gm, NULL), 0);
            Instance in = instance_make(id, v3_splat(0), v3_splat(0), k ? 2 : 1);
            in.material = over ? (int32_t)gm : -1;
            assert_int_equal(scene_add_instance(s, in, NULL), 0);
            prepare(s);
            const real x = R(0.05) * (real)(k + 1), y = R(0.07) * (real)(k + 1); /* one line of the model */
            const vec3 c = look(s, v3(x, y, 10), v3(x, y, 0));
            assert_true(c.x > 0 && c.x < R(0.9));
            logt[over][k] = log(c.x);
            scene_destroy(s);
        }
    print_message("absorbed through scale 2 over scale 1: model's glass %.4f, scene's %.4f\n",
                  (double)(logt[0][1] / logt[0][0]), (double)(logt[1][1] / logt[1][0]));
    assert_float_equal(logt[0][1] / logt[0][0], 1, 1e-3);
    assert_float_equal(logt[1][1] / logt[1][0], 2, 1e-3);
}

static void textured_triangle_and_instances(void **state)
{
    (void)state;
    Scene *s = empty_scene();
    s->ambient = v3_splat(1); /* colour = texture exactly */
    const uint8_t px[12] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255};
    uint32_t tex, mat;
    assert_int_equal(scene_add_texture(s, texture_from_rgb8(2, 2, px), &tex, NULL), 0);
    Material m = {.kd = v3(1, 1, 1), .ks = v3(0, 0, 0), .shininess = 1, .texture = (int32_t)tex};
    assert_int_equal(scene_add_material(s, m, &mat, NULL), 0);
    const vec3 p[3] = {v3(0, 0, 0), v3(2, 0, 0), v3(0, 2, 0)};
    const real uv[6] = {0, 0, 1, 0, 0, 1};
    assert_int_equal(scene_add_triangle(s, p, NULL, uv, mat, NULL), 0);
    s->settings.filter = FILTER_NEAREST;
    prepare(s);
    /* (0.5, 0.5) has uv (0.25, 0.25): the bottom-left texel, blue */
    vec3 c = look(s, v3(R(0.5), R(0.5), 3), v3(R(0.5), R(0.5), 0));
    assert_float_equal(c.z, 1, 0);
    assert_float_equal(c.x, 0, 0);
    /* an instance: a unit triangle model scaled by 3, turned 90 degrees about y, moved to x = 10 */
    Mesh mesh;
    assert_int_equal(mesh_init(&mesh, 0, NULL), 0);
    const vec3 q[3] = {v3(0, 0, 0), v3(1, 0, 0), v3(0, 1, 0)};
    assert_int_equal(mesh_add(&mesh, q, NULL, NULL, NULL, 0, NULL), 0);
    Model *model = sah_model(&mesh);
    uint32_t mid;
    assert_int_equal(scene_add_model(s, model, &mid, NULL), 0);
    assert_int_equal(scene_add_instance(s, instance_make(mid, v3(10, 0, 0), v3(0, 90, 0), 3), NULL), 0);
    prepare(s);
    /* rotating +x by 90 degrees about y gives -z: the model's (1,0,0) lands at (10, 0, -3) */
    Ray r = ray_make(v3(20, R(0.5), R(-1)), v3(-1, 0, 0), 0, REAL_INF);
    Hit h;
    assert_true(trace_closest(world_now(s), &r, &h));
    assert_int_equal(h.kind, HIT_INSTANCE);
    assert_float_equal(h.t, 10, R(1e-5));
    Surface sf;
    trace_surface(world_now(s), &r, &h, &sf);
    assert_float_equal(sf.ng.x, 1, R(1e-5)); /* faces the ray */
    assert_float_equal(sf.p.z, -1, R(1e-5));
    r = ray_make(v3(20, R(0.5), R(-3.5)), v3(-1, 0, 0), 0, REAL_INF); /* beyond the scaled edge */
    assert_false(trace_closest(world_now(s), &r, &h));
    scene_destroy(s);
}

/* The coarse sphere with one more small triangle far in front of it: the
 * same triangles, so hits on the sphere tie exactly with the plain model's,
 * but a box that a ray from +z enters first. */
static Model *sphere_with_fin(void)
{
    Model *plain = coarse_sphere();
    Mesh m;
    assert_int_equal(mesh_init(&m, MESH_NORMALS, NULL), 0);
    for (uint32_t i = 0; i < plain->tri_count; i++) {
        vec3 p[3], n[3];
        for (int k = 0; k < 3; k++)
            p[k] = tri_vertex(&plain->tris[i], k), n[k] = plain->normals[3 * i + k];
        assert_int_equal(mesh_add(&m, p, n, NULL, NULL, 0, NULL), 0);
    }
    const vec3 fin[3] = {v3(-3, -3, 6), v3(R(-2.9), -3, 6), v3(-3, R(-2.9), 6)};
    assert_int_equal(mesh_add(&m, fin, fin, NULL, NULL, 0, NULL), 0);
    model_destroy(plain);
    Model *model = sah_model(&m);
    return model;
}

/* A small model's transformed instance is traced as a placed copy
 * (world.h WorldInstance.placed; an untransformed or large one is not):
 * on every SIMD path its hits are the model's own, found with the ray
 * moved into model space, within rounding (the same triangle away from
 * its edges, the same distance to 1e-5), and a packet's rays find alone
 * exactly what they find in the packet. */
static void small_instances_are_placed(void **state)
{
    (void)state;
    Scene *s = empty_scene();
    uint32_t small, big;
    assert_int_equal(scene_add_model(s, sphere_model(6, 4), &small, NULL), 0);
    assert_int_equal(scene_add_model(s, coarse_sphere(), &big, NULL), 0);
    const vec3 at = v3(5, R(0.2), R(-1)), turn = v3(10, 35, 20);
    const real scale = R(0.7);
    assert_int_equal(scene_add_instance(s, instance_make(small, at, turn, scale), NULL), 0);
    assert_int_equal(scene_add_instance(s, instance_make(small, v3_splat(0), v3_splat(0), 1), NULL), 0);
    assert_int_equal(scene_add_instance(s, instance_make(big, v3(-5, 0, 0), turn, scale), NULL), 0);
    const Model *m = s->models[small];
    assert_true(m->tri_count <= WORLD_PLACED_TRIS && s->models[big]->tri_count > WORLD_PLACED_TRIS);
    const mat3 rot = m3_rotation_xyz(turn);
    int compared = 0;
    for (int path = -1; simd_next(&path);) {
        const World *w = world_now(s);
        assert_non_null(w->instances[0].placed);
        assert_null(w->instances[1].placed);
        assert_null(w->instances[2].placed);
        const vec3 eyes[2] = {v3(5, R(0.5), 3), v3(R(2.5), 2, R(-2.5))}; /* the others out of sight */
        for (int e = 0; e < 2; e++)
            for (int y = 0; y < 24; y++)
                for (int x0 = 0; x0 < 24; x0 += TRACE_PACKET) {
                    Ray rays[TRACE_PACKET];
                    for (int i = 0; i < TRACE_PACKET; i++) {
                        const vec3 target = v3_add(at, v3(R(-0.9) + R(0.075) * (real)(x0 + i), R(0.9) - R(0.075) * (real)y, 0));
                        rays[i] = ray_make(eyes[e], v3_norm(v3_sub(target, eyes[e])), 0, REAL_INF);
                    }
                    Hit hp[TRACE_PACKET];
                    trace_closest_packet(w, rays, TRACE_PACKET, hp);
                    for (int i = 0; i < TRACE_PACKET; i++) {
                        Hit h;
                        const int got = trace_closest(w, &rays[i], &h);
                        assert_int_equal(got, hp[i].kind != HIT_NONE);
                        assert_true(!got || (h.index == hp[i].index && h.sub == hp[i].sub && h.t == hp[i].t &&
                                             h.b1 == hp[i].b1 && h.b2 == hp[i].b2));
                        /* the ray in model space: R^T (o - T) / s, R^T d / s */
                        const Ray mr = ray_make(v3_scale(m3_apply_t(&rot, v3_sub(rays[i].org, at)), R(1) / scale),
                                                v3_scale(m3_apply_t(&rot, rays[i].dir), R(1) / scale), 0, REAL_INF);
                        ModelHit ref;
                        const int want = model_intersect(m, &mr, REAL_INF, 0, &ref);
                        const real edge = want ? fmin(fmin(ref.b1, ref.b2), R(1) - ref.b1 - ref.b2) : 1;
                        const real hedge = got ? fmin(fmin(h.b1, h.b2), R(1) - h.b1 - h.b2) : 1;
                        if (edge < R(1e-3) || hedge < R(1e-3))
                            continue; /* an edge: either triangle, or the silhouette, by rounding */
                        if (got != want)
                            fail_msg("%s: eye %d ray %d,%d: placed %s (kind %d #%u t %.9g), model %s", simd_name((SimdPath)path),
                                     e, x0 + i, y, got ? "hit" : "missed", h.kind, h.index, (double)h.t, want ? "hit" : "missed");
                        if (!want)
                            continue;
                        if (h.kind != HIT_INSTANCE || h.index != 0 || h.sub != ref.tri || fabs(h.t - ref.t) > R(1e-5) * ref.t)
                            fail_msg("%s: ray %d,%d: placed kind %d #%u tri %u t %.9g, model tri %u t %.9g",
                                     simd_name((SimdPath)path), x0 + i, y, h.kind, h.index, h.sub, (double)h.t,
                                     ref.tri, (double)ref.t);
                        compared++;
                    }
                }
    }
    scene_destroy(s);
    assert_true(compared > 200);
}

/* Rays traced by pairs (trace_closest_pair: a path's bounces) and each
 * alone (trace_closest_each: rays that part) get, on every SIMD path,
 * the hit each gets alone, in a world of one model (its walks by pairs),
 * of one model and a plane (ray by ray), and of spheres, a triangle,
 * instances and a plane (the top tree's walks by pairs): rays from random
 * points in random directions, from points on the surfaces outward (as
 * bounces), a ray of NaN, and limits short of the hits. */
static void pairs_equal_single_rays(void **state)
{
    (void)state;
    int compared = 0;
    for (int kind = 0; kind < 3; kind++) {
        Scene *s = empty_scene();
        uint32_t ball;
        assert_int_equal(scene_add_model(s, sphere_model(24, 12), &ball, NULL), 0);
        assert_int_equal(scene_add_instance(s, instance_make(ball, v3(0, 0, 0), v3(0, 0, 0), 1), NULL), 0);
        if (kind >= 1)
            assert_int_equal(scene_add_plane(s, plane_make(v3(0, -1, 0), v3(0, 1, 0), 0), NULL), 0);
        if (kind == 2) {
            for (int i = 0; i < 12; i++) {
                const vec3 c = v3(R(-3) + R(0.5) * (real)i, R(0.4) * (real)(i % 3), R(-1.5));
                assert_int_equal(scene_add_sphere(s, (Sphere){c, R(0.3), 0}, NULL), 0);
            }
            const vec3 flat[3] = {v3(-2, R(-0.5), -2), v3(2, R(-0.5), -2), v3(0, R(-0.5), 2)};
            assert_int_equal(scene_add_triangle(s, flat, NULL, NULL, 0, NULL), 0);
            assert_int_equal(
                scene_add_instance(s, instance_make(ball, v3(R(1.5), R(0.2), R(-1)), v3(10, 35, 0), R(0.7)), NULL), 0);
        }
        for (int path = -1; simd_next(&path);) {
            const World *w = world_now(s);
            Rng rng = {0x9e3779b97f4a7c15ull + (uint64_t)kind};
            for (int k = 0; k < 400; k++) {
                Ray rays[TRACE_PACKET];
                const int n = 1 + k % TRACE_PACKET;
                for (int i = 0; i < n; i++) {
                    vec3 o = rng_vec(&rng, -3, 3), d = rng_dir(&rng);
                    if (k % 2) { /* a bounce: from the ball's surface, outward or inward */
                        const vec3 on = rng_dir(&rng);
                        o = on;
                        d = v3_norm(v3_add(on, v3_scale(rng_dir(&rng), k % 4 == 1 ? R(0.9) : R(3))));
                    }
                    rays[i] = ray_make(o, d, R(1e-4), k % 5 == 4 ? rng_real(&rng, R(0.1), 2) : REAL_INF);
                    if (k % 37 == 36 && i == 0)
                        rays[i].dir.y = (real)NAN;
                }
                Hit hp[TRACE_PACKET], he[TRACE_PACKET];
                uint32_t got_pairs = 0;
                for (int i = 0; i + 1 < n; i += 2)
                    got_pairs |= trace_closest_pair(w, &rays[i], &rays[i + 1], &hp[i], &hp[i + 1]) << i;
                if (n % 2)
                    got_pairs |= (uint32_t)trace_closest(w, &rays[n - 1], &hp[n - 1]) << (n - 1);
                trace_closest_each(w, rays, n, he);
                for (int i = 0; i < n; i++) {
                    Hit h;
                    const int got = trace_closest(w, &rays[i], &h);
                    const Hit *other[2] = {&hp[i], &he[i]};
                    assert_int_equal(got, (int)(got_pairs >> i & 1));
                    for (int j = 0; j < 2; j++) {
                        const Hit *o = other[j];
                        if (got != (o->kind != HIT_NONE) ||
                            (got && (h.kind != o->kind || h.index != o->index || h.sub != o->sub || h.t != o->t ||
                                     h.b1 != o->b1 || h.b2 != o->b2)))
                            fail_msg("%s, world %d, %s %d ray %d: kind %d #%u/%u t %.9g, alone kind %d #%u/%u t %.9g",
                                     simd_name((SimdPath)path), kind, j ? "each" : "pair", k, i, o->kind, o->index,
                                     o->sub, (double)o->t, h.kind, h.index, h.sub, (double)h.t);
                    }
                    compared += got;
                }
            }
        }
        scene_destroy(s);
    }
    assert_true(compared > 1000);
}

/* An area light's points for a packet's shading, lane by lane
 * (shade_light_points: area_dirs, sphere_offsets, rect_offsets), are the
 * scalar code's (shade_light_point: area_point, light_towards) to the
 * bit: direction, distance and radiance, for round and rectangular lights
 * with and without falloff, seen from random points, points on the
 * light's axes and its centre's level, and (u, v) at the square's centre,
 * corners and edges. */
static void area_light_lanes_equal_scalar(void **state)
{
    (void)state;
    Scene *s = empty_scene();
    const vec3 white = v3(1, 1, 1);
    const Light lights[4] = {
        light_sphere(v3(R(0.3), 2, R(-0.7)), R(0.25), 3, v3(1, R(0.8), R(0.6)), R(0.9), 1),
        light_sphere(v3(-1, R(1.5), 1), R(0.1), 2, white, R(0.5), 0),
        light_rect(v3(-1, 3, -1), v3(2, 0, 0), v3(0, 0, R(1.5)), 2, white, R(0.4), 1),
        /* tilted: every coordinate of a point takes both edges */
        light_rect(v3(2, 1, -1), v3(1, 0, 1), v3(R(0.6), 1, R(-0.6)), 2, v3(R(0.5), 1, 1), R(0.3), 0),
    };
    for (int i = 0; i < 4; i++)
        assert_int_equal(scene_add_light(s, lights[i], NULL), 0);
    const World *w = world_now(s);
    Rng rng = {12345};
    const real edges[5] = {R(0), R(0.5), R(1) - REAL_EPS / 2, R(0.25), R(0.75)};
    int compared = 0;
    for (uint32_t li = 0; li < w->light_count; li++) {
        const vec3 c = w->lights[li].pos;
        for (int round = 0; round < 200; round++) {
            vec3 at[TRACE_PACKET];
            real u[TRACE_PACKET], v[TRACE_PACKET];
            const int n = 1 + round % TRACE_PACKET;
            for (int k = 0; k < n; k++) {
                at[k] = rng_vec(&rng, -3, 3);
                if (round % 4 == 1) /* straight below or beside the light: its frame's other branch */
                    at[k].e[k % 3] = c.e[k % 3];
                if (round % 4 == 2)
                    at[k] = v3_add(c, v3((real)(k % 2), k % 2 ? R(0) : R(-1), R(0)));
                u[k] = round % 3 == 0 ? edges[k % 5] : rng_real(&rng, 0, 1);
                v[k] = round % 3 == 0 ? edges[(k + round / 3) % 5] : rng_real(&rng, 0, 1);
            }
            vec3 dl[TRACE_PACKET], rl[TRACE_PACKET];
            real tl[TRACE_PACKET];
            const uint32_t ok = shade_light_points(w, li, n, at, u, v, dl, tl, rl);
            for (int k = 0; k < n; k++) {
                vec3 d, r;
                real t;
                const int got = shade_light_point(w, li, &at[k], u[k], v[k], &d, &t, &r);
                assert_int_equal(got, (int)(ok >> k & 1));
                if (!got)
                    continue;
                if (d.x != dl[k].x || d.y != dl[k].y || d.z != dl[k].z || t != tl[k] || r.x != rl[k].x ||
                    r.y != rl[k].y || r.z != rl[k].z)
                    fail_msg("light %u point %d (%g %g %g) at (%g, %g): lanes dir (%.9g %.9g %.9g) dist %.9g rad %.9g, "
                             "scalar (%.9g %.9g %.9g) %.9g %.9g",
                             li, k, (double)at[k].x, (double)at[k].y, (double)at[k].z, (double)u[k], (double)v[k],
                             (double)dl[k].x, (double)dl[k].y, (double)dl[k].z, (double)tl[k], (double)rl[k].x,
                             (double)d.x, (double)d.y, (double)d.z, (double)t, (double)r.x);
                compared++;
            }
        }
    }
    scene_destroy(s);
    assert_true(compared > 2000);
}

/* Packets give every ray the hit, the colour and the shadow answer it gets
 * alone, on every SIMD path, in scenes built for ties: the coarse sphere
 * twice at one place, as a plain model and with a fin that makes a single
 * ray visit it first (instances added in both orders: the lower index must
 * win either way), a third instance turned and scaled, a sphere through the
 * model, a triangle lying in a plane (ties with the plane), and a light. */
static void packets_equal_single_rays(void **state)
{
    (void)state;
    int ties = 0, packets = 0;
    /* orders 0 and 1: two instances tied at one place, in both orders,
     * beside a plane, a triangle, a sphere and a third instance; 2: a
     * world of one untransformed model (trace.c's shortcut to its walk);
     * 3: the same beside a plane (no shortcut) */
    for (int order = 0; order < 4; order++) {
        const int lone = order >= 2;
        Scene *s = empty_scene();
        Material red = {.kd = v3(1, R(0.2), R(0.2)), .ks = v3(R(0.5), R(0.5), R(0.5)), .shininess = 20, .texture = -1};
        uint32_t mat;
        assert_int_equal(scene_add_material(s, red, &mat, NULL), 0);
        if (order != 2)
            assert_int_equal(scene_add_plane(s, plane_make(v3(0, -1, 0), v3(0, 1, 0), 0), NULL), 0);
        const vec3 flat[3] = {v3(-2, -1, -2), v3(2, -1, -2), v3(0, -1, 2)};
        uint32_t plain, fin;
        assert_int_equal(scene_add_model(s, coarse_sphere(), &plain, NULL), 0);
        assert_int_equal(scene_add_model(s, sphere_with_fin(), &fin, NULL), 0);
        if (lone) {
            assert_int_equal(scene_add_instance(s, instance_make(fin, v3(0, 0, 0), v3(0, 0, 0), 1), NULL), 0);
        } else {
            assert_int_equal(scene_add_triangle(s, flat, NULL, NULL, mat, NULL), 0);
            assert_int_equal(scene_add_sphere(s, (Sphere){v3(R(0.7), R(0.3), 0), R(0.5), mat}, NULL), 0);
            assert_int_equal(scene_add_instance(s, instance_make(order ? fin : plain, v3(0, 0, 0), v3(0, 0, 0), 1), NULL),
                             0);
            assert_int_equal(scene_add_instance(s, instance_make(order ? plain : fin, v3(0, 0, 0), v3(0, 0, 0), 1), NULL),
                             0);
            assert_int_equal(
                scene_add_instance(s, instance_make(plain, v3(R(1.5), R(0.2), R(-1)), v3(10, 35, 0), R(0.7)), NULL), 0);
        }
        assert_int_equal(scene_add_light(s, light_point(v3(3, 4, 5), v3(1, 1, 1), 1, 0), NULL), 0);
        for (int path = -1; simd_next(&path);) {
            const World *w = world_now(s);
            assert_int_equal(w->lone_model, lone);
            const vec3 eyes[3] = {v3(0, R(0.5), 4), v3(R(3.5), 2, R(-0.5)), v3(R(0.01), 5, R(0.02))};
            for (int e = 0; e < 3; e++)
                for (int y = 0; y < 40; y++)
                    for (int x0 = 0; x0 < 40; x0 += TRACE_PACKET) {
                        Ray rays[TRACE_PACKET];
                        int n = 1 + (x0 / TRACE_PACKET + y) % TRACE_PACKET; /* every packet size */
                        for (int i = 0; i < n; i++) {
                            vec3 target = v3(R(-2) + R(0.1) * (real)(x0 + i), R(1.5) - R(0.1) * (real)y, 0);
                            rays[i] = ray_make(eyes[e], v3_norm(v3_sub(target, eyes[e])), 0, REAL_INF);
                        }
                        Hit hp[TRACE_PACKET];
                        trace_closest_packet(w, rays, n, hp);
                        vec3 cp[TRACE_PACKET];
                        uint64_t kp[TRACE_PACKET];
                        RayStats st = {0, 0, 0};
                        shade_packet(w, rays, n, cp, &st, kp, NULL, NULL);
                        real tm[TRACE_PACKET], far[TRACE_PACKET];
                        for (int i = 0; i < n; i++)
                            tm[i] = hp[i].kind ? hp[i].t * R(0.5) : R(100), far[i] = R(100);
                        uint32_t blocked = trace_occluded_packet(w, rays, n, tm, NULL);
                        /* and the limits past the hits: blocked where they hit */
                        uint32_t blocked_far = trace_occluded_packet(w, rays, n, far, NULL);
                        for (int i = 0; i < n; i++) {
                            Hit h;
                            int got = trace_closest(w, &rays[i], &h);
                            assert_int_equal(got, hp[i].kind != HIT_NONE);
                            if (got && (h.kind != hp[i].kind || h.index != hp[i].index || h.sub != hp[i].sub ||
                                        h.t != hp[i].t || h.b1 != hp[i].b1 || h.b2 != hp[i].b2))
                                fail_msg("%s, order %d: eye %d ray (%d,%d): packet kind %d #%u/%u t %.9g, alone kind "
                                         "%d #%u/%u t %.9g",
                                         simd_name((SimdPath)path), order, e, x0 + i, y, hp[i].kind, hp[i].index,
                                         hp[i].sub, (double)hp[i].t, h.kind, h.index, h.sub, (double)h.t);
                            /* the two instances at one place tie on the sphere: the first wins */
                            ModelHit first;
                            if (got && h.kind == HIT_INSTANCE && h.index == 1 &&
                                model_intersect(s->models[s->instances[0].model], &rays[i], REAL_INF, 0, &first) &&
                                first.t == h.t)
                                fail_msg("%s, order %d: ray (%d,%d) took the second of two tied instances",
                                         simd_name((SimdPath)path), order, x0 + i, y);
                            ties += got && h.kind == HIT_INSTANCE && h.index == 0;
                            uint64_t key;
                            RayStats st1 = {0, 0, 0};
                            vec3 c = shade_ray(w, &rays[i], &st1, &key);
                            if (memcmp(&c, &cp[i], sizeof c) != 0 || key != kp[i])
                                fail_msg("%s: ray (%d,%d): packet colour differs", simd_name((SimdPath)path), x0 + i, y);
                            assert_int_equal((int)(blocked >> i & 1), trace_occluded(w, &rays[i], tm[i], NULL));
                            assert_int_equal((int)(blocked_far >> i & 1), trace_occluded(w, &rays[i], far[i], NULL));
                        }
                        packets++;
                    }
        }
        scene_destroy(s);
    }
    assert_true(ties > 100);
    assert_true(packets > 100);
}

/* The built-in default scene (a bit of everything). */
static Scene *default_scene(void)
{
    Scene *s;
    BvhOptions opt = bvh_options_default(BVH_SAH);
    Err err;
    if (scene_default(&s, &opt, &err))
        fail_msg("%s", err.msg);
    return s;
}

static uint8_t *render_all(RenderPool *p, Scene *s, int w, int h, int segment)
{
    uint8_t *px = malloc((size_t)w * h * 3);
    Err err;
    const World *world = world_now(s);
    for (int y = 0; y < h; y += segment) {
        int n = y + segment <= h ? segment : h - y;
        if (render_lines(p, world, w, h, y, n, px + (size_t)y * w * 3, NULL, &err))
            fail_msg("%s", err.msg);
    }
    return px;
}

static void pixels_do_not_depend_on_threads_or_segments(void **state)
{
    (void)state;
    Scene *s = default_scene();
    Err err;
    RenderPool *one = render_pool_create(1, &err), *three = render_pool_create(3, &err);
    const int W = 97, H = 61;
    for (int mode = 0; mode < 3; mode++) {
        s->settings.aa = mode == 0 ? 1 : 3;
        s->settings.adaptive = mode == 2;
        uint8_t *ref = render_all(one, s, W, H, H);
        const int segments[] = {1, 2, 7, 13, 60};
        for (int i = 0; i < 5; i++) {
            uint8_t *px = render_all(three, s, W, H, segments[i]);
            assert_memory_equal(ref, px, (size_t)W * H * 3);
            free(px);
        }
        /* and the frame is not blank: the scene is in view */
        int distinct = 0;
        for (int i = 3; i < W * H * 3; i += 3)
            distinct += memcmp(ref + i, ref, 3) != 0;
        assert_true(distinct > W * H / 2);
        free(ref);
    }
    render_pool_destroy(one);
    render_pool_destroy(three);
    scene_destroy(s);
}

/* A Whitted frame's guides (settings guides, a moving frame's for the
 * server's history): the colours are the frame's without them, byte for
 * byte, and each pixel's guide is its camera ray's first hit (the
 * distance to 16 bits of its float; 0 where it met nothing; the instance
 * it is of), the mirror and glass balls' too; with settings denoise alone the guides stay empty
 * (a Whitted frame passes the filter as it is); guides are refused on a
 * path-traced frame. */
static void whitted_guides_are_first_hits(void **state)
{
    (void)state;
    Scene *s = default_scene();
    Err err;
    RenderPool *pool = render_pool_create(2, &err);
    const int W = 80, H = 60;
    const size_t n = (size_t)W * H, bpp = 3 + DENOISE_GUIDE_BYTES;
    uint8_t *plain = render_all(pool, s, W, H, H), *guided = malloc(n * bpp);
    for (int mode = 0; mode < 2; mode++) {
        s->settings.guides = mode == 0, s->settings.denoise = mode == 1;
        const World *world = world_now(s);
        if (render_lines(pool, world, W, H, 0, H, guided, NULL, &err))
            fail_msg("%s", err.msg);
        const CameraFrame cf = camera_frame(&world->view.camera, W, H);
        int surfaces = 0, sky = 0, knot = 0;
        for (size_t i = 0; i < n; i++) {
            const uint8_t *p = guided + i * bpp;
            assert_memory_equal(p, plain + i * 3, 3);
            float albedo[3], normal[3], depth, noise;
            denoise_guide_unpack(p + 3, albedo, normal, &depth, &noise);
            vec3 o, d;
            Hit hit;
            assert_true(camera_ray(&cf, (real)(i % W) + R(0.5), (real)(i / W) + R(0.5), &o, &d));
            const Ray r = ray_make(o, d, 0, REAL_INF);
            if (mode == 1 || !trace_closest(world, &r, &hit)) {
                assert_true(depth == 0.0f);
                sky += mode == 0;
                continue;
            }
            assert_true(fabs((double)depth - (double)hit.t) <= (double)hit.t * 0x1p-8);
            /* the normal faces the ray */
            assert_true(normal[0] * (float)d.x + normal[1] * (float)d.y + normal[2] * (float)d.z <= 0.01f);
            /* the instance it is of (the knot), for a turning model's history */
            assert_int_equal(denoise_guide_instance(p + 3), hit.kind == HIT_INSTANCE ? hit.index + 1 : 0);
            knot += hit.kind == HIT_INSTANCE;
            surfaces++;
        }
        if (mode == 0) {
            print_message("guides: %d pixels of surfaces (%d of the knot), %d of the sky\n", surfaces, knot, sky);
            assert_true(surfaces > (int)n / 2 && sky > 0 && knot > 0);
        }
    }
    s->settings.denoise = 0, s->settings.guides = 1, s->settings.integrator = INTEGRATOR_PATH;
    char why[200];
    assert_non_null(settings_problem(&s->settings, why, sizeof why));
    s->settings.integrator = INTEGRATOR_WHITTED;
    assert_null(settings_problem(&s->settings, why, sizeof why));
    free(plain);
    free(guided);
    render_pool_destroy(pool);
    scene_destroy(s);
}

/* A path-traced frame's guides (settings denoise) stop at curved glass:
 * where the camera ray meets the default scene's glass ball, in the ball's
 * inside (the pixel and its four neighbours on it), the guide's distance
 * is the ball's surface (it was what each sample saw through it, farther
 * and different from pixel to pixel: path.c guide_lens). */
static void path_guides_stop_at_a_glass_ball(void **state)
{
    (void)state;
    Scene *s = default_scene();
    s->settings.integrator = INTEGRATOR_PATH, s->settings.denoise = 1;
    Err err;
    RenderPool *pool = render_pool_create(2, &err);
    const int W = 80, H = 60;
    const size_t bpp = 3 + DENOISE_GUIDE_BYTES;
    uint8_t *px = malloc((size_t)W * H * bpp);
    const World *world = world_now(s);
    if (render_lines(pool, world, W, H, 0, H, px, NULL, &err))
        fail_msg("%s", err.msg);
    const CameraFrame cf = camera_frame(&world->view.camera, W, H);
    int glass = 0;
    for (int y = 1; y + 1 < H; y++)
        for (int x = 1; x + 1 < W; x++) {
            real t = 0;
            int on = 1;
            for (int k = 0; k < 5 && on; k++) { /* the pixel and its four neighbours, all on a glass sphere */
                const int dx = k == 1 ? -1 : k == 2 ? 1 : 0, dy = k == 3 ? -1 : k == 4 ? 1 : 0;
                vec3 o, d;
                Hit hit;
                assert_true(camera_ray(&cf, (real)(x + dx) + R(0.5), (real)(y + dy) + R(0.5), &o, &d));
                const Ray r = ray_make(o, d, 0, REAL_INF);
                Surface sf;
                on = trace_closest(world, &r, &hit) && hit.kind == HIT_SPHERE;
                if (on) {
                    trace_surface(world, &r, &hit, &sf);
                    on = material_dielectric(sf.mat);
                }
                t = k == 0 ? hit.t : t;
            }
            if (!on)
                continue;
            float albedo[3], normal[3], depth, noise;
            denoise_guide_unpack(px + ((size_t)y * W + x) * bpp + 3, albedo, normal, &depth, &noise);
            if (!(fabs((double)depth - (double)t) <= 0.05 * (double)t))
                fail_msg("pixel %d %d on the glass ball: guide distance %g, the ball at %g", x, y, (double)depth, (double)t);
            glass++;
        }
    print_message("guides at the glass ball: %d pixels\n", glass);
    assert_true(glass > 10);
    free(px);
    render_pool_destroy(pool);
    scene_destroy(s);
}

/* Segments that start and end inside lines (what the scheduler's adaptive
 * tail makes) give the same pixels as the whole frame; cancel stops work. */
static void partial_line_spans_and_cancel(void **state)
{
    (void)state;
    Scene *s;
    BvhOptions opt = bvh_options_default(BVH_SAH);
    assert_int_equal(scene_default(&s, &opt, NULL), 0);
    RenderPool *p = render_pool_create(2, NULL);
    const int W = 53, H = 29;
    const uint64_t N = (uint64_t)W * H;
    uint8_t *ref = malloc(N * 3), *px = malloc(N * 3);
    for (int mode = 0; mode < 3; mode++) {
        s->settings.aa = mode == 0 ? 1 : 2;
        s->settings.adaptive = mode == 2;
        assert_int_equal(render_span(p, world_now(s), W, H, 0, N, ref, NULL, NULL, NULL), 0);
        const uint64_t sizes[3] = {1, 37, 150};
        for (int k = 0; k < 3; k++) {
            memset(px, 0, N * 3);
            for (uint64_t a = 0; a < N; a += sizes[k]) {
                uint64_t n = a + sizes[k] <= N ? sizes[k] : N - a;
                assert_int_equal(render_span(p, world_now(s), W, H, a, n, px + 3 * a, NULL, NULL, NULL), 0);
            }
            assert_memory_equal(ref, px, N * 3);
        }
    }
    atomic_int cancel = 1;
    RayStats st;
    assert_int_equal(render_span(p, world_now(s), W, H, 0, N, px, &st, &cancel, NULL), RENDER_CANCELLED);
    assert_int_equal(st.primary, 0);
    Err err = {{0}};
    assert_int_equal(render_span(p, world_now(s), W, H, N - 5, 6, px, NULL, NULL, &err), -1);
    assert_contains(err.msg, "outside a frame");
    free(ref);
    free(px);
    render_pool_destroy(p);
    scene_destroy(s);
}

static void adaptive_refines_only_edges(void **state)
{
    (void)state;
    Scene *s;
    BvhOptions opt = bvh_options_default(BVH_SAH);
    assert_int_equal(scene_default(&s, &opt, NULL), 0);
    RenderPool *p = render_pool_create(2, NULL);
    const int W = 160, H = 120;
    uint8_t *px = malloc(W * H * 3);
    RayStats plain, adaptive, full;
    s->settings.aa = 4;
    assert_int_equal(render_lines(p, world_now(s), W, H, 0, H, px, &full, NULL), 0);
    s->settings.adaptive = 1;
    assert_int_equal(render_lines(p, world_now(s), W, H, 0, H, px, &adaptive, NULL), 0);
    s->settings.aa = 1;
    s->settings.adaptive = 0;
    assert_int_equal(render_lines(p, world_now(s), W, H, 0, H, px, &plain, NULL), 0);
    assert_int_equal(plain.primary, W * H);
    assert_int_equal(full.primary, 16 * W * H);
    /* more than one sample per pixel, far fewer than 16 */
    assert_true(adaptive.primary > plain.primary + W * H / 20);
    assert_true(adaptive.primary < full.primary / 2);
    free(px);
    render_pool_destroy(p);
    scene_destroy(s);
}

/* A texture's edges show in no key (one triangle, no lights): adaptive
 * sampling finds them by the contrast of neighbouring samples, and comes
 * out far nearer the full 4x4 image than one sample does.  Without the
 * contrast rule (contrast 255) it refines only the triangle's edge. */
static void adaptive_refines_texture_edges(void **state)
{
    (void)state;
    Scene *s = empty_scene();
    s->ambient = v3_splat(1); /* colour = texture */
    const uint8_t checker[12] = {0, 0, 0, 255, 255, 255, 255, 255, 255, 0, 0, 0};
    uint32_t tex, mat;
    assert_int_equal(scene_add_texture(s, texture_from_rgb8(2, 2, checker), &tex, NULL), 0);
    Material m = {.kd = v3(1, 1, 1), .ks = v3(0, 0, 0), .shininess = 1, .texture = (int32_t)tex};
    assert_int_equal(scene_add_material(s, m, &mat, NULL), 0);
    /* one triangle filling the view, the checker turned and repeated on it */
    const vec3 p3[3] = {v3(-10, -10, 0), v3(10, -10, 0), v3(-10, 10, 0)};
    const real uv[6] = {0, 0, R(7.3), R(2.1), R(-2.1), R(7.3)};
    assert_int_equal(scene_add_triangle(s, p3, NULL, uv, mat, NULL), 0);
    s->settings.filter = FILTER_NEAREST; /* hard texel edges */
    assert_int_equal(camera_look_at(&s->camera, v3(0, 0, 4), v3(0, 0, 0), 0, 1), 0);
    prepare(s);
    RenderPool *p = render_pool_create(2, NULL);
    const int W = 96, H = 72;
    uint8_t *one = malloc(W * H * 3), *ad = malloc(W * H * 3), *full = malloc(W * H * 3);
    RayStats st_one, st_ad, st_full;
    assert_int_equal(render_lines(p, world_now(s), W, H, 0, H, one, &st_one, NULL), 0);
    s->settings.aa = 4;
    assert_int_equal(render_lines(p, world_now(s), W, H, 0, H, full, &st_full, NULL), 0);
    s->settings.adaptive = 1;
    assert_int_equal(render_lines(p, world_now(s), W, H, 0, H, ad, &st_ad, NULL), 0);
    double e_one = 0, e_ad = 0;
    for (int i = 0; i < W * H * 3; i++) {
        e_one += (double)(one[i] - full[i]) * (one[i] - full[i]);
        e_ad += (double)(ad[i] - full[i]) * (ad[i] - full[i]);
    }
    assert_true(e_one > 0);                      /* the edges are there to find */
    assert_true(st_ad.primary > st_one.primary); /* some pixels were refined ... */
    assert_true(st_ad.primary < st_full.primary / 2); /* ... not all */
    assert_true(e_ad < e_one / 10);
    /* settings contrast 255: no colour differs by more, so only the
     * triangle's edge (a key) is refined, and the texture's edges stay as
     * one sample has them */
    s->settings.contrast = 255;
    RayStats st_none;
    assert_int_equal(render_lines(p, world_now(s), W, H, 0, H, ad, &st_none, NULL), 0);
    double e_none = 0;
    for (int i = 0; i < W * H * 3; i++)
        e_none += (double)(ad[i] - full[i]) * (ad[i] - full[i]);
    assert_true(st_none.primary > st_one.primary);
    assert_true(st_none.primary < st_ad.primary / 2);
    assert_true(e_none > e_one / 2);
    free(one);
    free(ad);
    free(full);
    render_pool_destroy(p);
    scene_destroy(s);
}

/* The floor's colour at three points under a lamp, seen from eye. */
static void floor_under(Scene *s, vec3 out[3])
{
    const vec3 at[3] = {v3(0, 0, 0), v3(1, 0, R(0.5)), v3(R(-0.7), 0, R(-0.3))};
    for (int i = 0; i < 3; i++)
        out[i] = look(s, v3(0, 3, 6), at[i]);
}

static void assert_lit_alike(const vec3 a[3], const vec3 b[3])
{
    for (int i = 0; i < 3; i++) {
        assert_true(a[i].x > R(0.05));
        if (!(fabs(b[i].x - a[i].x) <= R(0.01) * a[i].x))
            fail_msg("floor point %d: %g with the lamp shown, %g with the light alone", i, (double)b[i].x,
                     (double)a[i].x);
    }
}

/* A light shown by an emissive primitive around it (a lamp) lights the
 * floor as the light alone does: its shadow rays pass their own lamp, also
 * through glass (tinted shadows), where they followed it before. */
static void lamps_do_not_shadow_their_light(void **state)
{
    (void)state;
    for (int kind = 0; kind < 3; kind++) { /* a round lamp, a point in a bulb, a panel */
        Scene *s = empty_scene();
        Material bulb = {.kd = v3(0, 0, 0), .ke = v3(1, 1, 1), .texture = -1};
        uint32_t mb;
        assert_int_equal(scene_add_material(s, bulb, &mb, NULL), 0);
        assert_int_equal(scene_add_plane(s, plane_make(v3(0, 0, 0), v3(0, 1, 0), 0), NULL), 0);
        Light l = kind == 0   ? light_sphere(v3(0, 2, 0), R(0.2), 3, v3(1, 1, 1), 4, 1)
                  : kind == 1 ? light_point(v3(0, 2, 0), v3(1, 1, 1), 4, 1)
                              : light_rect(v3(R(-0.3), 2, R(-0.3)), v3(R(0.6), 0, 0), v3(0, 0, R(0.6)), 2, v3(1, 1, 1),
                                           4, 1);
        assert_int_equal(scene_add_light(s, l, NULL), 0);
        prepare(s);
        vec3 alone[3], shown[3];
        floor_under(s, alone);
        if (kind < 2) {
            for (int r = 0; r < 3; r++) { /* the same radius, a larger one, a smaller one */
                s->sphere_count = 0;
                const real radius[3] = {R(0.2), R(0.3), R(0.1)};
                assert_int_equal(scene_add_sphere(s, (Sphere){v3(0, 2, 0), radius[r], mb}, NULL), 0);
                prepare(s);
                assert_int_equal(world_now(s)->lights[0].lamp_count, 1);
                floor_under(s, shown);
                assert_lit_alike(alone, shown);
            }
        } else {
            const vec3 q[4] = {v3(R(-0.3), 2, R(-0.3)), v3(R(0.3), 2, R(-0.3)), v3(R(0.3), 2, R(0.3)),
                               v3(R(-0.3), 2, R(0.3))};
            const vec3 t1[3] = {q[0], q[1], q[2]}, t2[3] = {q[0], q[2], q[3]};
            assert_int_equal(scene_add_triangle(s, t1, NULL, NULL, mb, NULL), 0);
            assert_int_equal(scene_add_triangle(s, t2, NULL, NULL, mb, NULL), 0);
            prepare(s);
            assert_int_equal(world_now(s)->lights[0].lamp_count, 2);
            floor_under(s, shown);
            assert_lit_alike(alone, shown);
        }
        /* a glass ball between the light and the floor: shadow rays through
         * it go on to the light and pass the lamp (transmittance) */
        Material glass = {.ior = R(1.5), .kt = v3(1, 1, 1), .texture = -1};
        uint32_t mg;
        assert_int_equal(scene_add_material(s, glass, &mg, NULL), 0);
        assert_int_equal(scene_add_sphere(s, (Sphere){v3(0, 1, 0), R(0.3), mg}, NULL), 0);
        prepare(s);
        vec3 through = look(s, v3(0, 3, 6), v3(R(0.05), 0, 0));
        assert_true(through.x > R(0.5) * alone[0].x); /* clear glass: most of the light */
        /* an emissive ball that does not enclose the light is an occluder like any other */
        s->spheres[0].centre = v3(0, 1, 0);
        s->sphere_count = 1;
        prepare(s);
        assert_int_equal(world_now(s)->lights[0].lamp_count, kind == 2 ? 2 : 0);
        if (kind < 2)
            assert_true(look(s, v3(0, 3, 6), v3(0, 0, 0)).x < R(0.5) * alone[0].x);
        scene_destroy(s);
    }
}

/* A glass ray cut by the depth limit returns the chosen estimate times
 * what the cut rays would carry: nothing, the background, the ambient, or
 * the light at the point; a mirror the same times its reflectance; a
 * mirror share over glass the sum of its shares. */
static void depth_limit_returns_the_choice(void **state)
{
    (void)state;
    Scene *s = empty_scene();
    s->background = v3(R(0.5), R(0.6), R(0.7));
    s->ambient = v3_splat(R(0.2));
    Material glass = {.ior = R(1.5), .kt = v3(1, 1, 1), .texture = -1};
    uint32_t mg;
    assert_int_equal(scene_add_material(s, glass, &mg, NULL), 0);
    assert_int_equal(scene_add_sphere(s, (Sphere){v3(0, 0, 0), 1, mg}, NULL), 0);
    assert_int_equal(scene_add_light(s, light_directional(v3(0, 0, -1), v3(1, 1, 1), R(0.5)), NULL), 0);
    s->settings.depth = 0;
    s->settings.shadows = 0;
    const vec3 eye = v3(0, 0, 5);
    for (int l = 0; l < LIMIT_COUNT; l++) {
        s->settings.depth_limit = (DepthLimit)l;
        prepare(s);
        vec3 c = look(s, eye, v3(0, 0, 0)); /* head on: Fresnel 0.04, the rest transmitted: weight 1 */
        vec3 want = l == LIMIT_BLACK ? v3_splat(0)
                    : l == LIMIT_BACKGROUND ? s->background
                    : l == LIMIT_AMBIENT ? s->ambient
                                         : v3_splat(R(0.2) + R(0.5)); /* ambient + the light, N.L = 1 */
        for (int k = 0; k < 3; k++)
            assert_float_equal(c.e[k], want.e[k], R(1e-4));
    }
    /* a mirror: its reflectance times the estimate */
    s->materials[mg] = (Material){.kr = v3(R(0.5), R(0.5), R(0.5)), .texture = -1};
    s->settings.depth_limit = LIMIT_BACKGROUND;
    prepare(s);
    assert_float_equal(look(s, eye, v3(0, 0, 0)).z, R(0.35), R(1e-4));
    /* a half mirror over glass that transmits the other half (a glTF metal
     * with transmission): the mirror's 0.5, the glass's Fresnel reflection
     * at half strength and its transmitted 0.5 (1 - Fresnel) add up to 1,
     * cut at once or traced through the ball (no cutoff: every ray) */
    s->materials[mg] = (Material){.kr = v3_splat(R(0.5)), .ior = R(1.5), .kt = v3_splat(R(0.5)), .texture = -1};
    s->settings.cutoff = 0;
    for (int depth = 0; depth <= 8; depth += 8) {
        s->settings.depth = depth;
        prepare(s);
        for (int i = 0; i < 3; i++) { /* head on, and two rays nearer the rim */
            const vec3 c = look(s, eye, v3(R(0.3) * (real)i, R(0.2) * (real)i, 0));
            for (int k = 0; k < 3; k++)
                assert_float_equal(c.e[k], s->background.e[k], R(1e-4));
        }
    }
    scene_destroy(s);
}

/* A ray with a NaN in it (a degenerate camera's: fuzz_wire found a lens
 * camera of zoom 1e-28 whose rays overflowed) hits nothing and blocks
 * nothing, on every SIMD path: the wide kernels once walked such a ray into
 * their unused children and round the tree until the stack overflowed. */
static void nan_rays_hit_nothing(void **state)
{
    (void)state;
    BvhOptions opt = bvh_options_default(BVH_SAH);
    Scene *s;
    assert_int_equal(scene_default(&s, &opt, NULL), 0);
    const real nan = (real)NAN;
    const vec3 dirs[3] = {v3(nan, nan, nan), v3(0, nan, -1), v3(0, 0, -1)};
    const vec3 orgs[3] = {v3(0, 1, 5), v3(0, 1, 5), v3(nan, 1, 5)};
    for (int path = -1; simd_next(&path);) {
        const World *w = world_now(s);
        for (int k = 0; k < 3; k++) {
            Ray r = ray_make(orgs[k], dirs[k], 0, REAL_INF);
            Hit h;
            assert_false(trace_closest(w, &r, &h));
            assert_false(trace_occluded(w, &r, 100, NULL));
            Ray rays[4] = {r, r, r, r};
            Hit hs[4];
            trace_closest_packet(w, rays, 4, hs);
            for (int i = 0; i < 4; i++)
                assert_int_equal(hs[i].kind, HIT_NONE);
        }
    }
    scene_destroy(s);
}

static void frame_sizes_and_bad_requests(void **state)
{
    (void)state;
    Scene *s;
    BvhOptions opt = bvh_options_default(BVH_SAH);
    assert_int_equal(scene_default(&s, &opt, NULL), 0);
    RenderPool *p = render_pool_create(2, NULL);
    uint8_t px[3 * 4];
    RayStats st;
    assert_int_equal(render_lines(p, world_now(s), 1, 1, 0, 1, px, &st, NULL), 0);
    assert_int_equal(st.primary, 1);
    Err err = {{0}};
    assert_int_equal(render_lines(p, world_now(s), 2, 2, 1, 2, px, NULL, &err), -1);
    assert_contains(err.msg, "outside a frame");
    assert_int_equal(render_lines(p, world_now(s), 0, 2, 0, 1, px, NULL, &err), -1);
    assert_contains(err.msg, "out of range");
    assert_null(render_pool_create(0, &err));
    render_pool_destroy(p);
    scene_destroy(s);
}

/* The pixels of a 48x36 frame of world w. */
static void render_world(const World *w, uint8_t *px)
{
    RenderPool *p = render_pool_create(2, NULL);
    assert_non_null(p);
    assert_int_equal(render_lines(p, w, 48, 36, 0, 36, px, NULL, NULL), 0);
    render_pool_destroy(p);
}

/* A world built with the previous one takes its top-level BVH where the
 * boxes did not change (a camera move, a new colour), builds its own where
 * they did (a sphere moved), and renders what a world built alone renders;
 * a new view changes the pixels without a new world, and a bad one is
 * refused and leaves the view as it was. */
static void worlds_reuse_what_did_not_change(void **state)
{
    (void)state;
    static uint8_t a[48 * 36 * 3], b[48 * 36 * 3];
    BvhOptions opt = bvh_options_default(BVH_SAH);
    Scene *s;
    assert_int_equal(scene_default(&s, &opt, NULL), 0);
    World *w0 = world_build(s, NULL, NULL);
    assert_non_null(w0);
    s->camera.pos = v3_add(s->camera.pos, v3(R(0.3), R(0.1), 0));
    s->materials[0].kd = v3(R(0.2), R(0.7), R(0.3));
    assert_int_equal(scene_check(s, NULL), 0);
    World *w1 = world_build(s, w0, NULL), *alone = world_build(s, NULL, NULL);
    assert_true(world_shares_top(w1, w0));
    assert_false(world_shares_top(alone, w0));
    render_world(w1, a);
    render_world(alone, b);
    assert_memory_equal(a, b, sizeof a);
    world_destroy(alone);
    world_destroy(w0); /* w1 keeps the shared tree */
    assert_true(s->sphere_count > 0);
    s->spheres[0].centre.x += R(0.5);
    assert_int_equal(scene_check(s, NULL), 0);
    World *w2 = world_build(s, w1, NULL);
    alone = world_build(s, NULL, NULL);
    assert_false(world_shares_top(w2, w1));
    render_world(w2, a);
    render_world(alone, b);
    assert_memory_equal(a, b, sizeof a);
    render_world(w1, b);
    assert_memory_not_equal(a, b, sizeof a);
    /* the view: 2x2 samples a pixel, as a scene that asks for them */
    View v = w2->view;
    v.settings.aa = 2;
    v.settings.adaptive = 0;
    assert_int_equal(world_set_view(w2, &v, NULL), 0);
    render_world(w2, a);
    s->settings = v.settings;
    assert_int_equal(scene_check(s, NULL), 0);
    World *w3 = world_build(s, w2, NULL);
    assert_true(world_shares_top(w3, w2));
    render_world(w3, b);
    assert_memory_equal(a, b, sizeof a);
    render_world(alone, b);
    assert_memory_not_equal(a, b, sizeof a);
    View bad = v;
    bad.settings.aa = 0;
    Err err;
    assert_int_equal(world_set_view(w2, &bad, &err), -1);
    assert_contains(err.msg, "aa");
    assert_int_equal(w2->view.settings.aa, 2);
    world_destroy(alone);
    world_destroy(w1);
    world_destroy(w2);
    world_destroy(w3);
    scene_destroy(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(diffuse_and_phong_match_the_formula),
        cmocka_unit_test(packets_equal_single_rays),
        cmocka_unit_test(pairs_equal_single_rays),
        cmocka_unit_test(area_light_lanes_equal_scalar),
        cmocka_unit_test(small_instances_are_placed),
        cmocka_unit_test(shadows_attenuation_and_spot_cone),
        cmocka_unit_test(pixels_are_srgb_unless_linear),
        cmocka_unit_test(plane_and_sphere_texture_coordinates),
        cmocka_unit_test(smooth_mesh_has_no_shadow_terminator),
        cmocka_unit_test(textured_triangle_and_instances),
        cmocka_unit_test(pixels_do_not_depend_on_threads_or_segments),
        cmocka_unit_test(whitted_guides_are_first_hits),
        cmocka_unit_test(path_guides_stop_at_a_glass_ball),
        cmocka_unit_test(partial_line_spans_and_cancel),
        cmocka_unit_test(adaptive_refines_only_edges),
        cmocka_unit_test(adaptive_refines_texture_edges),
        cmocka_unit_test(lamps_do_not_shadow_their_light),
        cmocka_unit_test(depth_limit_returns_the_choice),
        cmocka_unit_test(frame_sizes_and_bad_requests),
        cmocka_unit_test(nan_rays_hit_nothing),
        cmocka_unit_test(scaled_instance_absorbs_in_model_units),
        cmocka_unit_test(clear_coat_reflects_fresnels_share),
        cmocka_unit_test(worlds_reuse_what_did_not_change),
    };
    int rc = cmocka_run_group_tests_name("render", tests, NULL, NULL);
    world_now_free();
    return rc;
}
