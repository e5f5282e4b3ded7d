/* test_metalmap.c - a model's metal-roughness texture: the material a hit
 * takes where the texture says how metal and how rough the surface is. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include "helpers.h"
#include "base/srgb.h"
#include "scene/trace.h"
#include "worlds.h"

static const vec3 BASE = {{0.8f, 0.6f, 0.4f}};

/* The unit quad x, y in [0, 1] at z = 0, u along x, its material glTF's
 * metal (factor `metal`, roughness factor 1) of base colour BASE with a
 * 2 x 1 metal-roughness texture: left texel blue 255 green 0 (metal,
 * smooth), right blue 0 green 128 (not metal, half rough); `colour`, a
 * base colour texture (2 x 1: grey, white) too; a clear coat of strength
 * `coat` (the importer's 1 for a glTF's) and roughness 0.5. */
static Scene *metal_scene(real metal, int colour, real coat)
{
    Mesh mesh;
    Err err;
    assert_int_equal(mesh_init(&mesh, MESH_UVS | MESH_MATERIALS, &err), 0);
    const uint8_t mr[6] = {0, 0, 255, 0, 128, 0}, grey[6] = {128, 128, 128, 255, 255, 255};
    Texture *t = texture_from_rgb8(2, 1, mr);
    t->closest = 1;
    uint32_t tex, ctex;
    assert_int_equal(mesh_add_texture(&mesh, t, &tex, &err), 0);
    Material m = material_default();
    m.kd = BASE, m.kr = v3_scale(BASE, metal), m.ks = m.kr, m.roughness = 1;
    m.kre = v3_splat(metal); /* glTF's metal rises to white at grazing (import.c) */
    m.metal_map = (int32_t)tex, m.metal_mapped = 1;
    m.coat = coat, m.coat_roughness = coat > 0 ? R(0.5) : R(0);
    if (colour) {
        Texture *c = texture_from_rgb8(2, 1, grey);
        c->closest = 1;
        assert_int_equal(mesh_add_texture(&mesh, c, &ctex, &err), 0);
        m.texture = (int32_t)ctex;
    }
    assert_int_equal(mesh_add_material(&mesh, m, &err), 0);
    const vec3 a[3] = {v3(0, 0, 0), v3(1, 0, 0), v3(1, 1, 0)}, b[3] = {v3(0, 0, 0), v3(1, 1, 0), v3(0, 1, 0)};
    const real ua[6] = {0, 0, 1, 0, 1, 1}, ub[6] = {0, 0, 1, 1, 0, 1};
    assert_int_equal(mesh_add(&mesh, a, NULL, ua, NULL, 0, &err), 0);
    assert_int_equal(mesh_add(&mesh, b, NULL, ub, NULL, 0, &err), 0);
    return worlds_scene_of_mesh(&mesh, v3(0, 0, 0));
}

/* The material the hit at x (y 0.5) takes. */
static Material material_at(Scene *s, real x)
{
    const World *w = world_now(s);
    Ray r = ray_make(v3(x, 0.5f, 1), v3(0, 0, -1), 0, REAL_MAX);
    Hit h;
    assert_true(trace_closest(w, &r, &h));
    Surface sf;
    trace_surface(w, &r, &h, &sf);
    trace_surface_metal(w, &sf, NULL);
    return *sf.mat;
}

static void assert_vec(vec3 got, vec3 want)
{
    for (int a = 0; a < 3; a++)
        if (fabs((double)got.e[a] - (double)want.e[a]) > 1e-6)
            fail_msg("(%g %g %g), expected (%g %g %g)", (double)got.x, (double)got.y, (double)got.z, (double)want.x,
                     (double)want.y, (double)want.z);
}

static void the_texture_says_where_the_surface_is_metal(void **state)
{
    (void)state;
    Scene *s = metal_scene(1, 0, 0);
    Material left = material_at(s, R(0.25)), right = material_at(s, R(0.75));
    /* metal and smooth: a perfect mirror of the base colour, no diffuse */
    assert_true(material_reflects(&left) && !material_rough(&left));
    assert_vec(left.kr, BASE);
    assert_vec(left.kd, v3(0, 0, 0));
    assert_vec(left.ks, BASE);
    assert_vec(left.kre, v3(1, 1, 1)); /* and its rim white */
    /* not metal: the base colour diffuse, no mirror, roughness 128 / 255 of the factor's */
    assert_false(material_reflects(&right));
    assert_false(material_edged(&right));
    assert_vec(right.kd, BASE);
    assert_float_equal(right.roughness, 128.0 / 255.0, 1e-6);
    world_now_free();
    scene_destroy(s);
}

/* The metallic factor scales the texel's share; the base colour texture
 * tints the metal as shading tints the diffuse colour (kd, which shading
 * multiplies by the texture itself, stays the base's share). */
static void the_factor_scales_and_the_colour_texture_tints(void **state)
{
    (void)state;
    Scene *s = metal_scene(R(0.5), 0, 0);
    Material left = material_at(s, R(0.25));
    assert_vec(left.kr, v3_scale(BASE, R(0.5)));
    assert_vec(left.kd, v3_scale(BASE, R(0.5)));
    assert_vec(left.kre, v3_splat(R(0.5))); /* the factor's share of white */
    world_now_free();
    scene_destroy(s);
    Scene *g = metal_scene(1, 1, 0);
    left = material_at(g, R(0.25)); /* the grey texel: code 128, 0.2158 in linear light */
    assert_vec(left.kr, v3_scale(BASE, srgb_decode8[128]));
    assert_vec(left.kd, v3(0, 0, 0));
    assert_vec(left.kre, v3(1, 1, 1)); /* the colour texture tints its colour, not its rim */
    world_now_free();
    scene_destroy(g);
}

/* A glTF's coat is its dielectric share's: where the texel is all metal
 * none, where it is no metal all of it (at the texel's roughness), and a
 * metallic factor of 0.5 leaves half of it on the metal texel. */
static void the_coat_is_the_dielectric_shares(void **state)
{
    (void)state;
    Scene *s = metal_scene(1, 0, 1);
    Material left = material_at(s, R(0.25)), right = material_at(s, R(0.75));
    assert_float_equal(left.coat, 0, 1e-6);
    assert_float_equal(right.coat, 1, 1e-6);
    assert_float_equal(right.coat_roughness, 0.5 * 128.0 / 255.0, 1e-6);
    world_now_free();
    scene_destroy(s);
    s = metal_scene(R(0.5), 0, 1);
    assert_float_equal(material_at(s, R(0.25)).coat, 0.5, 1e-6);
    world_now_free();
    scene_destroy(s);
}

/* A metal-roughness texture seen from afar reads its levels, which
 * average its codes as numbers: a checker of metal (blue 255) and
 * dielectric (blue 0) texels is, four texels to a sample, half metal
 * (blue 128: kr half the base, kd the other half); at a point, or over a
 * footprint of half a texel, one texel, all metal.  An occlusion texture
 * likewise (the same image's red: none on the metal texels, all on the
 * others). */
static void far_off_a_metal_map_reads_the_mean_of_its_texels(void **state)
{
    (void)state;
    Mesh mesh;
    Err err;
    assert_int_equal(mesh_init(&mesh, MESH_UVS | MESH_MATERIALS, &err), 0);
    const uint8_t mr[12] = {0, 0, 255, 255, 0, 0, 255, 0, 0, 0, 0, 255}; /* metal texels no red, the others all */
    uint32_t tex;
    assert_int_equal(mesh_add_texture(&mesh, texture_from_rgb8(2, 2, mr), &tex, &err), 0);
    Material m = material_default();
    m.kd = BASE, m.kr = BASE, m.ks = m.kr, m.roughness = 1;
    m.metal_map = (int32_t)tex, m.metal_mapped = 1;
    m.ao_map = (int32_t)tex, m.ao_strength = 1;
    assert_int_equal(mesh_add_material(&mesh, m, &err), 0);
    const vec3 a[3] = {v3(0, 0, 0), v3(1, 0, 0), v3(1, 1, 0)}, b[3] = {v3(0, 0, 0), v3(1, 1, 0), v3(0, 1, 0)};
    const real ua[6] = {0, 0, 1, 0, 1, 1}, ub[6] = {0, 0, 1, 1, 0, 1};
    assert_int_equal(mesh_add(&mesh, a, NULL, ua, NULL, 0, &err), 0);
    assert_int_equal(mesh_add(&mesh, b, NULL, ub, NULL, 0, &err), 0);
    Scene *s = worlds_scene_of_mesh(&mesh, v3(0, 0, 0)); /* world_build makes the data levels */
    const World *w = world_now(s);
    Ray r = ray_make(v3(R(0.25), R(0.75), 1), v3(0, 0, -1), 0, REAL_MAX); /* the metal texel, row 0 */
    Hit h;
    assert_true(trace_closest(w, &r, &h));
    const TexFootprint wide = {R(1), 0, 0, R(1)}, near = {R(0.25), 0, 0, R(0.25)};
    const TexFootprint *fps[3] = {&wide, &near, NULL};
    const real share[3] = {R(128) / R(255), 1, 1}, ao[3] = {R(128) / R(255), 0, 0};
    for (int i = 0; i < 3; i++) {
        Surface sf;
        trace_surface(w, &r, &h, &sf);
        assert_non_null(sf.aotex);
        trace_surface_metal(w, &sf, fps[i]);
        assert_vec(sf.mat->kr, v3_scale(BASE, share[i]));
        assert_vec(sf.mat->kd, v3_scale(BASE, R(1) - share[i]));
        /* occlusion: the red channel, the checker's mean from afar */
        assert_float_equal(trace_occlusion(&sf, fps[i]), ao[i], 1e-6);
    }
    world_now_free();
    scene_destroy(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(the_texture_says_where_the_surface_is_metal),
        cmocka_unit_test(the_factor_scales_and_the_colour_texture_tints),
        cmocka_unit_test(the_coat_is_the_dielectric_shares),
        cmocka_unit_test(far_off_a_metal_map_reads_the_mean_of_its_texels),
    };
    return cmocka_run_group_tests_name("metalmap", tests, NULL, NULL);
}
