/* test_scene.c - the scene-file parser: a full scene, and every kind of error with file and line. */
#include "helpers.h"
#include "worlds.h"

#include "scene/scene_fields.h"
#include "scene/scene_parse.h"

static int parse(const char *text, Scene **s, Err *err)
{
    char *buf = strdup(text);
    BvhOptions opt = bvh_options_default(BVH_SAH);
    int rc = scene_parse(buf, strlen(buf), "t.scene", test_tmpdir(), &opt, 0, s, err);
    free(buf);
    return rc;
}

/* `roughness` goes with `reflect` (a rough metal) or with `ior` (frosted
 * glass): either parses, neither is refused (test errors below). */
static void roughness_goes_with_a_mirror_or_glass(void **state)
{
    (void)state;
    Scene *s;
    Err err;
    if (parse("material frost ior 1.5 roughness 0.4\nmaterial brushed reflect 1 1 1 roughness 0.2\n", &s, &err))
        fail_msg("%s", err.msg);
    assert_int_equal(s->material_count, 3);
    assert_true(material_frosted(&s->materials[1]) && !material_rough(&s->materials[1]));
    assert_float_equal(s->materials[1].roughness, 0.4, 1e-6);
    assert_true(material_rough(&s->materials[2]) && !material_frosted(&s->materials[2]));
    scene_destroy(s);
}

static void full_scene(void **state)
{
    (void)state;
    char path[256];
    snprintf(path, sizeof path, "%s/tex.ppm", test_tmpdir());
    test_write_file(path, "P3\n2 2\n255\n255 0 0 0 255 0 0 0 255 255 255 255\n");
    snprintf(path, sizeof path, "%s/tri.obj", test_tmpdir());
    test_write_file(path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const char *text = "# everything the format has\n"
                       "camera position 0 1 5 lookat 0 0 0 fov 60\n"
                       "ambient 0.1 0.1 0.1\nbackground 0 0 0.2\n"
                       "settings aa 2 shading diffuse shadows off filter nearest\n"
                       "texture checker tex.ppm\n"
                       "texture tiles tex.ppm closest wrap mirror clamp\n"
                       "texture edge tex.ppm wrap clamp\n"
                       "material red diffuse 1 0 0 specular 0.5 0.5 0.5 shininess 30\n"
                       "material pic texture checker\n"
                       "sphere centre 0 1 0 radius 1 material red\n"
                       "plane point 0 0 0 normal 0 2 0\n"
                       "triangle vertices 0 0 0 1 0 0 0 1 0 uv 0 0 1 0 0 1 material pic\n"
                       "triangle vertices 0 0 1 1 0 1 0 1 1 normals 0 0 1 0 0 1 0 0 1\n"
                       "model tri tri.obj bvh mst\n"
                       "instance tri translate 1 2 3 rotate 0 90 0 scale 2 material red\n"
                       "instance tri\n"
                       "light point position 0 5 0 color 1 1 1 intensity 2 attenuate\n"
                       "light spot position 0 5 0 target 0 0 0 angle 40 soft 5\n"
                       "light directional direction 0 -1 0 intensity 0.5\n";
    Scene *s;
    Err err;
    if (parse(text, &s, &err))
        fail_msg("%s", err.msg);
    assert_int_equal(s->sphere_count, 1);
    assert_int_equal(s->plane_count, 1);
    assert_int_equal(s->tri_count, 2);
    assert_int_equal(s->model_count, 1);
    assert_int_equal(s->instance_count, 2);
    assert_int_equal(s->light_count, 3);
    assert_int_equal(s->material_count, 3); /* default, red, pic */
    assert_int_equal(s->texture_count, 3);
    assert_int_equal(s->textures[0]->wrap[0], TEXTURE_REPEAT);
    assert_int_equal(s->textures[0]->wrap[1], TEXTURE_REPEAT);
    assert_int_equal(s->textures[1]->closest, 1);
    assert_int_equal(s->textures[1]->wrap[0], TEXTURE_MIRROR);
    assert_int_equal(s->textures[1]->wrap[1], TEXTURE_CLAMP);
    assert_int_equal(s->textures[2]->closest, 0);
    assert_int_equal(s->textures[2]->wrap[0], TEXTURE_CLAMP);
    assert_int_equal(s->textures[2]->wrap[1], TEXTURE_CLAMP);
    assert_int_equal(s->models[0]->bvh.kind, BVH_MST);
    assert_int_equal(s->settings.aa, 2);
    assert_int_equal(s->settings.shading, SHADE_DIFFUSE);
    assert_int_equal(s->settings.shadows, 0);
    assert_int_equal(s->settings.filter, FILTER_NEAREST);
    assert_float_equal(s->planes[0].normal.y, 2, 0); /* as given */
    const World *w = world_now(s);
    assert_float_equal(w->planes[0].unit.y, 1, R(1e-6)); /* derived */
    assert_float_equal(s->spheres[0].radius, 1, 0);
    assert_int_equal(s->instances[0].material, 1);
    assert_float_equal(s->lights[1].dir.y, -5, 0); /* target - position, as given */
    assert_float_equal(w->lights[1].axis.y, -1, R(1e-6));
    assert_true(s->lights[0].attenuate);
    assert_true(world_has(w, FEAT_TEXTURES) && world_has(w, FEAT_SMOOTH) && world_has(w, FEAT_SPOT) &&
                world_has(w, FEAT_ATTENUATION) && world_has(w, FEAT_PLANES) && !world_has(w, FEAT_SHADOWS));
    assert_true(s->checked);
    scene_destroy(s);
}

static void features_reflect_what_is_used(void **state)
{
    (void)state;
    Scene *s;
    Err err;
    if (parse("sphere centre 0 0 0 radius 1\nlight point position 0 5 0\n", &s, &err))
        fail_msg("%s", err.msg);
    assert_int_equal(world_now(s)->features, FEAT_SHADOWS);
    scene_destroy(s);
}

/* A UTF-8 byte-order mark before the first directive is skipped, and both
 * spellings of centre/center and colour/color are taken. */
/* A smooth triangle made in code (or sent) with a zero vertex normal is
 * refused by the one check, as a file's `normals` with one is by the parser. */
static void a_smooth_triangle_needs_its_normals(void **state)
{
    (void)state;
    Scene *s = scene_create();
    assert_int_equal(scene_add_material(s, material_default(), NULL, NULL), 0);
    const vec3 p[3] = {v3(0, 0, 0), v3(1, 0, 0), v3(0, 1, 0)};
    vec3 n[3] = {v3(0, 0, 1), v3(0, 0, 1), v3(0, 0, 1)};
    assert_int_equal(scene_add_triangle(s, p, n, NULL, 0, NULL), 0);
    assert_int_equal(scene_check(s, NULL), 0);
    n[2] = v3(0, 0, 0);
    assert_int_equal(scene_add_triangle(s, p, n, NULL, 0, NULL), 0);
    Err err;
    assert_int_equal(scene_check(s, &err), -1);
    assert_contains(err.msg, "triangle 1");
    assert_contains(err.msg, "normals");
    assert_false(s->checked);
    scene_destroy(s);
}

/* A scene's own materials neither cut holes nor carry normal maps,
 * emission, metal-roughness or occlusion textures (a model's own do): a sent or coded one is
 * refused by name; a normal map without its scale is no material at all. */
static void scene_materials_have_no_cutouts_or_normal_maps(void **state)
{
    (void)state;
    Material cut = material_default(), bumpy = material_default(), half = material_default(),
             glow = material_default(), metal = material_default(), dark = material_default();
    cut.mask = 0, cut.cutoff = R(0.5);
    bumpy.normal_map = 0, bumpy.normal_scale = 1;
    glow.ke = v3(1, 1, 1), glow.emit_map = 0, glow.emit_mapped = 1;
    metal.kr = v3(1, 1, 1), metal.metal_map = 0, metal.metal_mapped = 1;
    dark.ao_map = 0, dark.ao_strength = 1;
    half.normal_map = 1;
    char why[160];
    assert_null(material_problem(&bumpy, why, sizeof why));
    assert_non_null(material_problem(&half, why, sizeof why));
    assert_non_null(strstr(why, "normal_scale"));
    const struct {
        Material m;
        const char *says;
    } cases[] = {{cut, "is a cutout"},
                 {bumpy, "has a normal map"},
                 {glow, "has an emission texture"},
                 {metal, "has a metal-roughness texture"},
                 {dark, "has an occlusion texture"}};
    for (int i = 0; i < 5; i++) {
        Scene *s = scene_create();
        assert_int_equal(scene_add_material(s, cases[i].m, NULL, NULL), 0);
        Err err;
        assert_int_equal(scene_check(s, &err), -1);
        assert_contains(err.msg, cases[i].says);
        scene_destroy(s);
    }
}

static void byte_order_mark_and_spellings(void **state)
{
    (void)state;
    Scene *s;
    Err err;
    if (parse("\xEF\xBB\xBF" "camera position 0 0 5 lookat 0 0 0\n"
              "sphere center 0 1 0 radius 1\nlight point position 0 5 0 colour 1 0.5 0.25\n", &s, &err))
        fail_msg("%s", err.msg);
    assert_float_equal(s->camera.pos.z, 5, 0);
    assert_float_equal(s->spheres[0].centre.y, 1, 0);
    assert_float_equal(s->lights[0].color.z, R(0.25), 0);
    scene_destroy(s);
    /* only at the start: elsewhere it is an unknown word */
    Scene *bad = NULL;
    assert_int_equal(parse("camera position 0 0 5 lookat 0 0 0\n\xEF\xBB\xBF" "sphere centre 0 0 0 radius 1\n", &bad, &err), -1);
    assert_contains(err.msg, "t.scene:2: unknown directive");
}

/* A camera written as a scene line (the window's K) reads back as the
 * same camera, field for field, whatever its kind; a directive's fields
 * alone (lanray-render --camera) read as the same line in a file does. */
static void camera_line_reads_back(void **state)
{
    (void)state;
    Camera cams[5];
    cams[0] = camera_from_angles(v3(R(0.1), R(-2.0000002), R(1e7)), R(-1234.567), R(-88.9), R(0.3), R(1.7320508));
    cams[1] = camera_from_angles(v3(R(3), R(1e-20), R(-4)), R(33.3), R(12.25), 0, R(0.7));
    cams[2] = cams[1], cams[2].kind = CAMERA_ORTHO, cams[2].size = R(6.5);
    cams[3] = cams[1], cams[3].kind = CAMERA_FISHEYE, cams[3].fov = R(187.5);
    cams[4] = cams[0], cams[4].aperture = R(0.05), cams[4].focus = R(3.3);
    for (int i = 0; i < 5; i++) {
        char line[512];
        assert_true(camera_line(&cams[i], line, sizeof line) < (int)sizeof line);
        Camera back;
        Err err = {{0}};
        assert_int_equal(scene_parse_camera(line, "K", &back, &err), 0);
        if (cams[i].kind != CAMERA_PINHOLE) /* a pinhole's zoom is none of theirs (the line leaves it out) */
            back.zoom = cams[i].zoom;
        assert_true(camera_same(&back, &cams[i]));
        /* in a scene file too */
        char text[600];
        snprintf(text, sizeof text, "%s\nsphere centre 0 0 0 radius 1\n", line);
        Scene *s = NULL;
        assert_int_equal(parse(text, &s, &err), 0);
        back = s->camera;
        if (cams[i].kind != CAMERA_PINHOLE)
            back.zoom = cams[i].zoom;
        assert_true(camera_same(&back, &cams[i]));
        scene_destroy(s);
    }
    Scene *s = NULL;
    Err err = {{0}};
    assert_int_equal(parse("camera position 0 1 5 lookat 0 0 0 fov 40\nsphere centre 0 0 0 radius 1\n", &s, &err), 0);
    Camera c;
    assert_int_equal(scene_parse_camera("position 0 1 5 lookat 0 0 0 fov 40", "--camera", &c, &err), 0);
    assert_true(camera_same(&c, &s->camera));
    scene_destroy(s);
    assert_int_equal(scene_parse_camera("position 0 0 0 lookat 0 0 0", "--camera", &c, &err), -1);
    assert_contains(err.msg, "--camera:1: camera 'lookat' point equals its position");
    assert_int_equal(scene_parse_camera("position 1 2 yaw 3", "--camera", &c, &err), -1);
    assert_contains(err.msg, "--camera:1:");
    assert_int_equal(scene_parse_camera("position 1 2 3\nsphere", "--camera", &c, &err), -1);
    assert_contains(err.msg, "--camera: one line");
    assert_int_equal(scene_parse_camera("", "--camera", &c, &err), -1);
    assert_contains(err.msg, "--camera");
}

static void expect_error(const char *text, const char *what)
{
    Scene *s = NULL;
    Err err = {{0}};
    assert_int_equal(parse(text, &s, &err), -1);
    assert_null(s);
    assert_contains(err.msg, what);
}

static void errors_name_file_line_and_expectation(void **state)
{
    (void)state;
    expect_error("\nspere centre 0 0 0 radius 1\n", "t.scene:2: unknown directive 'spere'");
    expect_error("sphere centre 0 0 0 radus 1\n", "t.scene:1: unknown keyword 'radus' for sphere (expected one of: centre, radius, material)");
    expect_error("sphere centre 0 0 0\n", "t.scene:1: sphere needs 'radius'");
    expect_error("sphere centre 0 x 0 radius 1\n", "t.scene:1: 'centre' of sphere expects 3 finite numbers, got 'x'");
    expect_error("sphere centre 0 0 0 radius\n", "got 'end of line'");
    expect_error("sphere centre 0 0 0 radius -1\n", "'radius' of sphere must be positive");
    expect_error("sphere centre 0 0 0 radius 1 radius 2\n", "keyword 'radius' given twice");
    expect_error("sphere centre 0 0 0 radius 1 material gold\n", "t.scene:1: unknown material 'gold'");
    expect_error("material a\nmaterial a\n", "t.scene:2: material 'a' is defined twice");
    expect_error("material a texture none\n", "unknown texture 'none'");
    expect_error("material a diffuse 1 -1 0\n", "'diffuse' of material must not be negative");
    expect_error("plane point 0 0 0 normal 0 0 0\n", "'normal' of plane must not be zero");
    expect_error("triangle vertices 0 0 0 1 1 1 2 2 2\n", "triangle has zero area");
    expect_error("light laser position 0 0 0\n", "unknown light kind 'laser'");
    expect_error("light spot position 0 5 0 direction 0 -1 0\n", "t.scene:1: spot light needs 'angle'");
    expect_error("light spot position 0 5 0 direction 0 -1 0 angle 190\n", "'angle' of spot light must be between 0 and 180");
    expect_error("light point direction 0 1 0\n", "a point light takes no 'direction' (it takes: color, intensity, position, attenuate)");
    expect_error("camera position 0 0 0 lookat 0 0 0\n", "camera 'lookat' point equals its position");
    expect_error("camera position 0 0 0 fov 180\n", "'fov' of camera must be between 0 and 180");
    expect_error("camera lookat 0 0 0\n", "camera needs 'position'");
    expect_error("camera position 0 0 1 fov 60 fisheye 180\n", "camera takes one of 'zoom', 'fov' (a pinhole), 'ortho' and 'fisheye'");
    expect_error("camera position 0 0 1 ortho 0\n", "t.scene:1: 'ortho' of camera must be positive");
    expect_error("camera position 0 0 1 fisheye 361\n", "'fisheye' of camera must be above 0 and at most 360");
    expect_error("material m transmit 1 1 1 reflect 1 1 1\n", "'transmit' of material needs 'ior'");
    expect_error("material m ior 20\n", "'ior' of material must be from 0.0625 to 16");
    expect_error("material m absorb 1 1 1\n", "'absorb' of material needs 'ior'");
    expect_error("material m roughness 0.3\n", "'roughness' of material needs 'reflect' (a rough metal) or 'ior' (frosted glass)");
    expect_error("material m emit -1 0 0\n", "'emit' of material must not be negative");
    expect_error("settings depth 65\n", "'depth' of settings must be a whole number from 0 to 64");
    expect_error("settings cutoff 1\n", "'cutoff' of settings must be from 0 up to");
    expect_error("settings fresnel fast\n", "'fresnel' of settings must be exact or schlick, not 'fast'");
    expect_error("settings glass_shadows dark\n", "'glass_shadows' of settings must be opaque or tinted, not 'dark'");
    expect_error("settings aa 33\n", "'aa' of settings must be a whole number from 1 to 32");
    expect_error("settings contrast 256\n", "'contrast' of settings must be a whole number from 0 to 255");
    expect_error("settings contrast -1\n", "'contrast' of settings must be a whole number from 0 to 255");
    expect_error("settings shading toon\n", "'shading' of settings must be phong or diffuse");
    expect_error("ambient 1 1\n", "ambient expects 3 finite numbers");
    expect_error("instance nothing\n", "unknown model 'nothing'");
    char obj[256];
    snprintf(obj, sizeof obj, "%s/tri.obj", test_tmpdir());
    test_write_file(obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    expect_error("model tri tri.obj\ninstance tri lights\n",
                 "t.scene:2: instance 'tri' takes its model's lights, which only a glTF (.gltf, .glb) gives");
    expect_error("model tri tri.obj\ninstance tri scale 2 camera lights\n", "takes its model's lights and camera, which only a glTF");
    expect_error("model m missing.tmd\n", "t.scene:1:");
    expect_error("model m thing.xyz\n", "must end in .tmd, .obj, or a format the importer reads");
    expect_error("model m thing.stl\n", "thing.stl: Unable to open file"); /* a format Assimp reads: its error, with the name */
    expect_error("texture t missing.ppm\n", "t.scene:1:");
    expect_error("texture t a.ppm wrap tile\n", "t.scene:1: texture wrap expects repeat, clamp or mirror (for u and v, or u then v), not 'tile'");
    expect_error("texture t a.ppm wrap\n", "texture wrap expects repeat, clamp or mirror (for u and v, or u then v)");
    expect_error("texture t a.ppm wrap clamp sharp\n", "texture wrap expects repeat, clamp or mirror for v, not 'sharp'");
    expect_error("texture t a.ppm wrap clamp clamp closest\n", "'closest' is none of them");
    expect_error("texture t\n", "texture expects a name, a file");
    expect_error("sphere centre 0 0 1e999 radius 1\n", "expects 3 finite numbers, got '1e999'");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(full_scene),
        cmocka_unit_test(camera_line_reads_back),
        cmocka_unit_test(features_reflect_what_is_used),
        cmocka_unit_test(a_smooth_triangle_needs_its_normals),
        cmocka_unit_test(roughness_goes_with_a_mirror_or_glass),
        cmocka_unit_test(scene_materials_have_no_cutouts_or_normal_maps),
        cmocka_unit_test(byte_order_mark_and_spellings),
        cmocka_unit_test(errors_name_file_line_and_expectation),
    };
    int rc = cmocka_run_group_tests_name("scene", tests, NULL, NULL);
    world_now_free();
    return rc;
}
