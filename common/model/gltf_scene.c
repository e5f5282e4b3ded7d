/* gltf_scene.c - see gltf_scene.h. */
#include "model/gltf_scene.h"

#include <json-c/json.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "model/gltf_json.h"

/* A 4 x 4 matrix, column-major as glTF writes one. */
typedef struct {
    double m[16];
} Mat4;

static Mat4 mat_mul(const Mat4 *a, const Mat4 *b)
{
    Mat4 r;
    for (int c = 0; c < 4; c++)
        for (int row = 0; row < 4; row++) {
            double s = 0.0;
            for (int k = 0; k < 4; k++)
                s += a->m[k * 4 + row] * b->m[c * 4 + k];
            r.m[c * 4 + row] = s;
        }
    return r;
}

/* Up to n numbers of array a into out (where a holds exactly n finite ones). */
static int read_numbers(json_object *a, size_t n, double *out)
{
    if (!a || !json_object_is_type(a, json_type_array) || json_object_array_length(a) != n)
        return 0;
    for (size_t k = 0; k < n; k++)
        if (!gltf_number(json_object_array_get_idx(a, k), &out[k]))
            return 0;
    return 1;
}

/* A node's own matrix: `matrix`, or translation x rotation x scale. */
static Mat4 node_local(json_object *node)
{
    Mat4 r = {{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}};
    if (read_numbers(gltf_member(node, "matrix"), 16, r.m))
        return r;
    double t[3] = {0, 0, 0}, q[4] = {0, 0, 0, 1}, s[3] = {1, 1, 1};
    read_numbers(gltf_member(node, "translation"), 3, t);
    read_numbers(gltf_member(node, "rotation"), 4, q);
    read_numbers(gltf_member(node, "scale"), 3, s);
    const double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (n > 0.0)
        for (int k = 0; k < 4; k++)
            q[k] /= n;
    const double x = q[0], y = q[1], z = q[2], w = q[3];
    const double rot[9] = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w),     2 * (x * z - y * w),
                           2 * (x * y - z * w),     1 - 2 * (x * x + z * z), 2 * (y * z + x * w),
                           2 * (x * z + y * w),     2 * (y * z - x * w),     1 - 2 * (x * x + y * y)};
    for (int c = 0; c < 3; c++)
        for (int row = 0; row < 3; row++)
            r.m[c * 4 + row] = rot[c * 3 + row] * s[c];
    for (int row = 0; row < 3; row++)
        r.m[12 + row] = t[row];
    return r;
}

/* Matrix m applied to (v, w): a point (w 1) or a direction (w 0). */
static void apply(const Mat4 *m, const double v[3], double w, double out[3])
{
    for (int row = 0; row < 3; row++)
        out[row] = m->m[row] * v[0] + m->m[4 + row] * v[1] + m->m[8 + row] * v[2] + m->m[12 + row] * w;
}

static int unit(double v[3])
{
    const double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(n > 0.0) || !isfinite(n))
        return 0;
    for (int k = 0; k < 3; k++)
        v[k] /= n;
    return 1;
}

typedef struct {
    json_object *nodes, *cameras, *lights;
    GltfScene *out;
    size_t visits, cap;
    int failed;
} Walk;

static void take_camera(Walk *wk, json_object *cam, const Mat4 *m)
{
    GltfCamera c;
    memset(&c, 0, sizeof c);
    const char *type = json_object_get_string(gltf_member(cam, "type"));
    json_object *p = gltf_member(cam, type && strcmp(type, "orthographic") == 0 ? "orthographic" : "perspective");
    c.ortho = type && strcmp(type, "orthographic") == 0;
    if (c.ortho ? !gltf_number(gltf_member(p, "xmag"), &c.xmag) || !(c.xmag > 0.0)
                : !gltf_number(gltf_member(p, "yfov"), &c.yfov) || !(c.yfov > 0.0 && c.yfov < 3.14159))
        return;
    if (!gltf_number(gltf_member(p, "aspectRatio"), &c.aspect) || !(c.aspect > 0.0))
        c.aspect = 0.0;
    const double origin[3] = {0, 0, 0}, fwd[3] = {0, 0, -1}, up[3] = {0, 1, 0};
    apply(m, origin, 1.0, c.pos);
    apply(m, fwd, 0.0, c.fwd);
    apply(m, up, 0.0, c.up);
    if (!unit(c.fwd) || !unit(c.up) || !isfinite(c.pos[0] + c.pos[1] + c.pos[2]))
        return;
    wk->out->camera = c;
    wk->out->has_camera = 1;
}

static void take_light(Walk *wk, json_object *l, const Mat4 *m)
{
    GltfLight g = {.color = {1, 1, 1}, .intensity = 1, .inner = 0, .outer = 3.14159265358979323846 / 4};
    const char *type = json_object_get_string(gltf_member(l, "type"));
    if (!type)
        return;
    if (strcmp(type, "point") == 0)
        g.kind = GLTF_POINT;
    else if (strcmp(type, "spot") == 0)
        g.kind = GLTF_SPOT;
    else if (strcmp(type, "directional") == 0)
        g.kind = GLTF_DIRECTIONAL;
    else
        return;
    read_numbers(gltf_member(l, "color"), 3, g.color);
    gltf_number(gltf_member(l, "intensity"), &g.intensity);
    json_object *spot = gltf_member(l, "spot");
    gltf_number(gltf_member(spot, "innerConeAngle"), &g.inner);
    gltf_number(gltf_member(spot, "outerConeAngle"), &g.outer);
    const double origin[3] = {0, 0, 0}, down[3] = {0, 0, -1};
    apply(m, origin, 1.0, g.pos);
    apply(m, down, 0.0, g.dir);
    if (!(g.intensity >= 0.0) || !(g.color[0] >= 0 && g.color[1] >= 0 && g.color[2] >= 0) || !unit(g.dir) ||
        !isfinite(g.pos[0] + g.pos[1] + g.pos[2]) || !(g.outer > 0.0) || !(g.inner >= 0.0 && g.inner <= g.outer))
        return;
    if (wk->out->light_count == wk->cap) {
        if (wk->cap >= GLTF_MAX_LIGHTS)
            return;
        const size_t cap = wk->cap ? 2 * wk->cap : 4;
        GltfLight *n = realloc(wk->out->lights, cap * sizeof *n);
        if (!n) {
            wk->failed = 1;
            return;
        }
        wk->out->lights = n, wk->cap = cap;
    }
    wk->out->lights[wk->out->light_count++] = g;
}

static void walk(Walk *wk, int64_t index, const Mat4 *parent, int depth)
{
    if (wk->failed || depth > GLTF_MAX_DEPTH || ++wk->visits > GLTF_MAX_VISITS || index < 0 ||
        (size_t)index >= json_object_array_length(wk->nodes))
        return;
    json_object *node = json_object_array_get_idx(wk->nodes, (size_t)index);
    const Mat4 local = node_local(node), m = mat_mul(parent, &local);
    json_object *cam = gltf_member(node, "camera");
    if (cam && wk->cameras && !wk->out->has_camera && json_object_is_type(cam, json_type_int) && json_object_get_int64(cam) >= 0 &&
        (size_t)json_object_get_int64(cam) < json_object_array_length(wk->cameras))
        take_camera(wk, json_object_array_get_idx(wk->cameras, (size_t)json_object_get_int64(cam)), &m);
    json_object *li = gltf_member(gltf_member(gltf_member(node, "extensions"), "KHR_lights_punctual"), "light");
    if (li && wk->lights && json_object_is_type(li, json_type_int) && json_object_get_int64(li) >= 0 &&
        (size_t)json_object_get_int64(li) < json_object_array_length(wk->lights))
        take_light(wk, json_object_array_get_idx(wk->lights, (size_t)json_object_get_int64(li)), &m);
    json_object *kids = gltf_member(node, "children");
    for (size_t k = 0; kids && json_object_is_type(kids, json_type_array) && k < json_object_array_length(kids); k++) {
        json_object *c = json_object_array_get_idx(kids, k);
        if (json_object_is_type(c, json_type_int))
            walk(wk, json_object_get_int64(c), &m, depth + 1);
    }
}

/* Array member key of o, or NULL. */
static json_object *array_of(json_object *o, const char *key)
{
    json_object *a = gltf_member(o, key);
    return a && json_object_is_type(a, json_type_array) ? a : NULL;
}

int gltf_scene_read(const uint8_t *bytes, size_t len, int glb, GltfScene *out)
{
    memset(out, 0, sizeof *out);
    json_object *root = gltf_json_parse(bytes, len, glb);
    json_object *scenes = array_of(root, "scenes");
    Walk wk = {.nodes = array_of(root, "nodes"), .cameras = array_of(root, "cameras"),
               .lights = array_of(gltf_member(gltf_member(root, "extensions"), "KHR_lights_punctual"), "lights"),
               .out = out};
    double which = 0;
    gltf_number(gltf_member(root, "scene"), &which);
    json_object *scene = scenes && which >= 0 && which < (double)json_object_array_length(scenes)
                             ? json_object_array_get_idx(scenes, (size_t)which)
                             : NULL;
    json_object *roots = array_of(scene, "nodes");
    const Mat4 id = {{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}};
    for (size_t k = 0; wk.nodes && roots && k < json_object_array_length(roots); k++) {
        json_object *r = json_object_array_get_idx(roots, k);
        if (json_object_is_type(r, json_type_int))
            walk(&wk, json_object_get_int64(r), &id, 0);
    }
    json_object_put(root);
    if (wk.failed) {
        gltf_scene_free(out);
        return -1;
    }
    return 0;
}

void gltf_scene_free(GltfScene *s)
{
    free(s->lights);
    memset(s, 0, sizeof *s);
}
