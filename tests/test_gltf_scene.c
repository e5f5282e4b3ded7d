/* test_gltf_scene.c - a glTF's camera and lights (model/gltf_scene.h): placed
 * by their nodes' matrices through the hierarchy (translation, rotation,
 * scale, or a matrix), looking down -z; spot cones and units as written;
 * what is malformed left out; a walk over shared children bounded; and
 * the preview that uses them (scene/scene_preview.h): the file's camera
 * and its lights in lanray's units in place of the framing and the lamps. */
#include "helpers.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model/gltf_scene.h"
#include "scene/scene_preview.h"

#define PI 3.14159265358979323846

static void read_text(const char *json, GltfScene *g)
{
    assert_int_equal(gltf_scene_read((const uint8_t *)json, strlen(json), 0, g), 0);
}

static void near3(const double *v, double x, double y, double z)
{
    if (!(fabs(v[0] - x) < 1e-9 && fabs(v[1] - y) < 1e-9 && fabs(v[2] - z) < 1e-9))
        fail_msg("%g %g %g, want %g %g %g", v[0], v[1], v[2], x, y, z);
}

/* A parent moved by (1, 2, 3) and turned 90 degrees about +y (the
 * quaternion (0, sin 45, 0, cos 45)) holds a child at (0, 0, 2) scaled by
 * 2: the child's origin is at (1, 2, 3) + R (0, 0, 2) = (3, 2, 3), its -z
 * along R (0, 0, -1) = (-1, 0, 0).  A camera and a point light on the
 * child, a spot on the parent's other child, a node of a matrix (moved by
 * (0, 5, 0): at (1, 7, 3); its -z down the matrix's columns, -y, which the
 * parent's turn keeps), a sun on a root of its own. */
static const char *scene_json =
    "{\"scene\":0,\"scenes\":[{\"nodes\":[0,3]}],"
    "\"nodes\":["
    "{\"translation\":[1,2,3],\"rotation\":[0,0.7071067811865476,0,0.7071067811865476],\"children\":[1,2]},"
    "{\"translation\":[0,0,2],\"scale\":[2,2,2],\"camera\":0,"
    "\"extensions\":{\"KHR_lights_punctual\":{\"light\":0}}},"
    "{\"matrix\":[1,0,0,0, 0,0,-1,0, 0,1,0,0, 0,5,0,1],\"extensions\":{\"KHR_lights_punctual\":{\"light\":1}}},"
    "{\"extensions\":{\"KHR_lights_punctual\":{\"light\":2}}}],"
    "\"cameras\":[{\"type\":\"perspective\",\"perspective\":{\"yfov\":0.5,\"aspectRatio\":2,\"znear\":0.1}}],"
    "\"extensions\":{\"KHR_lights_punctual\":{\"lights\":["
    "{\"type\":\"point\",\"color\":[1,0.5,0.25],\"intensity\":683},"
    "{\"type\":\"spot\",\"intensity\":10,\"spot\":{\"innerConeAngle\":0.2,\"outerConeAngle\":0.4}},"
    "{\"type\":\"directional\",\"intensity\":3}]}}}";

static void cameras_and_lights_are_placed_by_their_nodes(void **state)
{
    (void)state;
    GltfScene g;
    read_text(scene_json, &g);
    assert_true(g.has_camera);
    near3(g.camera.pos, 3, 2, 3);
    near3(g.camera.fwd, -1, 0, 0);
    near3(g.camera.up, 0, 1, 0);
    assert_true(fabs(g.camera.yfov - 0.5) < 1e-12 && fabs(g.camera.aspect - 2) < 1e-12 && !g.camera.ortho);
    assert_int_equal(g.light_count, 3);
    assert_int_equal(g.lights[0].kind, GLTF_POINT);
    near3(g.lights[0].pos, 3, 2, 3);
    near3(g.lights[0].color, 1, 0.5, 0.25);
    assert_true(g.lights[0].intensity == 683);
    assert_int_equal(g.lights[1].kind, GLTF_SPOT);
    near3(g.lights[1].pos, 1, 7, 3);
    near3(g.lights[1].dir, 0, -1, 0);
    assert_true(g.lights[1].inner == 0.2 && g.lights[1].outer == 0.4);
    assert_int_equal(g.lights[2].kind, GLTF_DIRECTIONAL);
    near3(g.lights[2].dir, 0, 0, -1);
    gltf_scene_free(&g);
}

static void what_is_malformed_is_left_out(void **state)
{
    (void)state;
    GltfScene g;
    /* a node index past the end, a light index past the end, a light of an
     * unknown type, a negative intensity, a camera of no field of view */
    read_text("{\"scenes\":[{\"nodes\":[7,0,1,2,3]}],\"nodes\":["
              "{\"extensions\":{\"KHR_lights_punctual\":{\"light\":9}}},"
              "{\"extensions\":{\"KHR_lights_punctual\":{\"light\":0}}},"
              "{\"extensions\":{\"KHR_lights_punctual\":{\"light\":1}},\"camera\":0},"
              "{\"camera\":5}],"
              "\"cameras\":[{\"type\":\"perspective\",\"perspective\":{}}],"
              "\"extensions\":{\"KHR_lights_punctual\":{\"lights\":[{\"type\":\"area\"},"
              "{\"type\":\"point\",\"intensity\":-1}]}}}",
              &g);
    assert_int_equal(g.light_count, 0);
    assert_false(g.has_camera);
    gltf_scene_free(&g);
    /* not JSON, a GLB's bytes that are not one, nothing */
    read_text("{\"nodes\":[", &g);
    assert_int_equal(g.light_count, 0);
    assert_int_equal(gltf_scene_read((const uint8_t *)"glTF", 4, 1, &g), 0);
    assert_int_equal(g.light_count, 0);
}

/* 40 nodes, each holding the next twice: 2^40 paths, GLTF_MAX_VISITS walked. */
static void a_walk_over_shared_children_ends(void **state)
{
    (void)state;
    char *json = malloc(8192);
    size_t n = (size_t)sprintf(json, "{\"scenes\":[{\"nodes\":[0]}],\"nodes\":[");
    for (int i = 0; i < 40; i++)
        n += (size_t)sprintf(json + n, "%s{\"children\":[%d,%d],\"extensions\":{\"KHR_lights_punctual\":{\"light\":0}}}",
                             i ? "," : "", i + 1, i + 1);
    n += (size_t)sprintf(json + n, ",{}],\"extensions\":{\"KHR_lights_punctual\":{\"lights\":[{\"type\":\"point\"}]}}}");
    GltfScene g;
    read_text(json, &g);
    assert_true(g.light_count == GLTF_MAX_LIGHTS);
    gltf_scene_free(&g);
    free(json);
}

/* The preview of a glTF with a camera and lights takes them: its camera
 * where the file's is, looking its way, the file's aspect 1024 wide; its
 * lights in lanray's units (683 candela: an intensity of 1 / pi), no lamp
 * of the preview's own, and the background's light as the ambient.  The file: a triangle (three
 * vertices in a data URI) on a node of its own, scene_json's camera on
 * the turned child, the point light there and the spot. */
static const char *preview_json =
    "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0,2,3]}],"
    "\"nodes\":["
    "{\"translation\":[1,2,3],\"rotation\":[0,0.7071067811865476,0,0.7071067811865476],\"children\":[1]},"
    "{\"translation\":[0,0,2],\"camera\":0,\"extensions\":{\"KHR_lights_punctual\":{\"light\":0}}},"
    "{\"matrix\":[1,0,0,0, 0,0,-1,0, 0,1,0,0, 0,5,0,1],\"extensions\":{\"KHR_lights_punctual\":{\"light\":1}}},"
    "{\"mesh\":0}],"
    "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}],"
    "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\","
    "\"min\":[0,0,0],\"max\":[1,1,0]}],"
    "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36}],"
    "\"buffers\":[{\"byteLength\":36,\"uri\":\"data:application/octet-stream;base64,"
    "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA\"}],"
    "\"cameras\":[{\"type\":\"perspective\",\"perspective\":{\"yfov\":0.5,\"aspectRatio\":2,\"znear\":0.1}}],"
    "\"extensions\":{\"KHR_lights_punctual\":{\"lights\":["
    "{\"type\":\"point\",\"color\":[1,0.5,0.25],\"intensity\":683},"
    "{\"type\":\"spot\",\"intensity\":10,\"spot\":{\"innerConeAngle\":0.2,\"outerConeAngle\":0.4}}]}}}";

static int close_to(real a, double b, double eps) { return fabs((double)a - b) < eps; }

static void a_preview_takes_the_files_camera_and_lights(void **state)
{
    (void)state;
    char path[512];
    snprintf(path, sizeof path, "%s/lit.gltf", test_tmpdir());
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(preview_json, f);
    fclose(f);
    Scene *s;
    Err err;
    BvhOptions opt = bvh_options_default(BVH_SAH);
    if (scene_preview(path, &opt, 0, 0, &s, &err))
        fail_msg("%s", err.msg);
    assert_true(close_to(s->camera.pos.x, 3, 1e-5) && close_to(s->camera.pos.y, 2, 1e-5) &&
                close_to(s->camera.pos.z, 3, 1e-5));
    /* looking along -x: yaw 90 (camera.h), level, upright */
    assert_true(close_to(s->camera.yaw, 90, 1e-3) && close_to(s->camera.pitch, 0, 1e-3) &&
                close_to(s->camera.roll, 0, 1e-3));
    /* the horizontal field of view from yfov 0.5 at 2:1 */
    const double fov = 2 * atan(tan(0.25) * 2);
    assert_true(close_to(s->camera.zoom, 1 / tan(fov / 2), 1e-4));
    assert_int_equal(s->settings.width, 1024);
    assert_int_equal(s->settings.height, 512);
    assert_int_equal(s->light_count, 2);
    assert_int_equal(s->lights[0].kind, LIGHT_POINT);
    assert_true(close_to(s->lights[0].intensity, 1 / PI, 1e-6) && s->lights[0].attenuate);
    assert_int_equal(s->lights[1].kind, LIGHT_SPOT);
    assert_true(close_to(s->lights[1].angle, 0.8 * 180 / PI, 1e-3) && close_to(s->lights[1].soft, 0.2 * 180 / PI, 1e-3));
    assert_true(s->ambient.x == s->background.x && s->ambient.z == s->background.z);
    scene_destroy(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(cameras_and_lights_are_placed_by_their_nodes),
        cmocka_unit_test(what_is_malformed_is_left_out),
        cmocka_unit_test(a_walk_over_shared_children_ends),
        cmocka_unit_test(a_preview_takes_the_files_camera_and_lights),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
